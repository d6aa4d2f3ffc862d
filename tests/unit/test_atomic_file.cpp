#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;

namespace {
fs::path freshDir(const char* name) {
  auto d = fs::temp_directory_path() / (std::string("ejecta-test-") + name + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST(AtomicFile, FailedWriterLeavesNothing) {
  const auto d = freshDir("atomic");
  EXPECT_THROW(ejecta::io::writeFileAtomically(d / "a.txt", [](std::ostream& os) {
    os << "half";
    throw std::runtime_error("interrupted");
  }), std::runtime_error);
  EXPECT_TRUE(fs::is_empty(d));
  ejecta::io::writeFileAtomically(d / "a.txt", std::string("whole"));
  std::ifstream f(d / "a.txt");
  std::string s;
  f >> s;
  EXPECT_EQ(s, "whole");
  fs::remove_all(d);
}

TEST(AtomicFile, TransactionWithoutCommitRemovesStagedFiles) {
  const auto d = freshDir("txn");
  {
    ejecta::io::OutputTransaction t;
    t.stage(d / "one.csv", [](std::ostream& os) { os << "1"; });
    t.stage(d / "two.csv", [](std::ostream& os) { os << "2"; });
  }
  EXPECT_TRUE(fs::is_empty(d));
  {
    ejecta::io::OutputTransaction t;
    t.stage(d / "one.csv", [](std::ostream& os) { os << "1"; });
    t.commit();
  }
  EXPECT_TRUE(fs::exists(d / "one.csv"));
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator{}), 1);
  fs::remove_all(d);
}

// The checkpoint envelope: a checkpoint from another build, solver revision or deck, or a damaged
// one, is refused with an InputError (exit 2) that says which.
TEST(CheckpointFile, RoundTripsAndRefusesAnotherBuildRevisionDeckOrDamage) {
  const auto dir = freshDir("checkpoint");
  const std::string path = (dir / "c.bin").string();
  ejecta::io::CheckpointHeader h;
  h.solver_revision = 7;
  h.deck_digest = 0x1234u;
  h.build_digest = 0xabcdu;
  h.time_s = 1.5e-3;
  const std::string payload = "fields and accumulators";
  ejecta::io::writeCheckpointFile(path, h, payload);
  double t = 0.0;
  EXPECT_EQ(ejecta::io::readCheckpointFile(path, h, &t), payload);
  EXPECT_EQ(t, 1.5e-3);
  const auto refusedWith = [&](ejecta::io::CheckpointHeader e, const std::string& words) {
    try {
      ejecta::io::readCheckpointFile(path, e, nullptr);
    } catch (const ejecta::InputError& err) {
      return std::string(err.what()).find(words) != std::string::npos;
    }
    return false;
  };
  auto other = h;
  other.build_digest = 0xabceu;
  EXPECT_TRUE(refusedWith(other, "another build"));
  other = h;
  other.solver_revision = 8;
  EXPECT_TRUE(refusedWith(other, "solver revision 7"));
  other = h;
  other.deck_digest = 0x1235u;
  EXPECT_TRUE(refusedWith(other, "another deck"));
  {   // one byte of the payload flipped
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-3, std::ios::end);
    f.put('X');
  }
  EXPECT_TRUE(refusedWith(h, "checksum"));
  std::filesystem::remove_all(dir);
}

// The envelope read from memory (what the fuzzer drives): a length is checked against the bytes
// there before anything is allocated for it, and what is not a regular file is never read.
TEST(CheckpointFile, ParsesFromMemoryAndRefusesALengthTheBytesDoNotHold) {
  const auto dir = freshDir("checkpoint-memory");
  const std::string path = (dir / "c.bin").string();
  ejecta::io::CheckpointHeader h;
  h.time_s = 2.5e-3;
  const std::string payload = "payload";
  ejecta::io::writeCheckpointFile(path, h, payload);
  const auto bytes = ejecta::io::readWholeFile(path).value();
  double t = 0.0;
  EXPECT_EQ(ejecta::io::parseCheckpoint(bytes, h, &t), payload);
  EXPECT_EQ(t, 2.5e-3);
  const auto refusedWith = [&](const std::string& b, const std::string& words) {
    try {
      ejecta::io::parseCheckpoint(b, h, nullptr, "c.bin");
    } catch (const ejecta::InputError& err) {
      return std::string(err.what()).find(words) != std::string::npos;
    }
    return false;
  };
  // The length field sits after magic, format, revision, two digests and the time: 8 + 4 * 4 + 8.
  std::string huge = bytes.substr(0, 32);
  const std::uint64_t length = 1ULL << 35;   // 32 GiB claimed by a 44-byte file
  huge.append(reinterpret_cast<const char*>(&length), sizeof length);
  huge.append(4, '\0');
  EXPECT_TRUE(refusedWith(huge, "truncated"));
  EXPECT_TRUE(refusedWith(bytes.substr(0, bytes.size() - 1), "truncated"));
  EXPECT_TRUE(refusedWith(bytes + "x", "bytes after the payload"));
  EXPECT_TRUE(refusedWith(bytes.substr(0, 20), "truncated"));
  EXPECT_TRUE(refusedWith("", "not an ejecta checkpoint"));
  EXPECT_THROW(ejecta::io::readCheckpointFile("/dev/zero", h, nullptr), ejecta::InputError);
  EXPECT_THROW(ejecta::io::readCheckpointFile(dir.string(), h, nullptr), ejecta::InputError);
  EXPECT_THROW(ejecta::io::readCheckpointFile((dir / "absent.bin").string(), h, nullptr), ejecta::InputError);
  fs::remove_all(dir);
}

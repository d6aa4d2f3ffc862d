#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/atomic_file.hpp"

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

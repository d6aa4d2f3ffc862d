#include "io/checkpoint.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"

namespace ejecta::io {
namespace {
constexpr char kMagic[8] = {'E', 'J', 'C', 'K', 'P', 'T', '\0', '\0'};
constexpr std::uint64_t kMaxPayload = 1ULL << 36;   // 64 GiB: more than any mesh this code runs

template <class T>
void put(std::ostream& os, const T& v) {
  os.write(reinterpret_cast<const char*>(&v), sizeof v);
}
[[noreturn]] void refuse(const std::string& why) { throw InputError("restart", why); }
}  // namespace

std::uint32_t crc32Of(const std::string& bytes) {
  uLong c = crc32(0L, Z_NULL, 0);
  const auto* p = reinterpret_cast<const Bytef*>(bytes.data());
  std::size_t left = bytes.size();
  while (left > 0) {   // zlib takes uInt lengths
    const uInt n = static_cast<uInt>(std::min<std::size_t>(left, 1u << 30));
    c = crc32(c, p, n);
    p += n;
    left -= n;
  }
  return static_cast<std::uint32_t>(c);
}

std::uint32_t buildDigest() {
  static const std::uint32_t digest = [] {
    std::ifstream exe("/proc/self/exe", std::ios::binary | std::ios::ate);
    std::string bytes;
    const std::streamoff size = exe ? static_cast<std::streamoff>(exe.tellg()) : -1;
    if (size > 0) {
      bytes.resize(static_cast<std::size_t>(size));
      exe.seekg(0);
      if (!exe.read(bytes.data(), size)) bytes.clear();
    }
    return crc32Of(bytes.empty() ? std::string("ejecta ") + build_info::version : bytes);
  }();
  return digest;
}

void writeCheckpointFile(const std::string& path, const CheckpointHeader& h, const std::string& payload) {
  writeFileAtomically(path, [&](std::ostream& os) {
    os.write(kMagic, sizeof kMagic);
    put(os, h.format);
    put(os, h.solver_revision);
    put(os, h.deck_digest);
    put(os, h.build_digest);
    put(os, h.time_s);
    put(os, static_cast<std::uint64_t>(payload.size()));
    put(os, crc32Of(payload));
    os.write(payload.data(), static_cast<std::streamsize>(payload.size()));
  });
}

std::string parseCheckpoint(std::string bytes, const CheckpointHeader& expected, double* time_s, const std::string& source) {
  std::size_t at = 0;
  // Copies the next field out of `bytes`; false (nothing read) when too few bytes are left.
  const auto take = [&](auto& v) {
    if (bytes.size() - at < sizeof v) return false;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return true;
  };
  char magic[8] = {};
  CheckpointHeader h;
  std::uint64_t length = 0;
  std::uint32_t crc = 0;
  if (!take(magic) || std::memcmp(magic, kMagic, sizeof magic) != 0) refuse(fmt::format("'{}' is not an ejecta checkpoint", source));
  if (!take(h.format) || h.format != expected.format)
    refuse(fmt::format("'{}' has checkpoint format {}; this build reads format {}", source, h.format, expected.format));
  if (!(take(h.solver_revision) && take(h.deck_digest) && take(h.build_digest) && take(h.time_s) && take(length) && take(crc)))
    refuse(fmt::format("'{}' is truncated", source));
  if (length > kMaxPayload) refuse(fmt::format("'{}' is damaged (payload length {})", source, length));
  // The length is checked against the bytes there before anything is allocated for it.
  if (length > bytes.size() - at) refuse(fmt::format("'{}' is truncated", source));
  if (length < bytes.size() - at) refuse(fmt::format("'{}' is damaged (bytes after the payload)", source));
  bytes.erase(0, at);
  if (crc32Of(bytes) != crc) refuse(fmt::format("'{}' is damaged (checksum mismatch)", source));
  if (h.solver_revision != expected.solver_revision)
    refuse(fmt::format("'{}' was written by solver revision {}; this build is revision {}", source, h.solver_revision, expected.solver_revision));
  if (h.build_digest != expected.build_digest)
    refuse(fmt::format("'{}' was written by another build of ejecta (build digest {:08x}, this one {:08x}); restarts are bit for bit only on the same build",
                       source, h.build_digest, expected.build_digest));
  if (h.deck_digest != expected.deck_digest)
    refuse(fmt::format("'{}' was written for another deck (deck digest {:08x}, this deck {:08x}); only end_time_s and output.* may differ on a restart",
                       source, h.deck_digest, expected.deck_digest));
  if (time_s) *time_s = h.time_s;
  return bytes;
}

std::string readCheckpointFile(const std::string& path, const CheckpointHeader& expected, double* time_s) {
  // A device or a FIFO is refused before it is read: /dev/zero would grow without bound.
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) refuse(fmt::format("'{}' is not a regular file", path));
  auto bytes = readWholeFile(path);
  if (!bytes) refuse(fmt::format("cannot read '{}'", path));
  return parseCheckpoint(std::move(*bytes), expected, time_s, path);
}

}  // namespace ejecta::io

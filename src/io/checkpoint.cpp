#include "io/checkpoint.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <algorithm>
#include <sstream>

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
template <class T>
bool get(std::istream& is, T& v) {
  return static_cast<bool>(is.read(reinterpret_cast<char*>(&v), sizeof v));
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

std::string readCheckpointFile(const std::string& path, const CheckpointHeader& expected, double* time_s) {
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(fmt::format("cannot read '{}'", path));
  char magic[8] = {};
  CheckpointHeader h;
  std::uint64_t length = 0;
  std::uint32_t crc = 0;
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0) refuse(fmt::format("'{}' is not an ejecta checkpoint", path));
  if (!get(in, h.format) || h.format != expected.format)
    refuse(fmt::format("'{}' has checkpoint format {}; this build reads format {}", path, h.format, expected.format));
  if (!(get(in, h.solver_revision) && get(in, h.deck_digest) && get(in, h.build_digest) && get(in, h.time_s) && get(in, length) && get(in, crc)))
    refuse(fmt::format("'{}' is truncated", path));
  if (length > kMaxPayload) refuse(fmt::format("'{}' is damaged (payload length {})", path, length));
  std::string payload(static_cast<std::size_t>(length), '\0');
  if (!in.read(payload.data(), static_cast<std::streamsize>(length))) refuse(fmt::format("'{}' is truncated", path));
  if (in.peek() != std::char_traits<char>::eof()) refuse(fmt::format("'{}' is damaged (bytes after the payload)", path));
  if (crc32Of(payload) != crc) refuse(fmt::format("'{}' is damaged (checksum mismatch)", path));
  if (h.solver_revision != expected.solver_revision)
    refuse(fmt::format("'{}' was written by solver revision {}; this build is revision {}", path, h.solver_revision, expected.solver_revision));
  if (h.build_digest != expected.build_digest)
    refuse(fmt::format("'{}' was written by another build of ejecta (build digest {:08x}, this one {:08x}); restarts are bit for bit only on the same build",
                       path, h.build_digest, expected.build_digest));
  if (h.deck_digest != expected.deck_digest)
    refuse(fmt::format("'{}' was written for another deck (deck digest {:08x}, this deck {:08x}); only end_time_s and output.* may differ on a restart",
                       path, h.deck_digest, expected.deck_digest));
  if (time_s) *time_s = h.time_s;
  return payload;
}

}  // namespace ejecta::io

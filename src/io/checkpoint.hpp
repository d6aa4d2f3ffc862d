#pragma once
// The checkpoint file's envelope: what ties a checkpoint to the deck and the build that wrote it.
// Layout (little-endian, as the machine writes it):
//   8 bytes magic "EJCKPT\0\0", u32 format version, u32 solver revision, u32 deck digest,
//   u32 build digest, f64 time (s), u64 payload length, u32 payload CRC-32, payload.
// The payload (the solver's fields and the driver's accumulators) is opaque here.
#include <cstdint>
#include <string>

namespace ejecta::io {

inline constexpr std::uint32_t kCheckpointFormat = 4;   // 3: the moving mesh and time-step state, named driver scalars; 4: the load split near the wall

struct CheckpointHeader {
  std::uint32_t format = kCheckpointFormat;
  std::uint32_t solver_revision = 0;
  std::uint32_t deck_digest = 0;    // CRC-32 of the resolved deck without end_time_s and output
  std::uint32_t build_digest = 0;   // CRC-32 of the executable that wrote it
  double time_s = 0.0;
};

std::uint32_t crc32Of(const std::string& bytes);
// CRC-32 of this process's executable (/proc/self/exe): a rebuild that changes the code changes it.
// Falls back to the CRC of the version string where the executable cannot be read.
std::uint32_t buildDigest();

// Writes the envelope and the payload to `path` atomically.
void writeCheckpointFile(const std::string& path, const CheckpointHeader& h, const std::string& payload);
// Checks a checkpoint's bytes: refused (InputError on "restart", exit 2) when they are not a
// checkpoint, of another format, truncated, damaged (CRC), or written by another deck, solver
// revision or build; `source` names them in the message. Returns the payload. `bytes` is taken by
// value so that a caller can move a large file in and the payload is cut out of it in place.
std::string parseCheckpoint(std::string bytes, const CheckpointHeader& expected, double* time_s, const std::string& source = "checkpoint");
// Reads the file at `path` (a regular file) and checks it as parseCheckpoint does.
std::string readCheckpointFile(const std::string& path, const CheckpointHeader& expected, double* time_s);

}  // namespace ejecta::io

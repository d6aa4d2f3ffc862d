// Writes the checkpoint fuzz target's seeds into the folder given: a valid checkpoint file of the
// tiny set-up (envelope and payload) and its bare payload. Generated at build time rather than
// committed, so that they follow the solver's payload layout when it changes.
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/atomic_file.hpp"
#include "checkpoint_setup.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s FOLDER\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  auto solver = ejecta::fuzz::tinySolver();
  std::ostringstream payload;
  solver.writeCheckpoint(payload);
  ejecta::io::writeCheckpointFile((dir / "tiny-checkpoint.bin").string(), ejecta::fuzz::expectedHeader(), payload.str());
  ejecta::io::writeFileAtomically(dir / "tiny-payload.bin", payload.str());
  return 0;
}

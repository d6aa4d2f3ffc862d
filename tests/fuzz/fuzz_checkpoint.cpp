// libFuzzer target: the checkpoint reader, both layers a restart goes through.
//   1. The envelope (io::parseCheckpoint): magic, format, digests, length, CRC-32.
//   2. The solver's payload (hydro::Solver::readCheckpoint) for two tiny set-ups, one whose body
//      carries the mesh (checkpoint_setup.hpp).
// Every input goes to both: as a whole file to the envelope (and its payload, where accepted, on
// to the solver), and as a bare payload to the solver, because a mutation almost never keeps the
// CRC right and would otherwise never reach the payload reader.
// Refusal with an InputError is the correct outcome for damaged bytes; any other exception, a
// crash or a sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <typeinfo>

#include "core/error.hpp"
#include "checkpoint_setup.hpp"

namespace {

template <class Read>
void expectOnlyInputErrors(const char* what, Read read) {
  try {
    read();
  } catch (const ejecta::InputError&) {
    // refused, saying why: what damaged bytes should get
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s threw %s (not an InputError): %s\n", what, typeid(e).name(), e.what());
    std::abort();
  }
}

void readPayload(const std::string& payload) {
  for (const bool moving_mesh : {false, true}) {
    auto solver = ejecta::fuzz::tinySolver(moving_mesh);
    std::istringstream in(payload);
    try {
      solver.readCheckpoint(in);
    } catch (const ejecta::InputError&) {
      // refused by this set-up; the other one reads it too
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  expectOnlyInputErrors("parseCheckpoint", [&] {
    double time_s = 0.0;
    readPayload(ejecta::io::parseCheckpoint(bytes, ejecta::fuzz::expectedHeader(), &time_s, "fuzz.bin"));
  });
  expectOnlyInputErrors("Solver::readCheckpoint", [&] { readPayload(bytes); });
  return 0;
}

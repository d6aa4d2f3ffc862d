#pragma once
// What the checkpoint fuzz target and its seed writer share: a tiny solver set-up whose payload
// is small (1D, one cell, air and steel so that the deviatoric stress fields are there too) and
// the envelope's expected header.
#include "hydro/solver.hpp"
#include "io/checkpoint.hpp"

namespace ejecta::fuzz {

inline hydro::Solver tinySolver() {
  return hydro::Solver(mesh::Grid(1, mesh::Geometry::Cartesian, {mesh::Axis::uniform(0.0, 1.0, 1), mesh::Axis{}, mesh::Axis{}}),
                       {materials::air(), materials::steel()}, hydro::SolverOptions{});
}

inline io::CheckpointHeader expectedHeader() {
  io::CheckpointHeader h;
  h.solver_revision = static_cast<std::uint32_t>(hydro::kSolverRevision);
  h.deck_digest = 0x6465636bu;   // fixed digests: the seeds carry them, so mutations start past those checks
  h.build_digest = 0x6275696cu;
  h.time_s = 1e-4;
  return h;
}

}  // namespace ejecta::fuzz

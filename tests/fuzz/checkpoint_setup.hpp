#pragma once
// What the checkpoint fuzz target and its seed writer share: tiny solver set-ups whose payload is
// small (1D, five cells, air and steel so that the deviatoric stress fields are there too), one
// with a body that carries the mesh with it (the payload's body offset moves the faces), and the
// envelope's expected header.
#include "hydro/solver.hpp"
#include "io/checkpoint.hpp"

namespace ejecta::fuzz {

inline hydro::Solver tinySolver(bool moving_mesh) {
  hydro::Solver s(mesh::Grid(1, mesh::Geometry::Cartesian, {mesh::Axis::uniform(0.0, 1.0, 5), mesh::Axis{}, mesh::Axis{}}),
                  {materials::air(), materials::steel()}, hydro::SolverOptions{});
  if (moving_mesh) {
    s.setBody([](const hydro::Vec3& x) { return x[0] > 0.4 && x[0] < 0.6; });
    s.moveMeshWithBody(0, 0.0, 1.0);
  }
  return s;
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

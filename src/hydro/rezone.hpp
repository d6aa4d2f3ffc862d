#pragma once
// Conservative mapping of one solver's state onto another's mesh (a rezone), per material: the
// early-time detonation is run on a fine mesh and mapped onto the run's coarser mesh, as LS-DYNA's
// initial ALE mapping and CTH's rezone do.
//
// Nested meshes (every source cell inside one target cell, the source faces subdividing the
// target's): each target cell that receives source cells takes, per material, the sums of volume,
// mass, internal energy and mass-weighted history and stress; the cell takes the sum of momentum.
// The kinetic energy that one velocity per target cell cannot hold (sum m u^2/2 over the source
// cells minus M U^2/2, never negative) is returned as heat, to each material as it lost it
// (shareHeat), so each material's mass, the cell's momentum and the total energy are exact.
//
// 2D axisymmetric into 3D (the V-plate work) is the same sums over source cells with weights:
// each 3D target cell's overlap with an (r, z) ring; only the overlap weights change.
#include <cstddef>

#include "hydro/solver.hpp"

namespace ejecta::hydro {

struct RezoneReport {
  std::size_t target_cells = 0;   // target cells that received source cells
  std::size_t source_cells = 0;
  double heat_J = 0.0;            // kinetic energy returned as heat (per radian in 2D axisymmetric)
};

// Maps `source` onto the cells of `target` that it covers. Both solvers must have the same
// materials in the same order, the same geometry, and nested meshes where they overlap (throws
// InputError otherwise). The target's other cells are left as they are.
RezoneReport mapNested(const Solver& source, Solver& target);

}  // namespace ejecta::hydro

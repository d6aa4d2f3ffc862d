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
// 2D axisymmetric into a 3D quarter (the V-plate work) is the same sums over source cells with
// weights: each 3D cell's overlap with an (r, z) ring, and the overlap's angular moments to turn
// the radial momentum and the stress into x and y.
#include <cstddef>
#include <vector>

#include "hydro/solver.hpp"

namespace ejecta::hydro {

struct RezoneReport {
  std::size_t target_cells = 0;   // target cells that received source cells
  std::size_t source_cells = 0;   // source cells mapped (into a 3D quarter: ring-column pieces times layers)
  // Kinetic energy returned as heat (J; per radian in 2D axisymmetric) by each target cell, in the
  // order of the cells (i, j, k; i slowest): the slabs' lists in rank order are the whole's list.
  std::vector<double> heat_by_cell;
  double heatJ() const {   // their sum, in that order (the same to the bit on slabs as in the whole)
    double sum = 0.0;
    for (const double h : heat_by_cell) sum += h;
    return sum;
  }
};

// Maps `source` onto the cells of `target` that it covers. Both solvers must have the same
// materials in the same order, the same geometry, and nested meshes where they overlap (throws
// InputError otherwise). The target's other cells are left as they are; a target that is a slab of
// a decomposed mesh takes the source cells over its own cells, as the whole's would.
RezoneReport mapNested(const Solver& source, Solver& target);

// The part of the ring r0 <= r < r1 inside the rectangle [x0, x1] x [y0, y1] (x0, y0 >= 0), m2,
// and the integrals over it of cos(theta), sin(theta), cos(2 theta), sin(2 theta) dA.
struct RingOverlap {
  double area = 0.0, cos = 0.0, sin = 0.0, cos2 = 0.0, sin2 = 0.0;
};
RingOverlap ringOverlap(double x0, double x1, double y0, double y1, double r0, double r1);

// Maps an axisymmetric (r, z) state onto a 3D quarter (x, y >= 0, z up) that starts on the axis:
// along z the meshes nest (the source must lie within the quarter's height); across, each quarter
// column takes its overlap with each ring (scaled so each ring's area and first moments sum
// exactly). Each material's mass, the total energy and the momentum (turned into x and y) map
// exactly: the source's quantities per radian times pi / 2, a quarter turn; the kinetic energy one
// velocity per cell cannot hold is heat, shared among the materials as they lost it. The stress is
// turned by the overlap's moments. A column the rings cover in part keeps its own contents in the
// rest. The target may be one slab of the quarter (mesh::Grid::slab, an MPI rank's): it takes its
// own columns, each ring still scaled over the whole's, so its cells are the whole's to the bit.
// Throws InputError if a body is in the way. (A swirl, u_theta, maps too, though the
// quarter's symmetry planes cannot hold one; the 2D solver keeps it zero.)
RezoneReport mapAxisymmetricToQuarter(const Solver& source, Solver& target);

}  // namespace ejecta::hydro

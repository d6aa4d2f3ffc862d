#pragma once
// Field snapshots that open in ParaView: VTK XML rectilinear grids (.vtr) with cell data, on MPI
// ranks one piece per rank's slab and an index (.pvtr) that joins them, and a .pvd collection that
// orders the snapshots in time.
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "hydro/solver.hpp"

namespace ejecta::io {

// Volume fractions of every material, mixture density (kg/m3), pressure (Pa), velocity (m/s) and
// the target's cells. Lengths in m; axisymmetric meshes are written as the r-z half plane.
// A slab (Solver::slab) writes its own cells as one piece, its extent in the whole's cell numbering.
void writeVtr(std::ostream& os, const hydro::Solver& solver);
// One slab's piece of a snapshot: cells [begin, end) of axis 0, in `file` (relative to the .pvtr).
struct VtrPiece {
  int begin = 0, end = 0;
  std::string file;
};
// The index of a snapshot written in pieces; `slab` is any of the slabs (for the arrays and extents).
void writePvtr(std::ostream& os, const hydro::Solver& slab, const std::vector<VtrPiece>& pieces);
void writePvd(std::ostream& os, const std::vector<std::pair<double, std::string>>& snapshots);

}  // namespace ejecta::io

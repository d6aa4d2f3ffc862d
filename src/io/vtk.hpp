#pragma once
// Field snapshots that open in ParaView: VTK XML rectilinear grids (.vtr) with cell data, and a
// .pvd collection that orders them in time.
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "hydro/solver.hpp"

namespace ejecta::io {

// Volume fractions of every material, mixture density (kg/m3), pressure (Pa), velocity (m/s) and
// the target's cells. Lengths in m; axisymmetric meshes are written as the r-z half plane.
void writeVtr(std::ostream& os, const hydro::Solver& solver);
void writePvd(std::ostream& os, const std::vector<std::pair<double, std::string>>& snapshots);

}  // namespace ejecta::io

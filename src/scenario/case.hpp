#pragma once
// From a deck to a ready solver: the graded r-z mesh, the materials (air, the explosive's
// products, one sand model per soil layer and the backfill), the painted regions and the target.
#include <memory>
#include <string>
#include <vector>

#include "hydro/solver.hpp"
#include "scenario/deck.hpp"

namespace ejecta::scenario {

struct ChargeGeometry {
  double radius_m, height_m, z_bottom_m, z_top_m;
  hydro::Vec3 detonation_m;
};

struct PlateGeometry {
  bool present = false;
  double r_inner_m = 0.0, r_outer_m = 0.0, z_bottom_m = 0.0, z_top_m = 0.0;
  double area_m2 = 0.0;   // loaded (underside) area
};

struct Case {
  std::unique_ptr<hydro::Solver> solver;
  int vertical = 1;          // the mesh axis that points up (1 in r-z, 2 in 3D)
  double symmetry = 0.0;     // modelled part -> whole: 2 pi (per radian, axisymmetric) or 4 (quarter)
  std::vector<std::string> material_kind;   // per material: "air", "products" or "soil"
  ChargeGeometry charge;
  PlateGeometry plate;
};

Case buildCase(const Deck& deck);
ChargeGeometry chargeGeometry(const ChargeSpec& c);

}  // namespace ejecta::scenario

#pragma once
// From a deck to a ready solver: the graded r-z mesh, the materials (air, the explosive's
// products, one sand model per soil layer and the backfill), the painted regions and the target.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hydro/solver.hpp"
#include "parallel/exchange.hpp"
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
  std::unique_ptr<hydro::Solver> solver;   // the whole domain's, or (built for a slab) that slab's alone
  std::optional<mesh::Grid> whole_grid;    // the whole domain's mesh, whichever part the solver holds
  // The target's cells (what Solver::setBody was given); empty without a target.
  std::function<bool(const hydro::Vec3&)> body_inside;
  parallel::Slab slab;                     // the cells along axis 0 the solver holds (all in the whole)
  const mesh::Grid& grid() const { return *whole_grid; }
  bool isBodyCell(std::size_t whole_cell) const;   // a cell of the whole's mesh, as Solver::isBody
  int vertical = 1;          // the mesh axis that points up (1 in r-z, 2 in 3D)
  double symmetry = 0.0;     // modelled part -> whole: 2 pi (per radian, axisymmetric) or 4 (quarter)
  std::vector<std::string> material_kind;   // per material: "air", "products" or "soil"
  ChargeGeometry charge;
  PlateGeometry plate;
};

// A uniform block of the r-z plane meshed on its own (the early-time fine run): [0, r_max] x
// [z_lo, z_hi], whole cells of the run's core each divided into `ratio` per axis (so the meshes
// nest); its cut sides let waves out.
struct FineBlock {
  double r_max_m = 0.0, z_lo_m = 0.0, z_hi_m = 0.0;
  double cell_size_m = 0.0;   // the larger of its two cell widths, m
  int ratio = 1;              // run cells per fine cell along each axis
  int run_cells_r = 0, run_cells_z = 0;
};

// The cells along axis 0 that rank `rank` of `ranks` holds and steps (parallel::slabs); throws
// InputError (key "ranks") where the whole has too few cells for that many slabs.
parallel::Slab rankSlab(const mesh::Grid& whole, int rank, int ranks);

// The deck's case on its graded mesh, or (with `block`) on that block alone; with `part` the solver
// holds only that rank's slab of cells along axis 0 (rankSlab; Solver::setExchange joins the
// slabs), painted as the whole's, so that no rank holds the whole.
struct RankPart {
  int rank = 0, ranks = 1;
};
// `paint` false: the materials' cells are left empty (a whole that slabs are assembled into).
Case buildCase(const Deck& deck, const FineBlock* block = nullptr, const RankPart* part = nullptr, bool paint = true);
ChargeGeometry chargeGeometry(const ChargeSpec& c);

// Where the target's loaded (under) face reaches past the uniform core of the mesh as built, its
// cells are the far field's, coarser than the core's: one sentence per way out (naming the key to
// raise and the coarsest cell there), empty when the flow cells under the face are all the core's.
// A warning, not an error: a user may choose it, but such a plate is not at the run's resolution.
std::vector<std::string> targetOutsideCore(const Deck& deck);

}  // namespace ejecta::scenario

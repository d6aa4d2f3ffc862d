#include "scenario/case.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"

namespace ejecta::scenario {

ChargeGeometry chargeGeometry(const ChargeSpec& c) {
  const auto mat = materials::explosive(c.explosive);
  const double volume = c.mass_kg / mat.jwl.rho0;
  ChargeGeometry g{};
  if (c.shape == "sphere") {
    g.radius_m = std::cbrt(3.0 * volume / (4.0 * M_PI));
    g.height_m = 2.0 * g.radius_m;
  } else if (c.shape == "box") {   // radius_m is the half side
    const double side = std::cbrt(volume / c.height_to_diameter);
    g.radius_m = 0.5 * side;
    g.height_m = c.height_to_diameter * side;
  } else {   // V = pi D^2 / 4 * (k D)  with k = height / diameter
    const double dia = std::cbrt(4.0 * volume / (M_PI * c.height_to_diameter));
    g.radius_m = 0.5 * dia;
    g.height_m = c.height_to_diameter * dia;
  }
  g.z_top_m = -c.depth_of_burial_m;
  g.z_bottom_m = g.z_top_m - g.height_m;
  const double zd = c.detonation == "bottom" ? g.z_bottom_m : (c.detonation == "top" ? g.z_top_m : 0.5 * (g.z_top_m + g.z_bottom_m));
  g.detonation_m = {0.0, zd, 0.0};
  return g;
}


bool Case::isBodyCell(std::size_t whole_cell) const {
  if (!body_inside) return false;
  const auto& g = grid();
  const auto ix = g.unflatten(whole_cell);
  hydro::Vec3 x{g.centre(0, ix.i), g.centre(1, ix.j), g.centre(2, ix.k)};
  if (g.curvilinear()) x[0] = std::abs(x[0]);   // as Solver::setBody
  return body_inside(x);
}

parallel::Slab rankSlab(const mesh::Grid& whole, int rank, int ranks) {
  if (whole.cells(0) < mesh::kGhost * ranks)   // every rank finds it alike, so every rank stops
    throw InputError("ranks", fmt::format("{} ranks need at least {} cells along the first axis ({} per slab); the mesh has {}", ranks,
                                          mesh::kGhost * ranks, mesh::kGhost, whole.cells(0)));
  return parallel::slabs(whole.cells(0), ranks)[static_cast<std::size_t>(rank)];
}

namespace {
// The run mesh's graded axes as the deck lays them: across (r, or x and y in 3D) and up, the soil
// surface (z = 0) a face at every cell size.
mesh::Axis acrossAxis(const MeshSpec& m) { return mesh::Axis::graded(0.0, m.domain_radius_m, 0.0, m.core_radius_m, m.cell_size_m, m.grading); }
mesh::Axis upAxis(const MeshSpec& m) {
  return mesh::Axis::graded(m.domain_bottom_m, m.domain_top_m, m.core_bottom_m, m.core_top_m, m.cell_size_m, m.grading, 0.0);
}
// A V's wing rises this much per unit of |y| (its ridge along x, keel down); 0 for a flat target.
double wingRise(const TargetSpec& t) { return t.kind == "v" ? 1.0 / std::tan(0.5 * t.apex_angle_deg * M_PI / 180.0) : 0.0; }
}  // namespace

std::vector<std::string> targetOutsideCore(const Deck& deck) {
  std::vector<std::string> out;
  const auto& t = deck.target;
  if (t.kind == "none") return out;
  const auto& m = deck.mesh;
  const double h = m.cell_size_m;
  // the loaded face: its lowest point at the standoff; a V's wings rise across its half-width
  const double z_lo = t.standoff_m, z_hi = t.standoff_m + t.half_width_m * wingRise(t);
  const bool round = t.kind == "disc" || t.kind == "annulus";
  const double reach = round ? t.radius_m : std::max(t.half_length_m, t.half_width_m);
  // The built mesh's cells (as buildCase lays them: the core's ends fall on whole cells, so up to
  // half a cell from the keys) whose centres lie in [lo, hi], against the core's own width: the
  // widest of them, or 0 where all are the core's.
  auto coarser = [](const mesh::Axis& a, double lo, double hi) {
    const auto& f = a.faces();
    double narrowest = std::numeric_limits<double>::infinity(), widest = 0.0;
    for (std::size_t i = 0; i + 1 < f.size(); ++i) {
      narrowest = std::min(narrowest, f[i + 1] - f[i]);
      const double c = 0.5 * (f[i] + f[i + 1]);
      if (c >= lo && c <= hi) widest = std::max(widest, f[i + 1] - f[i]);
    }
    return widest > narrowest * (1.0 + 1e-6) ? widest : 0.0;
  };
  // the flow cells under the face: from a cell below its lowest point to its highest
  if (const double w = coarser(upAxis(m), z_lo - h, z_hi); w > 0.0)
    out.push_back(fmt::format("mesh.core_top_m: the target's loaded face reaches z = {:.3f} m, above the uniform core's top ({:g} m), "
                              "where its cells grow to {:.3g} mm against mesh.cell_size_m = {:.3g} mm; raise mesh.core_top_m to at least {:.3f} m",
                              z_hi, m.core_top_m, 1e3 * w, 1e3 * h, z_hi + h));
  if (const double w = coarser(acrossAxis(m), 0.0, reach); w > 0.0)
    out.push_back(fmt::format("mesh.core_radius_m: the target reaches {:.3f} m {}, past the uniform core ({:g} m), "
                              "where its cells grow to {:.3g} mm against mesh.cell_size_m = {:.3g} mm; raise mesh.core_radius_m to at least {:.3f} m",
                              reach, round ? "from the axis" : "along x or y", m.core_radius_m, 1e3 * w, 1e3 * h, reach + h));
  return out;
}

Case buildCase(const Deck& deck, const FineBlock* block, const RankPart* part, bool paint) {
  const auto& m = deck.mesh;
  const mesh::Axis r_axis = block ? mesh::Axis::uniform(0.0, block->r_max_m, block->run_cells_r * block->ratio) : acrossAxis(m);
  const mesh::Axis z_axis = block ? mesh::Axis::uniform(block->z_lo_m, block->z_hi_m, block->run_cells_z * block->ratio) : upAxis(m);
  Case cs;
  cs.charge = chargeGeometry(deck.charge);
  const double r_in = block ? block->r_max_m : m.core_radius_m, z_in = block ? block->z_lo_m : m.core_bottom_m;
  if (cs.charge.radius_m > r_in || cs.charge.z_bottom_m < z_in)
    throw InputError("charge", fmt::format("the charge (radius {:.3f} m, bottom at z = {:.3f} m) must lie inside the uniform mesh core",
                                           cs.charge.radius_m, cs.charge.z_bottom_m));

  std::vector<materials::Material> mats{materials::air(), materials::explosive(deck.charge.explosive)};
  cs.material_kind = {"air", "products"};
  for (std::size_t i = 0; i < deck.soil.size(); ++i) {
    const auto& s = deck.soil[i];
    auto in = sandInputsOf(s);   // parseDeck has checked its inputs
    in.pore_pressure = deck.air_pressure_pa;   // the sand as laid is in equilibrium with the air
    mats.push_back(materials::sand(in, s.name));
    cs.material_kind.push_back("soil");
  }
  const int backfill_mat = deck.backfill.enabled ? static_cast<int>(mats.size()) : -1;
  if (deck.backfill.enabled) {
    const auto& b = deck.backfill;
    auto in = sandInputsOf(b, deck.soil[0]);
    in.pore_pressure = deck.air_pressure_pa;
    mats.push_back(materials::sand(in, "backfill"));
    cs.material_kind.push_back("soil");
  }

  const bool three_d = deck.geometry == "3d-quarter";
  cs.vertical = three_d ? 2 : 1;
  cs.symmetry = three_d ? 4.0 : 2.0 * M_PI;
  const int up = cs.vertical;
  hydro::SolverOptions o;
  o.cfl = deck.cfl;
  o.fragment_fold = deck.fragment_fold;
  o.mixture_reuss = deck.mixture_stiffness == "reuss";
  o.thinc_bvd = deck.interface_remap == "thinc-bvd";
  if (!deck.outflow_readmits_products) {   // material 1: the products
    o.inflow_barred = {1};
    o.inflow_fill = 0;
    o.inflow_fill_rho = deck.air_density_kg_m3;
    o.inflow_fill_p = deck.air_pressure_pa;
  }
  o.load_reference_pressure = deck.air_pressure_pa;   // the plate's load by material against the atmosphere
  // low sides: axis or symmetry planes; high sides: outflow; the bottom: rigid ground
  for (auto& b : o.boundary) b = {mesh::BoundaryKind::Reflect, mesh::BoundaryKind::Transmit};
  if (block) o.boundary[static_cast<std::size_t>(up)][0] = mesh::BoundaryKind::Transmit;   // a cut through the soil, not the ground
  if (deck.gravity) o.gravity[static_cast<std::size_t>(up)] = -9.81;
  hydro::Vec3 det{0.0, 0.0, 0.0};
  det[static_cast<std::size_t>(up)] = cs.charge.detonation_m[1];
  o.detonation.push_back({det, 0.0});
  o.initial_dt_fraction = 0.1;
  o.body_friction = deck.target.kind != "none" ? deck.target.friction : 0.0;
  cs.whole_grid = three_d ? mesh::Grid(3, mesh::Geometry::Cartesian, {r_axis, r_axis, z_axis})
                          : mesh::Grid(2, mesh::Geometry::Axisymmetric, {r_axis, z_axis, mesh::Axis{}});
  const bool split = part && part->ranks > 1;
  cs.slab = split ? rankSlab(*cs.whole_grid, part->rank, part->ranks) : parallel::Slab{0, cs.whole_grid->cells(0)};
  cs.solver = std::make_unique<hydro::Solver>(split ? cs.whole_grid->slab(cs.slab.begin, cs.slab.end) : *cs.whole_grid, mats, o);
  auto& s = *cs.solver;
  // shapes see (radius from the vertical axis, height) whatever the mesh
  auto rz = [three_d](const hydro::Vec3& x) { return three_d ? std::array<double, 2>{std::hypot(x[0], x[1]), x[2]} : std::array<double, 2>{x[0], x[1]}; };

  if (paint) {   // the air, the soil layers, the backfill, the charge
    const double e_air = deck.air_pressure_pa / (0.4 * deck.air_density_kg_m3);
    s.paint(0, [](const hydro::Vec3&) { return true; }, deck.air_density_kg_m3, e_air);
    for (std::size_t i = 0; i < deck.soil.size(); ++i) {
      const auto& l = deck.soil[i];
      const int k = static_cast<int>(2 + i);
      s.paint(k, [&l, &rz](const hydro::Vec3& x) { const auto p = rz(x); return p[1] < l.top_m && p[1] >= l.bottom_m && (l.radius_m <= 0.0 || p[0] < l.radius_m); },
              mats[static_cast<std::size_t>(k)].referenceDensity(), 0.0, {}, 4, hydro::Solver::Over::background);
    }
    const auto& ch = cs.charge;
    if (backfill_mat >= 0) {
      const double rb = deck.backfill.radius_m > 0.0 ? deck.backfill.radius_m : ch.radius_m + 0.05;
      s.paint(backfill_mat, [&](const hydro::Vec3& x) { const auto p = rz(x); return p[0] < rb && p[1] < 0.0 && p[1] >= ch.z_top_m; },
              mats[static_cast<std::size_t>(backfill_mat)].referenceDensity(), 0.0);
    }
    const auto& ex = mats[1].jwl;
    if (deck.charge.shape == "sphere") {
      const double zc = 0.5 * (ch.z_top_m + ch.z_bottom_m);
      s.paint(1, [&](const hydro::Vec3& x) { const auto p = rz(x); return std::hypot(p[0], p[1] - zc) < ch.radius_m; }, ex.rho0, ex.e0 / ex.rho0, {}, 8);
    } else if (deck.charge.shape == "box") {
      s.paint(1, [&](const hydro::Vec3& x) { return std::abs(x[0]) < ch.radius_m && std::abs(x[1]) < ch.radius_m && x[2] < ch.z_top_m && x[2] >= ch.z_bottom_m; },
              ex.rho0, ex.e0 / ex.rho0, {}, 4);
    } else {
      s.paint(1, [&](const hydro::Vec3& x) { const auto p = rz(x); return p[0] < ch.radius_m && p[1] < ch.z_top_m && p[1] >= ch.z_bottom_m; }, ex.rho0,
              ex.e0 / ex.rho0, {}, three_d ? 4 : 8);
    }
  }
  const auto& t = deck.target;
  if (t.kind != "none") {
    auto& p = cs.plate;
    p.present = true;
    p.z_bottom_m = t.standoff_m;
    p.z_top_m = t.standoff_m + t.thickness_m;
    if (t.kind == "disc" || t.kind == "annulus") {
      p.r_inner_m = t.kind == "annulus" ? t.inner_radius_m : 0.0;
      p.r_outer_m = t.radius_m;
      p.area_m2 = M_PI * (p.r_outer_m * p.r_outer_m - p.r_inner_m * p.r_inner_m);
      cs.body_inside = [p, rz](const hydro::Vec3& x) { const auto q = rz(x); return q[0] >= p.r_inner_m && q[0] < p.r_outer_m && q[1] >= p.z_bottom_m && q[1] < p.z_top_m; };
    } else {
      // rectangle, or a V whose ridge runs along x with its keel down: each wing rises at
      // (90 - apex/2) degrees; thickness measured across the wing.
      const double hl = t.half_length_m, hw = t.half_width_m;
      const double rise = wingRise(t);
      const double thick = t.kind == "v" ? t.thickness_m / std::sin(0.5 * t.apex_angle_deg * M_PI / 180.0) : t.thickness_m;
      p.area_m2 = 4.0 * hl * hw;
      p.r_outer_m = std::hypot(hl, hw);
      const double z0 = t.standoff_m;
      cs.body_inside = [=](const hydro::Vec3& x) {
        const double ax = std::abs(x[0]), ay = std::abs(x[1]);
        if (ax >= hl || ay >= hw) return false;
        const double zb = z0 + ay * rise;
        return x[2] >= zb && x[2] < zb + thick;
      };
    }
    s.setBody(cs.body_inside);
  }
  return cs;
}

}  // namespace ejecta::scenario

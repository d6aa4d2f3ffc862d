// The target coupling and the decks of `ejecta run`: momentum conservation, the reflected
// pressure of a shock on a fixed plate, and deck errors that name the key.
#include <filesystem>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "ejecta/build_info.hpp"
#include "core/error.hpp"
#include "hydro/solver.hpp"
#include "scenario/case.hpp"
#include "scenario/deck.hpp"
#include "verify/exact.hpp"
#include "verify/problems.hpp"

namespace {
using namespace ejecta;
using hydro::Vec3;
using mesh::Axis;
using mesh::BoundaryKind;

TEST(Coupling, FlowAndBodyExchangeMomentumExactly) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Periodic, BoundaryKind::Periodic};   // no walls: only the body takes momentum
  o.load_reference_pressure = 1e5;   // booked against a reference pressure, which sums to zero over the closed body
  hydro::Solver s(mesh::Grid(2, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 40), Axis::uniform(0.0, 1.0, 40), Axis{}}),
                  {materials::air()}, o);
  s.paint(0, [](const Vec3&) { return true; }, 1.225, 2e5);
  s.paint(0, [](const Vec3& x) { return std::hypot(x[0] - 0.3, x[1] - 0.3) < 0.15; }, 5.0, 2e6);   // a blast
  s.setBody([](const Vec3& x) { return x[0] > 0.55 && x[0] < 0.75 && x[1] > 0.5 && x[1] < 0.6; });
  const auto a = s.totals();
  Vec3 body{};
  for (int n = 0; n < 60; ++n) {
    s.step(s.stableTimeStep());
    for (int d = 0; d < 3; ++d) body[static_cast<std::size_t>(d)] += s.lastBodyImpulse()[static_cast<std::size_t>(d)];
  }
  const auto b = s.totals();
  EXPECT_GT(std::abs(body[1]), 1e-4);   // the blast has reached the body
  // what the body gained, the flow lost
  for (std::size_t d = 0; d < 2; ++d) EXPECT_NEAR(b.momentum[d] - a.momentum[d] + body[d], 0.0, 1e-9 * std::abs(body[1]) + 1e-12) << d;
  EXPECT_NEAR(b.mass[0] / a.mass[0], 1.0, 1e-12);   // nothing enters the body
}

TEST(Coupling, ShockReflectsFromAFixedPlateWithTheExactPressure) {
  // A shock in air running into a plate: the reflected pressure against the exact Riemann problem
  // of the post-shock state and its mirror image.
  const double g = 1.4;
  const verify::GasState pre{1.0, 0.0, 1.0};
  const double ms = 2.0;   // shock Mach number
  const double c0 = std::sqrt(g * pre.p / pre.rho), us = ms * c0;
  const double rho1 = pre.rho * (g + 1) * ms * ms / ((g - 1) * ms * ms + 2), p1 = pre.p * (2 * g * ms * ms - (g - 1)) / (g + 1);
  const double u1 = us * (1.0 - pre.rho / rho1);
  const verify::ExactRiemann refl({rho1, u1, p1}, {rho1, -u1, p1}, g);
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Transmit, BoundaryKind::Transmit};
  const int n = 400;
  hydro::Solver s(mesh::Grid(1, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, n), Axis{}, Axis{}}), {materials::idealGas("gas", g)}, o);
  s.paint(0, [](const Vec3&) { return true; }, pre.rho, pre.p / (0.4 * pre.rho));
  s.paint(0, [](const Vec3& x) { return x[0] < 0.3; }, rho1, p1 / (0.4 * rho1), {u1, 0.0, 0.0}, 1);
  s.setBody([](const Vec3& x) { return x[0] > 0.8; });
  s.advanceTo(0.5 / us + 0.05);   // the shock has reflected and travelled back a little
  const double p_wall = s.pressure(s.grid().index(static_cast<int>(0.8 * n) - 3, 0, 0));
  EXPECT_NEAR(p_wall / refl.starPressure(), 1.0, 0.02);
}

// A gas column leaving a wall faster than its escape speed 2c/(gamma - 1) leaves a vacuum behind it:
// the exact load on the wall is zero. The acoustic wall pressure p - Z u would be negative (the
// wall pulling the gas back); a gas carries no tension, so the load is never a pull.
TEST(Coupling, AWallThatTheFlowLeavesCannotPull) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Transmit, BoundaryKind::Transmit};
  const double rho = 1.2, p = 1e5, c = std::sqrt(1.4 * p / rho), u = 1.3 * 5.0 * c;
  hydro::Solver s(mesh::Grid(1, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 100), Axis{}, Axis{}}), {materials::air()}, o);
  s.paint(0, [](const Vec3&) { return true; }, rho, p / (0.4 * rho), {u, 0.0, 0.0});
  s.setBody([](const Vec3& x) { return x[0] < 0.1; });   // the body is at x < 0.1, the gas leaves it along +x
  EXPECT_EQ(s.bodyLoad()[0], 0.0);
  double impulse = 0.0, t = 0.0;
  for (int n = 0; n < 40; ++n) {
    const double dt = s.stableTimeStep();
    s.step(dt);
    t += dt;
    EXPECT_LE(s.lastBodyImpulse()[0], 0.0) << n;   // a pull would be along +x
    impulse += s.lastBodyImpulse()[0];
  }
  // nothing like the ambient pressure's push, p t (per unit area), reaches the wall
  EXPECT_LT(std::abs(impulse), 1e-3 * p * t);
}

// A rigid piston moving through gas at rest carries the mesh with it (the ALE region either side of
// it): ahead of it a shock, behind it a rarefaction, both with their exact pressures; the body gains
// exactly the momentum the flow loses, and the energy books close with the work done on it.
TEST(Coupling, APistonMovingTheMeshDrivesTheExactShockAndRarefaction) {
  const double g = 1.4, rho = 1.2, p0 = 1e5, c0 = std::sqrt(g * p0 / rho), up = 50.0;
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Transmit, BoundaryKind::Transmit};
  const int n = 400;
  hydro::Solver s(mesh::Grid(1, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, n), Axis{}, Axis{}}), {materials::idealGas("gas", g)}, o);
  s.paint(0, [](const Vec3&) { return true; }, rho, p0 / ((g - 1.0) * rho));
  s.setBody([](const Vec3& x) { return x[0] > 0.45 && x[0] < 0.55; });
  s.moveMeshWithBody(0, 0.0, 1.0);
  s.setBodyVelocity({up, 0.0, 0.0});
  const auto a = s.totals();
  double impulse = 0.0;
  while (s.time() < 2.5e-4) {   // the waves travel about 0.1 m: far from the ends
    s.step(s.stableTimeStep());
    impulse += s.lastBodyImpulse()[0];
  }
  const auto b = s.totals();
  EXPECT_NEAR(s.bodyOffset(), up * s.time(), 1e-12);
  EXPECT_NEAR(s.grid().face(0, static_cast<int>(0.45 * n)), 0.45 + up * s.time(), 1e-12);   // the body's faces are mesh faces
  // the pressure beside each face of the piston (the cells next to it keep their indices)
  const double us = 0.25 * (g + 1.0) * up + std::sqrt(std::pow(0.25 * (g + 1.0) * up, 2) + c0 * c0);
  const double p_shock = p0 + rho * us * up;
  const double p_rare = p0 * std::pow(1.0 - 0.5 * (g - 1.0) * up / c0, 2.0 * g / (g - 1.0));
  const double p_ahead = s.pressure(s.grid().index(static_cast<int>(0.55 * n) + 2, 0, 0));
  const double p_behind = s.pressure(s.grid().index(static_cast<int>(0.45 * n) - 3, 0, 0));
  EXPECT_NEAR(p_ahead / p_shock, 1.0, 0.01) << p_ahead << " vs " << p_shock;
  EXPECT_NEAR(p_behind / p_rare, 1.0, 0.01) << p_behind << " vs " << p_rare;
  // momentum: what the flow lost, the body gained; the net load is the pressure difference across it
  EXPECT_NEAR(b.momentum[0] - a.momentum[0], -impulse, 1e-10 * std::abs(impulse));
  EXPECT_NEAR(impulse / (s.time() * (p_rare - p_shock)), 1.0, 0.05);
  EXPECT_NEAR(b.mass[0] / a.mass[0], 1.0, 1e-13);
  EXPECT_NEAR(b.target_work, impulse * up, 1e-10 * std::abs(impulse * up));   // negative: the piston works on the flow
  EXPECT_NEAR(b.total(), b.accounted(a.total()), 1e-12 * a.total());
}

// The moving mesh keeps a uniform state uniform (the geometric conservation law): gas flowing with a
// body that carries the mesh, in r-z, stays at its density and velocity however unevenly the cells
// below the body stretch and those above it close up.
TEST(Coupling, AUniformFlowStaysUniformOnTheMovingMesh) {
  hydro::SolverOptions o;
  o.boundary[0] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.boundary[1] = {BoundaryKind::Transmit, BoundaryKind::Transmit};
  const double rho = 1.2, p = 1e5, w = 30.0;
  // graded in z, so that the stretch is uneven cell to cell
  hydro::Solver s(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 1.0, 20), Axis::graded(0.0, 2.0, 0.8, 1.2, 0.04, 1.1), Axis{}}),
                  {materials::air()}, o);
  s.paint(0, [](const Vec3&) { return true; }, rho, p / (0.4 * rho), {0.0, w, 0.0});
  s.setBody([](const Vec3& x) { return x[0] < 0.3 && x[1] > 0.9 && x[1] < 1.1; });
  s.moveMeshWithBody(1, 0.2, 1.8);
  s.setBodyVelocity({0.0, w, 0.0});
  const double z0 = s.grid().face(1, 5);
  for (int n = 0; n < 30; ++n) s.step(s.stableTimeStep());
  EXPECT_GT(s.grid().face(1, 5) - z0, 0.0);   // a face below the body has moved up with the stretch
  const auto& g = s.grid();
  double worst_rho = 0.0, worst_u = 0.0;
  for (int i = 0; i < g.cells(0); ++i)
    for (int j = 0; j < g.cells(1); ++j) {
      const std::size_t c = g.index(i, j, 0);
      if (s.isBody(c)) continue;
      worst_rho = std::max(worst_rho, std::abs(s.density(c) / rho - 1.0));
      worst_u = std::max({worst_u, std::abs(s.velocity(1)[c] / w - 1.0), std::abs(s.velocity(0)[c] / w)});
    }
  EXPECT_LT(worst_rho, 1e-10);
  EXPECT_LT(worst_u, 1e-9);
  EXPECT_NEAR(s.lastBodyImpulse()[1], 0.0, 1e-9 * p);   // the flow presses equally on its top and bottom
}

// Periodic in every direction but `wall_axis` (reflecting), with the EMI decks' friction, and the
// sand the friction tests slide.
static hydro::SolverOptions frictionOptions(int wall_axis) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Periodic, BoundaryKind::Periodic};
  o.boundary[static_cast<std::size_t>(wall_axis)] = {BoundaryKind::Reflect, BoundaryKind::Reflect};
  o.body_friction = 0.2;
  return o;
}
static materials::Material frictionSand() { return materials::sand(materials::SandInputs::fromWetDensity(1500.0, 0.1), "sand"); }

// A flow sliding under a plate (wall faces at y = 0.9): air everywhere, and in the row of cells
// beside the plate (0.85 < y < 0.90) sand filling the fraction `sand` of each cell's height. The air
// is at `p_air` (Pa; 0: the sand's pressure, so that a mixed cell is at rest in its closure and the
// sand's fraction stays what was painted until the sweep across the plate).
static hydro::Solver slidingUnderAPlate(double sand, double body_u, double p_air = 0.0) {
  const auto o = frictionOptions(1);
  const auto soil = frictionSand();
  hydro::Solver s(mesh::Grid(2, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 20), Axis::uniform(0.0, 1.0, 20), Axis{}}),
                  {materials::air(), soil}, o);
  if (p_air <= 0.0) {
    const auto probe = slidingUnderAPlate(1.0, 0.0, 1e5);
    p_air = probe.pressure(probe.grid().index(0, 17, 0));
  }
  s.paint(0, [](const Vec3&) { return true; }, 1.2, p_air / (0.4 * 1.2), {10.0, 0.0, 0.0});
  // compressed a little, so that the sand presses on the plate by its own pressure too
  if (sand > 0.0) s.paint(1, [&](const Vec3& x) { return x[1] > 0.9 - 0.05 * sand; }, 1.03 * soil.referenceDensity(), 0.0, {10.0, 0.0, 0.0}, 4);
  s.setBody([](const Vec3& x) { return x[1] > 0.9; });
  s.setBodyVelocity({body_u, 0.0, 0.0});
  return s;
}

// Coulomb friction is a plate-to-soil coefficient: it takes mu times the normal load on the part of
// the contact that the sand holds (its volume fraction beside the face), and nothing from a gas,
// which carries no shear stress. Giving it to the air too (as revision 11 did) fails the first case.
TEST(Coupling, FrictionTakesMuTimesTheNormalLoadOnTheSandsShareOfTheContact) {
  for (const double sand : {0.0, 0.5, 1.0}) {
    auto s = slidingUnderAPlate(sand, 0.0);
    const auto a = s.totals();
    const double dt = 0.2 * s.stableTimeStep();
    s.step(dt);
    const auto b = s.totals();
    const auto& J = s.lastBodyImpulse();
    ASSERT_GT(J[1], 0.0) << sand;   // the flow pushes the plate up
    EXPECT_NEAR(J[0] / J[1], 0.2 * sand, 1e-9) << sand;
    // the body gains exactly the momentum the flow loses (the target stays momentum-exact) ...
    EXPECT_NEAR(J[0], a.momentum[0] - b.momentum[0], 1e-12 * a.momentum[0]) << sand;
    EXPECT_NEAR(b.total() / a.total(), 1.0, 1e-12) << sand;   // ... and the lost kinetic energy became heat
    // booked to the sand: the air beside the face took none of it, at any depth
    EXPECT_EQ(s.lastBodyImpulseByMaterial()[0][0], 0.0) << sand;
    EXPECT_NEAR(s.lastBodyImpulseByMaterial()[1][0], J[0], 1e-12 * std::abs(J[1])) << sand;
    for (int l = 0; l < hydro::kNearWallDepths; ++l) EXPECT_EQ(s.lastBodyImpulseNearWall(l)[0][0], 0.0) << sand << " " << l;
  }
}

// The friction is one traction against the sliding in the face's plane: a flow sliding diagonally
// under a plate in 3D loses mu times the normal load, against its own direction (taken component by
// component it would lose sqrt(2) mu p on a 45 degree slide).
TEST(Coupling, FrictionOpposesADiagonalSlideWithMuTimesTheNormalLoad) {
  const auto o = frictionOptions(2);
  const auto soil = frictionSand();
  hydro::Solver s(mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 4), Axis::uniform(0.0, 1.0, 4), Axis::uniform(0.0, 1.0, 8)}),
                  {soil}, o);
  const Vec3 u{6.0, 8.0, 0.0};
  s.paint(0, [](const Vec3&) { return true; }, 1.03 * soil.referenceDensity(), 0.0, u);
  s.setBody([](const Vec3& x) { return x[2] > 0.875; });
  s.step(0.2 * s.stableTimeStep());
  const auto& J = s.lastBodyImpulse();
  ASSERT_GT(J[2], 0.0);
  EXPECT_NEAR(std::hypot(J[0], J[1]) / J[2], 0.2, 1e-9);
  EXPECT_NEAR(J[0] / J[1], u[0] / u[1], 1e-9);   // along the slide: the plate is dragged with the flow
  EXPECT_GT(J[0], 0.0);
}

// The rim's case: faces normal to the first axis (r, or x in 3D), the flow sliding along them, in a
// run of three materials whose pencils carry two (products and sand; no air is left anywhere), so a
// pencil's material slots are not the run's indices. The friction is mu times the sand's share of
// the normal load, booked to the sand's run index.
TEST(Coupling, FrictionOnARimFaceIsBookedToTheSandByItsRunIndex) {
  const auto o = frictionOptions(0);
  const auto soil = frictionSand();
  const auto probe = slidingUnderAPlate(1.0, 0.0, 1e5);
  const double p_sand = probe.pressure(probe.grid().index(0, 17, 0)), gamma = 3.0, rho_products = 50.0;
  hydro::Solver s(mesh::Grid(2, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 20), Axis::uniform(0.0, 1.0, 20), Axis{}}),
                  {materials::air(), materials::idealGas("products", gamma), soil}, o);
  const Vec3 u{0.0, 10.0, 0.0};
  s.paint(0, [](const Vec3&) { return true; }, 1.2, 1e5 / (0.4 * 1.2), u);
  s.paint(1, [](const Vec3&) { return true; }, rho_products, p_sand / ((gamma - 1.0) * rho_products), u);
  s.paint(2, [](const Vec3& x) { return x[0] > 0.875; }, 1.03 * soil.referenceDensity(), 0.0, u, 4);   // half the column beside the wall
  s.setBody([](const Vec3& x) { return x[0] > 0.9; });
  s.step(0.2 * s.stableTimeStep());
  const auto& J = s.lastBodyImpulse();
  ASSERT_GT(J[0], 0.0);
  EXPECT_NEAR(J[1] / J[0], 0.2 * 0.5, 1e-9);
  const auto& by = s.lastBodyImpulseByMaterial();
  EXPECT_EQ(by[0][1], 0.0);
  EXPECT_EQ(by[1][1], 0.0);
  EXPECT_NEAR(by[2][1], J[1], 1e-12 * J[0]);
}

TEST(Coupling, FrictionOnAMovingBodyBooksItsWork) {
  auto s = slidingUnderAPlate(1.0, 4.0);   // sliding along the flow, slower than it
  const auto a = s.totals();
  s.step(0.2 * s.stableTimeStep());
  const auto b = s.totals();
  EXPECT_GT(b.target_work, 0.0);
  EXPECT_NEAR(b.target_work, 4.0 * s.lastBodyImpulse()[0], 1e-12 * b.target_work);
  EXPECT_NEAR(b.total(), b.accounted(a.total()), 1e-13 * a.total());
}

TEST(Deck, UnknownKeysAndBadValuesNameTheKey) {
  const std::string base = R"(
[[soil]]
wet_density_kg_m3 = 1370.0
moisture = 0.07
)";
  EXPECT_NO_THROW(scenario::parseDeck(base));
  auto field = [&](const std::string& text, const std::vector<std::string>& ov = {}) {
    try {
      scenario::parseDeck(text, ov);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("no error");
  };
  EXPECT_EQ(field(base + "\n[charge]\nmas_kg = 1.0\n"), "charge.mas_kg");
  EXPECT_EQ(field(base + "\n[charge]\nmass_kg = -1.0\n"), "charge.mass_kg");
  EXPECT_EQ(field(base, {"charge.explosive=Semtex"}), "charge.explosive");
  EXPECT_EQ(field(base, {"soil.moisture=0.1"}), "soil.moisture");   // [[soil]] is a list: set it in the deck
  EXPECT_EQ(field(base, {"charge.depth_of_burial_m=5.0"}), "charge.depth_of_burial_m");   // outside the domain
  EXPECT_EQ(field(base, {"mesh.cell_size_m=-0.01"}), "mesh.cell_size_m");
  EXPECT_EQ(field(base, {"nonsense"}), "--set");
  EXPECT_EQ(field("[[soil]]\ndry_density_kg_m3 = 1600.0\nmoisture = 0.3\n"), "soil.0.moisture");   // saturation over 100%
  EXPECT_EQ(field("x = [\n"), "deck");   // syntax error
  EXPECT_EQ(field(base, {"charge.shape=box"}), "charge.shape");   // a box needs 3D
  // an entry of a list of tables is named by its index
  EXPECT_DOUBLE_EQ(scenario::parseDeck(base, {"soil.0.moisture=0.1"}).soil.at(0).moisture, 0.1);
  EXPECT_EQ(scenario::parseDeck(base, {"soil.0.water_eos=alt"}).soil.at(0).water_eos, "alt");
  EXPECT_EQ(field(base, {"soil.1.moisture=0.1"}), "soil.1.moisture");
  EXPECT_EQ(field(base, {"soil.x.moisture=0.1"}), "soil.x.moisture");
  EXPECT_EQ(field(base, {"soil.0.moisture=1.5"}), "soil.0.wet_density_kg_m3");   // leaves a dry density of porosity 0.79
  EXPECT_EQ(field(base, {"soil.0.moisture=-0.1"}), "soil.0.moisture");
  EXPECT_EQ(field(base, {"soil.0.dry_density_kg_m3=1300"}), "soil.0");   // both densities given
  EXPECT_EQ(field(base, {"soil.0.wet_density_kg_m3=100"}), "soil.0.wet_density_kg_m3");   // porosity over 0.7: the sand model's range, the deck's name
  EXPECT_EQ(field(base, {"soil.0.plateau_scale=11"}), "soil.0.plateau_scale");
  EXPECT_EQ(field(base, {"soil.0.shear_modulus_cap_pa=5"}), "soil.0.shear_modulus_cap_pa");
  EXPECT_EQ(field(base, {"soil.0.shear_modulus_cap_pa=-1"}), "soil.0.shear_modulus_cap_pa");
  EXPECT_EQ(field(base, {"soil.0.mosture=0.1"}), "soil.0.mosture");   // unknown key inside a layer
  EXPECT_EQ(field(base, {"cfl=0.3\nend_time_s=0.5"}), "cfl");        // one value per --set: no text after it
  EXPECT_EQ(field(base, {"mesh.cell_size_m=true"}), "mesh.cell_size_m");
  EXPECT_EQ(field(base, {"output.gauges_m=[[0.1, nan]]"}), "output.gauges_m");
  EXPECT_EQ(field(base, {"gravity=1"}), "gravity");   // a boolean
  EXPECT_EQ(field(base, {"products_adiabat=false"}), "products_adiabat");   // removed (solver revision 3): unknown
}

// The key table is the one declaration: the deck's ranges are the sand model's, every key has help
// and a unit where it is a number, and the echo is the resolved deck (defaults included).
TEST(Deck, OneTableDeclaresEveryKey) {
  const auto& keys = scenario::deckKeys();
  std::set<std::string> paths;
  for (const auto& k : keys) {
    SCOPED_TRACE(k.path);
    EXPECT_TRUE(paths.insert(k.path).second);
    EXPECT_FALSE(k.help.empty());
    EXPECT_FALSE(k.default_text.empty());
    if (k.type == scenario::KeyType::Number) {
      EXPECT_FALSE(k.unit.empty());
    }
  }
  auto find = [&](const std::string& p) {
    const auto it = std::find_if(keys.begin(), keys.end(), [&](const auto& k) { return k.path == p; });
    EXPECT_NE(it, keys.end()) << p;
    return *it;
  };
  for (const auto& [path, range] : {std::pair{"soil.N.moisture", materials::kMoistureRange}, {"soil.N.plateau_scale", materials::kPlateauScaleRange},
                                    {"soil.N.thermal_gamma", materials::kThermalGammaRange}, {"soil.N.shear_modulus_cap_pa", materials::kShearModulusCapRange},
                                    {"backfill.moisture", materials::kMoistureRange}}) {
    const auto k = find(path);
    EXPECT_EQ(k.range.text(), range.text()) << path;
  }
  // the echo holds every key, including those the file leaves to their defaults
  const auto d = scenario::parseDeck("[[soil]]\nwet_density_kg_m3 = 1370.0\n");
  EXPECT_DOUBLE_EQ(d.echo.at("target").at("standoff_m").get<double>(), scenario::TargetSpec{}.standoff_m);
  EXPECT_DOUBLE_EQ(d.echo.at("soil").at(0).at("moisture").get<double>(), scenario::SoilSpec{}.moisture);
  EXPECT_EQ(d.echo.at("early").at("enabled").get<bool>(), scenario::EarlySpec{}.enabled);
  std::size_t echoed = 0;
  for (const auto& [section, v] : d.echo.items()) {
    if (v.is_object()) echoed += v.size();
    else if (v.is_array()) echoed += v.at(0).size();
    else ++echoed;
  }
  EXPECT_EQ(echoed, keys.size());
}

// A calm case loads the plate with nothing, at every time: the built-in EMI deck (the plate 0.10 m
// over the sand, gravity on) with the charge replaced by sand. The sand carries the pore air's
// ambient pressure (SandInputs::pore_pressure), so it is in equilibrium with the air; its
// overburden is not initialised (the column settles a little under its own weight, far below the
// plate). The plate is held still here (the solver alone, without the run's equation of motion).
TEST(Case, ACalmEmiCaseLoadsThePlateWithNothing) {
  const auto deck = scenario::loadDeck((std::filesystem::path(build_info::decks_dir) / "emi-flat-7.toml").string(),
                                       {"mesh.cell_size_m=0.04", "early.enabled=false"});
  auto cs = scenario::buildCase(deck);
  auto& s = *cs.solver;
  const double rho_sand = s.materials()[2].referenceDensity();
  auto& products = s.fieldForSetup(1);
  auto& soil = s.fieldForSetup(2);
  for (std::size_t c = 0; c < products.alpha.size(); ++c) {
    if (products.alpha[c] <= 0.0) continue;
    soil.rho[c] = rho_sand;   // the sand as laid, uniform
    soil.e[c] = 0.0;
    soil.alpha[c] += products.alpha[c];
    products.clearCell(c);
  }
  const int up = cs.vertical;
  EXPECT_LT(std::abs(cs.symmetry * s.bodyLoad()[static_cast<std::size_t>(up)]), 1.0);   // N: no load at rest to take off
  double impulse = 0.0, peak = 0.0;
  while (s.time() < 0.01) {
    s.step(std::min(s.stableTimeStep(), 0.01 - s.time() + 1e-15));
    const double iz = cs.symmetry * s.lastBodyImpulse()[static_cast<std::size_t>(up)];
    impulse += iz;
    peak = std::max(peak, std::abs(impulse));
  }
  EXPECT_LT(peak, 1.0) << "N s at worst over 10 ms; at the end " << impulse;
}

TEST(Case, VPlateInThreeDimensionsSitsOnItsWingsAndTakesLoad) {
  const std::string text = R"(
geometry = "3d-quarter"
[mesh]
cell_size_m = 0.06
core_radius_m = 0.6
core_bottom_m = -0.3
core_top_m = 0.5
domain_radius_m = 0.9
domain_bottom_m = -0.6
domain_top_m = 0.9
[[soil]]
wet_density_kg_m3 = 1370.0
moisture = 0.07
bottom_m = -0.6
[target]
kind = "v"
apex_angle_deg = 90.0
half_length_m = 0.4
half_width_m = 0.4
standoff_m = 0.1
)";
  const auto deck = scenario::parseDeck(text);
  auto cs = scenario::buildCase(deck);
  auto& s = *cs.solver;
  const auto& g = s.grid();
  EXPECT_EQ(cs.vertical, 2);
  int body = 0;
  for (int i = 0; i < g.cells(0); ++i)
    for (int j = 0; j < g.cells(1); ++j)
      for (int k = 0; k < g.cells(2); ++k) {
        if (!s.isBody(g.index(i, j, k))) continue;
        ++body;
        const double y = g.centre(1, j), z = g.centre(2, k);
        EXPECT_GE(z, 0.1 + y * 1.0 - 1e-12);   // a 90 degree V: the wings rise 1:1 from the keel
        EXPECT_LT(g.centre(0, i), 0.4);
      }
  EXPECT_GT(body, 10);
  // At rest the V takes no load: air at the ambient pressure on its wings and over it.
  EXPECT_LT(std::abs(cs.symmetry * s.bodyLoad()[2]), 1.0);
  // Rising, it carries the mesh with it along z: its staircase keeps its cells, which move with it,
  // and the energy books close with the work it takes (the blast starts at the charge meanwhile).
  s.moveMeshWithBody(2, deck.mesh.core_bottom_m, deck.mesh.domain_top_m);
  s.setBodyVelocity({0.0, 0.0, 2.0});
  const int k_keel = [&] {
    for (int k = 0; k < g.cells(2); ++k)
      if (s.isBody(g.index(0, 0, k))) return k;
    return -1;
  }();
  ASSERT_GE(k_keel, 0);
  const double z_keel = g.face(2, k_keel);
  const auto a = s.totals();
  for (int n = 0; n < 15; ++n) s.step(s.stableTimeStep());
  const auto b = s.totals();
  EXPECT_NEAR(s.bodyOffset(), 2.0 * s.time(), 1e-12);
  EXPECT_NEAR(g.face(2, k_keel), z_keel + s.bodyOffset(), 1e-12);
  EXPECT_TRUE(s.isBody(g.index(0, 0, k_keel)));
  EXPECT_NE(b.target_work, 0.0);
  EXPECT_NEAR(b.total(), b.accounted(a.total()), 1e-12 * a.total());
  // every material's mass books close to round-off: held plus folded less what came in across the
  // boundaries (air crosses the outflow sides)
  for (std::size_t m = 0; m < a.mass.size(); ++m)
    EXPECT_NEAR(b.massBooks(m), a.massBooks(m), 1e-12 * a.mass[m] + 1e-15) << m;
}

TEST(Deck, SetOverridesAField) {
  const auto d = scenario::parseDeck("[[soil]]\nwet_density_kg_m3 = 1370.0\nmoisture = 0.07\n", {"mesh.cell_size_m=0.004", "charge.explosive=C4"});
  EXPECT_DOUBLE_EQ(d.mesh.cell_size_m, 0.004);
  EXPECT_EQ(d.charge.explosive, "C4");
  EXPECT_DOUBLE_EQ(d.echo["mesh"]["cell_size_m"].get<double>(), 0.004);
}

}  // namespace

// Every shipped deck loads: its keys are known, its values in range, its geometry consistent.
TEST(Decks, EveryShippedDeckLoads) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(ejecta::build_info::decks_dir)) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    ejecta::scenario::Deck deck;
    EXPECT_NO_THROW(deck = ejecta::scenario::loadDeck(entry.path().string()));
    // and its plate lies in its uniform core: a shipped deck runs its target at its cell size
    EXPECT_EQ(ejecta::scenario::targetOutsideCore(deck), std::vector<std::string>{});
    ++n;
  }
  EXPECT_GE(n, 14);
}

// A plate whose loaded face leaves the uniform core is named, with the key to raise and the
// coarsest cell there (the 90 degree V's wings rise 0.40 m over its keel at 0.10 m).
TEST(Decks, ATargetOutsideTheCoreIsNamedWithItsCoarsestCell) {
  const auto path = (std::filesystem::path(ejecta::build_info::decks_dir) / "emi-v90-7.toml").string();
  using ejecta::scenario::loadDeck;
  using ejecta::scenario::targetOutsideCore;
  EXPECT_TRUE(targetOutsideCore(loadDeck(path)).empty());
  const auto low = targetOutsideCore(loadDeck(path, {"mesh.core_top_m=0.35"}));
  ASSERT_EQ(low.size(), 1u);
  EXPECT_TRUE(low[0].starts_with("mesh.core_top_m:")) << low[0];
  EXPECT_NE(low[0].find("z = 0.500 m"), std::string::npos) << low[0];
  // at 20 mm and 1.15 a cell the face's highest cells are 20 x 1.15^k: coarser than the core's
  const auto pos = low[0].find("grow to ");
  ASSERT_NE(pos, std::string::npos);
  EXPECT_GT(std::stod(low[0].substr(pos + 8)), 30.0) << low[0];
  EXPECT_LT(std::stod(low[0].substr(pos + 8)), 60.0) << low[0];
  // a V wider than the core, and a V within it at a raised core: only the reach is named
  const auto wide = targetOutsideCore(loadDeck(path, {"mesh.core_radius_m=0.3"}));
  ASSERT_EQ(wide.size(), 1u);
  EXPECT_TRUE(wide[0].starts_with("mesh.core_radius_m:")) << wide[0];
  // a flat plate: its face is the standoff's height alone
  const auto flat = (std::filesystem::path(ejecta::build_info::decks_dir) / "emi-flat-7.toml").string();
  EXPECT_TRUE(targetOutsideCore(loadDeck(flat, {"target.standoff_m=0.15"})).empty());
  EXPECT_EQ(targetOutsideCore(loadDeck(flat, {"target.standoff_m=0.16"})).size(), 1u);
  // the mesh as built: at 20 mm the core's top falls on z = 0.16 m (whole cells from z = 0), so a
  // plate there sits on core cells; a flat "V" (180 degrees) is a flat plate
  EXPECT_TRUE(targetOutsideCore(loadDeck(flat, {"target.standoff_m=0.16", "mesh.cell_size_m=0.02"})).empty());
  EXPECT_TRUE(targetOutsideCore(loadDeck(path, {"mesh.core_top_m=0.35", "target.apex_angle_deg=180", "target.standoff_m=0.35"})).empty());
}

// The free-air blast row of `ejecta verify` restates how a run is set up (it sits below the
// scenario layer): a change to the deck's defaults must reach it too.
TEST(VerifyFreeAir, RunsWithTheDecksDefaults) {
  const ejecta::scenario::Deck deck;
  const ejecta::verify::RunSettings rs;
  EXPECT_DOUBLE_EQ(rs.cfl, deck.cfl);
  // and the solver's own defaults, which the other verification rows and the unit tests take, are the deck's
  const ejecta::hydro::SolverOptions so;
  EXPECT_DOUBLE_EQ(so.cfl, deck.cfl);
  EXPECT_EQ(so.mixture_reuss, deck.mixture_stiffness == "reuss");
  EXPECT_EQ(so.thinc_bvd, deck.interface_remap == "thinc-bvd");
  EXPECT_DOUBLE_EQ(rs.air_pressure_pa, deck.air_pressure_pa);
  EXPECT_DOUBLE_EQ(rs.air_density_kg_m3, deck.air_density_kg_m3);
  EXPECT_DOUBLE_EQ(rs.early_cells_per_charge_height, deck.early.cells_per_charge_height);
  EXPECT_DOUBLE_EQ(rs.early_signal_speed_m_s, deck.early.signal_speed_m_s);
  EXPECT_TRUE(deck.early.enabled);
  EXPECT_EQ(deck.early.block_margin_m, 0.0);   // 0: the reach in burn times (RunSettings::early_reach_burn_times)
}

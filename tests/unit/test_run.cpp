// The target coupling and the decks of `ejecta run`: momentum conservation, the reflected
// pressure of a shock on a fixed plate, and deck errors that name the key.
#include <filesystem>
#include <gtest/gtest.h>

#include <cmath>

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

TEST(Coupling, FrictionTakesMuTimesTheNormalLoadFromTheSlidingFlow) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Periodic, BoundaryKind::Periodic};
  o.boundary[1] = {BoundaryKind::Reflect, BoundaryKind::Reflect};
  o.body_friction = 0.2;
  const double p = 1e5, rho = 1.2, u = 10.0;
  hydro::Solver s(mesh::Grid(2, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 20), Axis::uniform(0.0, 1.0, 20), Axis{}}), {materials::air()}, o);
  s.paint(0, [](const Vec3&) { return true; }, rho, p / (0.4 * rho), {u, 0.0, 0.0});
  s.setBody([](const Vec3& x) { return x[1] > 0.9; });   // a plate over the flow, wall faces at y = 0.9
  const auto a = s.totals();
  const double dt = 0.2 * s.stableTimeStep();
  s.step(dt);
  const auto b = s.totals();
  // one wall face per column, 1 m wide in total, normal stress p (no normal velocity)
  EXPECT_NEAR((a.momentum[0] - b.momentum[0]) / (0.2 * p * 1.0 * dt), 1.0, 1e-6);
  EXPECT_NEAR(b.total() / a.total(), 1.0, 1e-12);   // the lost kinetic energy became heat
  // the body gains exactly the momentum the flow loses (the target stays momentum-exact)
  EXPECT_NEAR(s.lastBodyImpulse()[0], a.momentum[0] - b.momentum[0], 1e-12 * a.momentum[0]);
}

TEST(Coupling, FrictionOnAMovingBodyBooksItsWork) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Periodic, BoundaryKind::Periodic};
  o.boundary[1] = {BoundaryKind::Reflect, BoundaryKind::Reflect};
  o.body_friction = 0.2;
  hydro::Solver s(mesh::Grid(2, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 20), Axis::uniform(0.0, 1.0, 20), Axis{}}), {materials::air()}, o);
  s.paint(0, [](const Vec3&) { return true; }, 1.2, 1e5 / (0.4 * 1.2), {10.0, 0.0, 0.0});
  s.setBody([](const Vec3& x) { return x[1] > 0.9; });
  s.setBodyVelocity({4.0, 0.0, 0.0});   // sliding along the flow, slower than it
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
  EXPECT_EQ(field("[[soil]]\nwet_density_kg_m3 = 1370.0\nmoisture = 1.5\n"), "soil[0].moisture");
  EXPECT_EQ(field("x = [\n"), "deck");   // syntax error
  EXPECT_EQ(field(base, {"charge.shape=box"}), "charge.shape");   // a box needs 3D
  // an entry of a list of tables is named by its index
  EXPECT_DOUBLE_EQ(scenario::parseDeck(base, {"soil.0.moisture=0.1"}).soil.at(0).moisture, 0.1);
  EXPECT_EQ(scenario::parseDeck(base, {"soil.0.water_eos=alt"}).soil.at(0).water_eos, "alt");
  EXPECT_EQ(field(base, {"soil.1.moisture=0.1"}), "soil.1.moisture");
  EXPECT_EQ(field(base, {"soil.x.moisture=0.1"}), "soil.x.moisture");
  EXPECT_EQ(field(base, {"soil.0.moisture=1.5"}), "soil[0].moisture");
  EXPECT_EQ(field(base, {"gravity=1"}), "gravity");   // a boolean
  EXPECT_EQ(field(base, {"products_adiabat=false"}), "products_adiabat");   // removed (solver revision 3): unknown
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
  for (int n = 0; n < 15; ++n) s.step(s.stableTimeStep());
  EXPECT_TRUE(std::isfinite(s.lastBodyImpulse()[2]));
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
    EXPECT_NO_THROW(ejecta::scenario::loadDeck(entry.path().string()));
    ++n;
  }
  EXPECT_GE(n, 14);
}

// The free-air blast row of `ejecta verify` restates how a run is set up (it sits below the
// scenario layer): a change to the deck's defaults must reach it too.
TEST(VerifyFreeAir, RunsWithTheDecksDefaults) {
  const ejecta::scenario::Deck deck;
  const ejecta::verify::RunSettings rs;
  EXPECT_DOUBLE_EQ(rs.cfl, deck.cfl);
  EXPECT_DOUBLE_EQ(rs.air_pressure_pa, deck.air_pressure_pa);
  EXPECT_DOUBLE_EQ(rs.air_density_kg_m3, deck.air_density_kg_m3);
  EXPECT_DOUBLE_EQ(rs.early_cells_per_charge_height, deck.early.cells_per_charge_height);
  EXPECT_DOUBLE_EQ(rs.early_signal_speed_m_s, deck.early.signal_speed_m_s);
  EXPECT_TRUE(deck.early.enabled);
  EXPECT_EQ(deck.early.block_margin_m, 0.0);   // 0: the reach in burn times (RunSettings::early_reach_burn_times)
}

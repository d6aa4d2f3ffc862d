// A mixed cell's stiffness (SolverOptions::mixture_reuss, the default since solver revision 15, against the frozen sum) held against
// exact answers for an equilibrium mixture: the step's formula, a pulse at Wood's speed, and the
// Hugoniot of a dusty gas stopped by a wall (the gas on its own Hugoniot, the dust at rest in it).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hydro/solver.hpp"
#include "materials/material.hpp"

namespace {
using namespace ejecta;
using hydro::Vec3;
using mesh::Axis;
using mesh::BoundaryKind;

constexpr double kGamma = 1.4, kP0 = 1e5, kRhoGas = 1.2, kFrac = 1e-3;   // air at 1 bar carrying water at 1e-3 of the volume

hydro::SolverOptions options(bool reuss) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Reflect};
  o.mixture_reuss = reuss;
  o.cfl = reuss ? 0.30 : 0.45;   // each at its own default Courant number (the frozen sum's up to revision 14)
  return o;
}

// n cells over [0, length) of gas (material 0) with water (material 1, at 1000 kg/m3 and e = 0) as
// kFrac of every cell's volume; the gas's density and velocity from `gas_rho(x)` and `u(x)`.
template <class Rho, class U>
hydro::Solver dustyTube(bool reuss, int n, double length, Rho gas_rho, U u) {
  hydro::Solver s(mesh::Grid(1, mesh::Geometry::Cartesian, {Axis::uniform(0.0, length, n), Axis{}, Axis{}}),
                  {materials::idealGas("air", kGamma), materials::water()}, options(reuss));
  for (int i = 0; i < n; ++i) {
    const std::size_t c = s.grid().index(i, 0, 0);
    const double x = s.grid().centre(0, i);
    const double rho = gas_rho(x);
    auto& g = s.fieldForSetup(0);
    g.alpha[c] = 1.0 - kFrac;
    g.rho[c] = rho;
    g.e[c] = kP0 * std::pow(rho / kRhoGas, kGamma) / ((kGamma - 1.0) * rho);   // on the isentrope through (1.2 kg/m3, 1 bar)
    auto& w = s.fieldForSetup(1);
    w.alpha[c] = kFrac;
    w.rho[c] = 1000.0;
    w.e[c] = 0.0;
    s.setVelocity(c, {u(x), 0.0, 0.0});
  }
  return s;
}

// The water's bulk modulus at its reference state (the equation of state's own).
double waterBulk() { return materials::evaluateEos(materials::water(), 1000.0, 0.0, 0.0).bulk; }

// Wood's mixture at rest: rho_mix and the equilibrium (Reuss) bulk modulus.
struct Wood {
  double rho, bulk, speed;
};
Wood wood() {
  const double k_gas = kGamma * kP0;
  const double rho = (1.0 - kFrac) * kRhoGas + kFrac * 1000.0;
  const double bulk = 1.0 / ((1.0 - kFrac) / k_gas + kFrac / waterBulk());
  return {rho, bulk, std::sqrt(bulk / rho)};
}

// The step: the frozen sum takes sum alpha_k K_k / rho_mix (here the water's, 4 times Wood's
// speed); Reuss takes the closure's 1 / sum(alpha_k / K_k) (plus the dilution stiffness, 0 here: the
// water at p = 0 beside the gas at 1 bar gives sum alpha p - K_R sum alpha p / K = (1 - f) p0
// (1 - K_R / K_gas) < 0). A cell whose neighbours close on it also sees its soft fraction close:
// beside a wall met at v its faces close at v (the wall's face at rest, the other at -v), over
// soft = sum alpha_k^2 / K_k * K_R, up to the frozen mixture's speed.
TEST(MixtureStiffness, TheStepTakesTheFrozenSumOrTheClosuresReussModulus) {
  const auto w = wood();
  const double frozen = std::sqrt(((1.0 - kFrac) * kGamma * kP0 + kFrac * waterBulk()) / w.rho);
  ASSERT_GT(frozen, 3.5 * w.speed);
  const double dx = 0.25;
  for (const bool reuss : {false, true}) {
    auto s = dustyTube(reuss, 4, 1.0, [](double) { return kRhoGas; }, [](double) { return 0.0; });
    const double c = reuss ? w.speed : frozen;
    EXPECT_NEAR(s.stableTimeStep(), options(reuss).cfl * dx / c, 1e-9 * dx / c) << reuss;
  }
  const double v = 50.0;
  auto s = dustyTube(true, 4, 1.0, [](double) { return kRhoGas; }, [v](double) { return -v; });   // towards the wall at x = 0
  s.prepareStepNeighbours();
  const double k_gas = kGamma * kP0, k_w = waterBulk();
  const double soft = ((1.0 - kFrac) * (1.0 - kFrac) / k_gas + kFrac * kFrac / k_w) * w.bulk;
  EXPECT_NEAR(soft, 1.0 - kFrac, 1e-3);
  const double expect = dx / (v + w.speed + v / soft);   // the wall cell's (its faces: 0 and -v); the others close nothing
  EXPECT_NEAR(s.cellStepTime(0, 0, 0), expect, 1e-9 * expect);
  EXPECT_NEAR(s.cellStepTime(2, 0, 0), dx / (v + w.speed), 1e-9 * expect);
  // met at 1000 m/s the closing's speed, w.speed + 1000 / soft, would pass the frozen mixture's: the
  // stiff material's own wave then outruns it, and the cell takes the frozen speed
  const double fast = 1000.0;
  ASSERT_GT(w.speed + fast / soft, frozen);
  auto f = dustyTube(true, 4, 1.0, [](double) { return kRhoGas; }, [fast](double) { return -fast; });
  f.prepareStepNeighbours();
  EXPECT_NEAR(f.cellStepTime(0, 0, 0), dx / (fast + frozen), 1e-9 * dx / (fast + frozen));
}

// Where the step's closing comes from (revision 15): each face moves at the acoustic solution's
// velocity between the cell and its neighbour, and along a radius the faces' areas count.
// (1) A dusty gas at rest met by pure water moving into it at v: the water's impedance is about a
// thousand times the gas's, so the face moves at nearly v (the mean of the two velocities gave v/2).
// (2) The same dusty gas in r-z, flowing at one inward velocity v: no velocity differs across any
// face, but the rings shrink: the cell on the axis closes at 2 v over its width (its outer face's
// area over its volume, times its width, is 2), the next at v dr / r_c = 2 v / 3; along z nothing;
// (3) in spherical shells the centre's cell at 3 v.
TEST(MixtureStiffness, TheStepsClosingTakesTheFacesAcousticVelocityAndTheRingsAreas) {
  const auto w = wood();
  const double k_gas = kGamma * kP0, k_w = waterBulk();
  const double soft = ((1.0 - kFrac) * (1.0 - kFrac) / k_gas + kFrac * kFrac / k_w) * w.bulk;
  const double v = 20.0, dx = 0.25;
  {
    auto s = dustyTube(true, 4, 1.0, [](double) { return kRhoGas; }, [](double) { return 0.0; });
    const std::size_t c0 = s.grid().index(0, 0, 0);
    auto& g = s.fieldForSetup(0);
    auto& wt = s.fieldForSetup(1);
    g.alpha[c0] = 0.0;   // cell 0: pure water at rest pressure (e = 0), moving right at v
    g.rho[c0] = 0.0;
    g.e[c0] = 0.0;
    wt.alpha[c0] = 1.0;
    s.setVelocity(c0, {v, 0.0, 0.0});
    s.prepareStepNeighbours();
    const double z_w = 1000.0 * std::sqrt(k_w / 1000.0), z_d = w.rho * w.speed;
    const double face = (z_w * v + z_d * 0.0 + 0.0 - (1.0 - kFrac) * kP0) / (z_w + z_d);   // the acoustic face velocity
    ASSERT_GT(face, 0.9 * v);
    const double expect = dx / (w.speed + face / soft);   // cell 1 at rest: its left face closes at `face`, its right one stays
    EXPECT_NEAR(s.cellStepTime(1, 0, 0), expect, 1e-6 * expect);
    EXPECT_LT(s.cellStepTime(1, 0, 0), dx / (w.speed + 0.5 * v / soft));   // stricter than the mean's closing
  }
  // (2) and (3): every cell of an n-cell radius (and n cells along z in r-z) holds the dusty gas at 1
  // bar flowing inward at v
  auto converging = [v](int dims, mesh::Geometry geometry) {
    const int n = 4;
    hydro::Solver s(mesh::Grid(dims, geometry, {Axis::uniform(0.0, 1.0, n), dims > 1 ? Axis::uniform(0.0, 1.0, n) : Axis{}, Axis{}}),
                    {materials::idealGas("air", kGamma), materials::water()}, options(true));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < (dims > 1 ? n : 1); ++j) {
        const std::size_t c = s.grid().index(i, j, 0);
        auto& g = s.fieldForSetup(0);
        g.alpha[c] = 1.0 - kFrac;
        g.rho[c] = kRhoGas;
        g.e[c] = kP0 / ((kGamma - 1.0) * kRhoGas);
        auto& wt = s.fieldForSetup(1);
        wt.alpha[c] = kFrac;
        wt.rho[c] = 1000.0;
        wt.e[c] = 0.0;
        s.setVelocity(c, {-v, 0.0, 0.0});
      }
    s.prepareStepNeighbours();
    return s;
  };
  {
    const auto s = converging(2, mesh::Geometry::Axisymmetric);
    const double axis_cell = dx / (v + w.speed + 2.0 * v / soft), next = dx / (v + w.speed + (2.0 * v / 3.0) / soft);
    EXPECT_NEAR(s.cellStepTime(0, 1, 0), axis_cell, 1e-9 * axis_cell);
    EXPECT_NEAR(s.cellStepTime(1, 1, 0), next, 1e-9 * next);
  }
  {
    // (3) in 1D spherical shells: the centre's cell closes at 3 v (r^2 dr over r^3 / 3), the next at
    // (4 - 1) dr^3 / ((8 - 1) dr^3 / 3) v = 9 v / 7
    const auto s = converging(1, mesh::Geometry::Spherical);
    const double centre = dx / (v + w.speed + 3.0 * v / soft), next = dx / (v + w.speed + (9.0 * v / 7.0) / soft);
    EXPECT_NEAR(s.cellStepTime(0, 0, 0), centre, 1e-9 * centre);
    EXPECT_NEAR(s.cellStepTime(1, 0, 0), next, 1e-9 * next);
  }
}

// Out of pressure equilibrium the dilution stiffness counts: two ideal gases (gamma 1.4) sharing
// cells half and half at 10 and 1 bar. K_k = gamma p_k, so K_R = gamma H and D = sum alpha p - K_R
// sum alpha p / K = A - H, with A and H the pressures' arithmetic and harmonic means by volume:
// c^2 = (gamma H + A - H) / rho, against the frozen gamma A / rho.
TEST(MixtureStiffness, OutOfEquilibriumTheStepCountsTheDilutionStiffness) {
  const double p1 = 1e6, p2 = 1e5, r1 = 5.0, r2 = 1.0, dx = 0.25;
  const double A = 0.5 * (p1 + p2), H = 1.0 / (0.5 / p1 + 0.5 / p2), rho = 0.5 * (r1 + r2);
  for (const bool reuss : {false, true}) {
    hydro::Solver s(mesh::Grid(1, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 1.0, 4), Axis{}, Axis{}}),
                    {materials::idealGas("a", kGamma), materials::idealGas("b", kGamma)}, options(reuss));
    for (int i = 0; i < 4; ++i) {
      const std::size_t c = s.grid().index(i, 0, 0);
      auto& a = s.fieldForSetup(0);
      a.alpha[c] = 0.5;
      a.rho[c] = r1;
      a.e[c] = p1 / ((kGamma - 1.0) * r1);
      auto& b = s.fieldForSetup(1);
      b.alpha[c] = 0.5;
      b.rho[c] = r2;
      b.e[c] = p2 / ((kGamma - 1.0) * r2);
    }
    const double c = std::sqrt((reuss ? kGamma * H + A - H : kGamma * A) / rho);
    EXPECT_NEAR(s.stableTimeStep(), options(reuss).cfl * dx / c, 1e-9 * dx / c) << reuss;
  }
}

// A right-running pulse of 1% in pressure (the gas's density on its isentrope, the velocity dp / Z)
// in the equilibrium mixture runs at Wood's speed, 4 times below the frozen mixture's: with either
// stiffness the closure (volume shared by compressibility) sets the speed; Reuss gets there in
// about a quarter of the steps at one Courant number and keeps more of the pulse (the frozen impedance is 4 times too
// stiff, and its dissipation, Z du, with it).
TEST(MixtureStiffness, APulseInADustyGasRunsAtWoodsSpeed) {
  const auto w = wood();
  const double x0 = 0.5, width = 0.08, dp = 0.01 * kP0, length = 2.0, t_end = 1.0 / w.speed;   // 1 m of travel
  struct Result {
    double peak_x, peak_dp;
    long steps;
  };
  auto run = [&](bool reuss) {
    auto shape = [&](double x) { return std::exp(-0.5 * std::pow((x - x0) / width, 2.0)); };
    auto s = dustyTube(
        reuss, 400, length,
        [&](double x) {
          // the mixture's pressure rise dp: the gas takes all of the volume change (the water hardly any)
          return kRhoGas * std::pow(1.0 + dp * shape(x) / kP0, 1.0 / kGamma);
        },
        [&](double x) { return dp * shape(x) / (w.rho * w.speed); });
    s.advanceTo(t_end);
    Result r{0.0, -1.0, s.stats().steps};
    for (int i = 0; i < 400; ++i) {
      const double p = s.pressure(s.grid().index(i, 0, 0)) - kP0;
      if (p > r.peak_dp) r = {s.grid().centre(0, i), p, r.steps};
    }
    return r;
  };
  const auto frozen = run(false), reuss = run(true);
  const double expect = x0 + w.speed * t_end;
  for (const auto& r : {frozen, reuss}) EXPECT_NEAR(r.peak_x, expect, 0.02 * (expect - x0));   // within 2% of the travel
  EXPECT_LT(static_cast<double>(reuss.steps) * 3.0 * options(true).cfl, static_cast<double>(frozen.steps) * options(false).cfl);   // at one Courant number: a third of the steps
  EXPECT_GT(reuss.peak_dp, frozen.peak_dp);
  EXPECT_GT(reuss.peak_dp, 0.7 * dp);
  RecordProperty("frozen_steps", std::to_string(frozen.steps));
  RecordProperty("reuss_steps", std::to_string(reuss.steps));
}

// The dusty gas (equal velocities and pressures, the water hardly compressible) stopped by a wall:
// with the water's volume fixed the mixture's Rankine-Hugoniot relations reduce to the gas's own
// Hugoniot in its own specific volume (the mixture's energy jump is Y_gas times the gas's, and so is
// its volume jump), and the stopping velocity fixes the pressure: v^2 = (p - p0) Y_gas (v_g0 - v_g(p)).
// The stagnated layer's mean pressure within 2% and its gas's density within 1%, the shock's place
// within 3% and a cell, in both stiffnesses; the energy books close.
TEST(MixtureStiffness, ADustyGasStoppedByAWallTakesTheMixturesHugoniot) {
  const double v = 300.0, length = 1.0, t_end = 1.5e-3;
  const double y_gas = (1.0 - kFrac) * kRhoGas / ((1.0 - kFrac) * kRhoGas + kFrac * 1000.0);
  const double vg0 = 1.0 / kRhoGas;
  auto vg = [&](double p) { return vg0 * ((kGamma - 1.0) * p + (kGamma + 1.0) * kP0) / ((kGamma + 1.0) * p + (kGamma - 1.0) * kP0); };
  double lo = kP0, hi = 100.0 * kP0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    ((mid - kP0) * y_gas * (vg0 - vg(mid)) < v * v ? lo : hi) = mid;
  }
  const double p1 = 0.5 * (lo + hi);
  // mass: rho0 (U + v) = rho1 U, the shock running away from the wall at U (the lab's frame)
  const double rho0 = (1.0 - kFrac) * kRhoGas + kFrac * 1000.0;
  const double v_mix0 = 1.0 / rho0, v_mix1 = v_mix0 - y_gas * (vg0 - vg(p1));
  const double shock_speed = v * v_mix1 / (v_mix0 - v_mix1);
  ASSERT_GT(p1, 2.0 * kP0);   // a real shock
  for (const bool reuss : {false, true}) {
    auto s = dustyTube(reuss, 400, length, [](double) { return kRhoGas; }, [v](double) { return -v; });
    const auto a = s.totals();
    s.advanceTo(t_end);
    const auto b = s.totals();
    const auto& L = s.energyLedger();
    EXPECT_NEAR(b.total() - L.boundary_in - L.target_work - L.gravity_work, a.total(), 1e-12 * a.total()) << reuss;
    // the stagnated layer, from 10 cells off the wall (its start-up heating) to 0.9 of the way to the
    // shock: its mean pressure and gas density (cells swing by about 3% about it: the wall's start-up
    // waves ringing in a layer whose impedance is the gas's)
    const double dx = length / 400, front = shock_speed * t_end;
    double p_sum = 0.0, rho_sum = 0.0;
    int n = 0;
    for (int i = 10; i < static_cast<int>(0.9 * front / dx); ++i, ++n) {
      p_sum += s.pressure(s.grid().index(i, 0, 0));
      rho_sum += s.field(0).rho[s.grid().index(i, 0, 0)];
    }
    ASSERT_GT(n, 50);
    EXPECT_NEAR(p_sum / n, p1, 0.02 * p1) << reuss;
    EXPECT_NEAR(rho_sum / n * vg(p1), 1.0, 0.01) << reuss;
    // the shock: the last cell above halfway between p0 and p1
    double at = 0.0;
    for (int i = 0; i < 400; ++i)
      if (s.pressure(s.grid().index(i, 0, 0)) > 0.5 * (kP0 + p1)) at = s.grid().centre(0, i);
    EXPECT_NEAR(at, front, 0.03 * front + dx) << reuss;
  }
}

}  // namespace

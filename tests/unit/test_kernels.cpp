// The sweep's kernels one at a time (hydro/pencil.hpp), the rezone (hydro/rezone.hpp) and the
// sand's energy term, each against an exact answer: conservation to round-off, the acoustic
// Riemann solution, where mixed-cell heat goes.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <tuple>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <string>

#include "core/error.hpp"
#include "hydro/pencil.hpp"
#include "hydro/rezone.hpp"
#include "hydro/solver.hpp"
#include "materials/material.hpp"

namespace {
using namespace ejecta;
using hydro::Vec3;
using mesh::Axis;
using mesh::BoundaryKind;

// A pencil of n interior cells of unit width and area, one material, uniform state.
struct Line {
  hydro::Pencil P;
  std::vector<double> xc, w, xf, inv;
  hydro::SweepSetup S;
  Line(int n, int M, double dt) {
    P.resize(n, M);
    const int N = P.N;
    for (int i = 0; i < N; ++i) {
      xc.push_back(i - mesh::kGhost + 0.5);
      w.push_back(1.0);
      inv.push_back(1.0);
    }
    for (int i = 0; i <= N; ++i) xf.push_back(i - mesh::kGhost);
    S.d = 0;
    S.dt = dt;
    S.xc = xc.data();
    S.width = w.data();
    S.xf = xf.data();
    S.inv_dx = inv.data();
    for (int i = 0; i <= N; ++i) P.area[static_cast<std::size_t>(i)] = 1.0;
    for (int i = 0; i < N; ++i) P.vol[static_cast<std::size_t>(i)] = 1.0;
  }
  // cell i: mixture state (one material at alpha 1 unless set otherwise)
  void set(int i, double rho, double u, double p, double K) {
    const auto si = static_cast<std::size_t>(i);
    P.rho[si] = rho;
    P.u[0][si] = u;
    P.P[si] = p;
    P.hoop[si] = p;
    P.K[si] = P.Kp[si] = K;
    P.Z[si] = std::sqrt(rho * K);
    for (int k = 0; k < P.M; ++k) {
      const auto ki = P.at(k, i);
      P.a[ki] = k == 0 ? 1.0 : 0.0;
      P.r[ki] = rho;
      P.e[ki] = p / (0.4 * rho);
      P.pk[ki] = p;
      P.kk[ki] = K;
      P.wl[ki] = 1.0;
    }
  }
};

TEST(Kernels, UniformStateGivesItsOwnFaceStateAndNoSweptVolume) {
  Line L(8, 1, 1e-3);
  for (int i = 0; i < L.P.N; ++i) L.set(i, 1.2, 0.0, 1e5, 1.4e5);
  hydro::PencilLedger led;
  hydro::computeSlopes(L.P, L.S);
  hydro::solveFaces(L.P, L.S, led);
  for (int f = mesh::kGhost; f <= mesh::kGhost + 8; ++f) {
    EXPECT_DOUBLE_EQ(L.P.pstar[static_cast<std::size_t>(f)], 1e5);
    EXPECT_DOUBLE_EQ(L.P.ustar[static_cast<std::size_t>(f)], 0.0);
    EXPECT_DOUBLE_EQ(L.P.dvol[static_cast<std::size_t>(f)], 0.0);
  }
}

TEST(Kernels, AcousticRiemannSolutionOfTwoCollidingStates) {
  // Two equal gases colliding at +-u: the face stays put at p + Z u (the acoustic solver's exact answer).
  Line L(8, 1, 1e-9);
  L.S.second_order = false;
  const double rho = 1.0, K = 1.4e5, u = 10.0, Z = std::sqrt(rho * K);
  for (int i = 0; i < L.P.N; ++i) L.set(i, rho, i < L.P.N / 2 ? u : -u, 1e5, K);
  hydro::PencilLedger led;
  hydro::computeSlopes(L.P, L.S);
  hydro::solveFaces(L.P, L.S, led);
  const auto mid = static_cast<std::size_t>(L.P.N / 2);
  EXPECT_NEAR(L.P.ustar[mid], 0.0, 1e-12);
  EXPECT_NEAR(L.P.pstar[mid], 1e5 + Z * u, 1e-6);
}

// A linear velocity u = a x at uniform pressure: both face states are (a x_f, p - dt/2 Kp a), so the
// Riemann solution is that state, exactly: the predictor advances the stress with Kp (the mixed
// cell's Reuss modulus), not with the Voigt K that sets the impedance.
TEST(Kernels, PredictorAdvancesTheStressWithItsOwnStiffness) {
  const double dt = 1e-4, a = 50.0, p = 1e6, rho = 20.0, K = 3e9, Kp = 2e6;
  Line L(8, 1, dt);
  for (int i = 0; i < L.P.N; ++i) {
    L.set(i, rho, a * L.xc[static_cast<std::size_t>(i)], p, K);
    L.P.Kp[static_cast<std::size_t>(i)] = Kp;
  }
  hydro::PencilLedger led;
  hydro::computeSlopes(L.P, L.S);
  hydro::solveFaces(L.P, L.S, led);
  for (int f = mesh::kGhost; f <= mesh::kGhost + 8; ++f) {
    const auto sf = static_cast<std::size_t>(f);
    EXPECT_NEAR(L.P.pstar[sf], p - 0.5 * dt * Kp * a, 1e-9 * p) << "face " << f;
    EXPECT_NEAR(L.P.ustar[sf], a * L.xf[sf], 1e-12) << "face " << f;
  }
}

// Homologous expansion u = a r in an axisymmetric (spherical) r-sweep: div u = 2a (3a). The face
// stresses and the hoop stress are advanced by half a step of -Kp div u, so that a uniform pressure
// meets the hoop term at the same time level (the cell's net force is zero to round-off).
TEST(Kernels, RadialPredictorTakesTheWholeDivergenceAndTimeCentresTheHoopStress) {
  for (const bool spherical : {false, true}) {
    const double dt = 1e-5, a = 100.0, p = 1e7, rho = 50.0, K = 1.4e7;
    Line L(8, 1, dt);
    for (std::size_t i = 0; i < L.xc.size(); ++i) {   // radii 1 .. : no cell on the axis
      L.xc[i] += mesh::kGhost + 1.0;
      L.xf[i] += mesh::kGhost + 1.0;
    }
    L.xf.back() += mesh::kGhost + 1.0;
    L.P.radial = true;
    L.P.spherical = spherical;
    L.P.ring_width = 1.0;
    for (int i = 0; i < L.P.N; ++i) L.set(i, rho, a * L.xc[static_cast<std::size_t>(i)], p, K);
    hydro::PencilLedger led;
    hydro::computeSlopes(L.P, L.S);
    hydro::solveFaces(L.P, L.S, led);
    const double div = (spherical ? 3.0 : 2.0) * a, p_half = p - 0.5 * dt * K * div;
    for (int i = mesh::kGhost; i < mesh::kGhost + 8; ++i) {
      const auto si = static_cast<std::size_t>(i);
      EXPECT_NEAR(L.P.dil[si], div, 1e-12 * div) << "cell " << i;
      EXPECT_NEAR(L.P.hoop[si], p_half, 1e-9 * p) << "cell " << i;
    }
    for (int f = mesh::kGhost + 1; f < mesh::kGhost + 8; ++f) EXPECT_NEAR(L.P.pstar[static_cast<std::size_t>(f)], p_half, 1e-6 * p) << "face " << f;
  }
}

TEST(Kernels, WallFaceLoadsTheBodyAndBooksItsWork) {
  // Gas moving at u into a wall that recedes at w: p* = p + Z (u - w); the body's work is p* A w dt.
  Line L(6, 1, 1e-6);
  const double rho = 1.0, K = 1.4e5, u = 20.0, w = 5.0, Z = std::sqrt(rho * K);
  for (int i = 0; i < L.P.N; ++i) L.set(i, rho, u, 1e5, K);
  const int wall = mesh::kGhost + 4;
  for (int i = wall; i < L.P.N; ++i) L.P.solid[static_cast<std::size_t>(i)] = 1;
  L.S.wall_velocity = {w, 0.0, 0.0};
  hydro::PencilLedger led;
  hydro::computeSlopes(L.P, L.S);
  hydro::solveFaces(L.P, L.S, led);
  const double ps = 1e5 + Z * (u - w);
  EXPECT_NEAR(L.P.pstar[static_cast<std::size_t>(wall)], ps, 1e-6);
  EXPECT_NEAR(led.impulse_on_body[0][0], ps * 1e-6, 1e-12);
  EXPECT_NEAR(led.target_work, ps * 1e-6 * w, 1e-10);
}

// A film of sand (material 1) one cell thick on a wall, products (material 0) behind it: the cell
// beside the wall books the whole load to the sand; a layer of fixed depth books it by volume.
TEST(Kernels, LoadByMaterialNearTheWallCountsALayerOfFixedDepth) {
  Line L(8, 2, 1e-6);   // unit cells: depths are in cell widths here
  for (int i = 0; i < L.P.N; ++i) L.set(i, 1.0, 0.0, 1e5, 1.4e5);
  const int wall = mesh::kGhost + 6;   // the body fills cells wall.. ; the film is cell wall - 1
  for (int i = wall; i < L.P.N; ++i) L.P.solid[static_cast<std::size_t>(i)] = 1;
  auto setAlpha = [&](int i, double sand) {
    L.P.a[L.P.at(0, i)] = 1.0 - sand;
    L.P.a[L.P.at(1, i)] = sand;
  };
  for (int i = 0; i < wall; ++i) setAlpha(i, 0.0);
  setAlpha(wall - 1, 1.0);
  double share[2];
  hydro::nearWallShares(L.P, L.S, wall - 1, -1, 0.0, share);   // depth 0: the cell beside the wall
  EXPECT_DOUBLE_EQ(share[1], 1.0);
  hydro::nearWallShares(L.P, L.S, wall - 1, -1, 2.5, share);   // one cell of sand in 2.5
  EXPECT_NEAR(share[1], 0.4, 1e-15);
  EXPECT_NEAR(share[0] + share[1], 1.0, 1e-15);
  hydro::nearWallShares(L.P, L.S, wall - 1, -1, 100.0, share);   // stops at the pencil's interior
  EXPECT_NEAR(share[1], 1.0 / 6.0, 1e-15);
  // the face's load, booked both ways, sums to the same total
  hydro::PencilLedger led;
  hydro::computeSlopes(L.P, L.S);
  hydro::solveFaces(L.P, L.S, led);
  const double imp = L.P.pstar[static_cast<std::size_t>(wall)] * 1e-6;
  EXPECT_NEAR(led.impulse_on_body[1][0], imp, 1e-15);
  for (int l = 0; l < hydro::kNearWallDepths; ++l)
    EXPECT_NEAR(led.impulse_near_body[l][0][0] + led.impulse_near_body[l][1][0], imp, 1e-15) << l;
  // 10 / 20 / 40 mm on unit cells: the sand's share is its cell alone at every listed depth
  EXPECT_NEAR(led.impulse_near_body[0][1][0], imp, 1e-15);
}

// foldFragments: a trace under the cut goes to the others by their volumes with its mass and
// energy; the books say what each gave or took; with one material left its volume is the cell's.
TEST(Kernels, FragmentsUnderTheCutGoToTheOtherMaterialsByVolume) {
  const double vs = 1.0;
  double vk[3] = {0.75, 2e-11, 0.25 - 2e-11}, mk[3] = {0.75, 4e-11, 0.5}, ie[3] = {1.5, 8e-10, 2.0}, folded[3];
  hydro::foldFragments(3, 1e-10, vs, vk, mk, ie, folded);
  EXPECT_EQ(vk[1], 0.0);
  EXPECT_EQ(mk[1], 0.0);
  EXPECT_EQ(ie[1], 0.0);
  EXPECT_EQ(folded[1], 4e-11);
  EXPECT_NEAR(mk[0] - 0.75, 0.75 * 4e-11, 4e-16);   // by volume: 3/4 to the first
  EXPECT_NEAR(mk[2] - 0.5, 0.25 * 4e-11, 4e-16);
  EXPECT_EQ(folded[0], -(mk[0] - 0.75));
  EXPECT_EQ(folded[2], -(mk[2] - 0.5));
  EXPECT_NEAR(ie[0] + ie[2], 1.5 + 2.0 + 8e-10, 1e-15);
  EXPECT_NEAR(vk[0] + vk[2], vs, 4e-16);
  // one left: its volume is the cell's exactly; nothing under the cut: nothing moves
  double vk1[2] = {1.0 - 5e-11, 5e-11}, mk1[2] = {1.0, 1e-10}, ie1[2] = {1.0, 1e-9}, f1[2];
  hydro::foldFragments(2, 1e-10, 1.0, vk1, mk1, ie1, f1);
  EXPECT_EQ(vk1[0], 1.0);
  EXPECT_EQ(f1[1], 1e-10);
  double vk2[2] = {0.5, 0.5}, mk2[2] = {1.0, 2.0}, ie2[2] = {3.0, 4.0}, f2[2];
  hydro::foldFragments(2, 1e-10, 1.0, vk2, mk2, ie2, f2);
  EXPECT_EQ(mk2[0], 1.0);
  EXPECT_EQ(vk2[1], 0.5);
  EXPECT_EQ(f2[0], 0.0);
  EXPECT_EQ(f2[1], 0.0);
}

TEST(Kernels, MixedCellRelaxationWorksBothMaterialsAtOneCommonPressure) {
  // Products at 1 GPa beside air at 1 atm in one cell, nothing else happening: relaxation expands
  // the products and squeezes the air, both working at the same pressure, which lies between
  // theirs; nothing else changes hands (no heat routed from one to the other).
  hydro::MixedCell c;
  c.M = 2;
  c.alpha[0] = 0.5;  c.p[0] = 1e9;  c.K[0] = 1e10;  c.m[0] = 0.5 * 1600.0;  c.ie[0] = c.m[0] * 5e6;
  c.alpha[1] = 0.5;  c.p[1] = 1e5;  c.K[1] = 1.4e5; c.m[1] = 0.5 * 1.2;     c.ie[1] = c.m[1] * 2e5;
  const double V = 1.0;
  const double ie0[2] = {c.ie[0], c.ie[1]};
  hydro::closeMixedCell(c, V, V, 0.0);
  EXPECT_NEAR(c.v[0] + c.v[1], V, 1e-14);
  EXPECT_NEAR(c.ie[0] + c.ie[1], ie0[0] + ie0[1], 1e-12 * (ie0[0] + ie0[1]));
  const double dv_products = c.v[0] - 0.5, dv_air = 0.5 - c.v[1];
  EXPECT_GT(dv_products, 0.0);
  EXPECT_NEAR(dv_products, dv_air, 1e-14);
  const double p_air = (c.ie[1] - ie0[1]) / dv_air;   // the price the air was worked at
  EXPECT_GT(p_air, 1e5);
  EXPECT_LT(p_air, 1e9);
  // the linearised common pressure of the two (weights volume / bulk modulus)
  const double w0 = 0.5 / 1e10, w1 = 0.5 / 1.4e5;
  EXPECT_NEAR(p_air, (w0 * 1e9 + w1 * 1e5) / (w0 + w1), 1e-6 * p_air);
}

TEST(Kernels, MixedCellRelaxationStartsFromThePressuresAfterTheVolumeChange) {
  // Two stiff solids at different pressures in a cell compressed by 1%. Step 1 shares the change
  // by compressibility, which raises both pressures by the same dp = -dV / (V sum(alpha / K))
  // (1.33e8 Pa here, as much as the pressures themselves); the relaxation must then trade volume
  // at the common pressure of the compressed state, not at the one of the pressures before.
  hydro::MixedCell c;
  c.M = 2;
  const double p[2] = {1e8, 2e8}, K[2] = {1e10, 2e10};
  for (int k = 0; k < 2; ++k) {
    c.alpha[k] = 0.5; c.p[k] = p[k]; c.K[k] = K[k]; c.m[k] = 1000.0; c.ie[k] = 1e6;
  }
  const double V = 1.0, Vl = 0.99, dV = Vl - V, w = 0.5 / K[0] + 0.5 / K[1];
  double v1[2], w1[2], p1[2], die = 0.0;
  for (int k = 0; k < 2; ++k) {
    const double dv = dV * (0.5 / K[k]) / w;
    v1[k] = 0.5 + dv;
    p1[k] = p[k] - K[k] * dv / 0.5;
    w1[k] = -(p[k] - 0.5 * K[k] * dv / 0.5) * dv;   // the trapezoid, as volumeWork for a stiff material
    die += w1[k];
  }
  EXPECT_NEAR(p1[0] - p[0], -dV / (V * w), 1.0);
  const double p_after = (v1[0] / K[0] * p1[0] + v1[1] / K[1] * p1[1]) / (v1[0] / K[0] + v1[1] / K[1]);
  hydro::closeMixedCell(c, V, Vl, die);
  EXPECT_NEAR(c.v[0] + c.v[1], Vl, 1e-14);
  EXPECT_NEAR(c.ie[0] + c.ie[1], 2e6 + die, 1e-9 * die);
  const double traded = c.v[0] - v1[0];   // the softer, lower-pressure solid is squeezed
  ASSERT_LT(traded, 0.0);
  EXPECT_NEAR(traded, -(c.v[1] - v1[1]), 1e-12);
  const double price0 = (c.ie[0] - 1e6 - w1[0]) / -traded, price1 = (1e6 + w1[1] - c.ie[1]) / -traded;
  EXPECT_NEAR(price0, p_after, 1e-6 * p_after);
  EXPECT_NEAR(price1, p_after, 1e-6 * p_after);
}

TEST(Kernels, MixedCellRelaxationOfAGasBesideASolidStartsFromTheGassAdiabat) {
  // Air (gamma 1.4) at 1 MPa beside a stiff solid at 50 MPa in a cell that expands by 10%: step 1
  // gives the air nearly all of it, so its pressure falls along its adiabat to p (1 + x)^-1.4; the
  // relaxation then trades at the common pressure of that state. The price each pays per unit
  // volume traded is that pressure (weights volume / bulk modulus, the air's at G p1).
  hydro::MixedCell c;
  c.M = 2;
  const double pa = 1e6, ps = 5e7, Ks = 1e10;
  c.alpha[0] = 0.5; c.p[0] = pa; c.K[0] = 1.4 * pa; c.m[0] = 0.5 * 10.0; c.ie[0] = pa * 0.5 / 0.4;
  c.alpha[1] = 0.5; c.p[1] = ps; c.K[1] = Ks;       c.m[1] = 0.5 * 2000.0; c.ie[1] = 1e6;
  const double V = 1.0, Vl = 1.1, dV = Vl - V, w = 0.5 / (1.4 * pa) + 0.5 / Ks;
  double v1[2], w1[2], p1[2], K1[2], die = 0.0;
  for (int k = 0; k < 2; ++k) {
    const double dv = dV * (0.5 / c.K[k]) / w;
    v1[k] = 0.5 + dv;
    w1[k] = hydro::volumeWork(c.p[k], c.K[k], 0.5, dv);
    die += w1[k];
  }
  p1[0] = pa * std::pow(v1[0] / 0.5, -1.4);
  K1[0] = 1.4 * p1[0];
  p1[1] = ps - Ks * (v1[1] - 0.5) / 0.5;
  K1[1] = Ks;
  const double p_after = (v1[0] / K1[0] * p1[0] + v1[1] / K1[1] * p1[1]) / (v1[0] / K1[0] + v1[1] / K1[1]);
  const double ie0[2] = {c.ie[0], c.ie[1]};
  hydro::closeMixedCell(c, V, Vl, die);
  EXPECT_NEAR(c.v[0] + c.v[1], Vl, 1e-14);
  EXPECT_NEAR(c.ie[0] + c.ie[1], ie0[0] + ie0[1] + die, 1e-9 * (ie0[0] + ie0[1]));
  const double traded = c.v[0] - v1[0];   // the solid expands into the air
  ASSERT_LT(traded, 0.0);
  EXPECT_NEAR((c.ie[0] - ie0[0] - w1[0]) / -traded, p_after, 1e-6 * p_after);
  // the air's pressure after its share of the expansion, not before (1 MPa): 0.77 MPa here
  EXPECT_LT(p_after, 0.9 * pa);
}

TEST(Kernels, MixedCellDissipationGoesToTheCompressedMaterial) {
  // A cell compressed with two materials of equal stiffness but different mass: the shock heat
  // follows the compression (equal), not the mass.
  hydro::MixedCell c;
  c.M = 2;
  for (int k = 0; k < 2; ++k) {
    c.alpha[k] = 0.5;
    c.p[k] = 1e6;
    c.K[k] = 1e9;
    c.ie[k] = 0.0;
  }
  c.m[0] = 1000.0;   // twice the mass, the same compression
  c.m[1] = 500.0;
  const double V = 1.0, Vl = 0.99, work = 1e6 * 0.01, die = work + 500.0;   // 500 J of dissipation
  hydro::closeMixedCell(c, V, Vl, die);
  EXPECT_NEAR(c.ie[0], 0.5 * die, 1e-9);
  EXPECT_NEAR(c.ie[1], 0.5 * die, 1e-9);
}

TEST(Kernels, AGasBesideAStiffSolidCycled100TimesStaysOnItsAdiabat) {
  // Half air (gamma 1.4), half a stiff solid (K = 1e10 Pa, p = p0 + K (v0 - v) / v0), at one
  // pressure; the cell is squeezed 1% and let back 100 times, the cell's work that of the mixture
  // at equal pressures (the gas takes the volume change: its adiabat's work, as the Riemann
  // solver's time-centred face work gives it). The closure adds nothing irreversible of its own:
  // the gas must come back to its adiabat (p v^1.4), the solid to its volume, and no energy may
  // drift from the gas into the solid.
  const double gamma = 1.4, p0 = 1e5, Ks = 1e10;
  double V = 1.0, vg = 0.5, vs = 0.5, eg = p0 * vg / (gamma - 1.0), es = 0.0;
  const double mg = 0.6, ms = 1000.0, adiabat0 = p0 * std::pow(vg, gamma);
  for (int step = 0; step < 200; ++step) {
    const double Vl = step % 2 == 0 ? V * 0.99 : V / 0.99;
    const double pg = (gamma - 1.0) * eg / vg, ps = p0 + Ks * (0.5 - vs) / 0.5;
    hydro::MixedCell c;
    c.M = 2;
    c.alpha[0] = vg / V; c.p[0] = pg; c.K[0] = gamma * pg; c.m[0] = mg; c.ie[0] = eg;
    c.alpha[1] = vs / V; c.p[1] = ps; c.K[1] = Ks;         c.m[1] = ms; c.ie[1] = es;
    // the mixture's work: the gas's adiabat over the volume change (the solid's share is ~1e-5)
    const double dV = Vl - V, work = pg * vg * (std::pow(vg / (vg + dV), gamma - 1.0) - 1.0) / (gamma - 1.0);
    hydro::closeMixedCell(c, V, Vl, work);
    vg = c.v[0]; vs = c.v[1]; eg = c.ie[0]; es = c.ie[1]; V = Vl;
  }
  const double pg = (gamma - 1.0) * eg / vg;
  EXPECT_NEAR(V, 1.0, 1e-12);
  EXPECT_NEAR(pg * std::pow(vg, gamma) / adiabat0, 1.0, 1e-3) << "the gas's entropy drifted over 100 cycles";
  EXPECT_NEAR(vs, 0.5, 1e-6);
  EXPECT_LT(std::abs(es), 1e-3 * p0 * 0.5 / (gamma - 1.0)) << "J drifted into the solid";
}

TEST(Kernels, ExpansionWorkFollowsTheAdiabatAndNeverExceedsWhatAGasHolds) {
  // An ideal gas (gamma 1.4, K = 1.4 p) expanding from v0 to 11 v0 in one step: the work is its
  // isentrope's, p v0 (1 - 11^-0.4) / 0.4, not p dv, and never more than its energy p v0 / 0.4.
  const double p = 1e5, v0 = 0.01, dv = 0.1;
  const double w = hydro::volumeWork(p, 1.4 * p, v0, dv);
  EXPECT_NEAR(-w, p * v0 * (1.0 - std::pow(11.0, -0.4)) / 0.4, 1e-9);
  EXPECT_LT(-w, p * v0 / 0.4);
  // a small step is p dv to first order
  EXPECT_NEAR(hydro::volumeWork(p, 1.4 * p, v0, 1e-9) / (-p * 1e-9), 1.0, 1e-6);
  // a compression to half the volume is the isentrope's work too (p dv at the starting pressure
  // would fall 24% short), and a stiff material compressed is charged at its mean pressure
  EXPECT_NEAR(hydro::volumeWork(p, 1.4 * p, v0, -0.5 * v0), p * v0 * (std::pow(0.5, -0.4) - 1.0) / 0.4, 1e-9);
  const double K = 1e10, dvs = -1e-4 * v0;
  EXPECT_NEAR(hydro::volumeWork(p, K, v0, dvs), -(p + 0.5 * K * 1e-4) * dvs, 1e-12);
}

TEST(Kernels, RelaxationWorkOnAFilmWithNoMassIsBounded) {
  // Products at high pressure beside a film of air with almost no mass: the relaxation squeezes
  // the air at the common pressure, at most half its volume per step, so the film gains at most
  // p_eq v / 2 (here about 1e9 J/kg against the 5e9 J/kg it holds), not the products' excess.
  hydro::MixedCell c;
  c.M = 2;
  c.alpha[0] = 0.5; c.p[0] = 1e7; c.K[0] = 1.34e7; c.m[0] = 0.5 * 50.0; c.ie[0] = c.m[0] * 1e6;
  c.alpha[1] = 0.5; c.p[1] = 1e5; c.K[1] = 1.4e5; c.m[1] = 0.5 * 1e-4; c.ie[1] = c.m[1] * 2e5 / 0.4 * 1e4;
  const double total0 = c.ie[0] + c.ie[1], air0 = c.ie[1];
  hydro::closeMixedCell(c, 1.0, 1.0, 0.0);
  EXPECT_NEAR(c.ie[0] + c.ie[1], total0, 1e-12 * total0);
  EXPECT_GE(c.v[1], 0.25 - 1e-15);             // at most half the film's volume in one step
  const double gained = c.ie[1] - air0;
  EXPECT_GT(gained, 0.0);                      // the air was worked on...
  EXPECT_LE(gained, 1e7 * (0.5 - c.v[1]));     // ...at no more than the highest pressure present
  EXPECT_NEAR(gained / (0.5 - c.v[1]), (0.5 / 1.34e7 * 1e7 + 0.5 / 1.4e5 * 1e5) / (0.5 / 1.34e7 + 0.5 / 1.4e5), 1.0);
}

TEST(Kernels, ShareHeatSumsExactlyAndCapsASliver) {
  const double mass[3] = {1.0, 1.0, 1e-12}, loss[3] = {2.0, 0.5, 3.0}, held[3] = {10.0, 0.0, 1.0};
  double add[3];
  hydro::shareHeat(3, mass, loss, 5.5, held, add);
  EXPECT_NEAR(add[0] + add[1] + add[2], 5.5, 1e-14);
  EXPECT_LT(add[2] / mass[2], 3.0 * 5.5 / 2.0);   // no more than about twice the mean per unit mass
  EXPECT_GT(add[0], add[1]);                     // the one that lost more gets more
  // a net gain is taken from the energy held, not from a cold material by mass
  hydro::shareHeat(3, mass, loss, -1.0, held, add);
  EXPECT_NEAR(add[0] + add[1] + add[2], -1.0, 1e-14);
  EXPECT_EQ(add[1], 0.0);
}

// THINC's outflow against the profile integrated by quadrature: H(x) = (1 + g tanh(beta (x - xc))) / 2
// over the donor (x in [0, 1]), xc such that H averages to the fraction a, integrated over the part
// that leaves (the last b of the donor towards the face, or the first b).
double thincByQuadrature(double a, double b, bool increasing, bool out_high, double beta) {
  const double g = increasing ? 1.0 : -1.0;
  auto integral = [&](double xc, double from, double to) {
    const int n = 4000;   // Simpson: error about h^4 beta^4, under 1e-12
    const double h = (to - from) / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double x = from + i * h, w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      sum += w * 0.5 * (1.0 + g * std::tanh(beta * (x - xc)));
    }
    return sum * h / 3.0;
  };
  double lo = -20.0, hi = 20.0;   // the mean falls (g = 1) or rises (g = -1) with xc
  for (int it = 0; it < 64; ++it) {
    const double mid = 0.5 * (lo + hi);
    const bool too_much = integral(mid, 0.0, 1.0) > a;
    if (too_much == increasing) lo = mid; else hi = mid;
  }
  const double xc = 0.5 * (lo + hi);
  return out_high ? integral(xc, 1.0 - b, 1.0) : integral(xc, 0.0, b);
}

// The remap's and the scatter's x / d: a product by 1 / d for a normal divisor, and for a subnormal
// one (whose reciprocal overflows) the quotient itself, which stays finite.
TEST(Kernels, ReciprocalIsTheProductOrWhereItOverflowsTheQuotient) {
  const hydro::Reciprocal three(3.0);
  EXPECT_EQ(three.of(2.0), 2.0 * (1.0 / 3.0));
  const double tiny = std::numeric_limits<double>::denorm_min() * 8.0;   // 1 / tiny is not finite
  const hydro::Reciprocal sub(tiny);
  EXPECT_FALSE(std::isfinite(1.0 / tiny));
  EXPECT_EQ(sub.of(tiny * 4.0), 4.0);
  EXPECT_TRUE(std::isfinite(sub.of(1e-310)));
}

// THINC's flux as revision 13 computed it, the difference of two ln cosh of the profile's
// arguments (the reference for revision 14's one log of a ratio).
double thincByLnCosh(double a, double a_lo, double a_hi, double b, bool out_high, double beta) {
  const auto lnCosh = [](double x) { return std::abs(x) + std::log1p(std::exp(-2.0 * std::abs(x))) - std::log(2.0); };
  const double hi_cap = std::min(a, b), lo_cap = std::max(0.0, a - (1.0 - b));
  const auto capped = [&](double x) { return std::min(std::max(x, lo_cap), hi_cap); };
  if (a < 1e-6 || a > 1.0 - 1e-6 || (a_hi - a) * (a - a_lo) <= 0.0) return capped(a * b);
  const double gamma = a_hi > a_lo ? 1.0 : -1.0, eq = std::exp(2.0 * beta * gamma * (a - 0.5));
  const double xc = std::log((std::exp(beta) - eq) / (eq - std::exp(-beta))) / (2.0 * beta);
  const double f = out_high ? lnCosh(beta * (1.0 - xc)) - lnCosh(beta * (1.0 - b - xc)) : lnCosh(beta * (b - xc)) - lnCosh(beta * xc);
  return capped(0.5 * b + gamma / (2.0 * beta) * f);
}

TEST(Kernels, ThincOutflowAsOneLogIsTheTwoLnCoshFormToRoundOff) {
  // down to the fractions where the profile starts (1e-6 from either end) and the thinnest and
  // fullest sweeps, both sides, both slopes, and two sharpnesses; the face's exp shared by two
  // materials as the remap shares it
  for (const double beta : {3.5, 1.6})
    for (const double a : {1.01e-6, 1e-5, 1e-3, 0.2, 0.5, 0.9, 1.0 - 1e-3, 1.0 - 1e-5, 1.0 - 1.01e-6})
      for (const double b : {1e-12, 1e-9, 1e-6, 1e-3, 0.3, 0.7, 1.0 - 1e-6, 1.0})
        for (const bool increasing : {true, false})
          for (const bool out_high : {true, false}) {
            const double lo = increasing ? 0.0 : 1.0, hi = increasing ? 1.0 : 0.0;
            const hydro::ThincProfile th(beta);
            hydro::ThincFace face(b, out_high, th);
            const double f = hydro::thincOutflow(a, lo, hi, face), other = hydro::thincOutflow(1.0 - a, hi, lo, face);
            const double ref = thincByLnCosh(a, lo, hi, b, out_high, beta);
            EXPECT_NEAR(f, ref, 4e-15) << beta << " " << a << " " << b << " " << increasing << out_high;
            EXPECT_NEAR(f + other, b, 4e-15);
          }
}

TEST(Kernels, ThincOutflowMatchesItsProfileAndStaysWithinTheDonor) {
  const double beta = 3.5;
  for (const double a : {0.05, 0.3, 0.5, 0.8, 0.97})
    for (const double b : {0.1, 0.45, 0.9})
      for (const bool increasing : {true, false})
        for (const bool out_high : {true, false}) {
          const double lo = increasing ? 0.0 : 1.0, hi = increasing ? 1.0 : 0.0;   // neighbours that bracket the cell
          const double f = hydro::thincOutflow(a, lo, hi, b, out_high, beta);
          EXPECT_NEAR(f, thincByQuadrature(a, b, increasing, out_high, beta), 1e-12) << a << " " << b << " " << increasing << out_high;
          EXPECT_LE(f, std::min(a, b));                    // no more than the donor holds
          EXPECT_GE(f, std::max(0.0, a - (1.0 - b)));      // no more left behind than the others' room
          // the other material's profile is the complement: the two fill the swept volume
          const double other = hydro::thincOutflow(1.0 - a, hi, lo, b, out_high, beta);
          EXPECT_NEAR(f + other, b, 1e-14);
        }
  // a pure donor gives exactly the swept fraction, an empty one nothing, at every b (at a = 1 the
  // lower cap 1 - (1 - b) can round above b: the capping must not fail there)
  for (int i = 1; i < 1000; ++i) {
    const double b = i / 1000.0;
    EXPECT_EQ(hydro::thincOutflow(1.0, 1.0, 1.0, b, true, beta), b);
    EXPECT_EQ(hydro::thincOutflow(1.0, 0.0, 1.0, b, false, beta), b);
    EXPECT_EQ(hydro::thincOutflow(0.0, 0.0, 1.0, b, true, beta), 0.0);
  }
  // no bracketing neighbours: the donor mean
  EXPECT_DOUBLE_EQ(hydro::thincOutflow(0.4, 0.5, 0.5, 0.25, true, beta), 0.1);
}

// BVD's face values are THINC's profile at the cell's faces: the flux of a thin sliver through a
// face, over its width, tends to them. The choice: at an interface (0 | 0.5 | 1) THINC's step leaves
// the smaller jumps, in a dust (0.049 | 0.05 | 0.051) the donor mean does.
TEST(Kernels, ThincFaceValuesAreTheProfilesAndBvdPicksTheStepOnlyAtAnInterface) {
  const double beta = 3.5, sliver = 1e-7;
  const hydro::ThincProfile th(beta);
  for (const double a : {0.02, 0.3, 0.5, 0.8, 0.97})
    for (const bool increasing : {true, false}) {
      Line L(3, 1, 1e-3);
      const int c = mesh::kGhost + 1;
      L.P.a[static_cast<std::size_t>(c - 1)] = increasing ? 0.0 : 1.0;
      L.P.a[static_cast<std::size_t>(c)] = a;
      L.P.a[static_cast<std::size_t>(c + 1)] = increasing ? 1.0 : 0.0;
      hydro::thincFaceValues(L.P, c, c, th);
      const double lo = L.P.a[static_cast<std::size_t>(c - 1)], hi = L.P.a[static_cast<std::size_t>(c + 1)];
      EXPECT_NEAR(L.P.thi[static_cast<std::size_t>(c)], hydro::thincOutflow(a, lo, hi, sliver, true, beta) / sliver, 1e-6) << a << increasing;
      EXPECT_NEAR(L.P.tlo[static_cast<std::size_t>(c)], hydro::thincOutflow(a, lo, hi, sliver, false, beta) / sliver, 1e-6) << a << increasing;
    }
  // no profile (the fraction within 1e-6 of 0 or 1, or neighbours that do not bracket it): the
  // cell's fraction at both faces
  for (const auto& [lo, a, hi] : {std::tuple{0.0, 5e-7, 1.0}, std::tuple{0.0, 1.0 - 5e-7, 1.0}, std::tuple{0.2, 0.4, 0.3}, std::tuple{0.6, 0.4, 0.6}}) {
    Line L(3, 1, 1e-3);
    const int c = mesh::kGhost + 1;
    L.P.a[static_cast<std::size_t>(c - 1)] = lo;
    L.P.a[static_cast<std::size_t>(c)] = a;
    L.P.a[static_cast<std::size_t>(c + 1)] = hi;
    hydro::thincFaceValues(L.P, c, c, th);
    EXPECT_EQ(L.P.tlo[static_cast<std::size_t>(c)], a) << lo << " " << a << " " << hi;
    EXPECT_EQ(L.P.thi[static_cast<std::size_t>(c)], a) << lo << " " << a << " " << hi;
  }
  auto choice = [&](double a0, double a1, double a2) {
    Line L(5, 1, 1e-3);
    const int c = mesh::kGhost + 2;
    const double v[5] = {a0 - (a1 - a0), a0, a1, a2, a2 + (a2 - a1)};
    for (int i = 0; i < 5; ++i) L.P.a[static_cast<std::size_t>(c - 2 + i)] = std::clamp(v[i], 0.0, 1.0);
    hydro::thincFaceValues(L.P, c - 1, c + 1, th);
    return hydro::bvdTakesTheProfile(L.P, static_cast<std::size_t>(c));
  };
  EXPECT_TRUE(choice(0.0, 0.5, 1.0));
  EXPECT_TRUE(choice(1.0, 0.6, 0.0));
  EXPECT_TRUE(choice(0.02, 0.5, 0.98));      // an interface spread over three cells
  EXPECT_TRUE(choice(0.0, 1.0 / 3.0, 2.0 / 3.0));   // over two (the step's jumps are larger than the mean's here)
  EXPECT_TRUE(choice(1.0, 0.55, 0.05));      // sand against products carrying a dust
  EXPECT_FALSE(choice(0.049, 0.05, 0.051));  // a dust
  EXPECT_FALSE(choice(0.45, 0.5, 0.55));     // a smooth ramp of a half
}

TEST(Kernels, RemapOfAUniformFlowCarriesMassEnergyAndMomentumConsistently) {
  Line L(6, 1, 1e-3);
  for (int i = 0; i < L.P.N; ++i) L.set(i, 2.0, 50.0, 1e5, 1.4e5);
  hydro::PencilLedger led;
  hydro::computeSlopes(L.P, L.S);
  hydro::solveFaces(L.P, L.S, led);
  hydro::lagrangeUpdate(L.P, L.S, led);
  hydro::remapFluxes(L.P, L.S, led);
  for (int f = mesh::kGhost; f <= mesh::kGhost + 6; ++f) {
    const auto sf = static_cast<std::size_t>(f), kf = L.P.atFace(0, f);
    const double dv = L.P.fv[kf];
    EXPECT_NEAR(dv, 50.0 * 1e-3, 1e-12);
    EXPECT_NEAR(L.P.fm[kf], 2.0 * dv, 1e-12);
    EXPECT_NEAR(L.P.fmom[0][sf], 50.0 * L.P.fm[kf], 1e-9);
    EXPECT_NEAR(L.P.fkek[kf], 0.5 * L.P.fm[kf] * 2500.0, 1e-9);
  }
  // energy in through the low face equals energy out through the high face
  EXPECT_NEAR(led.boundary_in, 0.0, 1e-9);
}

TEST(Rezone, NestedMappingKeepsEachMaterialsMassMomentumAndTheTotalEnergy) {
  // A 2D axisymmetric fine state with two materials, velocities and a sharp interface, mapped onto
  // a 3x coarser nested mesh.
  auto make = [](int n) {
    hydro::SolverOptions o;
    for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Transmit};
    return hydro::Solver(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.3, n), Axis::uniform(-0.15, 0.15, n), Axis{}}),
                         {materials::air(), materials::explosive("CompB")}, o);
  };
  auto fine = make(30), coarse = make(10);
  for (auto* s : {&fine, &coarse}) {
    s->paint(0, [](const Vec3&) { return true; }, 1.225, 2e5);
    s->paint(1, [](const Vec3& x) { return std::hypot(x[0], x[1]) < 0.11; }, 1717.0, 5e6, {}, 8);
  }
  const auto& g = fine.grid();
  for (int i = 0; i < g.cells(0); ++i)
    for (int j = 0; j < g.cells(1); ++j) fine.setVelocity(g.index(i, j, 0), {300.0 * g.centre(0, i), 200.0 * std::sin(20.0 * g.centre(1, j)), 0.0});
  const auto a = fine.totals();
  const auto rep = hydro::mapNested(fine, coarse);
  const auto b = coarse.totals();
  EXPECT_EQ(rep.target_cells, 100u);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(b.mass[k], a.mass[k], 1e-13 * a.mass[k]);
  EXPECT_NEAR(b.momentum[1], a.momentum[1], 1e-12 * std::abs(a.momentum[1]) + 1e-12);
  EXPECT_NEAR(b.total(), a.total(), 1e-13 * a.total());
  EXPECT_GT(rep.heatJ(), 0.0);   // one velocity per coarse cell holds less kinetic energy
  EXPECT_NEAR(b.kinetic_energy + rep.heatJ(), a.kinetic_energy, 1e-10 * a.kinetic_energy);
}

TEST(Rezone, MeshesThatDoNotNestAreRefused) {
  hydro::SolverOptions o;
  auto make = [&](int n) {
    return hydro::Solver(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.3, n), Axis::uniform(0.0, 0.3, n), Axis{}}), {materials::air()}, o);
  };
  auto fine = make(7), coarse = make(3);
  EXPECT_THROW(hydro::mapNested(fine, coarse), InputError);
}

TEST(Rezone, RingOverlapAgainstClosedForms) {
  // a rectangle wholly inside the ring: its area and the moments of a box
  const auto in = hydro::ringOverlap(0.3, 0.4, 0.1, 0.2, 0.0, 1.0);
  EXPECT_NEAR(in.area, 0.01, 1e-12);
  // int x / r dA over the box, by a fine midpoint sum
  double c = 0.0, sn = 0.0;
  const int n = 1000;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = 0.3 + (i + 0.5) * 0.1 / n, y = 0.1 + (j + 0.5) * 0.1 / n, r = std::hypot(x, y);
      c += x / r * 1e-2 / (n * n);
      sn += y / r * 1e-2 / (n * n);
    }
  EXPECT_NEAR(in.cos, c, 1e-8);
  EXPECT_NEAR(in.sin, sn, 1e-8);
  // the unit square over the quarter disc of radius 1: pi / 4, first moments 1/2, int sin 2t = 1/2
  const auto q = hydro::ringOverlap(0.0, 1.0, 0.0, 1.0, 0.0, 1.0);
  EXPECT_NEAR(q.area, 0.25 * M_PI, 1e-9);
  EXPECT_NEAR(q.cos, 0.5, 1e-9);
  EXPECT_NEAR(q.sin, 0.5, 1e-9);
  EXPECT_NEAR(q.cos2, 0.0, 1e-9);
  EXPECT_NEAR(q.sin2, 0.5, 1e-9);
  // a ring cut by a square in its corner: the pieces of a split square add up
  const auto whole = hydro::ringOverlap(0.0, 0.6, 0.0, 0.6, 0.4, 0.7);
  double parts = 0.0;
  for (const double x0 : {0.0, 0.2, 0.4})
    for (const double y0 : {0.0, 0.3}) parts += hydro::ringOverlap(x0, x0 + 0.2, y0, y0 + 0.3, 0.4, 0.7).area;
  EXPECT_NEAR(parts, whole.area, 1e-9);
  // a square holding the quarter ring: the quarter ring
  EXPECT_NEAR(hydro::ringOverlap(0.0, 1.0, 0.0, 1.0, 0.4, 0.7).area, 0.25 * M_PI * (0.49 - 0.16), 1e-12);
  EXPECT_EQ(hydro::ringOverlap(0.5, 0.6, 0.5, 0.6, 0.0, 0.3).area, 0.0);
}

TEST(Rezone, AxisymmetricIntoAQuarterKeepsMassEnergyAndTurnsTheMomentum) {
  // An (r, z) state with a products ball in air, radial and axial velocity, mapped into a 3D quarter
  // whose columns are coarser than the rings and whose corner columns the rings cover in part.
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  const std::vector<materials::Material> mats{materials::air(), materials::explosive("CompB"),
                                              materials::sand(materials::SandInputs::fromWetDensity(1500.0, 0.1), "sand")};
  hydro::Solver axi(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.3, 45), Axis::uniform(-0.15, 0.15, 48), Axis{}}), mats, o);
  hydro::Solver quarter(mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 0.4, 8), Axis::uniform(0.0, 0.4, 8), Axis::uniform(-0.25, 0.25, 10)}),
                        mats, o);
  for (auto* s : {&axi, &quarter}) s->paint(0, [](const Vec3&) { return true; }, 1.225, 2e5);
  axi.paint(2, [](const Vec3& x) { return x[1] < 0.0; }, mats[2].referenceDensity(), 100.0, {}, 4);
  axi.paint(1, [](const Vec3& x) { return std::hypot(x[0], x[1]) < 0.11; }, 1717.0, 5e6, {}, 8);
  quarter.paint(2, [](const Vec3& x) { return x[2] < 0.0; }, mats[2].referenceDensity(), 100.0);
  const auto& g = axi.grid();
  // a trace of products that underflowed in a sand cell (the fine run leaves such): no volume to hold it
  axi.fieldForSetup(1).alpha[g.index(30, 3, 0)] = 1e-318;
  axi.fieldForSetup(1).rho[g.index(30, 3, 0)] = 1717.0;
  axi.fieldForSetup(1).e[g.index(30, 3, 0)] = 1e6;
  double radial = 0.0;   // per radian: sum of m u_r
  for (int i = 0; i < g.cells(0); ++i)
    for (int j = 0; j < g.cells(1); ++j) {
      const std::size_t c = g.index(i, j, 0);
      axi.setVelocity(c, {300.0 * g.centre(0, i), 200.0 * std::sin(20.0 * g.centre(1, j)), 0.0});
      double m = 0.0;
      for (int k = 0; k < 3; ++k) m += axi.field(k).alpha[c] * axi.field(k).rho[c] * g.cellVolume(i, j, 0);
      radial += m * 300.0 * g.centre(0, i);
    }
  // what the quarter holds outside the source's reach stays: its columns beyond r = 0.3 m and its
  // layers outside z = +-0.15 m
  const auto& q = quarter.grid();
  auto outside = [&](const hydro::Solver& s) {   // each material's mass, then the internal energy
    std::vector<double> m(4, 0.0);
    for (int I = 0; I < q.cells(0); ++I)
      for (int J = 0; J < q.cells(1); ++J)
        for (int L = 0; L < q.cells(2); ++L) {
          const bool reached = std::hypot(q.axis(0).faces()[static_cast<std::size_t>(I)], q.axis(1).faces()[static_cast<std::size_t>(J)]) < 0.3 &&
                               std::abs(q.centre(2, L)) < 0.15;
          if (reached) continue;
          for (int k = 0; k < 3; ++k) {
            const double mk = s.field(k).alpha[q.index(I, J, L)] * s.field(k).rho[q.index(I, J, L)] * q.cellVolume(I, J, L);
            m[static_cast<std::size_t>(k)] += mk;
            m[3] += mk * s.field(k).e[q.index(I, J, L)];
          }
        }
    return m;
  };
  const auto before = outside(quarter);
  const auto a = axi.totals(), q0 = quarter.totals();
  // the quarter's own contents in the part of each reached cell the rings do not cover
  double own_mass = 0.0, own_energy = 0.0;
  for (int I = 0; I < q.cells(0); ++I)
    for (int J = 0; J < q.cells(1); ++J) {
      {
        const double x0 = q.axis(0).faces()[static_cast<std::size_t>(I)], y0 = q.axis(1).faces()[static_cast<std::size_t>(J)];
        const double x1 = x0 + 0.05, y1 = y0 + 0.05;
        const double f = hydro::ringOverlap(x0, x1, y0, y1, 0.0, 0.3).area / 0.0025;
        if (f <= 0.0 || f >= 1.0 - 1e-12) continue;
        for (int L = 2; L <= 7; ++L) {   // the layers z = -0.15 to 0.15 m
          const std::size_t c = q.index(I, J, L);
          for (int k = 0; k < 3; ++k) {
            const double m = (1.0 - f) * quarter.field(k).alpha[c] * quarter.field(k).rho[c] * q.cellVolume(I, J, L);
            own_mass += m;
            own_energy += m * quarter.field(k).e[c];
          }
        }
      }
  }
  double reached_before = 0.0;
  for (int k = 0; k < 3; ++k) reached_before += q0.mass[static_cast<std::size_t>(k)] - before[static_cast<std::size_t>(k)];
  const auto rep = hydro::mapAxisymmetricToQuarter(axi, quarter);
  const auto b = quarter.totals();
  const auto after = outside(quarter);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(after[static_cast<std::size_t>(k)], before[static_cast<std::size_t>(k)]);
  // each material's mass: the source's per radian times a quarter turn, plus the quarter's own part kept
  double mapped = 0.0, src = 0.0;
  for (int k = 0; k < 3; ++k) {
    mapped += b.mass[static_cast<std::size_t>(k)] - before[static_cast<std::size_t>(k)];
    src += 0.5 * M_PI * a.mass[static_cast<std::size_t>(k)];
  }
  EXPECT_NEAR(mapped, src + own_mass, 1e-12 * mapped);
  EXPECT_GT(own_mass, 0.0);   // the partly covered columns did keep some of their own
  EXPECT_LT(own_mass, reached_before);
  // products: none outside the source, so exactly the source's
  EXPECT_NEAR(b.mass[1], 0.5 * M_PI * a.mass[1], 1e-12 * b.mass[1]);
  // momentum: z is m u_z summed; x and y are each sum m u_r over the quarter turn (int cos = 1)
  EXPECT_NEAR(b.momentum[2], 0.5 * M_PI * a.momentum[1], 1e-10 * std::abs(0.5 * M_PI * a.momentum[1]) + 1e-9);
  EXPECT_NEAR(b.momentum[0], radial, 1e-10 * radial);
  EXPECT_NEAR(b.momentum[1], radial, 1e-10 * radial);
  // energy: the source's total energy (per radian, a quarter turn) plus the quarter's own part kept;
  // the kinetic energy one velocity per column cannot hold is heat
  const double e_outside_before = before[3];
  EXPECT_NEAR(b.total(), 0.5 * M_PI * a.total() + own_energy + e_outside_before, 1e-11 * b.total());
  EXPECT_GT(rep.heatJ(), 0.0);
  EXPECT_NEAR(b.kinetic_energy + rep.heatJ(), 0.5 * M_PI * a.kinetic_energy, 1e-9 * a.kinetic_energy);
  for (int k = 0; k < 3; ++k)
    for (std::size_t c = 0; c < q.totalCells(); ++c)
      if (quarter.field(k).alpha[c] > 0.0) {
        ASSERT_TRUE(std::isfinite(quarter.field(k).rho[c] * quarter.field(k).e[c])) << k << " " << c;
      }
  // a quarter that does not hold the source's radius is refused
  hydro::Solver small(mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 0.2, 4), Axis::uniform(0.0, 0.2, 4), Axis::uniform(-0.25, 0.25, 10)}),
                      mats, o);
  EXPECT_THROW(hydro::mapAxisymmetricToQuarter(axi, small), InputError);
  // z layers that do not nest are refused
  hydro::Solver offset(mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 0.4, 8), Axis::uniform(0.0, 0.4, 8), Axis::uniform(-0.27, 0.23, 10)}),
                       mats, o);
  EXPECT_THROW(hydro::mapAxisymmetricToQuarter(axi, offset), InputError);
}

TEST(Rezone, AxisymmetricIntoAQuarterTurnsVelocityAndStressByEachColumnsMoments) {
  // One material of uniform density with u_r = c r, a swirl u_theta = w r, u_z = 0 and a uniform
  // deviatoric stress (s_rr, s_zz, s_tt, s_rz) over rings much finer than the quarter's columns.
  // A column inside the rings must get the velocity's mean over its area, (c x - w y, c y + w x),
  // and the stress turned by its area's cos 2t and sin 2t: s_xx = s_rr <cos^2> + s_tt <sin^2>, ...
  // (means by a fine midpoint sum over the column). Swapping cos and sin, a sign, or cos 2t fails it.
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  const std::vector<materials::Material> mats{materials::sand(materials::SandInputs::fromWetDensity(1500.0, 0.1), "sand")};
  hydro::Solver axi(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.3, 300), Axis::uniform(0.0, 0.1, 2), Axis{}}), mats, o);
  hydro::Solver quarter(mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 0.3, 6), Axis::uniform(0.0, 0.3, 6), Axis::uniform(0.0, 0.1, 1)}), mats, o);
  const double rho = mats[0].referenceDensity(), c = 50.0, w = 20.0;
  for (auto* s : {&axi, &quarter}) s->paint(0, [](const Vec3&) { return true; }, rho, 100.0);
  const double srr = 3e5, szz = -1e5, stt = -2e5, srz = 4e4;
  const auto& g = axi.grid();
  auto& F = axi.fieldForSetup(0);
  ASSERT_FALSE(F.s[0].empty());
  for (int i = 0; i < g.cells(0); ++i)
    for (int j = 0; j < g.cells(1); ++j) {
      const std::size_t cell = g.index(i, j, 0);
      axi.setVelocity(cell, {c * g.centre(0, i), 0.0, w * g.centre(0, i)});
      F.s[0][cell] = srr;
      F.s[1][cell] = szz;
      F.s[2][cell] = stt;
      F.s[3][cell] = srz;
    }
  hydro::mapAxisymmetricToQuarter(axi, quarter);
  const auto& q = quarter.grid();
  const auto& Q = quarter.field(0);
  for (const auto& [I, J] : {std::pair{0, 0}, std::pair{3, 1}, std::pair{1, 3}, std::pair{2, 2}}) {
    const std::size_t cell = q.index(I, J, 0);
    double ux = 0.0, uy = 0.0, c2 = 0.0, s2 = 0.0;
    const int n = 400;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const double x = 0.05 * (I + (a + 0.5) / n), y = 0.05 * (J + (b + 0.5) / n), r = std::hypot(x, y);
        ux += (c * x - w * y) / (n * n);
        uy += (c * y + w * x) / (n * n);
        c2 += (x * x - y * y) / (r * r) / (n * n);
        s2 += 2.0 * x * y / (r * r) / (n * n);
      }
    EXPECT_NEAR(quarter.velocity(0)[cell], ux, 1e-3 * c * 0.05) << I << "," << J;
    EXPECT_NEAR(quarter.velocity(1)[cell], uy, 1e-3 * c * 0.05) << I << "," << J;
    EXPECT_NEAR(quarter.velocity(2)[cell], 0.0, 1e-9);
    const double tol = 2e-3 * srr;
    EXPECT_NEAR(Q.s[0][cell], 0.5 * srr * (1.0 + c2) + 0.5 * stt * (1.0 - c2), tol) << I << "," << J;
    EXPECT_NEAR(Q.s[1][cell], 0.5 * srr * (1.0 - c2) + 0.5 * stt * (1.0 + c2), tol) << I << "," << J;
    EXPECT_NEAR(Q.s[2][cell], szz, tol);
    EXPECT_NEAR(Q.s[3][cell], 0.5 * (srr - stt) * s2, tol) << I << "," << J;
    EXPECT_GT(Q.s[5][cell], 0.0);   // x-z: s_rz cos t, positive over the quadrant
    EXPECT_GT(Q.s[4][cell], 0.0);   // y-z: s_rz sin t
  }
  // an off-diagonal rectangle's cos 2t and sin 2t against the midpoint sum
  const auto ov = hydro::ringOverlap(0.2, 0.3, 0.05, 0.1, 0.0, 1.0);
  double c2 = 0.0, s2 = 0.0;
  const int n = 1000;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double x = 0.2 + 0.1 * (a + 0.5) / n, y = 0.05 + 0.05 * (b + 0.5) / n, r2 = x * x + y * y;
      c2 += (x * x - y * y) / r2 * 0.005 / (n * n);
      s2 += 2.0 * x * y / r2 * 0.005 / (n * n);
    }
  EXPECT_NEAR(ov.cos2, c2, 1e-9);
  EXPECT_NEAR(ov.sin2, s2, 1e-9);
  // a source taller than the quarter would lose its top: refused
  hydro::Solver low(mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 0.3, 6), Axis::uniform(0.0, 0.3, 6), Axis::uniform(0.0, 0.05, 1)}), mats, o);
  EXPECT_THROW(hydro::mapAxisymmetricToQuarter(axi, low), InputError);
}

TEST(SandEnergyTerm, NoThermalPressureAsLaidFullTermAtLockup) {
  const auto m = materials::sand(materials::SandInputs::fromWetDensity(1370.0, 0.07));
  const auto& model = *m.sand_model;
  EXPECT_GT(model.thermalGamma(), 0.3);
  EXPECT_LT(model.thermalGamma(), 0.7);
  const double e = 1e5;   // J/kg
  // as laid (x = 0): the grains' heat goes into the voids
  const double rho0 = m.referenceDensity();
  EXPECT_DOUBLE_EQ(materials::evaluateEos(m, rho0, e, 0.0).pressure, materials::evaluateEos(m, rho0, 0.0, 0.0).pressure);
  // past lockup: p - C(x) = gamma rho e
  const double x = 1.2 * model.keyNumbers().lockup_strain, rho = rho0 * std::exp(x);
  const double dp = materials::evaluateEos(m, rho, e, x).pressure - materials::evaluateEos(m, rho, 0.0, x).pressure;
  EXPECT_NEAR(dp, model.thermalGamma() * rho * e, 1e-9 * dp);
  // heated compacted sand that unloads rebounds a little along its stiff unloading branch until the
  // total pressure reaches the cutoff: the energy term does not push it back to its laid density
  const auto hot = materials::evaluateEos(m, rho, 2e5, x);
  ASSERT_GT(hot.pressure, 0.0);
  double lo = 0.0, hi = x;   // the strain below x_max where the total pressure reaches the cutoff
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (materials::evaluateEos(m, rho0 * std::exp(x - mid), 2e5, x).pressure > m.sand->tensionCutoff() ? lo : hi) = mid;
  }
  EXPECT_LT(hi, 0.25 * x);   // most of the compaction stays (it went back to x = 0 before the fix)
  // the dry sand's coefficient is the quartz's; water lowers it
  const auto dry = materials::SandModel(materials::SandInputs::fromWetDensity(1280.0, 0.0));
  EXPECT_NEAR(dry.thermalGamma(), materials::QuartzParams{}.gruneisen, 1e-12);
}

TEST(Solver, BodyLoadAtRestEqualsTheFirstStepsImpulseRate) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  hydro::Solver s(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.5, 20), Axis::uniform(-0.25, 0.25, 20), Axis{}}),
                  {materials::air()}, o);
  s.paint(0, [](const Vec3& x) { return x[1] < 0.0; }, 1.225, 101325.0 / (0.4 * 1.225));
  s.paint(0, [](const Vec3& x) { return x[1] >= 0.0; }, 1.225, 2.0 * 101325.0 / (0.4 * 1.225));   // twice the pressure above
  s.setBody([](const Vec3& x) { return x[0] < 0.2 && x[1] > -0.05 && x[1] < 0.05; });
  const double f = s.bodyLoad()[1];
  EXPECT_NEAR(f, -101325.0 * 0.5 * 0.2 * 0.2, 1e-6 * 101325.0);   // net down: 1 atm over the disc (per radian)
  s.step(1e-7);
  EXPECT_NEAR(s.lastBodyImpulse()[1] / 1e-7, f, 1e-3 * std::abs(f));
}

// A pencil carries only the materials present in it (Pencil::mat): here a plate over sand and a
// charge, so that pencils through the plate carry air and sand without the products (index 1), and
// the load they book must land on the run's index of each. Every field of every cell, the load and
// its split by material agree to the bit with a run whose pencils carry every material.
TEST(Solver, PencilsCarryingOnlyTheirMaterialsGiveTheSameResultToTheBit) {
  auto build = [](bool carry_all) {
    hydro::SolverOptions o;
    for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Transmit};
    o.detonation.push_back({{0.0, -0.05, 0.0}, 0.0});
    o.load_reference_pressure = 101325.0;
    o.carry_all_materials = carry_all;
    hydro::Solver s(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.4, 32), Axis::uniform(-0.2, 0.2, 32), Axis{}}),
                    {materials::air(), materials::explosive("C4"), materials::sand(materials::SandInputs::fromWetDensity(1370.0, 0.07))}, o);
    // air at twice the ambient over a plate that rests on compacted sand: both load it from the start
    s.paint(0, [](const Vec3&) { return true; }, 1.225, 2.0 * 101325.0 / (0.4 * 1.225));
    s.paint(2, [](const Vec3& x) { return x[1] < 0.0; }, 1450.0, 0.0);
    s.paint(1, [](const Vec3& x) { return std::hypot(x[0], x[1] + 0.05) < 0.03; }, 1601.0, 9.0e9 / 1601.0);
    s.setBody([](const Vec3& x) { return x[0] < 0.3 && x[1] > 0.0 && x[1] < 0.0125; });
    return s;
  };
  auto lean = build(false), full = build(true);
  // the load along the axis in total, by material beside the plate and within each depth of it
  std::vector<double> load_lean(1 + 3 * (1 + hydro::kNearWallDepths), 0.0), load_full(load_lean.size(), 0.0);
  auto book = [](const hydro::Solver& s, std::vector<double>& load) {
    load[0] += s.lastBodyImpulse()[1];
    for (std::size_t k = 0; k < 3; ++k) {
      load[1 + k] += s.lastBodyImpulseByMaterial()[k][1];
      for (int l = 0; l < hydro::kNearWallDepths; ++l) load[4 + 3 * static_cast<std::size_t>(l) + k] += s.lastBodyImpulseNearWall(l)[k][1];
    }
  };
  for (int n = 0; n < 60; ++n) {
    const double dt = full.nextTimeStep(1.0);
    ASSERT_EQ(lean.nextTimeStep(1.0), dt);
    lean.step(dt);
    full.step(dt);
    book(lean, load_lean);
    book(full, load_full);
  }
  for (int k = 0; k < 3; ++k) {
    const auto &a = lean.field(k), &b = full.field(k);
    EXPECT_EQ(a.alpha, b.alpha) << "material " << k;
    EXPECT_EQ(a.rho, b.rho) << "material " << k;
    EXPECT_EQ(a.e, b.e) << "material " << k;
    EXPECT_EQ(a.h0, b.h0) << "material " << k;
    for (std::size_t q = 0; q < 6; ++q) EXPECT_EQ(a.s[q], b.s[q]) << "material " << k << ", stress " << q;
  }
  EXPECT_FALSE(full.field(2).s[0].empty());   // the sand's stress is there to compare
  // A material absent from a cell holds no energy, history or stress there: gatherPencil does not
  // read them (it writes zeros) and scatterPencil does not clear them again.
  std::size_t absent = 0;
  for (int k = 0; k < 3; ++k) {
    const auto& f = lean.field(k);
    for (std::size_t c = 0; c < f.alpha.size(); ++c) {
      if (f.alpha[c] > 0.0) continue;
      ++absent;
      ASSERT_EQ(f.e[c], 0.0) << "material " << k << ", cell " << c;
      ASSERT_EQ(f.h0[c], 0.0) << "material " << k << ", cell " << c;
      if (f.s[0].empty()) continue;
      for (std::size_t q = 0; q < 6; ++q) {
        ASSERT_EQ(f.s[q][c], 0.0) << "material " << k << ", cell " << c << ", stress " << q;
      }
    }
  }
  EXPECT_GT(absent, 1000u);
  for (int d = 0; d < 2; ++d) EXPECT_EQ(lean.velocity(d), full.velocity(d));
  EXPECT_EQ(load_lean, load_full);
  EXPECT_EQ(lean.energyLedger().boundary_in, full.energyLedger().boundary_in);
  EXPECT_EQ(lean.energyLedger().target_work, full.energyLedger().target_work);
  EXPECT_EQ(lean.energyLedger().gravity_work, full.energyLedger().gravity_work);
  const std::vector<double> by_mat_full(load_full.begin() + 1, load_full.begin() + 4);
  // the case is what it claims: air presses the plate down, sand pushes it up, products are in the run
  EXPECT_LT(by_mat_full[0], 0.0);
  EXPECT_GT(by_mat_full[2], 0.0);
  EXPECT_GT(full.totals().mass[1], 0.0);
}

// A tile of pencils swept through a staged copy of their cells (SolverOptions::sweep_tile) gives the
// same state, load and books to the bit as each pencil reading the mesh itself: in 2D (Cartesian and
// axisymmetric, whose r-sweep is the tiled one) and in 3D, with three materials, mixed cells, the
// sand's strength and a plate with friction that moves the mesh along the vertical axis, whatever
// the tile's width (3 does not divide the rows).
template <class T>
std::vector<std::uint64_t> bitsOf(const T& values) {
  std::vector<std::uint64_t> out;
  for (double v : values) out.push_back(std::bit_cast<std::uint64_t>(v));
  return out;
}

TEST(Solver, TilesOfPencilsGiveTheSameResultToTheBit) {
  struct Layout {
    int dims;
    mesh::Geometry geometry;
  };
  for (const Layout layout : {Layout{2, mesh::Geometry::Cartesian}, Layout{2, mesh::Geometry::Axisymmetric}, Layout{3, mesh::Geometry::Cartesian}}) {
    const int dims = layout.dims, up = 1;
    const std::string where = fmt::format("{}D {}", dims, layout.geometry == mesh::Geometry::Axisymmetric ? "axisymmetric" : "Cartesian");
    auto build = [&](int tile) {
      hydro::SolverOptions o;
      for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Transmit};
      o.detonation.push_back({{0.0, -0.05, 0.0}, 0.0});
      o.load_reference_pressure = 101325.0;
      o.body_friction = 0.3;
      o.gravity[static_cast<std::size_t>(up)] = -9.81;
      o.sweep_tile = tile;
      const int n = dims == 3 ? 20 : 32;
      hydro::Solver s(mesh::Grid(dims, layout.geometry,
                                 {Axis::uniform(0.0, 0.4, n), Axis::uniform(-0.2, 0.2, n), dims == 3 ? Axis::uniform(0.0, 0.4, n) : Axis{}}),
                      {materials::air(), materials::explosive("C4"), materials::sand(materials::SandInputs::fromWetDensity(1370.0, 0.07))}, o);
      s.paint(0, [](const Vec3&) { return true; }, 1.225, 2.0 * 101325.0 / (0.4 * 1.225));
      s.paint(2, [](const Vec3& x) { return x[1] < 0.0; }, 1450.0, 0.0);
      s.paint(1, [](const Vec3& x) { return std::hypot(x[0], x[1] + 0.05, x[2]) < 0.04; }, 1601.0, 9.0e9 / 1601.0);
      s.setBody([](const Vec3& x) { return x[0] < 0.3 && x[1] > 0.0 && x[1] < 0.025; });
      s.moveMeshWithBody(up, -0.1, 0.15);
      s.setBodyVelocity({0.0, 20.0, 0.0});
      return s;
    };
    // the load in total, by material beside the plate and within each depth of it, every component
    auto book = [](const hydro::Solver& s, std::vector<double>& load) {
      std::size_t at = 0;
      for (std::size_t q = 0; q < 3; ++q) {
        load[at++] += s.lastBodyImpulse()[q];
        for (std::size_t k = 0; k < 3; ++k) {
          load[at++] += s.lastBodyImpulseByMaterial()[k][q];
          for (int l = 0; l < hydro::kNearWallDepths; ++l) load[at++] += s.lastBodyImpulseNearWall(l)[k][q];
        }
      }
    };
    const std::size_t terms = 3 * (1 + 3 * (1 + hydro::kNearWallDepths));
    auto ref = build(1);
    std::vector<double> load_ref(terms, 0.0);
    std::vector<std::unique_ptr<hydro::Solver>> tiled;
    std::vector<std::vector<double>> load_tiled;
    for (int tile : {3, 8}) {
      tiled.push_back(std::make_unique<hydro::Solver>(build(tile)));
      load_tiled.emplace_back(terms, 0.0);
    }
    for (int n = 0; n < 40; ++n) {
      const double dt = ref.nextTimeStep(1.0);
      ref.step(dt);
      book(ref, load_ref);
      for (std::size_t t = 0; t < tiled.size(); ++t) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(tiled[t]->nextTimeStep(1.0)), std::bit_cast<std::uint64_t>(dt)) << where << ", step " << n;
        tiled[t]->step(dt);
        book(*tiled[t], load_tiled[t]);
      }
    }
    EXPECT_EQ(ref.stats().staged_tiles, 0) << where;   // width 1 reads the mesh in place
    for (std::size_t t = 0; t < tiled.size(); ++t) {
      const auto& s = *tiled[t];
      const std::string what = fmt::format("{}, tile {}", where, t == 0 ? 3 : 8);
      EXPECT_GT(s.stats().staged_tiles, 0) << what;   // the staged path was taken
      for (int k = 0; k < 3; ++k) {
        const auto &a = ref.field(k), &b = s.field(k);
        EXPECT_EQ(bitsOf(a.alpha), bitsOf(b.alpha)) << what << ", material " << k;
        EXPECT_EQ(bitsOf(a.rho), bitsOf(b.rho)) << what << ", material " << k;
        EXPECT_EQ(bitsOf(a.e), bitsOf(b.e)) << what << ", material " << k;
        EXPECT_EQ(bitsOf(a.h0), bitsOf(b.h0)) << what << ", material " << k;
        for (std::size_t q = 0; q < 6; ++q) EXPECT_EQ(bitsOf(a.s[q]), bitsOf(b.s[q])) << what << ", material " << k << ", stress " << q;
      }
      for (int d = 0; d < 3; ++d) EXPECT_EQ(bitsOf(ref.velocity(d)), bitsOf(s.velocity(d))) << what;
      EXPECT_EQ(bitsOf(load_ref), bitsOf(load_tiled[t])) << what;
      const auto &lr = ref.energyLedger(), &lt = s.energyLedger();
      EXPECT_EQ(bitsOf(std::vector<double>{lr.boundary_in, lr.target_work, lr.gravity_work}),
                bitsOf(std::vector<double>{lt.boundary_in, lt.target_work, lt.gravity_work}))
          << what;
      EXPECT_EQ(bitsOf(lr.folded_mass), bitsOf(lt.folded_mass)) << what;
      EXPECT_EQ(bitsOf(lr.boundary_mass), bitsOf(lt.boundary_mass)) << what;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(ref.bodyOffset()), std::bit_cast<std::uint64_t>(s.bodyOffset())) << what;
    }
    // the case is what it claims: the charge burnt into mixed cells, the sand carries stress, the
    // plate is loaded and has moved the mesh
    const auto& products = ref.field(1);
    std::size_t mixed = 0;
    for (double a : products.alpha) mixed += a > 0.0 && a < 1.0;
    EXPECT_GT(mixed, 10u) << where;
    double stress = 0.0;
    for (double v : ref.field(2).s[0]) stress = std::max(stress, std::abs(v));
    EXPECT_GT(stress, 0.0) << where;
    EXPECT_NE(load_ref[static_cast<std::size_t>(up) * (1 + 3 * (1 + hydro::kNearWallDepths))], 0.0) << where;
    EXPECT_GT(ref.bodyOffset(), 0.0) << where;
  }
}

}  // namespace

// The gather's equation of state over a pencil (one call per material, the kind switched once)
// gives each cell what the call per cell gives, to the bit, and zeros where the material is absent
// (pressure, bulk and history, whatever its fields hold): air, products part-burnt, wet sand
// loaded and unloaded, water.
TEST(EosBatch, SameAsOneCellAtATimeToTheBit) {
  const std::vector<std::pair<materials::Material, std::array<double, 4>>> cases{
      // material, {density range lo, hi, energy range lo, hi}
      {materials::air(), {0.01, 50.0, -1e4, 5e6}},
      {materials::explosive("CompB"), {1.0, 2500.0, 1e5, 8e6}},
      {materials::sand(materials::SandInputs::fromWetDensity(1670.0, 0.22)), {1200.0, 2600.0, 0.0, 1e6}},
      {materials::water(), {900.0, 1500.0, 0.0, 1e6}},
  };
  constexpr int n = 64;
  for (const auto& [mat, range] : cases) {
    std::vector<double> alpha(n), rho(n), e(n), h0(n), history(n), p(n, -1.0), bulk(n, -1.0);
    for (int i = 0; i < n; ++i) {
      const double t = (i * 37 % n) / static_cast<double>(n - 1), u = (i * 11 % n) / static_cast<double>(n - 1);
      alpha[i] = i % 5 == 0 ? 0.0 : (i % 7 == 0 ? 1e-12 : 0.5);
      // an absent material's values are not read: NaN and a stale history give zeros all the same
      const double nan = std::numeric_limits<double>::quiet_NaN();
      rho[i] = alpha[i] > 0.0 ? range[0] + t * (range[1] - range[0]) : nan;
      e[i] = alpha[i] > 0.0 ? range[2] + u * (range[3] - range[2]) : nan;
      // burn fraction for the products; the largest natural strain reached for the sand
      h0[i] = alpha[i] > 0.0 ? (mat.eos == materials::EosKind::Jwl ? u : 0.3 * t) : 0.7;
    }
    history = h0;
    materials::evaluateEosAndHistory(mat, n, alpha.data(), rho.data(), e.data(), history.data(), p.data(), bulk.data());
    for (int i = 0; i < n; ++i) {
      double h_one = -1.0;
      const auto one = alpha[i] > 0.0 ? materials::evaluateEosAndHistory(mat, rho[i], e[i], h0[i], h_one) : materials::EosState{0.0, 0.0};
      if (!(alpha[i] > 0.0)) h_one = 0.0;
      EXPECT_EQ(std::memcmp(&p[i], &one.pressure, sizeof(double)), 0) << mat.name << " cell " << i << ": " << p[i] << " vs " << one.pressure;
      EXPECT_EQ(std::memcmp(&bulk[i], &one.bulk, sizeof(double)), 0) << mat.name << " cell " << i;
      EXPECT_EQ(std::memcmp(&history[i], &h_one, sizeof(double)), 0) << mat.name << " cell " << i;
    }
  }
}

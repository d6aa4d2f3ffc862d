// The sand model against its bounding cases (shared/design/method.md section 2) and the
// properties the hydrocode relies on.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "core/error.hpp"
#include "materials/sand_model.hpp"

using namespace ejecta;
using namespace ejecta::materials;

namespace {
SandInputs dry(double rho_d) {
  SandInputs in;
  in.dry_density = rho_d;
  in.moisture = 0.0;
  return in;
}
SandInputs saturated(double rho_d, double s) {
  SandInputs in;
  in.dry_density = rho_d;
  in.max_porosity = 1.0;   // the bounding cases go to porosity -> 1
  in.moisture = s * (1.0 - rho_d / in.quartz.grain_density) * 1000.0 / rho_d;
  return in;
}
}  // namespace

TEST(SandState, DerivedQuantitiesOfEmi7) {
  const SandModel m(SandInputs::fromWetDensity(1370.0, 0.07));
  const auto& s = m.state();
  EXPECT_NEAR(s.dry_density, 1370.0 / 1.07, 1e-9);
  EXPECT_NEAR(s.porosity, 1.0 - s.dry_density / 2650.0, 1e-12);
  EXPECT_NEAR(s.water_fraction, 0.07 * s.dry_density / 1000.0, 1e-12);
  EXPECT_NEAR(s.saturation, s.water_fraction / s.porosity, 1e-12);
  EXPECT_NEAR(s.air_voids, s.porosity - s.water_fraction, 1e-12);
  EXPECT_NEAR(s.wet_density, 1370.0, 1e-9);
}

TEST(SandBounds, DrySjoboAtItsOwnDensityReproducesTheTable) {
  const SandModel m(dry(kSjoboDensity));
  for (const auto& row : kSjoboTable) {
    if (row.pressure == 0.0) continue;
    const double x_table = std::log(row.density / kSjoboDensity);
    EXPECT_NEAR(m.naturalStrain(row.pressure), x_table, 0.01 * x_table) << row.density;
    EXPECT_NEAR(m.pressureAtNaturalStrain(x_table), row.pressure, 0.01 * row.pressure) << row.density;
  }
}

TEST(SandBounds, DrySandOfOtherDensityEndsAtQuartz) {
  // Rescaled curve: starts at its own density, and at lockup reaches quartz compressed to p_lock.
  for (double rho_d : {1280.0, 1500.0, 1800.0}) {
    const SandModel m(dry(rho_d));
    const double p_lock = m.voidSpring().lockupPressure();
    const double rho_lock = rho_d / (1.0 - m.strain(p_lock));
    const double rho_quartz = 2650.0 / (1.0 - m.inputs().quartz.strain(p_lock));
    EXPECT_NEAR(rho_lock, rho_quartz, 1e-6 * rho_quartz);
  }
}

TEST(SandBounds, ZeroPorosityGivesQuartz) {
  const SandModel m(dry(2650.0 * (1.0 - 1e-9)));
  const QuartzParams q;
  for (double p : {1e6, 1e8, 1e9, 1e10}) EXPECT_NEAR(m.strain(p), q.strain(p), 1e-3 * q.strain(p)) << p;
  EXPECT_NEAR(m.loadingModulus(0.0), q.bulk_modulus, 0.01 * q.bulk_modulus);
}

TEST(SandBounds, PureWaterColumnFollowsTheWaterHugoniot) {
  // Porosity -> 1, saturated: the column is water. Compare with the Rankine-Hugoniot jump of
  // the linear Us-up fit, computed independently: Us = C + S1 up, p = rho0 Us up, eta = up/Us.
  const SandModel m(saturated(1e-3, 1.0));
  const auto w = waterAwg();
  for (double up : {10.0, 100.0, 500.0, 1000.0, 2000.0}) {
    const double us = w.c0 + w.s1 * up;
    const double p = w.rho0 * us * up, eta = up / us;
    EXPECT_NEAR(m.strain(p), eta, 1e-5 * eta) << "up = " << up;
  }
  EXPECT_NEAR(w.etaAsymptote(), 1.0 / w.s1, 1e-9);
}

TEST(SandBounds, SaturatedInitialModulusIsWoods) {
  for (double rho_d : {1300.0, 1490.0, 1700.0}) {
    const SandModel m(saturated(rho_d, 1.0));
    const double n = m.state().porosity;
    const double wood = 1.0 / ((1.0 - n) / 36.6e9 + n / (1000.0 * 1500.0 * 1500.0));
    EXPECT_NEAR(m.loadingModulus(0.0), wood, 0.01 * wood) << rho_d;
    EXPECT_NEAR(m.keyNumbers().wood_bulk_modulus, wood, 1e-9 * wood);
  }
}

TEST(SandBounds, PartialSaturationKneeSitsAtTheAirVoidFraction) {
  for (double s : {0.3, 0.6, 0.9}) {
    const SandModel m(saturated(1500.0, s));
    const double a = m.state().air_voids;
    // Below the knee the soil is soft: at half the air-void strain the pressure is modest...
    const double p_half = m.pressureAtNaturalStrain(-std::log1p(-0.5 * a));
    EXPECT_LT(p_half, 0.1 * m.voidSpring().lockupPressure()) << s;
    // ...the air voids close at lockup, at a strain just past the air-void fraction (plus what
    // the water and quartz have compressed by then)...
    const double p_lock = m.voidSpring().lockupPressure();
    const double eps_lock = m.strain(p_lock);
    EXPECT_GT(eps_lock, a);
    EXPECT_LT(eps_lock, a + 0.1) << s;
    // ...and past it the soil is as stiff as its water and quartz: far stiffer than below the knee.
    EXPECT_GT(m.loadingModulus(p_lock * 1.01), 5.0 * m.loadingModulus(p_half)) << s;
  }
}

TEST(SandCurves, MonotoneContinuousAndUnloadingStiffer) {
  for (double s : {0.0, 0.17, 0.5, 0.9, 1.0}) {
    const SandModel m(saturated(1300.0, s));
    const auto curve = m.sampleLoading(2000);
    for (std::size_t i = 1; i < curve.size(); ++i) {
      EXPECT_GT(curve[i].natural_strain, curve[i - 1].natural_strain) << s;
      // Continuity: a step in pressure makes a proportionate step in strain.
      const double dp = curve[i].pressure - curve[i - 1].pressure;
      const double dx_bound = 2.0 * dp / std::min(curve[i].loading_modulus, curve[i - 1].loading_modulus);
      EXPECT_LE(curve[i].natural_strain - curve[i - 1].natural_strain, dx_bound + 1e-12) << s;
      EXPECT_GE(curve[i].unloading_modulus, curve[i].loading_modulus * (1.0 - 1e-12)) << s;
      EXPECT_GT(curve[i].loading_modulus, 0.0);
    }
  }
}

TEST(SandStrength, BilinearWithPlateauFallingWithSaturation) {
  double previous = INFINITY;
  for (double s : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) {
    const SandModel m(saturated(1400.0, s));
    const double plateau = m.yieldPlateau();
    EXPECT_LT(plateau, previous) << s;
    previous = plateau;
    EXPECT_DOUBLE_EQ(m.yieldStrength(1e5), std::min(kSjoboFrictionSlope * 1e5, plateau));
    EXPECT_DOUBLE_EQ(m.yieldStrength(100e9), plateau);
    EXPECT_DOUBLE_EQ(m.yieldStrength(-1e3), 0.0);
  }
  EXPECT_DOUBLE_EQ(SandModel(saturated(1400.0, 1.0)).yieldPlateau(), 0.0);
  // Dry: the plateau is the friction strength at lockup.
  const SandModel d(dry(1400.0));
  EXPECT_NEAR(d.yieldPlateau(), kSjoboFrictionSlope * d.voidSpring().lockupPressure(), 1e-6 * d.yieldPlateau());
}

TEST(SandStrength, ShearModulusAnchoredToSjobo) {
  EXPECT_NEAR(SandModel(dry(kSjoboDensity)).shearModulus(0.0), kSjoboShearModulus, 1e-9 * kSjoboShearModulus);
  EXPECT_LT(SandModel(dry(1300.0)).shearModulus(0.0), kSjoboShearModulus);   // looser, softer
}

// Compaction stiffens the skeleton up to the cap: quartz's own by default, or the input's below it;
// below the cap nothing changes.
TEST(SandStrength, ShearModulusCappedAtQuartzOrTheInput) {
  SandInputs in = SandInputs::fromWetDensity(1370.0, 0.07);
  const SandModel quartz_capped(in);
  EXPECT_DOUBLE_EQ(quartz_capped.shearModulus(10e9), in.quartz.shear_modulus);
  in.shear_modulus_cap = 10e9;
  const SandModel capped(in);
  EXPECT_DOUBLE_EQ(capped.shearModulus(10e9), 10e9);
  EXPECT_DOUBLE_EQ(capped.shearModulus(0.0), quartz_capped.shearModulus(0.0));
  EXPECT_LT(capped.shearModulus(0.0), 10e9);
  in.shear_modulus_cap = 1e6;   // below the range (1e8 Pa up to quartz's)
  EXPECT_THROW(SandModel{in}, InputError);
  in.shear_modulus_cap = 50e9;
  EXPECT_THROW(SandModel{in}, InputError);
}

TEST(SandInputs, RejectsBadValuesNamingTheField) {
  auto field_of = [](const SandInputs& in) {
    try {
      SandModel m(in);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("none");
  };
  SandInputs in;
  in.dry_density = 1670.0;
  in.moisture = 0.30;
  EXPECT_EQ(field_of(in), "moisture");   // saturation over 100%
  in = SandInputs{};
  in.dry_density = 2650.0;
  EXPECT_EQ(field_of(in), "dry-density");
  in.dry_density = -5.0;
  EXPECT_EQ(field_of(in), "dry-density");
  in.dry_density = NAN;
  EXPECT_EQ(field_of(in), "dry-density");
  in = SandInputs{};
  in.moisture = -0.01;
  EXPECT_EQ(field_of(in), "moisture");
  in = SandInputs{};
  in.tension_cutoff = 5.0;
  EXPECT_EQ(field_of(in), "tension-cutoff");
  EXPECT_THROW(waterEosByName("seawater"), InputError);
}

TEST(SandPointEos, MatchesTheModelOnLoading) {
  const SandModel m(SandInputs::fromWetDensity(1490.0, 0.14));
  const SandPointEos eos(m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(1e-4, 0.9 * eos.tableTop());
  for (int i = 0; i < 300; ++i) {
    const double x = u(rng);
    const auto r = eos.evaluate(x, x);
    const double p = m.pressureAtNaturalStrain(x);
    EXPECT_NEAR(r.pressure, p, 5e-3 * p + 1e3) << x;
    EXPECT_NEAR(r.bulk_modulus, m.loadingModulus(p), 0.02 * m.loadingModulus(p)) << x;
  }
}

TEST(SandPointEos, UnloadsElasticallyAndReloadsOnTheSamePath) {
  const SandModel m(SandInputs::fromWetDensity(1370.0, 0.07));
  const SandPointEos eos(m);
  const double x_max = 0.3;
  const auto top = eos.evaluate(x_max, x_max);
  const double k_u = m.unloadingModulus(top.pressure);
  const double dx = 1e-4;
  const auto down = eos.evaluate(x_max - dx, x_max);
  EXPECT_NEAR(down.pressure, top.pressure - k_u * dx, 0.02 * k_u * dx);
  EXPECT_GE(down.bulk_modulus, top.bulk_modulus);
  EXPECT_DOUBLE_EQ(eos.evaluate(x_max, x_max).pressure, top.pressure);   // reload meets the curve
  // Far below: clamped at the tension cutoff.
  EXPECT_DOUBLE_EQ(eos.evaluate(-0.5, x_max).pressure, m.inputs().tension_cutoff);
  EXPECT_DOUBLE_EQ(eos.evaluate(-0.5, 0.0).pressure, m.inputs().tension_cutoff);
}

// The two laws of the hydrocode's shear modulus: by the compaction seen, G stays where the loading
// took it after the sand unloads; by the pressure now, unloaded sand is as soft as sand at that
// pressure on the loading curve (the pore air's pressure carries no shear), and on the loading
// curve itself the two agree.
TEST(SandPointEos, ShearModulusFollowsTheCompactionSeenOrThePressureNow) {
  SandInputs in = SandInputs::fromWetDensity(1370.0, 0.07);
  in.pore_pressure = 101325.0;
  in.shear_follows_pressure = false;
  const SandModel by_compaction(in);
  in.shear_follows_pressure = true;
  const SandModel by_pressure(in);
  const SandPointEos c(by_compaction), p(by_pressure);
  const double x_max = 0.3, p_top = by_compaction.pressureAtNaturalStrain(x_max) + in.pore_pressure;
  const double g_top = by_compaction.shearModulus(p_top - in.pore_pressure);
  EXPECT_NEAR(c.shearModulus(x_max, p_top), g_top, 0.02 * g_top);
  EXPECT_NEAR(p.shearModulus(x_max, p_top), g_top, 0.02 * g_top);   // loading: the same
  const double g0 = by_compaction.shearModulus(0.0);
  EXPECT_GT(g_top, 100.0 * g0);   // the loading took it far up: the test tells the laws apart
  EXPECT_NEAR(c.shearModulus(x_max, in.pore_pressure), c.shearModulus(x_max, p_top), 1e-12 * g_top);   // stays
  EXPECT_NEAR(p.shearModulus(x_max, in.pore_pressure), g0, 1e-6 * g0);   // back at the laid sand's
  EXPECT_NEAR(p.shearModulus(x_max, -1e5), g0, 1e-6 * g0);               // tension: no softer
  for (const double pe : {1e5, 3e6, 1e8, 2e9}) {
    const double g = by_compaction.shearModulus(pe);
    EXPECT_NEAR(p.shearModulus(x_max, pe + in.pore_pressure), g, 0.01 * g) << pe;
  }
}

// Poisson's ratio of the skeleton, nu = (3 K_u - 2 G) / (2 (3 K_u + G)), on the loading curve: the
// bound holds it at or above min_poisson_ratio where the skeleton's compliance alone would give
// nu < 0 (closing air voids), leaves the laid sand alone (Sjobo's measured G0), and the quartz cap
// still holds at the top.
TEST(SandModel, ShearModulusKeepsPoissonsRatioAtOrAboveTheBound) {
  const auto poisson = [](const CurvePoint& c) {
    return (3.0 * c.unloading_modulus - 2.0 * c.shear_modulus) / (2.0 * (3.0 * c.unloading_modulus + c.shear_modulus));
  };
  for (const double w : {0.0, 0.07, 0.14, 0.22}) {
    SandInputs in = SandInputs::fromWetDensity(1370.0 * (1.0 + w) / 1.07, w);
    const SandModel bounded(in);
    in.min_poisson_ratio = 0.0;
    const SandModel loose(in);
    double nu_min_bounded = 1.0, nu_min_loose = 1.0;
    for (const auto& c : bounded.sampleLoading(200)) {
      nu_min_bounded = std::min(nu_min_bounded, poisson(c));
      EXPECT_LE(c.shear_modulus, bounded.shearModulusCap()) << c.pressure;
    }
    for (const auto& c : loose.sampleLoading(200)) nu_min_loose = std::min(nu_min_loose, poisson(c));
    EXPECT_GE(nu_min_bounded, kSjoboPoisson - 1e-12) << w;
    EXPECT_LT(nu_min_loose, kSjoboPoisson - 0.1) << w;   // without the bound it would fall well below
  }
  EXPECT_DOUBLE_EQ(SandModel(dry(kSjoboDensity)).shearModulus(0.0), kSjoboShearModulus);   // laid: untouched
  SandInputs bad = dry(kSjoboDensity);
  bad.min_poisson_ratio = 0.5;
  try {
    SandModel m(bad);
    ADD_FAILURE() << "a Poisson's ratio of 0.5 leaves no shear modulus: it must be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "min-poisson-ratio");
  }
}

TEST(SharedData, EmbeddedSjoboTableMatchesSharedCsv) {
  std::ifstream f(std::string(EJECTA_SHARED_DATA_DIR) + "/sjobo_sand_compaction.csv");
  if (!f) GTEST_SKIP() << "shared/data not beside the project";
  std::string line;
  std::size_t i = 0;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("density", 0) == 0) continue;
    std::stringstream ss(line);
    std::string rho, lnv, p;
    std::getline(ss, rho, ',');
    std::getline(ss, lnv, ',');
    std::getline(ss, p, ',');
    ASSERT_LT(i, kSjoboTable.size());
    EXPECT_DOUBLE_EQ(std::stod(rho), kSjoboTable[i].density);
    EXPECT_NEAR(std::stod(p) * 1e6, kSjoboTable[i].pressure, 1.0);
    ++i;
  }
  EXPECT_EQ(i, kSjoboTable.size());
}

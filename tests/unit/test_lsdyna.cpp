// The keyword file: card order and field widths as LS-DYNA reads them, read back and compared.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "io/lsdyna.hpp"

using namespace ejecta;

namespace {
struct Written {
  std::string text;
  std::vector<std::pair<std::string, std::vector<std::string>>> blocks;
};
Written writeFor(const materials::SandModel& m, const std::string& units) {
  std::ostringstream os;
  io::writeLsdynaKeywords(os, m, {io::lsdynaUnitsByName(units), 7, 9, "test"});
  std::istringstream is(os.str());
  return {os.str(), io::readKeywordBlocks(is)};
}
}  // namespace

TEST(Lsdyna, CardOrderAndWidths) {
  const materials::SandModel m(materials::SandInputs::fromWetDensity(1370.0, 0.07));
  const auto w = writeFor(m, "kg-m-s");
  ASSERT_EQ(w.text.rfind("*KEYWORD", 0), 0u);
  ASSERT_GE(w.text.size(), 5u);
  EXPECT_EQ(w.text.substr(w.text.size() - 5), "*END\n");
  std::vector<std::string> names;
  for (auto& b : w.blocks) names.push_back(b.first);
  EXPECT_EQ(names, (std::vector<std::string>{"KEYWORD", "TITLE", "MAT_PSEUDO_TENSOR", "EOS_TABULATED_COMPACTION", "END"}));
  const auto& mat = w.blocks[2].second;
  const auto& eos = w.blocks[3].second;
  ASSERT_EQ(mat.size(), 7u);   // 3 cards of parameters, 2 of pressures, 2 of yields
  ASSERT_EQ(eos.size(), 9u);   // 1 card of ids, 8 of tables
  for (const auto& l : mat) {
    EXPECT_LE(l.size(), 80u);
    EXPECT_EQ(l.size() % 10, 0u) << l;
    for (std::size_t f = 0; f < l.size() / 10; ++f) EXPECT_EQ(l[f * 10], ' ') << "fields must not touch: " << l;
  }
  EXPECT_EQ(eos[0].size(), 40u);
  for (std::size_t i = 1; i < eos.size(); ++i) EXPECT_EQ(eos[i].size(), 80u) << eos[i];   // 5 x 16
  EXPECT_EQ(io::cardField(mat[0], 0, 10), 7.0);
  EXPECT_EQ(io::cardField(eos[0], 0, 10), 9.0);
  EXPECT_NEAR(io::cardField(eos[0], 1, 10), m.thermalGamma(), 1e-4);   // GAMA of the energy term
}

TEST(Lsdyna, ReadBackMatchesTheModel) {
  const materials::SandModel m(materials::SandInputs::fromWetDensity(1490.0, 0.14));
  for (const auto& [units, fd, fp] : {std::tuple{"kg-m-s", 1.0, 1.0}, std::tuple{"g-mm-ms", 1e-6, 1e-6},
                                      std::tuple{"t-mm-s", 1e-12, 1e-6}}) {
    const auto w = writeFor(m, units);
    const auto& mat = w.blocks[2].second;
    const auto& eos = w.blocks[3].second;
    EXPECT_NEAR(io::cardField(mat[0], 1, 10) / fd, 1490.0, 1e-4 * 1490.0) << units;
    EXPECT_NEAR(io::cardField(mat[0], 2, 10) / fp, m.keyNumbers().initial_shear_modulus, 1e-4 * 5e7) << units;
    // Yield table: 16 points on the model's curve.
    for (int i = 0; i < 16; ++i) {
      const double p = io::cardField(mat[3 + i / 8], i % 8, 10) / fp;
      const double y = io::cardField(mat[5 + i / 8], i % 8, 10) / fp;
      EXPECT_NEAR(y, m.yieldStrength(p), 2e-5 * m.yieldPlateau() + 1.0) << units << " point " << i;
    }
    // Compaction table: ln(V/V0) starts at 0, negative and decreasing; pressures and unloading
    // moduli are the model's at those strains.
    double previous = 1.0;
    bool lockup_listed = false;
    const double x_lock = m.keyNumbers().lockup_strain;
    for (int i = 0; i < 10; ++i) {
      const double ev = io::cardField(eos[1 + i / 5], i % 5, 16);
      const double c = io::cardField(eos[3 + i / 5], i % 5, 16) / fp;
      const double t = io::cardField(eos[5 + i / 5], i % 5, 16);
      const double k = io::cardField(eos[7 + i / 5], i % 5, 16) / fp;
      if (i == 0) {
        EXPECT_EQ(ev, 0.0);
      } else {
        EXPECT_LT(ev, previous) << units;
        EXPECT_LT(ev, 0.0);
      }
      previous = ev;
      const double p_model = m.pressureAtNaturalStrain(-ev);
      EXPECT_NEAR(c, p_model, 1e-4 * p_model + 1.0) << units << " point " << i;
      EXPECT_NEAR(k, m.unloadingModulus(p_model), 1e-4 * k) << units;
      EXPECT_NEAR(t, m.thermalFactor(-ev), 1e-5 * (1.0 + t));   // the energy term's T(ev)
      lockup_listed = lockup_listed || std::abs(-ev - x_lock) < 0.01;
    }
    EXPECT_TRUE(lockup_listed) << "lockup point must be in the table";
  }
}

TEST(Lsdyna, TenPointsRepresentTheCurve) {
  // Piecewise-linear interpolation of the 10 points stays within 25% in pressure (+0.1 MPa)
  // of the model over the tabulated range, for dry, moist and saturated soils.
  for (double w : {0.0, 0.07, 0.22}) {
    const materials::SandModel m(materials::SandInputs::fromWetDensity(1370.0 * (1 + w), w));
    const auto t = io::chooseCompactionPoints(m, 10);
    ASSERT_EQ(t.ln_v.size(), 10u);
    for (std::size_t s = 0; s + 1 < t.ln_v.size(); ++s) {
      for (int k = 1; k < 10; ++k) {
        const double x = -(t.ln_v[s] + (t.ln_v[s + 1] - t.ln_v[s]) * k / 10.0);
        const double p_lin = t.pressure[s] + (t.pressure[s + 1] - t.pressure[s]) * k / 10.0;
        const double p = m.pressureAtNaturalStrain(x);
        EXPECT_LT(std::abs(std::log((p_lin + 1e5) / (p + 1e5))), std::log(1.25)) << "w=" << w << " x=" << x;
      }
    }
  }
}

TEST(Lsdyna, FieldFitting) {
  EXPECT_EQ(io::fitField(0.0, 10), "       0.0");
  EXPECT_EQ(io::fitField(7.0, 10), "        7.");
  EXPECT_EQ(io::fitField(-0.123456789012, 16).size(), 16u);
  EXPECT_EQ(io::fitField(2.149e11, 10).size(), 10u);
  EXPECT_EQ(io::fitField(102970719.7, 10), " 1.02971e8");
  EXPECT_EQ(io::fitField(-1.5e-7, 10), "   -1.5e-7");
  EXPECT_NEAR(std::stod(io::fitField(2.149226e11, 10)), 2.149226e11, 1e-3 * 2.149e11);
  EXPECT_THROW(io::fitField(NAN, 10), std::invalid_argument);
  EXPECT_THROW(io::lsdynaUnitsByName("furlongs"), InputError);
}

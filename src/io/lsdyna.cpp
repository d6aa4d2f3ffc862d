#include "io/lsdyna.hpp"

#include <algorithm>
#include <cmath>
#include <istream>
#include <stdexcept>

#include <fmt/format.h>

#include "core/error.hpp"
#include "ejecta/build_info.hpp"

namespace ejecta::io {

LsdynaUnits lsdynaUnitsByName(const std::string& name) {
  if (name == "kg-m-s") return {name, 1.0, 1.0, "kg/m3", "Pa"};
  if (name == "g-mm-ms") return {name, 1e-6, 1e-6, "g/mm3", "MPa"};
  if (name == "t-mm-s") return {name, 1e-12, 1e-6, "t/mm3", "MPa"};
  throw InputError("units", "unknown unit system '" + name + "' (valid: kg-m-s, g-mm-ms, t-mm-s)");
}

std::string fitField(double v, int width) {
  if (!std::isfinite(v)) throw std::invalid_argument("fitField: non-finite value");
  if (v == 0.0) return fmt::format("{:>{}}", "0.0", width);
  // At most width-1 characters, so that adjacent fields never touch; at most 9 significant digits.
  for (int digits = std::min(width - 2, 9); digits >= 1; --digits) {
    std::string s = fmt::format("{:.{}g}", v, digits);
    // Compact exponent (e+08 -> e8): Fortran list and fixed reads accept it, and it buys digits.
    if (auto e = s.find('e'); e != std::string::npos) {
      std::string mant = s.substr(0, e), ex = s.substr(e + 1);
      const bool neg = ex[0] == '-';
      ex = ex.substr(ex.find_first_not_of("+-"));
      ex.erase(0, std::min(ex.find_first_not_of('0'), ex.size() - 1));
      if (mant.find('.') == std::string::npos) mant += ".";
      s = mant + "e" + (neg ? "-" : "") + ex;
    }
    if (s.find_first_of(".e") == std::string::npos) s += ".";   // LS-DYNA reads reals with a point
    if (static_cast<int>(s.size()) < width) return fmt::format("{:>{}}", s, width);
  }
  throw std::invalid_argument(fmt::format("fitField: {} does not fit in {} characters", v, width));
}

CompactionTable chooseCompactionPoints(const materials::SandModel& model, int count) {
  // Dense reference curve in natural strain up to a pressure well past lockup (quartz branch).
  const double p_lock = model.voidSpring().lockupPressure();
  const double p_end = std::max(5e9, 4.0 * p_lock);
  const int m = 1500;
  std::vector<double> xs(m), ps(m);
  for (int j = 0; j < m; ++j) {
    ps[j] = j == 0 ? 0.0 : 1e4 * std::pow(p_end / 1e4, double(j - 1) / (m - 2));
    xs[j] = model.naturalStrain(ps[j]);
  }
  auto lock_it = std::lower_bound(ps.begin(), ps.end(), p_lock);
  std::vector<int> chosen{0, static_cast<int>(lock_it - ps.begin()), m - 1};
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  const double p_ref = 1e5;   // Pa: errors are judged on log(p + 0.1 MPa)
  while (static_cast<int>(chosen.size()) < count) {
    double worst = -1.0;
    int worst_j = -1;
    for (std::size_t s = 0; s + 1 < chosen.size(); ++s) {
      const int a = chosen[s], b = chosen[s + 1];
      for (int j = a + 1; j < b; ++j) {
        const double t = (xs[j] - xs[a]) / (xs[b] - xs[a]);
        const double p_lin = ps[a] + t * (ps[b] - ps[a]);
        const double err = std::abs(std::log((p_lin + p_ref) / (ps[j] + p_ref)));
        if (err > worst) {
          worst = err;
          worst_j = j;
        }
      }
    }
    if (worst_j < 0) break;
    chosen.insert(std::upper_bound(chosen.begin(), chosen.end(), worst_j), worst_j);
  }
  CompactionTable t;
  for (int j : chosen) {
    t.ln_v.push_back(-xs[j]);
    t.pressure.push_back(ps[j]);
    t.unloading.push_back(model.unloadingModulus(ps[j]));
  }
  return t;
}

YieldTable chooseYieldPoints(const materials::SandModel& model) {
  // 16 points: the friction branch up to the knee on 6, then the plateau out to 1000 x knee.
  YieldTable t;
  const double slope = model.inputs().friction_slope;
  double knee = slope > 0.0 ? model.yieldPlateau() / slope : 0.0;
  if (!(knee > 0.0)) knee = 1e5;   // no friction branch: plateau from 0.1 MPa on
  for (int i = 0; i < 6; ++i) t.pressure.push_back(knee * i / 5.0);
  for (int i = 1; i <= 10; ++i) t.pressure.push_back(knee * std::pow(1000.0, i / 10.0));
  for (double p : t.pressure) t.yield.push_back(model.yieldStrength(p));
  return t;
}

namespace {
void card(std::ostream& os, const std::vector<double>& values, int width) {
  for (double v : values) os << fitField(v, width);
  os << '\n';
}
}  // namespace

void writeLsdynaKeywords(std::ostream& os, const materials::SandModel& model, const KeywordOptions& o) {
  const auto& s = model.state();
  const auto k = model.keyNumbers();
  const double fd = o.units.density_factor, fp = o.units.pressure_factor;
  const auto& in = model.inputs();
  os << "*KEYWORD\n";
  os << fmt::format("$ Sand model written by ejecta {}: two-input three-spring model\n", build_info::version);
  os << fmt::format("$ (air-void skeleton from dry Sjobo sand, quartz, water) with a saturation-dependent\n");
  os << fmt::format("$ yield plateau. Units: {} (density {}, pressure {}).\n", o.units.name, o.units.density_unit,
                    o.units.pressure_unit);
  if (!o.description.empty()) os << "$ Inputs: " << o.description << '\n';
  os << fmt::format("$   dry density {:.6g} kg/m3, moisture {:.4g}%, wet density {:.6g} kg/m3\n", s.dry_density,
                    100 * s.moisture, s.wet_density);
  os << fmt::format("$   porosity {:.4f}, water fraction {:.4f}, saturation {:.2f}%, air voids {:.4f}\n", s.porosity,
                    s.water_fraction, 100 * s.saturation, s.air_voids);
  os << fmt::format("$   grain density {:g} kg/m3, quartz K0 {:g} GPa, K' {:g}; water EOS set '{}' (C {:g} m/s, "
                    "S1 {:g}, S2 {:g})\n",
                    in.quartz.grain_density, in.quartz.bulk_modulus / 1e9, in.quartz.dK_dp, in.water.name,
                    in.water.c0, in.water.s1, in.water.s2);
  os << fmt::format("$   yield plateau {:.4g} MPa, friction slope {:g}, tension cutoff {:g} kPa\n",
                    model.yieldPlateau() / 1e6, in.friction_slope, in.tension_cutoff / 1e3);
  os << "*TITLE\n" << fmt::format("ejecta sand rho_d={:g} kg/m3 w={:.4g}%", s.dry_density, 100 * s.moisture) << '\n';

  os << "*MAT_PSEUDO_TENSOR\n";
  os << "$#     MID        RO         G        PR\n";
  os << fmt::format("{:>10}", o.material_id) << fitField(s.wet_density * fd, 10)
     << fitField(k.initial_shear_modulus * fp, 10) << fitField(in.poisson, 10) << '\n';
  os << "$#    SIGF        A0        A1        A2       A0F       A1F        B1       PER\n";
  card(os, {-in.tension_cutoff * fp, 0, 0, 0, 0, 0, 0, 0}, 10);
  os << "$#      ER       PRR      SIGY      ETAN       LCP       LCR\n";
  card(os, {0, 0, 0, 0, 0, 0}, 10);
  const auto y = chooseYieldPoints(model);
  std::vector<double> xp, ys;
  for (double p : y.pressure) xp.push_back(p * fp);
  for (double v : y.yield) ys.push_back(v * fp);
  os << "$#      X1        X2        X3        X4        X5        X6        X7        X8\n";
  card(os, {xp.begin(), xp.begin() + 8}, 10);
  os << "$#      X9       X10       X11       X12       X13       X14       X15       X16\n";
  card(os, {xp.begin() + 8, xp.end()}, 10);
  os << "$#     YS1       YS2       YS3       YS4       YS5       YS6       YS7       YS8\n";
  card(os, {ys.begin(), ys.begin() + 8}, 10);
  os << "$#     YS9      YS10      YS11      YS12      YS13      YS14      YS15      YS16\n";
  card(os, {ys.begin() + 8, ys.end()}, 10);

  const auto c = chooseCompactionPoints(model, 10);
  os << "*EOS_TABULATED_COMPACTION\n";
  os << "$#   EOSID      GAMA        E0        V0\n";
  // GAMA and T(ev): the energy term p = C(ev) + GAMA T(ev) E, E per unit reference volume (SandModel::thermalGamma)
  os << fmt::format("{:>10}", o.eos_id) << fitField(model.thermalGamma(), 10) << fitField(0.0, 10) << fitField(1.0, 10) << '\n';
  auto five = [&](const char* head, const std::vector<double>& v, double f, int first) {
    os << "$#" << fmt::format("{:>14}", fmt::format("{}{}", head, first));
    for (int i = first + 1; i < first + 5; ++i) os << fmt::format("{:>16}", fmt::format("{}{}", head, i));
    os << '\n';
    std::vector<double> out;
    for (int i = first - 1; i < first + 4; ++i) out.push_back(v[i] * f);
    card(os, out, 16);
  };
  five("EV", c.ln_v, 1.0, 1);
  five("EV", c.ln_v, 1.0, 6);
  five("C", c.pressure, fp, 1);
  five("C", c.pressure, fp, 6);
  std::vector<double> thermal;
  for (const double lv : c.ln_v) thermal.push_back(model.thermalFactor(-lv));   // ev = ln(V/V0) = -x
  five("T", thermal, 1.0, 1);
  five("T", thermal, 1.0, 6);
  five("K", c.unloading, fp, 1);
  five("K", c.unloading, fp, 6);
  os << "*END\n";
}

std::vector<std::pair<std::string, std::vector<std::string>>> readKeywordBlocks(std::istream& is) {
  std::vector<std::pair<std::string, std::vector<std::string>>> blocks;
  std::string line;
  while (std::getline(is, line)) {
    if (line.empty() || line[0] == '$') continue;
    if (line[0] == '*') {
      blocks.emplace_back(line.substr(1, line.find_last_not_of(" \r") ), std::vector<std::string>{});
    } else if (!blocks.empty()) {
      blocks.back().second.push_back(line);
    }
  }
  return blocks;
}

double cardField(const std::string& line, int index, int width) {
  const std::size_t start = static_cast<std::size_t>(index) * width;
  if (start >= line.size()) throw std::out_of_range(fmt::format("card has no field {}", index + 1));
  const std::string field = line.substr(start, static_cast<std::size_t>(width));
  std::size_t used = 0;
  const double v = std::stod(field, &used);
  if (field.find_first_not_of(' ', used) != std::string::npos)
    throw std::invalid_argument(fmt::format("field {} '{}' is not one number", index + 1, field));
  return v;
}

}  // namespace ejecta::io

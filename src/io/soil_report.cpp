#include "io/soil_report.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "ejecta/build_info.hpp"
#include "io/lsdyna.hpp"

namespace ejecta::io {

using nlohmann::json;
using materials::SandModel;

namespace {
constexpr int kCurveSamples = 240;

json keyNumbersJson(const SandModel& m) {
  const auto k = m.keyNumbers();
  return {{"initial_bulk_modulus_Pa", k.initial_bulk_modulus},
          {"initial_unloading_modulus_Pa", k.initial_unloading_modulus},
          {"initial_shear_modulus_Pa", k.initial_shear_modulus},
          {"lockup_pressure_Pa", k.lockup_pressure},
          {"lockup_natural_strain", k.lockup_strain},
          {"lockup_density_kg_m3", k.lockup_density},
          {"yield_plateau_Pa", k.yield_plateau},
          {"friction_knee_pressure_Pa", k.friction_knee_pressure},
          {"loading_wave_speed_m_s", k.loading_wave_speed},
          {"elastic_wave_speed_m_s", k.elastic_wave_speed},
          {"wood_bulk_modulus_Pa", k.wood_bulk_modulus},
          {"thermal_gamma", m.thermalGamma()}};
}

const char* lawName(materials::PlateauParams::Law law) {
  return law == materials::PlateauParams::Law::Fixed ? "fixed" : "effective-stress";
}
}  // namespace

json soilJson(const SandModel& m) {
  const auto& in = m.inputs();
  const auto& s = m.state();
  json j;
  j["ejecta_version"] = build_info::version;
  j["model"] = "two-input three-spring sand (shared/design/method.md section 2)";
  j["inputs"] = {{"dry_density_kg_m3", in.dry_density},
                 {"moisture", in.moisture},
                 {"grain_density_kg_m3", in.quartz.grain_density},
                 {"quartz_bulk_modulus_Pa", in.quartz.bulk_modulus},
                 {"quartz_dK_dp", in.quartz.dK_dp},
                 {"quartz_shear_modulus_Pa", in.quartz.shear_modulus},
                 {"shear_modulus_cap_Pa", m.shearModulusCap()},
                 {"shear_modulus_law", in.shear_follows_pressure ? "pressure" : "compaction"},
                 {"min_poisson_ratio", in.min_poisson_ratio},
                 {"water_eos", {{"name", in.water.name}, {"rho0_kg_m3", in.water.rho0}, {"C_m_s", in.water.c0},
                                {"S1", in.water.s1}, {"S2", in.water.s2}, {"S3", in.water.s3},
                                {"gamma0", in.water.gamma0}, {"status", in.water.status}}},
                 {"friction_slope", in.friction_slope},
                 {"tension_cutoff_Pa", in.tension_cutoff},
                 {"poisson_ratio", in.poisson},
                 {"plateau", {{"law", lawName(in.plateau.law)}, {"scale", in.plateau.scale},
                              {"residual_Pa", in.plateau.residual}, {"fixed_Pa", in.plateau.fixed}}}};
  j["state"] = {{"dry_density_kg_m3", s.dry_density}, {"moisture", s.moisture}, {"wet_density_kg_m3", s.wet_density},
                {"porosity", s.porosity}, {"water_fraction", s.water_fraction}, {"saturation", s.saturation},
                {"air_voids", s.air_voids}};
  j["key_numbers"] = keyNumbersJson(m);
  j["provenance"] = {
      {"sjobo_compaction", "Laine & Sandvik 2001 via LSTC decks: verified, except the 1740 kg/m3 row (recalled)"},
      {"sjobo_unloading", "recalled, provisional: clamped so unloading is never softer than loading"},
      {"sjobo_shear_modulus", "76.9 MPa at 1674 kg/m3, verified"},
      {"min_poisson_ratio", "ours: the Sjobo sand's measured Poisson's ratio (verified) as a lower bound, so G never exceeds what it gives on K_u (docs/sand-model.md)"},
      {"shear_modulus_cap", "ours: the quartz grains' own shear modulus unless given (compacted, crushed sand lies below it; not measured: an input with a sensitivity, docs/sand-model.md)"},
      {"quartz_dK_dp", "ours: 6 (alpha-quartz compression studies give 4-6)"},
      {"yield_plateau", "ours: effective-stress law, see docs/sand-model.md"},
      {"thermal_gamma", "ours: quartz 0.66 (alpha K / rho c_v, recalled handbook values) and water 0.28 (AWG), Reuss-weighted at equal temperature; see docs/sand-model.md"}};
  json curve = json::array();
  for (const auto& c : m.sampleLoading(kCurveSamples))
    curve.push_back({{"pressure_Pa", c.pressure}, {"strain", c.strain}, {"natural_strain", c.natural_strain},
                     {"density_kg_m3", c.density}, {"loading_modulus_Pa", c.loading_modulus},
                     {"unloading_modulus_Pa", c.unloading_modulus}, {"shear_modulus_Pa", c.shear_modulus}});
  j["loading_curve"] = curve;
  const auto y = chooseYieldPoints(m);
  j["yield_curve"] = {{"pressure_Pa", y.pressure}, {"yield_Pa", y.yield}};
  const auto t = chooseCompactionPoints(m);
  j["lsdyna_compaction_points"] = {{"ln_v", t.ln_v}, {"pressure_Pa", t.pressure}, {"unloading_modulus_Pa", t.unloading}};
  return j;
}

json soilPlotData(const SandModel& m) {
  auto curveOf = [](const SandModel& s, const std::string& label) {
    json c{{"label", label}, {"natural_strain", json::array()}, {"pressure_MPa", json::array()},
           {"yield_pressure_MPa", json::array()}, {"yield_MPa", json::array()}};
    for (const auto& pt : s.sampleLoading(kCurveSamples)) {
      c["natural_strain"].push_back(pt.natural_strain);
      c["pressure_MPa"].push_back(pt.pressure / 1e6);
    }
    for (int i = 0; i <= 200; ++i) {
      const double p = 1.5e9 * i / 200.0;
      c["yield_pressure_MPa"].push_back(p / 1e6);
      c["yield_MPa"].push_back(s.yieldStrength(p) / 1e6);
    }
    return c;
  };
  const auto& s = m.state();
  json j;
  j["title"] = fmt::format("Sand model: dry density {:g} kg/m3, moisture {:.3g}% (saturation {:.0f}%)", s.dry_density,
                           100 * s.moisture, 100 * s.saturation);
  j["family"] = json::array();
  for (double sat : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    auto in = m.inputs();
    in.moisture = sat * s.porosity * 1000.0 / s.dry_density;
    j["family"].push_back(curveOf(SandModel(in), fmt::format("S = {:.0f}%", 100 * sat)));
  }
  j["soil"] = curveOf(m, fmt::format("this soil, S = {:.0f}%", 100 * s.saturation));
  return j;
}

void writeLoadingCurveCsv(std::ostream& os, const SandModel& m) {
  os << "pressure_Pa,strain,natural_strain,density_kg_m3,loading_modulus_Pa,unloading_modulus_Pa,shear_modulus_Pa\n";
  for (const auto& c : m.sampleLoading(kCurveSamples))
    os << fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", c.pressure, c.strain, c.natural_strain,
                      c.density, c.loading_modulus, c.unloading_modulus, c.shear_modulus);
}

void writeYieldCurveCsv(std::ostream& os, const SandModel& m) {
  os << "pressure_Pa,yield_strength_Pa\n";
  const double top = std::max(4.0 * m.yieldPlateau() / std::max(m.inputs().friction_slope, 1e-12), 1e9);
  for (int i = 0; i <= 200; ++i) {
    const double p = top * i / 200.0;
    os << fmt::format("{:.9g},{:.9g}\n", p, m.yieldStrength(p));
  }
}

void writeSummaryCsv(std::ostream& os, const SandModel& m) {
  const auto j = soilJson(m);
  os << "quantity,value\n";
  for (const auto* section : {"state", "key_numbers"})
    for (auto& [key, value] : j[section].items()) os << key << ',' << fmt::format("{:.9g}", value.get<double>()) << '\n';
}

std::string soilSummaryText(const SandModel& m) {
  const auto& s = m.state();
  const auto k = m.keyNumbers();
  const auto& in = m.inputs();
  std::string out;
  out += fmt::format("ejecta {} sand model (three springs: air-void skeleton, quartz, water)\n", build_info::version);
  out += fmt::format("  dry density        {:10.1f} kg/m3\n", s.dry_density);
  out += fmt::format("  moisture           {:10.2f} %  (mass of water / mass of dry solids)\n", 100 * s.moisture);
  out += fmt::format("  wet density        {:10.1f} kg/m3\n", s.wet_density);
  out += fmt::format("  porosity           {:10.4f}\n", s.porosity);
  out += fmt::format("  water fraction     {:10.4f}  (volume)\n", s.water_fraction);
  out += fmt::format("  saturation         {:10.1f} %\n", 100 * s.saturation);
  out += fmt::format("  air voids          {:10.4f}  (volume)\n", s.air_voids);
  out += fmt::format("  initial bulk modulus, loading   {:10.1f} MPa\n", k.initial_bulk_modulus / 1e6);
  out += fmt::format("  initial bulk modulus, unloading {:10.1f} MPa\n", k.initial_unloading_modulus / 1e6);
  out += fmt::format("  initial shear modulus           {:10.1f} MPa\n", k.initial_shear_modulus / 1e6);
  out += fmt::format("  shear modulus cap               {:10.1f} MPa  ({})\n", m.shearModulusCap() / 1e6, in.shear_modulus_cap > 0.0 ? "input" : "quartz's");
  out += fmt::format("  shear modulus follows           {:>10}  (in the hydrocode)\n", in.shear_follows_pressure ? "pressure" : "compaction");
  out += fmt::format("  shear modulus bound             {:10.2f}  (Poisson's ratio at least; G <= 3 K_u (1 - 2 nu) / (2 (1 + nu)))\n", in.min_poisson_ratio);
  out += fmt::format("  lockup pressure                 {:10.1f} MPa\n", k.lockup_pressure / 1e6);
  out += fmt::format("  lockup strain, -ln(V/V0)        {:10.4f}  (density {:.0f} kg/m3)\n", k.lockup_strain,
                     k.lockup_density);
  out += fmt::format("  yield plateau                   {:10.2f} MPa  ({} law)\n", k.yield_plateau / 1e6,
                     lawName(in.plateau.law));
  out += fmt::format("  friction knee pressure          {:10.2f} MPa\n", k.friction_knee_pressure / 1e6);
  out += fmt::format("  energy term gamma               {:10.3f}      (p = C(x) + gamma T(x) rho0 e; T: 0 as laid, 1 at lockup)\n", m.thermalGamma());
  out += fmt::format("  loading wave speed              {:10.1f} m/s\n", k.loading_wave_speed);
  out += fmt::format("  elastic wave speed              {:10.1f} m/s\n", k.elastic_wave_speed);
  out += fmt::format("  water EOS set '{}' ({}); Sjobo unloading data recalled (provisional)\n", in.water.name,
                     in.water.status);
  return out;
}

}  // namespace ejecta::io

// `ejecta soil`: the two-input sand model, its summary, LS-DYNA cards, curves, JSON and plot.
#include <filesystem>
#include <iostream>
#include <optional>

#include <fmt/format.h>

#include "commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/lsdyna.hpp"
#include "io/soil_report.hpp"
#include "io/subprocess.hpp"
#include "materials/sand_model.hpp"

namespace ejecta::cli {

namespace fs = std::filesystem;

namespace {
struct SoilOptions {
  std::string dry_density, wet_density, moisture, saturation;
  std::string grain_density, quartz_k, quartz_kp, friction_slope, tension_cutoff, poisson;
  std::string water_eos = "awg", plateau_law = "effective-stress", shear_modulus_law = "pressure", yield_plateau, plateau_scale, plateau_residual, thermal_gamma, shear_modulus_cap,
              min_poisson_ratio;
  std::string lsdyna, units = "kg-m-s", csv_dir, json_out, plot;
  CLI::Option* json_opt = nullptr;
};

materials::SandInputs buildInputs(const SoilOptions& o) {
  materials::SandInputs in;
  double w = o.moisture.empty() ? 0.07 : parseNumber("moisture", o.moisture, true);
  if (!o.saturation.empty()) {
    // Saturation fixes the moisture from the dry density: w = S n rho_w / rho_d.
    const double s = parseNumber("saturation", o.saturation, true);
    if (s < 0.0 || s > 1.0) throw InputError("saturation", fmt::format("{:g}% is out of range; valid [0, 100%]", 100 * s));
    if (!o.wet_density.empty()) throw InputError("saturation", "give it with --dry-density, not --wet-density");
    const double rho_d = o.dry_density.empty() ? 1280.0 : parseNumber("dry-density", o.dry_density);
    const double rho_g = o.grain_density.empty() ? in.quartz.grain_density : parseNumber("grain-density", o.grain_density);
    if (rho_d > 0.0 && rho_d < rho_g) w = s * (1.0 - rho_d / rho_g) * 1000.0 / rho_d;
  }
  if (!o.wet_density.empty()) {
    in = materials::SandInputs::fromWetDensity(parseNumber("wet-density", o.wet_density), w);
  } else {
    in.dry_density = o.dry_density.empty() ? 1280.0 : parseNumber("dry-density", o.dry_density);
    in.moisture = w;
  }
  if (!o.grain_density.empty()) in.quartz.grain_density = parseNumber("grain-density", o.grain_density);
  if (!o.quartz_k.empty()) in.quartz.bulk_modulus = parseNumber("quartz-bulk-modulus", o.quartz_k);
  if (!o.quartz_kp.empty()) in.quartz.dK_dp = parseNumber("quartz-dK-dp", o.quartz_kp);
  if (!o.friction_slope.empty()) in.friction_slope = parseNumber("friction-slope", o.friction_slope);
  if (!o.tension_cutoff.empty()) in.tension_cutoff = parseNumber("tension-cutoff", o.tension_cutoff);
  if (!o.poisson.empty()) in.poisson = parseNumber("poisson", o.poisson);
  in.water = materials::waterEosByName(o.water_eos);
  if (o.plateau_law == "fixed" || !o.yield_plateau.empty()) {
    if (o.yield_plateau.empty()) throw InputError("yield-plateau", "the fixed plateau law needs --yield-plateau PA");
    in.plateau.law = materials::PlateauParams::Law::Fixed;
    in.plateau.fixed = parseNumber("yield-plateau", o.yield_plateau);
  } else if (o.plateau_law != "effective-stress") {
    throw InputError("plateau-law", "unknown law '" + o.plateau_law + "' (valid: effective-stress, fixed)");
  }
  if (!o.plateau_scale.empty()) in.plateau.scale = parseNumber("plateau-scale", o.plateau_scale);
  if (!o.thermal_gamma.empty()) {
    in.thermal_gamma = parseNumber("thermal-gamma", o.thermal_gamma);
    requireInRange("thermal-gamma", in.thermal_gamma, materials::kThermalGammaRange, "-");
  }
  // 0: quartz's, as in the deck; the sand model checks the range, naming this option
  if (!o.shear_modulus_cap.empty()) in.shear_modulus_cap = parseNumber("shear-modulus-cap", o.shear_modulus_cap);
  if (o.shear_modulus_law != "compaction" && o.shear_modulus_law != "pressure")
    throw InputError("shear-modulus-law", "unknown law '" + o.shear_modulus_law + "' (valid: compaction, pressure)");
  in.shear_follows_pressure = o.shear_modulus_law == "pressure";
  // the sand model checks the range, naming this option
  if (!o.min_poisson_ratio.empty()) in.min_poisson_ratio = parseNumber("min-poisson-ratio", o.min_poisson_ratio);
  if (!o.plateau_residual.empty()) in.plateau.residual = parseNumber("plateau-residual", o.plateau_residual);
  return in;
}

void requireParentExists(const std::string& field, const fs::path& p) {
  const auto parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(parent))
    throw InputError(field, fmt::format("directory '{}' does not exist", parent.string()));
}

int runSoil(const SoilOptions& o) {
  const materials::SandModel model(buildInputs(o));
  const auto units = io::lsdynaUnitsByName(o.units);
  const bool json_stdout = o.json_opt->count() > 0 && o.json_out.empty();
  if (!o.lsdyna.empty()) requireParentExists("lsdyna", o.lsdyna);
  if (!o.plot.empty()) requireParentExists("plot", o.plot);
  if (!o.json_out.empty()) requireParentExists("json", o.json_out);
  if (!o.csv_dir.empty() && fs::exists(o.csv_dir) && !fs::is_directory(o.csv_dir))
    throw InputError("csv", fmt::format("'{}' exists and is not a directory", o.csv_dir));
  if (!o.csv_dir.empty()) {
    // the folder itself, with or without a trailing separator ("vimf/" names the folder vimf)
    fs::path dir = fs::path(o.csv_dir).lexically_normal();
    if (!dir.has_filename() && dir.has_parent_path()) dir = dir.parent_path();
    requireParentExists("csv", dir);
  }

  // Everything is staged first and renamed into place only when all of it succeeded.
  io::OutputTransaction outputs;
  bool created_csv_dir = false;
  try {
    if (!o.lsdyna.empty()) {
      io::KeywordOptions ko{units, 1, 1, fmt::format("ejecta soil, wet density {:g} kg/m3", model.state().wet_density)};
      outputs.stage(o.lsdyna, [&](std::ostream& os) { io::writeLsdynaKeywords(os, model, ko); });
    }
    if (!o.json_out.empty())
      outputs.stage(o.json_out, [&](std::ostream& os) { os << io::soilJson(model).dump(2) << '\n'; });
    if (!o.csv_dir.empty()) {
      created_csv_dir = fs::create_directory(o.csv_dir);
      const fs::path dir(o.csv_dir);
      outputs.stage(dir / "loading_curve.csv", [&](std::ostream& os) { io::writeLoadingCurveCsv(os, model); });
      outputs.stage(dir / "yield_curve.csv", [&](std::ostream& os) { io::writeYieldCurveCsv(os, model); });
      outputs.stage(dir / "summary.csv", [&](std::ostream& os) { io::writeSummaryCsv(os, model); });
    }
    if (!o.plot.empty()) io::stagePlot(outputs, "plot_soil.py", io::soilPlotData(model).dump(), o.plot);
    outputs.commit();
  } catch (...) {
    outputs.discard();
    if (created_csv_dir) {
      std::error_code ec;
      fs::remove(o.csv_dir, ec);   // only removes it if empty
    }
    throw;
  }

  if (json_stdout) {
    std::cout << io::soilJson(model).dump(2) << '\n';
  } else {
    std::cout << io::soilSummaryText(model);
    for (const auto* what : {&o.lsdyna, &o.json_out, &o.csv_dir, &o.plot})
      if (!what->empty()) std::cout << "  wrote " << *what << '\n';
  }
  return 0;
}
}  // namespace

Action addSoilCommand(CLI::App& app) {
  auto o = std::make_shared<SoilOptions>();
  auto* sub = app.add_subcommand("soil", "The two-input sand model: summary, LS-DYNA cards, curves, plot.\n"
                                         "Default soil: EMI sand as received, 1280 kg/m3 dry at 7% moisture.");
  auto* dry = sub->add_option("--dry-density", o->dry_density, "Dry density, kg/m3 (default 1280), valid [0.3 x grain density, grain density): porosity at most 0.7");
  auto* wet = sub->add_option("--wet-density", o->wet_density, "Wet (gross) density, kg/m3; dry = wet / (1 + moisture)");
  dry->excludes(wet);
  auto* moist = sub->add_option("--moisture", o->moisture,
                                "Gravimetric moisture: a fraction (0.07) or a percentage (7%); default 7%");
  sub->add_option("--saturation", o->saturation, "Instead of --moisture: degree of saturation, 0-100% (with --dry-density)")
      ->excludes(moist);
  sub->add_option("--grain-density", o->grain_density, "Quartz grain density, kg/m3, about [2640, 5000] (the dry Sjobo baseline needs open voids; default 2650)");
  sub->add_option("--quartz-bulk-modulus", o->quartz_k, "Quartz bulk modulus, Pa (default 36.6e9)");
  sub->add_option("--quartz-dK-dp", o->quartz_kp, "Quartz pressure derivative of the bulk modulus, - (default 6)");
  sub->add_option("--water-eos", o->water_eos, "Water Gruneisen set: awg (default, verified) or alt (recalled)");
  sub->add_option("--friction-slope", o->friction_slope, "Initial slope of the yield curve dY/dp, - (default 1.396)");
  sub->add_option("--tension-cutoff", o->tension_cutoff, "Tension cutoff pressure, Pa, <= 0 (default -6.9e3)");
  sub->add_option("--poisson", o->poisson, "Poisson's ratio for the LS-DYNA card (default 0.22)");
  sub->add_option("--plateau-law", o->plateau_law, "Yield plateau law: effective-stress (default) or fixed");
  sub->add_option("--yield-plateau", o->yield_plateau, "Fixed yield plateau, Pa (implies --plateau-law fixed)");
  sub->add_option("--plateau-scale", o->plateau_scale, "Multiplier on the effective-stress plateau, - (default 1)");
  sub->add_option("--thermal-gamma", o->thermal_gamma, "Gruneisen coefficient of the energy term p = C(x) + gamma T(x) rho0 e, [0, 4] (default: from the constituents)");
  sub->add_option("--shear-modulus-cap", o->shear_modulus_cap, "Cap on the skeleton's shear modulus, Pa, [1e8, 4.5e10], or 0: quartz's (the default, 4.5e10)");
  sub->add_option("--shear-modulus-law", o->shear_modulus_law,
                  "What the skeleton's shear modulus follows in the hydrocode: pressure (the effective pressure now; default) or compaction (the largest seen)");
  sub->add_option("--min-poisson-ratio", o->min_poisson_ratio,
                  fmt::format("Poisson's ratio that bounds the skeleton's shear modulus, G <= 3 K_u (1 - 2 nu) / (2 (1 + nu)), [{:g}, {:g}] (default {:g}, Sjobo's)",
                              materials::kMinPoissonRatioRange.lo, materials::kMinPoissonRatioRange.hi, materials::kSjoboPoisson));
  sub->add_option("--plateau-residual", o->plateau_residual, "Floor of the plateau, Pa (default 0)");
  sub->add_option("--lsdyna", o->lsdyna, "Write an LS-DYNA keyword file (*MAT_PSEUDO_TENSOR, *EOS_TABULATED_COMPACTION)");
  sub->add_option("--units", o->units, "Unit system of the keyword file: kg-m-s (default), g-mm-ms, t-mm-s");
  sub->add_option("--csv", o->csv_dir, "Write the curves as CSV files into this directory");
  o->json_opt = sub->add_option("--json", o->json_out, "Write everything as JSON to FILE, or to stdout if no FILE")
                    ->expected(0, 1);
  sub->add_option("--plot", o->plot, "Write a PNG plot of compaction and yield curves (saturations 0-100%)");
  return [sub, o]() { return sub->parsed() ? runSoil(*o) : -1; };
}

}  // namespace ejecta::cli

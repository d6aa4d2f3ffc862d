#include "scenario/validation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "hydro/pencil.hpp"

namespace ejecta::scenario {
namespace {
using nlohmann::json;

// Cell sizes of each level, mm. Quick fits CI (a few minutes on 2 cores) and only exercises the
// pipeline and the trends; full is the published resolution (5 mm plates, 3 mm soil bubble).
struct LevelSizes {
  std::vector<double> mesh;   // coarse to fine
  double plate, sensitivity, bubble;
  double vplate;              // the 3D quarter runs
};
LevelSizes sizesOf(ValidationLevel level) {
  // The sensitivity study reports changes, not absolute values: at the full level it runs at 10 mm
  // (each 5 mm plate run takes 10-15 minutes on one core; six more would push --full past 2 hours).
  // The 3D V-plates: 10 mm at the full level (the published 5 mm needs a cluster: docs/validate.md),
  // 60 mm at the quick level (the pipeline and the ordering, a few seconds each).
  // The mesh study's finest three (judged) are 5, 4 and 3 mm at the full level: the published study
  // stopped at 4 mm; 3 mm shows whether what is judged there has settled (73 min on one thread, measured).
  if (level == ValidationLevel::Full) return {{10.0, 6.0, 5.0, 4.0, 3.0}, 5.0, 10.0, 3.0, 10.0};
  // The quick level's mesh study stops at 12 mm, so that the whole quick level stays a few minutes
  // of CI's time (the 10 mm case alone is about 16,000 steps); its soil bubble at 8 mm.
  return {{25.0, 20.0, 15.0, 12.0}, 20.0, 20.0, 8.0, 60.0};
}
LevelSizes sizesOf(const ValidationPlan& plan) {
  auto sz = sizesOf(plan.level);
  if (plan.vplate_mm > 0.0) sz.vplate = plan.vplate_mm;
  return sz;
}

// The sensitivity study's baseline: the EMI 7% case at the sensitivity cell size.
std::string sensitivityBaseline(const LevelSizes& sz) {
  return sz.sensitivity == sz.plate ? "emi-flat-7" : "sens-baseline-" + fmt::format("{:g}", sz.sensitivity) + "mm";
}

std::string mm(double v) { return fmt::format("{:g}", v); }

ValidationCase makeCase(std::string id, std::string deck, double cell_mm, std::vector<std::string> sets, std::string change, double cost_scale = 1.0) {
  ValidationCase c;
  c.id = std::move(id);
  c.deck = std::move(deck);
  c.sets = std::move(sets);
  c.sets.push_back(fmt::format("mesh.cell_size_m={:g}", cell_mm / 1000.0));
  c.cell_mm = cell_mm;
  c.change = change.empty() ? "-" : std::move(change);
  c.relative_cost = cost_scale * std::pow(10.0 / cell_mm, 3.0);   // 2D: cells ~ h^-2, steps ~ h^-1
  return c;
}

// The V-plate study's cases: the EMI flat plate in 3D (the same deck on the quarter mesh, its far
// field graded as the V-plate decks') and the 120 and 90 degree V-plates, with the 2D flat plate at
// the same cell size beside them.
struct VPlateCase {
  std::string id, deck, label;
  bool three_d;
};
std::vector<VPlateCase> vplateCases(const LevelSizes& sz, ValidationLevel level) {
  // The 2D flat plate is another study's run where that run is the same one: at the full level,
  // where every run goes to the deck's 10 ms (the quick level's V-plates stop at 5 ms).
  std::string flat2d = "vplate-flat-2d-" + fmt::format("{:g}", sz.vplate) + "mm";
  if (level == ValidationLevel::Full && sz.vplate == sz.sensitivity) flat2d = sensitivityBaseline(sz);
  else if (level == ValidationLevel::Full && sz.vplate == sz.plate) flat2d = "emi-flat-7";
  return {{flat2d, "emi-flat-7", "flat disc, 2D axisymmetric", false},
          {"emi-flat-7-3d", "emi-flat-7", "flat disc, 3D quarter", true},
          {"emi-v120-7", "emi-v120-7", "120 degree V, 3D quarter", true},
          {"emi-v90-7", "emi-v90-7", "90 degree V, 3D quarter", true}};
}
// A 3D quarter case: about 3 (quarter) x (r-z cells per axis) more cells than the 2D case at the
// same size; the cost measure below is per 2D EMI case at 10 mm.
constexpr double k3dCostScale = 40.0;
// The growth per cell outside the uniform core of the 3D quarter runs, as the V-plate decks have it
// (decks/emi-v120-7.toml, emi-v90-7.toml), so that the flat plate in 3D shares their far field. At
// 1.05, the 2D decks' value, 77% of a 10 mm quarter's cells lie outside the core; 1.15 moves the
// plates' impulse by 0.06-0.32% at 20 mm and the 120 degree V's by 0.5% at 10 mm, and takes 35-44%
// off the wall time (docs/validate.md, "The far field of the 3D decks").
constexpr double kQuarterGrading = 1.15;
// The quick level's V-plate runs end at 5 ms (the full level's at the decks' 10 ms).
constexpr double kVPlateQuickEnd_s = 0.005;

// Sensitivity inputs: what we do not know exactly (shared/data/validation_cases.md), and the time
// step, each changed alone from the EMI 7% deck. `per` turns the change into a rate for the table.
struct Perturbation {
  std::string id, input, base, changed, set, per_unit;
  double per;   // the change in units of per_unit
  std::string mesh_set = {};   // keeps the plate in the uniform core where the change moves it out
};
const std::vector<Perturbation>& perturbations() {
  static const std::vector<Perturbation> p{
      // the EMI standoff is inferred (0.10 m): the impulse over 0-0.3 m
      {"sens-standoff-0cm", "plate standoff", "0.10 m", "0 m (on the sand)", "target.standoff_m=0", "% per cm", -10.0},
      {"sens-standoff-5cm", "plate standoff", "0.10 m", "0.05 m", "target.standoff_m=0.05", "% per cm", -5.0},
      // (the deck's core ends 5 cm over its plate's face: so do theirs)
      {"sens-standoff-20cm", "plate standoff", "0.10 m", "0.20 m", "target.standoff_m=0.2", "% per cm", 10.0, "mesh.core_top_m=0.25"},
      {"sens-standoff-30cm", "plate standoff", "0.10 m", "0.30 m", "target.standoff_m=0.3", "% per cm", 20.0, "mesh.core_top_m=0.35"},
      // the coupling: a plate held fixed, and a free plate whose cells stay put (no ALE motion)
      {"sens-plate-fixed", "plate motion", "free, moving the mesh", "fixed", "target.motion=fixed", "% for the change", 1.0},
      {"sens-plate-static-mesh", "plate motion", "free, moving the mesh", "free, cells held in place", "target.move_mesh=false", "% for the change", 1.0},
      {"sens-aspect-0.5", "charge height/diameter", "1/3", "1/2", "charge.height_to_diameter=0.5", "% per +0.1", (0.5 - 1.0 / 3.0) / 0.1},
      {"sens-aspect-0.2", "charge height/diameter", "1/3", "1/5", "charge.height_to_diameter=0.2", "% per +0.1", (0.2 - 1.0 / 3.0) / 0.1},
      {"sens-plateau-0.5", "yield plateau law (scale)", "1", "0.5", "soil.0.plateau_scale=0.5", "% for the change", 1.0},
      {"sens-water-alt", "water EOS set", "awg", "alt", "soil.0.water_eos=alt", "% for the change", 1.0},
      // the cap on the compacted skeleton's shear modulus (quartz's own unless given: not measured),
      // which also sets the time step late in a run (docs/sand-model.md)
      {"sens-shear-cap-10gpa", "sand shear modulus cap", "45 GPa (quartz)", "10 GPa", "soil.0.shear_modulus_cap_pa=1e10", "% for the change", 1.0},
      {"sens-shear-cap-1gpa", "sand shear modulus cap", "45 GPa (quartz)", "1 GPa", "soil.0.shear_modulus_cap_pa=1e9", "% for the change", 1.0},
      // what the skeleton's G follows, and the Poisson's ratio that bounds it (revision 11's choices)
      {"sens-shear-law-compaction", "sand shear modulus law", "pressure now", "largest compaction seen (revision 10)",
       "soil.0.shear_modulus_law=\"compaction\"", "% for the change", 1.0},
      {"sens-min-poisson-0.1", "sand shear modulus bound (Poisson's ratio)", "0.22 (Sjobo)", "0.1", "soil.0.min_poisson_ratio=0.1", "% for the change", 1.0},
      // the plate-to-soil Coulomb coefficient (0.2 in shared/data, not measured for this plate), which acts on the
      // sand's share of the contact (revision 12)
      {"sens-friction-0", "plate-to-soil friction", "0.2", "0 (frictionless)", "target.friction=0", "% per +0.1", -2.0},
      {"sens-friction-0.4", "plate-to-soil friction", "0.2", "0.4", "target.friction=0.4", "% per +0.1", 2.0},
      // not an input of the physics: the time step at the same cells (the Courant number)
      {"sens-cfl-0.15", "time step (Courant number)", "0.30", "0.15", "cfl=0.15", "% for the change", 1.0},
      // a model form, not an input: the mixed cells' stiffness in the faces and the step (revision 15's
      // default, Reuss at Courant 0.30, against revision 14's frozen Voigt sum at 0.45)
      {"sens-mixture-frozen", "mixed cells' stiffness", "Reuss, Courant 0.30", "frozen (Voigt), Courant 0.45", "mixture_stiffness=\"frozen\"",
       "% for the change", 1.0, "cfl=0.45"},
  };
  return p;
}

struct FieldCase {
  std::string deck, cover;
  double thickness_cm;
};
const std::vector<FieldCase>& fieldCases() {
  static const std::vector<FieldCase> f{{"field-cover22-5cm", "1670 kg/m3, 22% (undisturbed)", 5.0},
                                        {"field-cover14-5cm", "1490 kg/m3, 14%", 5.0},
                                        {"field-cover7-5cm", "1370 kg/m3, 7%", 5.0},
                                        {"field-cover22-2.5cm", "1670 kg/m3, 22% (undisturbed)", 2.5},
                                        {"field-cover14-2.5cm", "1490 kg/m3, 14%", 2.5},
                                        {"field-cover7-2.5cm", "1370 kg/m3, 7%", 2.5}};
  return f;
}

const std::vector<std::pair<std::string, double>>& moistureDecks() {
  static const std::vector<std::pair<std::string, double>> m{{"emi-flat-7", 7.0}, {"emi-flat-14", 14.0}, {"emi-flat-22", 22.0}};
  return m;
}

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "-";
  return fmt::format("{:.{}f}", v, decimals);
}
std::string signedPct(double v) {
  if (!std::isfinite(v)) return "-";
  return fmt::format("{:+.1f}%", v);
}

// A case's energy imbalance over the charge's energy ("-" where not saved).
std::string imbalanceText(const json& outcome) {
  const auto it = outcome.find("energy_imbalance_fraction");
  if (it == outcome.end() || !it->is_number()) return "-";
  return fmt::format("{:.1e}", it->get<double>());
}

// A value that was not recorded (NaN) is written as null.
json check(const std::string& name, double value, const std::string& unit, const std::string& limit, json pass) {
  return json{{"name", name}, {"value", std::isfinite(value) ? json(value) : json(nullptr)}, {"unit", unit}, {"limit", limit}, {"pass", std::move(pass)}};
}

// The depth at which the report's tables show the load split by material (the mesh study judges
// every recorded depth, hydro::kNearWallDepth_m): two cells of the full level's coarsest mesh
// (10 mm) and far below the plate's 0.45 m radius.
constexpr double kJudgedDepth_m = 0.02;
// The energy below which the mesh study judges a material's internal or kinetic energy against this
// share of the charge's energy instead of against itself: 1% of the charge, the currency the energy
// books and issue 10 measure errors in, so such a part is judged negligible (to 0.05% of the
// charge), not converged. The products' kinetic energy under the mesh study's fixed plate, which
// rests on the sand, is 0.7-2.4 kJ of 3.34 MJ and scatters by 12% of itself; the momentum it can
// carry is under 2% of the impulse (docs/validate.md, with the floor's sensitivity).
constexpr double kEnergyFloorOfCharge = 0.01;
// A case's impulse by the materials of `kind` within `depth` of the target (NaN if not recorded).
double nearWallImpulse(const json& o, const std::string& kind, double depth = kJudgedDepth_m) {
  const auto it = o.find("impulse_within_Ns");
  if (it == o.end()) return std::nan("");
  const auto& d = it->at("depth_m");
  for (std::size_t l = 0; l < d.size(); ++l)
    if (std::abs(d.at(l).get<double>() - depth) < 1e-9) return it->at(kind).at(l).get<double>();
  return std::nan("");
}

json table(std::vector<std::string> columns) { return json{{"columns", columns}, {"rows", json::array()}}; }

// Limits of the judged checks, %. The published mesh study's claim, for converged cells: the
// finest three sizes within 2% of their mean. The quick level's cells (12-25 mm) are coarser than
// any the study used: 3% there (revision 3's quick run spread 0.85%, revision 4's full run 1.3%).
constexpr double kSpreadFullPct = 2.0, kSpreadQuickPct = 3.0;
// The published field-test finding: a looser, drier backfilled cover barely changes the impulse.
// "Barely" is taken as under half of what the bed's own moisture does (7% -> 22%: +20% at
// revision 4's full level), i.e. 10%; measured: 3.6% (revision 2, full), 4.4% (revision 3, quick).
constexpr double kFieldChangePct = 10.0;

}  // namespace

const std::vector<std::string>& validationStudies() {
  static const std::vector<std::string> s{"mesh", "moisture", "field", "share", "sensitivity", "dres", "vplates"};
  return s;
}

ValidationPlan validationPlan(ValidationLevel level, const std::vector<std::string>& only, double vplate_mm) {
  if (vplate_mm != 0.0 && !(vplate_mm >= 5.0 && vplate_mm <= 100.0))
    throw InputError("vplate-cell-size", fmt::format("{:g} mm is out of range; valid [5, 100] mm (or 0: the level's, quick 60 mm, full 10 mm)", vplate_mm));
  const auto& all = validationStudies();
  for (const auto& o : only)
    if (std::find(all.begin(), all.end(), o) == all.end())
      throw InputError("only", fmt::format("'{}' is not a study; valid: mesh, moisture, field, share, sensitivity, dres, vplates", o));
  ValidationPlan plan;
  plan.level = level;
  plan.vplate_mm = vplate_mm;
  for (const auto& s : all)
    if (only.empty() || std::find(only.begin(), only.end(), s) != only.end()) plan.studies.push_back(s);
  const auto sz = sizesOf(plan);
  auto add = [&](ValidationCase c) {
    for (const auto& e : plan.cases)
      if (e.id == c.id) {
        // one run serving two studies must be the same run
        if (e.deck != c.deck || e.sets != c.sets) throw RunError(fmt::format("validation case '{}' planned twice with different decks", c.id));
        return;
      }
    plan.cases.push_back(std::move(c));
  };
  auto wants = [&](const std::string& s) { return std::find(plan.studies.begin(), plan.studies.end(), s) != plan.studies.end(); };
  if (wants("mesh"))
    for (const double h : sz.mesh) add(makeCase("mesh-" + mm(h) + "mm", "mesh-study", h, {}, "fixed target, no gravity"));
  if (wants("moisture") || wants("share"))
    for (const auto& [deck, w] : moistureDecks()) add(makeCase(deck, deck, sz.plate, {}, ""));
  if (wants("field") || wants("share"))
    for (const auto& f : fieldCases()) add(makeCase(f.deck, f.deck, sz.plate, {}, ""));
  if (wants("sensitivity")) {
    add(makeCase(sensitivityBaseline(sz), "emi-flat-7", sz.sensitivity, {}, ""));
    for (const auto& p : perturbations()) {
      std::vector<std::string> sets{p.set};
      if (!p.mesh_set.empty()) sets.push_back(p.mesh_set);
      add(makeCase(p.id, "emi-flat-7", sz.sensitivity, sets, p.mesh_set.empty() ? p.set : p.set + ", " + p.mesh_set));
    }
  }
  if (wants("dres"))
    for (const std::string d : {"dres-3cm", "dres-8cm"}) add(makeCase(d, d, sz.bubble, {}, "", 0.15 * 0.6));
  if (wants("vplates"))
    for (const auto& v : vplateCases(sz, level)) {
      std::vector<std::string> sets;
      std::string change;
      if (v.three_d && v.deck == "emi-flat-7") {
        sets.push_back("geometry=\"3d-quarter\"");
        sets.push_back(fmt::format("mesh.grading={:g}", kQuarterGrading));
        change = fmt::format("3D quarter, graded {:g} outside the core", kQuarterGrading);
      }
      if (level == ValidationLevel::Quick) {   // the ordering only: 5 ms keeps CI's quick level short
        sets.push_back(fmt::format("end_time_s={:g}", kVPlateQuickEnd_s));
        change += change.empty() ? "to 5 ms" : ", to 5 ms";
      }
      auto c = makeCase(v.id, v.deck, sz.vplate, sets, change, v.three_d ? k3dCostScale * (10.0 / sz.vplate) : 1.0);
      add(std::move(c));
    }
  return plan;
}

json condenseOutcome(const ValidationCase& c, const RunResult& r, std::size_t max_rows) {
  json o;
  o["id"] = c.id;
  o["deck"] = c.deck;
  o["change"] = c.change;
  o["sets"] = c.sets;
  o["cell_mm"] = c.cell_mm;
  o["impulse_Ns"] = r.impulse_Ns;
  o["impulse_air_Ns"] = r.impulse_air_Ns;
  o["impulse_products_Ns"] = r.impulse_products_Ns;
  o["impulse_soil_Ns"] = r.impulse_soil_Ns;
  if (r.impulse_near_Ns.size() == 3 * hydro::kNearWallDepth_m.size()) {
    json near{{"depth_m", hydro::kNearWallDepth_m}, {"air", json::array()}, {"products", json::array()}, {"soil", json::array()}};
    for (std::size_t l = 0; l < hydro::kNearWallDepth_m.size(); ++l) {
      near["air"].push_back(r.impulse_near_Ns[3 * l]);
      near["products"].push_back(r.impulse_near_Ns[3 * l + 1]);
      near["soil"].push_back(r.impulse_near_Ns[3 * l + 2]);
    }
    o["impulse_within_Ns"] = near;
  }
  o["peak_force_N"] = r.peak_force_N;
  o["cells"] = r.cells;
  o["steps"] = r.steps;
  o["wall_s"] = r.wall_s + r.wall_before_s;   // all its parts, where it was continued from a checkpoint
  o["in_parts"] = r.wall_before_s > 0.0;
  o["energy_imbalance_fraction"] = r.energy_imbalance_fraction;
  o["charge_energy_J"] = r.charge_energy_J;
  // histories, thinned evenly; NaN (no soil in the column) as null
  auto value = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  json h;
  const std::size_t n = r.history.size();
  const std::size_t stride = std::max<std::size_t>(1, (n + max_rows - 1) / std::max<std::size_t>(max_rows, 1));
  for (std::size_t q = 0; q < r.history_columns.size(); ++q) {
    const auto& name = r.history_columns[q];
    static const std::array<const char*, 12> kept{"t_s", "impulse_Ns", "soil_top_m", "bubble_height_on_axis_m", "impulse_products_within_20mm_Ns",
                                                  "impulse_soil_within_20mm_Ns", "internal_energy_products_J", "kinetic_energy_products_J",
                                                  "internal_energy_soil_J", "kinetic_energy_soil_J", "mass_products_kg", "mass_soil_kg"};
    if (std::find(kept.begin(), kept.end(), name) == kept.end()) continue;
    json col = json::array();
    for (std::size_t i = 0; i < n; i += stride) col.push_back(value(r.history[i].at(q)));
    if (n > 0 && (n - 1) % stride != 0) col.push_back(value(r.history[n - 1].at(q)));
    h[name] = col;
  }
  o["history"] = h;
  json prof;
  prof["r_m"] = r.profile_r_m;
  prof["times_s"] = r.profile_times_s;
  json z = json::array();
  for (const auto& p : r.profiles_m) {
    json row = json::array();
    for (const double v : p) row.push_back(value(v));
    z.push_back(row);
  }
  prof["z_m"] = z;
  o["profiles"] = prof;
  return o;
}

json validationReport(const ValidationPlan& plan, const std::map<std::string, json>& outcomes, const json& run_info) {
  auto get = [&](const std::string& id) -> const json& {
    const auto it = outcomes.find(id);
    if (it == outcomes.end()) throw RunError(fmt::format("validation case '{}' has no result", id));
    return it->second;
  };
  auto impulse = [&](const std::string& id) { return get(id).at("impulse_Ns").get<double>(); };
  const auto sz = sizesOf(plan);
  const bool full = plan.level == ValidationLevel::Full;
  json rep;
  rep["title"] = fmt::format("ejecta validation report ({})", full ? "full" : "quick");
  rep["level"] = full ? "full" : "quick";
  rep["run"] = run_info;
  double case_s = 0.0;   // each case's own run time, whenever it ran: the cost of the whole report
  for (const auto& c : plan.cases) case_s += get(c.id).at("wall_s").get<double>();
  rep["run"]["case_time_sum_s"] = case_s;
  rep["units"] = "SI: impulse N s, cell size mm, times s (tables: ms where stated), heights m";
  rep["intro"] = json::array(
      {"Predictions of ejecta for the published buried-charge tests listed in shared/data/validation_cases.md, "
       "made with the built-in decks and no tuning: the sand model's only inputs are the dry density and the moisture.",
       "Measured impulses of the EMI tests, the DRES bubble histories and the VIMF impulses are not available to us "
       "(shared/data/README.md), so no case has a reference value and no error against a test is claimed here: the report "
       "shows the published findings that can be checked without them (mesh-insensitive impulse, impulse rising with moisture, "
       "backfill changing the impulse little) and how much the unknown inputs move the answer.",
       full ? "Level: full (plates at 5 mm cells, the mesh study at 10/6/5/4/3 mm, the soil bubble at 3 mm)."
            : "Level: quick (coarse cells, for CI: it exercises every study and shows the trends; its numbers are not converged, "
              "see the full report in docs/validation/)."});
  json sections = json::array();
  json checks = json::array();

  for (const auto& study : plan.studies) {
    json sec;
    sec["id"] = study;
    if (study == "mesh") {
      sec["title"] = "Mesh convergence (EMI flat plate, 7%, fixed target, no gravity)";
      std::vector<double> h = sz.mesh, imp;
      for (const double c : h) imp.push_back(impulse("mesh-" + mm(c) + "mm"));
      // the finest three: the published claim is that they barely differ
      const std::size_t k0 = h.size() >= 3 ? h.size() - 3 : 0;
      const double mean = std::accumulate(imp.begin() + static_cast<std::ptrdiff_t>(k0), imp.end(), 0.0) / static_cast<double>(imp.size() - k0);
      double spread = 0.0;
      auto t = table({"cell (mm)", "cells", "steps", "wall (s)", "impulse at 10 ms (N s)", "vs mean of the finest three", "products (N s)", "soil (N s)",
                      fmt::format("products within {:g} mm (N s)", 1e3 * kJudgedDepth_m), fmt::format("soil within {:g} mm (N s)", 1e3 * kJudgedDepth_m),
                      "energy imbalance (of charge)"});
      json plot{{"cell_mm", h}, {"impulse_Ns", imp}, {"mean_Ns", mean}, {"histories", json::array()}};
      for (std::size_t i = 0; i < h.size(); ++i) {
        const auto& o = get("mesh-" + mm(h[i]) + "mm");
        const double dev = 100.0 * (imp[i] - mean) / mean;
        if (i >= k0) spread = std::max(spread, std::abs(dev));
        t["rows"].push_back({mm(h[i]), std::to_string(o.at("cells").get<long long>()), std::to_string(o.at("steps").get<long long>()),
                             fixed(o.at("wall_s").get<double>(), 0), fixed(imp[i], 0), signedPct(dev), fixed(o.at("impulse_products_Ns").get<double>(), 0),
                             fixed(o.at("impulse_soil_Ns").get<double>(), 0), fixed(nearWallImpulse(o, "products"), 0), fixed(nearWallImpulse(o, "soil"), 0),
                             imbalanceText(o)});
        plot["histories"].push_back({{"label", mm(h[i]) + " mm"}, {"t_s", o.at("history").at("t_s")}, {"impulse_Ns", o.at("history").at("impulse_Ns")}});
      }
      sec["table"] = t;
      std::vector<std::string> fine;
      for (std::size_t i = k0; i < h.size(); ++i) fine.push_back(mm(h[i]));
      // The published claim is about converged cells (2%); the quick level's coarse cells are
      // judged by a wider band, kSpreadQuickPct, and by the trend below.
      const double spread_limit = full ? kSpreadFullPct : kSpreadQuickPct;
      const auto c = check(fmt::format("mesh: impulse at {} mm within {:g}% of their mean", fmt::join(fine, ", "), spread_limit), spread, "%",
                           full ? fmt::format("<= {:g}%", spread_limit) : fmt::format("<= {:g}% (quick level; {:g}% at the full level)", spread_limit, kSpreadFullPct),
                           spread <= spread_limit);
      sec["checks"] = json::array({c});
      checks.push_back(c);
      // A converging scheme changes less with each refinement. The finest step's change against the
      // coarsest's is shown at both levels and judged at neither: the quick sizes (25-12 mm) were
      // meant to lie before the changes reach the noise, but they do not (revision 10: 1.67 / 1.01 /
      // 1.00%, revision 11: 1.42 / 1.47 / 1.44%, no shrinking), and at the full level's cells the
      // changes are that noise too. The spread above judges the study at both levels.
      if (h.size() >= 3) {
        const std::size_t n = h.size();
        auto stepPct = [&](std::size_t i) { return 100.0 * std::abs(imp[i + 1] - imp[i]) / imp[i + 1]; };   // from h[i] to h[i + 1]
        const double first_step = stepPct(0), last_step = stepPct(n - 2);
        const auto ct = check(fmt::format("mesh: the impulse's change from {} to {} mm against the change from {} to {} mm ({:.2f}%)", mm(h[n - 2]), mm(h[n - 1]),
                                          mm(h[0]), mm(h[1]), first_step),
                              last_step, "%", "informative (the changes are at the noise of the mean at these cells; the spread judges the study)",
                              json(nullptr));
        sec["checks"].push_back(ct);
        checks.push_back(ct);
      }
      // Each material's share must converge too: a total that holds still while the products' and
      // the soil's parts move in opposite directions is two errors cancelling. Judged: the split by
      // the materials within each recorded depth of the plate (10, 20, 40 mm), the largest spread of
      // the three. Shown, not judged: the split by the cell beside the plate, the material touching
      // it, which these cells do not converge (a film of sand on the plate and the mixing at its
      // face: docs/validate.md, "The mesh study's split, judged within a fixed depth").
      // the mean of the finest three and their largest deviation from it; the spread is that over the mean, %
      auto meanAndDeviation = [&](const std::vector<double>& v) {
        const double pm = std::accumulate(v.begin() + static_cast<std::ptrdiff_t>(k0), v.end(), 0.0) / static_cast<double>(v.size() - k0);
        double dev = 0.0;
        for (std::size_t i = k0; i < v.size(); ++i) dev = std::max(dev, std::abs(v[i] - pm));
        return std::pair{pm, dev};
      };
      auto spreadOf = [&](const std::vector<double>& v) {
        const auto [pm, dev] = meanAndDeviation(v);
        return 100.0 * dev / std::abs(pm);
      };
      for (const char* part : {"impulse_products_Ns", "impulse_soil_Ns"}) {
        std::vector<double> v;
        for (const double c_h : h) v.push_back(get("mesh-" + mm(c_h) + "mm").at(part).get<double>());
        const double sp = spreadOf(v);
        plot[std::string(part)] = v;
        const std::string what = std::string(part) == "impulse_products_Ns" ? "products'" : "soil's";
        const auto cp = check(fmt::format("mesh: the {} impulse (by the cell beside the plate) at {} mm about their mean", what, fmt::join(fine, ", ")),
                              sp, "%", "informative (the material touching the plate: not converged at these cells)", json(nullptr));
        sec["checks"].push_back(cp);
        checks.push_back(cp);
      }
      // The layer split, at each recorded depth (table), each judged.
      bool near_recorded = true;
      for (const double c_h : h) near_recorded = near_recorded && get("mesh-" + mm(c_h) + "mm").contains("impulse_within_Ns");
      std::vector<double> near_spread;   // products, soil at kJudgedDepth_m (the paragraph's)
      std::array<double, 2> near_worst{0.0, 0.0};   // products, soil: the largest spread over the depths
      auto tn = table({"split by the materials within", "products by cell size (N s)", "products' spread", "soil by cell size (N s)", "soil's spread"});
      if (near_recorded) {
        for (const double depth : hydro::kNearWallDepth_m) {
          std::vector<std::string> row{fmt::format("{:g} mm", 1e3 * depth)};
          for (const char* kind : {"products", "soil"}) {
            std::vector<double> v;
            std::vector<std::string> txt;
            for (const double c_h : h) {
              v.push_back(nearWallImpulse(get("mesh-" + mm(c_h) + "mm"), kind, depth));
              txt.push_back(fmt::format("{}: {}", mm(c_h), fixed(v.back(), 0)));
            }
            const double sp = spreadOf(v);
            auto& worst = near_worst[std::string(kind) == "products" ? 0 : 1];
            worst = std::isfinite(sp) ? std::max(worst, sp) : std::nan("");
            if (std::abs(depth - kJudgedDepth_m) < 1e-9) {
              near_spread.push_back(sp);
              plot[std::string("within_") + kind] = v;
            }
            row.push_back(fmt::format("{}", fmt::join(txt, " / ")));
            row.push_back(fmt::format("{:.1f}%", sp));
          }
          tn["rows"].push_back(row);
        }
      }
      if (near_spread.size() != 2) {
        near_spread = {std::nan(""), std::nan("")};
        near_worst = {std::nan(""), std::nan("")};
      }
      std::vector<std::string> depths;
      for (const double depth : hydro::kNearWallDepth_m) depths.push_back(fmt::format("{:g}", 1e3 * depth));
      for (std::size_t q = 0; q < 2; ++q) {
        const bool judged = full && std::isfinite(near_worst[q]);
        const auto cn = check(fmt::format("mesh: the {} impulse (by the materials within {} mm of the plate, the largest spread) at {} mm within 5% of "
                                          "their mean",
                                          q == 0 ? "products'" : "soil's", fmt::join(depths, ", "), fmt::join(fine, ", ")),
                              near_worst[q], "%", full ? "<= 5%" : "<= 5% (judged at the full level)", judged ? json(near_worst[q] <= 5.0) : json(nullptr));
        sec["checks"].push_back(cn);
        checks.push_back(cn);
      }
      // Each material's internal and kinetic energy at fixed times (J, judged apart, so that an
      // exchange between the two cannot hide): where the energy goes, per material, must converge
      // as well as the load it makes. Each is judged to 5% of its mean, or of kEnergyFloorOfCharge
      // of the charge's energy where it holds less than that (a relative spread of a part near
      // zero measures nothing the budget can feel).
      auto te = table({"energy", "time (ms)", "by cell size (kJ)", "spread of the finest three about their mean",
                       fmt::format("judged: about the larger of the mean and {:g}% of the charge", 100.0 * kEnergyFloorOfCharge)});
      std::vector<std::string> below_floor;   // the parts whose mean lies under the floor at some judged time
      {
        const std::array<double, 5> times{0.5e-3, 1e-3, 2e-3, 5e-3, 10e-3};
        // linear in time between the two samples of the (thinned) history around t_s
        auto energyAt = [&](const json& o, const std::string& column, double t_s) {
          const auto& hist = o.at("history");
          if (!hist.contains(column)) return std::nan("");
          const auto& ts = hist.at("t_s");
          const auto& ys = hist.at(column);
          for (std::size_t i = 1; i < ts.size(); ++i) {
            const double t0 = ts.at(i - 1).get<double>(), t1 = ts.at(i).get<double>();
            if (t1 < t_s && i + 1 < ts.size()) continue;
            if (!ys.at(i - 1).is_number() || !ys.at(i).is_number() || !(t1 > t0)) return std::nan("");
            const double w = std::clamp((t_s - t0) / (t1 - t0), 0.0, 1.0);
            return (1.0 - w) * ys.at(i - 1).get<double>() + w * ys.at(i).get<double>();
          }
          return std::nan("");
        };
        // the charge's energy, the least any level recorded (the same deck at every level); where a
        // level did not record it (an earlier run), no floor: each part against its mean alone
        double charge_J = std::numeric_limits<double>::infinity();
        for (const double c_h : h) {
          const auto& o = get("mesh-" + mm(c_h) + "mm");
          charge_J = o.contains("charge_energy_J") ? std::min(charge_J, o.at("charge_energy_J").get<double>()) : 0.0;
        }
        const double floor_J = std::isfinite(charge_J) ? kEnergyFloorOfCharge * charge_J : 0.0;
        for (const std::string kind : {"products", "soil"})
          for (const std::string part : {"internal", "kinetic"}) {
            const std::string column = part + "_energy_" + kind + "_J";
            double worst = 0.0;
            bool recorded = true;
            for (const double t_s : times) {
              std::vector<double> v;
              std::vector<std::string> txt;
              for (const double c_h : h) {
                v.push_back(energyAt(get("mesh-" + mm(c_h) + "mm"), column, t_s));
                txt.push_back(fmt::format("{}: {}", mm(c_h), fixed(1e-3 * v.back(), 1)));
                recorded = recorded && std::isfinite(v.back());
              }
              const bool all = std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
              double sp = std::nan(""), judged = std::nan("");
              if (all) {
                const auto [pm, dev] = meanAndDeviation(v);
                sp = 100.0 * dev / std::abs(pm);
                judged = 100.0 * dev / std::max(std::abs(pm), floor_J);
                worst = std::max(worst, judged);
                const std::string name = fmt::format("the {} {} energy", kind, part);
                if (std::abs(pm) < floor_J && std::find(below_floor.begin(), below_floor.end(), name) == below_floor.end()) below_floor.push_back(name);
              }
              te["rows"].push_back({fmt::format("{} {}", kind, part), fmt::format("{:g}", 1e3 * t_s), fmt::format("{}", fmt::join(txt, " / ")),
                                    std::isfinite(sp) ? fmt::format("{:.1f}%", sp) : "-", std::isfinite(judged) ? fmt::format("{:.1f}%", judged) : "-"});
            }
            const auto ce = check(fmt::format("mesh: the {} {} energy at 0.5, 1, 2, 5, 10 ms, at {} mm, within 5% of their mean (or of {:g}% of the charge's "
                                              "energy, where larger: a part that small is judged negligible, not converged)",
                                              kind, part, fmt::join(fine, ", "), 100.0 * kEnergyFloorOfCharge),
                                  recorded ? worst : std::nan(""), "%", full ? "<= 5%" : "<= 5% (judged at the full level)",
                                  (full && recorded) ? json(worst <= 5.0) : json(nullptr));
            sec["checks"].push_back(ce);
            checks.push_back(ce);
          }
      }
      sec["tables"] = json::array({tn, te});
      const auto pctText = [](double v) { return std::isfinite(v) ? fmt::format("{:.1f}%", v) : std::string("not recorded"); };
      std::vector<std::string> levels, by_cell, of_total;   // the products' part by the cell beside the plate
      for (std::size_t i = 0; i < h.size(); ++i) {
        levels.push_back(mm(h[i]));
        const double pc = plot["impulse_products_Ns"][i].get<double>();
        by_cell.push_back(fixed(pc, 0));
        if (i >= k0) of_total.push_back(fmt::format("{:.1f}", 100.0 * pc / imp[i]));
      }
      const std::string judged_note = full ? "judged, 5%" : "judged at the full level";
      const std::string near_text =
          std::isfinite(near_worst[0])
              ? fmt::format("By material, split by the materials within {} mm of the plate, the products' impulse of the finest three lies within {} "
                            "of its mean at every depth ({} at {:g} mm) and the soil's within {} ({} at {:g} mm) ({}).",
                            fmt::join(depths, ", "), pctText(near_worst[0]), pctText(near_spread[0]), 1e3 * kJudgedDepth_m, pctText(near_worst[1]),
                            pctText(near_spread[1]), 1e3 * kJudgedDepth_m, judged_note)
              : std::string("By material, the split within a depth of the plate was not recorded (an earlier run).");
      sec["paragraphs"] = json::array(
          {fmt::format("The published study found the total impulse at 10 ms barely moves with the cell size. "
                       "Here the finest three sizes lie within {:.2f}% of their mean ({:.0f} N s); "
                       "the coarsest ({} mm) is {:+.1f}% off it. {} Total energy is conserved (no sink): "
                       "the last column is each run's energy imbalance over the charge's energy.",
                       spread, mean, mm(h[0]), 100.0 * (imp[0] - mean) / mean, near_text),
           fmt::format("A single wall pressure has no unique split by material; both splits are conventions. The split within a fixed depth of "
                       "the plate asks which materials lie in a layer of set thickness beneath it, the same layer at every cell size. The split "
                       "by the cell beside the plate asks which material touches it: its products' part is {} N s at {} mm ({}% of the total at "
                       "the finest three), falling about as the cell does, so the material at the plate's face (a film of sand, the mixing at its "
                       "face) is not converged at these cells and this split is not a prediction. It is shown, not judged (docs/validate.md).",
                       fmt::join(by_cell, " / "), fmt::join(levels, " / "), fmt::join(of_total, " / ")),
           fmt::format("Each material's internal and kinetic energy at fixed times is judged apart, to 5% of its mean or of {:g}% of the "
                       "charge's energy where that is larger. A part below that floor is judged negligible, not converged{}. The table gives both "
                       "spreads.",
                       100.0 * kEnergyFloorOfCharge,
                       below_floor.empty() ? std::string(": here none is") : fmt::format(": here {}", fmt::join(below_floor, " and ")))});
      sec["figure"] = "mesh.png";
      sec["caption"] = fmt::format("Impulse on the fixed plate vs time for each cell size (left), at 10 ms vs cell size (middle), and by material "
                                   "(right: within {:g} mm of the plate, judged; by the cell beside it, dashed, shown).",
                                   1e3 * kJudgedDepth_m);
      sec["plot"] = plot;
    } else if (study == "moisture") {
      sec["title"] = "Moisture (EMI flat plate, free 300 kg plate, friction 0.2)";
      auto t = table({"moisture", "impulse (N s)", "vs 7%", "air (N s)", "products (N s)", "soil (N s)", "peak force (MN)", "cell (mm)"});
      json plot{{"moisture_pct", json::array()}, {"impulse_Ns", json::array()}, {"histories", json::array()}};
      const double i7 = impulse("emi-flat-7");
      std::array<double, 3> imps{};
      std::size_t q = 0;
      for (const auto& [deck, w] : moistureDecks()) {
        const auto& o = get(deck);
        const double I = o.at("impulse_Ns").get<double>();
        imps.at(q++) = I;
        t["rows"].push_back({fmt::format("{:g}%", w), fixed(I, 0), signedPct(100.0 * (I - i7) / i7), fixed(o.at("impulse_air_Ns").get<double>(), 0),
                             fixed(o.at("impulse_products_Ns").get<double>(), 0), fixed(o.at("impulse_soil_Ns").get<double>(), 0),
                             fixed(o.at("peak_force_N").get<double>() / 1e6, 1), mm(o.at("cell_mm").get<double>())});
        plot["moisture_pct"].push_back(w);
        plot["impulse_Ns"].push_back(I);
        plot["histories"].push_back({{"label", fmt::format("{:g}%", w)}, {"t_s", o.at("history").at("t_s")}, {"impulse_Ns", o.at("history").at("impulse_Ns")}});
      }
      const double rise = 100.0 * (imps[2] - imps[0]) / imps[0];
      const bool monotone = imps[1] > imps[0] && imps[2] > imps[1];
      const auto c = check("moisture: impulse rises from 7% to 22%", rise, "%", "> 0", rise > 0.0);
      sec["checks"] = json::array({c});
      checks.push_back(c);
      sec["table"] = t;
      sec["paragraphs"] = json::array({fmt::format("The published tests show the impulse rising clearly with moisture. ejecta: {:+.1f}% from 7% to 22%, {}.", rise,
                                                   monotone ? "rising at each step" : "not rising at each step")});
      sec["figure"] = "moisture.png";
      sec["caption"] = "Impulse on the plate vs time at 7, 14 and 22% moisture (left) and at 10 ms vs moisture (right).";
      sec["plot"] = plot;
    } else if (study == "field") {
      sec["title"] = "Field-test conditions: a looser, drier backfilled cover (bed 1670 kg/m3 at 22%)";
      auto t = table({"cover thickness", "cover soil", "impulse (N s)", "vs undisturbed", "soil share"});
      json plot{{"groups", json::array()}};
      double worst = 0.0;
      for (const double thick : {5.0, 2.5}) {
        const std::string ref = thick == 5.0 ? "field-cover22-5cm" : "field-cover22-2.5cm";
        const double i0 = impulse(ref);
        json g{{"thickness_cm", thick}, {"labels", json::array()}, {"impulse_Ns", json::array()}, {"change_pct", json::array()}};
        for (const auto& f : fieldCases()) {
          if (f.thickness_cm != thick) continue;
          const auto& o = get(f.deck);
          const double I = o.at("impulse_Ns").get<double>();
          const double d = 100.0 * (I - i0) / i0;
          worst = std::max(worst, std::abs(d));
          t["rows"].push_back({fmt::format("{:g} cm", thick), f.cover, fixed(I, 0), signedPct(d),
                               fmt::format("{:.0f}%", 100.0 * o.at("impulse_soil_Ns").get<double>() / I)});
          g["labels"].push_back(f.cover.substr(0, f.cover.find(" (")));
          g["impulse_Ns"].push_back(I);
          g["change_pct"].push_back(d);
        }
        plot["groups"].push_back(g);
      }
      sec["table"] = t;
      const auto c = check("field: largest change of impulse from a backfilled cover", worst, "%", fmt::format("<= {:g}% (published: small)", kFieldChangePct),
                           worst <= kFieldChangePct);
      sec["checks"] = json::array({c});
      checks.push_back(c);
      sec["paragraphs"] = json::array({fmt::format(
          "The published study found that a looser, drier backfill over the charge barely changes the impulse on the plate. "
          "ejecta's largest change is {:.1f}%. The 5 cm undisturbed case is the EMI 22% deck with the cover drawn as a separate layer "
          "of the same soil; it differs from the EMI 22% deck only by the layering.",
          worst)});
      sec["figure"] = "field.png";
      sec["caption"] = "Impulse at 10 ms for each cover soil, 5 cm and 2.5 cm covers.";
      sec["plot"] = plot;
    } else if (study == "share") {
      sec["title"] = "Which material carries the impulse";
      auto t = table({"case", "impulse (N s)", "air", "products", "soil"});
      json plot{{"labels", json::array()}, {"air", json::array()}, {"products", json::array()}, {"soil", json::array()}};
      std::vector<std::string> ids;
      for (const auto& [deck, w] : moistureDecks()) ids.push_back(deck);
      for (const auto& f : fieldCases()) ids.push_back(f.deck);
      double soil_min = 100.0, soil_max = 0.0, air_min = 100.0, air_max = -100.0;
      for (const auto& id : ids) {
        const auto& o = get(id);
        const double I = o.at("impulse_Ns").get<double>();
        const double a = o.at("impulse_air_Ns").get<double>(), p = o.at("impulse_products_Ns").get<double>(), s = o.at("impulse_soil_Ns").get<double>();
        soil_min = std::min(soil_min, 100.0 * s / I);
        soil_max = std::max(soil_max, 100.0 * s / I);
        air_min = std::min(air_min, 100.0 * a / I);
        air_max = std::max(air_max, 100.0 * a / I);
        t["rows"].push_back({id, fixed(I, 0), fmt::format("{:.0f} N s ({:.0f}%)", a, 100.0 * a / I), fmt::format("{:.0f} N s ({:.0f}%)", p, 100.0 * p / I),
                             fmt::format("{:.0f} N s ({:.0f}%)", s, 100.0 * s / I)});
        plot["labels"].push_back(id);
        plot["air"].push_back(a);
        plot["products"].push_back(p);
        plot["soil"].push_back(s);
      }
      sec["table"] = t;
      sec["checks"] = json::array();
      sec["paragraphs"] = json::array({fmt::format(
          "The impulse split by the material in the flow cell beside each plate face (air, detonation products, soil). Soil carries "
          "{:.0f}% to {:.0f}% of it, the air {:.0f}% to {:.0f}%. Each share is booked against the ambient pressure (the load at rest is "
          "taken off the air's), so the air's share is what the blast adds to the air's push on the plate (docs/run.md, \"The load by "
          "material\").",
          soil_min, soil_max, air_min, air_max)});
      sec["figure"] = "share.png";
      sec["caption"] = "Impulse by material, N s.";
      sec["plot"] = plot;
    } else if (study == "sensitivity") {
      sec["title"] = "Sensitivity to the inputs we do not know exactly, and to the time step (EMI flat plate, 7%)";
      const double i0 = impulse(sensitivityBaseline(sz));
      auto t = table({"input", "baseline", "changed to", "impulse (N s)", "change", "rate"});
      json plot{{"labels", json::array()}, {"change_pct", json::array()}, {"baseline_Ns", i0}};
      for (const auto& p : perturbations()) {
        const double I = impulse(p.id);
        const double d = 100.0 * (I - i0) / i0;
        t["rows"].push_back({p.input, p.base, p.changed, fixed(I, 0), signedPct(d), fmt::format("{:+.2f} {}", d / p.per, p.per_unit)});
        plot["labels"].push_back(p.input + ": " + p.changed);
        plot["change_pct"].push_back(d);
      }
      sec["table"] = t;
      sec["checks"] = json::array();
      auto change = [&](const std::string& id) { return 100.0 * (impulse(id) - i0) / i0; };
      sec["paragraphs"] = json::array(
          {fmt::format("Each input changed alone from the EMI 7% deck (baseline {:.0f} N s at {} mm cells, plate 0.10 m over the sand). The "
                       "standoff of the EMI plate and the charge's shape are not stated in our sources; the yield plateau law is ours "
                       "(docs/sand-model.md); the water EOS sets are the two in shared/data.",
                       i0, mm(sz.sensitivity)),
           fmt::format("Impulse against standoff: {:.0f} / {:.0f} / {:.0f} / {:.0f} / {:.0f} N s at 0 / 0.05 / 0.10 / 0.20 / 0.30 m.", impulse("sens-standoff-0cm"),
                       impulse("sens-standoff-5cm"), i0, impulse("sens-standoff-20cm"), impulse("sens-standoff-30cm")),
           fmt::format("The coupling: held fixed, the plate takes {:+.1f}% against the free plate; a free plate whose cells stay where they started "
                       "(its velocity only in the wall condition) takes {:+.1f}%. A free plate that moves the mesh rises away from the "
                       "load: the gap beneath it opens and the soil and products in it expand and unload, so it takes less (docs/run.md).",
                       change("sens-plate-fixed"), change("sens-plate-static-mesh")),
           fmt::format("The plate-to-soil friction (0.2 in the EMI decks; since solver revision 12 it acts on the sand's share of the contact "
                       "only, gas and products sliding freely): frictionless the plate takes {:+.1f}%, at 0.4 {:+.1f}%.",
                       change("sens-friction-0"), change("sens-friction-0.4")),
           fmt::format("The time step: the shear modulus cap moves the impulse {:+.1f}% (10 GPa) and {:+.1f}% (1 GPa) and lets the step grow (the "
                       "compacted sand's longitudinal speed sets it late in the run); a smaller Courant number at the same cells moves it {:+.1f}%. "
                       "Part of the cap's change is the step's, not the sand's (docs/sand-model.md, docs/validate.md).",
                       change("sens-shear-cap-10gpa"), change("sens-shear-cap-1gpa"), change("sens-cfl-0.15")),
           fmt::format("The mixed cells' stiffness, a choice of the scheme rather than an input: revision 14's frozen (Voigt) sum at Courant "
                       "0.45 in place of the Reuss modulus at 0.30 moves the impulse {:+.1f}% (docs/solver.md, Revision 15).",
                       change("sens-mixture-frozen"))});
      sec["figure"] = "sensitivity.png";
      sec["caption"] = "Change of the impulse at 10 ms for each changed input.";
      sec["plot"] = plot;
    } else if (study == "vplates") {
      sec["title"] = fmt::format("V-plates in 3D (EMI 7%, free 300 kg plate, quarter symmetry, {} mm cells, impulse at {:g} ms)", mm(sz.vplate),
                                 full ? 10.0 : 1e3 * kVPlateQuickEnd_s);
      auto t = table({"plate", "impulse (N s)", "vs 3D flat", "air (N s)", "products (N s)", "soil (N s)", "peak force (MN)", "cells", "steps", "wall (s)",
                      "energy imbalance (of charge)"});
      const auto cases = vplateCases(sz, plan.level);
      std::array<double, 4> I{};
      for (std::size_t i = 0; i < I.size(); ++i) I.at(i) = impulse(cases.at(i).id);
      const double flat3 = I[1];
      json plot{{"labels", json::array()}, {"air", json::array()}, {"products", json::array()}, {"soil", json::array()}, {"histories", json::array()}};
      for (std::size_t i = 0; i < cases.size(); ++i) {
        const auto& o = get(cases[i].id);
        plot["labels"].push_back(cases[i].label);
        plot["air"].push_back(o.at("impulse_air_Ns"));
        plot["products"].push_back(o.at("impulse_products_Ns"));
        plot["soil"].push_back(o.at("impulse_soil_Ns"));
        plot["histories"].push_back({{"label", cases[i].label}, {"t_s", o.at("history").at("t_s")}, {"impulse_Ns", o.at("history").at("impulse_Ns")}});
        t["rows"].push_back({cases[i].label, fixed(I[i], 0), signedPct(100.0 * (I[i] - flat3) / flat3), fixed(o.at("impulse_air_Ns").get<double>(), 0),
                             fixed(o.at("impulse_products_Ns").get<double>(), 0), fixed(o.at("impulse_soil_Ns").get<double>(), 0),
                             fixed(o.at("peak_force_N").get<double>() / 1e6, 1), std::to_string(o.at("cells").get<long long>()),
                             std::to_string(o.at("steps").get<long long>()), fixed(o.at("wall_s").get<double>(), 0), imbalanceText(o)});
      }
      sec["table"] = t;
      const auto c1 = check("V-plates: the 120 degree V takes less impulse than the flat plate (3D)", 100.0 * (I[2] - flat3) / flat3, "%", "< 0", I[2] < flat3);
      const auto c2 = check("V-plates: the 90 degree V takes less than the 120 degree V", 100.0 * (I[3] - I[2]) / I[2], "%", "< 0", I[3] < I[2]);
      const double d23 = 100.0 * (flat3 - I[0]) / I[0];
      const auto c3 = check("V-plates: the 3D flat plate against the 2D one (same deck and core cells; the 3D far field graded as the V-plates')",
                            d23, "%", "informative", json(nullptr));
      sec["checks"] = json::array({c1, c2, c3});
      checks.push_back(c1);
      checks.push_back(c2);
      checks.push_back(c3);
      const double wall120 = get("emi-v120-7").at("wall_s").get<double>();
      const bool parts120 = get("emi-v120-7").value("in_parts", false);
      sec["paragraphs"] = json::array(
          {fmt::format("The published V-plate results are the cases where other codes were off by the most. The detonation and first expansion "
                       "run on the axisymmetric early-time block and are mapped onto the 3D quarter (docs/solver.md). The flat plate in 3D takes "
                       "{:+.1f}% against the 2D run of the same deck at the same core cells: the quarter's square cells against the rings, the "
                       "disc's staircase in 3D, and its far field graded as the V-plates' (docs/validate.md). The 120 degree V takes {:+.1f}% "
                       "and the 90 degree V {:+.1f}% against the 3D flat plate. The 120 degree case took {:.0f} s ({:.1f} min) here{} ({}).",
                       d23, 100.0 * (I[2] - flat3) / flat3, 100.0 * (I[3] - flat3) / flat3, wall120, wall120 / 60.0,
                       parts120 ? ", in parts continued from checkpoints (the parts' wall times added; the machine may have been shared)" : "",
                       sz.vplate != sizesOf(plan.level).vplate
                           ? fmt::format("{} mm cells chosen with --vplate-cell-size; the issue's aim, under 30 minutes on 2 cores, is for 10 mm", mm(sz.vplate))
                           : (full ? fmt::format("the issue's aim, under 30 minutes on 2 cores: {}", wall120 < 1800.0 ? "met" : "not met")
                                   : "quick level: 60 mm cells, the ordering only")),
           "The V's load by material is split by the cell beside each wing face, as for the flat plate."});
      sec["figure"] = "vplates.png";
      sec["caption"] = "Impulse on each plate vs time (left) and its split by the material in the cell beside the plate (right).";
      sec["plot"] = plot;
    } else if (study == "dres") {
      sec["title"] = "DRES soil bubble (100 g C-4, 3 cm and 8 cm burial, no target)";
      auto t = table({"time (ms)", "3 cm: top of soil (mm)", "3 cm: on axis (mm)", "8 cm: top of soil (mm)", "8 cm: on axis (mm)"});
      json plot{{"cases", json::array()}};
      const std::vector<double> times{0.1e-3, 0.2e-3, 0.3e-3, 0.5e-3, 0.75e-3, 1.0e-3};
      auto at = [](const json& h, const std::string& col, double time) {
        const auto& ts = h.at("t_s");
        const auto& v = h.at(col);
        for (std::size_t i = 1; i < ts.size(); ++i)
          if (ts[i].get<double>() >= time) {
            if (v[i - 1].is_null() || v[i].is_null()) return std::nan("");
            const double t0 = ts[i - 1].get<double>(), t1 = ts[i].get<double>();
            const double w = t1 > t0 ? (time - t0) / (t1 - t0) : 1.0;
            return v[i - 1].get<double>() + w * (v[i].get<double>() - v[i - 1].get<double>());
          }
        return std::nan("");
      };
      const auto& a = get("dres-3cm");
      const auto& b = get("dres-8cm");
      for (const double tm : times)
        t["rows"].push_back({fmt::format("{:g}", tm * 1e3), fixed(1e3 * at(a.at("history"), "soil_top_m", tm), 0),
                             fixed(1e3 * at(a.at("history"), "bubble_height_on_axis_m", tm), 0), fixed(1e3 * at(b.at("history"), "soil_top_m", tm), 0),
                             fixed(1e3 * at(b.at("history"), "bubble_height_on_axis_m", tm), 0)});
      // break-out: the first time the axis column above the charge holds no soil (under 10%) up to
      // the original surface, i.e. the products have vented through the dome
      auto breakout = [](const json& h) {
        const auto& ts = h.at("t_s");
        const auto& z = h.at("bubble_height_on_axis_m");
        for (std::size_t i = 0; i < ts.size(); ++i)
          if (!z[i].is_null() && z[i].get<double>() < 0.0) return ts[i].get<double>();
        return std::nan("");
      };
      const double ba = breakout(a.at("history")), bb = breakout(b.at("history"));
      t["rows"].push_back({"break-out (ms)", fixed(1e3 * ba, 2), "", fixed(1e3 * bb, 2), ""});
      for (const auto* o : {&a, &b})
        plot["cases"].push_back({{"label", o->at("id")}, {"history", o->at("history")}, {"profiles", o->at("profiles")}});
      sec["table"] = t;
      sec["checks"] = json::array();
      sec["paragraphs"] = json::array({fmt::format(
          "Height of the soil over the original surface: the top of the highest cell holding at least 10% soil by volume, anywhere (the "
          "bubble's or the ejecta's top) and on the axis. The measured histories (high-speed film) are not available to us, so this is a "
          "prediction to compare when they are. Break-out: the first time the axis column is clear of soil down to the original surface "
          "(the detonation products have vented through the dome). Cells of {} mm.",
          mm(sz.bubble))});
      sec["figure"] = "dres.png";
      sec["caption"] = "Soil-bubble height vs time (left) and the soil surface at the profile times (3 cm, 8 cm).";
      sec["plot"] = plot;
    }
    sections.push_back(sec);
  }
  rep["sections"] = sections;
  rep["checks"] = checks;

  // every case: the machine-readable table, and the last section
  json rows = json::array();
  auto t = table({"case", "deck", "change", "cell (mm)", "cells", "steps", "wall (s)", "impulse (N s)", "energy imbalance (of charge)", "reference", "error"});
  for (const auto& c : plan.cases) {
    const auto& o = get(c.id);
    const bool has_target = o.at("peak_force_N").get<double>() > 0.0;
    rows.push_back({{"id", c.id},
                    {"deck", c.deck},
                    {"change", c.change},
                    {"cell_mm", c.cell_mm},
                    {"cells", o.at("cells")},
                    {"steps", o.at("steps")},
                    {"wall_s", o.at("wall_s")},
                    {"impulse_Ns", has_target ? o.at("impulse_Ns") : json(nullptr)},
                    {"impulse_air_Ns", o.at("impulse_air_Ns")},
                    {"impulse_products_Ns", o.at("impulse_products_Ns")},
                    {"impulse_soil_Ns", o.at("impulse_soil_Ns")},
                    {"energy_imbalance_fraction", o.value("energy_imbalance_fraction", json(nullptr))},
                    {"reference_Ns", nullptr},
                    {"error_pct", nullptr},
                    {"reference_note", "no measured value in shared/data"}});
    t["rows"].push_back({c.id, c.deck, c.change, mm(c.cell_mm), std::to_string(o.at("cells").get<long long>()), std::to_string(o.at("steps").get<long long>()),
                         fixed(o.at("wall_s").get<double>(), 1), has_target ? fixed(o.at("impulse_Ns").get<double>(), 0) : "-", imbalanceText(o), "n/a", "-"});
  }
  rep["cases"] = rows;
  rep["cases_table"] = t;
  return rep;
}

}  // namespace ejecta::scenario

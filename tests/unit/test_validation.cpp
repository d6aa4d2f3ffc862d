// `ejecta validate`'s plan and analyses (every planned case's deck loads with its overrides; the
// studies' numbers from given results) and the report renderers (base64, HTML escaping, tables).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "core/error.hpp"
#include "ejecta/build_info.hpp"
#include "io/report.hpp"
#include "scenario/case.hpp"
#include "scenario/deck.hpp"
#include "scenario/validation.hpp"

namespace ejecta {
namespace {
using nlohmann::json;
using scenario::ValidationLevel;

// A planned case's deck as its run loads it: the built-in deck with the case's overrides.
scenario::Deck plannedDeck(const scenario::ValidationCase& c) {
  return scenario::loadDeck((std::filesystem::path(build_info::decks_dir) / (c.deck + ".toml")).string(), c.sets);
}

TEST(ValidationPlan, FullLevelRunsThePublishedResolutionsAndEveryDeckLoads) {
  const auto plan = scenario::validationPlan(ValidationLevel::Full);
  std::set<std::string> ids;
  std::set<double> mesh;
  for (const auto& c : plan.cases) {
    EXPECT_TRUE(ids.insert(c.id).second) << c.id << " planned twice";
    if (c.deck == "mesh-study") mesh.insert(c.cell_mm);
    else if (c.deck.starts_with("dres")) EXPECT_DOUBLE_EQ(c.cell_mm, 3.0);
    else if (c.id.starts_with("sens")) EXPECT_DOUBLE_EQ(c.cell_mm, 10.0) << c.id;   // changes only: 10 mm keeps --full under 2 h
    else if (c.deck.starts_with("emi-v") || c.id.ends_with("-3d")) {
      EXPECT_DOUBLE_EQ(c.cell_mm, 10.0) << c.id;   // the 3D quarter cases (the 2D flat beside them is the sensitivity baseline)
      EXPECT_EQ(plannedDeck(c).geometry, "3d-quarter") << c.id;
    } else EXPECT_DOUBLE_EQ(c.cell_mm, 5.0) << c.id;
    // the overrides name real keys (soil.0.plateau_scale, ...) and the cell size lands in the deck
    const auto deck = plannedDeck(c);
    EXPECT_DOUBLE_EQ(deck.mesh.cell_size_m, c.cell_mm / 1000.0) << c.id;
    // and every plate, the standoff study's raised ones too, lies in its case's uniform core
    EXPECT_EQ(scenario::targetOutsideCore(deck), std::vector<std::string>{}) << c.id;
  }
  EXPECT_EQ(mesh, (std::set<double>{3.0, 4.0, 5.0, 6.0, 10.0}));
  EXPECT_EQ(plan.studies.size(), scenario::validationStudies().size());
}

TEST(ValidationPlan, TheThreeQuarterPlatesShareTheirFarField) {
  // the flat plate in 3D comes from the 2D deck: its far field must be graded as the V-plates' are,
  // or the three 3D plates differ in more than the plate
  const auto plan = scenario::validationPlan(ValidationLevel::Full, {"vplates"}, 20.0);
  std::set<double> grading;
  int quarters = 0;
  for (const auto& c : plan.cases) {
    const auto deck = plannedDeck(c);
    if (deck.geometry != "3d-quarter") continue;
    ++quarters;
    grading.insert(deck.mesh.grading);
    EXPECT_DOUBLE_EQ(deck.mesh.cell_size_m, 0.020) << c.id;
  }
  EXPECT_EQ(quarters, 3);
  ASSERT_EQ(grading.size(), 1u) << "the 3D quarter plates have different far fields";
  EXPECT_GT(*grading.begin(), 1.05);   // coarser than the 2D decks' (docs/validate.md, "The far field of the 3D decks")
}

TEST(ValidationPlan, OnlyPicksStudiesAndTheirCasesAndRejectsUnknownNames) {
  const auto plan = scenario::validationPlan(ValidationLevel::Quick, {"sensitivity"});
  ASSERT_EQ(plan.studies, std::vector<std::string>{"sensitivity"});
  EXPECT_EQ(plan.cases.size(), 19u);   // the EMI 7% baseline and 18 changed inputs (four standoffs, two couplings, two charge shapes, the plateau, the water set, two shear caps, the shear law, the Poisson bound, two frictions, the step, the mixed cells' stiffness)
  EXPECT_EQ(plan.cases.front().id, "emi-flat-7");
  try {
    scenario::validationPlan(ValidationLevel::Quick, {"mesh", "bogus"});
    FAIL() << "an unknown study was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "only");
  }
}

TEST(ValidationPlan, VPlateCellSizeMovesOnlyTheVPlatesAndIsChecked) {
  const auto plan = scenario::validationPlan(ValidationLevel::Full, {"vplates"}, 20.0);
  ASSERT_EQ(plan.cases.size(), 4u);   // the 2D flat plate beside three 3D quarters, all at 20 mm
  for (const auto& c : plan.cases) {
    EXPECT_DOUBLE_EQ(c.cell_mm, 20.0) << c.id;
    const auto deck = plannedDeck(c);
    EXPECT_DOUBLE_EQ(deck.mesh.cell_size_m, 0.020) << c.id;
    EXPECT_DOUBLE_EQ(deck.end_time_s, 0.010) << c.id;   // the full level's 10 ms
  }
  // the other studies keep the level's sizes
  for (const auto& c : scenario::validationPlan(ValidationLevel::Full, {"mesh", "vplates"}, 20.0).cases)
    if (c.deck == "mesh-study") {
      EXPECT_NE(c.cell_mm, 20.0) << c.id;
    }
  // at the quick level the V-plates stop at 5 ms: the 2D flat plate beside them is their own run,
  // not the sensitivity study's 10 ms baseline, even at the same cell size
  const auto quick = scenario::validationPlan(ValidationLevel::Quick, {}, 20.0);
  for (const auto& c : quick.cases)
    if (c.id == "vplate-flat-2d-20mm") {
      EXPECT_DOUBLE_EQ(plannedDeck(c).end_time_s, 0.005);
    }
  EXPECT_EQ(std::count_if(quick.cases.begin(), quick.cases.end(), [](const auto& c) { return c.id == "vplate-flat-2d-20mm"; }), 1);
  for (const double bad : {3.0, 150.0, -20.0, std::nan("")}) {
    try {
      scenario::validationPlan(ValidationLevel::Full, {"vplates"}, bad);
      FAIL() << bad << " mm was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "vplate-cell-size");
    }
  }
}

// A made-up result for a case: impulse I split 10/20/70% air/products/soil (by the cell beside the
// plate; 10/30/60% within each depth), a straight history; each kind's energy scales with I.
json outcome(const scenario::ValidationCase& c, double impulse, bool near_recorded = true) {
  scenario::RunResult r;
  r.impulse_Ns = impulse;
  r.impulse_air_Ns = 0.1 * impulse;
  r.impulse_products_Ns = 0.2 * impulse;
  r.impulse_soil_Ns = 0.7 * impulse;
  r.peak_force_N = 1e6;
  r.cells = 100;
  r.steps = 10;
  if (near_recorded)
    for (int l = 0; l < 3; ++l) r.impulse_near_Ns.insert(r.impulse_near_Ns.end(), {0.1 * impulse, 0.3 * impulse, 0.6 * impulse});
  r.history_columns = {"t_s", "impulse_Ns", "soil_top_m", "bubble_height_on_axis_m"};
  if (near_recorded)
    for (const char* e : {"internal_energy_products_J", "kinetic_energy_products_J", "internal_energy_soil_J", "kinetic_energy_soil_J"})
      r.history_columns.push_back(e);
  for (int i = 0; i <= 1000; ++i) {
    r.history.push_back({1e-5 * i, impulse * i / 1000.0, 1e-4 * i, 5e-5 * i});
    if (near_recorded) r.history.back().insert(r.history.back().end(), {500.0 * impulse, 100.0 * impulse, 20.0 * impulse * i, 1e3 * impulse});
  }
  r.profile_r_m = {0.0, 0.1};
  r.profile_times_s = {1e-3};
  r.profiles_m = {{0.05, std::nan("")}};
  r.energy_imbalance_fraction = 1.25e-13;
  r.charge_energy_J = 3.3e6;
  return scenario::condenseOutcome(c, r, 100);
}

TEST(ValidationReport, StudiesComputeSpreadTrendsAndChangesFromTheResults) {
  const auto plan = scenario::validationPlan(ValidationLevel::Full);
  std::map<std::string, json> out;
  const std::map<std::string, double> given{{"mesh-10mm", 5400.0}, {"mesh-6mm", 4900.0}, {"mesh-5mm", 4900.0}, {"mesh-4mm", 5000.0}, {"mesh-3mm", 5100.0},
                                            {"emi-flat-7", 4000.0}, {"emi-flat-14", 4400.0}, {"emi-flat-22", 4200.0},
                                            {"field-cover22-5cm", 5000.0}, {"field-cover7-5cm", 5250.0}, {"sens-baseline-10mm", 4000.0},
                                            {"sens-standoff-5cm", 3800.0}};
  for (const auto& c : plan.cases) out[c.id] = outcome(c, given.contains(c.id) ? given.at(c.id) : 5000.0);
  const auto rep = scenario::validationReport(plan, out, json{{"ejecta_version", "test"}});
  auto section = [&](const std::string& id) {
    for (const auto& s : rep.at("sections"))
      if (s.at("id") == id) return s;
    return json();
  };
  // mesh: finest three 4900/5000/5100, mean 5000: spread 2% exactly, which passes
  const auto mesh = section("mesh");
  EXPECT_NEAR(mesh.at("checks")[0].at("value").get<double>(), 2.0, 1e-9);
  EXPECT_TRUE(mesh.at("checks")[0].at("pass").get<bool>());
  EXPECT_NEAR(mesh.at("plot").at("mean_Ns").get<double>(), 5000.0, 1e-9);
  EXPECT_EQ(mesh.at("table").at("rows")[1][10], "1.2e-13");   // the energy books' imbalance over the charge's energy
  EXPECT_EQ(mesh.at("table").at("rows")[1][8], "1470");      // the products within 20 mm: 30% of 4900 N s
  // the trend (5400 -> 4900 -> ... -> 5100: the last step 1.96%, the first 10.2%) is the quick
  // level's check; at the full level's converged cells it is shown, not judged
  ASSERT_EQ(mesh.at("checks").size(), 10u);
  EXPECT_NEAR(mesh.at("checks")[1].at("value").get<double>(), 100.0 * 100.0 / 5100.0, 1e-9);
  EXPECT_TRUE(mesh.at("checks")[1].at("pass").is_null());
  // each material's share is judged within 20 mm of the plate (here the parts scale with the
  // total, 2% each); by the cell beside it, a one-cell average, it is shown, not judged
  for (std::size_t i = 2; i < 4; ++i) {
    EXPECT_NEAR(mesh.at("checks")[i].at("value").get<double>(), 2.0, 1e-9) << i;
    EXPECT_TRUE(mesh.at("checks")[i].at("pass").is_null()) << i;
  }
  // ...and each material's internal and kinetic energy at fixed times (judged)
  for (std::size_t i = 4; i < 10; ++i) {
    EXPECT_NEAR(mesh.at("checks")[i].at("value").get<double>(), 2.0, 1e-9) << i;
    EXPECT_TRUE(mesh.at("checks")[i].at("pass").get<bool>()) << i;
  }
  EXPECT_EQ(mesh.at("tables")[0].at("rows").size(), 3u);    // the layer split at 10, 20 and 40 mm
  EXPECT_EQ(mesh.at("tables")[1].at("rows").size(), 20u);   // 2 materials x 2 energies x 5 times
  // moisture: 7% -> 22% rises by 5% although 14% -> 22% falls
  const auto moist = section("moisture");
  EXPECT_NEAR(moist.at("checks")[0].at("value").get<double>(), 5.0, 1e-9);
  EXPECT_TRUE(moist.at("checks")[0].at("pass").get<bool>());
  EXPECT_NE(moist.at("paragraphs")[0].get<std::string>().find("not rising at each step"), std::string::npos);
  // field: +5% against the undisturbed 5 cm case is the largest change, under the 10% limit
  EXPECT_NEAR(section("field").at("checks")[0].at("value").get<double>(), 5.0, 1e-9);
  EXPECT_TRUE(section("field").at("checks")[0].at("pass").get<bool>());
  // sensitivity: 5 cm less standoff (0.10 -> 0.05 m) costs 5% here, +1% per cm of standoff
  const auto sens = section("sensitivity");
  EXPECT_EQ(sens.at("table").at("rows")[1][2], "0.05 m");
  EXPECT_EQ(sens.at("table").at("rows")[1][4], "-5.0%");
  EXPECT_EQ(sens.at("table").at("rows")[1][5], "+1.00 % per cm");
  // the impulse against standoff over 0-0.3 m, and the fixed plate against the free one
  EXPECT_NE(sens.at("paragraphs")[1].get<std::string>().find("5000 / 3800 / 4000 / 5000 / 5000 N s at 0 / 0.05 / 0.10 / 0.20 / 0.30 m"), std::string::npos);
  EXPECT_NE(sens.at("paragraphs")[2].get<std::string>().find("held fixed, the plate takes +25.0%"), std::string::npos);
  // histories thinned to at most ~100 rows, the last kept
  const auto& h = out.at("mesh-5mm").at("history");
  EXPECT_LE(h.at("t_s").size(), 102u);
  EXPECT_DOUBLE_EQ(h.at("t_s").back().get<double>(), 1e-2);
  EXPECT_TRUE(out.at("mesh-5mm").at("profiles").at("z_m")[0][1].is_null());
  // the machine-readable table has every case, no reference values claimed
  EXPECT_EQ(rep.at("cases").size(), plan.cases.size());
  EXPECT_TRUE(rep.at("cases")[0].at("reference_Ns").is_null());
}

// A mesh study whose splits and energies the runs did not record (an earlier build's results)
// says so: the checks are shown as not recorded, never passed.
TEST(ValidationReport, SplitsAnEarlierRunDidNotRecordAreNotJudged) {
  const auto plan = scenario::validationPlan(ValidationLevel::Full, {"mesh"});
  std::map<std::string, json> out;
  for (const auto& c : plan.cases) out[c.id] = outcome(c, 5000.0, c.id != "mesh-4mm");
  const auto rep = scenario::validationReport(plan, out, json::object());
  const auto& checks = rep.at("checks");
  ASSERT_EQ(checks.size(), 10u);
  for (std::size_t i = 4; i < 10; ++i) {
    EXPECT_TRUE(checks[i].at("value").is_null()) << i;
    EXPECT_TRUE(checks[i].at("pass").is_null()) << i;
  }
  EXPECT_NE(io::renderReportMarkdown(rep).find("not recorded (an earlier run)"), std::string::npos);
}

// A products' share that falls with the cell size while the total holds fails its check (within
// 20 mm of the plate), and a soil kinetic energy that drifts fails its own.
TEST(ValidationReport, ADriftingShareAndADriftingEnergyFail) {
  const auto plan = scenario::validationPlan(ValidationLevel::Full, {"mesh"});
  std::map<std::string, json> out;
  const std::map<std::string, double> products{{"mesh-10mm", 0.45}, {"mesh-6mm", 0.4}, {"mesh-5mm", 0.33}, {"mesh-4mm", 0.3}, {"mesh-3mm", 0.25}};
  for (const auto& c : plan.cases) {
    out[c.id] = outcome(c, 5000.0);
    auto& w = out[c.id]["impulse_within_Ns"];
    for (std::size_t l = 0; l < 3; ++l) w["products"][l] = products.at(c.id) * 5000.0;
    for (auto& e : out[c.id]["history"]["kinetic_energy_soil_J"]) e = e.get<double>() * products.at(c.id);
  }
  const auto checks = scenario::validationReport(plan, out, json::object()).at("checks");
  EXPECT_FALSE(checks[4].at("pass").get<bool>());   // products 1650/1500/1250 N s: 14.8% about their mean
  EXPECT_NEAR(checks[4].at("value").get<double>(), 100.0 * (4400.0 / 3.0 - 1250.0) / (4400.0 / 3.0), 1e-9);
  EXPECT_TRUE(checks[5].at("pass").get<bool>());    // the soil within 20 mm: unchanged
  EXPECT_TRUE(checks[2].at("pass").is_null());      // by the cell beside the plate: shown only
  EXPECT_TRUE(checks[6].at("pass").get<bool>());    // products' internal energy: unchanged
  EXPECT_FALSE(checks[9].at("pass").get<bool>());   // soil's kinetic energy: 0.33 / 0.3 / 0.25 of it
  EXPECT_NEAR(checks[9].at("value").get<double>(), 100.0 * (0.88 / 3.0 - 0.25) / (0.88 / 3.0), 1e-9);
}

// A material's energy part near zero is judged against 1% of the charge's energy: a 20% scatter of
// 2 kJ passes (0.2 kJ of the 33 kJ floor), the same scatter of 200 kJ fails; where a level did not
// record the charge's energy (an earlier run) there is no floor, and the small part fails too.
TEST(ValidationReport, APartNearZeroIsJudgedAgainstAShareOfTheCharge) {
  const auto plan = scenario::validationPlan(ValidationLevel::Full, {"mesh"});
  const std::map<std::string, double> scatter{{"mesh-10mm", 1.0}, {"mesh-6mm", 1.0}, {"mesh-5mm", 0.9}, {"mesh-4mm", 1.0}, {"mesh-3mm", 1.2}};
  auto checksWith = [&](double products_kinetic_J, bool charge_recorded) {
    std::map<std::string, json> out;
    for (const auto& c : plan.cases) {
      out[c.id] = outcome(c, 5000.0);
      for (auto& e : out[c.id]["history"]["kinetic_energy_products_J"]) e = products_kinetic_J * scatter.at(c.id);
      if (!charge_recorded) out[c.id].erase("charge_energy_J");
    }
    return scenario::validationReport(plan, out, json::object());
  };
  auto floorParagraph = [](const json& rep) { return rep.at("sections")[0].at("paragraphs")[2].get<std::string>(); };
  const double mean = 3.1 / 3.0;   // of the finest three, in units of the part
  const auto small_rep = checksWith(2e3, true);
  const auto& small = small_rep.at("checks");
  EXPECT_NEAR(small[7].at("value").get<double>(), 100.0 * (1.2 - mean) * 2e3 / 3.3e4, 1e-9);
  EXPECT_TRUE(small[7].at("pass").get<bool>());
  EXPECT_NE(floorParagraph(small_rep).find("here the products kinetic energy"), std::string::npos);
  const auto large_rep = checksWith(2e5, true);
  const auto& large = large_rep.at("checks");
  EXPECT_NEAR(large[7].at("value").get<double>(), 100.0 * (1.2 - mean) / mean, 1e-9);
  EXPECT_FALSE(large[7].at("pass").get<bool>());
  EXPECT_NE(floorParagraph(large_rep).find("here none is"), std::string::npos);
  const auto earlier_rep = checksWith(2e3, false);
  const auto& earlier = earlier_rep.at("checks");
  EXPECT_NEAR(earlier[7].at("value").get<double>(), 100.0 * (1.2 - mean) / mean, 1e-9);
  EXPECT_FALSE(earlier[7].at("pass").get<bool>());
  EXPECT_TRUE(earlier[6].at("pass").get<bool>());   // the products' internal energy: judged as before
}

TEST(ValidationReport, AFallingMoistureTrendFailsItsCheck) {
  const auto plan = scenario::validationPlan(ValidationLevel::Quick, {"moisture"});
  std::map<std::string, json> out;
  for (const auto& c : plan.cases) out[c.id] = outcome(c, c.id == "emi-flat-22" ? 3000.0 : 4000.0);
  const auto rep = scenario::validationReport(plan, out, json::object());
  EXPECT_FALSE(rep.at("checks")[0].at("pass").get<bool>());
  // a case without a result is an error, not a silent gap
  out.erase("emi-flat-14");
  EXPECT_THROW(scenario::validationReport(plan, out, json::object()), RunError);
}

// The quick level judges what it computes: the mesh study's spread (its trend is shown), and the
// field study's change. Synthetic impulses for the quick sizes 25/20/15/12 mm.
json quickMeshChecks(const std::vector<double>& impulses) {
  const auto plan = scenario::validationPlan(ValidationLevel::Quick, {"mesh"});
  std::map<std::string, json> out;
  std::size_t i = 0;
  for (const auto& c : plan.cases) out[c.id] = outcome(c, impulses.at(i++));
  return scenario::validationReport(plan, out, json::object()).at("checks");
}

TEST(ValidationReport, QuickMeshStudyJudgesItsSpreadAndShowsItsTrend) {
  // converging: changes of 2.5%, 1.5%, 0.4% (revision 3's quick run, 4250/4357/4423/4404 N s)
  const auto good = quickMeshChecks({4250.0, 4357.0, 4423.0, 4404.0});
  ASSERT_EQ(good.size(), 10u);
  EXPECT_TRUE(good[0].at("pass").get<bool>());   // the finest three within 3% (0.85%)
  const double mean = (4357.0 + 4423.0 + 4404.0) / 3.0;
  EXPECT_NEAR(good[0].at("value").get<double>(), 100.0 * (mean - 4357.0) / mean, 1e-9);
  // the trend (the finest step's change, 0.43%, against the coarsest's) is shown, never judged:
  // the quick sizes' changes are at the noise (revision 11: 1.42 / 1.47 / 1.44%)
  EXPECT_NEAR(good[1].at("value").get<double>(), 100.0 * 19.0 / 4404.0, 1e-9);
  EXPECT_TRUE(good[1].at("pass").is_null());
  EXPECT_TRUE(quickMeshChecks({4239.0, 4300.0, 4364.0, 4302.0})[1].at("pass").is_null());
  EXPECT_TRUE(good[2].at("pass").is_null());      // the materials' shares: judged at the full level only
  EXPECT_TRUE(good[3].at("pass").is_null());
  // steadily falling by 5% a step: the spread (5%) fails
  const auto falling = quickMeshChecks({5000.0, 4750.0, 4512.5, 4290.0});
  EXPECT_FALSE(falling[0].at("pass").get<bool>());
  // diverging: each refinement moves the impulse more (2%, 3%, 5%): the spread (4.4%) fails
  const auto diverging = quickMeshChecks({4400.0, 4490.0, 4630.0, 4870.0});
  EXPECT_FALSE(diverging[0].at("pass").get<bool>());
}

TEST(ValidationReport, FieldStudyFailsWhenABackfilledCoverMovesTheImpulseMuch) {
  const auto plan = scenario::validationPlan(ValidationLevel::Quick, {"field"});
  auto judge = [&](double cover7_2_5cm) {
    std::map<std::string, json> out;
    for (const auto& c : plan.cases) out[c.id] = outcome(c, c.id == "field-cover7-2.5cm" ? cover7_2_5cm : 5000.0);
    return scenario::validationReport(plan, out, json::object()).at("checks").at(0);
  };
  EXPECT_TRUE(judge(4780.0).at("pass").get<bool>());    // -4.4%, as revision 3's quick run
  const auto big = judge(4400.0);                       // -12%
  EXPECT_NEAR(big.at("value").get<double>(), 12.0, 1e-9);
  EXPECT_FALSE(big.at("pass").get<bool>());
  EXPECT_EQ(big.at("limit"), "<= 10% (published: small)");
}

TEST(Report, Base64AndEscapingMatchTheirDefinitions) {
  EXPECT_EQ(io::base64(""), "");
  EXPECT_EQ(io::base64("M"), "TQ==");
  EXPECT_EQ(io::base64("Ma"), "TWE=");
  EXPECT_EQ(io::base64("Man"), "TWFu");
  EXPECT_EQ(io::base64(std::string("\xff\x00\x10", 3)), "/wAQ");
  EXPECT_EQ(io::escapeHtml("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
}

TEST(Report, MarkdownAndHtmlCarryTheTablesAndTheInlinedFigure) {
  const json rep{{"title", "T"},
                 {"level", "quick"},
                 {"run", {{"ejecta_version", "x"}}},
                 {"units", "SI"},
                 {"intro", {"hello"}},
                 {"checks", {{{"name", "c1"}, {"value", 1.5}, {"unit", "%"}, {"limit", "<= 2%"}, {"pass", true}}}},
                 {"sections", {{{"id", "mesh"}, {"title", "S <1>"}, {"paragraphs", {"p"}}, {"table", {{"columns", {"a", "b|c"}}, {"rows", {{"1", "2"}}}}},
                                {"figure", "mesh.png"}, {"caption", "cap"}}}},
                 {"cases_table", {{"columns", {"case"}}, {"rows", {{"x"}}}}}};
  const auto md = io::renderReportMarkdown(rep);
  EXPECT_NE(md.find("| a | b\\|c |"), std::string::npos);
  EXPECT_NE(md.find("| c1 | 1.50% | <= 2% | pass |"), std::string::npos);
  EXPECT_NE(md.find("![cap](mesh.png)"), std::string::npos);
  const auto html = io::renderReportHtml(rep, {{"mesh.png", "Man"}});
  EXPECT_NE(html.find("<h2>S &lt;1&gt;</h2>"), std::string::npos);
  EXPECT_NE(html.find("data:image/png;base64,TWFu"), std::string::npos);
  EXPECT_EQ(io::renderReportHtml(rep, {}).find("<img"), std::string::npos);   // no figure, no broken image
}

}  // namespace
}  // namespace ejecta

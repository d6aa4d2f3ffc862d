#pragma once
// `ejecta validate`: the built-in validation plan (which decks, at which cell sizes, for which
// study, shared/data/validation_cases.md) and the analyses that turn the runs' results into the
// report's tables, checks and plot data. No files and no threads here: the front end runs the
// cases and writes the report (io/report.hpp renders it).
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario/run.hpp"

namespace ejecta::scenario {

enum class ValidationLevel { Quick, Full };

struct ValidationCase {
  std::string id;                  // unique; also the case's folder name
  std::string deck;                // built-in deck name
  std::vector<std::string> sets;   // deck overrides (KEY=VALUE), the cell size last
  double cell_mm = 0.0;
  std::string change;              // what differs from the deck, for the tables ("-" if nothing)
  double relative_cost = 1.0;      // about (cell updates) / (EMI flat at 10 mm): the largest run first
};

struct ValidationPlan {
  ValidationLevel level = ValidationLevel::Quick;
  double vplate_mm = 0.0;              // the 3D V-plates' cell size; 0: the level's (quick 60 mm, full 10 mm)
  std::vector<std::string> studies;    // in report order
  std::vector<ValidationCase> cases;   // each run once, even when two studies use it
};

// Studies: mesh, moisture, field, share, sensitivity, dres. `only` (empty: all) picks some; an
// unknown name is an InputError naming `only`.
const std::vector<std::string>& validationStudies();
// `vplate_mm` (0: the level's) runs the 3D V-plates at another cell size, [5, 100] mm, else an
// InputError naming `vplate-cell-size`.
ValidationPlan validationPlan(ValidationLevel level, const std::vector<std::string>& only = {}, double vplate_mm = 0.0);

// What the report keeps of one run: the result and its histories thinned to at most `max_rows`
// rows (the last row always kept), the profiles whole. Also what `--reuse` reads back.
nlohmann::json condenseOutcome(const ValidationCase& c, const RunResult& r, std::size_t max_rows = 400);

// The report document: for each study a section with text, a table, checks (value, limit, pass)
// and the data its figure is drawn from; and a table of every case. `outcomes` maps case id to
// condenseOutcome(); every case of the plan must be there.
nlohmann::json validationReport(const ValidationPlan& plan, const std::map<std::string, nlohmann::json>& outcomes,
                                const nlohmann::json& run_info);

}  // namespace ejecta::scenario

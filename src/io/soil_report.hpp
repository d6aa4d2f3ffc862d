#pragma once
// Machine-readable and tabular descriptions of a sand model (JSON, CSV, plot data).
#include <filesystem>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "materials/sand_model.hpp"

namespace ejecta::io {

nlohmann::json soilJson(const materials::SandModel& model);
// The saturation family (0 to 100% at the model's dry density) plus the model itself, as the
// plot script reads it.
nlohmann::json soilPlotData(const materials::SandModel& model);
void writeLoadingCurveCsv(std::ostream& os, const materials::SandModel& model);
void writeYieldCurveCsv(std::ostream& os, const materials::SandModel& model);
void writeSummaryCsv(std::ostream& os, const materials::SandModel& model);
std::string soilSummaryText(const materials::SandModel& model);

}  // namespace ejecta::io

#pragma once
// Renders the validation report document (scenario::validationReport) as Markdown, with the
// figures as files beside it, and as one self-contained HTML page with the figures inlined.
#include <map>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace ejecta::io {

std::string renderReportMarkdown(const nlohmann::json& report);
// `figures` maps a section's figure file name to the PNG's bytes; a figure not in the map is
// left out of the page.
std::string renderReportHtml(const nlohmann::json& report, const std::map<std::string, std::string>& figures);

std::string base64(std::string_view bytes);
std::string escapeHtml(std::string_view text);

}  // namespace ejecta::io

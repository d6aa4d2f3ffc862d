#include "io/report.hpp"

#include <fmt/format.h>

namespace ejecta::io {
namespace {
using nlohmann::json;

std::string checkValue(const json& c) {
  const auto unit = c.at("unit").get<std::string>();
  if (!c.at("value").is_number()) return "not recorded";
  return fmt::format("{:.2f}{}{}", c.at("value").get<double>(), unit == "%" ? "" : " ", unit);
}
std::string checkResult(const json& c) {
  if (c.at("pass").is_null()) return c.at("value").is_number() ? "informative" : "not recorded (an earlier run)";
  return c.at("pass").get<bool>() ? "pass" : "FAIL";
}

std::string runLine(const json& r) {
  const auto& run = r.at("run");
  std::string s = fmt::format("ejecta {}", run.value("ejecta_version", "?"));
  if (run.contains("solver_revision")) s += fmt::format(" (solver revision {})", run.at("solver_revision").get<int>());
  s += fmt::format(", level {}", r.value("level", "?"));
  if (run.contains("threads")) s += fmt::format(", {} threads", run.at("threads").get<int>());
  if (run.contains("jobs")) s += fmt::format(" in {} parallel jobs", run.at("jobs").get<int>());
  if (run.contains("machine")) s += ", " + run.at("machine").get<std::string>();
  if (run.contains("case_time_sum_s")) {
    const double minutes = run.at("case_time_sum_s").get<double>() / 60.0;
    s += fmt::format(". The cases' own run times add up to {:.1f} min", minutes);
    if (const int jobs = run.value("jobs", 1); jobs > 1) s += fmt::format(" (about {:.1f} min of wall time with {} jobs)", minutes / jobs, jobs);
  }
  if (run.contains("reused") && run.at("reused").get<int>() > 0)
    s += fmt::format("; {} case(s) were taken from an earlier run of the same decks", run.at("reused").get<int>());
  return s + ".";
}

std::string mdCell(std::string s) {
  for (std::size_t p = 0; (p = s.find('|', p)) != std::string::npos; p += 2) s.replace(p, 1, "\\|");
  return s;
}
std::string mdTable(const json& t) {
  std::string s = "|";
  for (const auto& c : t.at("columns")) s += fmt::format(" {} |", mdCell(c.get<std::string>()));
  s += "\n|";
  for (std::size_t i = 0; i < t.at("columns").size(); ++i) s += "---|";
  s += "\n";
  for (const auto& r : t.at("rows")) {
    s += "|";
    for (const auto& c : r) s += fmt::format(" {} |", mdCell(c.get<std::string>()));
    s += "\n";
  }
  return s + "\n";
}

std::string htmlTable(const json& t) {
  std::string s = "<table>\n<tr>";
  for (const auto& c : t.at("columns")) s += fmt::format("<th>{}</th>", escapeHtml(c.get<std::string>()));
  s += "</tr>\n";
  for (const auto& r : t.at("rows")) {
    s += "<tr>";
    for (const auto& c : r) s += fmt::format("<td>{}</td>", escapeHtml(c.get<std::string>()));
    s += "</tr>\n";
  }
  return s + "</table>\n";
}

json checksTable(const json& checks) {
  json t{{"columns", {"check", "value", "limit", "result"}}, {"rows", json::array()}};
  for (const auto& c : checks) t["rows"].push_back({c.at("name"), checkValue(c), c.at("limit"), checkResult(c)});
  return t;
}
}  // namespace

std::string base64(std::string_view bytes) {
  static constexpr char k[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) | static_cast<unsigned char>(bytes[i + 2]);
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += k[(v >> 6) & 63];
    out += k[v & 63];
  }
  if (const std::size_t rest = bytes.size() - i; rest > 0) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (rest == 2) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += rest == 2 ? k[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string escapeHtml(std::string_view text) {
  std::string s;
  for (const char c : text) switch (c) {
      case '&': s += "&amp;"; break;
      case '<': s += "&lt;"; break;
      case '>': s += "&gt;"; break;
      case '"': s += "&quot;"; break;
      default: s += c;
    }
  return s;
}

std::string renderReportMarkdown(const json& r) {
  std::string s = "# " + r.at("title").get<std::string>() + "\n\n";
  s += "<!-- written by `ejecta validate`; regenerate, do not edit -->\n\n";
  s += runLine(r) + " Units: " + r.at("units").get<std::string>() + ".\n\n";
  for (const auto& p : r.at("intro")) s += p.get<std::string>() + "\n\n";
  if (!r.at("checks").empty()) s += "## Checks\n\n" + mdTable(checksTable(r.at("checks")));
  for (const auto& sec : r.at("sections")) {
    s += "## " + sec.at("title").get<std::string>() + "\n\n";
    for (const auto& p : sec.at("paragraphs")) s += p.get<std::string>() + "\n\n";
    s += mdTable(sec.at("table"));
    if (sec.contains("tables"))   // further tables of a section, after its main one
      for (const auto& t : sec.at("tables")) s += mdTable(t);
    if (sec.contains("figure")) s += fmt::format("![{0}]({1})\n\n*{0}*\n\n", sec.at("caption").get<std::string>(), sec.at("figure").get<std::string>());
  }
  s += "## Every case\n\nReference and error: the measured values are not in shared/data (see above).\n\n" + mdTable(r.at("cases_table"));
  return s;
}

std::string renderReportHtml(const json& r, const std::map<std::string, std::string>& figures) {
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + escapeHtml(r.at("title").get<std::string>()) + "</title>\n";
  s += "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;line-height:1.45;color:#222}"
       "table{border-collapse:collapse;margin:0.8em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:left}"
       "th{background:#eee}img{max-width:100%}figcaption{font-style:italic;color:#444}</style>\n</head>\n<body>\n";
  s += "<h1>" + escapeHtml(r.at("title").get<std::string>()) + "</h1>\n";
  s += "<p>" + escapeHtml(runLine(r) + " Units: " + r.at("units").get<std::string>() + ".") + "</p>\n";
  for (const auto& p : r.at("intro")) s += "<p>" + escapeHtml(p.get<std::string>()) + "</p>\n";
  if (!r.at("checks").empty()) s += "<h2>Checks</h2>\n" + htmlTable(checksTable(r.at("checks")));
  for (const auto& sec : r.at("sections")) {
    s += "<h2>" + escapeHtml(sec.at("title").get<std::string>()) + "</h2>\n";
    for (const auto& p : sec.at("paragraphs")) s += "<p>" + escapeHtml(p.get<std::string>()) + "</p>\n";
    s += htmlTable(sec.at("table"));
    if (sec.contains("tables"))
      for (const auto& t : sec.at("tables")) s += htmlTable(t);
    if (sec.contains("figure")) {
      const auto it = figures.find(sec.at("figure").get<std::string>());
      if (it != figures.end())
        s += "<figure><img alt=\"" + escapeHtml(sec.at("caption").get<std::string>()) + "\" src=\"data:image/png;base64," + base64(it->second) +
             "\"><figcaption>" + escapeHtml(sec.at("caption").get<std::string>()) + "</figcaption></figure>\n";
    }
  }
  s += "<h2>Every case</h2>\n<p>Reference and error: the measured values are not in shared/data (see above).</p>\n" + htmlTable(r.at("cases_table"));
  return s + "</body>\n</html>\n";
}

}  // namespace ejecta::io

// `ejecta verify`: the solver against exact solutions: table, CSV, JSON and a PNG of profiles.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"
#include "io/subprocess.hpp"
#include "verify/problems.hpp"


namespace ejecta::cli {
namespace {
namespace fs = std::filesystem;

struct VerifyOptions {
  bool full = false;
  bool quick_flag = false;
  std::string out = "out/verify";
  std::vector<std::string> only;
  int threads = 0;
  bool plot = true;
};

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string tableText(const verify::Report& rep) {
  std::string s = fmt::format("{:<24} {:<16} {:>6} {:>9} {:>7} {:>11} {:>7} {:>10} {:>8}  {}\n", "problem", "geometry", "res", "cells", "steps", "error",
                              "order", "conserv.", "wall s", "check");
  for (const auto& r : rep.rows) {
    const std::string order = std::isfinite(r.order) ? fmt::format("{:.2f}", r.order) : "-";
    const std::string cons = std::isfinite(r.conservation) ? fmt::format("{:.1e}", r.conservation) : "-";
    const std::string check = r.check.empty() ? "" : fmt::format("{} [{}]", r.check, r.passed ? "pass" : "FAIL");
    s += fmt::format("{:<24} {:<16} {:>6} {:>9} {:>7} {:>11.3e} {:>7} {:>10} {:>8.2f}  {}\n", r.problem, r.geometry, r.resolution, r.cells,
                     r.steps > 0 ? std::to_string(r.steps) : "-", r.error, order, cons, r.wall_seconds, check);
  }
  return s;
}

void writeCsv(std::ostream& os, const verify::Report& rep) {
  os << "problem,geometry,metric,resolution,cells,steps,error,observed_order,conservation_drift,wall_seconds,check,passed\n";
  for (const auto& r : rep.rows)
    os << fmt::format("{},{},\"{}\",{},{},{},{:.6e},{},{},{:.3f},\"{}\",{}\n", r.problem, r.geometry, r.metric, r.resolution, r.cells, r.steps, r.error,
                      std::isfinite(r.order) ? fmt::format("{:.4f}", r.order) : "", std::isfinite(r.conservation) ? fmt::format("{:.3e}", r.conservation) : "",
                      r.wall_seconds, r.check, r.check.empty() ? "" : (r.passed ? "true" : "false"));
}

nlohmann::json reportJson(const verify::Report& rep, bool quick) {
  nlohmann::json j;
  j["ejecta_version"] = build_info::version;
  j["level"] = quick ? "quick" : "full";
  j["all_passed"] = rep.allPassed();
  for (const auto& r : rep.rows)
    j["rows"].push_back({{"problem", r.problem}, {"geometry", r.geometry}, {"metric", r.metric}, {"resolution", r.resolution}, {"cells", r.cells}, {"steps", r.steps},
                         {"error", number(r.error)}, {"observed_order", number(r.order)}, {"conservation_drift", number(r.conservation)},
                         {"wall_seconds", r.wall_seconds}, {"check", r.check}, {"passed", r.passed}});
  return j;
}

nlohmann::json plotData(const verify::Report& rep) {
  // the finest profile of each problem, with its exact solution
  nlohmann::json j = nlohmann::json::array();
  for (std::size_t p = 0; p < rep.profiles.size(); ++p) {
    const auto& pr = rep.profiles[p];
    const bool finest = p + 1 == rep.profiles.size() || rep.profiles[p + 1].problem != pr.problem;
    if (!finest) continue;
    nlohmann::json e{{"problem", pr.problem}, {"resolution", pr.resolution}, {"x_label", pr.x_label}, {"y_label", pr.y_label}};
    for (std::size_t i = 0; i < pr.x.size(); ++i) {
      e["x"].push_back(pr.x[i]);
      e["numeric"].push_back(number(pr.numeric[i]));
      e["exact"].push_back(number(i < pr.exact.size() ? pr.exact[i] : NAN));
    }
    j.push_back(e);
  }
  return j;
}

int runVerify(const VerifyOptions& o) {
  applyThreads(o.threads);
  const fs::path out(o.out);
  if (fs::exists(out) && !fs::is_directory(out)) throw InputError("out", fmt::format("'{}' exists and is not a directory", o.out));
  verify::Options vo;
  vo.quick = !o.full;
  vo.only = o.only;
  vo.log = [](const std::string& m) { std::cerr << "verify: " << m << '\n'; };
  const auto rep = verify::runVerification(vo);   // validates --only before any output exists
  const std::string table = tableText(rep);
  std::cout << table;

  fs::create_directories(out / "profiles");
  io::OutputTransaction outputs;
  outputs.stage(out / "verify.txt", [&](std::ostream& os) { os << table; });
  outputs.stage(out / "verify.csv", [&](std::ostream& os) { writeCsv(os, rep); });
  outputs.stage(out / "verify.json", [&](std::ostream& os) { os << reportJson(rep, vo.quick).dump(2) << '\n'; });
  for (const auto& pr : rep.profiles)
    outputs.stage(out / "profiles" / fmt::format("{}_{}.csv", pr.problem, pr.resolution), [&](std::ostream& os) {
      os << pr.x_label << ',' << pr.y_label << " (ejecta),exact\n";
      for (std::size_t i = 0; i < pr.x.size(); ++i)
        os << fmt::format("{:.8e},{:.8e},{}\n", pr.x[i], pr.numeric[i], i < pr.exact.size() && std::isfinite(pr.exact[i]) ? fmt::format("{:.8e}", pr.exact[i]) : "");
    });
  if (o.plot) io::stagePlot(outputs, "plot_verify.py", plotData(rep).dump(), out / "verify.png");
  outputs.commit();
  std::cout << fmt::format("wrote {}/verify.{{txt,csv,json{}}} and profiles/\n", o.out, o.plot ? ",png" : "");
  if (!rep.allPassed()) {
    std::cerr << "ejecta: verification FAILED: see the rows marked FAIL\n";
    return 4;   // a failed check, as validate (1 is kept for internal errors)
  }
  std::cout << "all checks passed\n";
  return 0;
}
}  // namespace

Action addVerifyCommand(CLI::App& app) {
  auto o = std::make_shared<VerifyOptions>();
  auto* sub = app.add_subcommand("verify", "Runs the solver against exact solutions (Sod, smooth advection, Sedov, Noh, interface\n"
                                           "advection, JWL detonation, products on the CJ isentrope, a charge in wet sand, sand piston,\n"
                                           "steel precursor, free-air TNT) and reports L1 errors, observed orders and conservation.\n"
                                           "Exit code 4 if a check fails.");
  auto* quick = sub->add_flag("--quick", o->quick_flag, "Quick resolutions (the default; about 2-4 minutes on 2 cores)");
  sub->add_flag("--full", o->full, "Finer resolutions as well (tens of minutes)")->excludes(quick);
  sub->add_option("--out", o->out, "Output directory (default out/verify)");
  std::string groups;   // from the suite itself, so that the help cannot fall behind it
  for (const auto& g : verify::problemGroups()) groups += (groups.empty() ? "" : " ") + g;
  sub->add_option("--only", o->only, "Run only these problem groups: " + groups)
      ->expected(1, -1);
  sub->add_option("--threads", o->threads, "OpenMP threads (default: all cores)");
  sub->add_flag("!--no-plot", o->plot, "Skip the PNG plot");
  return [sub, o]() -> int {
    if (!sub->parsed()) return -1;
    return runVerify(*o);
  };
}

}  // namespace ejecta::cli

// `ejecta sweep DECK --vary KEY=V1,V2,...`: a parameter study over one deck, full factorial, run in
// turn; the impulses go to sweep.csv / sweep.json with a plot.
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
#include "scenario/run.hpp"


namespace ejecta::cli {
namespace {
namespace fs = std::filesystem;

struct SweepOptions {
  std::string deck;
  std::vector<std::string> vary, sets;
  std::string out = "out/sweep";
  std::string cell_size_mm;
  int threads = 0;
  bool plot = true;
};

struct Axis {
  std::string key;
  std::vector<std::string> values;
};

Axis parseVary(const std::string& v) {
  const auto eq = v.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= v.size()) throw InputError("--vary", fmt::format("'{}' is not KEY=V1,V2,...", v));
  Axis a{v.substr(0, eq), {}};
  std::string rest = v.substr(eq + 1);
  std::size_t start = 0;
  while (start <= rest.size()) {
    const auto comma = rest.find(',', start);
    const std::string item = rest.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty()) throw InputError("--vary", fmt::format("empty value in '{}'", v));
    a.values.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return a;
}

int runSweep(const SweepOptions& o) {
  applyThreads(o.threads);
  if (o.vary.empty()) throw InputError("--vary", "at least one KEY=V1,V2,... is needed");
  std::vector<Axis> axes;
  for (const auto& v : o.vary) axes.push_back(parseVary(v));
  const std::string path = resolveDeck(o.deck);
  std::vector<std::string> base = o.sets;
  if (!o.cell_size_mm.empty()) base.push_back(cellSizeOverride(o.cell_size_mm));
  // every combination, validated before the first run
  std::vector<std::vector<std::size_t>> combos{{}};
  for (const auto& a : axes) {
    std::vector<std::vector<std::size_t>> next;
    for (const auto& c : combos)
      for (std::size_t i = 0; i < a.values.size(); ++i) {
        auto d = c;
        d.push_back(i);
        next.push_back(d);
      }
    combos = next;
  }
  std::vector<scenario::Deck> decks;
  for (const auto& c : combos) {
    auto ov = base;
    for (std::size_t q = 0; q < axes.size(); ++q) ov.push_back(axes[q].key + "=" + axes[q].values[c[q]]);
    decks.push_back(scenario::loadDeck(path, ov));
  }
  const fs::path out(o.out);
  if (fs::exists(out) && !fs::is_directory(out)) throw InputError("out", fmt::format("'{}' exists and is not a directory", o.out));
  fs::create_directories(out);
  nlohmann::json rows = nlohmann::json::array();
  std::string csv = "case";
  for (const auto& a : axes) csv += "," + a.key;
  csv += ",impulse_Ns,impulse_air_Ns,impulse_products_Ns,impulse_soil_Ns,peak_force_N,cells,steps,wall_s\n";
  for (std::size_t n = 0; n < combos.size(); ++n) {
    std::string label;
    for (std::size_t q = 0; q < axes.size(); ++q) label += fmt::format("{}{}={}", q ? ", " : "", axes[q].key, axes[q].values[combos[n][q]]);
    std::cerr << fmt::format("sweep: case {}/{}: {}\n", n + 1, combos.size(), label);
    scenario::RunOptions ro;
    ro.out_dir = (out / fmt::format("case_{:03d}", n)).string();
    ro.progress = false;
    ro.plot = false;
    const auto r = scenario::runCase(decks[n], ro);
    nlohmann::json row{{"case", n}, {"impulse_Ns", r.impulse_Ns}, {"impulse_air_Ns", r.impulse_air_Ns}, {"impulse_products_Ns", r.impulse_products_Ns},
                       {"impulse_soil_Ns", r.impulse_soil_Ns}, {"peak_force_N", r.peak_force_N}, {"cells", r.cells}, {"steps", r.steps},
                       {"wall_s", r.wall_s}};
    csv += fmt::format("{}", n);
    for (std::size_t q = 0; q < axes.size(); ++q) {
      row["values"][axes[q].key] = axes[q].values[combos[n][q]];
      csv += "," + axes[q].values[combos[n][q]];
    }
    csv += fmt::format(",{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{},{:.2f}\n", r.impulse_Ns, r.impulse_air_Ns, r.impulse_products_Ns, r.impulse_soil_Ns,
                       r.peak_force_N, r.cells, r.steps, r.wall_s);
    rows.push_back(row);
    std::cout << fmt::format("{:>4}  {:<50} impulse {:>10.1f} N s  ({} cells, {:.1f} s)\n", n, label, r.impulse_Ns, r.cells, r.wall_s);
  }
  nlohmann::json doc{{"ejecta_version", build_info::version}, {"deck", path}, {"rows", rows}};
  for (const auto& a : axes) doc["vary"].push_back({{"key", a.key}, {"values", a.values}});
  io::OutputTransaction outputs;
  outputs.stage(out / "sweep.csv", [&](std::ostream& os) { os << csv; });
  outputs.stage(out / "sweep.json", [&](std::ostream& os) { os << doc.dump(2) << '\n'; });
  if (o.plot) io::stagePlot(outputs, "plot_sweep.py", doc.dump(), out / "sweep.png");
  outputs.commit();
  std::cout << fmt::format("wrote {}/sweep.csv, sweep.json{} and case_*/\n", o.out, o.plot ? ", sweep.png" : "");
  return 0;
}
}  // namespace

Action addSweepCommand(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  auto* sub = app.add_subcommand("sweep", "A parameter study over one deck: every combination of the --vary values, run in turn;\n"
                                          "impulses to sweep.csv, sweep.json and sweep.png.");
  sub->add_option("deck", o->deck, "Deck file or built-in deck name")->required();
  sub->add_option("--vary", o->vary, "KEY=V1,V2,... (dotted deck key, TOML values); repeat for a full factorial")->required();
  sub->add_option("--set", o->sets, "Fixed override KEY=VALUE for every case, repeatable");
  sub->add_option("--cell-size", o->cell_size_mm, "Core cell size, mm");
  sub->add_option("--out", o->out, "Output folder (default out/sweep)");
  sub->add_option("--threads", o->threads, "OpenMP threads (default: all cores)");
  sub->add_flag("!--no-plot", o->plot, "Skip sweep.png");
  return [sub, o]() -> int {
    if (!sub->parsed()) return -1;
    return runSweep(*o);
  };
}

}  // namespace ejecta::cli

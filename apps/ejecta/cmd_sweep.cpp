// `ejecta sweep DECK --vary KEY=V1,V2,...`: a parameter study over one deck, full factorial, run in
// turn; the impulses go to sweep.csv / sweep.json with a plot.
//
// A study runs for hours, so: every case is checked (deck and geometry) before the first starts;
// the index (sweep.csv, sweep.json) is rewritten after each case, so what has finished can be read
// while the rest runs; a case that fails is recorded and the others still run; `--reuse` takes a
// case's result from its folder when its resolved deck is unchanged, so an interrupted study
// continues where it stopped.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"
#include "hydro/solver.hpp"
#include "io/subprocess.hpp"
#include "scenario/run.hpp"


namespace ejecta::cli {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;

struct SweepOptions {
  std::string deck;
  std::vector<std::string> vary, sets;
  std::string out = "out/sweep";
  std::string cell_size_mm;
  int threads = 0;
  double checkpoint_every_min = 0.0;
  bool plot = true, reuse = false;
};

struct Axis {
  std::string key;
  std::vector<std::string> values;
};

// KEY=V1,V2,...: the values are TOML, so a comma inside brackets, braces or quotes is the value's
// own (a list such as [0.1, -0.01], a string such as "a,b").
Axis parseVary(const std::string& v) {
  const auto eq = v.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= v.size()) throw InputError("--vary", fmt::format("'{}' is not KEY=V1,V2,...", v));
  Axis a{v.substr(0, eq), {}};
  const auto trim = [](std::string s) {
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  };
  a.key = trim(a.key);
  const std::string rest = v.substr(eq + 1);
  int depth = 0;
  char quote = 0;
  std::string item;
  auto push = [&]() {
    const std::string value = trim(item);
    if (value.empty()) throw InputError("--vary", fmt::format("empty value in '{}'", v));
    a.values.push_back(value);
    item.clear();
  };
  for (const char c : rest) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      if (--depth < 0) throw InputError("--vary", fmt::format("unbalanced '{}' in '{}'", c, v));
    } else if (c == ',' && depth == 0) {
      push();
      continue;
    }
    item += c;
  }
  if (quote || depth != 0) throw InputError("--vary", fmt::format("unclosed {} in '{}'", quote ? "quote" : "bracket", v));
  push();
  return a;
}

// One CSV field: quoted where it holds a separator, a quote or a line break (RFC 4180).
std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + '"';
}

// case_NNN: a case folder's index, or nothing.
std::optional<std::size_t> caseIndex(const std::string& name) {
  if (name.rfind("case_", 0) != 0 || name.size() < 8 || name.size() > 14) return std::nullopt;
  std::size_t n = 0;
  for (std::size_t i = 5; i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9') return std::nullopt;
    n = 10 * n + static_cast<std::size_t>(name[i] - '0');
  }
  return n;
}

int exitCodeOf(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const InputError&) {
    return 2;
  } catch (const fs::filesystem_error&) {
    return 2;   // as the front end says it: a path the run could not write
  } catch (const RunError&) {
    return 3;
  } catch (...) {
    return 1;
  }
}

int runSweep(const SweepOptions& o) {
  // a signal at any point of the study (between cases, while checking them) is seen, not fatal
  const scenario::InterruptScope signals;
  auto stopIfSignalled = [](const std::string& where) {
    if (const int sig = scenario::interruptedBy(); sig != 0) throw Interrupted(sig, fmt::format("interrupted by signal {} {}", sig, where));
  };
  applyThreads(o.threads);
  if (o.vary.empty()) throw InputError("--vary", "at least one KEY=V1,V2,... is needed");
  std::vector<Axis> axes;
  std::set<std::string> keys;
  for (const auto& v : o.vary) {
    axes.push_back(parseVary(v));
    if (!keys.insert(axes.back().key).second) throw InputError("--vary", fmt::format("{} is varied twice; give its values once", axes.back().key));
  }
  for (const auto& s : o.sets) {
    const auto eq = s.find('=');
    std::string key = s.substr(0, eq);
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t") + 1);
    if (keys.count(key)) throw InputError("--set", fmt::format("{} is both set and varied; give it to one of them", key));
  }
  const std::string path = resolveDeck(o.deck);
  std::vector<std::string> base = o.sets;
  if (!o.cell_size_mm.empty()) base.push_back(cellSizeOverride(o.cell_size_mm));
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
  auto labelOf = [&](std::size_t n) {
    std::string label;
    for (std::size_t q = 0; q < axes.size(); ++q) label += fmt::format("{}{}={}", q ? ", " : "", axes[q].key, axes[q].values[combos[n][q]]);
    return label;
  };
  // Every combination, deck and geometry, checked before the first run: a study must not stop
  // hours in on a case it could have refused at the start.
  std::vector<scenario::Deck> decks;
  for (std::size_t n = 0; n < combos.size(); ++n) {
    auto ov = base;
    for (std::size_t q = 0; q < axes.size(); ++q) ov.push_back(axes[q].key + "=" + axes[q].values[combos[n][q]]);
    try {
      decks.push_back(scenario::loadDeck(path, ov));
      scenario::checkCase(decks.back());
      stopIfSignalled("while the cases were checked");
    } catch (const InputError& e) {
      throw InputError(e.field(), fmt::format("{} (case {}: {})", std::string(e.what()).substr(e.field().size() + 2), n, labelOf(n)));
    }
  }

  // The folder: new, empty, or an earlier study's (it has sweep.json), whose index this one
  // replaces at once and whose case folders beyond this study's go when it ends.
  const fs::path out(o.out);
  if (fs::exists(out) && !fs::is_directory(out)) throw InputError("out", fmt::format("'{}' exists and is not a directory", o.out));
  if (fs::is_directory(out) && !fs::is_empty(out) && !fs::exists(out / "sweep.json"))
    throw InputError("out", fmt::format("'{}' holds files and is not an ejecta sweep folder (no sweep.json); name a new or empty folder, or an "
                                        "earlier sweep's",
                                        o.out));
  fs::create_directories(out);

  std::vector<json> rows(combos.size());
  for (std::size_t n = 0; n < combos.size(); ++n) {
    rows[n] = {{"case", n}, {"status", "not run"}};
    for (std::size_t q = 0; q < axes.size(); ++q) rows[n]["values"][axes[q].key] = axes[q].values[combos[n][q]];
  }
  static const std::vector<std::string> kNumbers{"impulse_Ns", "impulse_air_Ns", "impulse_products_Ns", "impulse_soil_Ns", "peak_force_N", "cells", "steps", "wall_s"};
  auto indexDoc = [&](const std::string& status) {
    json doc{{"ejecta_version", build_info::version}, {"deck", path}, {"status", status}, {"cases", combos.size()}, {"rows", rows}};
    for (const auto& a : axes) doc["vary"].push_back({{"key", a.key}, {"values", a.values}});
    return doc;
  };
  auto csvOf = [&]() {
    std::string csv = "case";
    for (const auto& a : axes) csv.append(",").append(csvField(a.key));
    for (const auto& k : kNumbers) csv.append(",").append(k);
    csv += ",status\n";
    for (const auto& r : rows) {
      csv += fmt::format("{}", r.at("case").get<std::size_t>());
      for (const auto& a : axes) csv.append(",").append(csvField(r.at("values").at(a.key).get<std::string>()));
      for (const auto& k : kNumbers) {
        csv += ",";
        if (!r.contains(k)) continue;
        if (k == "cells" || k == "steps") csv += fmt::format("{}", r.at(k).get<long long>());
        else if (k == "wall_s") csv += fmt::format("{:.2f}", r.at(k).get<double>());
        else csv += fmt::format("{:.6g}", r.at(k).get<double>());
      }
      csv.append(",").append(r.at("status").get<std::string>()).append("\n");
    }
    return csv;
  };
  // sweep.csv and sweep.json together (each file atomically)
  auto writeIndex = [&](const std::string& status) {
    io::OutputTransaction outputs;
    outputs.stage(out / "sweep.csv", [&](std::ostream& os) { os << csvOf(); });
    outputs.stage(out / "sweep.json", [&](std::ostream& os) { os << indexDoc(status).dump(2) << '\n'; });
    outputs.commit();
  };
  std::error_code ec;
  fs::remove(out / "sweep.png", ec);   // an earlier study's plot: this study's is drawn at its end
  writeIndex("running");

  std::exception_ptr first_failure;
  std::size_t failed = 0, reused = 0, ran = 0;
  double run_wall = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t n = 0; n < combos.size(); ++n) {
    const fs::path dir = out / fmt::format("case_{:03d}", n);
    const fs::path saved = dir / "sweep_case.json";
    auto& row = rows[n];
    if (o.reuse && fs::exists(saved)) {
      try {
        const auto j = json::parse(io::readWholeFile(saved).value_or(""));
        if (j.at("deck_echo") == decks[n].echo && j.value("solver_revision", 0) == hydro::kSolverRevision && fs::exists(dir / "summary.json")) {
          for (const auto& k : kNumbers) row[k] = j.at("row").at(k);
          row["status"] = "reused";
          ++reused;
          std::cout << fmt::format("{:>4}  {:<50} impulse {:>10.1f} N s  (reused: {})\n", n, labelOf(n), row.at("impulse_Ns").get<double>(), dir.string());
          writeIndex("running");
          continue;
        }
      } catch (const json::exception&) {
        // unreadable or from another layout: the case runs again
      }
    }
    std::cerr << fmt::format("sweep: case {}/{}: {}\n", n + 1, combos.size(), labelOf(n));
    scenario::RunOptions ro;
    ro.out_dir = dir.string();
    ro.plot = false;
    ro.checkpoint_every_s = 60.0 * o.checkpoint_every_min;
    ro.log = [n](const std::string& m) { std::cerr << fmt::format("sweep: case {}: {}\n", n, m); };
    try {
      const auto r = runOrContinue(decks[n], ro, o.reuse, fmt::format("sweep: case {}", n));
      row["impulse_Ns"] = r.impulse_Ns;
      row["impulse_air_Ns"] = r.impulse_air_Ns;
      row["impulse_products_Ns"] = r.impulse_products_Ns;
      row["impulse_soil_Ns"] = r.impulse_soil_Ns;
      row["peak_force_N"] = r.peak_force_N;
      row["cells"] = r.cells;
      row["steps"] = r.steps;
      row["wall_s"] = r.wall_s + r.wall_before_s;   // all its parts, where it was continued from a checkpoint
      row["status"] = "done";
      json keep{{"deck_echo", decks[n].echo}, {"solver_revision", hydro::kSolverRevision}, {"ejecta_version", build_info::version}, {"row", row}};
      io::writeFileAtomically(saved, keep.dump() + "\n");
      ++ran;
      run_wall += r.wall_s;
      std::cout << fmt::format("{:>4}  {:<50} impulse {:>10.1f} N s  ({} cells, {:.1f} s)\n", n, labelOf(n), r.impulse_Ns, r.cells, r.wall_s);
    } catch (const Interrupted&) {
      row["status"] = "interrupted";
      writeIndex("interrupted");   // what finished stays readable; --reuse continues it
      throw;
    } catch (const std::exception& e) {
      // the case is recorded and the study goes on; the exit code says it at the end
      if (!first_failure) first_failure = std::current_exception();
      ++failed;
      row["status"] = "failed";
      row["error"] = e.what();
      std::cerr << fmt::format("sweep: case {} ({}) failed: {}\n", n, labelOf(n), e.what());
    }
    writeIndex("running");
    if (scenario::interruptedBy() != 0) {   // came after the case's last step: the next one does not start
      writeIndex("interrupted");
      stopIfSignalled(fmt::format("after case {}", n));
    }
    const std::size_t left = combos.size() - n - 1;
    if (ran > 0 && left > 0) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::cerr << fmt::format("sweep: {}/{} cases done; elapsed {:.1f} min, left ~{:.1f} min (at the mean of the {} case(s) run so far)\n", n + 1,
                               combos.size(), elapsed / 60.0, static_cast<double>(left) * run_wall / static_cast<double>(ran) / 60.0, ran);
    }
  }
  writeIndex(failed ? "failed" : "complete");
  // an earlier, larger study's case folders (run folders: runCase writes a case whole) are not this
  // one's, nor the staging folders its interrupted cases left (.case_NNN.staging-PID, a checkpoint)
  std::set<std::string> gone;   // the cases' names
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    const auto k = caseIndex(name);
    if (k && *k >= combos.size() && entry.is_directory() && fs::exists(entry.path() / "summary.json")) fs::remove_all(entry.path());
    const std::string staged = scenario::stagedRunName(name);
    if (const auto ks = caseIndex(staged); ks && *ks >= combos.size()) gone.insert(staged);
  }
  for (const auto& name : gone) scenario::removeLeftStages((out / name).string());
  // the plot last, on its own: a plot that cannot be drawn (no matplotlib) is said, the index stands
  bool plotted = false;
  if (o.plot && failed < combos.size()) {
    try {
      io::OutputTransaction outputs;
      io::stagePlot(outputs, "plot_sweep.py", indexDoc("complete").dump(), out / "sweep.png");
      outputs.commit();
      plotted = true;
    } catch (const std::exception& e) {
      stopIfSignalled("while sweep.png was drawn");
      std::cerr << fmt::format("sweep: sweep.png not drawn: {}\n", e.what());
    }
  }
  std::cout << fmt::format("wrote {}/sweep.csv, sweep.json{} and case_*/ ({} run, {} reused{})\n", o.out, plotted ? ", sweep.png" : "", ran, reused,
                           failed ? fmt::format(", {} FAILED", failed) : "");
  if (failed) {
    std::cerr << fmt::format("sweep: {} of {} case(s) failed (sweep.json holds each error)\n", failed, combos.size());
    return exitCodeOf(first_failure);
  }
  return 0;
}
}  // namespace

Action addSweepCommand(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  auto* sub = app.add_subcommand("sweep", "A parameter study over one deck: every combination of the --vary values, run in turn;\n"
                                          "impulses to sweep.csv, sweep.json (rewritten after each case) and sweep.png.\n"
                                          "Every case is checked before the first runs; a failed case is recorded and the rest run\n"
                                          "(exit code of the first failure: 2 input, 3 a run that could not go on, 1 other).");
  sub->add_option("deck", o->deck, "Deck file or built-in deck name")->required();
  sub->add_option("--vary", o->vary, "KEY=V1,V2,... (dotted deck key, TOML values; commas inside [] or quotes belong to the value); repeat for a full factorial")->required();
  sub->add_option("--set", o->sets, "Fixed override KEY=VALUE for every case, repeatable");
  sub->add_option("--cell-size", o->cell_size_mm, "Core cell size, mm");
  sub->add_option("--out", o->out, "Output folder: new, empty or an earlier sweep's (default out/sweep)");
  sub->add_option("--threads", o->threads, "OpenMP threads (default: all cores)");
  sub->add_flag("--reuse", o->reuse,
                "Take a case's result from its folder in --out when its resolved deck is unchanged, and continue a case that an\n"
                "interrupted sweep left a checkpoint of (continues an interrupted sweep)");
  addCaseCheckpointOption(sub, o->checkpoint_every_min);
  sub->add_flag("!--no-plot", o->plot, "Skip sweep.png");
  return [sub, o]() -> int {
    if (!sub->parsed()) return -1;
    return runSweep(*o);
  };
}

}  // namespace ejecta::cli

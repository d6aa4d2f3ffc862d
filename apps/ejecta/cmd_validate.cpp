// `ejecta validate [--quick | --full]`: runs the built-in validation decks (several at once when
// there are cores to spare) and writes the report: validation.md with its figures, one
// self-contained validation.html, and validation.json. Every case keeps its run folder under
// --work; `--reuse` takes a case's earlier result when its deck is unchanged.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"
#include "hydro/solver.hpp"
#include "io/report.hpp"
#include "io/subprocess.hpp"
#include "scenario/run.hpp"
#include "scenario/validation.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ejecta::cli {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

struct ValidateOptions {
  bool quick = false, full = false;
  std::string out = "out/validate";
  std::string work;   // default: <out>/cases
  std::vector<std::string> only;
  int threads = 0, jobs = 0;
  double vplate_mm = 0.0;
  double checkpoint_every_min = 0.0;
  bool reuse = false, plot = true;
};

int availableThreads(int requested) {
#ifdef _OPENMP
  return requested > 0 ? requested : omp_get_num_procs();
#else
  return requested > 0 ? requested : 1;
#endif
}

int runValidate(const ValidateOptions& o) {
  // a signal between two cases is seen too (the next case stops at once, and none starts after it)
  const scenario::InterruptScope signals;
  if (o.quick && o.full) throw InputError("level", "give --quick or --full, not both");
  if (o.jobs < 0) throw InputError("jobs", fmt::format("{} is out of range; valid >= 0 (0: one case per thread)", o.jobs));
  applyThreads(o.threads);
  const auto level = o.full ? scenario::ValidationLevel::Full : scenario::ValidationLevel::Quick;
  const auto plan = scenario::validationPlan(level, o.only, o.vplate_mm);
  const int threads = availableThreads(o.threads);
  const int jobs = std::clamp(o.jobs > 0 ? o.jobs : threads, 1, static_cast<int>(plan.cases.size()));
  const int threads_per_job = std::max(1, threads / jobs);

  // every deck read and checked before anything runs
  std::vector<scenario::Deck> decks;
  for (const auto& c : plan.cases) decks.push_back(scenario::loadDeck(resolveDeck(c.deck), c.sets));
  const fs::path out(o.out), work(o.work.empty() ? (out / "cases").string() : o.work);
  for (const auto& p : {out, work})
    if (fs::exists(p) && !fs::is_directory(p)) throw InputError(p == out ? "out" : "work", fmt::format("'{}' exists and is not a directory", p.string()));
  fs::create_directories(out);
  fs::create_directories(work);

  std::map<std::string, json> outcomes;
  std::vector<std::size_t> todo;
  int reused = 0;
  for (std::size_t i = 0; i < plan.cases.size(); ++i) {
    const fs::path saved = work / plan.cases[i].id / "validation_case.json";
    if (o.reuse && fs::exists(saved)) {
      try {
        auto j = json::parse(io::readWholeFile(saved).value_or(""));
        if (j.at("deck_echo") == decks[i].echo && j.value("solver_revision", 1) == hydro::kSolverRevision) {
          outcomes[plan.cases[i].id] = std::move(j);
          ++reused;
          continue;
        }
      } catch (const json::exception&) {
        // unreadable: run the case again
      }
    }
    todo.push_back(i);
  }
  // the dearest first, so that parallel jobs finish together
  std::stable_sort(todo.begin(), todo.end(), [&](std::size_t a, std::size_t b) { return plan.cases[a].relative_cost > plan.cases[b].relative_cost; });
  double cost_all = 0.0;
  for (const auto i : todo) cost_all += plan.cases[i].relative_cost;
  std::cerr << fmt::format("validate ({}): {} cases to run{}, {} at a time with {} thread(s) each; cases in {}\n", o.full ? "full" : "quick", todo.size(),
                           reused ? fmt::format(" ({} reused)", reused) : "", jobs, threads_per_job, work.string());

  std::mutex lock;
  std::size_t next = 0, done = 0;
  double cost_done = 0.0, cpu_s = 0.0;
  std::exception_ptr failure;
  std::atomic<bool> stop{false};
  const auto t0 = std::chrono::steady_clock::now();
  auto worker = [&]() {
#ifdef _OPENMP
    omp_set_num_threads(threads_per_job);
#endif
    for (;;) {
      std::size_t i = 0;
      {
        std::lock_guard<std::mutex> g(lock);
        if (stop || next >= todo.size()) return;
        i = todo[next++];
        std::cerr << fmt::format("validate: start {} ({} at {:g} mm)\n", plan.cases[i].id, plan.cases[i].deck, plan.cases[i].cell_mm);
      }
      try {
        const auto& c = plan.cases[i];
        scenario::RunOptions ro;
        ro.out_dir = (work / c.id).string();
        ro.progress = false;
        ro.log_progress_every_s = 300.0;   // a 3D case runs for half an hour: say how far it is
        ro.plot = false;
        ro.checkpoint_every_s = 60.0 * o.checkpoint_every_min;
        ro.log = [&lock, id = c.id](const std::string& m) {
          const std::lock_guard<std::mutex> g(lock);
          std::cerr << fmt::format("validate: {}: {}\n", id, m);
        };
        const auto r = runOrContinue(decks[i], ro, o.reuse, "validate: " + c.id);
        auto j = scenario::condenseOutcome(c, r);
        j["deck_echo"] = decks[i].echo;
        j["ejecta_version"] = build_info::version;
        j["solver_revision"] = hydro::kSolverRevision;
        io::writeFileAtomically(work / c.id / "validation_case.json", j.dump() + "\n");
        std::lock_guard<std::mutex> g(lock);
        outcomes[c.id] = std::move(j);
        ++done;
        cost_done += c.relative_cost;
        cpu_s += r.wall_s;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double left = cost_done > 0.0 ? elapsed * (cost_all - cost_done) / cost_done : 0.0;
        std::cerr << fmt::format("validate: {}/{} done: {} {} ({:.0f} s); elapsed {:.1f} min, left ~{:.1f} min\n", done, todo.size(), c.id,
                                 r.peak_force_N > 0.0 ? fmt::format("impulse {:.0f} N s", r.impulse_Ns) : "no target", r.wall_s, elapsed / 60.0,
                                 left / 60.0);
      } catch (...) {
        std::lock_guard<std::mutex> g(lock);
        if (!failure) failure = std::current_exception();
        stop = true;
        std::cerr << fmt::format("validate: {} failed; no new cases start\n", plan.cases[i].id);
        return;
      }
    }
  };
  if (jobs == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (int j = 0; j < jobs; ++j) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  if (failure) std::rethrow_exception(failure);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  json info{{"ejecta_version", build_info::version}, {"solver_revision", hydro::kSolverRevision}, {"threads", threads}, {"jobs", jobs}, {"wall_s", wall}, {"cpu_s", cpu_s},
            {"reused", reused}, {"machine", fmt::format("{} cores seen", std::thread::hardware_concurrency())}};
  auto report = scenario::validationReport(plan, outcomes, info);
  if (!o.plot)
    for (auto& sec : report["sections"]) sec.erase("figure");

  io::OutputTransaction outputs;
  std::map<std::string, std::string> figures;
  for (const auto& sec : report.at("sections")) {
    if (!sec.contains("figure")) continue;
    const std::string name = sec.at("figure").get<std::string>();
    const fs::path png = outputs.reserve(out / name);
    const fs::path data = io::temporarySibling(out / (name + ".json"));
    io::writeFileAtomically(data, json{{"figure", sec.at("id")}, {"title", sec.at("title")}, {"plot", sec.at("plot")}}.dump());
    try {
      io::runPlotScript("plot_validate.py", data, png);
    } catch (...) {
      fs::remove(data);
      throw;
    }
    fs::remove(data);
    figures[name] = io::readWholeFile(png).value_or("");
  }
  outputs.stage(out / "validation.json", [&](std::ostream& os) { os << report.dump(1) << '\n'; });
  outputs.stage(out / "validation.md", [&](std::ostream& os) { os << io::renderReportMarkdown(report); });
  outputs.stage(out / "validation.html", [&](std::ostream& os) { os << io::renderReportHtml(report, figures); });
  outputs.commit();

  std::cout << io::renderReportMarkdown(json{{"title", report.at("title")},
                                             {"level", report.at("level")},
                                             {"run", report.at("run")},
                                             {"units", report.at("units")},
                                             {"intro", json::array()},
                                             {"checks", report.at("checks")},
                                             {"sections", json::array()},
                                             {"cases_table", report.at("cases_table")}});
  std::cout << fmt::format("wrote {0}/validation.md, validation.html, validation.json{1}; case folders in {2}\n", o.out,
                           o.plot ? " and the figures" : "", work.string());
  for (const auto& c : report.at("checks"))
    if (c.at("pass").is_boolean() && !c.at("pass").get<bool>()) return 4;
  return 0;
}
}  // namespace

Action addValidateCommand(CLI::App& app) {
  auto o = std::make_shared<ValidateOptions>();
  auto* sub = app.add_subcommand("validate",
                                 "Runs the built-in validation decks (mesh study, moisture, field-test covers, impulse by material,\n"
                                 "sensitivity to the unknown inputs, DRES soil bubble, 3D V-plates) and writes the report: validation.md + PNG\n"
                                 "figures, a self-contained validation.html and validation.json. Exit code 4 if a check fails.");
  sub->add_flag("--quick", o->quick, "Coarse cells, a few minutes on 2 cores (the default)");
  sub->add_flag("--full", o->full, "The published resolution: plates at 5 mm, mesh study 10/6/5/4/3 mm, soil bubble 3 mm, sensitivity 10 mm (about 40 min on 2 cores; the three 3D plates at 10 mm about 1.3 hours more: on revision 15 22.0 / 26.6 / 27.2 min for the flat, 120 and 90 degree plates)");
  sub->add_option("--only", o->only, "Studies to run, comma-separated: mesh, moisture, field, share, sensitivity, dres, vplates (default: all)")
      ->delimiter(',');
  sub->add_option("--vplate-cell-size", o->vplate_mm,
                  "Cell size of the 3D V-plates, mm, [5, 100] (default: the level's, quick 60 mm to 5 ms, full 10 mm to 10 ms; 20 mm at --full takes about 12 minutes on 2 cores)");
  sub->add_option("--out", o->out, "Report folder (default out/validate)");
  sub->add_option("--work", o->work, "Folder for the case runs (default <out>/cases)");
  sub->add_option("--threads", o->threads, "Threads in all (default: all cores)");
  sub->add_option("--jobs", o->jobs, "Cases run at once, sharing the threads (default: one case per thread)");
  sub->add_flag("--reuse", o->reuse,
                "Take a case's result from an earlier run in --work when its deck is unchanged, and continue a case that an\n"
                "interrupted study left a checkpoint of");
  addCaseCheckpointOption(sub, o->checkpoint_every_min);
  sub->add_flag("!--no-plot", o->plot, "Skip the figures");
  return [sub, o]() -> int {
    if (!sub->parsed()) return -1;
    return runValidate(*o);
  };
}

}  // namespace ejecta::cli

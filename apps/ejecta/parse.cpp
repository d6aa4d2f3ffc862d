#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"
#include "scenario/run.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ejecta::cli {

double parseNumber(const std::string& field, const std::string& text, bool percent_ok) {
  std::string body = text;
  const bool percent = !body.empty() && body.back() == '%';
  if (percent) {
    if (!percent_ok) throw InputError(field, fmt::format("'{}' is not a number (no % here)", text));
    body.pop_back();
  }
  char* end = nullptr;
  const double v = std::strtod(body.c_str(), &end);
  if (body.empty() || end != body.c_str() + body.size() || !std::isfinite(v))
    throw InputError(field, fmt::format("'{}' is not a finite number", text));
  if (percent) return v / 100.0;
  if (percent_ok && v > 1.0)
    throw InputError(field, fmt::format("'{}' is ambiguous: give a fraction in [0, 1] (0.07) or a percentage (7%)", text));
  return v;
}

std::string resolveDeck(const std::string& name) {
  namespace fs = std::filesystem;
  if (name.empty()) return (fs::path(build_info::decks_dir) / "emi-flat-7.toml").string();
  if (fs::exists(name)) return name;
  const fs::path builtin = fs::path(build_info::decks_dir) / (name.ends_with(".toml") ? name : name + ".toml");
  if (fs::exists(builtin)) return builtin.string();
  throw InputError("deck", fmt::format("'{}' is neither a file nor a built-in deck (see {})", name, build_info::decks_dir));
}

void applyThreads(int threads) {
  constexpr int kMaxThreads = 1024;   // beyond this the OpenMP runtime fails (seen: a crash at 100000)
  if (threads < 0 || threads > kMaxThreads)
    throw InputError("threads", fmt::format("{} is out of range; valid [0, {}] (0: all cores)", threads, kMaxThreads));
#ifdef _OPENMP
  if (threads > 0) omp_set_num_threads(threads);
#endif
}

std::string cellSizeOverride(const std::string& millimetres) {
  return "mesh.cell_size_m=" + fmt::format("{:g}", parseNumber("cell-size", millimetres) / 1000.0);
}

scenario::RunResult runOrContinue(const scenario::Deck& deck, scenario::RunOptions ro, bool reuse, const std::string& label) {
  if (reuse) ro.restart = scenario::leftCheckpoint(ro.out_dir);
  if (ro.restart.empty()) return scenario::runCase(deck, ro);
  std::cerr << fmt::format("{}: continues from {}\n", label, ro.restart);
  try {
    return scenario::runCase(deck, ro);
  } catch (const InputError& e) {
    // the checkpoint is not this case's to continue (another build, damaged, other gauges, past the end)
    if (e.field() != "restart" && e.field() != "end_time_s") throw;
    std::cerr << fmt::format("{}: cannot continue ({}); runs from the start\n", label, e.what());
  }
  ro.restart.clear();
  return scenario::runCase(deck, ro);
}

void addCaseCheckpointOption(CLI::App* sub, double& minutes) {
  sub->add_option("--checkpoint-every", minutes,
                  "Each case writes a checkpoint every MIN minutes of wall time and when a signal stops it (see ejecta run);\n"
                  "--reuse continues from it")
      ->check(CLI::Range(0.0, 1e6));
}

}  // namespace ejecta::cli

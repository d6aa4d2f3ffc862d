#pragma once
// `ejecta run`: one buried-charge case from its deck to the run folder: summary.json,
// history.csv (plate impulse, force, velocity, displacement, impulse by material, bubble height),
// gauges.csv, surface_profiles.csv, fields/*.vtr (on MPI ranks .pvtr indexes of per-rank pieces) + fields.pvd (ParaView), plots.png, and on
// request a checkpoint that a restart continues bit for bit.
#include <functional>
#include <string>
#include <vector>

#include "scenario/deck.hpp"

namespace ejecta::parallel {
class Exchange;   // parallel/exchange.hpp
}

namespace ejecta::scenario {

struct RunOptions {
  std::string out_dir = "out/run";
  double checkpoint_at_s = -1.0;   // write checkpoint.bin when the run passes this time (< 0: never)
  // Write checkpoint.bin every this many seconds of wall time on the run mesh, replacing the last
  // (0: never), and when a signal stops the run: a run cut short (a scheduler's time limit, a
  // crash) restarts from the last one. It lands no step, so the results are those of a run without it.
  double checkpoint_every_s = 0.0;
  std::string restart;             // continue from this checkpoint
  bool progress = true;            // progress lines on stderr
  // Every this many seconds of wall time, a line through `log` with the run's time, steps and time
  // left (0: none): a study's cases, whose progress lines are off, still say how far they are.
  double log_progress_every_s = 0.0;
  bool plot = true;
  std::function<void(const std::string&)> log;
  // MPI ranks (more than one): every rank runs the early time and builds and steps only its slab of
  // the run mesh (docs/solver.md); each rank writes its pieces of the field snapshots into
  // the run folder (which every rank must see), rank 0 the rest, and the result is the same on
  // every rank, to the last bit of the impulse.
  parallel::Exchange* exchange = nullptr;
};

struct RunResult {
  double impulse_Ns = 0.0;          // total, delivered by the flow to the target (full 360 degrees)
  double impulse_air_Ns = 0.0, impulse_products_Ns = 0.0, impulse_soil_Ns = 0.0;   // by the material beside each face
  // by the materials within hydro::kNearWallDepth_m[l] of each face: [3 l + (air, products, soil)]
  std::vector<double> impulse_near_Ns;
  double peak_force_N = 0.0;
  double final_velocity_m_s = 0.0;
  double displacement_m = 0.0;
  long long steps = 0;
  std::size_t cells = 0;
  double wall_s = 0.0;              // this run's
  double wall_before_s = 0.0;       // the runs' before the checkpoint it restarted from (0: a fresh run)
  double energy_imbalance_fraction = 0.0;   // energy books' imbalance / the charge's energy (round-off)
  double charge_energy_J = 0.0;             // the charge's detonation energy, mass x E0 / rho0 (0: no products)
  // What history.csv and surface_profiles.csv hold, for callers that study many runs.
  std::vector<std::string> history_columns;
  std::vector<std::vector<double>> history;
  std::vector<double> profile_r_m, profile_times_s;
  std::vector<std::vector<double>> profiles_m;   // per profile time, per r column; NaN: no soil
};

RunResult runCase(const Deck& deck, const RunOptions& opt);

// What runCase checks of a fresh run before its first step, without running it: the deck's
// geometry on its mesh (the charge inside the uniform core, gauges in the flow, the end after the
// early time). Throws InputError naming the field. A study checks all its cases with it first.
void checkCase(const Deck& deck);

// While one lives, SIGINT, SIGTERM and SIGHUP set a flag instead of ending the process (a signal
// the process was started ignoring stays ignored). runCase holds one and stops at its next step;
// a study holds one over all its cases, so that a signal between two is seen too. Scopes nest.
class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};
// The signal that came (0: none). Never cleared: once one came, a study starts no further case.
int interruptedBy();

// The checkpoint that an interrupted run into `out_dir` left in its staging folder
// (.NAME.staging-PID/checkpoint.bin, its process gone; the newest if several), or "" if none:
// what `--reuse` in a study continues a case from.
std::string leftCheckpoint(const std::string& out_dir);
// Removes the staging folders that runs into `out_dir` left and whose processes are gone (an
// interrupted run's, with its checkpoint): for a study that no longer has that case.
void removeLeftStages(const std::string& out_dir);
// The name of the run folder a staging folder's name (.NAME.staging-PID) belongs to, or "".
std::string stagedRunName(const std::string& name);

}  // namespace ejecta::scenario

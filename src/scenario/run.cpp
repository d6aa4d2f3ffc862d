#include "scenario/run.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <optional>
#include <map>
#include <mutex>
#include <sstream>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"
#include "io/subprocess.hpp"
#include "parallel/exchange.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif
#include "io/checkpoint.hpp"
#include "io/vtk.hpp"
#include "hydro/rezone.hpp"
#include "coupling/target.hpp"
#include "scenario/case.hpp"

namespace ejecta::scenario {
namespace {
namespace fs = std::filesystem;

// Everything the driver accumulates, so that a checkpoint holds it and a restart continues it.
struct DriverState {
  double energy_initial = 0.0;   // J in the cells at t = 0 (axisymmetric: per radian)
  coupling::TargetState target;
  std::vector<std::vector<double>> history, gauges;
  std::vector<double> profile_times;
  std::vector<std::vector<double>> profiles;   // surface height per r column
  std::vector<double> field_times;
  double next_history = 0.0;
  std::size_t next_profile = 0, next_field = 0;
  bool checkpoint_written = false;
  double wall_before_s = 0.0;   // wall time of the runs before the checkpoint this one restarted from
};

void putList(std::ostream& os, const std::vector<double>& v) {
  const std::uint64_t n = v.size();
  os.write(reinterpret_cast<const char*>(&n), sizeof n);
  os.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(n * sizeof(double)));
}
[[noreturn]] void damagedCheckpoint() { throw InputError("restart", "the checkpoint is damaged"); }
// A count stored as a double: a whole number in [0, 2^32], else the checkpoint is damaged (casting
// a NaN, a negative or a huge double to an integer is undefined).
std::size_t countOf(double v) {
  if (!(v >= 0.0 && v <= 4294967296.0 && v == std::floor(v))) damagedCheckpoint();
  return static_cast<std::size_t>(v);
}
std::vector<double> getList(std::istream& is) {
  std::uint64_t n = 0;
  is.read(reinterpret_cast<char*>(&n), sizeof n);
  if (!is || n > (1ULL << 32)) damagedCheckpoint();
  // Read in blocks, so that a damaged length allocates no more than the bytes that are there.
  std::vector<double> v;
  while (v.size() < n && is) {
    const std::size_t at = v.size(), k = std::min<std::size_t>(n - at, std::size_t{1} << 16);
    v.resize(at + k);
    is.read(reinterpret_cast<char*>(v.data() + at), static_cast<std::streamsize>(k * sizeof(double)));
  }
  return v;
}
void putTable(std::ostream& os, const std::vector<std::vector<double>>& t) {
  putList(os, {static_cast<double>(t.size())});
  for (const auto& r : t) putList(os, r);
}
std::vector<std::vector<double>> getTable(std::istream& is) {
  const auto n = getList(is);
  if (n.size() != 1) damagedCheckpoint();
  std::vector<std::vector<double>> t;
  for (std::size_t i = 0, rows = countOf(n[0]); i < rows; ++i) t.push_back(getList(is));
  return t;
}
// The driver's scalars by name (a JSON object), so that the checkpoint says what each one is; its
// lists and tables follow as binary lists.
constexpr std::uint64_t kMaxStateText = 1u << 16;
void putState(std::ostream& os, const DriverState& s) {
  const auto& t = s.target;
  const std::string scalars = nlohmann::json{{"target_z_m", t.z},
                                             {"target_velocity_m_s", t.v},
                                             {"impulse_Ns", t.impulse},
                                             {"peak_force_N", t.peak_force},
                                             {"static_known", t.static_known},
                                             {"static_force_N", t.static_force},
                                             {"energy_initial_J", s.energy_initial},
                                             {"next_history_s", s.next_history},
                                             {"next_profile", s.next_profile},
                                             {"next_field", s.next_field},
                                             {"wall_s", s.wall_before_s}}
                                  .dump(-1, ' ', false, nlohmann::json::error_handler_t::strict);
  const std::uint64_t n = scalars.size();
  os.write(reinterpret_cast<const char*>(&n), sizeof n);
  os.write(scalars.data(), static_cast<std::streamsize>(n));
  putList(os, t.impulse_kind);
  putList(os, t.impulse_kind_near);
  putTable(os, s.history);
  putTable(os, s.gauges);
  putList(os, s.profile_times);
  putTable(os, s.profiles);
  putList(os, s.field_times);
}
// Reads what putState wrote; refused unless every named scalar is there with its type and what the
// run indexes without further checks fits it: three impulse kinds, one profile per profile time
// with a value per r column (`profile_columns`).
void getState(std::istream& is, DriverState& s, std::size_t profile_columns) {
  std::uint64_t n = 0;
  is.read(reinterpret_cast<char*>(&n), sizeof n);
  if (!is || n > kMaxStateText) damagedCheckpoint();
  std::string text(static_cast<std::size_t>(n), '\0');
  is.read(text.data(), static_cast<std::streamsize>(n));
  if (!is) damagedCheckpoint();
  auto& t = s.target;
  try {
    const auto j = nlohmann::json::parse(text);
    auto number = [&](const char* key) {
      const auto& v = j.at(key);
      if (!v.is_number() || !std::isfinite(v.get<double>())) damagedCheckpoint();
      return v.get<double>();
    };
    t.z = number("target_z_m");
    t.v = number("target_velocity_m_s");
    t.impulse = number("impulse_Ns");
    t.peak_force = number("peak_force_N");
    t.static_force = number("static_force_N");
    if (!j.at("static_known").is_boolean()) damagedCheckpoint();
    t.static_known = j.at("static_known").get<bool>();
    s.energy_initial = number("energy_initial_J");
    s.next_history = number("next_history_s");
    s.next_profile = countOf(number("next_profile"));
    s.next_field = countOf(number("next_field"));
    // (not in the checkpoints of 3 December 2026 and before: their runs' time is not known)
    s.wall_before_s = j.contains("wall_s") ? number("wall_s") : 0.0;
    if (s.wall_before_s < 0.0) damagedCheckpoint();
  } catch (const nlohmann::json::exception&) {
    damagedCheckpoint();
  }
  t.impulse_kind = getList(is);
  t.impulse_kind_near = getList(is);
  s.history = getTable(is);
  s.gauges = getTable(is);
  s.profile_times = getList(is);
  s.profiles = getTable(is);
  s.field_times = getList(is);
  const bool profiles_fit = s.profiles.size() == s.profile_times.size() &&
                            std::all_of(s.profiles.begin(), s.profiles.end(), [&](const auto& p) { return p.size() == profile_columns; });
  if (t.impulse_kind.size() != 3 || t.impulse_kind_near.size() != 3 * hydro::kNearWallDepths || !profiles_fit) damagedCheckpoint();
}
// A restart's gauges are its deck's: rows of another list would not fit gauges.csv's columns.
void checkGauges(const DriverState& s, std::size_t gauges) {
  for (const auto& row : s.gauges)
    if (row.size() != gauges + 1)
      throw InputError("restart", fmt::format("the checkpoint's run recorded {} gauge(s), the deck's output.gauges_m has {}; valid: the same gauges",
                                              row.size() - 1, gauges));
}

// The load split by the materials within each of kNearWallDepth_m of the target.
nlohmann::json nearWallJson(const std::vector<double>& near) {
  nlohmann::json j{{"depth_m", hydro::kNearWallDepth_m}, {"air", nlohmann::json::array()}, {"products", nlohmann::json::array()}, {"soil", nlohmann::json::array()}};
  for (std::size_t l = 0; l < hydro::kNearWallDepth_m.size(); ++l) {
    j["air"].push_back(near.at(3 * l));
    j["products"].push_back(near.at(3 * l + 1));
    j["soil"].push_back(near.at(3 * l + 2));
  }
  return j;
}

// What ties a checkpoint to its deck and build. The deck digest leaves out end_time_s and the
// output settings: a restart may run longer or write other outputs, but not change the physics.
io::CheckpointHeader checkpointHeader(const Deck& deck, double t) {
  auto physics = deck.echo;
  physics.erase("end_time_s");
  physics.erase("output");
  io::CheckpointHeader h;
  h.solver_revision = static_cast<std::uint32_t>(hydro::kSolverRevision);
  h.deck_digest = io::crc32Of(physics.dump());
  h.build_digest = io::buildDigest();
  h.time_s = t;
  return h;
}

// Height of the soil surface in each column along the first horizontal axis (r; x at y = 0 in 3D):
// the top of the highest cell holding at least `threshold` of soil by volume.
std::vector<double> surfaceProfile(const Case& cs, const hydro::Solver& s, double threshold) {
  const auto& g = s.grid();
  const int up = cs.vertical;
  std::vector<double> z(static_cast<std::size_t>(g.cells(0)), std::nan(""));
  for (int i = 0; i < g.cells(0); ++i)
    for (int j = g.cells(up) - 1; j >= 0; --j) {
      const std::size_t c = up == 1 ? g.index(i, j, 0) : g.index(i, 0, j);
      if (s.isBody(c)) continue;
      double soil = 0.0;
      for (int k = 0; k < s.materialCount(); ++k)
        if (cs.material_kind[static_cast<std::size_t>(k)] == "soil") soil += s.field(k).alpha[c];
      if (soil >= threshold) {
        z[static_cast<std::size_t>(i)] = g.face(up, j + 1);
        break;
      }
    }
  return z;
}

// The cell holding the point at radius r (x in 3D, on the y = 0 plane) and height z.
std::size_t cellAt(const mesh::Grid& g, int up, double r, double z) {
  auto find = [&](int d, double x) {
    const auto& f = g.axis(d).faces();
    const auto it = std::upper_bound(f.begin(), f.end(), x);
    return std::clamp(static_cast<int>(it - f.begin()) - 1, 0, g.cells(d) - 1);
  };
  return up == 1 ? g.index(find(0, r), find(1, z), 0) : g.index(find(0, r), 0, find(2, z));
}

// The early-time fine block for this deck on this run mesh, or nothing where the run's own cells
// resolve the charge. The block is axisymmetric (r, z) and spans whole cells of the run's uniform
// core around the charge, so along z (and along r in 2D) the meshes nest; a 3D run takes it onto
// its quarter by each column's overlap with the rings, so there the block must stay below the
// target and the charge must be round (not a box). The map time is when the fastest wave
// (early.signal_speed_m_s) could first reach the block's nearest cut side.
struct EarlyPlan {
  FineBlock block;
  int ratio = 1;          // run cells per fine cell along each axis
  double map_time_s = 0.0;
  double burn_time_s = 0.0;
};
std::optional<EarlyPlan> planEarly(const Deck& deck, const Case& cs) {
  const auto& e = deck.early;
  const double H = cs.charge.height_m;
  const auto& g = cs.grid();
  const bool three_d = cs.vertical == 2;
  const int up = cs.vertical;
  if (!e.enabled || (three_d && deck.charge.shape == "box")) return std::nullopt;
  // the run's core cells (the radial core is divided evenly, so its width may differ from
  // mesh.cell_size_m by a fraction; the vertical one is laid from z = 0 at that size)
  auto widthAt = [&g](int d, double x) {
    const auto& f = g.axis(d).faces();
    const int i = std::clamp(static_cast<int>(std::upper_bound(f.begin(), f.end(), x) - f.begin()) - 1, 0, g.cells(d) - 1);
    return f[static_cast<std::size_t>(i) + 1] - f[static_cast<std::size_t>(i)];
  };
  const double wr = widthAt(0, 0.5 * cs.charge.radius_m), wz = widthAt(up, 0.5 * (cs.charge.z_top_m + cs.charge.z_bottom_m));
  const double h = std::max(wr, wz);
  if (h * e.cells_per_charge_height <= H * (1.0 + 1e-9)) return std::nullopt;
  EarlyPlan p;
  p.ratio = static_cast<int>(std::ceil(h * e.cells_per_charge_height / H - 1e-9));
  p.block.cell_size_m = h / p.ratio;
  p.block.ratio = p.ratio;
  // the uniform core's faces along axis d: the run of cells of the width at x
  auto core = [&](int d, double x) {
    const auto& f = g.axis(d).faces();
    int i = static_cast<int>(std::upper_bound(f.begin(), f.end(), x) - f.begin()) - 1;
    i = std::clamp(i, 0, g.cells(d) - 1);
    const double w = f[static_cast<std::size_t>(i) + 1] - f[static_cast<std::size_t>(i)];
    auto uniform = [&](int c) { return c >= 0 && c < g.cells(d) && std::abs(f[static_cast<std::size_t>(c) + 1] - f[static_cast<std::size_t>(c)] - w) < 1e-9 * w; };
    int lo = i, hi = i;
    while (uniform(lo - 1)) --lo;
    while (uniform(hi + 1)) ++hi;
    return std::vector<double>(f.begin() + lo, f.begin() + hi + 2);
  };
  const auto& ch = cs.charge;
  const auto ex = materials::explosive(deck.charge.explosive).jwl;
  p.burn_time_s = std::hypot(ch.radius_m, ch.height_m) / ex.d_cj;
  // the block scales with the charge: by default it holds the fastest wave for four burn times
  const double margin = e.block_margin_m > 0.0 ? e.block_margin_m : 4.0 * p.burn_time_s * e.signal_speed_m_s;
  const auto rf = core(0, 0.5 * ch.radius_m), zf = core(up, 0.5 * (ch.z_top_m + ch.z_bottom_m));
  auto firstAtOrAbove = [](const std::vector<double>& f, double x) { const auto it = std::lower_bound(f.begin(), f.end(), x - 1e-12); return it == f.end() ? f.back() : *it; };
  auto lastAtOrBelow = [](const std::vector<double>& f, double x) { auto it = std::upper_bound(f.begin(), f.end(), x + 1e-12); return it == f.begin() ? f.front() : *(it - 1); };
  p.block.r_max_m = firstAtOrAbove(rf, ch.radius_m + margin);
  p.block.z_lo_m = lastAtOrBelow(zf, ch.z_bottom_m - margin);
  p.block.z_hi_m = firstAtOrAbove(zf, ch.z_top_m + margin);
  // No cut side within the ghost layers of a target face: a face of the target on (or next to) a
  // cut would take its load from ghost cells. The block stops short of it instead.
  if (cs.plate.present) {
    const double gap = mesh::kGhost * h;
    const auto& pl = cs.plate;
    const bool under = pl.r_inner_m < p.block.r_max_m;   // the target spans the block's radius
    if (three_d) {   // the block holds no target: it ends at or below the target's lowest point
      if (p.block.z_hi_m > pl.z_bottom_m) p.block.z_hi_m = lastAtOrBelow(zf, pl.z_bottom_m);
    } else if (under && p.block.z_hi_m > pl.z_bottom_m - gap && p.block.z_hi_m < pl.z_top_m + gap)
      p.block.z_hi_m = lastAtOrBelow(zf, pl.z_bottom_m - gap);
    const bool beside = !three_d && pl.z_bottom_m < p.block.z_hi_m && pl.z_top_m > p.block.z_lo_m;
    for (const double face : {pl.r_inner_m, pl.r_outer_m})
      if (beside && face > 0.0 && std::abs(p.block.r_max_m - face) < gap) p.block.r_max_m = lastAtOrBelow(rf, face - gap);
  }
  const double reach = std::min({p.block.r_max_m - ch.radius_m, ch.z_bottom_m - p.block.z_lo_m, p.block.z_hi_m - ch.z_top_m});
  if (!(reach > 0.0)) return std::nullopt;
  auto between = [](const std::vector<double>& f, double a, double b) {   // run cells from face a to face b
    const auto ia = std::lower_bound(f.begin(), f.end(), a - 1e-12), ib = std::lower_bound(f.begin(), f.end(), b - 1e-12);
    return static_cast<int>(ib - ia);
  };
  if (rf.front() != 0.0) return std::nullopt;   // the radial core starts on the axis
  p.block.run_cells_r = between(rf, 0.0, p.block.r_max_m);
  p.block.run_cells_z = between(zf, p.block.z_lo_m, p.block.z_hi_m);
  const double t_block = reach / e.signal_speed_m_s;
  p.map_time_s = e.map_time_s > 0.0 ? std::min(e.map_time_s, t_block) : t_block;
  return p;
}

// The checks of a case's set-up that need its mesh (loadDeck made the deck's own): gauges in the
// flow, and a fresh run's end after its early time. buildCase has checked the charge's place.
void checkSetUp(const Deck& deck, const Case& cs, bool fresh) {
  const auto& g = cs.grid();
  for (const auto& p : deck.output.gauges_m)   // a gauge reads the flow: in the target's cells it reads nothing
    if (cs.isBodyCell(cellAt(g, cs.vertical, p[0], p[1])))
      throw InputError("output.gauges_m", fmt::format("gauge ({:g}, {:g}) m lies in the target's cells; valid: a point in the flow", p[0], p[1]));
  if (!fresh) return;
  if (const auto plan = planEarly(deck, cs); plan && deck.end_time_s < plan->map_time_s)
    throw InputError("end_time_s", fmt::format("{:g} s ends within the early time, which runs to {:.6g} s on its fine block; valid: at least "
                                               "{:.6g} s, or early.enabled = false",
                                               deck.end_time_s, plan->map_time_s, plan->map_time_s));
}

int threadCount() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

std::string csvRow(const std::vector<double>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += fmt::format("{}{:.9g}", i ? "," : "", v[i]);
  return s + "\n";
}

// A snapshot's file name: field_NNNN.vtr (whole), field_NNNN.pvtr (an index) or field_NNNN_pRRRR.vtr
// (a piece); anything else is not one.
struct SnapshotFile {
  std::size_t number = 0;
  bool piece = false;
};
std::optional<SnapshotFile> snapshotFile(const std::string& name) {
  auto digits = [&](std::size_t& at) {
    const std::size_t from = at;
    while (at < name.size() && name[at] >= '0' && name[at] <= '9') ++at;
    return at > from && at - from <= 9;
  };
  if (name.rfind("field_", 0) != 0) return std::nullopt;
  std::size_t at = 6;
  const std::size_t from = at;
  if (!digits(at)) return std::nullopt;
  SnapshotFile f;
  f.number = std::stoul(name.substr(from, at - from));
  if (name.compare(at, 2, "_p") == 0) {
    at += 2;
    if (!digits(at)) return std::nullopt;
    f.piece = true;
  }
  const std::string rest = name.substr(at);
  if (rest == ".vtr" || (!f.piece && rest == ".pvtr")) return f;
  return std::nullopt;
}

// SIGINT / SIGTERM / SIGHUP: the run stops at the next step and cleans up (runCase), rather than
// dying with its staging folder half written.
// The flag is cleared by no run: once a signal came, every later check in the process stops (a sweep
// or validate does not start its next case).
std::atomic<int> interrupted_by{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler stores into it");
extern "C" void onInterrupt(int sig) { interrupted_by.store(sig); }
// `every_rank`: the ranks agreed on `sig` (the stepping loop's collective), so every one stops here.
void stopIfInterrupted(double t, int sig = interrupted_by.load(), bool every_rank = false) {
  if (sig != 0) throw Interrupted(sig, fmt::format("interrupted by signal {} at t = {:.6g} s", sig, t), every_rank);
}
// The handlers' state while any scope lives (`ejecta validate` runs cases on several threads).
constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};
std::mutex interrupt_mutex;
int interrupt_scopes = 0;
std::array<struct sigaction, 3> interrupt_previous{};

// Runs the case into `out`, a staging folder that runCase swaps into place when the run ends.
RunResult runStaged(const Deck& deck, const RunOptions& opt, const fs::path& out) {
  auto say = [&](const std::string& m) {
    if (opt.log) opt.log(m);
  };
  parallel::Exchange* const ex = opt.exchange && opt.exchange->size() > 1 ? opt.exchange : nullptr;   // MPI ranks
  const bool writer = !opt.exchange || opt.exchange->rank() == 0;                                      // writes the run folder
  // On MPI ranks each rank builds, paints and steps only its slab of the run mesh (no rank holds the
  // whole); a restart reads the whole checkpoint, then keeps its slab. Validates everything before
  // the run folder is touched.
  const RankPart part{ex ? ex->rank() : 0, ex ? ex->size() : 1};
  Case cs = buildCase(deck, nullptr, ex && opt.restart.empty() ? &part : nullptr);
  checkSetUp(deck, cs, opt.restart.empty());
  const auto mesh_warnings = targetOutsideCore(deck);
  for (const auto& w : mesh_warnings) say("warning: " + w);
  hydro::Solver* rs = cs.solver.get();   // this rank's solver: the whole, or its slab
  if (rs->grid().isSlab()) rs->setExchange(ex);
  const auto& g = cs.grid();             // the whole's mesh (its radial axis never moves)
  const auto up = static_cast<std::size_t>(cs.vertical);
  DriverState st;
  st.target.z = cs.plate.z_bottom_m;
  // The totals of the whole: on slabs the cells' sums column by column in the whole's order (the
  // same numbers as one process), the energy and mass books summed over the slabs (to round-off).
  auto totalsNow = [&]() {
    if (!rs->grid().isSlab()) return rs->totals();
    auto t = rs->totalsOf(ex->gatherAll(rs->columnTotals()));
    const auto& l = rs->energyLedger();
    const std::size_t nm = static_cast<std::size_t>(rs->materialCount()), per = 3 + 2 * nm;
    std::vector<double> mine{l.boundary_in, l.target_work, l.gravity_work};
    mine.insert(mine.end(), l.folded_mass.begin(), l.folded_mass.begin() + static_cast<std::ptrdiff_t>(nm));
    mine.insert(mine.end(), l.boundary_mass.begin(), l.boundary_mass.begin() + static_cast<std::ptrdiff_t>(nm));
    const auto books = ex->gatherAll(mine);
    t.boundary_in = t.target_work = t.gravity_work = 0.0;
    for (std::size_t k = 0; k < nm; ++k) t.folded_mass[k] = t.boundary_mass[k] = 0.0;
    for (std::size_t r = 0; r + per <= books.size(); r += per) {
      t.boundary_in += books[r];
      t.target_work += books[r + 1];
      t.gravity_work += books[r + 2];
      for (std::size_t k = 0; k < nm; ++k) {
        t.folded_mass[k] += books[r + 3 + k];
        t.boundary_mass[k] += books[r + 3 + nm + k];
      }
    }
    return t;
  };
  st.energy_initial = totalsNow().total();
  const double static_run = cs.plate.present ? cs.symmetry * rs->wholeBodyLoad()[up] : 0.0;   // N, the load at rest
  // A free target carries the mesh between the uniform core's bottom and the domain's top with it
  // (the run's solver, and the whole a checkpoint on ranks is assembled into).
  auto moveMeshWithTarget = [&](hydro::Solver& s) {
    if (cs.plate.present && deck.target.motion == "free" && deck.target.move_mesh)
      s.moveMeshWithBody(cs.vertical, deck.mesh.core_bottom_m, deck.mesh.domain_top_m);
  };
  moveMeshWithTarget(*rs);
  if (!opt.restart.empty()) {
    std::istringstream in(io::readCheckpointFile(opt.restart, checkpointHeader(deck, 0.0), nullptr));
    rs->readCheckpoint(in);
    getState(in, st, static_cast<std::size_t>(g.cells(0)));
    checkGauges(st, deck.output.gauges_m.size());
    if (!in) throw InputError("restart", "the checkpoint is truncated");
    if (!(rs->time() < deck.end_time_s))
      throw InputError("end_time_s", fmt::format("{:g} s is not after the checkpoint's time, {:g} s", deck.end_time_s, rs->time()));
    if (opt.checkpoint_at_s > 0.0 && !(opt.checkpoint_at_s > rs->time()))
      throw InputError("checkpoint-at", fmt::format("{:g} s is not after the checkpoint's time, {:g} s", opt.checkpoint_at_s, rs->time()));
    say(fmt::format("restarted from {} at t = {:.6g} s", opt.restart, rs->time()));
    if (ex) {   // this rank's slab of the whole the checkpoint held; the whole goes
      cs.slab = rankSlab(g, ex->rank(), ex->size());
      cs.solver = std::make_unique<hydro::Solver>(rs->slab(cs.slab.begin, cs.slab.end));
      rs = cs.solver.get();
      rs->setExchange(ex);
    }
    // The output times are this deck's (a restart may change them): those at or before the
    // checkpoint's time were the earlier run's to take; the snapshots and profiles it took stay.
    const double t0 = rs->time();
    auto firstAfter = [t0](const std::vector<double>& times) {
      std::size_t i = 0;
      while (i < times.size() && t0 >= times[i] * (1.0 - 1e-12)) ++i;
      return i;
    };
    st.next_field = firstAfter(deck.output.field_times_s);
    st.next_profile = firstAfter(deck.output.profile_times_s);
  }
  if (writer) fs::create_directories(out / "fields");
  if (writer && !opt.restart.empty()) {
    // The snapshots before the checkpoint belong to this run too: copied from the checkpoint's
    // folder where they are there; fields.pvd lists only the snapshots the folder holds.
    // A snapshot is one .vtr, or on ranks a .pvtr index and its pieces (field_NNNN_pRRRR.vtr): the
    // pieces are copied with their index only.
    const fs::path from = fs::path(opt.restart).parent_path() / "fields";
    std::error_code ec;
    if (fs::is_directory(from, ec))
      for (const auto& entry : fs::directory_iterator(from, ec)) {
        const std::string name = entry.path().filename().string();
        const auto file = snapshotFile(name);
        if (!file || file->number >= st.field_times.size() || !entry.is_regular_file(ec)) continue;
        if (file->piece && !fs::is_regular_file(from / fmt::format("field_{:04d}.pvtr", file->number), ec)) continue;
        fs::copy_file(entry.path(), out / "fields" / name, fs::copy_options::overwrite_existing);
      }
  }

  const coupling::Target target(cs.plate.present, deck.target.motion == "free", deck.target.mass_kg, deck.gravity ? 9.81 : 0.0, cs.symmetry,
                                cs.vertical, cs.material_kind);
  // On MPI ranks each steps its slab (`rs`); what a sample needs from the whole is summed or gathered
  // in rank order.
  const bool split = rs->grid().isSlab();
  auto profileNow = [&]() {   // per column of axis 0: the slabs' columns in rank order are the whole's
    auto z = surfaceProfile(cs, *rs, deck.output.surface_soil_fraction);
    return split ? ex->gatherAll(z) : z;
  };
  // a gauge's pressure, from the slab that holds its cell (the radial axis never moves)
  auto gaugeNow = [&](const std::vector<double>& p) {
    if (!split) return rs->pressure(cellAt(rs->grid(), cs.vertical, p[0], p[1]));
    const auto& f = g.axis(0).faces();
    const int i = std::clamp(static_cast<int>(std::upper_bound(f.begin(), f.end(), p[0]) - f.begin()) - 1, 0, g.cells(0) - 1);
    const auto& sg = rs->grid();
    const bool mine = i >= sg.offset0() && i < sg.offset0() + sg.cells(0);
    const double r_local = mine ? sg.centre(0, i - sg.offset0()) : sg.centre(0, 0);
    const auto all = ex->gatherAll({mine ? rs->pressure(cellAt(sg, cs.vertical, r_local, p[1])) : std::nan("")});
    for (const double v : all)
      if (!std::isnan(v)) return v;
    return std::nan("");
  };
  const auto t_wall0 = std::chrono::steady_clock::now();
  auto last_progress = t_wall0, last_logged = t_wall0;
  const double t_end = deck.end_time_s;
  const double h_interval = deck.output.history_interval_s;
  auto& ts = st.target;
  // history.csv: each column declared once, with what fills it (SI units in the names)
  std::vector<double> prof;   // the soil surface at the sample being recorded
  hydro::Totals row_totals;   // the energy books at that sample
  // the whole charge's (all of the symmetry's parts): one kind of material's internal or kinetic
  // energy (J) or mass (kg) on the mesh
  enum class Held { internal, kinetic, mass };
  auto heldBy = [&](const char* kind, Held what) {
    double e = 0.0;
    for (std::size_t k = 0; k < cs.material_kind.size(); ++k)
      if (cs.material_kind[k] == kind)
        e += what == Held::kinetic ? row_totals.kinetic_by_material[k] : (what == Held::internal ? row_totals.internal_by_material[k] : row_totals.mass[k]);
    return cs.symmetry * e;
  };
  const std::vector<std::pair<const char*, std::function<double()>>> history_columns{
      {"t_s", [&] { return rs->time(); }},
      {"impulse_Ns", [&] { return ts.impulse; }},
      {"force_N", [&] { return target.lastForce(*rs, ts); }},
      {"plate_velocity_m_s", [&] { return ts.v; }},
      {"plate_displacement_m", [&] { return ts.z - cs.plate.z_bottom_m; }},
      {"impulse_air_Ns", [&] { return ts.impulse_kind[0]; }},
      {"impulse_products_Ns", [&] { return ts.impulse_kind[1]; }},
      {"impulse_soil_Ns", [&] { return ts.impulse_kind[2]; }},
      // the same split by the materials within 20 mm of the target (kNearWallDepth_m[1])
      {"impulse_air_within_20mm_Ns", [&] { return ts.impulse_kind_near[3]; }},
      {"impulse_products_within_20mm_Ns", [&] { return ts.impulse_kind_near[4]; }},
      {"impulse_soil_within_20mm_Ns", [&] { return ts.impulse_kind_near[5]; }},
      {"bubble_height_on_axis_m", [&] { return prof.empty() ? 0.0 : prof[0]; }},
      {"soil_top_m", [&] {   // the highest soil anywhere: the top of the bubble or the ejecta cloud
         double top = std::nan("");
         for (const double z : prof)
           if (std::isfinite(z) && !(top >= z)) top = z;
         return top;
       }},
      {"dt_s", [&] { return rs->lastDt(); }},
      // where the target's underside is on the mesh (it moves the mesh with it; fixed: where it started)
      {"target_z_m", [&] { return cs.plate.present ? cs.plate.z_bottom_m + rs->bodyOffset() : std::nan(""); }},
      // each kind of material's energy and mass on the mesh (what has left through the boundaries
      // is not): convergence by material, not only in the impulse's sum
      {"internal_energy_air_J", [&] { return heldBy("air", Held::internal); }},
      {"kinetic_energy_air_J", [&] { return heldBy("air", Held::kinetic); }},
      {"internal_energy_products_J", [&] { return heldBy("products", Held::internal); }},
      {"kinetic_energy_products_J", [&] { return heldBy("products", Held::kinetic); }},
      {"internal_energy_soil_J", [&] { return heldBy("soil", Held::internal); }},
      {"kinetic_energy_soil_J", [&] { return heldBy("soil", Held::kinetic); }},
      {"mass_products_kg", [&] { return heldBy("products", Held::mass); }},
      {"mass_soil_kg", [&] { return heldBy("soil", Held::mass); }},
  };
  auto record = [&]() {
    prof = profileNow();
    row_totals = totalsNow();
    std::vector<double> row;
    for (const auto& [name, value] : history_columns) row.push_back(value());
    st.history.push_back(std::move(row));
    std::vector<double> gr{rs->time()};   // gauges stay at their points in space while the mesh moves
    for (const auto& p : deck.output.gauges_m) gr.push_back(gaugeNow(p));
    st.gauges.push_back(gr);
  };
  auto writeField = [&]() {
    const std::string stem = fmt::format("field_{:04d}", st.field_times.size());   // numbered as taken
    if (!split) {
      if (writer) io::writeFileAtomically(out / "fields" / (stem + ".vtr"), [&](std::ostream& os) { io::writeVtr(os, *rs); });
    } else {
      // Each rank writes its slab as a piece, and rank 0 the index once every piece is on disk: no
      // rank gathers the whole, and a snapshot whose piece failed gets no index.
      const auto slabs = parallel::slabs(g.cells(0), ex->size());
      auto pieceName = [&](int r) { return fmt::format("{}_p{:04d}.vtr", stem, r); };
      std::string failed;
      try {
        io::writeFileAtomically(out / "fields" / pieceName(ex->rank()), [&](std::ostream& os) { io::writeVtr(os, *rs); });
      } catch (const std::exception& e) {
        failed = e.what();
      }
      // every rank learns every failure in words, so that rank 0 says the cause once
      const std::string all = parallel::gatherText(*ex, failed.empty() ? std::string() : fmt::format("rank {}: {}", ex->rank(), failed));
      if (!all.empty()) throw SharedFailure(fmt::format("could not write the pieces of fields/{}.pvtr: {}", stem, all));
      if (writer) {
        std::vector<io::VtrPiece> pieces;
        for (int r = 0; r < ex->size(); ++r) pieces.push_back({slabs[static_cast<std::size_t>(r)].begin, slabs[static_cast<std::size_t>(r)].end, pieceName(r)});
        io::writeFileAtomically(out / "fields" / (stem + ".pvtr"), [&](std::ostream& os) { io::writePvtr(os, *rs, pieces); });
      }
    }
    st.field_times.push_back(rs->time());
  };
  if (rs->time() == 0.0) record();

  // ---- the early time: the detonation and first expansion on a fine block, mapped onto the run mesh
  nlohmann::json early_json = {{"enabled", deck.early.enabled}, {"used", false}};
  if (const auto plan = opt.restart.empty() ? planEarly(deck, cs) : std::nullopt) {
    const auto t_early0 = std::chrono::steady_clock::now();
    // A 3D run's block is the same deck's axisymmetric case, without the target (it lies above).
    const bool onto_3d = cs.vertical == 2;
    Deck deck_rz = deck;
    if (onto_3d) {
      deck_rz.geometry = "axisymmetric";
      deck_rz.target.kind = "none";
    }
    Case fine = buildCase(deck_rz, &plan->block);
    auto& fs_ = *fine.solver;
    // per radian (the block) -> the run's part of the whole (a quarter in 3D, per radian in 2D)
    const double to_run = onto_3d ? 0.5 * M_PI : 1.0;
    // The target on the fine block is the run mesh's, cell for cell (the staircase of a run cell
    // is the staircase of its fine cells), so that the mapping moves no material into the target.
    if (cs.plate.present && !onto_3d)
      fs_.setBody([&g, &cs](const hydro::Vec3& x) {
        auto at = [&g](int d, double v) {
          const auto& f = g.axis(d).faces();
          return std::clamp(static_cast<int>(std::upper_bound(f.begin(), f.end(), v) - f.begin()) - 1, 0, g.cells(d) - 1);
        };
        return cs.isBodyCell(g.index(at(0, x[0]), at(1, x[1]), 0));
      });
    const auto& fg = fs_.grid();
    say(fmt::format("early time: fine block r <= {:.3f} m, z {:.3f} to {:.3f} m, {} x {} cells of {:.3g} mm ({:.1f} per charge height), to t = {:.3g} us",
                    plan->block.r_max_m, plan->block.z_lo_m, plan->block.z_hi_m, fg.cells(0), fg.cells(1), 1e3 * plan->block.cell_size_m,
                    cs.charge.height_m / plan->block.cell_size_m, 1e6 * plan->map_time_s));
    // A charge far smaller than the run's cells gets a block of whole run cells at a fine cell
    // size: said before the work when it is ten times the run's (cells times the steps each mesh
    // needs at one signal speed).
    const double early_work = static_cast<double>(fg.interiorCells()) * plan->map_time_s / plan->block.cell_size_m;
    const double run_work = static_cast<double>(g.interiorCells()) * deck.end_time_s / deck.mesh.cell_size_m;
    if (early_work > 10.0 * run_work)
      say(fmt::format("early time: its block costs about {:.3g} times the run mesh's work ({} cells of {:.3g} mm for the charge's {:.3g} mm "
                      "height against {} run cells of {:.3g} mm): smaller run cells, a lower early.cells_per_charge_height, or "
                      "early.enabled = false cost less",
                      early_work / run_work, fg.interiorCells(), 1e3 * plan->block.cell_size_m, 1e3 * cs.charge.height_m, g.interiorCells(),
                      1e3 * deck.mesh.cell_size_m));
    const double e_fine0 = fs_.totals().total();
    // the load at rest on the part of the target inside the block (the rest is undisturbed)
    const double static_fine = cs.plate.present && !onto_3d ? cs.symmetry * fs_.bodyLoad()[up] : 0.0;
    auto last = std::chrono::steady_clock::now();
    while (fs_.time() < plan->map_time_s * (1.0 - 1e-12)) {
      stopIfInterrupted(fs_.time());
      const double dt = fs_.nextTimeStep(plan->map_time_s);
      if (!onto_3d) fs_.setBodyVelocity(target.wallVelocity(ts));
      fs_.step(dt);
      if (!onto_3d) target.bookStep(fs_, static_fine, dt, ts);
      const auto now = std::chrono::steady_clock::now();
      if (opt.progress && std::chrono::duration<double>(now - last).count() > 2.0) {
        last = now;
        std::fprintf(stderr, "early time (fine block, %.3g mm): t = %.4g us / %.4g us, step %lld, %zu cells\n", 1e3 * plan->block.cell_size_m,
                     fs_.time() * 1e6, plan->map_time_s * 1e6, static_cast<long long>(fs_.stats().steps), fg.interiorCells());
      }
    }
    const auto fine_tot = fs_.totals();
    // The block must have held everything until the map: what crossed its cut sides never reaches
    // the run mesh outside it (the books would still close, so this is checked on its own).
    const double charge_energy = deck.charge.mass_kg * rs->materials()[1].jwl.e0 / rs->materials()[1].jwl.rho0;
    const double leaked = std::abs(fine.symmetry * fine_tot.boundary_in);
    std::vector<std::string> early_warnings;
    if (leaked > 1e-3 * charge_energy)
      early_warnings.push_back(fmt::format("{:.3g} J ({:.2g}% of the charge's energy) crossed the fine block's cut sides before the map; "
                                           "raise early.block_margin_m or lower early.signal_speed_m_s's margin (early.map_time_s)",
                                           leaked, 100.0 * leaked / charge_energy));
    if (fs_.time() < plan->burn_time_s)
      early_warnings.push_back(fmt::format("the map time {:.3g} us comes before the burn ends ({:.3g} us): the run mesh finishes the burn",
                                           1e6 * fs_.time(), 1e6 * plan->burn_time_s));
    for (const auto& w : early_warnings) say("early time: warning: " + w);
    // (on ranks each maps onto its own slab; the fine block's books go to rank 0's, as a slab cut
    // from the whole keeps them on the slab holding cell 0)
    // A map that fails on one slab (a cell it cannot cover) stops every rank, said once.
    hydro::RezoneReport rz;
    std::string map_failed;
    try {
      rz = onto_3d ? hydro::mapAxisymmetricToQuarter(fs_, *rs) : hydro::mapNested(fs_, *rs);
    } catch (const InputError& e) {
      if (!split) throw;
      map_failed = fmt::format("rank {}: {}", ex->rank(), e.what());
    }
    if (split) {
      if (const std::string all = parallel::gatherText(*ex, map_failed); !all.empty()) throw InputError("rezone", all);
      // the counts summed; each cell's heat in the whole's order (its sum is one process's number)
      const auto counts = ex->gatherAll({static_cast<double>(rz.source_cells), static_cast<double>(rz.target_cells)});
      rz.heat_by_cell = ex->gatherAll(rz.heat_by_cell);
      rz.source_cells = rz.target_cells = 0;
      for (std::size_t r = 0; r + 2 <= counts.size(); r += 2) {
        rz.source_cells += static_cast<std::size_t>(counts[r]);
        rz.target_cells += static_cast<std::size_t>(counts[r + 1]);
      }
    }
    const auto& led = fs_.energyLedger();
    rs->startAt(fs_.time(), !split || ex->rank() == 0 ? led.scaled(to_run) : hydro::EnergyLedger{});
    // the initial energy as the fine run painted the block: the books then close over both runs
    st.energy_initial = totalsNow().total() - to_run * (fine_tot.total() - e_fine0);
    const double wall_early = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_early0).count();
    early_json = {{"enabled", true},
                  {"used", true},
                  {"cells_per_charge_height", cs.charge.height_m / plan->block.cell_size_m},
                  {"cell_size_m", plan->block.cell_size_m},
                  {"run_cells_per_fine_cell", plan->ratio},
                  {"block_m", {{"r_max", plan->block.r_max_m}, {"z_lo", plan->block.z_lo_m}, {"z_hi", plan->block.z_hi_m}}},
                  {"cells", fg.interiorCells()},
                  {"steps", fs_.stats().steps},
                  {"map_time_s", fs_.time()},
                  {"burn_time_s", plan->burn_time_s},
                  {"mapping", onto_3d ? "axisymmetric block onto the 3D quarter" : "nested"},
                  {"mapped_run_cells", rz.target_cells},
                  {"mapping_heat_J", cs.symmetry * rz.heatJ()},
                  {"boundary_flux_J", -fine.symmetry * fine_tot.boundary_in},
                  {"warnings", early_warnings},
                  {"wall_seconds", wall_early}};
    say(fmt::format("early time: mapped {} fine {} onto {} run cells at t = {:.3g} us ({:.1f} s); the kinetic energy one velocity per run cell "
                    "cannot hold, {:.3g} J, is heat",
                    rz.source_cells, onto_3d ? "ring-column pieces" : "cells", rz.target_cells, 1e6 * fs_.time(), wall_early, cs.symmetry * rz.heatJ()));
    st.next_history = rs->time();
    record();
  }

  if (ex) say(fmt::format("{} MPI ranks: this rank steps cells {} to {} of {} along axis 0", ex->size(), cs.slab.begin, cs.slab.end - 1, g.cells(0)));
  const long long steps_before = rs->stats().steps;
  const double t_step_from = rs->time();
  const auto t_step0 = std::chrono::steady_clock::now();
  // Output times at or before the run mesh's first state (the start, or an early time that ran on
  // its own block past them) are taken now, at that state's time, which the outputs record.
  for (; st.next_profile < deck.output.profile_times_s.size() && deck.output.profile_times_s[st.next_profile] <= rs->time(); ++st.next_profile) {
    if (rs->time() > 0.0)
      say(fmt::format("output.profile_times_s: {:g} s is within the early time; the profile is taken at the map time, {:.6g} s",
                      deck.output.profile_times_s[st.next_profile], rs->time()));
    st.profile_times.push_back(rs->time());
    st.profiles.push_back(profileNow());
  }
  for (; st.next_field < deck.output.field_times_s.size() && deck.output.field_times_s[st.next_field] <= rs->time(); ++st.next_field) {
    if (rs->time() > 0.0)
      say(fmt::format("output.field_times_s: {:g} s is within the early time; the snapshot is taken at the map time, {:.6g} s",
                      deck.output.field_times_s[st.next_field], rs->time()));
    writeField();
  }
  // The whole's state and the driver's at this step's end: one file whatever the number of ranks
  // (a restart may use any number). Writing it changes nothing in the run.
  // On ranks rank 0 assembles the whole for the file alone, on a whole built for it and then let go.
  auto writeCheckpoint = [&]() {
    std::optional<Case> whole;
    std::string failed;
    if (split && writer) {
      try {   // (a failure here still takes part in the gather below: the others are in it)
        whole = buildCase(deck, nullptr, nullptr, false);   // the cells come from the slabs: not painted
        moveMeshWithTarget(*whole->solver);
      } catch (const std::exception& e) {
        whole.reset();
        failed = e.what();
      }
    }
    try {   // (every rank is in the gather; one that fails says why below, with the others)
      if (whole)
        whole->solver->assemble(*rs, *ex);
      else if (split)
        hydro::Solver::sendForAssembly(*rs, *ex);
    } catch (const std::exception& e) {
      whole.reset();
      if (failed.empty()) failed = e.what();
    }
    if (writer && failed.empty()) {
      try {
        std::ostringstream payload;
        (whole ? *whole->solver : *rs).writeCheckpoint(payload);
        DriverState at = st;   // (a copy: the wall time so far goes into the file, not into the run's state)
        at.wall_before_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_wall0).count();
        putState(payload, at);
        io::writeCheckpointFile((out / "checkpoint.bin").string(), checkpointHeader(deck, rs->time()), std::move(payload).str());   // (moved out: the bytes are not held twice)
      } catch (const std::exception& e) {
        if (!ex) throw;
        failed = e.what();
      }
    }
    // every rank waits until the file is on disk (and learns if it failed): none goes on, or stops
    // and takes the others down, before it is
    if (ex)
      if (const std::string all = parallel::gatherText(*ex, failed); !all.empty())
        throw SharedFailure(fmt::format("could not write checkpoint.bin: {}", all));
    st.checkpoint_written = true;   // this run's own: a restart does not copy its input over it
    say(fmt::format("wrote checkpoint at t = {:.6g} s: {} (checkpoint.bin in the run folder when the run ends; restart from this path if "
                    "the run is interrupted before)",
                    rs->time(), (out / "checkpoint.bin").string()));
  };
  auto last_checkpoint = t_step0;
  while (rs->time() < t_end * (1.0 - 1e-12)) {
    // land exactly on output times, the checkpoint time and the end
    double stop = std::min(t_end, st.next_history + h_interval);
    if (st.next_profile < deck.output.profile_times_s.size()) stop = std::min(stop, deck.output.profile_times_s[st.next_profile]);
    if (st.next_field < deck.output.field_times_s.size()) stop = std::min(stop, deck.output.field_times_s[st.next_field]);
    if (opt.checkpoint_at_s > rs->time()) stop = std::min(stop, opt.checkpoint_at_s);
    // Once a step, every rank takes the same decision: a signal on any rank stops them all at this
    // step (so rank 0 is there to clean up), and rank 0's clock says when a periodic checkpoint is due.
    int sig = interrupted_by.load();
    bool due = opt.checkpoint_every_s > 0.0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint).count() >= opt.checkpoint_every_s;
    if (ex) {
      const auto all = ex->gatherAll({static_cast<double>(sig), due ? 1.0 : 0.0});
      for (std::size_t r = 0; r + 1 < all.size(); r += 2) sig = std::max(sig, static_cast<int>(all[r]));
      due = all[1] != 0.0;
    }
    if (sig != 0) {
      if (opt.checkpoint_every_s > 0.0) writeCheckpoint();   // the staging folder is kept for the restart
      stopIfInterrupted(rs->time(), sig, true);
    }
    if (due) {
      writeCheckpoint();
      last_checkpoint = std::chrono::steady_clock::now();
    }
    const double dt = rs->nextTimeStep(stop);
    rs->setBodyVelocity(target.wallVelocity(ts));
    rs->step(dt);
    // The target: what the blast gives it, per material kind. The load at rest (about zero now that
    // the sand carries the pore air's pressure; in the test the supports carry whatever is left) is
    // measured before any wave arrives and taken off.
    if (!ts.static_known) {   // measured on the run mesh at rest (before the early time, if any)
      ts.static_force = static_run;
      ts.static_known = true;
    }
    target.bookStep(*rs, ts.static_force, dt, ts);
    const double t = rs->time();
    if (t >= st.next_history + h_interval * (1.0 - 1e-9) || t >= t_end * (1.0 - 1e-12)) {
      st.next_history = t;
      record();
    }
    if (st.next_profile < deck.output.profile_times_s.size() && t >= deck.output.profile_times_s[st.next_profile] * (1.0 - 1e-12)) {
      st.profile_times.push_back(t);
      st.profiles.push_back(profileNow());
      ++st.next_profile;
    }
    if (st.next_field < deck.output.field_times_s.size() && t >= deck.output.field_times_s[st.next_field] * (1.0 - 1e-12)) {
      writeField();
      ++st.next_field;
    }
    if (opt.checkpoint_at_s > 0.0 && !st.checkpoint_written && t >= opt.checkpoint_at_s * (1.0 - 1e-12)) writeCheckpoint();
    const auto now = std::chrono::steady_clock::now();
    const bool show = opt.progress && std::chrono::duration<double>(now - last_progress).count() > 2.0;
    const bool tell = opt.log_progress_every_s > 0.0 && std::chrono::duration<double>(now - last_logged).count() > opt.log_progress_every_s;
    if (writer && (show || tell)) {
      const double wall = std::chrono::duration<double>(now - t_wall0).count();
      // by the stepping's own pace (a restart starts at the checkpoint's time, a mapped run after the early time)
      const double stepped = std::chrono::duration<double>(now - t_step0).count();
      const double left = t > t_step_from ? stepped * (t_end - t) / (t - t_step_from) : 0.0;
      if (show) {
        last_progress = now;
        std::fprintf(stderr, "t = %.4g ms / %.4g ms, step %lld, dt %.3g s, %zu cells, wall %.1f s, left ~%.0f s, impulse %.1f N s\n", t * 1e3,
                     t_end * 1e3, static_cast<long long>(rs->stats().steps), dt, g.interiorCells(), wall, left, ts.impulse);
      }
      if (tell) {
        last_logged = now;
        say(fmt::format("t = {:.4g} ms of {:.4g} ms, step {}, wall {:.1f} min, left ~{:.1f} min, impulse {:.1f} N s", t * 1e3, t_end * 1e3,
                        rs->stats().steps, wall / 60.0, left / 60.0, ts.impulse));
      }
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_wall0).count();
  const auto end_totals = totalsNow();   // the end state of the whole, for the books and the summary
  // Each rank's peak resident memory over the run, MB (the operating system's count; on ranks, in
  // rank order; gathered here, before rank 0 alone writes the folder).
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  const double peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;   // (Linux counts KiB)
  const std::vector<double> peaks = ex ? ex->gatherAll({peak_mb}) : std::vector<double>{peak_mb};

  RunResult res;
  res.impulse_Ns = ts.impulse;
  res.impulse_air_Ns = ts.impulse_kind[0];
  res.impulse_products_Ns = ts.impulse_kind[1];
  res.impulse_soil_Ns = ts.impulse_kind[2];
  res.impulse_near_Ns = ts.impulse_kind_near;
  res.peak_force_N = ts.peak_force;
  res.final_velocity_m_s = ts.v;
  res.displacement_m = ts.z - cs.plate.z_bottom_m;
  res.steps = rs->stats().steps;
  res.cells = g.interiorCells();
  res.wall_s = wall;
  res.wall_before_s = st.wall_before_s;

  // ---- the run folder
  for (const auto& c : history_columns) res.history_columns.push_back(c.first);
  res.history = st.history;
  for (int i = 0; i < g.cells(0); ++i) res.profile_r_m.push_back(g.centre(0, i));
  res.profile_times_s = st.profile_times;
  res.profiles_m = st.profiles;
  if (writer) {   // on MPI ranks, rank 0 writes the run folder
    io::writeFileAtomically(out / "history.csv", [&](std::ostream& os) {
      for (std::size_t i = 0; i < res.history_columns.size(); ++i) os << (i ? "," : "") << res.history_columns[i];
      os << "\n";
      for (const auto& r : st.history) os << csvRow(r);
    });
    io::writeFileAtomically(out / "gauges.csv", [&](std::ostream& os) {
      os << "t_s";
      for (const auto& p : deck.output.gauges_m) os << fmt::format(",p_Pa@r{:g}_z{:g}", p[0], p[1]);
      os << "\n";
      for (const auto& r : st.gauges) os << csvRow(r);
    });
    io::writeFileAtomically(out / "surface_profiles.csv", [&](std::ostream& os) {
      os << "r_m";
      for (const double t : st.profile_times) os << fmt::format(",z_m@t{:.6g}s", t);
      os << "\n";
      for (int i = 0; i < g.cells(0); ++i) {
        os << fmt::format("{:.6g}", g.centre(0, i));
        for (const auto& p : st.profiles) os << fmt::format(",{:.6g}", p[static_cast<std::size_t>(i)]);
        os << "\n";
      }
    });
    std::vector<std::pair<double, std::string>> snaps;
    for (std::size_t i = 0; i < st.field_times.size(); ++i)
      for (const char* kind : {".pvtr", ".vtr"})   // pieces joined by an index, or one file
        if (const std::string name = fmt::format("fields/field_{:04d}{}", i, kind); fs::exists(out / name)) {
          snaps.push_back({st.field_times[i], name});
          break;
        }
    io::writeFileAtomically(out / "fields.pvd", [&](std::ostream& os) { io::writePvd(os, snaps); });
    // A restart that writes no checkpoint of its own keeps the one it started from, so that the new
    // folder holds the whole run (and a checkpoint in the folder this run replaces, or in an
    // interrupted run's staging folder, is not lost). Copied at the end: an interrupted restart
    // holds no checkpoint of its own and keeps nothing staged.
    std::error_code same_ec;
    if (!opt.restart.empty() && !st.checkpoint_written && !fs::equivalent(opt.restart, out / "checkpoint.bin", same_ec))
      fs::copy_file(opt.restart, out / "checkpoint.bin", fs::copy_options::overwrite_existing);
  }
  nlohmann::json sum;
  sum["ejecta_version"] = build_info::version;
  sum["title"] = deck.title;
  sum["deck"] = deck.echo;
  sum["units"] = "SI: N s, N, m/s, m, s";
  sum["geometry"] = deck.geometry;
  sum["static_load_N"] = ts.static_force;
  sum["note"] = "impulse and force are the blast's: the load at rest (static_load_N) is taken off";
  sum["result"] = {{"impulse_Ns", res.impulse_Ns},
                   {"impulse_by_material_Ns", {{"air", res.impulse_air_Ns}, {"products", res.impulse_products_Ns}, {"soil", res.impulse_soil_Ns}}},
                   {"impulse_by_material_within_Ns", nearWallJson(res.impulse_near_Ns)},
                   {"peak_force_N", res.peak_force_N},
                   {"final_plate_velocity_m_s", res.final_velocity_m_s},
                   {"plate_displacement_m", res.displacement_m},
                   {"end_time_s", rs->time()}};
  const std::size_t nmat = static_cast<std::size_t>(rs->materialCount());
  {
    // The energy books: nothing enters or leaves but through the boundaries, the target and
    // gravity, so final = initial + inflow - work on the target + gravity's work, to round-off.
    double e_charge = 0.0;
    for (std::size_t k = 0; k < nmat; ++k)
      if (cs.material_kind[k] == "products") e_charge = deck.charge.mass_kg * rs->materials()[k].jwl.e0 / rs->materials()[k].jwl.rho0;
    const auto& tot = end_totals;
    const double f = cs.symmetry;
    const double e0 = f * st.energy_initial, e1 = f * tot.total();
    const double imbalance = e1 - f * tot.accounted(st.energy_initial);
    std::map<std::string, std::array<double, 2>> kinds;   // internal, kinetic by material kind
    for (std::size_t k = 0; k < nmat; ++k) {
      auto& e = kinds[cs.material_kind[k]];
      e[0] += f * tot.internal_by_material[k];
      e[1] += f * tot.kinetic_by_material[k];
    }
    nlohmann::json by_kind = nlohmann::json::object();
    for (const auto& [name, e] : kinds) by_kind[name] = {{"internal_J", e[0]}, {"kinetic_J", e[1]}};
    sum["energy"] = {{"charge_J", e_charge},
                     {"initial_J", e0},
                     {"final_J", e1},
                     {"work_on_target_J", f * tot.target_work},
                     {"boundary_flux_J", -f * tot.boundary_in},
                     {"gravity_work_J", f * tot.gravity_work},
                     {"imbalance_J", imbalance},
                     {"imbalance_fraction", e_charge > 0.0 ? imbalance / e_charge : imbalance / std::max(e0, 1e-300)},
                     {"by_material_J", by_kind},
                     {"note", "final = initial - boundary_flux (net outflow) - work_on_target + gravity_work; imbalance_fraction is over the charge's energy"}};
    res.energy_imbalance_fraction = sum["energy"]["imbalance_fraction"].get<double>();
    res.charge_energy_J = e_charge;
  }
  {
    // Global totals at the end, for the regression tier (tests/regression) and conservation checks:
    // each material's mass (what left through the outflow boundaries is gone) and the flow's
    // momentum along the vertical (the other components cancel by symmetry), for the whole charge.
    const auto& tot = end_totals;
    nlohmann::json mats = nlohmann::json::array();
    for (std::size_t k = 0; k < nmat; ++k)
      mats.push_back({{"name", rs->materials()[k].name}, {"kind", cs.material_kind[k]}, {"mass_kg", cs.symmetry * tot.mass[k]}});
    sum["totals"] = {{"materials", mats}, {"flow_momentum_vertical_Ns", cs.symmetry * tot.momentum[up]}};
    // Fragments folded into other materials (docs/solver.md, Fragments): books, summed pencil by
    // pencil (on MPI ranks slab by slab, so equal to round-off, where totals are equal to the bit).
    nlohmann::json folded = nlohmann::json::object();
    for (std::size_t k = 0; k < nmat; ++k) folded[rs->materials()[k].name] = cs.symmetry * tot.folded_mass[k];
    sum["fragments"] = {{"fold_below", deck.fragment_fold},
                        {"folded_mass_kg", folded},
                        {"note", "each material's mass given to other materials by folding its fragments, less what it took; "
                                 "totals.materials' mass_kg + folded_mass_kg = the initial mass less the net outflow (outflow.mass_kg)"}};
    // What left through the outflow sides, by material: books too (round-off under MPI, as above).
    nlohmann::json left = nlohmann::json::object();
    for (std::size_t k = 0; k < nmat; ++k) left[rs->materials()[k].name] = -cs.symmetry * tot.boundary_mass[k];
    sum["outflow"] = {{"mass_kg", left},
                      {"note", "each material's net mass out through the domain's outflow sides (and the early-time block's cut "
                               "sides, which nothing reaches by construction); negative: net inflow. The products that left no longer "
                               "load the target (docs/solver.md, Boundaries)"}};
  }
  sum["early_time"] = early_json;
  sum["mesh_warnings"] = mesh_warnings;   // the target's face outside the uniform core (targetOutsideCore)
  sum["charge"] = {{"radius_m", cs.charge.radius_m}, {"height_m", cs.charge.height_m}, {"z_top_m", cs.charge.z_top_m},
                   {"z_bottom_m", cs.charge.z_bottom_m}, {"detonation_z_m", cs.charge.detonation_m[1]}};
  sum["run"] = {{"cells", res.cells},
                {"steps", res.steps},
                {"wall_seconds", res.wall_s},
                {"cell_updates_per_second", res.wall_s > 0 ? static_cast<double>(res.steps - steps_before) * static_cast<double>(res.cells) / res.wall_s : 0.0},
                {"core_cell_size_m", deck.mesh.cell_size_m},
                {"solver_revision", hydro::kSolverRevision},
                {"ranks", opt.exchange ? opt.exchange->size() : 1},
                {"threads", threadCount()},
                {"peak_memory_mb_by_rank", peaks},
                {"restarted_from", opt.restart},
                {"wall_seconds_before_restart", st.wall_before_s}};
  if (writer) io::writeFileAtomically(out / "summary.json", sum.dump(2) + "\n");
  if (opt.plot && writer) {
    const fs::path data = io::temporarySibling(out / "plot_data.json");
    nlohmann::json pd;
    pd["title"] = deck.title;
    pd["history"] = st.history;
    pd["profile_times"] = st.profile_times;
    std::vector<double> rc;
    for (int i = 0; i < g.cells(0); ++i) rc.push_back(g.centre(0, i));
    pd["r"] = rc;
    nlohmann::json profs = nlohmann::json::array();
    for (const auto& p : st.profiles) {
      nlohmann::json row = nlohmann::json::array();
      for (const double v : p) row.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
      profs.push_back(row);
    }
    pd["profiles"] = profs;
    io::writeFileAtomically(data, pd.dump());
    const fs::path png_tmp = io::temporarySibling(out / "plots.png");
    try {
      io::runPlotScript("plot_run.py", data, png_tmp);
      fs::rename(png_tmp, out / "plots.png");
    } catch (...) {
      fs::remove(data);
      fs::remove(png_tmp);
      throw;
    }
    fs::remove(data);
  }
  return res;
}

bool processAlive(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

// The process id in a staging folder's name (prefix + digits), or 0 if the name is not one.
long stagePid(const std::string& name, const std::string& prefix) {
  if (name.rfind(prefix, 0) != 0) return 0;
  char* end = nullptr;
  const long pid = std::strtol(name.c_str() + prefix.size(), &end, 10);
  return end && *end == '\0' && pid > 0 ? pid : 0;
}

// Clears the staging folders that dead runs into the same place left and makes this run's: an
// empty string, or why it cannot (said as bad input, naming the folder).
std::string makeStage(const fs::path& parent, const std::string& prefix, const fs::path& stage, const std::string& out_dir,
                      const std::string& restart, const fs::path& out, const fs::path& old) {
  std::error_code ec;
  // The folder is replaced by renaming at the end: tried now, so that a folder that cannot be (a
  // mount point) is said before the run rather than after it.
  if (fs::exists(out, ec)) {
    fs::rename(out, old, ec);
    if (ec) return fmt::format("'{}' cannot be replaced ({}; a mount point?): name a folder inside it", out_dir, ec.message());
    fs::rename(old, out, ec);
    if (ec) return fmt::format("'{}' could not be put back from {}: {}", out_dir, old.string(), ec.message());
  }
  const fs::path input = restart.empty() ? fs::path() : fs::weakly_canonical(fs::path(restart), ec);
  if (fs::is_directory(parent, ec))
    for (const auto& entry : fs::directory_iterator(parent, ec)) {
      const long pid = stagePid(entry.path().filename().string(), prefix);
      if (pid == 0) continue;
      // an interrupted run's checkpoint that this run restarts from stays until the run has ended
      if (!input.empty() && fs::weakly_canonical(entry.path(), ec) == input.parent_path()) continue;
      if (!processAlive(pid)) fs::remove_all(entry.path(), ec);
    }
  if (!input.empty() && fs::weakly_canonical(stage, ec) == input.parent_path()) {
    // an interrupted run of the same process id (a container's) left the checkpoint this run
    // restarts from in the folder of this run's name: kept, and the rest cleared
    for (const auto& entry : fs::directory_iterator(stage, ec))
      if (entry.path().filename() != input.filename()) fs::remove_all(entry.path(), ec);
    return ec ? fmt::format("cannot clear the staging folder '{}': {}", stage.string(), ec.message()) : std::string();
  }
  fs::remove_all(stage, ec);
  ec.clear();
  fs::create_directories(parent, ec);
  if (!ec) fs::create_directory(stage, ec);
  return ec ? fmt::format("cannot create the run folder '{}': {}", out_dir, ec.message()) : std::string();
}

// The staging folders of runs into `out` are named by this prefix and the run's process id.
std::string stagingPrefix(const fs::path& out) {
  // (built by append: GCC 12 warns falsely, -Wrestrict, on "." + name + "...")
  std::string prefix(1, '.');
  prefix.append(out.filename().string()).append(".staging-");
  return prefix;
}

fs::path runFolder(const std::string& out_dir) {
  fs::path out = fs::path(out_dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();
  return out;
}

}  // namespace

InterruptScope::InterruptScope() {
  const std::lock_guard<std::mutex> g(interrupt_mutex);
  if (interrupt_scopes++ > 0) return;
  for (std::size_t i = 0; i < kSignals.size(); ++i) {
    struct sigaction now{};
    now.sa_handler = onInterrupt;
    sigemptyset(&now.sa_mask);
    ::sigaction(kSignals[i], &now, &interrupt_previous[i]);
    // a signal the run was started ignoring stays ignored (nohup's SIGHUP, a script's background job's SIGINT)
    if (interrupt_previous[i].sa_handler == SIG_IGN) ::sigaction(kSignals[i], &interrupt_previous[i], nullptr);
  }
}

InterruptScope::~InterruptScope() {
  const std::lock_guard<std::mutex> g(interrupt_mutex);
  if (--interrupt_scopes > 0) return;
  for (std::size_t i = 0; i < kSignals.size(); ++i) ::sigaction(kSignals[i], &interrupt_previous[i], nullptr);
}

int interruptedBy() { return interrupted_by.load(); }

namespace {
// The staging folders of runs into `out_dir` beside it, with the process id each names.
std::vector<std::pair<fs::path, long>> stagesOf(const std::string& out_dir) {
  const fs::path out = runFolder(out_dir);
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  const std::string prefix = stagingPrefix(out);
  std::vector<std::pair<fs::path, long>> stages;
  std::error_code ec;
  if (fs::is_directory(parent, ec))
    for (const auto& entry : fs::directory_iterator(parent, ec))
      if (const long pid = stagePid(entry.path().filename().string(), prefix); pid != 0) stages.emplace_back(entry.path(), pid);
  return stages;
}
}  // namespace

std::string leftCheckpoint(const std::string& out_dir) {
  std::error_code ec;
  fs::path best;
  fs::file_time_type newest{};
  for (const auto& [stage, pid] : stagesOf(out_dir)) {
    const fs::path file = stage / "checkpoint.bin";
    // (this process's id on a folder: a run of another process that had the same id, as in containers)
    if ((processAlive(pid) && pid != static_cast<long>(::getpid())) || !fs::is_regular_file(file, ec)) continue;
    const auto when = fs::last_write_time(file, ec);
    if (!ec && (best.empty() || when > newest)) {
      best = file;
      newest = when;
    }
  }
  return best.string();
}

void removeLeftStages(const std::string& out_dir) {
  std::error_code ec;
  for (const auto& [stage, pid] : stagesOf(out_dir))
    if (!processAlive(pid)) fs::remove_all(stage, ec);
}

std::string stagedRunName(const std::string& name) {
  const auto at = name.find(".staging-");
  if (name.size() < 2 || name[0] != '.' || at == std::string::npos) return {};
  const std::string run = name.substr(1, at - 1);
  return stagePid(name, stagingPrefix(fs::path(run))) != 0 ? run : std::string();
}

void checkCase(const Deck& deck) {
  const Case cs = buildCase(deck);
  checkSetUp(deck, cs, true);
}

// A run folder is written as one unit: the run writes into a hidden staging folder beside it
// (.NAME.staging-PID), which replaces the folder only when the run has ended well. A failed or
// interrupted run leaves the previous complete folder as it was (and a killed one's staging
// folder is removed by the next run into the same place).
RunResult runCase(const Deck& deck, const RunOptions& opt) {
  // the options first: a run refused for them clears no earlier run's staging folder
  if (opt.checkpoint_at_s > 0.0 && !(opt.checkpoint_at_s < deck.end_time_s))
    throw InputError("checkpoint-at", fmt::format("{:g} s is out of range; valid (0, end_time_s = {:g}) s", opt.checkpoint_at_s, deck.end_time_s));
  if (!(opt.checkpoint_every_s >= 0.0 && opt.checkpoint_every_s < 1e9))
    throw InputError("checkpoint-every", fmt::format("{:g} s is out of range; valid [0, 1e9) s (0: none)", opt.checkpoint_every_s));
  if (opt.checkpoint_every_s > 0.0 && opt.checkpoint_at_s > 0.0)
    throw InputError("checkpoint-every", "give --checkpoint-at or --checkpoint-every, not both (both write checkpoint.bin)");
  const InterruptScope guard;
  // On ranks the staging folder is named by rank 0's process: every rank writes its pieces of the
  // field snapshots there (rank 0 makes it and writes the rest).
  long stage_pid = static_cast<long>(::getpid());
  if (opt.exchange && opt.exchange->size() > 1) stage_pid = static_cast<long>(opt.exchange->gatherAll({static_cast<double>(stage_pid)})[0]);
  const fs::path out = runFolder(opt.out_dir);
  if (out.empty() || out.filename() == "." || out.filename() == "..")
    throw InputError("out", fmt::format("'{}' does not name a folder to write", opt.out_dir));
  if (fs::exists(out) && !fs::is_directory(out)) throw InputError("out", fmt::format("'{}' exists and is not a directory", opt.out_dir));
  // A run replaces its folder whole (by renaming): a folder of other files is not a run's to delete,
  // and the root cannot be renamed (nor a mount point: makeStage tries the rename).
  if (fs::is_directory(out) && !fs::is_empty(out) && !fs::exists(out / "summary.json"))
    throw InputError("out", fmt::format("'{}' holds files and is not an ejecta run folder (no summary.json); a run replaces its folder "
                                        "whole: name a new or empty folder, or an earlier run's",
                                        opt.out_dir));
  if (out == out.root_path()) throw InputError("out", fmt::format("'{}' is the root; a run replaces its folder whole: name a folder", opt.out_dir));
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  const std::string prefix = stagingPrefix(out);
  std::string old_name(1, '.');
  old_name.append(out.filename().string()).append(".old-").append(std::to_string(static_cast<long>(::getpid())));
  const fs::path stage = parent / (prefix + std::to_string(stage_pid));
  if (opt.exchange && opt.exchange->size() > 1) {
    // Only rank 0 clears and makes folders (a rank on another node would find rank 0's process
    // dead); every rank writes its pieces of the field snapshots into the staging folder, so every
    // rank must see it: checked before the run starts, bad input (exit 2) if one cannot.
    auto& ex = *opt.exchange;
    std::string made;
    if (ex.rank() == 0) made = makeStage(parent, prefix, stage, opt.out_dir, opt.restart, out, parent / old_name);
    if (const std::string why = parallel::gatherText(ex, made); !why.empty()) throw InputError("out", why);
    std::error_code ec;
    const bool sees = fs::is_directory(stage, ec);
    const std::string blind = parallel::gatherText(ex, sees ? std::string() : std::to_string(ex.rank()));
    if (!blind.empty()) {
      if (ex.rank() == 0) fs::remove_all(stage, ec);
      throw InputError("out", fmt::format("'{}' must be on a file system every rank sees: rank(s) {} cannot see {}", opt.out_dir, blind, stage.string()));
    }
    if (ex.rank() != 0) return runStaged(deck, opt, stage);
  } else if (const std::string why = makeStage(parent, prefix, stage, opt.out_dir, opt.restart, out, parent / old_name); !why.empty()) {
    throw InputError("out", why);
  }
  // A run that did not end well leaves what it staged only where that holds a checkpoint to
  // restart from (the log named its path; the next run into the same place clears it otherwise).
  auto dropStage = [&]() {
    std::error_code ec;
    if (fs::exists(stage / "checkpoint.bin", ec)) {
      if (opt.log) opt.log(fmt::format("kept {}: restart from its checkpoint.bin", stage.string()));
      return;
    }
    fs::remove_all(stage, ec);
  };
  // a signal that came while the run wrote its outputs: the run goes as any interrupted run
  auto interruptedWhileWriting = [&](int sig) {
    dropStage();
    return Interrupted(sig, fmt::format("interrupted by signal {} while writing the run folder", sig));
  };
  RunResult res;
  try {
    res = runStaged(deck, opt, stage);
  } catch (const Interrupted&) {
    dropStage();
    throw;
  } catch (...) {
    // (a signal may have failed the outputs: the plot script's child got it too)
    if (const int sig = interrupted_by.load(); sig != 0) throw interruptedWhileWriting(sig);
    dropStage();
    throw;
  }
  if (const int sig = interrupted_by.load(); sig != 0) throw interruptedWhileWriting(sig);   // after the last step
  std::error_code ec;
  if (fs::exists(out)) {
    const fs::path old = parent / old_name;
    fs::remove_all(old, ec);
    fs::rename(out, old);
    fs::rename(stage, out);
    fs::remove_all(old);
  } else {
    fs::rename(stage, out);
  }
  // the interrupted run's staging folder whose checkpoint this run restarted from (kept above):
  // the checkpoint is in the new folder now
  if (!opt.restart.empty()) {
    const fs::path from = fs::weakly_canonical(fs::path(opt.restart), ec).parent_path();
    const long pid = stagePid(from.filename().string(), prefix);
    // (not the folder of a run still going: its log named the checkpoint as it wrote it)
    if (!ec && pid > 0 && !processAlive(pid) && from.parent_path() == fs::weakly_canonical(parent, ec))
      fs::remove_all(from, ec);
  }
  return res;
}

}  // namespace ejecta::scenario

// Cell updates per second of the Eulerian solver: one material and three materials (air,
// detonation products, sand), in 2D and 3D. A "cell update" is one cell advanced one full time
// step (all directional sweeps). Beside each, the memory traffic a cell update needs at least
// (modelledBytes) and what that is per second, against the machine's STREAM triad measured here
// (BM_StreamTriad): the ratio says how far the step is from being bound by memory bandwidth.
// Run: scripts/bench.sh (writes bench/results/hydro.json).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "hydro/solver.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
using namespace ejecta;
using hydro::Vec3;

hydro::Solver makeCase(int dims, int n, bool three_materials, bool carry_all = false) {
  std::array<mesh::Axis, 3> ax{mesh::Axis::uniform(0.0, 1.0, n), mesh::Axis::uniform(0.0, 1.0, n),
                               dims == 3 ? mesh::Axis::uniform(0.0, 1.0, n) : mesh::Axis{}};
  hydro::SolverOptions o;
  o.carry_all_materials = carry_all;
  for (auto& b : o.boundary) b = {mesh::BoundaryKind::Reflect, mesh::BoundaryKind::Transmit};
  std::vector<materials::Material> mats{materials::air()};
  if (three_materials) {
    mats.push_back(materials::explosive("C4"));
    mats.push_back(materials::sand(materials::SandInputs::fromWetDensity(1370.0, 0.07)));
    o.detonation.push_back({{0.0, 0.3, 0.0}, 0.0});
  }
  hydro::Solver s(mesh::Grid(dims, mesh::Geometry::Cartesian, ax), mats, o);
  const double e_air = 101325.0 / (0.4 * 1.225);
  s.paint(0, [](const Vec3&) { return true; }, 1.225, e_air);
  if (three_materials) {
    // sand below y = 0.5, a charge buried in it
    s.paint(2, [](const Vec3& x) { return x[1] < 0.5; }, 1370.0, 0.0);
    s.paint(1, [](const Vec3& x) { return std::hypot(x[0], x[1] - 0.3, x[2]) < 0.1; }, 1601.0, 9.0e9 / 1601.0);
  } else {
    // a pressurised region: a blast that keeps the flow busy
    s.paint(0, [](const Vec3& x) { return std::hypot(x[0], x[1], x[2]) < 0.2; }, 10.0, 100.0 * e_air);
  }
  return s;
}

// The least main-memory traffic of one cell update (bytes), counting each cell array once per pass
// that must stream it (the pencils' scratch stays in cache): per sweep, the gather reads the
// velocity (3 doubles) and each material's fraction, density, energy, history (4), its interface
// weight (1, with several materials) and its stress (6, with strength), and the scatter writes the
// same less the weights; the interface weights read each fraction and write the weights; the time
// step reads the state once (3 + 4 per material); the stress update reads the state and writes the
// stress of the materials with strength.
double modelledBytes(int dims, int materials, int with_strength) {
  const double M = materials, St = with_strength, w = materials > 1 ? 1.0 : 0.0;
  const double sweep = (3.0 + M * (4.0 + w) + 6.0 * St) + (3.0 + 4.0 * M + 6.0 * St) + (materials > 1 ? 2.0 * M : 0.0);
  const double step_once = (3.0 + 4.0 * M) + (St > 0.0 ? (3.0 + 4.0 * M + 6.0 * St) + 6.0 * St : 0.0);
  return 8.0 * (dims * sweep + step_once);
}

void run(benchmark::State& state, int dims, bool three, bool carry_all = false) {
  const int n = static_cast<int>(state.range(0));
  auto s = makeCase(dims, n, three, carry_all);
  for (int i = 0; i < 3; ++i) s.step(0.2 * s.stableTimeStep());   // warm up
  double updates = 0.0;
  for (auto _ : state) {
    s.step(0.5 * s.stableTimeStep());
    updates += static_cast<double>(s.grid().interiorCells());
  }
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  state.counters["cell_updates_per_s"] = benchmark::Counter(updates, benchmark::Counter::kIsRate);
  state.counters["cell_updates_per_s_per_thread"] = benchmark::Counter(updates / threads, benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
  state.counters["cells"] = static_cast<double>(s.grid().interiorCells());
  const double bytes = modelledBytes(dims, three ? 3 : 1, three ? 1 : 0);
  state.counters["modelled_bytes_per_cell_update"] = bytes;
  state.counters["modelled_bytes_per_s"] = benchmark::Counter(updates * bytes, benchmark::Counter::kIsRate);
}

// STREAM's triad, a[i] = b[i] + q c[i], over arrays far larger than the caches, on the same threads
// as the solver: the machine's sustainable memory bandwidth (3 arrays x 8 bytes per element; the
// write-allocate read of a is not counted, as STREAM does not).
void BM_StreamTriad(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  const double q = 3.0;
  const auto len = static_cast<std::ptrdiff_t>(n);
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < len; ++i) a[static_cast<std::size_t>(i)] = b[static_cast<std::size_t>(i)] + q * c[static_cast<std::size_t>(i)];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.counters["bytes_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()) * 24.0 * static_cast<double>(n), benchmark::Counter::kIsRate);
}

void BM_Hydro2D_OneMaterial(benchmark::State& st) { run(st, 2, false); }
void BM_Hydro2D_ThreeMaterials(benchmark::State& st) { run(st, 2, true); }
void BM_Hydro3D_OneMaterial(benchmark::State& st) { run(st, 3, false); }
void BM_Hydro3D_ThreeMaterials(benchmark::State& st) { run(st, 3, true); }
// The same with every pencil carrying all three materials, as every sweep did before a pencil
// carried only the materials present in it (Pencil::mat; the same result to the bit): what that buys.
void BM_Hydro2D_ThreeMaterialsCarryAll(benchmark::State& st) { run(st, 2, true, true); }
void BM_Hydro3D_ThreeMaterialsCarryAll(benchmark::State& st) { run(st, 3, true, true); }
BENCHMARK(BM_Hydro2D_OneMaterial)->Arg(400)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro2D_ThreeMaterials)->Arg(400)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro3D_OneMaterial)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro3D_ThreeMaterials)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro2D_ThreeMaterialsCarryAll)->Arg(400)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro3D_ThreeMaterialsCarryAll)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_StreamTriad)->Arg(1 << 24)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);   // 3 x 128 MiB
}  // namespace

BENCHMARK_MAIN();

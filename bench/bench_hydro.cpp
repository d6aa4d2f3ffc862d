// Cell updates per second of the Eulerian solver: one material and three materials (air,
// detonation products, sand), in 2D and 3D. A "cell update" is one cell advanced one full time
// step (all directional sweeps). Run: scripts/bench.sh (writes bench/results/hydro.json).
#include <benchmark/benchmark.h>

#include <cmath>

#include "hydro/solver.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
using namespace ejecta;
using hydro::Vec3;

hydro::Solver makeCase(int dims, int n, bool three_materials) {
  std::array<mesh::Axis, 3> ax{mesh::Axis::uniform(0.0, 1.0, n), mesh::Axis::uniform(0.0, 1.0, n),
                               dims == 3 ? mesh::Axis::uniform(0.0, 1.0, n) : mesh::Axis{}};
  hydro::SolverOptions o;
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

void run(benchmark::State& state, int dims, bool three) {
  const int n = static_cast<int>(state.range(0));
  auto s = makeCase(dims, n, three);
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
}

void BM_Hydro2D_OneMaterial(benchmark::State& st) { run(st, 2, false); }
void BM_Hydro2D_ThreeMaterials(benchmark::State& st) { run(st, 2, true); }
void BM_Hydro3D_OneMaterial(benchmark::State& st) { run(st, 3, false); }
void BM_Hydro3D_ThreeMaterials(benchmark::State& st) { run(st, 3, true); }
BENCHMARK(BM_Hydro2D_OneMaterial)->Arg(400)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro2D_ThreeMaterials)->Arg(400)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro3D_OneMaterial)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Hydro3D_ThreeMaterials)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
}  // namespace

BENCHMARK_MAIN();

// Calls per second of the sand point evaluator, the hydrocode's innermost material call.
// Run: scripts/bench.sh (writes bench/results/*.json).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "materials/sand_model.hpp"

namespace {
void BM_SandPointEos(benchmark::State& state) {
  const ejecta::materials::SandModel model(ejecta::materials::SandInputs::fromWetDensity(1370.0, 0.07));
  const ejecta::materials::SandPointEos eos(model);
  const std::size_t n = 1 << 16;
  std::vector<double> x(n), x_max(n), p(n), k(n);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.01, 0.6);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = u(rng);
    x_max[i] = std::max(0.0, x[i] + (i % 3 == 0 ? 0.05 : 0.0));   // a third unloading
  }
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto r = eos.evaluate(x[i], x_max[i]);
      p[i] = r.pressure;
      k[i] = r.bulk_modulus;
    }
    benchmark::DoNotOptimize(p.data());
    benchmark::DoNotOptimize(k.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n));
}
BENCHMARK(BM_SandPointEos);

void BM_SandModelConstruction(benchmark::State& state) {
  for (auto _ : state) {
    const ejecta::materials::SandModel model(ejecta::materials::SandInputs::fromWetDensity(1370.0, 0.07));
    const ejecta::materials::SandPointEos eos(model);
    benchmark::DoNotOptimize(&eos);
  }
}
BENCHMARK(BM_SandModelConstruction)->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();

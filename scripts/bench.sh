#!/usr/bin/env bash
# Builds (release) and runs the benchmarks; figures go to bench/results/ as JSON:
#   sand_eos.json  calls per second of the sand point evaluator
#   hydro.json     cell updates per second of the solver (1 and 3 materials, 2D and 3D)
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh release
mkdir -p bench/results
./build/release/bench/ejecta_bench --benchmark_out=bench/results/sand_eos.json --benchmark_out_format=json "$@"
./build/release/bench/ejecta_bench_hydro --benchmark_out=bench/results/hydro.json --benchmark_out_format=json "$@"

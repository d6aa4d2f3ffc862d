#!/usr/bin/env bash
# Builds (release) and runs the benchmarks; figures go to bench/results/ as JSON.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh release
mkdir -p bench/results
./build/release/bench/ejecta_bench --benchmark_out=bench/results/sand_eos.json --benchmark_out_format=json "$@"

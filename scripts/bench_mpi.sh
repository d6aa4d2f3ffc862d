#!/usr/bin/env bash
# Strong and weak scaling of `ejecta run` over MPI ranks and OpenMP threads on this machine; figures
# to bench/results/mpi_scaling.json (cell updates per second of the run loop, from summary.json).
#   strong: EMI flat plate at 7%, 10 mm, to 3 ms: 1 process x 1 and 2 threads, 2 ranks x 1 thread,
#           4 ranks x 1 thread (more ranks than cores: oversubscribed, labelled so)
#   weak:   the cells per rank held about constant: 1 rank at 14 mm, 2 ranks at 10 mm
#   memory: each rank's peak resident memory (summary.json run.peak_memory_mb_by_rank) on a mesh that
#           dominates it: the 3D 120 degree V-plate at 12 mm (497,664 cells) to 0.2 ms, 1, 2 and 4 ranks
set -euo pipefail
cd "$(dirname "$0")/.."
[[ -x build/release/ejecta ]] || ./scripts/build.sh release
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cores=$(nproc)
rows=()
one() {   # label ranks threads cell_mm [deck end_time_s]
  local label=$1 n=$2 t=$3 h=$4 deck=${5:-emi-flat-7} end=${6:-0.003} out="$work/$1"
  if [[ $n -eq 1 ]]; then
    OMP_NUM_THREADS=$t build/release/ejecta run "$deck" --cell-size "$h" --set end_time_s="$end" --threads "$t" --no-plot --quiet --out "$out" > /dev/null
  else
    OMP_NUM_THREADS=$t mpirun -np "$n" --oversubscribe build/release/ejecta run "$deck" --cell-size "$h" --set end_time_s="$end" --threads "$t" \
      --no-plot --quiet --out "$out" > /dev/null
  fi
  rows+=("$(python3 - "$out/summary.json" "$label" "$n" "$t" "$h" "$cores" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["run"]
n, t, cores = int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[6])
print(json.dumps({"case": sys.argv[2], "ranks": n, "threads_per_rank": t, "cell_mm": float(sys.argv[5]), "cells": s["cells"], "steps": s["steps"],
                  "wall_s": s["wall_seconds"], "cell_updates_per_s": s["cell_updates_per_second"],
                  "per_rank": s["cell_updates_per_second"] / n, "oversubscribed": n * t > cores,
                  "peak_memory_mb_by_rank": s.get("peak_memory_mb_by_rank")}))
PY
)")
  echo "${rows[-1]}"
}
one strong-1x1 1 1 10
one strong-1x2 1 2 10
one strong-2x1 2 1 10
one strong-4x1-oversubscribed 4 1 10
one weak-1x1-14mm 1 1 14
one weak-2x1-10mm 2 1 10
one memory-v120-12mm-1x1 1 1 12 emi-v120-7 0.0002
one memory-v120-12mm-2x1 2 1 12 emi-v120-7 0.0002
one memory-v120-12mm-4x1-oversubscribed 4 1 12 emi-v120-7 0.0002
mkdir -p bench/results
printf '{"machine_cores": %s, "date": "%s", "runs": [%s]}\n' "$cores" "$(date -u +%FT%TZ)" "$(IFS=,; echo "${rows[*]}")" | python3 -m json.tool > bench/results/mpi_scaling.json
echo "wrote bench/results/mpi_scaling.json"

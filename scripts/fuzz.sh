#!/usr/bin/env bash
# Builds the libFuzzer targets (build/fuzz: clang, ASan + UBSan) and fuzzes each for a bounded
# time, the targets side by side; fails on any crash, sanitizer report, leak, hang or blow-up of
# memory. scripts/test.sh runs it last. First every committed and generated input runs once (the
# regression check), then the fuzzing.
#   scripts/fuzz.sh [SECONDS]   seconds per target (default 60)
#   FUZZ_RUNS=N                 N executions per target instead of a time (docs/testing.md's figures)
#   FUZZ_TARGETS="deck"         a subset of the targets (deck, checkpoint)
# A failing input is left in build/fuzz/artifacts/TARGET/; rerun it with build/fuzz/fuzz_TARGET FILE.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
read -r -a targets <<< "${FUZZ_TARGETS:-deck checkpoint}"
./scripts/setup.sh
cmake --preset fuzz -G Ninja >/dev/null
cmake --build --preset fuzz -j "$(nproc)"

# Reports name files and lines (addr2line: llvm-symbolizer is not installed).
export ASAN_OPTIONS=external_symbolizer_path=/usr/bin/addr2line
export UBSAN_OPTIONS=print_stacktrace=1:external_symbolizer_path=/usr/bin/addr2line
ctest --test-dir build/fuzz --output-on-failure -L fuzz

# Seeds and dictionaries: committed ones, and those build/fuzz generates from the code (make_fuzz_inputs).
declare -A seeds=(
  [deck]="tests/fuzz/corpus/deck decks"
  [checkpoint]="tests/fuzz/corpus/checkpoint build/fuzz/tests/fuzz/seeds/checkpoint"
)
declare -A dicts=([deck]=build/fuzz/tests/fuzz/deck.dict [checkpoint]=tests/fuzz/checkpoint.dict)
if [[ -n ${FUZZ_RUNS:-} ]]; then budget=(-runs="$FUZZ_RUNS"); else budget=(-max_total_time="$seconds"); fi
declare -A pids
for t in "${targets[@]}"; do
  [[ -n ${seeds[$t]:-} ]] || { echo "fuzz.sh: no target '$t' (deck, checkpoint)" >&2; exit 2; }
  # The first folder collects what the fuzzer finds (kept between local runs); the seeds are read only.
  mkdir -p "build/fuzz/corpus/$t" "build/fuzz/artifacts/$t"
  # shellcheck disable=SC2086  # the seed folders are words
  "build/fuzz/fuzz_$t" "${budget[@]}" -timeout=10 -rss_limit_mb=2048 -dict="${dicts[$t]}" \
    -artifact_prefix="build/fuzz/artifacts/$t/" -print_final_stats=1 "build/fuzz/corpus/$t" ${seeds[$t]} \
    > "build/fuzz/fuzz_$t.log" 2>&1 &
  pids[$t]=$!
done
final_stat() { sed -n "s/^stat::$2: *//p" "$1"; }
failed=0
for t in "${targets[@]}"; do
  log="build/fuzz/fuzz_$t.log"
  if wait "${pids[$t]}"; then
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1)
    echo "fuzz $t: $(final_stat "$log" number_of_executed_units) executions, $(final_stat "$log" average_exec_per_sec) exec/s, $cov, 0 crashes"
  else
    failed=1
    echo "fuzz $t: FAILED (log $log, input in build/fuzz/artifacts/$t/):" >&2
    grep -v -E '^#[0-9]+' "$log" | tail -60 >&2
  fi
done
exit "$failed"

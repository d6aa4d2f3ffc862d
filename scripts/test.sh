#!/usr/bin/env bash
# Sets up, builds and runs every test: once optimised with warnings as errors, once under
# AddressSanitizer + UndefinedBehaviorSanitizer; then fuzzes the deck and checkpoint readers for
# a minute each (scripts/fuzz.sh). This is the command CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
jobs=$(nproc)
./scripts/build.sh release
ctest --test-dir build/release --output-on-failure -j "$jobs" -LE long
./scripts/build.sh sanitize
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/sanitize --output-on-failure -j "$jobs" -LE 'long|nosan'
# the release build is tuned for this machine (-march=native), the sanitizer build is portable:
# the regression cases must give the same totals to the bit in both
python3 tests/regression/regression.py --same-bits build/release/tests/regression build/sanitize/tests/regression
./scripts/fuzz.sh 60

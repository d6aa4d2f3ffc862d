#!/usr/bin/env bash
# Sets up, builds and runs ejecta's main job on its built-in default case: the EMI flat plate over
# 0.674 kg Comp B at 5 cm in sand at 7% moisture, 10 mm cells, to 10 ms (about a minute on 2
# cores). Results in out/run/emi-flat-7/; also writes the EMI 7% sand's LS-DYNA cards to out/soil/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh release
mkdir -p out/soil
./build/release/ejecta soil --lsdyna out/soil/emi7.k --plot out/soil/emi7.png --json out/soil/emi7.json > /dev/null
./build/release/ejecta run "$@"

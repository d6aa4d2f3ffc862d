#!/usr/bin/env bash
# Sets up, builds and runs ejecta's main job on its built-in default case.
# Today that is the sand model of the EMI 7% soil: summary on screen, cards, curves and plot in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh release
mkdir -p out/soil
./build/release/ejecta soil --lsdyna out/soil/emi7.k --csv out/soil/emi7 --plot out/soil/emi7.png \
  --json out/soil/emi7.json "$@"

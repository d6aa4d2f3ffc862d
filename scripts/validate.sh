#!/usr/bin/env bash
# Regenerates the full validation report in docs/validation/ (validation.md with its figures,
# validation.html, validation.json): sets up, builds, and runs `ejecta validate --full`: about 40
# min on 2 cores for the 2D studies (38.9 min with 2 jobs on revision 15), and the three 3D V-plate runs at 10 mm on top (docs/validate.md
# gives their time; `--only mesh,moisture,field,share,sensitivity,dres` leaves them out). The case runs stay in out/validate-full/cases, so an interrupted run continues
# where it stopped (--reuse takes every finished case whose deck is unchanged). Extra arguments go
# to ejecta validate (for example --jobs 1 or --threads 4). Exit code 4: the report is written but
# a check failed (see its Checks table).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh release
exec ./build/release/ejecta validate --full --out docs/validation --work out/validate-full/cases --reuse "$@"

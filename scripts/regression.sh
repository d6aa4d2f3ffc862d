#!/usr/bin/env bash
# The regression tier (docs/testing.md): runs the short cases of tests/regression/regression.py
# with a built ejecta and compares their global totals with tests/regression/totals.json.
#   scripts/regression.sh                      compare (build/release)
#   scripts/regression.sh --update             store this build's totals: only for a physics change
#                                              that is meant; commit the file with the change
#   scripts/regression.sh --build build/sanitize --case emi-flat-22-40mm
# Other arguments go to regression.py (--case, --work, --threads).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/release
args=()
while (($#)); do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
[[ -x "$build/ejecta" ]] || ./scripts/build.sh "$(basename "$build")"
exec python3 tests/regression/regression.py --ejecta "$build/ejecta" "${args[@]}"

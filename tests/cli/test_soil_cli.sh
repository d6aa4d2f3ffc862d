#!/usr/bin/env bash
# `ejecta soil` as a user runs it: outputs written, bad input refused with a one-line error that
# names the input, exit code 2, and no file written or left behind.
ejecta=$1
source "$(dirname "$0")/lib.sh"

"$ejecta" soil --dry-density 1280 --moisture 7% --lsdyna x.k --plot x.png --json > j.json
check "good run exits 0" "[[ $? -eq 0 ]]"
check "keyword file written" "[[ -s x.k ]] && head -1 x.k | grep -q '^\*KEYWORD' && tail -1 x.k | grep -q '^\*END'"
check "png written" "[[ \$(head -c 4 x.png | od -An -c | tr -d ' ') == '211PNG' ]]"
check "json to stdout parses" "python3 -c 'import json,sys; d=json.load(open(\"j.json\")); assert d[\"state\"][\"dry_density_kg_m3\"]==1280' "
"$ejecta" soil --wet-density 1670 --moisture 0.22 --csv curves --json s.json --units t-mm-s --lsdyna t.k > /dev/null
check "csv dir written" "[[ -s curves/loading_curve.csv && -s curves/yield_curve.csv && -s curves/summary.csv && -s s.json ]]"
# a trailing separator names the folder itself (the README's example: --csv vimf/)
"$ejecta" soil --dry-density 1490 --saturation 100% --csv vimf/ > /dev/null
check "csv dir with a trailing slash written" "[[ -s vimf/loading_curve.csv && -s vimf/summary.csv ]]"
check "t-mm-s density" "grep -q 'Units: t-mm-s' t.k"
check "no temporary files left" "[[ -z \$(find . -name '.*tmp*') ]]"

bad() {   # name, expected field, args...
  local name=$1 field=$2; shift 2
  rm -rf out; mkdir out
  local err
  err=$("$ejecta" soil "$@" --lsdyna out/b.k --plot out/b.png --json out/b.json --csv out/c 2>&1 >/dev/null)
  local rc=$?
  check "$name: exit 2 (got $rc)" "[[ $rc -eq 2 ]]"
  check "$name: one line naming $field ('$err')" "[[ \$(printf '%s\n' \"\$err\" | wc -l) -eq 1 ]] && grep -q -- '$field' <<< \"\$err\""
  check "$name: nothing written" "[[ -z \$(ls -A out) ]]"
}
bad "saturation over 100%" "moisture" --dry-density 1670 --moisture 30%
bad "density at grain density" "dry-density" --dry-density 2650 --moisture 0
bad "density above grain density" "dry-density" --dry-density 2800 --moisture 0
bad "negative density" "dry-density" --dry-density=-5 --moisture 7%
bad "non-numeric density" "dry-density" --dry-density abc --moisture 7%
bad "negative moisture" "moisture" --dry-density 1280 --moisture=-3%
bad "ambiguous moisture" "moisture" --dry-density 1280 --moisture 7
bad "unknown flag" "--frobnicate" --frobnicate 3
bad "unknown water set" "water-eos" --water-eos seawater
bad "unknown units" "units" --units furlongs
bad "saturation over 100% via --saturation" "saturation" --dry-density 1490 --saturation 120%
bad "grains lighter than the baseline's compacted sand" "grain-density" --grain-density 1300
bad "vanishing dry density" "dry-density" --dry-density 1e-300 --moisture 0
bad "porosity over 0.7" "dry-density" --dry-density 0.1 --moisture 0
bad "energy term gamma out of range" "thermal-gamma" --thermal-gamma 9
bad "shear modulus cap out of range" "shear-modulus-cap" --shear-modulus-cap 5e10

# Output paths that are not regular files are refused, never replaced (device, FIFO, symbolic link).
mknod -m 666 dev c 1 3 2>/dev/null && {
  "$ejecta" soil --lsdyna dev > /dev/null 2>&1
  check "device node: exit 2 and still a device" "[[ $? -eq 2 && -c dev ]]"
}
mkfifo fifo
"$ejecta" soil --lsdyna fifo > /dev/null 2>&1
check "FIFO: exit 2 and still a FIFO" "[[ $? -eq 2 && -p fifo ]]"
ln -s target.k link
"$ejecta" soil --lsdyna link > /dev/null 2>&1
check "symbolic link: exit 2, the link kept, nothing written through it" "[[ $? -eq 2 && -L link && ! -e target.k ]]"

# A failing plot (no matplotlib found) must leave none of the other outputs behind.
rm -rf out; mkdir out
EJECTA_PYTHON=/bin/false "$ejecta" soil --lsdyna out/b.k --plot out/b.png --json out/b.json --csv out/c >/dev/null 2>&1
rc=$?
check "failed plot: non-zero exit" "[[ $rc -ne 0 ]]"
check "failed plot: nothing left behind" "[[ -z \$(ls -A out) ]]"

"$ejecta" --help > /dev/null
check "help exits 0" "[[ $? -eq 0 ]]"
finish

#!/usr/bin/env bash
# `ejecta verify` as a user runs it: a small subset writes its table, CSV, JSON and plot; bad
# options are refused with exit code 2 and leave nothing behind.
ejecta=$1
source "$(dirname "$0")/lib.sh"

"$ejecta" verify --only sand-piston steel-precursor --out v > out.txt 2> err.txt
rc=$?
check "subset runs and passes (rc $rc)" "[[ $rc -eq 0 ]]"
check "table printed" "grep -q 'steel-precursor' out.txt"
check "csv, json, png written" "[[ -s v/verify.csv && -s v/verify.json && -s v/verify.png && -s v/verify.txt ]]"
check "json parses" "python3 -c 'import json; d=json.load(open(\"v/verify.json\")); assert d[\"all_passed\"] is True and len(d[\"rows\"]) > 3'"
check "profiles written" "ls v/profiles/sand-piston_*.csv > /dev/null"
check "no temporary files left" "[[ -z \$(find . -name '.*tmp*') ]]"

err=$("$ejecta" verify --only bogus --out w 2>&1 >/dev/null)
rc=$?
check "unknown problem: exit 2 (got $rc)" "[[ $rc -eq 2 ]]"
check "unknown problem: names --only ('$err')" "grep -q -- '--only' <<< \"\$err\""
check "unknown problem: nothing written" "[[ ! -e w ]]"
err=$("$ejecta" verify --bogus 2>&1 >/dev/null)
check "unknown flag: exit 2" "[[ $? -eq 2 ]]"
err=$("$ejecta" verify --threads -1 --out w 2>&1 >/dev/null)
check "negative threads: exit 2" "[[ $? -eq 2 ]] && grep -q threads <<< \"\$err\""

finish

#!/usr/bin/env bash
# `ejecta validate` as a user runs it. Mode "errors": bad options exit 2 naming the option and write
# nothing. Mode "run": the V-plate study at the quick level writes the report (Markdown + figure,
# self-contained HTML, JSON) and a second run with --reuse takes every case from the first.
ejecta=$1
mode=$2
source "$(dirname "$0")/lib.sh"

if [[ $mode == errors ]]; then
  err=$("$ejecta" validate --quick --full --out v 2>&1 >/dev/null)
  check "--quick with --full: exit 2" "[[ $? -eq 2 ]] && grep -q -- '--full' <<< \"\$err\""
  err=$("$ejecta" validate --only mesh,bogus --out v 2>&1 >/dev/null)
  rc=$?
  check "unknown study: exit 2 naming --only (rc $rc: $err)" "[[ $rc -eq 2 ]] && grep -q 'only' <<< \"\$err\" && grep -q bogus <<< \"\$err\""
  err=$("$ejecta" validate --jobs -1 --out v 2>&1 >/dev/null)
  check "negative jobs: exit 2" "[[ $? -eq 2 ]] && grep -q jobs <<< \"\$err\""
  err=$("$ejecta" validate --checkpoint-every -1 --out v 2>&1 >/dev/null)
  check "negative checkpoint interval: exit 2" "[[ $? -eq 2 ]] && grep -q checkpoint-every <<< \"\$err\""
  touch afile
  err=$("$ejecta" validate --only dres --out afile 2>&1 >/dev/null)
  check "output folder is a file: exit 2" "[[ $? -eq 2 ]] && grep -q afile <<< \"\$err\""
  check "nothing written" "[[ ! -e v ]]"
  "$ejecta" validate --help | grep -q -- '--reuse'
  check "help lists --reuse" "[[ $? -eq 0 ]]"
else
  # the V-plate study: its four cases are the quick level's cheapest (3D quarter and 2D, 60 mm)
  "$ejecta" validate --quick --only vplates --out v > v.txt 2> v.err
  rc=$?
  check "validate exits 0 (rc $rc: $(tail -1 v.err))" "[[ $rc -eq 0 ]]"
  for f in validation.md validation.html validation.json vplates.png cases/emi-v90-7/history.csv cases/emi-v120-7/validation_case.json; do
    check "v/$f written" "[[ -s v/$f ]]"
  done
  check "HTML carries the figure inline" "grep -q 'data:image/png;base64,' v/validation.html && ! grep -q 'src=\"vplates.png\"' v/validation.html"
  check "Markdown links the figure" "grep -q '](vplates.png)' v/validation.md"
  check "the report names the solver revision" "grep -Eq '^ejecta .* \\(solver revision [0-9]+\\), level' v/validation.md"
  check "JSON: four cases, the 90 degree V last" "python3 -c 'import json; d=json.load(open(\"v/validation.json\")); assert len(d[\"cases\"]) == 4; rows=d[\"sections\"][0][\"table\"][\"rows\"]; assert rows[-1][0].startswith(\"90 degree\"), rows[-1]'"
  check "no temporary files left" "[[ -z \$(find . -name '.*tmp*') ]]"
  "$ejecta" validate --quick --only vplates --out v --reuse > w.txt 2> w.err
  check "reuse: exit 0, every case reused" "[[ $? -eq 0 ]] && grep -q '4 reused' w.err"
fi
finish

#!/usr/bin/env bash
# `ejecta validate` as a user runs it. Mode "errors": bad options exit 2 naming the option and write
# nothing. Mode "run": the DRES study at the quick level writes the report (Markdown + figure,
# self-contained HTML, JSON) and a second run with --reuse takes both cases from the first.
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
  touch afile
  err=$("$ejecta" validate --only dres --out afile 2>&1 >/dev/null)
  check "output folder is a file: exit 2" "[[ $? -eq 2 ]] && grep -q afile <<< \"\$err\""
  check "nothing written" "[[ ! -e v ]]"
  "$ejecta" validate --help | grep -q -- '--reuse'
  check "help lists --reuse" "[[ $? -eq 0 ]]"
else
  "$ejecta" validate --quick --only dres --out v > v.txt 2> v.err
  rc=$?
  check "validate exits 0 (rc $rc: $(tail -1 v.err))" "[[ $rc -eq 0 ]]"
  for f in validation.md validation.html validation.json dres.png cases/dres-3cm/history.csv cases/dres-8cm/validation_case.json; do
    check "v/$f written" "[[ -s v/$f ]]"
  done
  check "HTML carries the figure inline" "grep -q 'data:image/png;base64,' v/validation.html && ! grep -q 'src=\"dres.png\"' v/validation.html"
  check "Markdown links the figure" "grep -q '](dres.png)' v/validation.md"
  check "JSON: two cases, a break-out time" "python3 -c 'import json; d=json.load(open(\"v/validation.json\")); assert len(d[\"cases\"]) == 2; rows=d[\"sections\"][0][\"table\"][\"rows\"]; assert rows[-1][0].startswith(\"break-out\"), rows[-1]'"
  check "no temporary files left" "[[ -z \$(find . -name '.*tmp*') ]]"
  "$ejecta" validate --quick --only dres --out v --reuse > w.txt 2> w.err
  check "reuse: exit 0, both cases reused" "[[ $? -eq 0 ]] && grep -q '2 reused' w.err"
fi
finish

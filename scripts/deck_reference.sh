#!/usr/bin/env bash
# Regenerates (or, with --check, verifies) the deck reference in docs/run.md from the key table
# (`ejecta run --help-deck markdown`). Usage: scripts/deck_reference.sh [--check] [EJECTA]
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
[[ ${1:-} == --check ]] && { check=1; shift; }
ejecta=${1:-build/release/ejecta}
doc=docs/run.md
begin='<!-- deck-reference:begin (generated: scripts/deck_reference.sh) -->'
end='<!-- deck-reference:end -->'
table=$("$ejecta" run --help-deck markdown)
new=$(awk -v b="$begin" -v e="$end" -v t="$table" '
  $0 == b { print; print t; skip = 1; next }
  $0 == e { skip = 0 }
  !skip { print }' "$doc")
if ((check)); then
  if [[ "$new" != "$(cat "$doc")" ]]; then
    echo "docs/run.md's deck reference is out of date: run scripts/deck_reference.sh" >&2
    diff <(cat "$doc") <(printf '%s\n' "$new") >&2 || true
    exit 1
  fi
  echo "docs/run.md's deck reference is current"
else
  printf '%s\n' "$new" > "$doc.tmp" && mv "$doc.tmp" "$doc"
fi

# Shared by the command-line tests: a scratch folder removed on exit, and `check NAME CONDITION`
# that counts passes and reports failures. Each test ends with `finish`.
set -uo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail=0
pass=0
check() { if eval "$2"; then pass=$((pass + 1)); else echo "FAIL: $1"; fail=$((fail + 1)); fi; }
finish() {
  echo "$pass passed, $fail failed"
  [[ $fail -eq 0 ]]
}

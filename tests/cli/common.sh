# Sourced by the tests/cli scripts: strict mode, a scratch folder $work removed on exit, fail()
# and logged(), so that each script states only what it checks.
set -eu
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# logged LOG WHAT CMD...: runs CMD with its output in LOG; if it fails, prints LOG and fails WHAT.
logged() {
  local log=$1 what=$2
  shift 2
  "$@" > "$log" 2>&1 || { cat "$log"; fail "$what"; }
}

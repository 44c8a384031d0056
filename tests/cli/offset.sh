#!/usr/bin/env bash
# cdbench offset end to end on a small mesh: exit code, manifest, byte-identical outputs from a
# fresh directory, reuse on a re-run, and a clear error for a bad level list.
set -eu
cdbench=$1
mesh=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
args=(offset "$mesh" --levels=-50%,-150%,0,0.2 --tolerance 5e-3 --mesher-radius 0.05)
"$cdbench" "${args[@]}" -o "$work/a" > "$work/a.txt"
grep -q '"status": "certified"' "$work/a/manifest.json"
grep -q '"status": "empty"' "$work/a/manifest.json"
grep -q '"status": "original"' "$work/a/manifest.json"
[ "$(ls "$work/a"/*.off | wc -l)" -eq 2 ] || { echo "expected 2 OFF files"; exit 1; }
"$cdbench" "${args[@]}" -o "$work/b" > "$work/b.txt"
for f in manifest.json $(cd "$work/a" && ls *.off); do
  cmp "$work/a/$f" "$work/b/$f" || { echo "not byte-identical: $f"; exit 1; }
done
"$cdbench" "${args[@]}" -o "$work/a" > "$work/c.txt"
[ "$(grep -c '(reused)' "$work/c.txt")" -eq 4 ] || { echo "expected 4 reused levels"; cat "$work/c.txt"; exit 1; }
set +e
"$cdbench" offset "$mesh" --levels=-50%,abc -o "$work/d" > /dev/null 2> "$work/err.txt"
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "'abc' is not a number" "$work/err.txt" || { echo "bad --levels: exit $rc"; cat "$work/err.txt"; exit 1; }
echo "offset cli: ok"

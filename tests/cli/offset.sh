#!/usr/bin/env bash
# cdbench offset end to end on a small mesh: exit code, manifest, byte-identical outputs from a
# fresh directory, reuse on a re-run, and a clear error for a bad level list.
. "$(dirname "$0")/common.sh"
cdbench=$1
mesh=$2
args=(offset "$mesh" --levels=-50%,-150%,0,0.2 --tolerance 5e-3 --mesher-radius 0.05)
# The generator of larger meshes of the same shape: 4x the faces, validated, written.
"$cdbench" subdivide "$mesh" "$work/fine.off" --steps 1 > "$work/s.txt"
grep -q "verdict: valid closed solid, written" "$work/s.txt" || { cat "$work/s.txt"; exit 1; }
[ "$(sed -n 2p "$work/fine.off" | cut -d' ' -f2)" -eq $(( 4 * $(sed -n 2p "$mesh" | cut -d' ' -f2) )) ] || { echo "subdivide: expected 4x the faces"; exit 1; }
set +e
"$cdbench" subdivide "$mesh" "$work/fine.stl" > "$work/s.txt" 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "must be an .off file" "$work/s.txt" || { echo "subdivide to .stl: exit $rc"; exit 1; }
# An output that cannot be written is refused before the work (no "input:" line), and named.
set +e
"$cdbench" subdivide "$mesh" "$work/no/such/dir/fine.off" > "$work/s.txt" 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "no/such/dir/fine.off" "$work/s.txt" && ! grep -q "^input:" "$work/s.txt" ||
  { cat "$work/s.txt"; echo "subdivide to a missing directory: exit $rc"; exit 1; }
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
# Mesh_3 on all threads: a different candidate, so nothing is reused from the Surface_mesher run;
# certified all the same, and the mesher is recorded.
"$cdbench" "${args[@]}" --parallel-mesher -o "$work/a" > "$work/p.txt"
[ "$(grep -c "(reused)" "$work/p.txt")" -eq 0 ] || { echo "--parallel-mesher: nothing may be reused"; cat "$work/p.txt"; exit 1; }
grep -q '"mesher": "mesh3-parallel"' "$work/a/manifest.json" || { echo "--parallel-mesher: mesher not recorded"; exit 1; }
grep -q '"status": "certified"' "$work/a/manifest.json"
set +e
"$cdbench" offset "$mesh" --levels=-50%,abc -o "$work/d" > /dev/null 2> "$work/err.txt"
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "'abc' is not a number" "$work/err.txt" || { echo "bad --levels: exit $rc"; cat "$work/err.txt"; exit 1; }
echo "offset cli: ok"

#!/usr/bin/env bash
# cdbench repair / wrap end to end: exact union of touching parts, the wrap fallback, the distance
# report (JSON beside the output), refusal with --no-wrap, and FCL's test meshes where present
# (../shared/meshes/fcl beside the checkout), checked independently by validation/check_repair
# when it is built.
. "$(dirname "$0")/common.sh"
cdbench=$1
data=$2
check_repair=${3:-}

# Two unit cubes as separate blocks touching along x = 1 (the soup a CAD export gives).
python3 - "$work/two.off" <<'PY'
import sys
def box(x0):
    V = [(x0 + x, y, z) for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
    F = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    return V, F
V, F = [], []
for x0 in (0.0, 1.0):
    v, f = box(x0)
    F += [tuple(i + len(V) for i in t) for t in f]
    V += v
with open(sys.argv[1], "w") as o:
    o.write("OFF\n%d %d 0\n" % (len(V), len(F)))
    o.writelines("%r %r %r\n" % v for v in V)
    o.writelines("3 %d %d %d\n" % t for t in F)
PY
"$cdbench" repair "$work/two.off" "$work/two-r.off" > "$work/out.txt" || fail "repair exit $?"
grep -q "method:   exact-union of 2 closed parts" "$work/out.txt" || { cat "$work/out.txt"; fail "expected the exact union"; }
"$cdbench" check "$work/two-r.off" --no-max-penetration | grep -q "volume:             2 " || fail "union volume"
python3 - "$work/two-r.repair.json" <<'PY' || fail "distance report"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["method"] == "exact-union", j["method"]
# Every output point lies on the input; the shared wall is 0.5 from the union's surface.
assert j["output_to_input"]["lo"] == 0 and j["output_to_input"]["hi"] < 1e-8, j["output_to_input"]
assert j["input_to_output"]["lo"] <= 0.5 <= j["input_to_output"]["hi"], j["input_to_output"]
PY

# An open surface: no exact repair; --no-wrap refuses and writes nothing, the default wraps.
set +e
"$cdbench" repair "$data/bad/open_surface.off" "$work/open-r.off" --no-wrap > "$work/out.txt" 2>&1
rc=$?
set -e
[ "$rc" -eq 1 ] || fail "--no-wrap on an open surface: exit $rc"
[ ! -e "$work/open-r.off" ] || fail "--no-wrap wrote an output"
# An output that cannot be written is refused before the repair, and named.
set +e
"$cdbench" repair "$data/bad/open_surface.off" "$work/no/such/dir/r.off" > "$work/out.txt" 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "no/such/dir/r.off" "$work/out.txt" && ! grep -q "^method:" "$work/out.txt" ||
  { cat "$work/out.txt"; fail "repair to a missing directory: exit $rc"; }
"$cdbench" repair "$data/bad/open_surface.off" "$work/open-r.off" --relative-alpha 10 > "$work/out.txt"
grep -q "method:   alpha-wrap" "$work/out.txt" || fail "expected the wrap"
"$cdbench" check "$work/open-r.off" --no-max-penetration > /dev/null || fail "wrap output invalid"

# wrap reports its distance too.
"$cdbench" wrap "$data/bad/two_cubes_edge.off" "$work/w.off" --relative-alpha 10 > "$work/out.txt"
grep -q "distance: input -> output in \[" "$work/out.txt" || fail "wrap distance line"
[ -s "$work/w.repair.json" ] || fail "wrap JSON"

# A wrap far larger than --max-faces is refused before the work, naming the limit; nothing written.
set +e
"$cdbench" wrap "$data/bad/two_cubes_edge.off" "$work/big.off" --relative-alpha 1e5 > "$work/out.txt" 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q -- "--max-faces" "$work/out.txt" || { cat "$work/out.txt"; fail "a too fine wrap: exit $rc"; }
[ ! -e "$work/big.off" ] || fail "a refused wrap wrote an output"

fcl="$(cd "$(dirname "$0")/../.." && pwd)/../shared/meshes/fcl"
if [ -f "$fcl/rob.obj" ] && [ -f "$fcl/env.obj" ]; then
  for m in rob env; do
    "$cdbench" repair "$fcl/$m.obj" "$work/$m.off" > "$work/$m.txt" || fail "$m: exit $?"
    "$cdbench" check "$work/$m.off" --no-max-penetration > /dev/null || fail "$m: output not a valid solid"
    if [ -n "$check_repair" ] && [ -x "$check_repair" ]; then
      "$check_repair" "$fcl/$m.obj" "$work/$m.off" "$work/$m.repair.json" 1e-4 || fail "$m: CGAL disagrees"
    fi
  done
else
  echo "FCL test meshes not found at $fcl: skipped them"
fi
echo "repair: all checks passed"

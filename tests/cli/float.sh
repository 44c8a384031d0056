#!/usr/bin/env bash
# The float pipeline and validate end to end: `poses --pipeline float` on the sphere (statuses,
# manifest, byte-identical for 1 and 2 threads), `validate` of it (the issue's CSV columns, a
# table, no wrong sign on a smooth mesh) and of a certified pose set of the same
# request (zero wrong signs and missed contacts), several grids (error against voxel size), and
# bad options. With validation/check_poses (third argument), validate's intervals are confirmed
# independently.
. "$(dirname "$0")/common.sh"
cdbench=$1
meshes=$2
check_poses=${3:-}
mesh="$meshes/sphere.off"
req=(--levels=-20%,0,10% --directions 5 --orientations 2)

"$cdbench" poses "$mesh" "${req[@]}" --pipeline float --grid 64 --keep-offsets --threads 2 -o "$work/f64" > "$work/out.txt" 2>&1 ||
  { cat "$work/out.txt"; fail "float poses"; }
"$cdbench" poses "$mesh" "${req[@]}" --pipeline float --grid 64 --keep-offsets --threads 1 -o "$work/f64-1" > /dev/null 2>&1 || fail "float poses, 1 thread"
cmp -s "$work/f64/poses.csv" "$work/f64-1/poses.csv" || fail "float poses.csv differs between 1 and 2 threads"
rows=$(tail -n +2 "$work/f64/poses.csv" | wc -l)
[ "$rows" -eq 30 ] || fail "expected 30 rows, found $rows"
float_rows=$(grep -c ',uncertified:float,' "$work/f64/poses.csv" || true)
[ "$float_rows" -ge 24 ] || fail "only $float_rows rows placed by the float pipeline"
python3 - "$work/f64/poseset.json" <<'PY' || fail "poseset.json of the float pipeline"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["pipeline"] == "float", j["pipeline"]
assert j["grid"]["voxel"] > 0 and j["grid"]["grid_option"] == 64
assert all(l["float_offset"]["faces"] > 0 for l in j["levels"])
assert j["timings"]["grid"] > 0 and j["timings"]["poses"] > 0
PY

"$cdbench" poses "$mesh" "${req[@]}" --pipeline float --grid 32 -o "$work/f32" > /dev/null 2>&1 || fail "float poses, grid 32"
"$cdbench" poses "$mesh" "${req[@]}" --threads 2 -o "$work/cert" > /dev/null 2>&1 || fail "certified poses"

"$cdbench" validate "$work/f64" --reference "$work/cert" --offsets -o "$work/v64" > "$work/v.txt" 2>&1 ||
  { cat "$work/v.txt"; fail "validate"; }
grep -q "wrong" "$work/v.txt" || fail "no table printed"
head -1 "$work/v64/validation.csv" | grep -qx "pose,level,target,clearance_lo,clearance_hi,error,wrong_sign,missed_contact,past_first_contact" ||
  fail "validation.csv header"
[ "$(tail -n +2 "$work/v64/validation.csv" | wc -l)" -eq 30 ] || fail "validation.csv rows"
python3 - "$work/v64/validation.json" <<'PY' || fail "validation.json of the float set"
import json, sys
j = json.load(open(sys.argv[1]))
for l in j["levels"]:
    assert l["certified"] == l["placed"], l
    assert l["wrong_sign"] == 0, l                      # a smooth mesh
    assert l["error_over_max_penetration"]["max_abs"] < 0.05, l
    assert l["missed_contact_undecided"] == 0, l        # with a reference, everything is decided
    if l["target"] != 0:
        assert l["float_offset"]["band"] > 0, l
    assert l["seconds_per_pose"]["pipeline"] > 0 and l["seconds_per_pose"]["reference_certified"] > 0, l
PY
if [ -n "$check_poses" ]; then
  "$check_poses" "$work/f64" --poses 10 --grid 6 --intervals "$work/v64/validation.csv" > "$work/c.txt" 2>&1 ||
    { cat "$work/c.txt"; fail "validate's intervals not confirmed by check_poses"; }
fi
# A certified pose set validates with no wrong sign, no missed contact and errors within the tolerance.
"$cdbench" validate "$work/cert" -o "$work/vcert" > /dev/null 2>&1 || fail "validate of the certified set"
python3 - "$work/vcert/validation.json" <<'PY' || fail "validation of the certified set"
import json, sys
j = json.load(open(sys.argv[1]))
for l in j["levels"]:
    assert l["wrong_sign"] == 0 and l["missed_contact"] == 0, l
    assert l["target"] < 0 or l["past_first_contact"]["poses"] == 0, l
    assert l["error"]["max_abs"] <= 2 * j["tolerance"], (l, j["tolerance"])
PY
# Several grids: one directory each and the convergence plot's data.
"$cdbench" validate "$work/f32" "$work/f64" -o "$work/vall" > /dev/null 2>&1 || fail "validate of two grids"
[ -f "$work/vall/0-f32/validation.csv" ] && [ -f "$work/vall/1-f64/validation.csv" ] || fail "per-set outputs"
[ -f "$work/vall/error_vs_voxel.csv" ] || fail "error_vs_voxel.csv"
if command -v gnuplot > /dev/null; then
  [ -s "$work/vall/error_vs_voxel.png" ] && [ -s "$work/vall/error_distribution_0.svg" ] || fail "plots"
fi

# Bad options: exit 2 with the option named.
set +e
"$cdbench" validate "$work/f32" --offsets -o "$work/bad" > "$work/e.txt" 2>&1
[ $? -eq 2 ] && grep -q -- "--keep-offsets" "$work/e.txt" || fail "validate --offsets of a set without kept offsets"
"$cdbench" poses "$mesh" "${req[@]}" --pipeline float --resume -o "$work/bad" > "$work/e.txt" 2>&1
[ $? -eq 2 ] && grep -q -- "--resume" "$work/e.txt" || fail "--pipeline float --resume must be refused"
"$cdbench" poses "$mesh" "${req[@]}" --pipeline float --grid 3 -o "$work/bad" > "$work/e.txt" 2>&1
[ $? -eq 2 ] && grep -q -- "--grid" "$work/e.txt" || fail "--grid 3 must be refused"
"$cdbench" validate "$work" -o "$work/bad" > "$work/e.txt" 2>&1
[ $? -eq 2 ] && grep -q "poseset.json" "$work/e.txt" || fail "validate of a folder without a pose set"
# The OpenVDB module (lib/floatpipe/grid_module.h) missing or not a module: exit 3, the path and
# the reason named, nothing written. The certified pipeline never loads it.
CDBENCH_GRID_MODULE="$work/none.so" "$cdbench" poses "$mesh" "${req[@]}" --pipeline float -o "$work/nomod" > "$work/e.txt" 2>&1
[ $? -eq 3 ] && grep -q "OpenVDB module" "$work/e.txt" && grep -q "$work/none.so" "$work/e.txt" && [ ! -e "$work/nomod" ] ||
  { cat "$work/e.txt"; fail "a missing grid module must be named, exit 3, nothing written"; }
echo "not a library" > "$work/fake.so"
CDBENCH_GRID_MODULE="$work/fake.so" "$cdbench" poses "$mesh" "${req[@]}" --pipeline float -o "$work/nomod" > "$work/e.txt" 2>&1
[ $? -eq 3 ] && grep -q "fake.so" "$work/e.txt" && [ ! -e "$work/nomod" ] || { cat "$work/e.txt"; fail "a file that is not a module"; }
CDBENCH_GRID_MODULE="$work/none.so" "$cdbench" poses "$mesh" --levels=0 --directions 2 --orientations 1 -o "$work/cmod" > "$work/e.txt" 2>&1
[ $? -eq 0 ] || { cat "$work/e.txt"; fail "the certified pipeline must not need the grid module"; }
set -e
echo "float pipeline and validate: ok"

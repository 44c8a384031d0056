#!/usr/bin/env bash
# The independent checker (validation/check_poses) itself: its pruned search finds the same sampled
# minimum as the literal evaluation of every sample (--exhaustive), bit for bit, on penetrating,
# touching and separated poses of a torus and of a box moved against a torus; it confirms the
# certificates of a pose set, sampled evenly over its levels, and refuses one whose intervals were
# moved (exit 1, NOT CONFIRMED); usage errors exit 2.
. "$(dirname "$0")/common.sh"
cdbench=$1
meshes=$2
check=$3
logged "$work/self.txt" "pose set of the torus" \
  "$cdbench" poses "$meshes/torus.off" --levels=-30%,0,7% --directions 6 --orientations 2 -o "$work/self"
"$cdbench" poses "$meshes/torus.off" --mover "$meshes/box.off" --levels=-20%,0,3% --directions 6 --orientations 2 \
  -o "$work/box" > "$work/box.txt" 2>&1 || { cat "$work/box.txt"; fail "pose set of the box against the torus"; }
for set in self box; do
  "$check" "$work/$set" --poses 36 --grid 5 --verbose > "$work/$set.pruned" || { cat "$work/$set.pruned"; fail "$set: not confirmed"; }
  "$check" "$work/$set" --poses 36 --grid 5 --verbose --exhaustive > "$work/$set.all" ||
    { cat "$work/$set.all"; fail "$set: not confirmed (exhaustive)"; }
  grep -o "sampled minimum [^,]*" "$work/$set.pruned" > "$work/$set.m1"
  grep -o "sampled minimum [^,]*" "$work/$set.all" > "$work/$set.m2"
  [ "$(wc -l < "$work/$set.m1")" -eq 36 ] || fail "$set: expected 36 checked poses"
  cmp -s "$work/$set.m1" "$work/$set.m2" || { diff "$work/$set.m1" "$work/$set.m2"; fail "$set: pruned and exhaustive minima differ"; }
done
# The pruned search must skip triangles (else it would be the exhaustive one under another name).
python3 - "$work/self.pruned" <<'PY' || fail "the pruned search evaluated every triangle of every pose"
import re, sys
counts = [tuple(map(int, m)) for m in re.findall(r"\((\d+) of (\d+) triangles", open(sys.argv[1]).read())]
sys.exit(0 if any(a < b for a, b in counts) else 1)
PY
# A sample of 12 of the box's 36 poses: 4 from each of its 3 levels (a stride of 3 over the file
# would check level 0 only).
"$check" "$work/box" --poses 12 --grid 3 --verbose > "$work/twelve.txt" || { cat "$work/twelve.txt"; fail "sample of 12"; }
for level in 0 1 2; do
  [ "$(grep -c "^pose [0-9]* level $level:" "$work/twelve.txt")" -eq 4 ] || { cat "$work/twelve.txt"; fail "sample of 12: level $level"; }
done
# Move every certificate up by 1 % of the bounding box's diagonal: far outside the sampled enclosure.
python3 - "$work/self/poses.csv" "$work/self/poseset.json" <<'PY'
import csv, json, sys
diag = json.load(open(sys.argv[2]))["certification"]["diagonal"]
rows = list(csv.reader(open(sys.argv[1])))
lo, hi = rows[0].index("clearance_lo"), rows[0].index("clearance_hi")
for r in rows[1:]:
    if r[lo] not in ("nan", "NaN", ""):
        r[lo] = repr(float(r[lo]) + 0.01 * diag)
        r[hi] = repr(float(r[hi]) + 0.01 * diag)
csv.writer(open(sys.argv[1], "w", newline=""), lineterminator="\n").writerows(rows)
PY
set +e
"$check" "$work/self" --poses 6 --grid 5 > "$work/moved.txt" 2>&1
rc=$?
set -e
[ $rc -eq 1 ] || { cat "$work/moved.txt"; fail "moved certificates: exit $rc, expected 1"; }
[ "$(grep -c "NOT CONFIRMED" "$work/moved.txt")" -eq 6 ] || { cat "$work/moved.txt"; fail "moved certificates confirmed"; }
grep -q "0 of 6 sampled certificates confirmed" "$work/moved.txt" || { cat "$work/moved.txt"; fail "summary line"; }
# Usage errors: exit 2 with a message naming the option.
set +e
"$check" "$work/box" --grid > "$work/usage.txt" 2>&1; rc1=$?
"$check" "$work/box" --pose 3 >> "$work/usage.txt" 2>&1; rc2=$?
set -e
[ $rc1 -eq 2 ] && [ $rc2 -eq 2 ] || { cat "$work/usage.txt"; fail "usage errors: exit $rc1, $rc2, expected 2"; }
grep -q -- "--grid: needs a value" "$work/usage.txt" && grep -q -- "--pose: unknown option" "$work/usage.txt" ||
  { cat "$work/usage.txt"; fail "usage error messages"; }
echo "check_poses: all checks passed"

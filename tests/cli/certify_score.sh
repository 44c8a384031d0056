#!/usr/bin/env bash
# cdbench certify and score end to end: poses written "by another tool" (random, near-contact,
# deeply penetrating; both header forms), bad rows named by line, an interrupted run resumed to a
# byte-identical poses.csv, the bundle accepted by bench and score, and deliberately wrong answers
# scored as exactly those false positives and negatives. With validation/check_poses (third
# argument), sampled certificates are confirmed independently.
. "$(dirname "$0")/common.sh"
cdbench=$1
meshes=$2
check_poses=${3:-}

# Fixed: the sphere (radius 1 about the origin); mover: the box. Random rotations; translations
# from deep inside to well apart.
python3 - "$work" <<'PY'
import math, random, sys
random.seed(5)
w = sys.argv[1]
def quat():
    q = [random.gauss(0, 1) for _ in range(4)]
    s = math.sqrt(sum(x * x for x in q))
    return [x / s for x in q]
def mat(q):
    a, b, c, d = q
    return [1 - 2 * (c * c + d * d), 2 * (b * c - a * d), 2 * (b * d + a * c),
            2 * (b * c + a * d), 1 - 2 * (b * b + d * d), 2 * (c * d - a * b),
            2 * (b * d - a * c), 2 * (c * d + a * b), 1 - 2 * (b * b + c * c)]
with open(w + "/matrix.csv", "w") as m, open(w + "/quat.csv", "w") as q:
    m.write("pose,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz,source\n")
    q.write("qw,qx,qy,qz,tx,ty,tz,pose,target\n")
    for i in range(24):
        u = quat()
        r = [0.0, 0.3, 1.2, 1.45, 1.5, 2.5][i % 6]  # deep, penetrating, near contact, apart
        d = [random.gauss(0, 1) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in d))
        t = [r * x / n for x in d]
        m.write("%d,%s,%s,gen\n" % (100 + 2 * i, ",".join(repr(v) for v in mat(u)), ",".join(repr(v) for v in t)))
        q.write("%s,%s,%d,%s\n" % (",".join(repr(v) for v in u), ",".join(repr(v) for v in t), i, ["-0.5", "0.1"][i % 2]))
PY

"$cdbench" certify "$meshes/sphere.off" "$work/matrix.csv" --mover "$meshes/box.off" --tolerance 1e-4 -o "$work/m" > "$work/m.txt" \
  || { cat "$work/m.txt"; fail "certify (matrix form) exit $?"; }
grep -q "24 poses, rotation matrices" "$work/m.txt" || fail "matrix form summary"
grep -q "ignored columns: source" "$work/m.txt" || fail "ignored column not named"
"$cdbench" certify "$meshes/sphere.off" "$work/quat.csv" --mover "$meshes/box.off" --tolerance 1e-4 -o "$work/q" > "$work/q.txt" \
  || fail "certify (quaternion form) exit $?"
python3 - "$work" <<'PY' || fail "bundle contents"
import csv, json, sys
w = sys.argv[1]
m = list(csv.DictReader(open(w + "/m/poses.csv")))
q = list(csv.DictReader(open(w + "/q/poses.csv")))
assert [int(r["pose"]) for r in m] == [100 + 2 * i for i in range(24)], "poses sorted by id"
assert all(r["status"] == "certified" for r in m + q)
lo = [float(r["clearance_lo"]) for r in m]
hi = [float(r["clearance_hi"]) for r in m]
assert all(a <= b for a, b in zip(lo, hi))
assert sum(h < 0 for h in hi) >= 8 and sum(l > 0 for l in lo) >= 4, (lo, hi)
# The same rotations and translations in both files: the intervals agree (the matrices differ by
# the quaternion conversion's rounding only, far below the interval widths' scale).
for a, b in zip(m, q):
    assert abs(float(a["clearance_lo"]) - float(b["clearance_lo"])) < 1e-9, (a, b)
meta = json.load(open(w + "/q/poseset.json"))
assert [l["spec"] for l in meta["levels"]] == ["-0.5", "0.1"], meta["levels"]
assert {r["target"] for r in q} == {"-0.5", "0.10000000000000001"}
PY

# Bad rows: the error names the file and line; nothing is written.
printf 'pose,qw,qx,qy,qz,tx,ty,tz\n0,1,0,0,0,0,0,0\n1,1,0,0,0,0,inf,0\n' > "$work/bad.csv"
set +e
"$cdbench" certify "$meshes/sphere.off" "$work/bad.csv" -o "$work/bad" > "$work/bad.txt" 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] || fail "bad row: exit $rc"
grep -q "bad.csv:3: column ty is not finite" "$work/bad.txt" || { cat "$work/bad.txt"; fail "bad row message"; }
[ ! -e "$work/bad/poses.csv" ] || fail "bad input wrote poses.csv"

# Interrupted after 5 journal appends (as by a kill), then resumed: byte-identical poses.csv.
set +e
CDBENCH_TEST_KILL_AFTER_APPENDS=5 "$cdbench" certify "$meshes/sphere.off" "$work/matrix.csv" --mover "$meshes/box.off" --tolerance 1e-4 \
  --threads 1 -o "$work/r" > /dev/null 2>&1
set -e
[ -s "$work/r/certify.journal" ] || fail "no journal after the interruption"
[ ! -e "$work/r/poses.csv" ] || fail "an interrupted run left poses.csv"
set +e
"$cdbench" certify "$meshes/sphere.off" "$work/matrix.csv" --mover "$meshes/box.off" --tolerance 1e-4 -o "$work/r" > /dev/null 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] || fail "a journal without --resume: exit $rc"
"$cdbench" certify "$meshes/sphere.off" "$work/matrix.csv" --mover "$meshes/box.off" --tolerance 1e-4 -o "$work/r" --resume > "$work/r.txt"
grep -q "resumed:         5 poses" "$work/r.txt" || { cat "$work/r.txt"; fail "resume count"; }
cmp "$work/m/poses.csv" "$work/r/poses.csv" || fail "resumed poses.csv differs"
[ ! -e "$work/r/certify.journal" ] || fail "journal left after completion"

# bench accepts the bundle; score of its own answers agrees; deliberately wrong answers are
# scored exactly.
"$cdbench" bench "$work/m" --impl obb --repeat 1 -o "$work/b" > /dev/null || fail "bench on a certify bundle"
# Its poses have no targets: the plots place the levels by their order (gnuplot refused the NaN
# percentages until session 59).
if command -v gnuplot > /dev/null 2>&1; then
  logged "$work/plot.txt" "plot of poses without targets" "$cdbench" plot "$work/b"
  [ -s "$work/b/time_vs_level.png" ] && [ -s "$work/b/bv_tests_vs_level.svg" ] || fail "plot files missing"
  # validate has no errors to plot there: its figure says so instead of gnuplot failing.
  logged "$work/v.txt" "validate of poses without targets" "$cdbench" validate "$work/m" -o "$work/v"
  [ -s "$work/v/error_distribution_0.png" ] || fail "validate's figure missing"
fi
python3 - "$work" <<'PY'
import csv, sys
w = sys.argv[1]
rows = list(csv.DictReader(open(w + "/b/results.csv")))
fp = fn = 0
with open(w + "/answers.csv", "w") as out:
    out.write("pose,collides,time_ns\n")
    for k, r in enumerate(rows):
        c = int(r["collides"])
        if k % 4 == 0:
            c = 1 - c
            lo, hi = float(r["clearance_lo"]), float(r["clearance_hi"])
            fp += lo > 0 and c == 1
            fn += hi < 0 and c == 0
        if k == 3:
            continue  # a missing answer
        out.write("%s,%d,%s\n" % (r["pose"], c, r["time_ns"]))
    out.write("5,1,10\n")  # not a pose of the set
open(w + "/expected.txt", "w").write("%d %d\n" % (fp, fn))
PY
"$cdbench" score "$work/m" "$work/answers.csv" -o "$work/s" > "$work/s.txt" || fail "score exit $?"
python3 - "$work" <<'PY' || { cat "$work/s.txt"; fail "score verdicts"; }
import json, sys
w = sys.argv[1]
fp, fn = map(int, open(w + "/expected.txt").read().split())
s = json.load(open(w + "/s/summary.json"))
lv = s["implementations"][0]["levels"]
assert sum(l["false_positives"] for l in lv) == fp, (fp, lv)
assert sum(l["false_negatives"] for l in lv) == fn, (fn, lv)
assert s["unknown_poses"] == [5] and len(s["missing_poses"]) == 1, s
PY
grep -q "unknown:  1 answers" "$work/s.txt" || fail "unknown poses not reported"
grep -q "missing:  1 placed poses" "$work/s.txt" || fail "missing poses not reported"
set +e
"$cdbench" score "$work/m" "$work/answers.csv" -o "$work/s2" --strict > /dev/null 2>&1
rc=$?
set -e
[ "$rc" -eq 1 ] || fail "--strict with wrong answers: exit $rc"

# The numpy example of doc/validate-your-library.md (bounding boxes never miss a collision).
example="$(dirname "$0")/../../scripts/score_bounding_boxes.py"
for py in python3 /usr/bin/python3; do
  if "$py" -c "import numpy" > /dev/null 2>&1; then
    "$py" "$example" "$work/m" "$work/py" "$cdbench" > "$work/py.txt" || { cat "$work/py.txt"; fail "numpy example"; }
    grep -q "numpy-aabb: 24 poses, [0-9]* false positives, 0 missed collisions" "$work/py.txt" || fail "numpy example output"
    break
  fi
done

# A thin tube (48 sides, wall 0.01, 4 long: its walls are slivers) apart from the sphere: the
# pair search proves each interval a few ulps wide. It runs on the sweep trees, whose oriented boxes
# fit the slivers; on the box trees it ran out of its budget (16 pairs per triangle) and the
# branch and bound's interval, about the tolerance wide, was written (session 92).
python3 - "$work" <<'PY'
import math, random, sys
w = sys.argv[1]
random.seed(7)
n, length, radii = 48, 4.0, (0.1, 0.09)
V = [(r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n), z)
     for k in range(n) for r in radii for z in (0.0, length)]
at = lambda k, outer, top: 4 * (k % n) + (0 if outer else 2) + (1 if top else 0)
F = []
for k in range(n):
    a0, a1, b0, b1 = at(k, 1, 0), at(k + 1, 1, 0), at(k, 1, 1), at(k + 1, 1, 1)
    c0, c1, d0, d1 = at(k, 0, 0), at(k + 1, 0, 0), at(k, 0, 1), at(k + 1, 0, 1)
    F += [(a0, a1, b1), (a0, b1, b0), (c0, d1, c1), (c0, d0, d1), (a0, c0, c1), (a0, c1, a1), (b0, b1, d1), (b0, d1, d0)]
with open(w + "/tube.off", "w") as f:
    f.write("OFF\n%d %d 0\n" % (len(V), len(F)))
    f.writelines("%r %r %r\n" % v for v in V)
    f.writelines("3 %d %d %d\n" % t for t in F)
with open(w + "/apart.csv", "w") as f:
    f.write("pose,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz\n")
    for i in range(12):
        q = [random.gauss(0, 1) for _ in range(4)]
        s = math.sqrt(sum(x * x for x in q))
        a, b, c, d = (x / s for x in q)
        R = [1 - 2 * (c * c + d * d), 2 * (b * c - a * d), 2 * (b * d + a * c),
             2 * (b * c + a * d), 1 - 2 * (b * b + d * d), 2 * (c * d - a * b),
             2 * (b * d - a * c), 2 * (c * d + a * b), 1 - 2 * (b * b + c * c)]
        axis = (R[2], R[5], R[8])
        u = [random.gauss(0, 1) for _ in range(3)]
        along = sum(x * y for x, y in zip(u, axis))
        u = [x - along * y for x, y in zip(u, axis)]
        s = math.sqrt(sum(x * x for x in u))
        # The tube's axis 1.15-1.35 from the sphere's centre, its middle beside it: the wall 0.05-0.25 apart.
        gap = 1.15 + 0.2 * random.random()
        t = [gap * x / s - 2.0 * y for x, y in zip(u, axis)]
        f.write("%d,%s,%s\n" % (i, ",".join(repr(v) for v in R), ",".join(repr(v) for v in t)))
PY
logged "$work/tube.txt" "certify a thin tube apart" \
  "$cdbench" certify "$meshes/sphere.off" "$work/apart.csv" --mover "$work/tube.off" --tolerance 1e-4 -o "$work/tube"
python3 - "$work" <<'PY' || fail "a thin tube apart: intervals a few ulps wide"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/tube/poses.csv")))
assert len(rows) == 12 and all(r["status"] == "certified" for r in rows)
for r in rows:
    lo, hi = float(r["clearance_lo"]), float(r["clearance_hi"])
    assert 0.04 < lo <= hi < 0.26 and hi - lo < 1e-12, (r["pose"], lo, hi)
PY

# A cube resting face-on on the step of an L-shaped part (a face that does not support the part),
# on it, over its edge, in the corner, turned about the vertical, and pushed in by 1e-3: every
# pose certified at the default tolerance, its interval holding 0 (or -1e-3). Before session 93
# the resting faces' cells, centred exactly on F, had no depth bound: four of the five resting
# poses ran out of cells (8 s) and were reported uncertified.
python3 - "$work" <<'PY'
import math, sys
w = sys.argv[1]
profile = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
V = [(x, y, z) for y in (0.0, 1.0) for (x, z) in profile]
F = [(0, k, k + 1) for k in range(1, 5)] + [(6, 7 + k, 6 + k) for k in range(1, 5)]
for i in range(6):
    j = (i + 1) % 6
    F += [(i, i + 6, j + 6), (i, j + 6, j)]
cube = [(x, y, z) for z in (0, 0.5) for y in (0, 0.5) for x in (0, 0.5)]
CF = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6),
      (1, 3, 5), (3, 7, 5)]
for name, vs, fs in (("step", V, F), ("cube", cube, CF)):
    with open("%s/%s.off" % (w, name), "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(vs), len(fs)))
        f.writelines("%r %r %r\n" % tuple(map(float, v)) for v in vs)
        f.writelines("3 %d %d %d\n" % t for t in fs)
c, s = math.cos(0.7), math.sin(0.7)
I = "1,0,0,0,1,0,0,0,1"
rows = [(I, "1.2,0.2,1"), (I, "1.75,0.2,1"), (I, "1,0.25,1"), ("%r,%r,0,%r,%r,0,0,0,1" % (c, -s, s, c), "1.6,0.1,1"),
        (I, "1.2,0.2,0.999")]
with open(w + "/resting.csv", "w") as f:
    f.write("pose,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz\n")
    f.writelines("%d,%s,%s\n" % (i, R, t) for i, (R, t) in enumerate(rows))
PY
logged "$work/rest.txt" "certify cubes resting on a step" \
  "$cdbench" certify "$work/step.off" "$work/resting.csv" --mover "$work/cube.off" -o "$work/rest"
python3 - "$work" <<'PY' || fail "cubes resting on a step: certified, holding the exact clearance"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/rest/poses.csv")))
assert len(rows) == 5 and all(r["status"] == "certified" for r in rows), [r["status"] for r in rows]
for r in rows:
    lo, hi = float(r["clearance_lo"]), float(r["clearance_hi"])
    exact = -1e-3 if r["pose"] == "4" else 0.0
    assert lo <= exact + 1e-12 and exact - 1e-12 <= hi and hi - lo <= 3e-6, (r["pose"], lo, hi)
PY

if [ -n "$check_poses" ] && [ -x "$check_poses" ]; then
  "$check_poses" "$work/m" --poses 8 --grid 8 || fail "independent check of the certify bundle"
  "$check_poses" "$work/rest" --poses 5 || fail "independent check of the resting cubes"
fi
echo "certify and score: all checks passed"

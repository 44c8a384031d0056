#!/usr/bin/env bash
# validation/bench_poses, whose tables doc/performance.md quotes: on a torus pose set it times every
# level against FCL's conservative advancement, prints one --per-pose line per approach and level
# (their work adding up to the level's "work a pose"), reports the share of the timed wall time the
# timing thread ran (a loaded machine named) and the ratios on its CPU time, writes a --trace CSV whose certificates'
# cells add up to the same and whose events are counted by kind in each level's time line, finds
# every contact FCL finds, and refuses
# bad usage and a folder that is not a pose set (exit 2, as every validation program: the file
# named).
. "$(dirname "$0")/common.sh"
cdbench=$1
meshes=$2
bench=$3
logged "$work/poses.txt" "pose set of the torus" \
  "$cdbench" poses "$meshes/torus.off" --levels=-30%,0,6% --directions 4 --orientations 2 -o "$work/set"
logged "$work/bench.txt" "bench_poses" "$bench" "$work/set" --approaches 6 --per-pose --trace "$work/trace.csv"
for level in -30% 0 6%; do
  grep -q "^$level " "$work/bench.txt" || { cat "$work/bench.txt"; fail "no row for level $level"; }
  [ "$(grep -c "^pose approach [0-9]* level $level:" "$work/bench.txt")" -eq 6 ] ||
    { cat "$work/bench.txt"; fail "expected 6 per-pose lines at level $level"; }
done
grep -q "^all " "$work/bench.txt" || fail "no all-levels row"
# The timing thread's share of the timed wall time: a percentage (above 100 only by the clocks'
# granularity), with the warning that goes with it when under 90.
share=$(sed -n 's/^timing thread on its core \([0-9.]*\) % of the timed wall time.*/\1/p' "$work/bench.txt")
[ -n "$share" ] && awk -v s="$share" 'BEGIN { exit !(s > 0 && s <= 101) }' ||
  { cat "$work/bench.txt"; fail "no plausible share of the timed wall time: '$share'"; }
# The ratios to FCL again on that thread's CPU time: one a level, and all levels.
grep -Eq "^pose / FCL CA on the timing thread's CPU time: -30% [0-9.]+, 0 [0-9.]+, 6% [0-9.]+, all [0-9.]+$" "$work/bench.txt" ||
  { cat "$work/bench.txt"; fail "no ratios on the CPU time"; }
if awk -v s="$share" 'BEGIN { exit !(s < 90) }'; then
  grep -q "repeat on an idle machine" "$work/bench.txt" || fail "a loaded run must say so"
else
  ! grep -q "repeat on an idle machine" "$work/bench.txt" || fail "an idle run must not be called loaded"
fi
grep -q "FCL found none 0" "$work/bench.txt" || { cat "$work/bench.txt"; fail "FCL missed a contact the exact sweep found"; }
# The per-pose cells at -30 % add up to the level's mean "certificate cells" times the approaches.
python3 - "$work/bench.txt" <<'PY' || fail "per-pose cells do not add up to the level's work"
import re, sys
text = open(sys.argv[1]).read()
cells = [int(c) for c in re.findall(r"^pose approach \d+ level -30%: .*?cells (\d+),", text, re.M)]
mean = float(re.search(r"^work a pose -30%: certificate cells ([0-9.]+)", text, re.M).group(1))
sys.exit(0 if len(cells) == 6 and abs(sum(cells) / 6 - mean) <= 0.5 else 1)
PY
# The trace: a header, rows of the polished levels, each -30 % pose's certificate cells equal to
# its per-pose line's.
python3 - "$work/bench.txt" "$work/trace.csv" <<'PY' || fail "the trace does not match the per-pose lines"
import csv, re, sys
text = open(sys.argv[1]).read()
per_pose = {int(a): int(c) for a, c in re.findall(r"^pose approach (\d+) level -30%: .*?cells (\d+),", text, re.M)}
rows = list(csv.DictReader(open(sys.argv[2])))
# Level 0's touching poses are certified by the exact sweep, with no branch and bound: no rows.
assert rows and {r["level"] for r in rows} == {"-30%", "6%"}, {r["level"] for r in rows}
assert all(r["event"] in ("certificate", "segment", "zone-query") for r in rows), "events"
traced = {}
for r in rows:
    if r["level"] == "-30%" and r["event"] == "certificate":
        traced[int(r["approach"])] = traced.get(int(r["approach"]), 0) + int(r["work"])
assert traced == per_pose, (traced, per_pose)
# Every event's wall time (ms), and per traced level a line of where its time went, by kind.
assert all(float(r["ms"]) >= 0.0 for r in rows), "ms"
for level in ("-30%", "6%"):
    line = re.search(r"^time a pose " + re.escape(level) + r", traced: (.*)$", text, re.M)
    assert line and "certificate" not in line.group(1) and line.group(1).endswith("ms"), level
    kinds = re.findall(r" ([a-z -]+) [0-9.]+ ms \(\d+ %, (\d+), [0-9.]+ ms each\);", " " + line.group(1))
    counted = {}
    for r in rows:
        if r["level"] == level:
            k = r["purpose"] if r["event"] == "certificate" else ("segment " + r["verdict"] if r["event"] == "segment" else "zone query")
            counted[k] = counted.get(k, 0) + 1
    assert {k: int(n) for k, n in kinds} == counted, (level, kinds, counted)
assert not re.search(r"^time a pose 0,", text, re.M), "level 0 has no traced events"
PY
set +e
"$bench" "$work/set" --approaches 6 --trace "$work/no/such/dir/trace.csv" > "$work/trace_err.txt" 2>&1
[ $? -eq 2 ] || { cat "$work/trace_err.txt"; fail "a trace file that cannot be written must exit 2"; }
grep -q "trace.csv" "$work/trace_err.txt" || { cat "$work/trace_err.txt"; fail "the trace file must be named"; }
! grep -q "certified polished pose" "$work/trace_err.txt" ||
  { cat "$work/trace_err.txt"; fail "an unwritable trace file must be refused before the run"; }
"$bench" "$work/set" --approaches 6 --no-such-option > "$work/usage.txt" 2>&1
[ $? -eq 2 ] || fail "an unknown option must exit 2"
"$bench" > /dev/null 2>&1
[ $? -eq 2 ] || fail "no pose set must exit 2"
mkdir -p "$work/empty"
"$bench" "$work/empty" > "$work/empty.txt" 2>&1
rc=$?
set -e
[ $rc -eq 2 ] || { cat "$work/empty.txt"; fail "a folder without a pose set must exit 2 (got $rc)"; }
grep -q "poseset.json" "$work/empty.txt" || { cat "$work/empty.txt"; fail "the missing file must be named"; }
echo "bench_poses: ok"

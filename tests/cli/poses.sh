#!/usr/bin/env bash
# cdbench poses / merge: determinism across thread counts and shards, resume after a hard
# interruption, and errors on bad options. Usage: poses.sh CDBENCH MESH
set -u
bin=$1
mesh=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
args=(--levels=-20%,0,10% --directions 6 --orientations 3 --band-tolerance 5e-3)

"$bin" poses "$mesh" "${args[@]}" --threads 2 -o "$dir/a" > "$dir/a.log" 2>&1 || { cat "$dir/a.log"; fail "reference run"; }
head -1 "$dir/a/poses.csv" | grep -q '^pose,level,target,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz,dir_x,dir_y,dir_z,clearance_lo,clearance_hi,status' || fail "header"
[ "$(tail -n +2 "$dir/a/poses.csv" | wc -l)" -eq 54 ] || fail "expected 54 poses"
grep -q '"format": "cdbench-poseset"' "$dir/a/poseset.json" || fail "poseset.json format"
[ ! -e "$dir/a/poses.journal" ] || fail "journal left behind"
# Every pose certified and on target.
awk -F, 'NR > 1 && $21 != "certified" { bad++ } END { exit bad > 0 }' "$dir/a/poses.csv" || fail "uncertified poses"

# The default starts need no offset mesh: level 0 and the penetrating level start at the exact
# first contact with the surface, the separated one far away.
grep -q '"start": "surface"' "$dir/a/poseset.json" && grep -q '"start": "far"' "$dir/a/poseset.json" || fail "level starts"
[ -z "$(ls "$dir/a/offsets" | grep '\.off$')" ] || fail "offset meshes made without --start offset"
# Starts from certified offsets (the former default): every pose certified, on the same targets.
"$bin" poses "$mesh" "${args[@]}" --start offset -o "$dir/o" > "$dir/o.log" 2>&1 || { cat "$dir/o.log"; fail "--start offset"; }
[ "$(ls "$dir/o/offsets" | grep -c '\.off$')" -eq 2 ] || fail "--start offset: expected 2 offset meshes"
awk -F, 'NR > 1 && $21 != "certified" { bad++ } END { exit bad > 0 }' "$dir/o/poses.csv" || fail "--start offset: uncertified poses"
grep -q '"start": "offset"' "$dir/o/poseset.json" || fail "--start offset: level starts"
# Offsets meshed by Mesh_3 on all threads: certified all the same, the mesher recorded in the
# offsets' manifest and in the run's key (a resume must not mix meshers); refused without offsets.
"$bin" poses "$mesh" "${args[@]}" --start offset --parallel-mesher -o "$dir/p" > "$dir/p.log" 2>&1 ||
  { cat "$dir/p.log"; fail "--parallel-mesher"; }
awk -F, 'NR > 1 && $21 != "certified" { bad++ } END { exit bad > 0 }' "$dir/p/poses.csv" || fail "--parallel-mesher: uncertified poses"
grep -q '"mesher": "mesh3-parallel"' "$dir/p/offsets/manifest.json" || fail "--parallel-mesher: offsets' mesher not recorded"
grep -q '"offset_mesher": "mesh3-parallel"' "$dir/p/poseset.json" || fail "--parallel-mesher: not in the run key"
"$bin" poses "$mesh" "${args[@]}" --parallel-mesher -o "$dir/x" > "$dir/x.log" 2>&1
[ $? -eq 2 ] && grep -q "only with --start offset" "$dir/x.log" || fail "--parallel-mesher without offsets must be refused"

"$bin" poses "$mesh" "${args[@]}" --threads 1 -o "$dir/b" > /dev/null 2>&1 || fail "one-thread run"
cmp -s "$dir/a/poses.csv" "$dir/b/poses.csv" || fail "poses.csv depends on the thread count"
# More threads than approaches of an orientation and than cores (a 16-core machine's schedule
# differs from two cores' most there): the same bytes.
"$bin" poses "$mesh" "${args[@]}" --threads 7 -o "$dir/c" > /dev/null 2>&1 || fail "seven-thread run"
cmp -s "$dir/a/poses.csv" "$dir/c/poses.csv" || fail "poses.csv differs on seven threads"

"$bin" poses "$mesh" "${args[@]}" --shard 0/2 -o "$dir/s0" > /dev/null 2>&1 || fail "shard 0"
"$bin" poses "$mesh" "${args[@]}" --shard 1/2 -o "$dir/s1" > /dev/null 2>&1 || fail "shard 1"
"$bin" merge "$dir/s1" "$dir/s0" -o "$dir/m" > /dev/null 2>&1 || fail "merge"
cmp -s "$dir/a/poses.csv" "$dir/m/poses.csv" || fail "merged shards differ from the single run"
# Three shards (approaches [6 I, 6 I + 6) each), on three threads, merged in another order.
for i in 0 1 2; do
  "$bin" poses "$mesh" "${args[@]}" --shard $i/3 --threads 3 -o "$dir/t$i" > /dev/null 2>&1 || fail "shard $i/3"
done
"$bin" merge "$dir/t2" "$dir/t0" "$dir/t1" -o "$dir/m3" > /dev/null 2>&1 || fail "merge of three shards"
cmp -s "$dir/a/poses.csv" "$dir/m3/poses.csv" || fail "three merged shards differ from the single run"
"$bin" merge "$dir/s0" -o "$dir/m2" > "$dir/m2.log" 2>&1
[ $? -eq 2 ] && grep -q "missing shard(s) 1 of 2" "$dir/m2.log" || fail "merge with a missing shard must fail"

# Hard interruption after 5 approaches are journaled (others in flight are lost), then --resume.
CDBENCH_TEST_KILL_AFTER_APPENDS=5 "$bin" poses "$mesh" "${args[@]}" -o "$dir/r" > /dev/null 2>&1
[ -s "$dir/r/poses.journal" ] || fail "no journal after the interruption"
[ ! -e "$dir/r/poses.csv" ] || fail "a poses.csv after the interruption"
"$bin" poses "$mesh" "${args[@]}" -o "$dir/r" > "$dir/r.log" 2>&1
[ $? -eq 2 ] && grep -q "pass --resume" "$dir/r.log" || fail "a run over a journal without --resume must refuse"
"$bin" poses "$mesh" --levels=-20%,0,10% --directions 7 --orientations 3 --band-tolerance 5e-3 --resume -o "$dir/r" > "$dir/r.log" 2>&1
[ $? -eq 2 ] && grep -q "belongs to a run with other inputs" "$dir/r.log" || fail "--resume with other options must refuse"
"$bin" poses "$mesh" "${args[@]}" --resume -o "$dir/r" > "$dir/r.log" 2>&1 || { cat "$dir/r.log"; fail "resume"; }
grep -q "resuming: 5 of 18 approaches already certified" "$dir/r.log" || { cat "$dir/r.log"; fail "resume did not reuse the journal"; }
cmp -s "$dir/a/poses.csv" "$dir/r/poses.csv" || fail "resumed run differs"

# Bad options.
"$bin" poses "$mesh" "${args[@]}" --shard 2/2 -o "$dir/x" > "$dir/x.log" 2>&1
[ $? -eq 2 ] && grep -q "0 <= I < N" "$dir/x.log" || fail "--shard 2/2"
"$bin" poses "$mesh" --levels=1,1 --directions 2 --orientations 1 -o "$dir/x" > "$dir/x.log" 2>&1
[ $? -eq 2 ] && grep -q "listed twice" "$dir/x.log" || fail "duplicate level"
"$bin" poses "$mesh" --levels=0,0% --directions 2 --orientations 1 -o "$dir/x" > "$dir/x.log" 2>&1
[ $? -eq 2 ] && grep -q "levels '0' and '0%' both lie at d = 0" "$dir/x.log" || fail "two levels at one distance"
# A coarse tolerance still certifies M to the reported width: percentage levels stay apart.
"$bin" poses "$mesh" --levels=-20%,0,5% --directions 2 --orientations 1 --tolerance 0.1 -o "$dir/coarse" \
  > "$dir/coarse.log" 2>&1 || { cat "$dir/coarse.log"; fail "--tolerance 0.1"; }
# The collision benchmark on this pose set: every implementation, answers checked against the
# certificates (a wrong answer of our trees exits 3), then the plots.
"$bin" bench "$dir/a" --repeat 1 -o "$dir/bench" > "$dir/bench.log" 2>&1 || { cat "$dir/bench.log"; fail "bench"; }
[ "$(tail -n +2 "$dir/bench/results.csv" | cut -d, -f6 | sort -u | wc -l)" -ge 3 ] || fail "bench: implementations missing"
grep -q '"format": "cdbench-bench"' "$dir/bench/summary.json" || fail "bench summary"
awk -F, 'NR > 1 && ($12 == "false-positive" || $12 == "false-negative") { bad++ } END { exit bad > 0 }' \
  "$dir/bench/results.csv" || fail "bench: an implementation contradicts a certificate"
if command -v gnuplot > /dev/null 2>&1; then
  "$bin" plot "$dir/bench" > /dev/null 2>&1 || fail "plot"
  for f in time_vs_level.png time_vs_level.svg time_band_vs_level.png time_band_vs_level.svg bv_tests_vs_level.png bv_tests_vs_level.svg errors.txt; do
    [ -s "$dir/bench/$f" ] || fail "plot: $f missing"
  done
fi
"$bin" bench "$dir/a" --impl obb,nope -o "$dir/bench2" > "$dir/x.log" 2>&1
[ $? -eq 2 ] && grep -q "unknown implementation 'nope'" "$dir/x.log" || fail "bench with an unknown implementation"
# FCL and Bullet come from a module loaded when asked for (lib/collide/peer_module.h): without it
# they are refused before any work (exit 3, the path named), and our own trees run without it.
if "$bin" bench --help | grep -q "fcl-obbrss"; then
  CDBENCH_PEER_MODULE="$dir/none.so" "$bin" bench "$dir/a" --impl obb,fcl-obbrss -o "$dir/bench3" > "$dir/x.log" 2>&1
  [ $? -eq 3 ] && grep -q "$dir/none.so" "$dir/x.log" && [ ! -e "$dir/bench3" ] ||
    { cat "$dir/x.log"; fail "bench without the peer module must name it, exit 3, write nothing"; }
  CDBENCH_PEER_MODULE="$dir/none.so" "$bin" bench "$dir/a" --impl obb --repeat 1 -o "$dir/bench3" > "$dir/x.log" 2>&1 ||
    { cat "$dir/x.log"; fail "our own trees must not need the peer module"; }
fi
"$bin" bench "$dir/a/offsets" -o "$dir/bench2" > "$dir/x.log" 2>&1
[ $? -eq 2 ] && grep -q "poseset.json: cannot be read" "$dir/x.log" || fail "bench on a directory without a pose set"

# An open surface: exit 1, nothing written, and the command that makes it a solid named.
open="$(dirname "$0")/../../data/bad/open_surface.off"
"$bin" poses "$open" --levels=0 -o "$dir/open" > "$dir/x.log" 2>&1
[ $? -eq 1 ] && grep -q "boundary edges" "$dir/x.log" && grep -qF "'cdbench repair $open OUT.off'" "$dir/x.log" &&
  [ ! -e "$dir/open/poses.csv" ] || { cat "$dir/x.log"; fail "poses on an open surface"; }

# The numpy reader of doc/pose-set-format.md, when a python3 with numpy is at hand.
reader="$(dirname "$0")/../../scripts/read_poseset.py"
for py in python3 /usr/bin/python3; do
  if "$py" -c "import numpy" > /dev/null 2>&1; then
    "$py" "$reader" "$dir/a" || fail "numpy reader"
    break
  fi
done
echo "poses: all checks passed"

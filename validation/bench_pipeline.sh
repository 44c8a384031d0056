#!/usr/bin/env bash
# The certified pose pipeline on a panel of meshes: for each, `cdbench poses` on one thread and on
# all cores (speedup; poses.csv must be byte-identical), then validation/bench_poses on the same
# pose set: certified polished poses per level against FCL's conservative advancement (OBBRSS,
# conservativeAdvancementMeshOriented) on the same approaches, in the same run, one thread.
# Usage: validation/bench_pipeline.sh [MESH ...]
#   default panel: armadillo, bunny00, fandisk_large, knot1 (CGAL's data) and armadillo Loop-
#   subdivided once (x4, 208K faces) and twice (x16, 832K faces), made by `cdbench subdivide`.
# Environment: LEVELS (default -25%,-10%,0,10%,25%), DIRECTIONS (40), ORIENTATIONS (2),
#   APPROACHES for bench_poses (40), OUT (build/bench-pipeline), SKIP_ONE_THREAD=1 to skip the
#   one-thread run (no speedup figure, no 16-thread model), SKIP_OFFSETS=1 to skip the offsets.
# The offsets: `cdbench offset MESH --levels=LEVELS` on all cores, the certified offset surfaces of
# the same levels (pose sets do not need them with the default --start auto; a user who wants the
# offset surfaces, or poses started from them, pays this): seconds and faces per level.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/cdbench"
levels=${LEVELS:--25%,-10%,0,10%,25%}
directions=${DIRECTIONS:-40}
orientations=${ORIENTATIONS:-2}
approaches=${APPROACHES:-40}
out=${OUT:-$root/build/bench-pipeline}
cores=$(nproc)
mkdir -p "$out"
data="$root/data/cgal/meshes"
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  [ -f "$data/armadillo.off" ] || bash "$root/scripts/fetch-cgal-data.sh"
  for k in 1 2; do
    f="$out/armadillo_x$((4 ** k)).off"
    [ -f "$f" ] || "$bin" subdivide "$data/armadillo.off" "$f" --steps $k > /dev/null
  done
  meshes=("$data/armadillo.off" "$data/bunny00.off" "$data/fandisk_large.off" "$data/knot1.off"
          "$out/armadillo_x4.off" "$out/armadillo_x16.off")
fi
seconds() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['timings'][sys.argv[2]])" "$1" "$2"; }
now() { date +%s.%N; }
# The 16-thread model (doc/performance.md, "Thread scaling"): the poses phase as poseset.json's
# timings.approaches.modelled_speedup (the one-thread run's approach times, handed out as cdbench
# does); the rest of the whole command (reading, validation, trees, max penetration, writing) split
# into a serial part s and a parallel part p from its one- and all-core wall times (s + p = r1,
# s + p / cores = rn), then Amdahl's law for it.
model16() {  # ONE_DIR ALL_DIR WALL_ONE WALL_ALL -> "poses-model whole-model"
  python3 - "$@" "$cores" <<'PY'
import json, sys
d1, dn, w1, wn, cores = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
t1 = json.load(open(d1 + "/poseset.json"))["timings"]
tn = json.load(open(dn + "/poseset.json"))["timings"]
m = {e["threads"]: e["speedup"] for e in t1["approaches"].get("modelled_speedup", [])}
if 16 not in m or cores < 2:
    print("- -"); sys.exit(0)
r1, rn = w1 - t1["poses"], wn - tn["poses"]
s = max(0.0, min(r1, (cores * rn - r1) / (cores - 1)))
whole16 = s + (r1 - s) / 16 + t1["poses"] / m[16]
print("%.1f %.1f" % (m[16], w1 / whole16))
PY
}
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); levels $levels;" \
     "$directions directions x $orientations orientations"
summary=()
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .off)
  dn="$out/$name-all"
  rm -rf "$dn"
  t0=$(now)
  "$bin" poses "$mesh" --levels="$levels" --directions "$directions" --orientations "$orientations" \
    --threads "$cores" -o "$dn" > "$out/$name-all.log" 2>&1
  wall_n=$(python3 -c "print($(now) - $t0)")
  tn=$(seconds "$dn/poseset.json" total)
  speedup="-"
  models="- -"
  if [ "${SKIP_ONE_THREAD:-0}" != 1 ]; then
    d1="$out/$name-one"
    rm -rf "$d1"
    t0=$(now)
    "$bin" poses "$mesh" --levels="$levels" --directions "$directions" --orientations "$orientations" \
      --threads 1 -o "$d1" > "$out/$name-one.log" 2>&1
    wall_1=$(python3 -c "print($(now) - $t0)")
    cmp -s "$d1/poses.csv" "$dn/poses.csv" || { echo "$name: poses.csv differs between 1 and $cores threads"; exit 1; }
    speedup=$(python3 -c "print('%.2f' % ($(seconds "$d1/poseset.json" poses) / $(seconds "$dn/poseset.json" poses)))")
    models=$(model16 "$d1" "$dn" "$wall_1" "$wall_n")
  fi
  read -r model_poses model_whole <<< "$models"
  offsets_s="-"
  echo
  echo "== $name"
  if [ "${SKIP_OFFSETS:-0}" != 1 ]; then
    do_="$out/$name-offsets"
    rm -rf "$do_"
    "$bin" offset "$mesh" --levels="$levels" --threads "$cores" -o "$do_" > "$out/$name-offsets.log" 2>&1 ||
      echo "$name: cdbench offset failed (exit $?), see $out/$name-offsets.log"
    offsets_s=$(python3 - "$do_" <<'PY'
import json, sys
d = sys.argv[1]
try:
    m = json.load(open(d + "/manifest.json"))
    t = json.load(open(d + "/timings.json"))
except (OSError, ValueError) as e:
    print("-"); print("offsets: no manifest (%s)" % e, file=sys.stderr); sys.exit(0)
secs = {l["level"]: l for l in t["levels"]}
print("%.1f" % t["total"])
print("offsets (cdbench offset, all cores; total %.1f s, of which max penetration %.1f s):"
      % (t["total"], t.get("max_penetration", 0.0)), file=sys.stderr)
print("  %-10s %-9s %9s %10s %8s %8s %8s %8s" % ("level", "status", "faces", "eps/diag", "s",
      "mesh s", "band s", "compl s"), file=sys.stderr)
for l in m["levels"]:
    s = secs.get(l["level"], {})
    det = s.get("detail", {})
    print("  %-10s %-9s %9d %10.2e %8.1f %8.1f %8.1f %8.1f" % (l["level"], l["status"], l["faces"],
          l["epsilon_over_diagonal"], s.get("seconds", float("nan")), det.get("mesh", float("nan")),
          det.get("band", float("nan")), det.get("completeness", float("nan"))), file=sys.stderr)
PY
    )
  fi
  grep -E "^(fixed|level|time)|^-?[0-9.]+%|^0 " "$out/$name-all.log" || true
  "$root/build/validation/bench_poses" "$dn" --approaches "$approaches" | tee "$out/$name-bench.txt"
  faces=$(python3 -c "import json; print(json.load(open('$dn/poseset.json'))['fixed']['faces'])")
  certified=$(awk -F, 'NR > 1 { n++; if ($21 == "certified") c++ } END { printf "%d/%d", c, n }' "$dn/poses.csv")
  ratio=$(awk '$1 == "all" { print $NF }' "$out/$name-bench.txt")
  summary+=("$(printf '%-20s %9s %10.1f %12s %9s %9s %9s %16s %10s' "$name" "$faces" "$tn" "$certified" "$speedup" \
    "$model_poses" "$model_whole" "$ratio" "$offsets_s")")
done
echo
printf '%-20s %9s %10s %12s %9s %9s %9s %16s %10s\n' mesh faces "total s" certified "speedup" "16 poses" "16 whole" \
  "pose / FCL CA" "offsets s"
printf '%s\n' "${summary[@]}"
echo "(total s: the whole 'cdbench poses' on $cores threads, offsets included when any; speedup: poses stage, 1 vs $cores threads;"
echo " 16 poses, 16 whole: modelled speed-ups on 16 threads of the poses stage and of the whole command, from the"
echo " one- and $cores-thread runs: a model, not a measurement (doc/performance.md, \"Thread scaling\");"
echo " offsets s: the whole 'cdbench offset' for the same levels on $cores threads, per level above)"

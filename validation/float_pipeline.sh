#!/usr/bin/env bash
# The float pipeline (`cdbench poses --pipeline float`) against the certified one on the same
# request, in one run, and its convergence with the grid: for each mesh, the certified pose set,
# then float pose sets at several grid resolutions, each validated against the certified one
# (`cdbench validate --reference`). Prints, per grid: the float run's time and its speed-up over
# the certified run (whole commands, offsets and grids included), and per level the p95 and max
# of |c - target| (% of the certified max penetration), wrong signs and missed contacts.
# Usage: validation/float_pipeline.sh [MESH ...]   (default: armadillo and fandisk_large)
# Environment: LEVELS (-25%,-10%,0,10%,25%), DIRECTIONS (200), ORIENTATIONS (5), GRIDS
#   ("64 128 256 512"), THREADS (all cores), OUT (build/float-pipeline).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/cdbench"
levels=${LEVELS:--25%,-10%,0,10%,25%}
directions=${DIRECTIONS:-200}
orientations=${ORIENTATIONS:-5}
grids=(${GRIDS:-64 128 256 512})
threads=${THREADS:-$(nproc)}
out=${OUT:-$root/build/float-pipeline}
mkdir -p "$out"
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  data="$root/data/cgal/meshes"
  [ -f "$data/armadillo.off" ] || bash "$root/scripts/fetch-cgal-data.sh"
  meshes=("$data/armadillo.off" "$data/fandisk_large.off")
fi
now() { date +%s.%N; }
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $threads threads;" \
     "levels $levels; $directions directions x $orientations orientations"
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh"); name=${name%.*}
  req=(--levels="$levels" --directions "$directions" --orientations "$orientations" --threads "$threads")
  rm -rf "$out/$name-certified"
  t0=$(now)
  "$bin" poses "$mesh" "${req[@]}" -o "$out/$name-certified" > "$out/$name-certified.log" 2>&1
  t_cert=$(python3 -c "print($(now) - $t0)")
  sets=()
  declare -A t_float=()
  for g in "${grids[@]}"; do
    d="$out/$name-float$g"
    rm -rf "$d"
    t0=$(now)
    "$bin" poses "$mesh" "${req[@]}" --pipeline float --grid "$g" -o "$d" > "$d.log" 2>&1
    t_float[$g]=$(python3 -c "print($(now) - $t0)")
    sets+=("$d")
  done
  # FCL's conservative advancement on the same approaches (touching poses only), when built.
  fcl="$root/build/validation/fcl_poses"
  if [ -x "$fcl" ]; then
    rm -rf "$out/$name-fcl-ca"
    "$fcl" "$out/$name-certified" -o "$out/$name-fcl-ca" > "$out/$name-fcl-ca.log" 2>&1
    sets+=("$out/$name-fcl-ca")
  fi
  rm -rf "$out/$name-validation"
  "$bin" validate "${sets[@]}" --reference "$out/$name-certified" --threads "$threads" -o "$out/$name-validation" \
    > "$out/$name-validation.log" 2>&1
  echo
  echo "== $name: certified pose set $(printf '%.1f' "$t_cert") s (whole command)"
  printf '%-6s %-12s %-9s %-9s %s\n' grid voxel/diag float_s speed-up "per level: p95 |err| / max |err| (% of max penetration), wrong sign, missed"
  k=0
  for g in "${grids[@]}"; do
    python3 - "$out/$name-validation/$k-$name-float$g/validation.json" "$g" "${t_float[$g]}" "$t_cert" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
g, tf, tc = sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
cells = []
for l in j["levels"]:
    e = l["error_over_max_penetration"]
    cells.append("%s: %.3f/%.3f %d %d" % (l["spec"], 100 * e["p95_abs"], 100 * e["max_abs"], l["wrong_sign"], l["missed_contact"]))
print("%-6s %-12.3e %-9.2f %-9.1f %s" % (g, j["voxel"] / j["diagonal"], tf, tc / tf, " | ".join(cells)))
PY
    k=$((k + 1))
  done
  if [ -x "$fcl" ]; then
    python3 - "$out/$name-validation/$k-$name-fcl-ca" <<'PY'
import csv, json, sys
j = json.load(open(sys.argv[1] + "/validation.json"))
rows = [r for r in csv.DictReader(open(sys.argv[1] + "/validation.csv")) if r["clearance_hi"] != "nan"]
pen = sum(1 for r in rows if float(r["clearance_hi"]) < 0)
l = j["levels"][0]
e = l["error_over_max_penetration"]
print("fcl-ca (conservative advancement, OBBRSS; touching poses only): %.3f ms per approach, one thread;"
      " p95/max |c| %.4f/%.4f %% of max penetration; certainly penetrating %d of %d; missed contacts %d"
      % (1e3 * l["seconds_per_pose"]["pipeline"], 100 * e["p95_abs"], 100 * e["max_abs"], pen, len(rows),
         l["missed_contact"]))
PY
  fi
  unset t_float
done
echo
echo "outputs, validations and plots (error_vs_voxel.png): $out"

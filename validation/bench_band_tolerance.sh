#!/usr/bin/env bash
# The band tolerance of the offsets a pose set starts from (`cdbench poses --start offset
# --band-tolerance B`): a wider band gives coarser offsets (faster to mesh and certify) but starts
# each pose further above its target (2 bands), so polishing takes more steps. For each mesh, one
# run per band in BANDS and one with the default start (`--start auto`: no offsets), each in a
# fresh directory, alternated REPEAT times; a row per run: the whole command's seconds, the offsets'
# and the poses' seconds, the offsets' faces, the mean polishing steps over the levels, certified
# poses, and the whole command's time over the `--start auto` run's of the same round.
# Usage: validation/bench_band_tolerance.sh [MESH ...]   (default: armadillo pinion knot1, CGAL's data)
# Environment: BANDS (5e-4 1e-3 3e-3 1e-2), LEVELS (-20%,0,5%), DIRECTIONS (20), ORIENTATIONS (2),
#   THREADS (all cores), REPEAT (1), OUT (build/bench-band-tolerance).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/cdbench"
read -r -a bands <<< "${BANDS:-5e-4 1e-3 3e-3 1e-2}"
levels=${LEVELS:--20%,0,5%}
directions=${DIRECTIONS:-20}
orientations=${ORIENTATIONS:-2}
threads=${THREADS:-$(nproc)}
repeat=${REPEAT:-1}
out=${OUT:-$root/build/bench-band-tolerance}
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  [ -d "$root/data/cgal/meshes" ] || bash "$root/scripts/fetch-cgal-data.sh"
  meshes=(armadillo pinion knot1)
fi
mkdir -p "$out"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //');" \
     "levels $levels; $directions directions x $orientations orientations; $threads threads; $repeat round(s)"
printf '%-12s %-7s %8s %8s %9s %8s %9s %7s %11s %9s\n' mesh start band whole-s offsets-s poses-s faces steps certified "x auto"
for name in "${meshes[@]}"; do
  mesh=$name
  [ -f "$mesh" ] || mesh="$root/data/cgal/meshes/$name.off"
  name=$(basename "$name" .off)
  for round in $(seq "$repeat"); do
    auto_s=
    for band in auto "${bands[@]}"; do
      dir="$out/$name-$band"
      rm -rf "$dir"
      args=(--levels="$levels" --directions "$directions" --orientations "$orientations" --threads "$threads")
      if [ "$band" = auto ]; then args+=(--start auto); else args+=(--start offset --band-tolerance "$band"); fi
      start=$(date +%s.%N)
      "$bin" poses "$mesh" "${args[@]}" -o "$dir" > "$dir.out" 2> "$dir.err" || echo "  ($name $band: exit $?)"
      end=$(date +%s.%N)
      whole=$(echo "$end - $start" | bc)
      [ "$band" = auto ] && auto_s=$whole
      # "time: X s (offsets Y s, poses Z s, ...)" and poseset.json's per-level counts.
      offsets_s=$(sed -n 's/^time: .*(offsets \([0-9.]*\) s, poses .*/\1/p' "$dir.out")
      poses_s=$(sed -n 's/^time: .*, poses \([0-9.]*\) s, .*/\1/p' "$dir.out")
      read -r faces steps certified < <(python3 - "$dir/poseset.json" <<'EOF'
import json, sys
try:
    levels = json.load(open(sys.argv[1]))["levels"]
except (OSError, ValueError, KeyError):
    print("- - -"); sys.exit()
faces = sum((l.get("swept_offset") or {}).get("faces", 0) or 0 for l in levels)
steps = sum(l.get("mean_polish_steps", 0) for l in levels) / max(len(levels), 1)
print(faces, "%.1f" % steps, "%d/%d" % (sum(l["certified"] for l in levels), sum(l["poses"] for l in levels)))
EOF
)
      printf '%-12s %-7s %8s %8.1f %9s %8s %9s %7s %11s %9.2f\n' "$name" \
        "$([ "$band" = auto ] && echo auto || echo offset)" "$([ "$band" = auto ] && echo - || echo "$band")" \
        "$whole" "${offsets_s:--}" "${poses_s:--}" "$faces" "$steps" "$certified" "$(echo "$whole / $auto_s" | bc -l)"
    done
  done
done

#!/usr/bin/env bash
# The two candidate meshers of `cdbench offset` on one level at a time: Surface_mesher (the
# default: one thread, reproducible) against Mesh_3 in parallel mode (--parallel-mesher) on one
# thread and on all cores, alternated REPEAT times. Prints a row per run: the whole command's
# seconds, the mesh phase's seconds (all meshings of the level), how many meshings it took, the
# faces and the level's status; then validation/check_offsets (independent: CGAL's AABB tree and
# Side_of_triangle_mesh) on the last Mesh_3 offset of each level.
# Usage: validation/bench_offset_meshers.sh [MESH:LEVEL ...]
#   default: pinion:-20% spool:-20% armadillo:-10% knot1:5% rotor_small:5% fandisk:-20% (CGAL's data)
# Environment: REPEAT (2), THREADS (all cores), OUT (build/bench-offset-meshers), TIME_LIMIT (900 s).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/cdbench"
checker="$root/build/validation/check_offsets"
repeat=${REPEAT:-2}
threads=${THREADS:-$(nproc)}
out=${OUT:-$root/build/bench-offset-meshers}
limit=${TIME_LIMIT:-900}
cases=("$@")
if [ ${#cases[@]} -eq 0 ]; then
  [ -d "$root/data/cgal/meshes" ] || bash "$root/scripts/fetch-cgal-data.sh"
  cases=(pinion:-20% spool:-20% armadillo:-10% knot1:5% rotor_small:5% fandisk:-20%)
fi
mkdir -p "$out"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $repeat rounds"
printf '%-14s %-7s %-15s %7s %8s %8s %9s %8s  %s\n' mesh level mesher threads whole-s mesh-s meshings faces status
for c in "${cases[@]}"; do
  name=${c%%:*}
  level=${c#*:}
  mesh=$name
  [ -f "$mesh" ] || mesh="$root/data/cgal/meshes/$name.off"
  name=$(basename "$name" .off)
  for round in $(seq "$repeat"); do
    for run in surface-mesher:"$threads" mesh3-parallel:1 mesh3-parallel:"$threads"; do
      mesher=${run%%:*}
      t=${run#*:}
      flag=()
      [ "$mesher" = mesh3-parallel ] && flag=(--parallel-mesher)
      dir="$out/$name-$mesher-$t"
      rm -rf "$dir"
      start=$(date +%s.%N)
      timeout "$limit" "$bin" offset "$mesh" --levels="$level" --threads "$t" --verbose "${flag[@]}" -o "$dir" \
        > "$dir.out" 2> "$dir.err"
      end=$(date +%s.%N)
      mesh_s=$(grep -o 'meshed [0-9]* faces .* in [0-9.e+-]* s:' "$dir.err" | awk '{s += $(NF-1)} END {printf "%.2f", s}')
      meshings=$(grep -c 'meshed [0-9]* faces' "$dir.err")
      row=$(awk '/^-?[0-9.]+%?[ \t]/ && NF >= 8 {print $3, $4; exit}' "$dir.out")
      printf '%-14s %-7s %-15s %7s %8.1f %8s %9s %8s  %s\n' "$name" "$level" "$mesher" "$t" \
        "$(echo "$end - $start" | bc)" "$mesh_s" "$meshings" "${row#* }" "${row%% *}"
    done
  done
  [ -x "$checker" ] && "$checker" "$out/$name-mesh3-parallel-$threads" --grid 4 --points 100000 2>&1 | tail -n +2 |
    sed "s/^/  check_offsets $name: /"
done

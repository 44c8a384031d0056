#!/usr/bin/env bash
# `cdbench offset` on every closed solid of a mesh collection (by default CGAL's data up to
# MAX_FACES faces), one mesh after another: the certified offsets alone, no poses. Prints one row
# per mesh (faces, the whole command's seconds and exit code, levels certified of those computed,
# mesher attempts, the completeness searches' seconds and their largest cell count, searches that
# found missed regions, and with COMPARE whether the manifest's meshes equal an earlier run's) and
# a summary (failed levels, total and slowest seconds). Meshes that `cdbench check` rejects are
# skipped. Where doc/offsets.md quotes "the 77 closed solids", this is the command.
# Usage: validation/sweep_offsets.sh [MESH ...]
# Environment: MAX_FACES (10000), LEVELS (-20%,0,5%), THREADS (all cores), OUT
#   (build/sweep-offsets), TIME_LIMIT (900 s per command), COMPARE (an earlier run's OUT: each
#   mesh's levels, statuses and offset SHA-256 compared with its manifest there).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/cdbench"
max_faces=${MAX_FACES:-10000}
levels=${LEVELS:--20%,0,5%}
threads=${THREADS:-$(nproc)}
out=${OUT:-$root/build/sweep-offsets}
limit=${TIME_LIMIT:-900}
compare=${COMPARE:-}
mkdir -p "$out"
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  [ -d "$root/data/cgal/meshes" ] || bash "$root/scripts/fetch-cgal-data.sh"
  meshes=("$root"/data/cgal/meshes/*)
fi
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //');" \
     "levels $levels; $threads threads; at most $max_faces faces${compare:+; compared with $compare}"
printf '%-28s %7s %8s %4s %9s %8s %12s %11s %6s %s\n' mesh faces seconds exit certified attempts search-s max-cells missed same
# One row's statistics from the manifest and the verbose log: certified/computed levels, attempts,
# completeness seconds and largest cell count, searches that missed, and the comparison.
row_stats() {
  python3 - "$1" "$2" "$3" <<'EOF'
import json, os, re, sys
manifest, log, earlier = sys.argv[1], sys.argv[2], sys.argv[3]
try:
    levels = json.load(open(manifest))["levels"]
except (OSError, ValueError, KeyError):
    print("- - - - - -"); sys.exit()
computed = [l for l in levels if l.get("status") not in ("original", "empty")]
certified = sum(l.get("status") == "certified" for l in computed)
attempts = sum(l.get("attempts", 0) for l in computed)
text = open(log, errors="replace").read() if os.path.exists(log) else ""
searches = re.findall(r"complete[^(\n]*\((\d+) cells[^)\n]*\) in ([0-9.e+-]+) s", text)
seconds = sum(float(s) for _, s in searches)
cells = max((int(c) for c, _ in searches), default=0)
missed = len(re.findall(r"NOT complete \(\d+ cells, [1-9]", text))
same = "-"
if earlier:
    key = lambda ls: [(l.get("level"), l.get("status"), l.get("sha256")) for l in ls]
    try:
        same = "yes" if key(json.load(open(earlier))["levels"]) == key(levels) else "NO"
    except (OSError, ValueError, KeyError):
        same = "?"
print(f"{certified}/{len(computed)} {attempts} {seconds:.1f} {cells} {missed} {same}")
EOF
}
tried=0 failed_levels=0 total=0 slowest=0 slowest_name=- differ=0
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh")
  check="$out/$name.check"
  timeout "$limit" "$bin" check "$mesh" --no-max-penetration > "$check" 2>&1 || continue
  faces=$(awk '/^mesh:/ && /triangles/ { print $(NF-1); exit }' "$check")
  if [ -z "$faces" ] || [ "$faces" -gt "$max_faces" ]; then continue; fi
  tried=$((tried + 1))
  dir="$out/$name.d"
  rm -rf "$dir"  # a fresh run: the command would reuse the levels of an earlier one
  start=$(date +%s.%N)
  timeout "$limit" "$bin" offset "$mesh" --levels="$levels" -o "$dir" --threads "$threads" --verbose > "$out/$name.log" 2>&1
  rc=$?
  t=$(python3 -c "print('%.1f' % ($(date +%s.%N) - $start))")
  read -r certified attempts search cells missed same < <(row_stats "$dir/manifest.json" "$out/$name.log" \
    "${compare:+$compare/$name.d/manifest.json}")
  printf '%-28s %7s %8s %4s %9s %8s %12s %11s %6s %s\n' "$name" "$faces" "$t" "$rc" "$certified" "$attempts" \
    "$search" "$cells" "$missed" "$same"
  if [ "$certified" = "-" ]; then
    failed_levels=$((failed_levels + 1))
  else
    failed_levels=$((failed_levels + ${certified#*/} - ${certified%/*}))
  fi
  [ "$same" = "NO" ] && differ=$((differ + 1))
  total=$(python3 -c "print('%.1f' % ($total + $t))")
  if python3 -c "import sys; sys.exit(0 if $t > $slowest else 1)"; then slowest=$t slowest_name=$name; fi
done
echo "meshes: $tried; failed levels: $failed_levels; total ${total} s; slowest $slowest_name ${slowest} s${compare:+; manifests differing from $compare: $differ}"

#!/usr/bin/env bash
# The certified pose pipeline on every closed solid of a mesh collection (by default CGAL's data
# up to MAX_FACES faces): for each mesh that `cdbench check` accepts, the whole `cdbench poses`
# command (levels -20%, 0, +5 % of the maximum penetration; 20 directions x 2 orientations, all
# cores), then validation/check_poses on a sample of its certificates. Prints one row per mesh (its
# max-steps column: the most polishing steps one pose took) and a summary: meshes tried, failed
# levels, certified fraction (and the poses whose approach line the exact sweep proves to miss
# the solid, `no-contact`), sampled certificates confirmed, the slowest run. Meshes that are not
# closed solids are counted and skipped (their rejection is `cdbench check`'s business, tested
# elsewhere), or with REPAIR=1 repaired first.
# Usage: validation/sweep_meshes.sh [MESH ...]
# Environment: MAX_FACES (10000), LEVELS (-20%,0,5%), DIRECTIONS (20), ORIENTATIONS (2),
#   CHECK_POSES (24: certificates sampled per mesh), TIME_LIMIT (300 s per command), OUT
#   (build/sweep-meshes), MOVER (a mesh moved against every one: the default is each mesh itself),
#   TOLERANCE (cdbench poses --tolerance; its default when unset), POSES_ARGS (more options for
#   cdbench poses, e.g. "--direction-sampling grid": axis-aligned approach directions), BENCH
#   (approaches: also time validation/bench_poses on that many approaches, one thread, and print
#   a certified polished pose's time over FCL's conservative advancement, all levels, and the
#   largest of one level with that level, e.g. 27.2@-20%; empty: not),
#   REPAIR (1: a mesh that `cdbench check` rejects is first made a closed solid by `cdbench repair`
#   into OUT, as a user would, and run on that (faces: the repaired solid's); its note says so with
#   the repair's seconds; empty: such meshes are skipped).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/cdbench"
checker="$root/build/validation/check_poses"
bencher="$root/build/validation/bench_poses"
bench=${BENCH:-}
max_faces=${MAX_FACES:-10000}
levels=${LEVELS:--20%,0,5%}
directions=${DIRECTIONS:-20}
orientations=${ORIENTATIONS:-2}
check_poses=${CHECK_POSES:-24}
limit=${TIME_LIMIT:-300}
out=${OUT:-$root/build/sweep-meshes}
extra=()
[ -n "${MOVER:-}" ] && extra+=(--mover "$MOVER")
[ -n "${TOLERANCE:-}" ] && extra+=(--tolerance "$TOLERANCE")
# shellcheck disable=SC2206  # POSES_ARGS is a list of words by design
[ -n "${POSES_ARGS:-}" ] && extra+=(${POSES_ARGS})
mkdir -p "$out"
# Seconds since START (a `date +%s.%N` reading), one decimal.
seconds_since() { python3 -c "print('%.1f' % ($(date +%s.%N) - $1))"; }
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  [ -d "$root/data/cgal/meshes" ] || bash "$root/scripts/fetch-cgal-data.sh"
  meshes=("$root"/data/cgal/meshes/*)
fi
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //');" \
     "levels $levels; $directions directions x $orientations orientations; at most $max_faces faces;" \
     "mover ${MOVER:-each mesh itself}; tolerance ${TOLERANCE:-default}; ${POSES_ARGS:-}${bench:+; bench_poses on $bench approaches}"
printf '%-28s %8s %8s %11s %8s %10s %9s %9s %12s %s\n' mesh faces seconds certified failed confirmed max-steps pose/FCL level/FCL note
tried=0 skipped=0 repaired_count=0 repair_failed=0 too_big=0 failed_levels=0 poses=0 certified=0 no_contact=0 sampled=0 confirmed=0 slowest=0 slowest_name=-
worst_ratio=0 worst_name=- worst_level_ratio=0 worst_level=-
greater() { python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) > float(sys.argv[2]) else 1)" "$1" "$2"; }  # A > B, as numbers
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh")
  name=${name//./_}  # keeps the extension: CGAL's data has sphere.off and sphere.obj
  check="$out/$name.check"
  repaired=""
  if ! timeout "$limit" "$bin" check "$mesh" --no-max-penetration > "$check" 2>&1; then
    if [ "${REPAIR:-}" != 1 ]; then
      skipped=$((skipped + 1))
      continue
    fi
    start=$(date +%s.%N)
    if ! timeout "$limit" "$bin" repair "$mesh" "$out/$name.repaired.off" > "$out/$name.repair.log" 2>&1 ||
       ! timeout "$limit" "$bin" check "$out/$name.repaired.off" --no-max-penetration > "$check" 2>&1; then
      printf '%-28s %8s %8s %11s %8s %10s %9s %9s %s\n' "$name" - - - - - - - \
        "repair failed: see $out/$name.repair.log and $check"
      repair_failed=$((repair_failed + 1))
      continue
    fi
    repaired=$(seconds_since "$start")
    mesh="$out/$name.repaired.off"
  fi
  faces=$(awk '/^mesh:/ && /triangles/ { print $(NF-1); exit }' "$check")
  if [ -z "$faces" ] || [ "$faces" -gt "$max_faces" ]; then
    too_big=$((too_big + 1))
    continue
  fi
  tried=$((tried + 1))
  [ -n "$repaired" ] && repaired_count=$((repaired_count + 1))
  dir="$out/$name"
  rm -rf "$dir"
  start=$(date +%s.%N)
  timeout "$limit" "$bin" poses "$mesh" --levels="$levels" --directions "$directions" \
    --orientations "$orientations" "${extra[@]}" -o "$dir" > "$out/$name.log" 2>&1
  rc=$?
  secs=$(seconds_since "$start")
  note=""
  [ -n "$repaired" ] && note="repaired ($repaired s)"
  [ $rc -eq 124 ] && note="$note time limit"
  [ $rc -ne 0 ] && [ $rc -ne 124 ] && note="$note exit $rc"
  n=0 c=0 nc=0 f=0 ok="-" most=0 ratio="-" level_ratio="-"
  if [ -f "$dir/poses.csv" ]; then
    # Poses, certified poses, poses whose approach line is proved to miss (no-contact), and the
    # most polishing steps one pose took (long plateaus).
    read -r n c nc most < <(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "status") s = i; if ($i == "polish_steps") p = i }; next }
                           { n++; if ($s == "certified") c++; if ($s == "uncertified:no-contact") x++; if ($p + 0 > m) m = $p + 0 }
                           END { print n + 0, c + 0, x + 0, m + 0 }' "$dir/poses.csv")
    # A failed level: a pose neither certified nor certified to have no contact, or an offset
    # that could not be certified (--start offset).
    f=$(python3 -c "
import json, sys
levels = json.load(open(sys.argv[1]))['levels']
print(sum(1 for l in levels if l['certified'] + l['no_contact'] < l['poses']
          or (l.get('swept_offset') or {}).get('status') == 'failed'))" "$dir/poseset.json" 2>/dev/null || echo '?')
    line=$(timeout "$limit" "$checker" "$dir" --poses "$check_poses" --grid 6 2>&1 | tail -1)
    read -r k m < <(echo "$line" | sed -n 's/.*: \([0-9]*\) of \([0-9]*\) sampled.*/\1 \2/p')
    if [ -n "${k:-}" ]; then
      ok="$k/$m"
      sampled=$((sampled + m))
      confirmed=$((confirmed + k))
    else
      note="$note checker: ${line:0:60}"
    fi
    if [ -n "$bench" ]; then
      # bench_poses' per-level table: its last column is pose / FCL CA, in the "all" row over all
      # levels; the largest of the level rows (first word a level: 0, 5%, -0.01, ...) apart.
      table=$(timeout "$limit" "$bencher" "$dir" --approaches "$bench" 2>&1)
      ratio=$(echo "$table" | awk '$1 == "all" { r = $NF } END { print r }')
      level_ratio=$(echo "$table" | awk '/^level / { on = 1; next } on && $1 ~ /^[-+]?[0-9.]+(e[-+]?[0-9]+)?%?$/ && $NF + 0 > m { m = $NF + 0; l = $1 }
                                        $1 == "all" { on = 0 } END { if (l != "") print m "@" l }')
      [ -z "$level_ratio" ] && level_ratio="-"
      if [ "$level_ratio" != "-" ] && greater "${level_ratio%@*}" "$worst_level_ratio"; then
        worst_level_ratio=${level_ratio%@*}
        worst_level="$name ${level_ratio#*@}"
      fi
      if [ -z "$ratio" ]; then
        ratio="-"
        note="$note bench_poses failed"
      elif greater "$ratio" "$worst_ratio"; then
        worst_ratio=$ratio
        worst_name=$name
      fi
    fi
  fi
  poses=$((poses + n))
  certified=$((certified + c))
  no_contact=$((no_contact + nc))
  if [ "$f" = "?" ]; then note="$note poseset.json unreadable"; failed_levels=$((failed_levels + 1)); else failed_levels=$((failed_levels + f)); fi
  if greater "$secs" "$slowest"; then
    slowest=$secs
    slowest_name=$name
  fi
  printf '%-28s %8s %8s %11s %8s %10s %9s %9s %12s %s\n' "$name" "$faces" "$secs" "$c/$n" "$f" "$ok" "$most" "$ratio" "$level_ratio" "$note"
done
echo
echo "meshes run: $tried (repaired first: $repaired_count; repair failed: $repair_failed; not closed solids:" \
     "$skipped; more than $max_faces faces: $too_big)"
echo "failed levels: $failed_levels; certified poses: $certified/$poses ($no_contact more proved to have no contact);" \
     "sampled certificates confirmed: $confirmed/$sampled; slowest: $slowest_name $slowest s"
if [ -n "$bench" ]; then
  echo "largest certified pose / FCL CA (all levels): $worst_name $worst_ratio; on one level: $worst_level $worst_level_ratio"
fi

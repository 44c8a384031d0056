#!/usr/bin/env bash
# Faults: runs interrupted by SIGINT/SIGTERM at different moments (offset, poses, certify, bench)
# exit with a message and 130/143, leave no temporary file and no output that looks complete, and
# resume to byte-identical outputs; a full disk (RLIMIT_FSIZE) and a read-only output folder give
# a clear error with earlier outputs intact; a pose set whose mesh changed is refused by bench; an
# offsets folder whose mesh was edited is not reused.
set -u
cdbench=$1
meshes=$2
work=$(mktemp -d)
trap 'chmod -R u+w "$work" 2>/dev/null; rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
cp "$meshes/sphere.off" "$work/sphere.off"
cp "$meshes/box.off" "$work/box.off"
poses=(poses "$work/sphere.off" --mover "$work/box.off" --levels=-20%,0,10% --directions 8 --orientations 3 --band-tolerance 5e-3)
offset=(offset "$work/sphere.off" --levels=-20%,10%,30% --tolerance 5e-3 --mesher-radius 0.05)

# The reference runs, timed: interruptions land at fractions of their duration (any build type).
now() { date +%s.%N; }
t0=$(now)
"$cdbench" "${poses[@]}" -o "$work/ref" > "$work/ref.txt" 2>&1 || { cat "$work/ref.txt"; fail "reference pose set"; }
t1=$(now)
"$cdbench" "${offset[@]}" -o "$work/oref" > "$work/oref.txt" 2>&1 || { cat "$work/oref.txt"; fail "reference offsets"; }
t2=$(now)
at() { awk -v a="$1" -v b="$2" -v f="$3" 'BEGIN { printf "%.2f", (b - a) * f }'; }

# Sends signal $1 after $2 seconds to the command that follows; prints its exit code.
interrupt_after() {
  local sig=$1 delay=$2
  shift 2
  "$@" > "$work/int.txt" 2>&1 &
  local pid=$!
  # Not before the program has installed its handlers (SIGTERM, bit 14 of SigCgt): a signal
  # during start-up (loading the libraries, slow on a loaded machine) kills it silently.
  local cgt
  for _ in $(seq 500); do
    cgt=$(awk '/^SigCgt/ {print $2}' "/proc/$pid/status" 2>/dev/null) || break
    [ -z "$cgt" ] && break
    (( (16#$cgt >> 14) & 1 )) && break
    sleep 0.01
  done
  sleep "$delay"
  kill "-$sig" "$pid" 2>/dev/null
  wait "$pid"
  echo $?
}
# The interrupted folder $1: the expected exit code and message, no temporary file, and (when
# interrupted) no final file that looks complete ($3...).
check_interrupted() {
  local dir=$1 rc=$2
  shift 2
  [ -z "$(find "$dir" -name '*.tmp.*' 2>/dev/null)" ] || fail "temporary files left in $dir: $(find "$dir" -name '*.tmp.*')"
  case "$rc" in
    0) return 1 ;;  # finished before the signal: nothing to check
    130) grep -q "interrupted (SIGINT)" "$work/int.txt" || { cat "$work/int.txt"; fail "no SIGINT message"; } ;;
    143) grep -q "terminated (SIGTERM)" "$work/int.txt" || { cat "$work/int.txt"; fail "no SIGTERM message"; } ;;
    *) cat "$work/int.txt"; fail "interrupted run: exit code $rc" ;;
  esac
  for f in "$@"; do [ ! -e "$dir/$f" ] || fail "interrupted run left $dir/$f, which looks complete"; done
  return 0
}

# poses: interrupted early (max penetration, first poses) and late, by either signal; resumed.
n=0
for spec in TERM:$(at "$t0" "$t1" 0.1) INT:$(at "$t0" "$t1" 0.5) TERM:$(at "$t0" "$t1" 0.85); do
  sig=${spec%%:*}
  delay=${spec##*:}
  n=$((n + 1))
  rc=$(interrupt_after "$sig" "$delay" "$cdbench" "${poses[@]}" -o "$work/p$n")
  if check_interrupted "$work/p$n" "$rc" poses.csv poseset.json; then
    "$cdbench" "${poses[@]}" -o "$work/p$n" --resume > "$work/res.txt" 2>&1 || { cat "$work/res.txt"; fail "poses --resume after SIG$sig at ${delay}s"; }
  fi
  cmp -s "$work/ref/poses.csv" "$work/p$n/poses.csv" || fail "poses interrupted by SIG$sig at ${delay}s and resumed: poses.csv differs"
  echo "poses, SIG$sig after ${delay}s: exit $rc, resumed to identical poses.csv"
done

# offset: levels finished before the interruption are reused; the result is identical.
delay=$(at "$t1" "$t2" 0.7)
rc=$(interrupt_after INT "$delay" "$cdbench" "${offset[@]}" -o "$work/o")
check_interrupted "$work/o" "$rc" timings.json && grep -q '"finished": true' "$work/o/manifest.json" 2>/dev/null \
  && fail "an interrupted offset run wrote a complete manifest"
"$cdbench" "${offset[@]}" -o "$work/o" > "$work/o.txt" 2>&1 || { cat "$work/o.txt"; fail "offset after the interruption"; }
cmp -s "$work/oref/manifest.json" "$work/o/manifest.json" || fail "offset interrupted and re-run: manifest differs"
echo "offset, SIGINT after ${delay}s: exit $rc, $(grep -c '(reused)' "$work/o.txt") level(s) reused, identical manifest"

# certify: interrupted, resumed.
python3 "$(dirname "$0")/random_poses.py" "$work/user.csv" 60 5 0.6,1.2,1.6
certify=(certify "$work/sphere.off" "$work/user.csv" --mover "$work/box.off" --tolerance 1e-4)
t3=$(now)
"$cdbench" "${certify[@]}" -o "$work/cref" > /dev/null 2>&1 || fail "reference certify"
delay=$(at "$t3" "$(now)" 0.6)
rc=$(interrupt_after TERM "$delay" "$cdbench" "${certify[@]}" -o "$work/c")
if check_interrupted "$work/c" "$rc" poses.csv poseset.json; then
  "$cdbench" "${certify[@]}" -o "$work/c" --resume > "$work/c.txt" 2>&1 || { cat "$work/c.txt"; fail "certify --resume"; }
fi
cmp -s "$work/cref/poses.csv" "$work/c/poses.csv" || fail "certify interrupted and resumed: poses.csv differs"
echo "certify, SIGTERM after ${delay}s: exit $rc, resumed to identical poses.csv"

# bench: interrupted, no results that look complete.
rc=$(interrupt_after INT 2 "$cdbench" bench "$work/ref" --repeat 200 -o "$work/b")
check_interrupted "$work/b" "$rc" summary.json results.csv || fail "bench finished before the signal"
echo "bench, SIGINT after 2s: exit $rc, no summary or results"

# A full disk: the writes fail with a clear error; the earlier outputs of the folder are intact.
cp -r "$work/ref" "$work/full"
before=$(cd "$work/full" && sha256sum poses.csv poseset.json)
other=(poses "$work/sphere.off" --mover "$work/box.off" --levels=-20%,0,10% --directions 9 --orientations 3 --band-tolerance 5e-3)
( ulimit -f 8; "$cdbench" "${other[@]}" -o "$work/full" > "$work/full.txt" 2>&1 )
rc=$?
[ "$rc" -eq 2 ] && grep -q -E "disk full|cannot write|write failed" "$work/full.txt" || { cat "$work/full.txt"; fail "full disk: exit $rc"; }
[ "$(cd "$work/full" && sha256sum poses.csv poseset.json)" = "$before" ] || fail "full disk: earlier outputs changed"
[ -z "$(find "$work/full" -name '*.tmp.*')" ] || fail "full disk: temporary files left"
echo "full disk (RLIMIT_FSIZE 8 KiB): exit 2, $(grep -o -m1 -E "[^ ]*(disk full|cannot write|write failed)[^.]*" "$work/full.txt" | head -c 100)"

# A read-only output folder: as a user, permissions; as root, a read-only bind mount.
cp -r "$work/ref" "$work/ro"
before=$(cd "$work/ro" && sha256sum poses.csv poseset.json)
run_ro() { "$cdbench" bench "$work/ro" --impl obb --repeat 1 -o "$work/ro" > "$work/ro.txt" 2>&1; }
if [ "$(id -u)" -ne 0 ]; then
  chmod a-w "$work/ro"
  run_ro
  rc=$?
  chmod u+w "$work/ro"
elif unshare -m true 2>/dev/null; then
  export -f run_ro
  export cdbench work
  unshare -m bash -c 'mount --bind -o ro "$work/ro" "$work/ro" && run_ro'
  rc=$?
else
  rc=skip
fi
if [ "$rc" != skip ]; then
  # Refused before the benchmark runs (prepare_output_directory), not when its outputs are written.
  [ "$rc" -eq 2 ] && grep -q "(output directory): cannot write there" "$work/ro.txt" ||
    { cat "$work/ro.txt"; fail "read-only folder: exit $rc"; }
  [ "$(cd "$work/ro" && sha256sum poses.csv poseset.json)" = "$before" ] || fail "read-only folder: outputs changed"
  echo "read-only output folder: exit 2, $(head -c 160 "$work/ro.txt")"
else
  echo "read-only output folder: not tested (root without mount namespaces)"
fi

# The mesh of a pose set changed: bench refuses. Its offsets are not reused for the edited mesh.
echo "# edited" >> "$work/sphere.off"
"$cdbench" bench "$work/ref" --impl obb --repeat 1 -o "$work/b2" > "$work/b2.txt" 2>&1
rc=$?
[ "$rc" -eq 2 ] && grep -q "SHA-256 mismatch" "$work/b2.txt" || { cat "$work/b2.txt"; fail "bench on a changed mesh: exit $rc"; }
"$cdbench" "${offset[@]}" -o "$work/oref" > "$work/o2.txt" 2>&1 || { cat "$work/o2.txt"; fail "offset of the edited mesh"; }
! grep -q '(reused)' "$work/o2.txt" || fail "offsets of another version of the mesh were reused"
echo "changed mesh: bench refuses (SHA-256 mismatch); offsets recomputed, none reused"
echo "faults: all checks passed"

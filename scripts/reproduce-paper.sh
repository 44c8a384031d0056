#!/usr/bin/env bash
# The seed paper's three experiments end to end (doc/reproduction.md):
#   reproduce-paper.sh --scale small|paper -o DIR [--threads N] [--mesh FILE]
#                      [--directions N] [--orientations K] [--repeat R] [--impl LIST]
# For each sample set (scripts/paper_sets.sh): a certified pose set (cdbench poses), the timed
# collision queries of the paper's three bounding volumes and FCL's (cdbench bench, every answer
# checked against the certificates), the figures with their spread band (cdbench plot), then the
# paper's claims beside our measurements (scripts/paper_claims.py -> DIR/claims.md).
# small: CGAL's armadillo (52,000 faces). paper: armadillo Loop-subdivided twice (832,000 faces,
# made here by `cdbench subdivide`; the paper's 480,076-triangle dragon is not available offline).
# A step whose output exists is reused (re-running after an interruption continues).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
# shellcheck source=paper_sets.sh
source "$root/scripts/paper_sets.sh"

usage() {
  sed -n '2,4p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}
die() {
  echo "reproduce-paper.sh: error: $*" >&2
  exit 2
}

cdbench="${CDBENCH:-$root/build/cdbench}"
while [ $# -gt 0 ]; do
  if paper_option "$@"; then shift "$PAPER_SHIFT"; continue; fi
  case "$1" in
    -h|--help) usage ;;
    *) die "unknown option '$1' (see --help)" ;;
  esac
done
paper_check_options die
threads="${threads:-$(nproc)}"

if [ ! -x "$cdbench" ]; then
  bash "$root/scripts/install-deps.sh"
  bash "$root/scripts/build.sh"
fi
mkdir -p "$out" || die "$out: cannot create the output directory"
out="$(cd "$out" && pwd)"
log="$out/timings.txt"
: > "$log"
stamp() { date +%s.%N; }
timed() {  # timed LABEL COMMAND...: runs it, appends "LABEL seconds" to timings.txt
  local label="$1" t0 t1
  shift
  t0=$(stamp)
  "$@"
  t1=$(stamp)
  awk -v l="$label" -v a="$t0" -v b="$t1" 'BEGIN { printf "%-28s %9.1f s\n", l, b - a }' | tee -a "$log"
}
t_start=$(stamp)

# The mesh.
if [ -z "$mesh" ]; then
  t0=$(stamp)
  mesh="$(bash "$root/scripts/paper-step.sh" mesh "$scale" "$out" "$cdbench")"
  awk -v a="$t0" -v b="$(stamp)" 'BEGIN { printf "%-28s %9.1f s\n", "mesh", b - a }' | tee -a "$log"
  mesh_note="CGAL's armadillo (52,000 faces)"
  [ "$PRESET_MESH_KIND" = armadillo-x16 ] &&
    mesh_note="CGAL's armadillo Loop-subdivided twice (832,000 faces): the paper's 480,076-triangle dragon is not available offline"
else
  [ -r "$mesh" ] || die "--mesh: $mesh cannot be read"
  mesh_note="$mesh (given with --mesh)"
fi
echo "mesh: $mesh_note" | tee "$out/mesh.txt"
echo "per set: $directions directions x $orientations orientations, $threads threads; bench: $impls, median of $repeat runs" | tee -a "$out/mesh.txt"

for i in 0 1 2; do
  name="${PAPER_SET_NAMES[$i]}"
  set_dir="$out/$name"
  echo
  echo "== ${PAPER_SET_TITLES[$i]}"
  if [ ! -s "$set_dir/poses/poseset.json" ]; then
    resume=()
    [ -e "$set_dir/poses/poses.journal" ] && resume=(--resume)
    timed "$name poses" "$cdbench" poses "$mesh" --levels="${PAPER_SET_LEVELS[$i]}" --directions "$directions" \
      --orientations "$orientations" --threads "$threads" "${resume[@]}" -o "$set_dir/poses"
  fi
  timed "$name bench" bash "$root/scripts/paper-step.sh" bench "$cdbench" "$out" "$name" "$impls" "$repeat"
done
echo
bash "$root/scripts/paper-step.sh" claims "$out"
cat "$out/claims.md"
awk -v a="$t_start" -v b="$(stamp)" 'BEGIN { printf "%-28s %9.1f s\n", "total", b - a }' | tee -a "$log"
echo "figures: $out/figures/ (one time figure with its spread band and one BV-test figure per set)"
echo "claims:  $out/claims.md; timings: $log"

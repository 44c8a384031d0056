#!/usr/bin/env bash
# The steps of the paper reproduction shared by scripts/reproduce-paper.sh (local) and
# scripts/slurm/submit.sh (cluster), so that both run exactly the same commands:
#   paper-step.sh mesh SCALE OUT CDBENCH       prints the mesh path (makes armadillo x16 for paper)
#   paper-step.sh bench CDBENCH OUT SET IMPLS REPEAT
#                                              cdbench bench + plot of OUT/SET/poses, figures copied
#                                              to OUT/figures (a bench already there is reused)
#   paper-step.sh claims OUT                   OUT/claims.md (scripts/paper_claims.py)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
# shellcheck source=paper_sets.sh
source "$root/scripts/paper_sets.sh"
die() {
  echo "paper-step.sh: error: $*" >&2
  exit 2
}
step="${1:-}"
shift || true
case "$step" in
  mesh)
    [ $# -eq 3 ] || die "usage: paper-step.sh mesh SCALE OUT CDBENCH"
    scale="$1" out="$2" cdbench="$3"
    paper_preset "$scale" || die "unknown scale '$scale'"
    bash "$root/scripts/fetch-cgal-data.sh" > /dev/null ||
      die "CGAL's data (armadillo) is not available: install libcgal-demo (scripts/install-deps.sh)"
    mesh="$root/data/cgal/meshes/armadillo.off"
    if [ "$PRESET_MESH_KIND" = armadillo-x16 ]; then
      big="$out/mesh/armadillo_x16.off"
      if [ ! -s "$big" ]; then
        mkdir -p "$out/mesh"
        "$cdbench" subdivide "$mesh" "$big" --steps 2 >&2
      fi
      mesh="$big"
    fi
    echo "$mesh"
    ;;
  bench)
    [ $# -eq 5 ] || die "usage: paper-step.sh bench CDBENCH OUT SET IMPLS REPEAT"
    cdbench="$1" out="$2" name="$3" impls="$4" repeat="$5"
    set_dir="$out/$name"
    if [ ! -s "$set_dir/bench/summary.json" ]; then
      mkdir -p "$set_dir/bench"
      # The full per-level table goes to bench.txt beside summary.json.
      "$cdbench" bench "$set_dir/poses" --impl "$impls" --repeat "$repeat" -o "$set_dir/bench" > "$set_dir/bench/bench.txt"
    fi
    "$cdbench" plot "$set_dir/bench" > /dev/null
    mkdir -p "$out/figures"
    for ext in png svg; do
      cp "$set_dir/bench/time_band_vs_level.$ext" "$out/figures/$name-time.$ext"
      cp "$set_dir/bench/bv_tests_vs_level.$ext" "$out/figures/$name-bv-tests.$ext"
    done
    ;;
  claims)
    [ $# -eq 1 ] || die "usage: paper-step.sh claims OUT"
    python3 "$root/scripts/paper_claims.py" "$1" > "$1/claims.md.tmp"
    mv "$1/claims.md.tmp" "$1/claims.md"
    ;;
  *) die "unknown step '$step' (mesh, bench, claims)" ;;
esac

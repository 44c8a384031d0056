# The seed paper's three sample sets and the presets of scripts/reproduce-paper.sh, sourced by it
# and by scripts/slurm/submit.sh (one definition for the local and the cluster run).
# Levels are percentages of the certified maximum penetration (< 0: penetrating).

# Set 1: penetration and distance from 0 to 25 % in fine steps (2.5 %).
PAPER_SET_NAMES=(set1-boundary-25 set2-deep-80 set3-boundary-10)
PAPER_SET_LEVELS=(
  "-25%,-22.5%,-20%,-17.5%,-15%,-12.5%,-10%,-7.5%,-5%,-2.5%,0,2.5%,5%,7.5%,10%,12.5%,15%,17.5%,20%,22.5%,25%"
  # Set 2: penetration up to 80 % in coarse steps (10 %).
  "-80%,-70%,-60%,-50%,-40%,-30%,-20%,-10%,0"
  # Set 3: +-10 % in fine steps (1 %) around the boundary.
  "-10%,-9%,-8%,-7%,-6%,-5%,-4%,-3%,-2%,-1%,0,1%,2%,3%,4%,5%,6%,7%,8%,9%,10%"
)
PAPER_SET_TITLES=(
  "Set 1: -25 % to +25 % of the maximum penetration, steps of 2.5 % (paper: Figure 10)"
  "Set 2: 0 to -80 %, steps of 10 % (paper: Figure 11)"
  "Set 3: -10 % to +10 %, steps of 1 % (paper: Figure 12)"
)
# The paper's three bounding volumes (our OBB, AABB and sphere trees) and FCL's OBB and OBBRSS.
PAPER_IMPLS="obb,aabb,sphere,fcl-obb,fcl-obbrss"

# paper_preset SCALE: sets PRESET_MESH_KIND (armadillo | armadillo-x16), PRESET_DIRECTIONS,
# PRESET_ORIENTATIONS, PRESET_REPEAT; returns 1 for an unknown scale.
paper_preset() {
  case "$1" in
    small) PRESET_MESH_KIND=armadillo; PRESET_DIRECTIONS=20; PRESET_ORIENTATIONS=2; PRESET_REPEAT=5 ;;
    paper) PRESET_MESH_KIND=armadillo-x16; PRESET_DIRECTIONS=20; PRESET_ORIENTATIONS=2; PRESET_REPEAT=3 ;;
    *) return 1 ;;
  esac
}

# Options common to reproduce-paper.sh and slurm/submit.sh. paper_option "$@" consumes the first
# option if it is one of them (sets PAPER_SHIFT to the arguments used) and returns 1 otherwise.
# (Defined here without overwriting a caller's values.)
scale="${scale:-}" out="${out:-}" threads="${threads:-}" mesh="${mesh:-}" directions="${directions:-}"
orientations="${orientations:-}" repeat="${repeat:-}" impls="${impls:-$PAPER_IMPLS}"
paper_option() {
  PAPER_SHIFT=2
  case "$1" in
    --scale) scale="${2:-}" ;;
    -o|--output) out="${2:-}" ;;
    --threads) threads="${2:-}" ;;
    --mesh) mesh="${2:-}" ;;
    --directions) directions="${2:-}" ;;
    --orientations) orientations="${2:-}" ;;
    --repeat) repeat="${2:-}" ;;
    --impl) impls="${2:-}" ;;
    *) return 1 ;;
  esac
}
# paper_check_options DIE_FUNCTION [MORE_INTEGER_OPTIONS...]: validates them, fills the preset's
# defaults (directions, orientations, repeat).
paper_check_options() {
  local die="$1" v val
  shift
  [ -n "$scale" ] || "$die" "--scale small|paper is required"
  paper_preset "$scale" || "$die" "--scale: '$scale' is not one of small, paper"
  [ -n "$out" ] || "$die" "-o DIR is required"
  for v in threads directions orientations repeat "$@"; do
    val="${!v}"
    if [ -n "$val" ] && ! [[ "$val" =~ ^[1-9][0-9]*$ ]]; then "$die" "--$v: '$val' is not a positive integer"; fi
  done
  directions="${directions:-$PRESET_DIRECTIONS}"
  orientations="${orientations:-$PRESET_ORIENTATIONS}"
  repeat="${repeat:-$PRESET_REPEAT}"
}

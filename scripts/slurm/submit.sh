#!/usr/bin/env bash
# The paper reproduction (scripts/reproduce-paper.sh) as Slurm jobs (doc/reproduction.md):
#   submit.sh --scale small|paper -o DIR [--shards N] [--threads N] [--mesh FILE] [--directions N]
#             [--orientations K] [--repeat R] [--impl LIST] [--sbatch "ARGS"] [--wait]
# Jobs, all with their logs in DIR/slurm-logs:
#   mesh (paper scale only: armadillo x16), then for each of the three sample sets
#   an array of N pose shards (cdbench poses --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT),
#   merge (afterok: the array), bench + plot (afterok: merge); then claims (afterok: every bench).
# DIR must be on a file system shared by the nodes (as the repository and build/cdbench). Pose
# sets need no offset meshes (the default start), so there are no offset tasks to wait for.
# --wait: return when every job has ended: 0 when the claims were written, 1 when a step failed
# (its dependents are cancelled: --kill-on-invalid-dep).
# Prints the job ids, also written to DIR/slurm-jobs.txt.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
# shellcheck source=../paper_sets.sh
source "$root/scripts/paper_sets.sh"
die() {
  echo "submit.sh: error: $*" >&2
  exit 2
}

shards=4 extra="" wait=0
cdbench="${CDBENCH:-$root/build/cdbench}"
while [ $# -gt 0 ]; do
  if paper_option "$@"; then shift "$PAPER_SHIFT"; continue; fi
  case "$1" in
    --shards) shards="${2:-}"; shift 2 ;;
    --sbatch) extra="${2:-}"; shift 2 ;;
    --wait) wait=1; shift ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2 ;;
    *) die "unknown option '$1' (see --help)" ;;
  esac
done
paper_check_options die shards
command -v sbatch > /dev/null || die "sbatch not found: Slurm's client commands are needed (Debian: slurm-client)"
[ -x "$cdbench" ] || die "$cdbench not found: build first (scripts/build.sh) or set CDBENCH"
cdbench="$(cd "$(dirname "$cdbench")" && pwd)/$(basename "$cdbench")"  # jobs run in DIR
threads="${threads:-1}"
mkdir -p "$out/slurm-logs" || die "$out: cannot create the output directory"
out="$(cd "$out" && pwd)"
jobs_file="$out/slurm-jobs.txt"
: > "$jobs_file"

# sbatch_job NAME [SBATCH OPTIONS...] -- SCRIPT ARGS...: submits, records and prints the job id.
sbatch_job() {
  local name="$1" id
  shift
  # shellcheck disable=SC2086  # --sbatch ARGS are split on purpose
  id="$(sbatch --parsable --job-name="cdbench-$name" --output="$out/slurm-logs/%x-%A_%a.out" --chdir="$out" \
    --kill-on-invalid-dep=yes $extra "$@")" ||
    die "sbatch refused the $name job"
  id="${id%%;*}"
  echo "$name $id" | tee -a "$jobs_file" >&2
  echo "$id"
}

after=()
if [ -n "$mesh" ]; then
  [ -r "$mesh" ] || die "--mesh: $mesh cannot be read"
  mesh="$(cd "$(dirname "$mesh")" && pwd)/$(basename "$mesh")"
elif [ "$PRESET_MESH_KIND" = armadillo-x16 ]; then
  mesh="$out/mesh/armadillo_x16.off"
  id="$(sbatch_job mesh --cpus-per-task=1 "$root/scripts/slurm/step.sbatch" \
    bash "$root/scripts/paper-step.sh" mesh "$scale" "$out" "$cdbench")"
  after=(--dependency="afterok:$id")
else
  mesh="$(bash "$root/scripts/paper-step.sh" mesh "$scale" "$out" "$cdbench")"
fi

bench_ids=()
for i in 0 1 2; do
  name="${PAPER_SET_NAMES[$i]}"
  mkdir -p "$out/$name/shards"
  poses_id="$(sbatch_job "$name-poses" "${after[@]}" --array="0-$((shards - 1))" --cpus-per-task="$threads" \
    "$root/scripts/slurm/poses.sbatch" "$cdbench" "$mesh" "${PAPER_SET_LEVELS[$i]}" "$directions" "$orientations" \
    "$threads" "$out/$name/shards")"
  shard_dirs=()
  for ((k = 0; k < shards; ++k)); do shard_dirs+=("$out/$name/shards/shard-$k"); done
  merge_id="$(sbatch_job "$name-merge" --dependency="afterok:$poses_id" --cpus-per-task=1 \
    "$root/scripts/slurm/step.sbatch" "$cdbench" merge "${shard_dirs[@]}" -o "$out/$name/poses")"
  bench_ids+=("$(sbatch_job "$name-bench" --dependency="afterok:$merge_id" --cpus-per-task=1 \
    "$root/scripts/slurm/step.sbatch" bash "$root/scripts/paper-step.sh" bench "$cdbench" "$out" "$name" "$impls" "$repeat")")
done
deps="afterok$(printf ':%s' "${bench_ids[@]}")"
rm -f "$out/claims.md"
sbatch_job claims --dependency="$deps" --cpus-per-task=1 "$root/scripts/slurm/step.sbatch" \
  bash "$root/scripts/paper-step.sh" claims "$out" > /dev/null
echo "submitted: $(wc -l < "$jobs_file") jobs (ids in $jobs_file); results in $out (claims.md when all are done)"
[ "$wait" = 1 ] || exit 0
ids="$(awk '{print $2}' "$jobs_file" | paste -sd, -)"
while [ -n "$(squeue -h -j "$ids" 2> /dev/null)" ]; do sleep 2; done
if [ ! -s "$out/claims.md" ]; then
  echo "submit.sh: error: a job failed (the chain after it was cancelled); logs in $out/slurm-logs:" >&2
  grep -l -i "error" "$out"/slurm-logs/*.out >&2 || true
  exit 1
fi
echo "done: $out/claims.md"

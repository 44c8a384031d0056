#!/usr/bin/env bash
# A real single-node Slurm cluster, started by this test: munged and slurmctld/slurmd with a
# configuration in a temporary directory (own ports, own munge socket; nothing system-wide is
# touched). scripts/slurm/submit.sh runs a small paper reproduction on it (three sample sets, each
# an array of pose shards, merge, bench, plot, claims); every merged poses.csv must be
# byte-identical to a local unsharded `cdbench poses` of the same request.
# Usage: slurm.sh CDBENCH MESH. Exit 77 (skipped, with the reason) without Slurm/munge or root.
set -euo pipefail
cdbench="$1"
mesh="$2"
root="$(cd "$(dirname "$0")/../.." && pwd)"
skip() {
  echo "SKIPPED: $*"
  exit 77
}
for tool in munged slurmctld slurmd sbatch squeue sinfo; do
  command -v "$tool" > /dev/null || skip "$tool not found (Debian's slurm-wlm and munge: scripts/install-deps.sh installs them)"
done
[ "$(id -u)" = 0 ] || skip "starting slurmd needs root"

work="$(mktemp -d /tmp/cdbench-slurm.XXXXXX)"
chmod 700 "$work"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  sleep 1
  for p in "${pids[@]}"; do kill -9 "$p" 2> /dev/null || true; done
  if [ "${KEEP:-0}" = 1 ]; then echo "kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  for f in "$work"/*.log "$work"/out/slurm-logs/*; do
    [ -f "$f" ] && { echo "--- $f"; tail -20 "$f"; }
  done
  exit 1
}

# munge: its own key, socket and state in the work directory.
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge.key"
mkdir -p "$work/munge"
chmod 700 "$work/munge"
munged --force --key-file="$work/munge.key" --socket="$work/munge/socket" --pid-file="$work/munge/pid" \
  --log-file="$work/munge.log" --seed-file="$work/munge/seed" || fail "munged did not start"
pids+=("$(cat "$work/munge/pid")")

# Free ports for the two daemons (a range unlikely to be taken; checked).
port_free() { ! (exec 3<> "/dev/tcp/127.0.0.1/$1") 2> /dev/null; }
base=$((20000 + RANDOM % 20000))
while ! port_free "$base" || ! port_free $((base + 1)); do base=$((base + 2)); done
host="$(hostname -s)"
cpus="$(nproc)"
mkdir -p "$work/state" "$work/spool"
cat > "$work/slurm.conf" << EOF
ClusterName=cdbenchtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$base
SlurmdPort=$((base + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge/socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1,sched_min_interval=100000
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MinJobAge=600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"
slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start"
for _ in $(seq 50); do [ -s "$work/slurmctld.pid" ] && break; sleep 0.2; done
pids+=("$(cat "$work/slurmctld.pid")")
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
for _ in $(seq 50); do [ -s "$work/slurmd.pid" ] && break; sleep 0.2; done
pids+=("$(cat "$work/slurmd.pid")")
for _ in $(seq 60); do
  state="$(sinfo -h -N -o '%t' 2> /dev/null || true)"
  [ "$state" = idle ] && break
  sleep 1
done
[ "$state" = idle ] || fail "the node did not become idle (state '$state')"

# A small reproduction on the cluster: 3 shards per set.
request=(--scale small --mesh "$mesh" --directions 3 --orientations 2 --repeat 1 --impl obb,aabb)
CDBENCH="$cdbench" timeout 900 bash "$root/scripts/slurm/submit.sh" "${request[@]}" --shards 3 -o "$work/out" --wait ||
  fail "the cluster run failed"
[ -s "$work/out/claims.md" ] || fail "no claims.md"
jobs="$(wc -l < "$work/out/slurm-jobs.txt")"
[ "$jobs" = 10 ] || fail "expected 10 jobs (3 x poses array, merge, bench; claims), got $jobs"

# The same request locally, unsharded: byte-identical poses.csv per set.
source "$root/scripts/paper_sets.sh"
for i in 0 1 2; do
  name="${PAPER_SET_NAMES[$i]}"
  "$cdbench" poses "$mesh" --levels="${PAPER_SET_LEVELS[$i]}" --directions 3 --orientations 2 --threads 2 \
    -o "$work/local/$name" > /dev/null
  cmp "$work/local/$name/poses.csv" "$work/out/$name/poses/poses.csv" ||
    fail "$name: the cluster's merged poses.csv differs from the local run"
  for f in summary.json time_band_vs_level.png bv_tests_vs_level.svg; do
    [ -s "$work/out/$name/bench/$f" ] || fail "$name: bench/$f missing"
  done
  ls "$work/out/$name/shards" | grep -q '^shard-2$' || fail "$name: no third shard"
done
for f in set1-boundary-25-time.png set2-deep-80-time.svg set3-boundary-10-bv-tests.png; do
  [ -s "$work/out/figures/$f" ] || fail "figures/$f missing"
done
grep -q "Time peaks around the boundary" "$work/out/claims.md" || fail "claims.md has no claims table"
echo "ok: 10 Slurm jobs (3 arrays of 3 shards), merged pose sets byte-identical to local runs, claims and figures written"

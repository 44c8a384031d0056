#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang, ASan and UBSan (build-fuzz/), replays the
# committed corpus (tests/fuzz/corpus/<target>/: seeds and every past finding), then fuzzes each
# target for SECONDS (default 60), JOBS targets at a time. Exits non-zero on any finding, with the
# input kept in build-fuzz/findings/ and the command that reproduces it.
#   scripts/fuzz.sh [--seconds N] [--jobs J] [--merge] [TARGET...]
# --merge adds new coverage-increasing inputs to the committed corpus (minimised); without it
# the corpus is only read.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds=60
jobs=2
merge=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --merge) merge=1; shift ;;
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_mesh fuzz_csv fuzz_json fuzz_levels)

export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
clangxx=$(command -v clang++-14 || command -v clang++ || true)
[ -n "$clangxx" ] || { echo "fuzz: clang++ not found (Debian: apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 2; }
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
build="$root/build-fuzz"
start=$(date +%s)
cmake -S "$root" -B "$build" "${gen[@]}" -DCMAKE_CXX_COMPILER="$clangxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCDBENCH_FUZZ=ON -DCDBENCH_BUILD_TESTS=OFF -DCDBENCH_BUILD_VALIDATION=OFF > /dev/null
cmake --build "$build" --target "${targets[@]}" -j "$(nproc)"
echo "fuzz: build done in $(( $(date +%s) - start )) s"

export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
mkdir -p "$build/findings"
status=0
run_target() {
  local t=$1 corpus="$root/tests/fuzz/corpus/$1" work="$build/work/$1" bin="$build/tests/fuzz/$1"
  local flags=(-timeout=10 -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$build/findings/$t-" -print_final_stats=1)
  [ -f "$root/tests/fuzz/$t.dict" ] && flags+=(-dict="$root/tests/fuzz/$t.dict")
  mkdir -p "$corpus" "$work"
  # Replay: every committed input once (a regression of an old finding fails here).
  if ! "$bin" "${flags[@]}" -runs=0 "$corpus" > "$build/work/$t.replay.log" 2>&1; then
    tail -n 40 "$build/work/$t.replay.log"; echo "fuzz: $t: a committed corpus input fails"; return 1
  fi
  echo "fuzz: $t: corpus of $(ls "$corpus" | wc -l) inputs replayed"
  [ "$seconds" -gt 0 ] || return 0
  if ! "$bin" "${flags[@]}" -max_total_time="$seconds" "$work" "$corpus" > "$build/work/$t.log" 2>&1; then
    tail -n 60 "$build/work/$t.log"
    echo "fuzz: $t: FINDING; input: $(ls -t "$build/findings/$t-"* 2>/dev/null | head -n 1)"
    echo "fuzz: reproduce: $bin <that file>"
    return 1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$build/work/$t.log" | tr '\n' ' ' | sed "s/^/fuzz: $t: /"; echo
  if [ "$merge" -eq 1 ]; then
    "$bin" "${flags[@]}" -merge=1 "$corpus" "$work" > "$build/work/$t.merge.log" 2>&1
    echo "fuzz: $t: corpus now $(ls "$corpus" | wc -l) inputs"
  fi
}
pids=()
names=()
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 1; done
  run_target "$t" > "$build/work-$t.out" 2>&1 &
  pids+=($!); names+=("$t")
done
for i in "${!pids[@]}"; do
  if ! wait "${pids[$i]}"; then status=1; fi
  cat "$build/work-${names[$i]}.out"
done
exit $status

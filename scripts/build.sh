#!/usr/bin/env bash
# Configures and builds cdbench (Release) in build/ with ccache when available.
# Usage: scripts/build.sh [extra cmake arguments]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
# ccache: hash paths relative to the checkout, so that another clone (CI) reuses the cache.
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
cmake -S "$root" -B "$root/build" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$root/build" -j "$(nproc)"

#!/usr/bin/env bash
# Certified poses per second on a mesh, and FCL's translational conservative advancement on the
# same approaches. Defaults are the issue's benchmark: armadillo, 1000 directions x 10
# orientations x 5 levels (-25%..25% of the max penetration), 2 threads.
# Usage: validation/bench_poses.sh [MESH] [DIRECTIONS] [ORIENTATIONS] [OUT]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mesh=${1:-$root/data/cgal/meshes/armadillo.off}
directions=${2:-1000}
orientations=${3:-10}
out=${4:-$root/build/bench-poses}
"$root/build/cdbench" poses "$mesh" --levels=-25%,-10%,0,10%,25% --directions "$directions" \
  --orientations "$orientations" --threads 2 -o "$out"
"$root/build/validation/bench_poses" "$out" --approaches 1000

#!/usr/bin/env bash
# The main job on the embedded default input: install, build, check CGAL's armadillo (from
# Debian's libcgal-demo; the committed torus when that data is unavailable), then make a certified
# pose set of it (5 levels from -25% to +25% of the maximum penetration, 40 directions x 2
# orientations), summarise it with the numpy reader when numpy is present, and benchmark the
# static collision implementations (our OBB/AABB/sphere trees, FCL) over it, with plots.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/build.sh"
mesh="$root/data/meshes/torus.off"
if bash "$root/scripts/fetch-cgal-data.sh"; then mesh="$root/data/cgal/meshes/armadillo.off"; fi
"$root/build/cdbench" check "$mesh"
echo
out="$root/build/demo-poses"
"$root/build/cdbench" poses "$mesh" --levels=-25%,-10%,0,10%,25% --directions 40 --orientations 2 -o "$out"
for py in python3 /usr/bin/python3; do
  if "$py" -c "import numpy" > /dev/null 2>&1; then
    echo
    "$py" "$root/scripts/read_poseset.py" "$out"
    break
  fi
done
echo
"$root/build/cdbench" bench "$out" -o "$root/build/demo-bench"
echo
"$root/build/cdbench" plot "$root/build/demo-bench"

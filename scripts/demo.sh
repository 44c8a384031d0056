#!/usr/bin/env bash
# The main job on the embedded default input: install, build, then `cdbench check` with the
# certified maximum penetration on CGAL's armadillo (from Debian's libcgal-demo), falling back to
# the committed torus when the CGAL data is unavailable.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/build.sh"
mesh="$root/data/meshes/torus.off"
if bash "$root/scripts/fetch-cgal-data.sh"; then mesh="$root/data/cgal/meshes/armadillo.off"; fi
"$root/build/cdbench" check "$mesh"

#!/usr/bin/env bash
# Extracts CGAL's example meshes from Debian's libcgal-demo package into data/cgal/ (git-ignored).
# Idempotent; these files are never committed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
archive=/usr/share/doc/libcgal-dev/data.tar.gz
dest="$root/data/cgal"
if [ -f "$dest/meshes/armadillo.off" ]; then
  echo "fetch-cgal-data: $dest already present"
  exit 0
fi
if [ ! -f "$archive" ]; then
  echo "fetch-cgal-data: $archive not found; install libcgal-demo (scripts/install-deps.sh does)" >&2
  exit 1
fi
mkdir -p "$dest"
tar xzf "$archive" -C "$dest" --strip-components=1 data/meshes
echo "fetch-cgal-data: $(ls "$dest/meshes" | wc -l) files in $dest/meshes"

#!/usr/bin/env bash
# Installs cdbench's build and test dependencies from Debian 12's packages.
# Idempotent: when every package is already present it only checks and returns (about a second).
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config git
  libcgal-dev libcgal-demo libeigen3-dev libgmp-dev libmpfr-dev libboost-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev libssl-dev
  python3 python3-numpy libfcl-dev libbullet-dev gnuplot-nox libopenvdb-dev libboost-iostreams-dev
  clang-14 libclang-rt-14-dev
  slurm-wlm munge  # the Slurm test starts its own single-node cluster (tests/cli/slurm.sh)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"

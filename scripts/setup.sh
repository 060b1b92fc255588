#!/usr/bin/env bash
# Installs every Debian package pcrt needs (fast when they are there) and builds it in build/.
# Run as root on Debian 12. Usage: scripts/setup.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libnanoflann-dev libfmt-dev nlohmann-json3-dev catch2 libbenchmark-dev libtbb-dev libpng-dev libtinyexr-dev libembree-dev
  libcli11-dev
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  clang libclang-rt-14-dev
  python3 python3-numpy python3-matplotlib python3-skimage
  python3-dev pybind11-dev python3-pybind11 python3-pytest python3-pandas
  slurm-wlm munge
  ca-certificates
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)"

#!/bin/bash
# Installs what sphrect needs from Debian 12's packages (if missing), then configures and builds.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(cmake g++ make pkg-config blender libembree-dev libtbb-dev pybind11-dev python3-dev python3-numpy python3-pytest
          python3-matplotlib python3-scipy python3-mpmath python3-distributed python3-dask libboost-math-dev libhwy-dev libopenimageio-dev libgtest-dev libbenchmark-dev xvfb xauth
          clang-format python3-flake8 python3-pip python3-venv python3-setuptools python3-wheel)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "Installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 > build-configure.log 2>&1 \
  || { cat build-configure.log; exit 1; }
cmake --build build -j"$(nproc)"

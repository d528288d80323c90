#!/usr/bin/env bash
# Installs the Debian packages rangefuse needs (skipping those already present), then
# configures and builds into build/. Safe to run again: it only does what is missing.
# RANGEFUSE_EXTRA_PACKAGES adds packages (jobs/fuzz.sh: clang and its libFuzzer runtime).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config openmpi-bin libopenmpi-dev libhdf5-openmpi-dev
          libeigen3-dev libnanoflann-dev libboost-program-options-dev libgtest-dev
          libpng-dev libjpeg-dev nlohmann-json3-dev procps
          pybind11-dev python3-dev python3-numpy python3-pytest python3-mpi4py
          ${RANGEFUSE_EXTRA_PACKAGES:-})
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo=sudo
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi

# A unity build (sources compiled eight to a unit) halves a fresh build on two cores.
# The Python module is built for Debian's interpreter, where apt put numpy, pytest and mpi4py.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build build -j "$(nproc)"

#!/usr/bin/env bash
# Installs the Debian packages hemivem needs to build and test. Idempotent: packages
# already present are left alone and apt is not touched when nothing is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libcli11-dev libtomlplusplus-dev libmuparser-dev
  libsuitesparse-dev libopenblas0-pthread
  libmumps-seq-dev libmumps-dev libopenmpi-dev openmpi-bin
  libgtest-dev libgmock-dev libbenchmark-dev
  libnlopt-dev libceres-dev
  libpetsc-real3.18-dev
  nlohmann-json3-dev zlib1g-dev python3-meshio gnuplot-nox
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib python3-vtk9
  python3-venv python3-pip python3-setuptools python3-wheel
  clang
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"

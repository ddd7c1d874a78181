#!/usr/bin/env bash
# Configures hemivem (Release) in ./build and builds what a run needs: the libraries, the
# command (build/drivers/hemivem), the mumps-mpi module and the Python module (the target
# hemivem_product). scripts/test.sh builds the tests and benchmarks. Usage: scripts/build.sh
# [extra cmake args]
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
else
  cmake -S . -B build "$@" >/dev/null
fi
cmake --build build --parallel "$(nproc)" --target hemivem_product

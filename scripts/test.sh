#!/usr/bin/env bash
# Runs the whole test suite on the build in ./build (scripts/build.sh): builds what
# scripts/build.sh left out (the test programs, the benchmarks, the fuzzers when configured);
# checks the house rules (scripts/check-house.py); runs every registered test; then the Python module's tests (tests/python, pytest, with the
# interpreter the module was built for); then the installed package against a fresh prefix
# (scripts/test-install.sh); then `pip install .` into a fresh virtual environment, reusing
# ./build (scripts/test-pip.sh); then the input-facing tests under AddressSanitizer and
# UndefinedBehaviorSanitizer (scripts/test-sanitizers.sh, its own build in ./build-asan); then
# the libFuzzer targets, built with Clang and run for 5 seconds each (scripts/fuzz.sh, its own
# build in ./build-fuzz) so that they keep building.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --parallel "$(nproc)"
/usr/bin/python3 scripts/check-house.py
ctest --test-dir build --output-on-failure -j2
python="$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' build/CMakeCache.txt)"
if compgen -G "build/python/hemivem/_hemivem*.so" >/dev/null && [ -n "$python" ]; then
  PYTHONPATH="$PWD/build/python" HEMIVEM_BUILD_DIR="$PWD/build" "$python" -m pytest -q -p no:cacheprovider tests/python
else
  echo "test.sh: skipped tests/python: the Python module was not built (pybind11, python3-dev, python3-numpy)"
fi
scripts/test-install.sh build
if compgen -G "build/python/hemivem/_hemivem*.so" >/dev/null; then
  scripts/test-pip.sh build
else
  echo "test.sh: skipped scripts/test-pip.sh: the Python module was not built"
fi
scripts/test-sanitizers.sh
scripts/fuzz.sh 5

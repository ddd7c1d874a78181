#!/usr/bin/env bash
# Runs the whole test suite on the build in ./build (scripts/build.sh): every registered test.
set -euo pipefail
cd "$(dirname "$0")/.."
ctest --test-dir build --output-on-failure -j2

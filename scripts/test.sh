#!/usr/bin/env bash
# Runs the whole test suite on the build in ./build (scripts/build.sh): every registered test,
# then the installed package against a fresh prefix (scripts/test-install.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
ctest --test-dir build --output-on-failure -j2
scripts/test-install.sh build

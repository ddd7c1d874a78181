#!/usr/bin/env bash
# Runs the whole test suite on the build in ./build (scripts/build.sh): every registered test;
# then the installed package against a fresh prefix (scripts/test-install.sh); then the
# input-facing tests under AddressSanitizer and UndefinedBehaviorSanitizer
# (scripts/test-sanitizers.sh, its own build in ./build-asan).
set -euo pipefail
cd "$(dirname "$0")/.."
ctest --test-dir build --output-on-failure -j2
scripts/test-install.sh build
scripts/test-sanitizers.sh

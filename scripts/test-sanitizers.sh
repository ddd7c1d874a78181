#!/usr/bin/env bash
# Builds and runs the input-facing tests (scene parser, mesh readers, mesh checks, generators,
# hostile inputs) under AddressSanitizer and UndefinedBehaviorSanitizer: the CMake preset
# `asan` (CMakePresets.json) in build-asan/ (or $HEMIVEM_ASAN_BUILD_DIR). Only these test
# programs are built. The whole suite under the preset: see README (Sanitizers).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${HEMIVEM_ASAN_BUILD_DIR:-build-asan}"
tests=(test_scene test_mesh_io test_gmsh test_mesh test_mesh_generators test_polygon_meshes test_hostile_inputs)
cmake --preset asan -B "$build" "$@" >/dev/null
cmake --build "$build" --target "${tests[@]}"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
for t in "${tests[@]}"; do
  echo "== $t (AddressSanitizer, UndefinedBehaviorSanitizer)"
  "$build/tests/$t" --gtest_brief=1
done

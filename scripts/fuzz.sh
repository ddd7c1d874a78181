#!/usr/bin/env bash
# Fuzzes the scene parser and the mesh readers with libFuzzer (Clang, AddressSanitizer and
# UndefinedBehaviorSanitizer). Usage: scripts/fuzz.sh [seconds-per-target] (default 60).
# Configures build-fuzz/ (or $HEMIVEM_FUZZ_BUILD_DIR), builds fuzz_scene, fuzz_poly2d and
# fuzz_gmsh, seeds each from the test corpora and runs it for the given time. The corpus
# grown by a run stays in <build>/corpus/<target>; crashing inputs are written to
# <build>/artifacts/<target>/. Exits non-zero when any target finds a crash, a hang or a leak.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
build="${HEMIVEM_FUZZ_BUILD_DIR:-build-fuzz}"
shared="${HEMIVEM_SHARED_DIR:-$PWD/../shared}"
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DBUILD_TESTING=OFF -DHEMIVEM_BUILD_BENCHMARKS=OFF -DHEMIVEM_WITH_MUMPS_MPI=OFF \
  -DHEMIVEM_BUILD_FUZZERS=ON -DHEMIVEM_SHARED_DIR="$shared" >/dev/null
cmake --build "$build" --target fuzz_scene fuzz_poly2d fuzz_gmsh

# Seeds: every file of the given folders with the given suffix.
seed() {
  local target="$1" suffix="$2"; shift 2
  local dir="$build/seeds/$target"
  rm -rf "$dir" && mkdir -p "$dir"
  local d f
  for d in "$@"; do
    [ -d "$d" ] || continue
    while IFS= read -r -d '' f; do
      cp "$f" "$dir/$(echo "$f" | tr '/' '_')"
    done < <(find "$d" -type f -name "*$suffix" -print0)
  done
}
seed fuzz_scene .toml scenes tests/data/scenes-bad tests/data/hostile
seed fuzz_poly2d .poly2d tests/data/malformed tests/data/hostile "$shared/meshes"
seed fuzz_gmsh .msh tests/data/gmsh tests/data/hostile

status=0
for target in fuzz_scene fuzz_poly2d fuzz_gmsh; do
  mkdir -p "$build/corpus/$target" "$build/artifacts/$target"
  echo "== $target: $seconds s"
  if ! UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      "$build/fuzz/$target" "$build/corpus/$target" "$build/seeds/$target" \
      -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
      -print_final_stats=1 -artifact_prefix="$build/artifacts/$target/" \
      >"$build/$target.log" 2>&1; then
    echo "$target: FAILED (log $build/$target.log, inputs in $build/artifacts/$target/)"
    grep -E "^==[0-9]+==ERROR|runtime error|deadly signal|uncaught exception|Test unit written" "$build/$target.log" | head -5 || true
    status=1
  else
    grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$build/$target.log" | tail -2 || true
  fi
done
exit "$status"

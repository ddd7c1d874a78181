#!/usr/bin/env bash
# Example 4.1 on squares: one factorization of A against producing S and c, per linear
# engine and N, each case in its own process so that its peak memory can be read.
# Usage: scripts/bench-condensation.sh [build-dir] [N ...]     (default N: 64 128 256 512)
# Prints a Markdown table: time (s) and peak RSS (MB) of (a) and (b), and (b)/(a).
set -euo pipefail
build=${1:-build}
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(64 128 256 512)
bench="$build/tests/bench/bench_condensation"
[ -x "$bench" ] || { echo "bench-condensation: $bench not found (build first)" >&2; exit 2; }
# `hemivem backends` prints "linear engines: eigen cholmod ..." and "minimizers: ...": the names
# after the colon of the first line
engines=$("$build/drivers/hemivem" backends | sed -n 's/^linear engines: //p')
[ -n "$engines" ] || { echo "bench-condensation: no linear engine in 'hemivem backends'" >&2; exit 2; }

run() {  # prints "seconds peak_MB" for one benchmark case
  local out
  out=$( { /usr/bin/time -f 'RSS %M' "$bench" --benchmark_filter="^$1\$" --benchmark_format=csv 2>&1; } )
  local ms rss
  ms=$(echo "$out" | grep "^\"$1\"" | cut -d, -f3)
  rss=$(echo "$out" | sed -n 's/^RSS //p')
  awk -v ms="$ms" -v rss="$rss" 'BEGIN { printf "%.3f %.0f", ms / 1000, rss / 1024 }'
}

echo "| engine | N | dofs | (a) factorize [s] | (a) peak [MB] | (b) S and c [s] | (b) peak [MB] | (b)/(a) time |"
echo "|---|---|---|---|---|---|---|---|"
for e in $engines; do
  for n in "${sizes[@]}"; do
    read -r ta ma <<<"$(run "factorize/$e/$n/iterations:1/real_time")"
    read -r tb mb <<<"$(run "condense/$e/$n/iterations:1/real_time")"
    dofs=$(( 2 * (n + 1) * (n + 1) - 4 * (n + 1) ))
    awk -v e="$e" -v n="$n" -v d="$dofs" -v ta="$ta" -v ma="$ma" -v tb="$tb" -v mb="$mb" \
      'BEGIN { printf "| %s | %d | %d | %.3f | %.0f | %.3f | %.0f | %.2f |\n", e, n, d, ta, ma, tb, mb, tb / ta }'
  done
done

#!/usr/bin/env bash
# hemivem solve (Example 4.1 on N x N squares) with the sequential mumps engine, and with
# mumps-mpi under mpirun -np 1 and -np 2: the stage timings of result.json and the largest
# peak memory of one process.
# Usage: scripts/bench-mpi.sh [build-dir] [N ...]     (default N: 256 512)
# Prints a Markdown table (times in seconds, memory in MB). Needs jq, /usr/bin/time, mpirun.
set -euo pipefail
build=${1:-build}
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(256 512)
hemivem="$build/drivers/hemivem"
[ -x "$hemivem" ] || { echo "bench-mpi: $hemivem not found (build first)" >&2; exit 2; }
for tool in jq mpirun /usr/bin/time; do
  command -v "$tool" >/dev/null || { echo "bench-mpi: $tool not found" >&2; exit 2; }
done
mpiflags=()
if mpirun --version 2>&1 | grep -q "Open MPI"; then
  mpiflags=(--oversubscribe)
  [ "$(id -u)" -eq 0 ] && mpiflags+=(--allow-run-as-root)
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

row() {  # engine, N, command prefix...
  local label=$1 n=$2
  shift 2
  local out="$work/$label-$n-$#"
  "$@" /usr/bin/time -o "$out.rss" -a -f '%M' "$hemivem" solve --n "$n" -q --out "$out" --linear "$label"
  local rss
  rss=$(sort -n "$out.rss" | tail -1)
  jq -r --arg engine "$label" --arg n "$n" --arg rss "$rss" '
    [$engine, $n, (.mesh.dofs | tostring), (.processes | tostring), .converged,
     (.timings | .assembly, .condensation, .minimize, .back_substitution, .total | . * 10000 | round / 10000),
     ($rss | tonumber / 1024 | round)] | "| " + (map(tostring) | join(" | ")) + " |"' "$out/result.json"
}

echo "| engine | N | dofs | processes | converged | assembly | condensation | minimize | back_substitution | total | peak per process [MB] |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
  row mumps "$n"
  row mumps-mpi "$n" mpirun "${mpiflags[@]}" -np 1
  row mumps-mpi "$n" mpirun "${mpiflags[@]}" -np 2
done

#!/usr/bin/env bash
# Draws the paper's Figures 1 and 2 for Example 4.1 into docs/:
#   docs/figure1-sutton-meshes.png  u_nu along Gamma_3 on Sutton's mesh types (../shared/meshes)
#   docs/figure2-refinement.png     u_nu along Gamma_3 on squares for N = 4 ... 64
# Figure 3 (the error plot) is docs/table1.png, drawn by `hemivem study`.
# Usage: scripts/figures.sh [build-dir]   (needs gnuplot and ../shared/meshes)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
hemivem="$build/drivers/hemivem"
shared=../shared/meshes
[ -x "$hemivem" ] || { echo "figures: $hemivem not found (build first)" >&2; exit 2; }
[ -d "$shared" ] || { echo "figures: $shared not found" >&2; exit 2; }
command -v gnuplot >/dev/null || { echo "figures: gnuplot not found" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# contact.csv: vertex,x,y,u_nu,law_force,reaction,pressure,state -> "x u_nu" sorted by x
curve() { tail -n +2 "$1/contact.csv" | awk -F, '{ print $2, $4 }' | sort -g > "$2"; }

plots=()
for m in squares triangles voronoi-merged smoothed-voronoi-merged non-convex; do
  "$hemivem" solve --mesh "$shared/sutton-$m.poly2d" --out "$work/$m" -q
  curve "$work/$m" "$work/$m.dat"
  plots+=("'$work/$m.dat' using 1:2 with linespoints pt 7 ps 0.6 title 'sutton-$m'")
done
gnuplot <<GP
set terminal pngcairo size 1000,650 font ",12"
set output 'docs/figure1-sutton-meshes.png'
set title "Example 4.1: normal displacement u_{/Symbol n} along {/Symbol G}_3 on Sutton's meshes"
set xlabel 'x (scene units)'; set ylabel 'normal displacement u_{/Symbol n} (scene units)'; set grid; set key bottom center
plot $(IFS=,; echo "${plots[*]}")
GP

plots=()
for n in 4 8 16 32 64; do
  "$hemivem" solve --n "$n" --out "$work/n$n" -q
  curve "$work/n$n" "$work/n$n.dat"
  plots+=("'$work/n$n.dat' using 1:2 with linespoints pt 7 ps 0.5 title 'N = $n'")
done
gnuplot <<GP
set terminal pngcairo size 1000,650 font ",12"
set output 'docs/figure2-refinement.png'
set title "Example 4.1: u_{/Symbol n} along {/Symbol G}_3 on N x N squares"
set xlabel 'x (scene units)'; set ylabel 'normal displacement u_{/Symbol n} (scene units)'; set grid; set key bottom center
plot $(IFS=,; echo "${plots[*]}")
GP
echo "figures: wrote docs/figure1-sutton-meshes.png docs/figure2-refinement.png"

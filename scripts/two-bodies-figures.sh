#!/usr/bin/env bash
# Draws the figures of docs/two-bodies.md from the shipped scenes:
#   docs/two-blocks-pressure.png     the pressure at every pair of the contact patch test
#                                    (scenes/two-blocks.toml: Voronoi cells on squares, matched)
#   docs/two-cylinders-pressure.png  Hertz's two cylinders (scenes/two-cylinders.toml, paired by
#                                    projection): every node's pressure against Hertz's profile
# Usage: scripts/two-bodies-figures.sh [build-dir]   (needs gnuplot)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
hemivem="$build/drivers/hemivem"
[ -x "$hemivem" ] || { echo "two-bodies-figures: $hemivem not found (build first)" >&2; exit 2; }
command -v gnuplot >/dev/null || { echo "two-bodies-figures: gnuplot not found" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$hemivem" solve scenes/two-blocks.toml --out "$work/blocks" --set 'output.write=["contact-csv"]' -q
"$hemivem" solve scenes/two-cylinders.toml --out "$work/cylinders" --set 'output.write=["contact-csv"]' -q
# contact.csv: vertex,x,y,u_nu,law_force,reaction,pressure,state,gap,nx,ny,partner -> "x pressure force*(-ny)"
tail -n +2 "$work/blocks/contact.csv" | awk -F, '{ print $2, $7 }' | sort -g > "$work/blocks.dat"
tail -n +2 "$work/cylinders/contact.csv" | awk -F, '{ print $2, $7, ($5 + $6) * (-$11) }' | sort -g > "$work/cylinders.dat"
gnuplot <<GP
set terminal pngcairo size 900,560 font ",12"
set output 'docs/two-blocks-pressure.png'
set title "The contact patch test: 5 x 3 Voronoi cells on 7 x 3 squares, matched along y = 0.5\nthe pressure at every contact pair against the load"
set xlabel "x"
set ylabel "contact pressure"
set yrange [0:2.5]
set grid
set key bottom right
plot '$work/blocks.dat' using 1:2 with points pt 7 ps 1.2 lc rgb "#1f77b4" title 'hemivem (every pair)', \
     2 with lines lw 2 lc rgb "#d62728" title 'the load, 2'
GP
gnuplot <<GP
set terminal pngcairo size 900,560 font ",12"
set output 'docs/two-cylinders-pressure.png'
stats '$work/cylinders.dat' using 3 nooutput
P = STATS_sum
R = 1.0 * 1.5 / 2.5
E = 1.0 / ((1 - 0.3**2) / 1.0 + (1 - 0.2**2) / 2.0)
a = sqrt(4 * P * R / (pi * E))
p0 = 2 * P / (pi * a)
set title sprintf("Hertz's two cylinders (radii 1 and 1.5), paired by projection\nP = %.4g per unit length: a = %.4f, p_0 = %.4f", P, a, p0)
set xlabel "x / a"
set ylabel "p / p_0"
set xrange [-1.6:1.6]
set yrange [-0.05:1.15]
set grid
set key top right
f(x) = abs(x) < 1 ? sqrt(1 - x*x) : 0
set samples 500
plot '$work/cylinders.dat' using (\$1/a):(\$2/p0) with points pt 7 ps 0.9 lc rgb "#1f77b4" title 'hemivem (every node of the upper cylinder)', \
     f(x) with lines lw 2 lc rgb "#d62728" title 'Hertz'
GP
echo "wrote docs/two-blocks-pressure.png docs/two-cylinders-pressure.png"

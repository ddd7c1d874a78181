#!/usr/bin/env bash
# The pressure profile of the 3D Hertz problem against Hertz's formula (docs/three-dimensions.md):
# runs build/tests/bench/hertz3d to h = a/8 and draws docs/hertz3d-pressure.png with gnuplot.
# Usage: scripts/hertz3d-pressure.sh (after scripts/test.sh or a build of the target hertz3d)
set -euo pipefail
cd "$(dirname "$0")/.."
csv=$(mktemp)
trap 'rm -f "$csv"' EXIT
build/tests/bench/hertz3d 3 1 "$csv"
gnuplot <<GNUPLOT
set terminal pngcairo size 900,600 font ",12"
set output "docs/hertz3d-pressure.png"
set datafile separator ","
a = 0.05
p0 = 3.49791
set xlabel "r / a"
set ylabel "p / p_0"
set title "Hertz in 3D: a rigid sphere pressed into a block (quarter model, h = a/8)\\nnodal pressures of the contact nodes against p_0 sqrt(1 - r^2/a^2)"
set xrange [0:2]
set yrange [-0.05:1.15]
set grid
set key top right
f(x) = x < 1 ? sqrt(1 - x*x) : 0
set samples 500
plot "$csv" every ::1 using (\$1/a):(\$2/p0) with points pt 7 ps 0.8 lc rgb "#1f77b4" title "hemivem (every contact node)", \\
     f(x) with lines lw 2 lc rgb "#d62728" title "Hertz"
GNUPLOT

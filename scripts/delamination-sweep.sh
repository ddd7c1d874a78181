#!/usr/bin/env bash
# The delamination benchmark of docs/nonconvex.md: scenes/delamination.toml under a sweep of
# the pulling traction, solved by every built minimizer alone (solver.search = "local") and
# by the global search, each run timed by hemivem itself (result.json).
#
#   scripts/delamination-sweep.sh [BUILD] [OUT] [LOADS]
#
# BUILD defaults to build, OUT to out/delamination, LOADS (MPa, comma-separated) to
# 20,21,22,23,24,25,26,27. Writes OUT/sweep.csv (load, search, minimizer, status, energy,
# seconds, separated and debonded nodes, critical points found), OUT/profiles.csv (the binding
# traction along the interface at each load, from the global search), OUT/sweep.md (the
# tables of docs/nonconvex.md) and, when gnuplot is installed, OUT/delamination.png.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/delamination}
loads=${3:-20,21,22,23,24,25,26,27}
hemivem="$build/drivers/hemivem"
scene=scenes/delamination.toml
[ -x "$hemivem" ] || { echo "delamination-sweep: $hemivem not found; run scripts/build.sh" >&2; exit 2; }
mkdir -p "$out"
minimizers=$("$hemivem" backends | sed -n 's/^minimizers: *//p')
[ -n "$minimizers" ] || minimizers="ssn bundle-dca nlopt-mma ceres-active-set"

IFS=, read -r -a load_list <<<"$loads"
for load in "${load_list[@]}"; do
  traction=$(python3 -c "print(repr(float('$load') * 1e6))")
  for m in $minimizers; do
    dir="$out/runs/$load/local-$m"
    "$hemivem" solve "$scene" --minimizer "$m" --set solver.search=\"local\" \
      --set "loads.traction[0].value=[0.0, $traction]" -q --out "$dir" || true
  done
  dir="$out/runs/$load/global"
  echo "delamination-sweep: load $load MPa, global search" >&2
  "$hemivem" solve "$scene" --set "loads.traction[0].value=[0.0, $traction]" -q --out "$dir" || true
done

python3 - "$out" "$loads" "$minimizers" <<'EOF'
import csv, json, os, sys
out, loads, minimizers = sys.argv[1], sys.argv[2].split(","), sys.argv[3].split()
runs = [("local", m) for m in minimizers] + [("global", "global")]
rows = []
for load in loads:
    for search, m in runs:
        d = os.path.join(out, "runs", load, "global" if search == "global" else "local-" + m)
        try:
            r = json.load(open(os.path.join(d, "result.json")))
        except OSError:
            rows.append(dict(load=load, search=search, minimizer=m, status="no result"))
            continue
        contact = r["contact"]
        separated = sum(1 for n in contact if n["u_nu"] < 0)
        debonded = sum(1 for n in contact if n["u_nu"] <= -2e-3)
        rows.append(dict(load=load, search=search, minimizer=r["backends"]["minimizer"] if search == "local" else "global",
                         status=r["status"], energy=r["potential_energy"], seconds=r["timings"]["minimize"],
                         total=r["timings"]["total"], separated=separated, debonded=debonded,
                         critical_points=len(r["critical_points"]),
                         runs=len(open(os.path.join(d, "history.csv")).read().splitlines()) - 1 if search == "global" else 1))
        if search == "global" or m == "ssn":
            with open(os.path.join(out, "profile-%s-%s.csv" % ("global" if search == "global" else "ssn", load)), "w") as f:
                f.write("x,u_nu,binding_traction\n")
                for n in contact:
                    f.write("%.9g,%.9g,%.9g\n" % (n["x"], n["u_nu"], -n["pressure"]))
keys = ["load", "search", "minimizer", "status", "energy", "seconds", "total", "separated", "debonded", "critical_points", "runs"]
with open(os.path.join(out, "sweep.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, keys)
    w.writeheader()
    for row in rows:
        w.writerow({k: row.get(k, "") for k in keys})
# the tables: energy reached and time (minimize stage) per load, every engine and the search
with open(os.path.join(out, "sweep.md"), "w") as f:
    names = [m for _, m in runs]
    header = "| load [MPa] | " + " | ".join(names) + " |\n" + "|---" * (len(names) + 1) + "|\n"
    f.write(header)
    for load in loads:
        cells = []
        best = min((r["energy"] for r in rows if r["load"] == load and r.get("status") == "converged"), default=None)
        for name in names:
            r = next(r for r in rows if r["load"] == load and r["minimizer"] == name)
            if r.get("status") != "converged":
                cells.append(r.get("status", "-"))
            else:
                mark = " **(lowest)**" if best is not None and r["energy"] <= best + 1e-9 * abs(best) else ""
                cells.append("%.6f J/m%s" % (r["energy"], mark))
        f.write("| %s | %s |\n" % (load, " | ".join(cells)))
    f.write("\n" + header)
    for load in loads:
        cells = []
        for name in names:
            r = next(r for r in rows if r["load"] == load and r["minimizer"] == name)
            cells.append("%.3g s" % r["seconds"] if "seconds" in r else "-")
        f.write("| %s | %s |\n" % (load, " | ".join(cells)))
    f.write("\n| load [MPa] | debonded nodes (s >= 2 mm), ssn alone | debonded nodes, global search | critical points found | local runs |\n|---|---|---|---|---|\n")
    for load in loads:
        r = next(r for r in rows if r["load"] == load and r["minimizer"] == "global")
        l = next(r for r in rows if r["load"] == load and r["minimizer"] == "ssn")
        f.write("| %s | %s | %s | %s | %s |\n" % (load, l.get("debonded", "-"), r.get("debonded", "-"),
                                               r.get("critical_points", "-"), r.get("runs", "-")))
# energy above the lowest found at that load against the time taken: one file per engine
for name in [m for _, m in runs]:
    with open(os.path.join(out, "work-%s.csv" % name), "w") as f:
        f.write("load,seconds,gap\n")
        for load in loads:
            best = min((r["energy"] for r in rows if r["load"] == load and r.get("status") == "converged"), default=None)
            r = next(r for r in rows if r["load"] == load and r["minimizer"] == name)
            if best is not None and r.get("status") == "converged":
                f.write("%s,%.6g,%.9g\n" % (load, r["seconds"], (r["energy"] - best) / abs(best)))
print(open(os.path.join(out, "sweep.md")).read())
EOF

if command -v gnuplot >/dev/null 2>&1; then
  plot_of() {  # the profiles of one kind of run (ssn or global), one line per load
    local p=""
    for load in "${load_list[@]}"; do
      p+="${p:+, }'$out/profile-$1-$load.csv' using (1000*\$1):(\$3/1e6) with linespoints pt 7 ps 0.4 title '$load MPa'"
    done
    echo "$p"
  }
  gnuplot <<EOF
set terminal pngcairo size 1000,760 font ',11' noenhanced
set output '$out/delamination.png'
set datafile separator ','
set key outside right title 'pulling traction'
set grid
set multiplot layout 2,1
set xlabel 'x along the bonded interface [mm] (clamped at x = 0)'
set ylabel 'binding traction -j''(u_nu) [MPa]'
set title 'ssn alone (from u = 0): the bonded branch'
plot $(plot_of ssn)
set title 'global search: the lowest critical point found'
plot $(plot_of global)
unset multiplot
EOF
  work=""
  for m in $minimizers global; do
    work+="${work:+, }'$out/work-$m.csv' using 2:3 with points pt 7 ps 1.2 title '$m'"
  done
  gnuplot <<EOF
set terminal pngcairo size 820,520 font ',11' noenhanced
set output '$out/delamination-work.png'
set datafile separator ','
set key top right
set grid
set logscale x
set format x '%g'
set xlabel 'time of the minimize stage [s]'
set ylabel '(F - F_lowest) / |F_lowest|'
set title 'Delamination, 20-27 MPa: energy reached against time (certified runs only)'
plot $work
EOF
  plot=1
fi
echo "delamination-sweep: wrote $out/sweep.csv, $out/sweep.md${plot:+, $out/delamination.png, $out/delamination-work.png}" >&2

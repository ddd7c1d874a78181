#!/usr/bin/env python3
"""The delamination benchmark loaded from zero (docs/nonconvex.md, "Loaded from zero"): follows
scenes/delamination-path.toml with `hemivem solve` in small load steps, up to MAX MPa and back
to zero, and compares the path with the static solves of scenes/delamination.toml at a few loads
(ssn alone from u = 0, and the global search).

    scripts/delamination-path.py [--build BUILD] [--out OUT] [--step MPA] [--max MPA] [--loads L1,L2,...]

BUILD defaults to build, OUT to out/delamination-path, the step to 0.01 MPa, MAX to 30 MPa,
the loads of the static solves to 20,...,27,27.2,28,29,30 MPa. Prints the jumps of the path
(PathStep.jump), the comparison with the static solves and where the bonds come back on
unloading; writes OUT/path.csv (per step of both runs: load, energy, debonded nodes, nodes past
0.5 mm and 1 mm, largest separation, jump), OUT/static.csv and, when gnuplot is installed,
OUT/delamination-path.png. A node is debonded when its separation s = -u_nu is at least 2 mm,
where the law's potential is constant (no binding force).
"""
import argparse
import collections
import csv
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(hemivem, scene, out, overrides):
    command = [hemivem, "solve", os.path.join(ROOT, "scenes", scene), "--out", out, "-q"]
    for o in overrides:
        command += ["--set", o]
    subprocess.run(command, check=True)


def counts(u_nu):
    return dict(debonded=sum(1 for u in u_nu if u <= -2e-3), past_1mm=sum(1 for u in u_nu if u < -1e-3),
                past_05mm=sum(1 for u in u_nu if u < -5e-4), separation=-min(u_nu))


def read_path(out, load_of_t):
    steps = collections.defaultdict(list)
    for r in csv.DictReader(open(os.path.join(out, "path-contact.csv"))):
        steps[int(r["step"])].append(float(r["u_nu"]))
    rows = []
    for s in json.load(open(os.path.join(out, "path.json")))["steps"]:
        row = dict(step=s["step"], t=s["t"], load=load_of_t(s["t"]), status=s["status"], energy=s["energy"],
                   jump=s["jump"], change=s["change"])
        row.update(counts(steps[s["step"]]))
        rows.append(row)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="out/delamination-path")
    parser.add_argument("--step", type=float, default=0.01, help="the load step [MPa]")
    parser.add_argument("--max", type=float, default=30.0, help="the largest load [MPa]")
    parser.add_argument("--loads", default="20,21,22,23,24,25,26,27,27.2,28,29,30",
                        help="the loads of the static solves [MPa]")
    args = parser.parse_args()
    hemivem = os.path.join(args.build, "drivers", "hemivem")
    os.makedirs(args.out, exist_ok=True)
    n = round(args.max / args.step)
    top = args.max * 1e6

    # loading: t = k / n, the traction t * max. Loading and unloading: t = k / (2 n - 1), the
    # traction max (1 - |2 f t - 1|) with f = (2 n - 1) / (2 n), up to max at step n and down to
    # one step above zero at step 2 n - 1
    f = (2.0 * n - 1.0) / (2.0 * n)
    run(hemivem, "delamination-path.toml", os.path.join(args.out, "load"),
        ["loads.traction[0].value=[0.0, %r]" % top, "path.steps=%d" % n, "path.frames=1"])
    run(hemivem, "delamination-path.toml", os.path.join(args.out, "unload"),
        ['loads.traction[0].value=[0.0, "%r*(1 - abs(2*%r*t - 1))"]' % (top, f), "path.steps=%d" % (2 * n - 1),
         "path.frames=1"])
    up = read_path(os.path.join(args.out, "load"), lambda t: args.max * t)
    both = read_path(os.path.join(args.out, "unload"), lambda t: args.max * (1.0 - abs(2.0 * f * t - 1.0)))
    down = both[n - 1:]

    keys = ["run", "step", "t", "load", "status", "energy", "debonded", "past_1mm", "past_05mm", "separation", "jump", "change"]
    with open(os.path.join(args.out, "path.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, keys)
        w.writeheader()
        for name, rows in (("load", up), ("unload", both)):
            for r in rows:
                w.writerow(dict(r, run=name))

    failed = [r for r in up + both if r["status"] != "converged"]
    print("loading to %g MPa in %d steps of %g MPa, then back to 0: %d steps, %d not converged\n"
          % (args.max, n, args.step, len(up) + len(both), len(failed)))
    print("**Jumps of the path** (PathStep.jump) on the way up:\n")
    print("| load [MPa] | nodes past 0.5 mm | past 1 mm | debonded (s >= 2 mm) | largest separation [mm] | energy before -> after [J/m] |")
    print("|---|---|---|---|---|---|")
    for before, r in zip(up, up[1:]):
        if r["jump"]:
            print("| %.2f | %d -> %d | %d -> %d | %d -> %d | %.3f -> %.3f | %.3f -> %.3f |" % (
                r["load"], before["past_05mm"], r["past_05mm"], before["past_1mm"], r["past_1mm"], before["debonded"],
                r["debonded"], 1e3 * before["separation"], 1e3 * r["separation"], before["energy"], r["energy"]))
    print()

    # the static solves
    static = []
    for load in args.loads.split(","):
        value = float(load)
        for search in ("local", "global"):
            d = os.path.join(args.out, "static", load, search)
            run(hemivem, "delamination.toml", d,
                ["loads.traction[0].value=[0.0, %r]" % (value * 1e6), 'solver.search="%s"' % search])
            r = json.load(open(os.path.join(d, "result.json")))
            row = dict(load=value, search=search, status=r["status"], energy=r["potential_energy"])
            row.update(counts([c["u_nu"] for c in r["contact"]]))
            static.append(row)
    with open(os.path.join(args.out, "static.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, ["load", "search", "status", "energy", "debonded", "past_1mm", "past_05mm", "separation"])
        w.writeheader()
        w.writerows(static)
    print("**The path against the static solves** (energy in J/m; debonded nodes in parentheses):\n")
    print("| load [MPa] | path from zero | ssn alone from u = 0 | global search (lowest found) | path - lowest |")
    print("|---|---|---|---|---|")
    for load in args.loads.split(","):
        value = float(load)
        p = min(up, key=lambda r: abs(r["load"] - value))
        loc = next(r for r in static if r["load"] == value and r["search"] == "local")
        glo = next(r for r in static if r["load"] == value and r["search"] == "global")
        cell = lambda r: "%.6f (%d)" % (r["energy"], r["debonded"]) if r.get("status", "converged") == "converged" else r["status"]
        print("| %s | %s | %s | %s | %.3g |" % (load, cell(p), cell(loc), cell(glo), p["energy"] - glo["energy"]))
    print()

    print("**Unloading** from %g MPa: the debonded nodes as the load falls\n" % args.max)
    print("| load [MPa] | debonded | largest separation [mm] | energy [J/m] | jump |")
    print("|---|---|---|---|---|")
    for before, r in zip(down, down[1:]):
        if r["debonded"] != before["debonded"] and (r["debonded"] == 0 or r["debonded"] % 5 == 0 or r["jump"]):
            print("| %.2f | %d -> %d | %.3f -> %.3f | %.3f -> %.3f | %s |" % (
                r["load"], before["debonded"], r["debonded"], 1e3 * before["separation"], 1e3 * r["separation"],
                before["energy"], r["energy"], "yes" if r["jump"] else "no"))

    if shutil.which("gnuplot"):
        data = os.path.join(args.out, "path.csv")
        stat = os.path.join(args.out, "static.csv")
        script = """set terminal pngcairo size 900,760 font ',11' noenhanced
set output '{png}'
set datafile separator ','
set key top left
set grid
set multiplot layout 2,1
set xlabel 'pulling traction [MPa]'
set ylabel 'potential energy [J/m]'
set title 'Delamination loaded from zero (ssn from the step before, steps of {step} MPa)'
plot '{data}' using (strcol(1) eq "load" ? $4 : 1/0):6 with lines lw 2 title 'path, loading', \\
     '{data}' using (strcol(1) eq "unload" && $2 >= {n} ? $4 : 1/0):6 with lines lw 2 dt 2 title 'path, unloading', \\
     '{stat}' using (strcol(2) eq "local" ? $1 : 1/0):4 with points pt 6 ps 1.5 title 'ssn alone from u = 0', \\
     '{stat}' using (strcol(2) eq "global" ? $1 : 1/0):4 with points pt 7 ps 1 title 'global search'
set ylabel 'debonded nodes (s >= 2 mm, of 64)'
set title ''
plot '{data}' using (strcol(1) eq "load" ? $4 : 1/0):7 with lines lw 2 title 'path, loading', \\
     '{data}' using (strcol(1) eq "unload" && $2 >= {n} ? $4 : 1/0):7 with lines lw 2 dt 2 title 'path, unloading', \\
     '{stat}' using (strcol(2) eq "global" ? $1 : 1/0):5 with points pt 7 ps 1 title 'global search'
unset multiplot
""".format(png=os.path.join(args.out, "delamination-path.png"), data=data, stat=stat, step=args.step, n=n)
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
        print("\nwrote %s" % os.path.join(args.out, "delamination-path.png"), file=sys.stderr)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The Cattaneo-Mindlin validation of docs/paths.md: solves scenes/cattaneo-mindlin.toml along
its path with `hemivem solve` and compares, step by step, the stick zone with
c = a sqrt(1 - Q / (mu P)), a = sqrt(4 P R / (pi E*)) Hertz's half-width for the computed
normal force P, Q the computed tangential force.

    scripts/cattaneo-mindlin.py [--build BUILD] [--out OUT] [--fine H] [--block W D] [--set KEY=VALUE ...]

BUILD defaults to build, OUT to out/cattaneo-mindlin. --fine H solves on a mesh refined to H
under the cylinder instead of the scene's, --block W D on the block [-W, W] x [-D, 0] instead of
[-2, 2] x [-2, 0] (either mesh written to OUT by scripts/make-graded-block-poly2d.py);
--set is passed to `hemivem solve` (e.g. --set material.nu=0.29). Prints the table of docs/paths.md
and writes OUT/stick-zone.csv (one row per step), OUT/traction.csv (the friction traction over the
contact at three steps, positive along the tangential force, with Cattaneo and Mindlin's) and, when gnuplot is installed,
OUT/cattaneo-mindlin.png.

The stick zone measured is the span of the nodes in contact whose slip in the step is zero,
widened by half a node spacing h at each end: c_h = (x_max - x_min + h) / 2 (its edge lies
between the last node that sticks and the first that slips); the contact zone likewise.
"""
import argparse
import collections
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="out/cattaneo-mindlin")
    parser.add_argument("--fine", type=float, help="the finest squares' side of a mesh made for this run")
    parser.add_argument("--block", type=float, nargs=2, metavar=("W", "D"), help="the block [-W, W] x [-D, 0]")
    parser.add_argument("--set", action="append", default=[], dest="overrides")
    args = parser.parse_args()

    os.makedirs(args.out, exist_ok=True)
    command = [os.path.join(args.build, "drivers", "hemivem"), "solve", os.path.join(ROOT, "scenes", "cattaneo-mindlin.toml"),
               "--out", os.path.join(args.out, "run"), "-q"]
    if args.fine or args.block:
        mesh = os.path.abspath(os.path.join(args.out, "graded-block.poly2d"))
        make = [sys.executable, os.path.join(HERE, "make-graded-block-poly2d.py"), mesh]
        if args.fine:
            make += ["--fine", repr(args.fine)]
        if args.block:
            make += ["--width", repr(args.block[0]), "--depth", repr(args.block[1])]
        subprocess.run(make, check=True)
        command += ["--set", 'mesh.file="%s"' % mesh]
    for o in args.overrides:
        command += ["--set", o]
    subprocess.run(command, check=True)
    run = os.path.join(args.out, "run")

    scene = tomllib.load(open(os.path.join(run, "scene.toml"), "rb"))
    E, nu = scene["material"]["E"], scene["material"]["nu"]
    mu = scene["contact"]["friction"]["coefficient"]
    R = scene["contact"]["obstacle"]["radius"]
    Estar = E / (1.0 - nu * nu)
    beta = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))

    steps = collections.OrderedDict()
    for r in csv.DictReader(open(os.path.join(run, "path-contact.csv"))):
        steps.setdefault(int(r["step"]), []).append(r)
    status = {s["step"]: s["status"] for s in json.load(open(os.path.join(run, "path.json")))["steps"]}

    rows, profiles = [], {}
    for k, nodes in steps.items():
        nodes.sort(key=lambda r: float(r["x"]))
        xs = [float(r["x"]) for r in nodes]
        h = min(b - a for a, b in zip(xs, xs[1:]))
        force = lambda r: float(r["law_force"]) + float(r["reaction"])
        contact = [r for r in nodes if force(r) > 0.0]
        P = sum(force(r) for r in nodes)
        Q = abs(sum(float(r["friction_force"]) for r in nodes))
        a = math.sqrt(4.0 * P * R / (math.pi * Estar))
        zone = 0.5 * (float(contact[-1]["x"]) - float(contact[0]["x"]) + h)
        stick = [float(r["x"]) for r in contact if r["friction_state"] == "stick"]
        ratio = Q / (mu * P)
        c = 0.5 * (max(stick) - min(stick) + h) if stick else 0.0
        centre = 0.5 * (max(stick) + min(stick)) if stick else float("nan")
        c_theory = a * math.sqrt(max(0.0, 1.0 - ratio))
        rows.append(dict(step=k, t=float(nodes[0]["t"]), status=status.get(k, "?"), P=P, Q=Q, ratio=ratio, a=a,
                         zone=zone, contact=len(contact), stick=len(stick), c=c, c_theory=c_theory, h=h, centre=centre))
        profiles[k] = (contact, P, a, ratio)

    with open(os.path.join(args.out, "stick-zone.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    print("E = %g, nu = %g (Dundurs' beta = %.4f), mu = %g, R = %g; h = %.6g under the cylinder\n" % (E, nu, beta, mu, R, rows[0]["h"]))
    print("| t | P | Q / (mu P) | a (Hertz) | contact zone (nodes) | stick nodes | c measured | c = a sqrt(1 - Q/(mu P)) | difference | centre of the stick zone |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        d = r["c"] - r["c_theory"]
        print("| %.2f | %.5f | %.3f | %.5f | %.5f (%d) | %d | %.5f | %.5f | %+.5f (%+.2f h) | %s |" % (
            r["t"], r["P"], r["ratio"], r["a"], r["zone"], r["contact"], r["stick"], r["c"], r["c_theory"], d, d / r["h"],
            "%+.5f" % r["centre"] if r["stick"] else "-"))
        if r["status"] != "converged":
            print("  step %d: %s" % (r["step"], r["status"]))

    # the friction traction at three steps, against q(x) = mu p0 (sqrt(1 - x^2/a^2) - (c/a) sqrt(1 - x^2/c^2))
    chosen = []
    for target in (0.25, 0.5, 0.75):
        sheared = [r for r in rows if 0.0 < r["ratio"] < 1.0]
        if sheared:
            chosen.append(min(sheared, key=lambda r: abs(r["ratio"] - target)))
    with open(os.path.join(args.out, "traction.csv"), "w") as f:
        f.write("step,ratio,x_over_a,q_over_mu_p0,theory\n")
        for r in chosen:
            contact, P, a, ratio = profiles[r["step"]]
            p0 = 2.0 * P / (math.pi * a)
            c = a * math.sqrt(1.0 - ratio)
            sign = 1.0 if sum(float(n["friction_force"]) for n in contact) >= 0.0 else -1.0
            for n in contact:
                x = float(n["x"])
                weight = force(n) / float(n["pressure"])
                q = sign * float(n["friction_force"]) / weight  # positive along the resultant
                s = lambda half: math.sqrt(max(0.0, 1.0 - (x / half) ** 2))
                theory = s(a) - (c / a) * s(c)
                f.write("%d,%.4f,%.6g,%.6g,%.6g\n" % (r["step"], ratio, x / a, q / (mu * p0), theory))
            f.write("\n\n")
    if shutil.which("gnuplot") and chosen:
        low = "0" if all(float(l.split(",")[3]) >= 0.0 for l in open(os.path.join(args.out, "traction.csv")).read().split("\n")[1:]
                         if l.count(",") == 4) else "-1.1"
        plots = []
        for i, r in enumerate(chosen):
            plots.append("'%s' index %d using 3:4 with points pt 7 ps 0.5 lc %d title 'Q/(mu P) = %.2f, hemivem'"
                         % (os.path.join(args.out, "traction.csv"), i, i + 1, r["ratio"]))
            plots.append("'%s' index %d using 3:5 with lines lw 2 lc %d title 'Cattaneo-Mindlin'"
                         % (os.path.join(args.out, "traction.csv"), i, i + 1))
        script = """set terminal pngcairo size 900,560 font ',11' noenhanced
set output '%s'
set datafile separator ','
set key outside right
set grid
set xlabel 'x / a'
set ylabel 'friction traction / (mu p0)'
set title 'Cattaneo-Mindlin: E = %g, nu = %g, mu = %g; h = %.3g'
plot [-1.1:1.1] [%s:1.1] %s
""" % (os.path.join(args.out, "cattaneo-mindlin.png"), E, nu, mu, rows[0]["h"], low, ", ".join(plots))
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
        print("\nwrote %s" % os.path.join(args.out, "cattaneo-mindlin.png"), file=sys.stderr)


if __name__ == "__main__":
    main()

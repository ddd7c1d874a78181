#!/usr/bin/env python3
"""Nonconvex methods compared by the energy they reach and the time they take.

The delamination benchmark of docs/nonconvex.md (scenes/delamination.toml: a layer pulled
off its adhesive, a law with three concave kinks, several critical points). For each pulling
traction the scene is condensed once (hemivem.condense); then every built minimizer runs
alone from a = 0 and the global search runs with all of them (hemivem.minimize(...,
search="global")). Each result is certified by the one certificate (docs/reference/certificate.md); the table
gives F (the reduced objective, J/m), how far above the lowest found it is, and the time; the
figure plots that gap against the time.

    PYTHONPATH=build/python python3 examples/python/delamination.py [--loads 20,24,27]
        [--n 64,8] [--max-starts 64] [--out delamination.png]
"""

import argparse
import pathlib
import time

import hemivem

SCENE = pathlib.Path(__file__).resolve().parents[2] / "scenes" / "delamination.toml"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loads", default="20,24,27", help="pulling tractions in MPa, comma-separated")
    parser.add_argument("--n", default="64,8", help="cells along x and y")
    parser.add_argument("--max-starts", type=int, default=64, help="local runs of the global search")
    parser.add_argument("--out", default="delamination.png", help="the figure (needs matplotlib)")
    args = parser.parse_args()

    scene = hemivem.Scene.from_toml(SCENE)
    scene.set("mesh.n", [int(k) for k in args.n.split(",")])
    engines = hemivem.available_engines()["minimizer"]
    points = {name: [] for name in engines + ["global"]}
    print(f"{'load [MPa]':>10} {'method':>17} {'status':>10} {'F [J/m]':>16} {'above lowest':>13} {'seconds':>9}")
    for load in (float(x) for x in args.loads.split(",")):
        scene.set("loads.traction[0].value", [0.0, load * 1e6])
        p = hemivem.condense(scene)
        runs = {}
        for name in engines:
            t = time.perf_counter()
            runs[name] = (hemivem.minimize(p, name), time.perf_counter() - t)
        t = time.perf_counter()
        runs["global"] = (hemivem.minimize(p, "ssn", search="global", max_starts=args.max_starts),
                          time.perf_counter() - t)
        lowest = min(r.objective for r, _ in runs.values() if r.converged)
        for name, (r, seconds) in runs.items():
            gap = (r.objective - lowest) / abs(lowest)
            if r.converged:
                points[name].append((seconds, gap))
            shown = f"{gap:13.3%}" if r.converged else f"{'-':>13}"
            print(f"{load:10g} {name:>17} {r.status:>10} {r.objective:16.6f} {shown} {seconds:9.4f}")
        g = runs["global"][0]
        print(f"{'':10} {'':17} the search: {len(g.critical_points)} critical point(s) from "
              f"{len(g.history['iteration'])} local runs")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no figure")
        return
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for name, xy in points.items():
        if xy:
            ax.scatter([x for x, _ in xy], [y for _, y in xy], label=name, s=36)
    ax.set_xscale("log")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("(F - F_lowest) / |F_lowest|")
    ax.set_title(f"Delamination, {args.loads} MPa: energy reached against time (certified runs)")
    ax.grid(True, alpha=0.4)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

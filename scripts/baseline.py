#!/usr/bin/env python3
"""Records or compares the numbers of reference runs of the command, bit for bit.

A refactoring must not change what a solve computes. This script runs the plane default
solve (Example 4.1 on 64 x 64 squares) and the solid one (scenes/example-4.1-3d.toml, on 8 x 4
x 8 and 16 x 8 x 16 cubes) with the command in build/, and records for each the certificate,
the potential energy and a SHA-256 of the displacement's doubles (result.json and
displacement.csv are read back; displacement.csv prints 17 significant digits, enough to
round-trip a double). `record FILE` writes them as JSON; `compare FILE` runs them again and
fails naming every number that differs. The bits depend on the machine (the BLAS picks its
kernels by the processor), so compare on the machine that recorded.

Usage: scripts/baseline.py record|compare FILE [--build DIR]
"""
import argparse
import csv
import hashlib
import json
import os
import struct
import subprocess
import sys
import tempfile

RUNS = {
    "plane-default": [],
    "solid-example-4.1-3d": ["scenes/example-4.1-3d.toml"],
    "solid-example-4.1-3d-n16": ["scenes/example-4.1-3d.toml", "--set", "mesh.n=[16, 8, 16]"],
}


def run(build, args):
    with tempfile.TemporaryDirectory() as out:
        cmd = [os.path.join(build, "drivers", "hemivem"), "solve", *args, "--out", out, "--json"]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"baseline: {' '.join(cmd)} exited {p.returncode}: {p.stderr}")
        result = json.loads(p.stdout)
        digest = hashlib.sha256()
        with open(os.path.join(out, "displacement.csv")) as f:
            for row in csv.DictReader(f):
                for key in sorted(k for k in row if k.startswith("u")):
                    digest.update(struct.pack("<d", float(row[key])))
        return {
            "status": result["status"],
            "certificate": {k: result["certificate"][k] for k in ("primal", "dual")},
            "energy": result.get("potential_energy"),
            "uniqueness_margin": result.get("uniqueness_margin"),
            "iterations": result.get("iterations"),
            "displacement_sha256": digest.hexdigest(),
        }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("action", choices=["record", "compare"])
    parser.add_argument("file")
    parser.add_argument("--build", default="build")
    a = parser.parse_args()
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    now = {name: run(a.build, args) for name, args in RUNS.items()}
    if a.action == "record":
        with open(a.file, "w") as f:
            json.dump(now, f, indent=2)
        print(f"baseline: recorded {len(now)} runs in {a.file}")
        return 0
    with open(a.file) as f:
        then = json.load(f)
    bad = [f"{name}: {then.get(name)} != {numbers}" for name, numbers in now.items() if then.get(name) != numbers]
    for line in bad:
        print("baseline: differs:", line)
    print(f"baseline: {len(now) - len(bad)} of {len(now)} runs bit for bit")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

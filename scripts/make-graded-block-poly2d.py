#!/usr/bin/env python3
"""Writes a .poly2d mesh (docs/reference/poly2d.md) of the block [-WIDTH, WIDTH] x [-DEPTH, 0]
made of squares refined towards a segment of its top side: a quadtree. The block is cut into
squares of side BASE; a square is split into four while it is larger than FINE and larger than
GRADING times its distance to the segment [-HALF, HALF] x {0}; then squares are split until
neighbours differ by at most one level (each side carries at most one hanging vertex, at its
midpoint). A square whose neighbour across a side is split lists that midpoint as a fifth
vertex: a polygon the virtual element method takes as it is, so the mesh is conforming.

scenes/cattaneo-mindlin.toml reads scenes/meshes/graded-block.poly2d, the default: the block
[-2, 2] x [-2, 0] in squares of 1/8 refined to 1/512 (about 0.002) on the top within
|x| <= 0.15, where the cylinder touches, each square at most 0.15 times as large as its distance
from there (5515 vertices, 5186 elements).

Usage: scripts/make-graded-block-poly2d.py [OUTPUT] [--fine H] [--half W] [--grading G]
       [--width W] [--depth D]   (deterministic: the same file every time; OUTPUT defaults to
       scenes/meshes/graded-block.poly2d)
"""
import argparse
import math
import os
import sys

BASE = 0.125
GRADING = 0.15


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("output", nargs="?", default=os.path.join(here, "..", "scenes", "meshes", "graded-block.poly2d"))
    parser.add_argument("--fine", type=float, default=BASE / 64, help="the side of the finest squares (BASE / 2^k)")
    parser.add_argument("--half", type=float, default=0.15, help="the half-width of the refined segment of the top")
    parser.add_argument("--width", type=float, default=2.0, help="the block is [-WIDTH, WIDTH] x [-DEPTH, 0]")
    parser.add_argument("--depth", type=float, default=2.0, help="the block's depth")
    parser.add_argument("--grading", type=float, default=GRADING,
                        help="the largest ratio of a square's side to its distance from the segment")
    args = parser.parse_args()

    x0, x1, y0 = -args.width, args.width, -args.depth
    levels = round(math.log2(BASE / args.fine))
    if levels < 0 or abs(BASE / 2**levels - args.fine) > 1e-12 * BASE:
        sys.exit("--fine must be %g / 2^k" % BASE)
    unit = 2**levels                       # a base square is `unit` finest squares wide
    hf = BASE / unit
    nx, ny = round((x1 - x0) / BASE), round(-y0 / BASE)
    if abs(nx * BASE - (x1 - x0)) > 1e-12 or abs(ny * BASE + y0) > 1e-12:
        sys.exit("the width and the depth must be multiples of %g" % BASE)

    def distance(i, j, s):
        """Distance (in metres) from the square (i, j, s) (finest-grid units) to the segment."""
        xa, xb = x0 + i * hf, x0 + (i + s) * hf
        yb = y0 + (j + s) * hf
        dx = max(0.0, xa - args.half, -args.half - xb)
        dy = max(0.0, -yb)
        return math.hypot(dx, dy)

    # the quadtree's leaves: (i, j, s), i and j the lower-left corner on the finest grid
    leaves = set()
    stack = [(a * unit, b * unit, unit) for a in range(nx) for b in range(ny)]
    while stack:
        i, j, s = stack.pop()
        size = s * hf
        if s > 1 and size > args.grading * distance(i, j, s) + 1e-12:
            h = s // 2
            stack += [(i, j, h), (i + h, j, h), (i, j + h, h), (i + h, j + h, h)]
        else:
            leaves.add((i, j, s))

    # 2:1 balance: the leaf covering each finest cell; split a leaf while a neighbour across one
    # of its sides is more than twice smaller
    W, H = nx * unit, ny * unit

    def leaf_at(i, j):
        """The leaf holding the finest cell (i, j)."""
        s = 1
        while s <= unit:
            key = (i - i % s, j - j % s, s)
            if key in leaves:
                return key
            s *= 2
        raise RuntimeError("no leaf at %d %d" % (i, j))

    changed = True
    while changed:
        changed = False
        for (i, j, s) in sorted(leaves, key=lambda k: -k[2]):
            if (i, j, s) not in leaves or s < 4:
                continue
            # finest cells just outside each side
            outside = []
            for k in range(s):
                outside += [(i + k, j - 1), (i + k, j + s), (i - 1, j + k), (i + s, j + k)]
            if any(0 <= a < W and 0 <= b < H and leaf_at(a, b)[2] * 2 < s for a, b in outside):
                leaves.discard((i, j, s))
                h = s // 2
                leaves.update([(i, j, h), (i + h, j, h), (i, j + h, h), (i + h, j + h, h)])
                changed = True

    corners = set()
    for (i, j, s) in leaves:
        corners.update([(i, j), (i + s, j), (i + s, j + s), (i, j + s)])
    vertices = sorted(corners, key=lambda p: (p[1], p[0]))
    index = {p: k for k, p in enumerate(vertices)}
    elements = []
    for (i, j, s) in sorted(leaves, key=lambda k: (k[1], k[0])):
        h = s // 2
        ring = []
        for corner, mid in (((i, j), (i + h, j)), ((i + s, j), (i + s, j + h)),
                            ((i + s, j + s), (i + h, j + s)), ((i, j + s), (i, j + h))):
            ring.append(index[corner])
            if s > 1 and mid in index:
                ring.append(index[mid])
        elements.append(ring)

    with open(args.output, "w") as f:
        f.write("# the block [%g, %g] x [%g, 0]: squares of %g refined to %g towards the top within |x| <= %g\n"
                % (x0, x1, y0, BASE, hf, args.half))
        f.write("# written by scripts/make-graded-block-poly2d.py --fine %r --half %r --grading %r --width %r --depth %r\n"
                % (args.fine, args.half, args.grading, args.width, args.depth))
        f.write("vertices %d\n" % len(vertices))
        for (i, j) in vertices:
            f.write("%.17g %.17g\n" % (x0 + i * hf, y0 + j * hf))
        f.write("elements %d\n" % len(elements))
        for ring in elements:
            f.write("%d %s\n" % (len(ring), " ".join(map(str, ring))))
    print("%s: %d vertices, %d elements, finest side %g" % (args.output, len(vertices), len(elements), hf),
          file=sys.stderr)


if __name__ == "__main__":
    main()

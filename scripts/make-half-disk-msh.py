#!/usr/bin/env python3
"""Writes scenes/meshes/half-disk.msh: a Gmsh 4.1 ASCII mesh of the lower half of the disk of
radius 1 centred at (0, 1) (flat side on top, y = 1; the arc touches y = 0 at x = 0), made of
triangles between concentric rings, symmetric about x = 0. The outer BAND rings have
ARC_SEGMENTS arcs each and are spaced like the arc's nodes (near the boundary the triangles
are halves of near-squares of side pi / 256); inside them INNER evenly spaced rings, ring i
with 4 i arcs. The arc's nodes lie exactly on the circle. Physical groups: the
curve "arc" (tag 1), the curve "top" (tag 2), the surface "body" (tag 3).

Usage: scripts/make-half-disk-msh.py [OUTPUT]   (deterministic: the same file every time)
"""
import math
import sys

ARC_SEGMENTS = 256            # arcs of the body's boundary: 257 nodes, spacing pi / 256
BAND = 8                      # rings of ARC_SEGMENTS arcs, spaced like the arc's nodes
INNER = 40                    # inner rings: ring i has 4 i arcs
RADIUS, CENTRE = 1.0, (0.0, 1.0)


def radii():
    """(radius, number of arcs) of every ring but the centre, inside out."""
    h = math.pi * RADIUS / ARC_SEGMENTS
    inner = RADIUS - BAND * h
    rings = [(inner * i / INNER, 4 * i) for i in range(1, INNER + 1)]
    rings += [(RADIUS - j * h, ARC_SEGMENTS) for j in range(BAND - 1, -1, -1)]
    return rings


def ring(r, n):
    """Node coordinates of a ring, angle pi -> 2 pi (left corner, bottom, right corner)."""
    pts = []
    for k in range(n + 1):
        t = math.pi + math.pi * k / n
        x, y = CENTRE[0] + r * math.cos(t), CENTRE[1] + r * math.sin(t)
        if k == 0 or k == n:  # on the flat side exactly
            y = CENTRE[1]
        pts.append((x, y))
    return pts


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/meshes/half-disk.msh"
    rings = [[CENTRE]] + [ring(r, n) for r, n in radii()]
    last = len(rings) - 1
    ids = []  # ids[i][k]: node tag of point k of ring i
    coords = {}
    tag = 0
    for pts in rings:
        row = []
        for p in pts:
            tag += 1
            coords[tag] = p
            row.append(tag)
        ids.append(row)

    def ccw(a, b, c):
        (ax, ay), (bx, by), (cx, cy) = coords[a], coords[b], coords[c]
        return (a, b, c) if (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) > 0 else (a, c, b)

    triangles = []
    for i in range(1, last + 1):
        inner, outer = ids[i - 1], ids[i]
        if i == 1:
            for k in range(len(outer) - 1):
                triangles.append(ccw(inner[0], outer[k], outer[k + 1]))
            continue
        # the left quarter (angle pi -> 3 pi / 2) advancing along both rings by angle, and
        # its mirror image, so that the mesh is symmetric about x = 0
        ni, no = len(inner) - 1, len(outer) - 1
        a, b = 0, 0
        while a < ni // 2 or b < no // 2:
            if b < no // 2 and (a == ni // 2 or (b + 1) / no <= (a + 1) / ni):
                tri = ((0, a), (1, b), (1, b + 1))
                b += 1
            else:
                tri = ((0, a), (1, b), (0, a + 1))
                a += 1
            for mirror in (False, True):
                nodes = [(inner, ni) if r == 0 else (outer, no) for r, _ in tri]
                t = [ring_[n - k if mirror else k] for (ring_, n), (_, k) in zip(nodes, tri)]
                triangles.append(ccw(*t))

    arc = ids[last]                                     # left corner -> bottom -> right corner
    top = [ids[i][-1] for i in range(last, 0, -1)] + [ids[0][0]] + [ids[i][0] for i in range(1, last + 1)]
    left, right = arc[0], arc[-1]
    on_curve = set(arc) | set(top)

    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat",
             "$PhysicalNames", "3", '1 1 "arc"', '1 2 "top"', '2 3 "body"', "$EndPhysicalNames",
             "$Entities", "2 2 1 0"]
    lx, ly = coords[left]
    rx, ry = coords[right]
    lines += [f"1 {lx!r} {ly!r} 0 0", f"2 {rx!r} {ry!r} 0 0"]
    lines += [f"1 -1 0 0 1 1 0 1 1 2 1 -2", f"2 -1 1 0 1 1 0 1 2 2 2 -1",
              f"1 -1 0 0 1 1 0 1 3 2 1 2", "$EndEntities"]

    blocks = [(0, 1, [left]), (0, 2, [right]), (1, 1, arc[1:-1]), (1, 2, top[1:-1]),
              (2, 1, [t for t in sorted(coords) if t not in on_curve])]
    lines += ["$Nodes", f"{len(blocks)} {len(coords)} 1 {len(coords)}"]
    for dim, ent, tags in blocks:
        lines.append(f"{dim} {ent} 0 {len(tags)}")
        lines += [str(t) for t in tags]
        lines += [f"{coords[t][0]!r} {coords[t][1]!r} 0" for t in tags]
    lines.append("$EndNodes")

    arc_lines = list(zip(arc[:-1], arc[1:]))
    top_lines = list(zip(top[:-1], top[1:]))
    count = len(arc_lines) + len(top_lines) + len(triangles)
    lines += ["$Elements", f"3 {count} 1 {count}"]
    tag = 0
    for ent, segs in ((1, arc_lines), (2, top_lines)):
        lines.append(f"1 {ent} 1 {len(segs)}")
        for a, b in segs:
            tag += 1
            lines.append(f"{tag} {a} {b}")
    lines.append(f"2 1 2 {len(triangles)}")
    for t in triangles:
        tag += 1
        lines.append(f"{tag} {t[0]} {t[1]} {t[2]}")
    lines.append("$EndElements")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()

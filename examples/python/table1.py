#!/usr/bin/env python3
"""Table 1 of Feng, Han and Huang (2021) from Python: the relative energy error of Example 4.1
on N x N squares against the h = 1/256 solution, and its figure (table1.png).

On squares the virtual element space is the bilinear (Q1) space, so each coarse solution is
prolonged exactly to the reference mesh by bilinear interpolation, and the error is the exact
energy (sigma(v), eps(v)) of the bilinear difference v, integrated with 2 x 2 Gauss points (exact
for bilinear fields). `hemivem study` computes the same table in C++ (docs/table1.md); this
script does it with NumPy on hemivem.solve's displacements.

    PYTHONPATH=build/python python3 examples/python/table1.py [--out table1.png] [--ref 256]
"""

import argparse
import math

import numpy as np

import hemivem

PAPER = {4: 52.07, 8: 30.67, 16: 17.89, 32: 10.31, 64: 5.602}


def grid(u, n):
    """The displacement (num_vertices, 2) of n x n squares as an (n+1, n+1, 2) grid [j, i]."""
    return u.reshape(n + 1, n + 1, 2)


def prolong(coarse, n, m):
    """Bilinear interpolation of an (n+1)^2 grid of vectors to the vertices of m x m squares."""
    x = np.linspace(0.0, 1.0, m + 1)
    cell = np.minimum((x * n).astype(int), n - 1)
    t = x * n - cell
    c = grid(coarse, n)
    J, I = cell[:, None], cell[None, :]
    s, r = t[:, None, None], t[None, :, None]
    return ((1 - s) * (1 - r) * c[J, I] + (1 - s) * r * c[J, I + 1] + s * r * c[J + 1, I + 1] + s * (1 - r) * c[J + 1, I])


def q1_stiffness(E, nu):
    """The 8 x 8 stiffness of a bilinear element on a square (plane strain; independent of its
    size), corners (0,0), (1,0), (1,1), (0,1), dofs (ux, uy) per corner."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    C = np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])
    K = np.zeros((8, 8))
    g = 0.5 + np.array([-1, 1]) / (2 * math.sqrt(3))
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]
    for xi in g:
        for eta in g:
            B = np.zeros((3, 8))
            for k, (a, b) in enumerate(corners):
                dx = (1 if a else -1) * (eta if b else 1 - eta)
                dy = (1 if b else -1) * (xi if a else 1 - xi)
                B[0, 2 * k], B[1, 2 * k + 1] = dx, dy
                B[2, 2 * k], B[2, 2 * k + 1] = dy, dx
            K += 0.25 * B.T @ C @ B
    return K


def energy(v, m, K):
    """(sigma(v), eps(v)) of the bilinear field with vertex values v, an (m+1, m+1, 2) grid."""
    d = np.concatenate([v[:-1, :-1], v[:-1, 1:], v[1:, 1:], v[1:, :-1]], axis=2).reshape(-1, 8)
    return float(np.einsum("ei,ij,ej->", d, K, d))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ns", default="4,8,16,32,64", help="coarse meshes (comma-separated N)")
    parser.add_argument("--ref", type=int, default=256, help="N of the reference mesh")
    parser.add_argument("--out", default="table1.png", help="the figure")
    args = parser.parse_args()
    ns = [int(n) for n in args.ns.split(",")]
    if any(args.ref % n for n in ns):
        parser.error("every N must divide the reference N (nested meshes)")

    scene = hemivem.Scene.default()
    E, nu = scene.get("material.E"), scene.get("material.nu")
    K = q1_stiffness(E, nu)

    def solve(n):
        s = scene.copy()
        s.set("mesh.n", n)
        r = hemivem.solve(s)
        if not r.converged:
            raise SystemExit(f"N = {n}: {r.status}: {r.message}")
        return r

    ref = solve(args.ref)
    u_ref = grid(ref.displacement, args.ref)
    norm = energy(u_ref, args.ref, K)
    print(f"Example 4.1, relative energy error against N = {args.ref} "
          f"({ref.linear} + {ref.minimizer}, certificate {ref.certificate.worst:.1e})")
    print(f"{'h':>8} {'hemivem':>10} {'paper':>10} {'rate':>6}")
    errors = []
    for n in ns:
        e = math.sqrt(energy(u_ref - prolong(solve(n).displacement, n, args.ref), args.ref, K) / norm)
        rate = "" if not errors else f"{math.log2(errors[-1] / e):6.2f}"
        errors.append(e)
        paper = f"{PAPER[n]:9.2f}%" if n in PAPER else f"{'-':>10}"
        print(f"{'1/' + str(n):>8} {100 * e:9.2f}% {paper} {rate}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = [1.0 / n for n in ns]
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.loglog(h, [100 * e for e in errors], "o-", label="hemivem (Python)")
    paper_ns = [n for n in ns if n in PAPER]
    ax.loglog([1.0 / n for n in paper_ns], [PAPER[n] for n in paper_ns], "s--", label="paper, Table 1")
    ax.loglog(h, [100 * errors[0] * (x / h[0]) for x in h], ":", color="gray", label="O(h)")
    ax.set_xlabel("h")
    ax.set_ylabel(f"relative energy error against h = 1/{args.ref} [%]")
    ax.set_title("Example 4.1 on squares")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

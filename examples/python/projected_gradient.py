#!/usr/bin/env python3
"""A minimizer of one's own against hemivem's `ssn`, judged by the same certificate.

The reduced problem of Example 4.1 (hemivem.condense) is min F(a) = 1/2 a^T S a - c^T a +
sum_i w_i j(a_i) over the box |a_i| <= g_i. Below, a plain projected-gradient method written
in NumPy: a <- P_C(a - t (S a - c + w j'(a))) with the fixed step t = 1 / (lambda_max(S) +
alpha_j max w) (the gradient's Lipschitz constant: j' is alpha_j-semi-Lipschitz for the
paper's law, which has no kink). It stops when reduced.certificate(a) — hemivem::certify, the
rule that decides "converged" for every built-in engine — says converged, and is then
compared with ssn.

    PYTHONPATH=build/python python3 examples/python/projected_gradient.py [--n 16] [--tol 1e-10]
"""

import argparse
import time

import numpy as np

import hemivem


def projected_gradient(p, tol, max_iterations=200000):
    S, c, w = np.asarray(p.S), p.c, p.w
    law, lower, upper = p.law, p.lower, p.upper
    step = 1.0 / (np.linalg.eigvalsh(S)[-1] + law.alpha * w.max())
    a = np.zeros(p.size)
    for k in range(1, max_iterations + 1):
        grad = S @ a - c + w * law.derivative(a)
        a = np.clip(a - step * grad, lower, upper)
        if k % 10 == 0 and p.certificate(a, tol).converged:
            return a, k
    return a, max_iterations


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=16, help="N x N squares")
    parser.add_argument("--tol", type=float, default=1e-10, help="tolerance of the certificate")
    args = parser.parse_args()

    scene = hemivem.Scene.default()
    scene.set("mesh.n", args.n)
    p = hemivem.condense(scene)
    print(f"{p!r}: {p.size} contact nodes, S {p.S.shape}, law {p.law.name} (alpha_j = {p.law.alpha:g})")

    t = time.perf_counter()
    a, iterations = projected_gradient(p, args.tol)
    mine_seconds = time.perf_counter() - t
    mine = p.certify(a, args.tol)

    ssn = hemivem.minimize(p, "ssn", tolerance=args.tol)
    print(f"{'':18} {'iterations':>10} {'primal':>10} {'dual':>10} {'F(a)':>16} {'seconds':>9}")
    print(f"{'projected gradient':18} {iterations:10d} {mine.certificate.primal:10.2e} {mine.certificate.dual:10.2e} "
          f"{p.energy(mine.a):16.12f} {mine_seconds:9.4f}")
    print(f"{'ssn':18} {ssn.iterations:10d} {ssn.certificate.primal:10.2e} {ssn.certificate.dual:10.2e} "
          f"{ssn.objective:16.12f} {ssn.timings['total']:9.4f}")
    diff = np.max(np.abs(mine.a - ssn.a)) / np.max(np.abs(ssn.a))
    at_bound = int(np.sum((mine.a == p.lower) | (mine.a == p.upper)))
    print(f"max |a - a_ssn| / max |a_ssn| = {diff:.2e}; nodes at the bound: {at_bound} "
          f"(ssn: {int(np.sum((ssn.a == p.lower) | (ssn.a == p.upper)))}); "
          f"uniqueness margin {p.uniqueness_margin:.4g} ({'unique' if p.uniqueness_margin > 0 else 'maybe several'})")
    if not mine.converged:
        raise SystemExit("the projected gradient did not reach the certificate's tolerance")
    u = p.back_substitute(mine.a)
    print(f"displacement from the projected gradient's a: max |u| = {np.abs(u).max():.6g}")


if __name__ == "__main__":
    main()

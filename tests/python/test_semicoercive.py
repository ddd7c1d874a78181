"""A body held by its contact only: S positive semidefinite. Solved when the contact stops the
free motion; status 'unbounded' at once when the load pulls the body away from its support."""

import numpy as np

import hemivem


def chain(n, k=50.0):
    """k times the Laplacian of a chain of n nodes (null space: the constants)."""
    S = np.zeros((n, n))
    for i in range(n - 1):
        S[i, i] += k
        S[i + 1, i + 1] += k
        S[i, i + 1] -= k
        S[i + 1, i] -= k
    return S


def test_a_chain_pushed_against_a_gap_rests_on_it():
    n = 12
    p = hemivem.ReducedProblem(chain(n), c=np.full(n, 0.3), w=np.ones(n), g=np.full(n, 0.01), law="zero",
                               constraint="one-sided")
    for name in hemivem.available_engines()["minimizer"]:
        m = hemivem.minimize(p, name)
        assert m.converged and m.status == "converged", (name, m.message)
        assert np.max(np.abs(m.a - 0.01)) <= 1e-12, name


def test_a_chain_pulled_off_its_support_has_no_solution():
    n = 12
    p = hemivem.ReducedProblem(chain(n), c=np.full(n, -0.3), w=np.ones(n), g=np.full(n, 0.01), law="zero",
                               constraint="one-sided")
    for name in hemivem.available_engines()["minimizer"]:
        m = hemivem.minimize(p, name)
        assert m.status == "unbounded" and not m.converged, name
        assert m.iterations == 0, name
        assert "there is no solution" in m.message, m.message

"""Claims the numbers support, from Python: a margin is computed, never trusted, and zero within
round-off; a change of law recomputes it; tolerances are checked; an unreliable displacement is
warned about."""

import math
from pathlib import Path

import numpy as np
import pytest

import hemivem

DATA = Path(__file__).resolve().parents[1] / "data"


def test_a_given_margin_that_is_not_the_problems_is_refused():
    S = -np.eye(2)  # F is concave: a margin of 1 would make a maximum "converged and unique"
    with pytest.raises(hemivem.InputError, match="uniqueness_margin"):
        hemivem.ReducedProblem(S, c=[0.0, 0.0], w=[1.0, 1.0], law="zero", constraint="none", uniqueness_margin=1.0)
    p = hemivem.ReducedProblem(S, c=[0.0, 0.0], w=[1.0, 1.0], law="zero", constraint="none", uniqueness_margin=-1.0)
    assert p.uniqueness_margin == -1.0 and p.uniqueness == "negative"


def test_a_margin_within_roundoff_is_zero():
    k = 65.0
    S = k * np.array([[1.0, -1.0], [-1.0, 1.0 + 1e-15]])  # exact lambda_min ~ k 5e-16
    p = hemivem.ReducedProblem(S, c=[0.1, 0.1], w=[1.0, 1.0], g=[0.05, 0.05], law="linear", constraint="box")
    assert p.uniqueness_margin == 0.0 and p.uniqueness == "zero"
    assert 0 < p.uniqueness_roundoff < 1e-12
    m = hemivem.minimize(p, "ssn")
    assert m.converged and m.may_be_nonunique


def test_reading_with_another_law_recomputes_the_margin(tmp_path):
    S = np.array([[100.0, -10.0], [-10.0, 100.0]])
    p = hemivem.ReducedProblem(S, c=[0.1, 0.1], w=[1.0, 1.0], g=[0.05, 0.05], law="paper", constraint="box")
    assert p.uniqueness_margin > 0
    p.write(tmp_path / "red")
    assert hemivem.ReducedProblem.read(tmp_path / "red").uniqueness_margin == p.uniqueness_margin
    q = hemivem.ReducedProblem.read(tmp_path / "red", law="sawtooth")
    assert q.uniqueness_margin == -math.inf and q.uniqueness == "negative"
    assert hemivem.minimize(q, "ssn").may_be_nonunique


@pytest.mark.parametrize("tol", [1e300, 0.999, 0.5, 0.0, -1e-10, math.nan])
def test_tolerances_outside_the_range_are_refused(tol, small_scene):
    p = hemivem.ReducedProblem(2 * np.eye(2), c=[0.1, 0.1], w=[1.0, 1.0], law="linear", constraint="none")
    for call in (
        lambda: p.certificate([0.0, 0.0], tolerance=tol),
        lambda: p.certify([0.0, 0.0], tolerance=tol),
        lambda: hemivem.minimize(p, "ssn", tolerance=tol),
        lambda: hemivem.solve(small_scene, tolerance=tol),
    ):
        with pytest.raises(hemivem.InputError, match=r"tolerance: must be in \[1e-300, 0.01\]"):
            call()
    assert p.certificate([0.0, 0.0], tolerance=1e-2).tolerance == 1e-2


def test_solve_warns_about_unreliable_digits(small_scene):
    assert hemivem.solve(small_scene, linear="eigen").warnings == []
    s = hemivem.Scene.default()
    s.set("mesh.file", str(DATA / "claims" / "near-coincident-columns.poly2d"))
    r = hemivem.solve(s, linear="eigen")
    assert r.converged
    assert any("condition number" in w for w in r.warnings), r.warnings

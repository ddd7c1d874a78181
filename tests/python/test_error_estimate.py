"""The error estimate and adaptive solves from Python: Result.error_estimate, the indicators
as an array, hemivem.solve(adapt=True) and a scene's [adapt] table."""

import numpy as np
import pytest

import hemivem


def small(n=8):
    scene = hemivem.Scene()
    scene.set("mesh.n", n)
    return scene


def test_every_result_has_its_estimate_and_indicators():
    r = hemivem.solve(small(), linear="eigen")
    e = r.error_estimate
    assert e["energy"] > 0 and e["norm"] > 0
    assert e["relative"] == pytest.approx(e["energy"] / e["norm"], rel=1e-15)
    eta = r.indicators
    assert eta.shape == (r.mesh.num_elements,)
    assert np.all(eta >= 0)
    assert np.sqrt(np.sum(eta**2)) == pytest.approx(e["energy"], rel=1e-12)
    assert r.json()["error_estimate"]["energy"] == e["energy"]
    assert r.adapt is None
    assert "estimate" in r.stages


def test_an_adaptive_solve_from_python():
    r = hemivem.solve(small(4), linear="eigen", adapt=True)
    a = r.adapt
    assert a["stopped"] in ("target", "max_steps", "max_unknowns")
    steps = a["steps"]
    assert len(steps) >= 2
    assert steps[-1]["unknowns"] > steps[0]["unknowns"]
    assert steps[-1]["estimate"] == r.error_estimate["relative"]
    assert r.indicators.shape == (r.mesh.num_elements,)
    assert r.mesh.num_elements == steps[-1]["elements"]


def test_a_scene_table_adapt_is_honoured():
    scene = small(4)
    scene.set("adapt.target", 0.1)
    scene.set("adapt.max_steps", 3)
    r = hemivem.solve(scene, linear="eigen")
    steps = r.adapt["steps"]
    assert len(steps) <= 3
    assert r.adapt["target"] == 0.1
    with pytest.raises(hemivem.InputError, match="adapt.fraction"):
        scene.set("adapt.fraction", 0.0)

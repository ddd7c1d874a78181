"""Loading paths from Python (docs/paths.md): hemivem.solve_path, Result.path, its steps and the
files the command writes; checked against a static solve and the balance of forces."""

import json

import numpy as np
import pytest

import hemivem


def test_a_one_step_path_is_the_static_solve():
    static = hemivem.solve(hemivem.Scene.default())
    r = hemivem.solve_path(hemivem.Scene.default(), t=[1.0])
    assert r.path is not None and len(r.path) == 1
    np.testing.assert_allclose(r.displacement, static.displacement, rtol=0, atol=1e-10 * np.abs(static.displacement).max())
    assert static.path is None


def test_steps_carry_their_arrays_and_the_last_step_is_the_result(coulomb_scene):
    r = hemivem.solve_path(coulomb_scene(), t=[0.5, 1.0, 1.5, 2.0], frames=4)
    path = r.path
    assert len(path) == 4 and path.converged
    np.testing.assert_array_equal(path.t, [0.5, 1.0, 1.5, 2.0])
    steps = list(path)
    assert [s.index for s in steps] == [1, 2, 3, 4]
    last = path[-1]
    np.testing.assert_array_equal(last.displacement, r.displacement)
    for s in steps:
        assert s.converged, s.message
        assert s.fixed_point is not None and s.fixed_point["converged"]
        assert s.balance is not None and s.balance < 1e-8
        table = s.contact
        mu = 0.3
        # Coulomb: every friction force within mu times the normal force, equal where it slips
        force = table.law_force + table.reaction
        limit = mu * np.maximum(force, 0.0)
        scale = s.certificate["force_scale"]
        assert np.all(np.abs(table.friction_force) <= limit + 1e-9 * scale)
        slipping = table.friction_state == "slip"
        np.testing.assert_allclose(np.abs(table.friction_force[slipping]), limit[slipping], atol=1e-9 * scale)
        assert s.slip.shape == (len(table),)
    # the shear starts at t = 1: the friction resultant grows with it
    assert abs(path[3].contact_force[0]) > abs(path[1].contact_force[0])
    doc = path.json()
    assert doc["schema"] == "hemivem-path/1" and len(doc["steps"]) == 4
    assert r.json()["path"]["steps"] == 4


def test_solve_path_writes_the_path_files(tmp_path, coulomb_scene):
    r = hemivem.solve_path(coulomb_scene(), steps=3)
    written = {p.name for p in r.write(tmp_path / "out")}
    for name in ("path.json", "path-contact.csv", "path-displacement.csv", "solution.pvd", "solution-0003.vtu"):
        assert name in written
    doc = json.loads((tmp_path / "out" / "path.json").read_text())
    assert [s["t"] for s in doc["steps"]] == pytest.approx([1 / 3, 2 / 3, 1.0])
    rows = (tmp_path / "out" / "path-contact.csv").read_text().splitlines()
    assert rows[0].startswith("step,t,vertex")
    assert len(rows) == 1 + 3 * len(r.contact)


def test_bad_path_keys_are_input_errors(coulomb_scene):
    with pytest.raises(hemivem.InputError):
        hemivem.solve_path(coulomb_scene(), t=[1.0, 0.5])
    with pytest.raises(hemivem.InputError):
        hemivem.solve_path(coulomb_scene(), steps=0)


def test_coulomb_is_named_coulomb_with_its_coefficient(coulomb_scene):
    # solved as Tresca problems whose bounds a fixed point sets; named as the scene poses it
    r = hemivem.solve_path(coulomb_scene(), t=[1.0, 2.0])
    friction = r.json()["friction"]
    assert friction["law"] == "coulomb"
    assert friction["models"] == [{"part": "contact", "law": "coulomb", "coefficient": 0.3}]
    assert "friction      coulomb (mu = 0.3): " in r.full_report()
    assert "tresca" not in r.full_report() and "tresca" not in r.to_json()

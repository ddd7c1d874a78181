"""Result.forces: the balance of forces on the body, as result.json's "forces"."""

import math
import pathlib

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_forces_of_example_4_1_balance_and_match_result_json(small_scene):
    r = hemivem.solve(small_scene)
    f = r.forces
    assert set(f) == {"applied", "reactions", "contact", "balance_residual"}
    assert f["applied"][0] == 0.0 and math.isclose(f["applied"][1], -8.0, rel_tol=1e-14)  # traction -8 on the top
    assert list(f["reactions"]) == ["clamped"]
    assert f["contact"] == r.contact_force
    # the contact resultant is the sum of -(law_force + reaction) times the node normals
    c = r.contact
    fx = -sum((c.law_force + c.reaction) * c.normal[:, 0])
    fy = -sum((c.law_force + c.reaction) * c.normal[:, 1])
    assert math.isclose(f["contact"][0], fx, abs_tol=1e-12) and math.isclose(f["contact"][1], fy, rel_tol=1e-12)
    total = [f["applied"][k] + f["reactions"]["clamped"][k] + f["contact"][k] for k in range(2)]
    assert math.isclose(math.hypot(*total) / 8.0, f["balance_residual"], abs_tol=1e-15)  # summed in another order
    assert f["balance_residual"] < 1e-10
    written = r.json()["forces"]
    assert written["balance_residual"] == f["balance_residual"]
    assert tuple(written["reactions"]["clamped"]) == f["reactions"]["clamped"]


def test_reactions_named_as_in_the_scene():
    s = hemivem.Scene.from_toml(ROOT / "scenes" / "rollers-pressure.toml")
    s.set("mesh.n", 16)
    f = hemivem.solve(s).forces
    assert sorted(f["reactions"]) == ["clamped", "dirichlet[0]"]
    assert f["reactions"]["dirichlet[0]"][1] == 0.0  # a roller in x holds nothing in y
    assert f["balance_residual"] < 1e-10

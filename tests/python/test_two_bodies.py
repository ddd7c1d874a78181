"""Two deformable bodies ([[body]], docs/two-bodies.md) from Python: the shipped contact patch
tests solved, the arrays per body against the exact field and against result.json."""

import pathlib

import numpy as np

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_two_blocks_give_each_body_its_exact_displacement():
    s = hemivem.Scene.from_file(ROOT / "scenes" / "two-blocks.toml")
    r = hemivem.solve(s)
    assert r.converged
    bodies = r.bodies
    assert list(bodies) == ["upper", "lower"]
    upper, lower = bodies["upper"], bodies["lower"]
    assert upper["first_vertex"] == 0 and lower["first_vertex"] == upper["vertices"]
    assert upper["vertices"] + lower["vertices"] == r.displacement.shape[0]
    assert lower["cells"] == 21
    # each body's rows are a view of the displacement's
    assert np.shares_memory(lower["displacement"], r.displacement)
    assert np.array_equal(lower["displacement"], r.displacement[lower["first_vertex"]:])
    # plane strain, sigma_yy = -2, sigma_xx = 0: the exact linear field of each block
    x = np.array(r.mesh.vertices)

    def strains(E, nu):
        return 2.0 * nu * (1.0 + nu) / E, -2.0 * (1.0 - nu * nu) / E

    exx_l, eyy_l = strains(4.0, 0.1)
    exx_u, eyy_u = strains(10.0, 0.3)
    xl = x[lower["first_vertex"]:]
    xu = x[: upper["vertices"]]
    np.testing.assert_allclose(lower["displacement"][:, 0], exx_l * xl[:, 0], atol=1e-10)
    np.testing.assert_allclose(lower["displacement"][:, 1], eyy_l * xl[:, 1], atol=1e-10)
    np.testing.assert_allclose(upper["displacement"][:, 0], exx_u * xu[:, 0], atol=1e-10)
    np.testing.assert_allclose(upper["displacement"][:, 1], eyy_l * 0.5 + eyy_u * (xu[:, 1] - 0.5), atol=1e-10)
    j = r.json()
    assert [b["name"] for b in j["bodies"]] == ["upper", "lower"]
    assert j["bodies"][1]["first_vertex"] == lower["first_vertex"]


def test_a_scene_of_one_body_has_no_bodies():
    r = hemivem.solve(hemivem.Scene.from_file(ROOT / "scenes" / "signorini.toml"))
    assert r.bodies == {}
    assert r.json()["bodies"] is None

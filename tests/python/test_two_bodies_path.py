"""Two deformable bodies along a loading path from Python (docs/two-bodies.md, docs/paths.md):
the blocks of scenes/two-blocks.toml pressed by 2 t while the lower block's bottom sinks by
0.01 t^2, every step's displacement the contact patch test's exact field at its t, and
Result.bodies and result.json's bodies those of the last step."""

import pathlib

import numpy as np

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]


def exact(x, upper, t):
    """Plane strain, sigma_yy = -2 t and sigma_xx = 0 in both blocks, u_x = 0 on x = 0, u_y
    continuous across y = 0.5 and -0.01 t^2 on y = 0."""

    def strains(E, nu):
        p = 2.0 * t
        return p * nu * (1.0 + nu) / E, -p * (1.0 - nu * nu) / E

    exx_l, eyy_l = strains(4.0, 0.1)
    exx_u, eyy_u = strains(10.0, 0.3)
    base = -0.01 * t * t
    u = np.empty_like(x)
    u[:, 0] = np.where(upper, exx_u, exx_l) * x[:, 0]
    u[:, 1] = np.where(upper, base + eyy_l * 0.5 + eyy_u * (x[:, 1] - 0.5), base + eyy_l * x[:, 1])
    return u


def test_two_blocks_along_a_path_are_exact_at_every_step():
    s = hemivem.Scene.from_file(ROOT / "scenes" / "two-blocks.toml")
    s.update({"body[0].loads.traction[0].pressure": "2*t", "body[1].dirichlet[1].uy": "-0.01*t^2"})
    r = hemivem.solve_path(s, t=[0.5, 1.0, 2.0], frames=3)
    assert r.converged and len(r.path) == 3
    upper, lower = r.bodies["upper"], r.bodies["lower"]
    x = np.array(r.mesh.vertices)
    is_upper = np.arange(x.shape[0]) < upper["vertices"]
    for step in r.path:
        assert step.converged, step.message
        np.testing.assert_allclose(step.displacement, exact(x, is_upper, step.t), rtol=0, atol=1e-10)
        np.testing.assert_allclose(step.contact.pressure, 2.0 * step.t, rtol=0, atol=1e-10)
    # the bodies of the last step, t = 2
    last = exact(x, is_upper, 2.0)
    np.testing.assert_allclose(lower["displacement"], last[lower["first_vertex"]:], rtol=0, atol=1e-10)
    np.testing.assert_allclose(upper["displacement"], last[: upper["vertices"]], rtol=0, atol=1e-10)
    j = r.json()
    assert [b["name"] for b in j["bodies"]] == ["upper", "lower"]
    for b in j["bodies"]:
        assert b["forces"]["balance_residual"] < 1e-10
    assert abs(j["bodies"][0]["forces"]["contact"][1] - 4.0) < 1e-10
    assert abs(j["bodies"][1]["forces"]["contact"][1] + 4.0) < 1e-10

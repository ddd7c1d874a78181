"""Bodies held by their contact (docs/supports.md): the free rigid motions, named."""
import pathlib

import pytest

import hemivem

BLOCK = """
schema_version = 1
[mesh]
generator = "squares"
n = [16, 4]
domain = [0, 4, 0, 1]
[material]
E = 100.0
nu = 0.3
[[dirichlet]]
side = "left"
{left} = 0.0
[[dirichlet]]
side = "right"
{right} = 0.0
[loads]
[[loads.traction]]
side = "top"
value = [0.0, -2.0]
[contact]
{contact}
law = "linear"
constraint = "none"
[contact.parameters]
stiffness = 50.0
"""


def test_a_block_between_rollers_is_held_by_its_foundation():
    s = hemivem.Scene.from_string(BLOCK.format(left="ux", right="ux", contact='side = "bottom"'))
    r = hemivem.solve(s)
    assert r.certificate.converged
    assert r.held_by_contact == ["translation along (0, 1) of the body"]
    # one-dimensional: the settlement is the load over the foundation stiffness
    assert max(abs(u - 2.0 / 50.0) for u in r.contact.u_nu) < 1e-10 * 2.0 / 50.0
    assert "held by the contact alone: translation along (0, 1) of the body" in r.full_report()


def test_a_motion_nothing_holds_is_refused_by_name():
    s = hemivem.Scene.from_string(
        BLOCK.format(left="uy", right="uy", contact="segments = [[0.5, 0, 3.5, 0]]"))
    with pytest.raises(hemivem.InputError, match=r"translation along \(1, 0\) of the body"):
        hemivem.solve(s)


def test_a_clamped_body_has_no_free_motion():
    assert hemivem.solve(hemivem.Scene.default()).held_by_contact == []


def test_a_point_support_pins_one_vertex_and_the_plate_benchmark_poses_as_written():
    # the published plate: a roller on its symmetry line meets the frictional contact at the
    # corner, which a point support pins in y; its tangential displacements at t = 1 agree with
    # the published ones within their 5 %
    s = hemivem.Scene.from_toml(pathlib.Path(__file__).parents[2] / "scenes" / "plate-friction-benchmark.toml")
    assert s.to_dict()["dirichlet"][1]["point"] == [0.04, 0.0]
    r = hemivem.solve(s)
    assert r.certificate.converged
    x = list(r.contact.x)
    for at, ux in [(0.0, 2.86e-5), (0.00125, 2.72e-5), (0.005, 2.28e-5), (0.0075, 1.98e-5), (0.01125, 1.5e-5)]:
        i = min(range(len(x)), key=lambda k: abs(x[k] - at))
        assert abs(x[i] - at) < 1e-12
        assert abs(r.contact.u_tau[i] - ux) <= 0.05 * ux
    assert max(x) < 0.04  # the pinned corner under the roller left the contact
    # a point with no vertex is an error naming the entry
    bad = hemivem.Scene.from_string(s.to_toml().replace("point = [0.04, 0.0]", "point = [0.04, 0.001]"))
    with pytest.raises(hemivem.InputError, match=r"dirichlet\[1\]\.point: no vertex of the mesh"):
        hemivem.solve(bad)

"""Two deformable bodies ([[body]], docs/two-bodies.md) from Python: the shipped contact patch
tests solved, the arrays per body against the exact field and against result.json, each body's
VTU read by VTK through solution.vtm."""

import pathlib

import numpy as np
import pytest

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


def test_each_body_has_its_vtu_and_the_vtm_opens_them_as_one_scene(tmp_path):
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    r = hemivem.solve(hemivem.Scene.from_file(ROOT / "scenes" / "two-blocks.toml"))
    assert r.converged
    written = {p.name for p in r.write(tmp_path, ["result.json", "solution.vtu"])}
    assert {"solution.body-upper.vtu", "solution.body-lower.vtu", "solution.vtm"} <= written
    reader = vtk.vtkXMLMultiBlockDataReader()
    reader.SetFileName(str(tmp_path / "solution.vtm"))
    reader.Update()
    scene = reader.GetOutput()
    assert scene.GetNumberOfBlocks() == 2
    for i, name in enumerate(["upper", "lower"]):
        assert scene.GetMetaData(i).Get(vtk.vtkCompositeDataSet.NAME()) == name
        block = scene.GetBlock(i)
        body = r.bodies[name]
        assert block.GetNumberOfPoints() == body["vertices"]
        u = vtk_to_numpy(block.GetPointData().GetArray("displacement"))
        assert np.array_equal(u[:, :2], body["displacement"]) and not u[:, 2].any()
        polygons = sum(block.GetCellType(c) == vtk.VTK_POLYGON for c in range(block.GetNumberOfCells()))
        assert polygons == body["cells"]


def test_shrink_fit_gives_lames_pressure_at_every_node():
    """scenes/shrink-fit.toml (pairing by projection, polar meshes) against Lame's closed form,
    computed here: u_r = A r + B / r in each ring, free surfaces, the overlap closed, the forces
    per unit angle equal and opposite."""
    r = hemivem.solve(hemivem.Scene.from_file(ROOT / "scenes" / "shrink-fit.toml"))
    assert r.converged
    a, b, c, delta = 0.5, 1.0, 2.0, 1e-3

    def moduli(E, nu):
        mu = E / (2 * (1 + nu))
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        return 2 * (lam + mu), 2 * mu

    ki, mi = moduli(2.0, 0.3)
    ko, mo = moduli(1.0, 0.25)
    s = b + delta
    m = np.array([[ki, -mi / a**2, 0, 0], [0, 0, ko, -mo / c**2], [-s, -1 / s, b, 1 / b],
                  [s * ki, -s * mi / s**2, -b * ko, b * mo / b**2]])
    A1, B1, A2, B2 = np.linalg.solve(m, [0, 0, delta, 0])
    p = -(ko * A2 - mo * B2 / b**2) * b / s  # on the inner ring's surface
    assert r.contact.pressure.shape == (512,)
    np.testing.assert_allclose(r.contact.pressure, p, rtol=2e-3)
    np.testing.assert_allclose(r.contact.gap, -delta, atol=1e-12)
    # the outer ring's outer circle moves out by A2 c + B2 / c
    outer = r.bodies["outer"]
    x = np.array(r.mesh.vertices)[outer["first_vertex"]:]
    on = np.abs(np.hypot(x[:, 0], x[:, 1]) - c) < 1e-12
    ur = np.sum(outer["displacement"][on] * x[on], axis=1) / c
    np.testing.assert_allclose(ur, A2 * c + B2 / c, rtol=2e-3)

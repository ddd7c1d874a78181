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

"""The VTK files of a three-dimensional solve read by VTK itself (vtkXMLUnstructuredGridReader):
Voronoi polyhedra of different vertex counts as VTK_POLYHEDRON cells whose volumes VTK computes
from their faces, the point and cell arrays, and the contact faces as polygons."""

import numpy as np
import pytest

import hemivem

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

# Voronoi cells of the unit cube, the bottom on a stiff nonmonotone foundation, pressed on top
VORONOI_BLOCK = """
schema_version = 1
title = "Voronoi block on a foundation"

[mesh]
generator = "voronoi"
n = [3, 3, 3]
domain = [0.0, 1.0, 0.0, 1.0, 0.0, 1.0]

[material]
E = 100.0
nu = 0.3

[[dirichlet]]
side = "x0"
ux = 0.0

[[dirichlet]]
side = "y0"
uy = 0.0

[[dirichlet]]
side = "top"
uz = -0.01

[contact]
side = "bottom"
law = "paper"
gap = 0.02
constraint = "box"
"""


def read(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


@pytest.fixture(scope="module")
def solved(tmp_path_factory):
    r = hemivem.solve(VORONOI_BLOCK, linear="eigen", minimizer="ssn")
    assert r.converged, r.message
    folder = tmp_path_factory.mktemp("voronoi-solid")
    r.write(folder)
    return r, folder


def test_vtk_reads_the_polyhedra_and_their_volumes(solved):
    r, folder = solved
    grid = read(folder / "solution.vtu")
    mesh = r.mesh
    assert grid.GetNumberOfPoints() == mesh.num_vertices
    assert grid.GetNumberOfCells() == mesh.num_cells
    assert {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())} == {vtk.VTK_POLYHEDRON}
    # cells of different vertex counts, in the order of the mesh
    counts = [grid.GetCell(i).GetNumberOfPoints() for i in range(grid.GetNumberOfCells())]
    assert counts == [len(v) for v in mesh.cell_vertices]
    assert len(set(counts)) > 1
    assert [grid.GetCell(i).GetNumberOfFaces() for i in range(grid.GetNumberOfCells())] == [len(c) for c in mesh.cells]
    sizes = vtk.vtkCellSizeFilter()
    sizes.SetInputData(grid)
    sizes.ComputeVolumeOn()
    sizes.Update()
    volumes = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Volume"))
    assert np.allclose(volumes, mesh.volumes, rtol=1e-12, atol=0.0)
    assert abs(volumes.sum() - 1.0) < 1e-12


def test_the_arrays_are_the_results(solved):
    r, folder = solved
    grid = read(folder / "solution.vtu")
    points = vtk_to_numpy(grid.GetPoints().GetData())
    assert np.array_equal(points, r.mesh.vertices)
    assert np.array_equal(vtk_to_numpy(grid.GetPointData().GetArray("displacement")), r.displacement)
    cells = grid.GetCellData()
    assert np.array_equal(vtk_to_numpy(cells.GetArray("error_indicator")), r.indicators)
    assert vtk_to_numpy(cells.GetArray("stress")).shape == (r.mesh.num_cells, 6)
    assert np.all(vtk_to_numpy(cells.GetArray("von_mises")) >= 0.0)
    u_nu = vtk_to_numpy(grid.GetPointData().GetArray("u_nu"))
    assert np.array_equal(u_nu[r.contact.vertex], r.contact.u_nu)


def test_the_contact_surface_is_the_bottom(solved):
    r, folder = solved
    surface = read(folder / "contact-surface.vtu")
    assert {surface.GetCellType(i) for i in range(surface.GetNumberOfCells())} == {vtk.VTK_POLYGON}
    sizes = vtk.vtkCellSizeFilter()
    sizes.SetInputData(surface)
    sizes.ComputeAreaOn()
    sizes.Update()
    areas = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Area"))
    assert abs(areas.sum() - 1.0) < 1e-12
    # the contact weights are the nodes' shares of that area
    assert abs(r.contact.weight.sum() - areas.sum()) < 1e-12
    vertex = vtk_to_numpy(surface.GetPointData().GetArray("vertex"))
    node = vtk_to_numpy(surface.GetPointData().GetArray("contact_node")).astype(bool)
    assert set(vertex[node].tolist()) == set(r.contact.vertex.tolist())

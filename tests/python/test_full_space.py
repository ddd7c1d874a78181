"""The full-space route from Python: a Krylov engine given as `linear` solves the problem the
condensed route solves, to the same displacement, nothing factorized (docs/full-space.md)."""

import json
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE_3D = ROOT / "scenes" / "example-4.1-3d.toml"


def krylov_engines():
    return hemivem.available_engines()["krylov"]


def test_every_build_has_a_krylov_engine():
    assert "eigen-cg" in krylov_engines()


@pytest.mark.parametrize("engine", krylov_engines())
def test_the_full_space_route_gives_the_condensed_routes_displacement(engine):
    scene = hemivem.Scene.from_toml(EXAMPLE_3D)
    scene.set("mesh.n", 4)
    condensed = hemivem.solve(scene, linear="eigen")
    full = hemivem.solve(scene, linear=engine)
    assert condensed.status == full.status == "converged"
    u0, u1 = np.asarray(condensed.displacement), np.asarray(full.displacement)
    assert u1.shape == u0.shape
    assert np.max(np.abs(u1 - u0)) <= 1e-8 * np.max(np.abs(u0))
    result = json.loads(full.to_json())
    assert result["stages"][:3] == ["assembly", "posing", "full_space"]
    assert result["backends"]["linear"] == engine
    assert condensed.full_space is None
    assert full.full_space == result["full_space"]
    assert full.full_space["newton_iterations"] == full.iterations >= 1
    assert full.full_space["krylov_iterations"] >= full.iterations
    assert 1 <= full.full_space["preconditioner_setups"] <= full.iterations


def test_a_grid_sequence_starts_the_solve_and_is_recorded():
    scene = hemivem.Scene.from_toml(EXAMPLE_3D)
    scene.set("mesh.n", [8, 8, 8])
    condensed = hemivem.solve(scene, linear="eigen")
    scene.set("solver.grid_sequence", 2)
    full = hemivem.solve(scene, linear="eigen-cg")
    assert full.status == "converged"
    u0, u1 = np.asarray(condensed.displacement), np.asarray(full.displacement)
    assert np.max(np.abs(u1 - u0)) <= 1e-8 * np.max(np.abs(u0))
    grids = full.full_space["grid_sequence"]
    assert [g["n"] for g in grids] == ["2", "4"]
    assert all(g["converged"] for g in grids)
    assert full.stages[0] == "grid_sequence"
    assert full.timings["grid_sequence"] >= sum(g["seconds"] for g in grids)
    # the condensed route takes none: refused by key
    with pytest.raises(hemivem.InputError, match="solver.grid_sequence = 2"):
        hemivem.solve(scene, linear="eigen")


def test_python_runs_every_krylov_engine_built():
    engines = hemivem.available_engines()
    assert not set(engines["krylov"]) & set(engines["command_only"])
    assert "petsc-gamg" not in engines["command_only"] and "petsc-hypre" not in engines["command_only"]


@pytest.mark.parametrize("engine", krylov_engines())
def test_a_path_on_the_full_space_route_is_the_condensed_routes(coulomb_scene, engine):
    t = [0.5, 1.0, 1.5, 2.0]
    condensed = hemivem.solve_path(coulomb_scene(), t=t, frames=4, linear="eigen")
    full = hemivem.solve_path(coulomb_scene(), t=t, frames=4, linear=engine)
    assert condensed.path.converged and full.path.converged
    for a, b in zip(condensed.path, full.path):
        u0, u1 = np.asarray(a.displacement), np.asarray(b.displacement)
        assert np.max(np.abs(u1 - u0)) <= 1e-8 * np.max(np.abs(u0))
    result = json.loads(full.to_json())
    assert result["stages"][:3] == ["assembly", "posing", "path"]
    assert result["backends"]["linear"] == engine
    # the route's Newton iterations are the steps' (each summed over its fixed point)
    assert condensed.full_space is None
    assert full.full_space["newton_iterations"] == sum(step.iterations for step in full.path)


# Run by `mpiexec -n 2 python3 ACROSS <folder>`: a solve and a Coulomb path across the
# processes (the path's linear engine "auto", which takes the route across them under the
# launcher), each process keeping what it holds in <folder>/rank<r>.npz.
ACROSS = """
import json, os, sys
import numpy as np
import hemivem
folder = sys.argv[1]
rank = int(os.environ.get("OMPI_COMM_WORLD_RANK", os.environ.get("PMI_RANK", "0")))
scene = hemivem.Scene.from_toml(sys.argv[2])
scene.set("mesh.n", 4)
r = hemivem.solve(scene, linear="petsc-gamg")
written = r.write(os.path.join(folder, "solve"))
p = hemivem.solve_path(sys.argv[3], t=[0.5, 1.0, 1.5, 2.0], frames=4)
path_json = json.loads(p.to_json())
np.savez(os.path.join(folder, f"rank{rank}.npz"), u=r.displacement, writer=r.writer, written=len(written),
         processes=json.loads(r.to_json())["processes"], pieces=json.loads(r.to_json())["mesh"]["pieces"],
         cells=r.mesh.num_cells, steps=np.array([s.displacement for s in p.path]),
         converged=r.converged and p.path.converged, estimate=r.error_estimate["relative"],
         path_pieces=path_json["mesh"]["pieces"], path_cells=p.mesh.num_elements,
         path_estimate=p.error_estimate["relative"], path_linear=path_json["backends"]["linear"],
         path_processes=path_json["processes"], path_warnings=" ".join(path_json["warnings"]))
"""


@pytest.mark.skipif("petsc-gamg" not in krylov_engines(), reason="PETSc's engines are not built")
def test_a_solve_and_a_path_across_processes_from_python(tmp_path, coulomb_scene, hemivem_command):
    mpiexec = shutil.which("mpiexec") or shutil.which("mpirun")
    if mpiexec is None:
        pytest.skip("no MPI launcher on PATH")
    version = subprocess.run([mpiexec, "--version"], capture_output=True, text=True).stdout
    flags = ["--allow-run-as-root", "--oversubscribe"] if "Open MPI" in version or "OpenRTE" in version else []
    (tmp_path / "across.py").write_text(ACROSS)
    (tmp_path / "coulomb.toml").write_text(coulomb_scene())
    p = subprocess.run([mpiexec, "-n", "2", *flags, sys.executable, str(tmp_path / "across.py"), str(tmp_path),
                        str(EXAMPLE_3D), str(tmp_path / "coulomb.toml")],
                       capture_output=True, text=True, timeout=600,
                       env=dict(os.environ))  # not what MPI, started here by other tests, put in the C environment
    assert p.returncode == 0, p.stdout + p.stderr
    ranks = [np.load(tmp_path / f"rank{r}.npz") for r in (0, 1)]
    scene = hemivem.Scene.from_toml(EXAMPLE_3D)
    scene.set("mesh.n", 4)
    one = hemivem.solve(scene, linear="eigen")
    path = hemivem.solve_path(coulomb_scene(), t=[0.5, 1.0, 1.5, 2.0], frames=4, linear="eigen")
    steps = np.array([s.displacement for s in path.path])
    for rank in ranks:  # every process holds the whole solution, the one process's
        assert rank["converged"] and rank["processes"] == 2
        # each process made its piece of the mesh for the solve, and holds the whole mesh after it
        assert rank["pieces"] == 2 and rank["cells"] == one.mesh.num_cells
        assert np.max(np.abs(rank["u"] - one.displacement)) <= 1e-8 * np.max(np.abs(one.displacement))
        assert rank["steps"].shape == steps.shape
        assert np.max(np.abs(rank["steps"] - steps)) <= 1e-8 * np.max(np.abs(steps))
        # the path too: made in pieces, the whole mesh after it, the whole mesh's estimate
        assert rank["path_pieces"] == 2 and rank["path_cells"] == path.mesh.num_elements
        # "auto" took the route across the processes, and said so
        assert str(rank["path_linear"]) == "petsc-gamg" and rank["path_processes"] == 2
        assert 'solver.linear = "auto": started as 2 processes by an MPI launcher' in str(rank["path_warnings"])
        assert rank["path_estimate"] == pytest.approx(path.error_estimate["relative"], rel=1e-6)
        assert rank["estimate"] == pytest.approx(one.error_estimate["relative"], rel=1e-6)
    # the first process writes, the other returns []
    assert [bool(r["writer"]) for r in ranks] == [True, False]
    assert ranks[0]["written"] > 0 and ranks[1]["written"] == 0
    assert json.loads((tmp_path / "solve" / "result.json").read_text())["processes"] == 2
    # Python's processes hold the whole mesh: the first writes solution.vtu whole
    assert (tmp_path / "solve" / "solution.vtu").exists()
    assert not list((tmp_path / "solve").glob("solution.piece-*.vtu"))
    # the command writes it in pieces, each process its own, named by solution.pvtu
    solve = tmp_path / "command"
    p = subprocess.run([mpiexec, "-n", "2", *flags, str(hemivem_command), "solve", str(EXAMPLE_3D), "--set", "mesh.n=4",
                        "--linear", "petsc-gamg", "-q", "--out", str(solve)],
                       capture_output=True, text=True, timeout=600, env=dict(os.environ))
    assert p.returncode == 0, p.stdout + p.stderr
    assert not (solve / "solution.vtu").exists()
    assert sorted(f.name for f in solve.glob("solution.piece-*.vtu")) == ["solution.piece-0.vtu", "solution.piece-1.vtu"]
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    def cells_and_points(reader, path):
        reader.SetFileName(str(path))
        reader.Update()
        grid = reader.GetOutput()
        centers = vtk.vtkCellCenters()
        centers.SetInputData(grid)
        centers.Update()
        c = vtk_to_numpy(centers.GetOutput().GetPoints().GetData())
        order = np.lexsort(np.round(c, 9).T)
        cells = {name: vtk_to_numpy(grid.GetCellData().GetArray(name))[order] for name in ("stress", "von_mises")}
        x = np.round(vtk_to_numpy(grid.GetPoints().GetData()), 9)
        u = vtk_to_numpy(grid.GetPointData().GetArray("displacement"))
        return grid.GetNumberOfCells(), c[order], cells, {tuple(p): d for p, d in zip(x, u)}

    one.write(tmp_path / "one", files=["solution.vtu"])
    n, centers, cells, points = cells_and_points(vtk.vtkXMLPUnstructuredGridReader(), solve / "solution.pvtu")
    n1, centers1, cells1, points1 = cells_and_points(vtk.vtkXMLUnstructuredGridReader(), tmp_path / "one" / "solution.vtu")
    # every cell once, with one process's stresses; every point with one process's displacement
    assert n == n1 == one.mesh.num_cells
    assert np.max(np.abs(centers - centers1)) <= 1e-12
    for name in ("stress", "von_mises"):
        assert np.max(np.abs(cells[name] - cells1[name])) <= 1e-7 * np.max(np.abs(cells1[name]))
    assert points.keys() == points1.keys()
    scale = np.max(np.abs(one.displacement))
    assert max(np.max(np.abs(points[x] - points1[x])) for x in points1) <= 1e-8 * scale


@pytest.mark.skipif("petsc-gamg" not in krylov_engines(), reason="PETSc's engines are not built")
def test_the_bodies_pieces_across_processes_open_in_vtk_as_one_processs_bodies(tmp_path, hemivem_command):
    """The command on two processes writes each body's file in pieces; solution.vtm names them,
    each body a block of its pieces, which VTK's multiblock reader opens as one process's body."""
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    mpiexec = shutil.which("mpiexec") or shutil.which("mpirun")
    if mpiexec is None:
        pytest.skip("no MPI launcher on PATH")
    version = subprocess.run([mpiexec, "--version"], capture_output=True, text=True).stdout
    flags = ["--allow-run-as-root", "--oversubscribe"] if "Open MPI" in version or "OpenRTE" in version else []
    scene = ROOT / "scenes" / "two-blocks.toml"
    solve = tmp_path / "command"
    p = subprocess.run([mpiexec, "-n", "2", *flags, str(hemivem_command), "solve", str(scene), "--linear", "petsc-gamg",
                        "-q", "--out", str(solve)], capture_output=True, text=True, timeout=600, env=dict(os.environ))
    assert p.returncode == 0, p.stdout + p.stderr
    assert not list(solve.glob("solution.body-*[!0-9].vtu"))  # no body's file whole
    one = hemivem.solve(hemivem.Scene.from_file(scene), linear="eigen")
    reader = vtk.vtkXMLMultiBlockDataReader()
    reader.SetFileName(str(solve / "solution.vtm"))
    reader.Update()
    blocks = reader.GetOutput()
    assert blocks.GetNumberOfBlocks() == 2
    scale = np.max(np.abs(one.displacement))
    for i, name in enumerate(["upper", "lower"]):
        assert blocks.GetMetaData(i).Get(vtk.vtkCompositeDataSet.NAME()) == name
        pieces = blocks.GetBlock(i)
        assert pieces.IsA("vtkMultiPieceDataSet") and pieces.GetNumberOfPieces() == 2
        body = one.bodies[name]
        polygons, points = 0, {}
        for k in range(2):
            piece = pieces.GetPiece(k)
            polygons += sum(piece.GetCellType(c) == vtk.VTK_POLYGON for c in range(piece.GetNumberOfCells()))
            u = vtk_to_numpy(piece.GetPointData().GetArray("displacement"))
            for x, d in zip(np.round(vtk_to_numpy(piece.GetPoints().GetData())[:, :2], 12), u):
                points.setdefault(tuple(x), d[:2])
        # each of the body's cells in one piece, and every vertex of the body with its displacement
        assert polygons == body["cells"]
        assert len(points) == body["vertices"]
        x = np.asarray(one.mesh.vertices)[body["first_vertex"]:body["first_vertex"] + body["vertices"]]
        mine = np.array([points[tuple(v)] for v in np.round(x, 12)])
        assert np.max(np.abs(mine - body["displacement"])) <= 1e-8 * scale


def test_auto_takes_the_full_space_route_where_the_condensed_one_does_not_fit(monkeypatch):
    # Example 4.1 on 128 x 128 squares: an estimated 81 MiB on the condensed route, 70 MiB on
    # the full-space route with eigen-cg, the one Krylov engine whose estimate fits in 75 MiB
    # (PETSc's engines bring their libraries)
    scene = hemivem.Scene.default()
    scene.set("mesh.n", 128)
    reference = hemivem.solve(scene, linear="eigen")
    monkeypatch.setenv("HEMIVEM_MEMORY_LIMIT", "75M")
    chosen = hemivem.solve(scene)
    with pytest.raises(hemivem.InputError, match="full-space route, which factorizes nothing"):
        hemivem.solve(scene, linear="eigen")
    monkeypatch.delenv("HEMIVEM_MEMORY_LIMIT")
    result = json.loads(chosen.to_json())
    assert result["backends"]["linear"] == "eigen-cg"
    assert "solved on the full-space route with eigen-cg" in result["warnings"][0]
    assert chosen.reduced is None
    u0, u1 = np.asarray(reference.displacement), np.asarray(chosen.displacement)
    assert np.max(np.abs(u1 - u0)) <= 1e-8 * np.max(np.abs(u0))

"""hemivem.solve on three-dimensional scenes: (n, 3) arrays, the files of `hemivem solve`, an
exact solution, what a 3D Result does not have, and 2D unchanged."""

import csv
import json
import pathlib

import numpy as np
import pytest

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE_3D = ROOT / "scenes" / "example-4.1-3d.toml"

# A block [0, 1] x [0, 1] x [0, 0.5] on the rigid plane z = 0 (frictionless, one-sided, no
# law), symmetry planes x = 0 and y = 0, the top pushed down by DEPTH (its z component only):
# uniaxial stress, u = (nu e x, nu e y, -e z) with e = DEPTH / 0.5, pressure E e on the bottom
# (tests/test_contact3d.cpp, BlockPressedOnAPlaneIsUniaxialStress).
YOUNG, POISSON, DEPTH, HEIGHT = 100.0, 0.3, 0.01, 0.5
PRESSED_BLOCK = f"""
schema_version = 1
title = "a block pressed onto a plane"

[mesh]
generator = "cubes"
n = [3, 3, 2]
domain = [0.0, 1.0, 0.0, 1.0, 0.0, {HEIGHT}]

[material]
E = {YOUNG}
nu = {POISSON}

[[dirichlet]]
side = "x0"
ux = 0.0

[[dirichlet]]
side = "y0"
uy = 0.0

[[dirichlet]]
side = "top"
uz = {-DEPTH}

[contact]
side = "bottom"
law = "zero"
constraint = "one-sided"

[contact.obstacle]
shape = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
"""


@pytest.fixture(scope="module")
def small_3d():
    """Example 4.1 in 3D on 4 x 4 x 4 cubes, solved once."""
    s = hemivem.Scene.from_toml(EXAMPLE_3D)
    s.set("mesh.n", 4)
    return s, hemivem.solve(s, linear="eigen")


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def test_small_scene_converges_with_three_columns(small_3d):
    scene, r = small_3d
    assert scene.dimension == 3 and r.dimension == 3
    assert r.status == "converged" and r.converged and r.certificate.converged
    mesh = r.mesh
    assert isinstance(mesh, hemivem.Mesh3D)
    assert (mesh.num_vertices, mesh.num_cells) == (5 * 5 * 5, 4 * 4 * 4)
    n = mesh.num_vertices
    assert mesh.vertices.shape == (n, 3)
    d = r.displacement
    assert d.shape == (n, 3) and d.dtype == np.float64
    assert d.flags.c_contiguous and not d.flags.writeable
    assert np.all(np.isfinite(d)) and np.max(np.abs(d[:, 2])) > 0.0
    t = r.contact
    n_c = len(t)
    assert n_c > 0
    for name in ["vertex", "x", "y", "z", "u_nu", "law_force", "reaction", "pressure", "gap", "weight", "state", "part"]:
        assert t[name].shape == (n_c,), name
    assert t.normal.shape == (n_c, 3)
    # the bottom face z = 0 with outward normal -z; its nodes off the clamped sides x = 0, x = 1
    assert np.all(t.z == 0.0)
    assert np.allclose(t.normal, [0.0, 0.0, -1.0], rtol=0, atol=1e-15)
    assert np.array_equal(np.column_stack([t.x, t.y, t.z]), mesh.vertices[t.vertex])
    assert len(r.contact_force) == 3
    assert all(len(v) == 3 for v in [r.forces["applied"], r.forces["contact"], *r.forces["reactions"].values()])
    assert r.forces["balance_residual"] < 1e-10


def test_json_is_the_three_dimensional_document(small_3d):
    _, r = small_3d
    j = r.json()
    assert j["schema"] == "hemivem-result/26" and j["dimension"] == 3
    assert j["status"] == r.status and j["potential_energy"] == r.energy
    assert j["mesh"]["vertices"] == r.mesh.num_vertices and j["mesh"]["elements"] == r.mesh.num_cells
    assert len(j["contact"]) == len(r.contact)
    assert [c["vertex"] for c in j["contact"]] == r.contact.vertex.tolist()
    assert np.array_equal(np.array([c["x"] for c in j["contact"]]),
                          np.column_stack([r.contact.x, r.contact.y, r.contact.z]))
    assert np.array_equal(np.array([c["normal"] for c in j["contact"]]), r.contact.normal)
    assert [c["u_nu"] for c in j["contact"]] == r.contact.u_nu.tolist()
    assert j["error_estimate"] == r.error_estimate and j["adapt"] is None and j["path"] is None and j["friction"] is None
    assert set(r.timings) >= {"mesh", "assembly", "condensation", "minimize", "back_substitution", "total"}


def test_write_holds_the_arrays(small_3d, tmp_path):
    _, r = small_3d
    written = {p.name for p in r.write(tmp_path / "out")}
    assert {"result.json", "contact.csv", "displacement.csv", "history.csv", "solution.vtu",
            "contact-surface.vtu", "scene.toml"} <= written
    assert not written & {"u_nu.png", "error.png", "mesh.png", "adapt.png"}
    rows = read_csv(tmp_path / "out" / "displacement.csv")
    assert list(rows[0]) == ["vertex", "x", "y", "z", "ux", "uy", "uz"]
    assert [int(row["vertex"]) for row in rows] == list(range(r.mesh.num_vertices))
    u = np.array([[float(row[k]) for k in ("ux", "uy", "uz")] for row in rows])
    x = np.array([[float(row[k]) for k in ("x", "y", "z")] for row in rows])
    # shortest round-trip numbers: the very same doubles
    assert np.array_equal(u, r.displacement)
    assert np.array_equal(x, r.mesh.vertices)
    contact = read_csv(tmp_path / "out" / "contact.csv")
    assert len(contact) == len(r.contact) == len(r.json()["contact"])
    assert [float(row["u_nu"]) for row in contact] == r.contact.u_nu.tolist()
    assert [float(row["pressure"]) for row in contact] == r.contact.pressure.tolist()
    assert np.array_equal(np.array([[float(row[k]) for k in ("nx", "ny", "nz")] for row in contact]), r.contact.normal)
    assert json.loads((tmp_path / "out" / "result.json").read_text())["dimension"] == 3
    # a chosen file, and a name of no 3D output
    assert [p.name for p in r.write(tmp_path / "one", files=["displacement.csv"])] == ["displacement.csv"]
    with pytest.raises(hemivem.InputError, match="three-dimensional"):
        r.write(tmp_path / "bad", files=["u_nu.png"])


def test_write_gives_the_files_of_the_command(small_3d, tmp_path, run_command):
    scene, r = small_3d
    scene_file = tmp_path / "scene.toml"
    scene.write(scene_file)
    out = tmp_path / "cmd"
    run_command("solve", scene_file, "--linear", "eigen", "--out", out, "--export-reduced", tmp_path / "red", "-q")
    r2 = hemivem.solve(scene_file, linear="eigen")
    written = r2.write(tmp_path / "py")
    assert sorted(p.name for p in written) == sorted(p.name for p in out.iterdir())
    for name in ["contact.csv", "displacement.csv", "stress.csv", "scene.toml"]:
        assert (tmp_path / "py" / name).read_text() == (out / name).read_text(), name
    mine = json.loads((tmp_path / "py" / "result.json").read_text())
    theirs = json.loads((out / "result.json").read_text())
    for doc in (mine, theirs):
        doc.pop("timings")
    assert mine == theirs
    assert np.array_equal(r2.displacement, r.displacement)
    exported = hemivem.ReducedProblem.read(tmp_path / "red")
    assert np.array_equal(exported.S, r2.reduced.S) and np.array_equal(exported.c, r2.reduced.c)
    assert np.array_equal(exported.w, r2.reduced.w)


def test_pressed_block_is_uniaxial_stress():
    r = hemivem.solve(PRESSED_BLOCK, linear="eigen", minimizer="ssn")
    assert r.dimension == 3 and r.converged
    x = r.mesh.vertices
    strain = DEPTH / HEIGHT
    expected = np.column_stack([POISSON * strain * x[:, 0], POISSON * strain * x[:, 1], -strain * x[:, 2]])
    assert r.displacement.shape == (4 * 4 * 3, 3)
    assert np.max(np.linalg.norm(r.displacement - expected, axis=1)) < 1e-11
    t = r.contact
    assert len(t) == 16  # every bottom vertex, those on the symmetry planes included
    assert list(t.state) == ["at-gap"] * 16
    assert np.max(np.abs(t.u_nu)) < 1e-14
    assert np.allclose(t.normal, [0.0, 0.0, -1.0], rtol=0, atol=1e-15)
    stress = YOUNG * strain
    assert np.max(np.abs(t.pressure - stress)) <= 1e-9 * stress
    assert abs(t.weight.sum() - 1.0) < 1e-14
    assert np.allclose(r.contact_force, (0.0, 0.0, stress), rtol=0, atol=1e-9 * stress)


def test_what_a_three_dimensional_result_has_not(small_3d):
    _, r = small_3d
    assert r.adapt is None and r.path is None
    assert r.held_by_contact == []
    # a frictionless contact: the friction columns are zero vectors and empty states
    assert r.contact.u_tau.shape == (len(r.contact), 3) and not r.contact.u_tau.any()
    assert not r.contact.friction_force.any() and set(r.contact["friction_state"]) == {""}
    assert "z" in r.contact.columns


def test_reports_and_reduced_problem(small_3d):
    _, r = small_3d
    assert r.brief_report().startswith("converged (certificate: ")
    assert f"{r.iterations} iterations" in r.brief_report()
    full = r.full_report()
    assert "(three-dimensional)" in full and f"contact       {len(r.contact)} nodes" in full
    assert "dimension=3" in repr(r) and f"vertices={r.mesh.num_vertices}" in repr(r)
    p = r.reduced
    assert isinstance(p, hemivem.ReducedProblem) and len(p) == len(r.contact)
    assert p.certificate(r.a, tolerance=r.certificate.tolerance).converged
    assert p.energy(r.a) == pytest.approx(r.objective, rel=1e-12)


def test_global_search_and_no_contact():
    s = hemivem.Scene.from_toml(EXAMPLE_3D)
    s.update({"mesh.n": 3, "contact.law": "sawtooth"})
    runs = []
    r = hemivem.solve(s, search="global", max_starts=8, progress=lambda g: runs.append(g.run))
    assert r.converged and r.search["kind"] == "global" and runs
    j = r.json()
    assert [c.potential_energy for c in r.critical_points] == [c["potential_energy"] for c in j["critical_points"]]
    assert r.critical_points[0].potential_energy == pytest.approx(r.energy, rel=1e-12)
    s.set("contact", None)
    free = hemivem.solve(s)
    assert free.dimension == 3 and free.converged and free.displacement.shape == (free.mesh.num_vertices, 3)
    assert len(free.contact) == 0 and free.contact.normal.shape == (0, 3)
    assert free.minimizer_result is None and free.reduced is None and free.critical_points == []


def test_mesh3d_geometry(small_3d):
    _, r = small_3d
    m = r.mesh
    assert len(m) == m.num_cells == len(m.cells) == len(m.cell_vertices) == len(m.volumes)
    assert m.bounding_box == (0.0, 1.0, 0.0, 0.5, 0.0, 1.0)
    assert m.volumes.sum() == pytest.approx(0.5, rel=1e-14)
    assert m.centroids.shape == (m.num_cells, 3) and m.face_normals.shape == (m.num_faces, 3)
    assert len(m.faces) == m.num_faces and m.face_cells.shape == (m.num_faces, 2)
    boundary = m.boundary_faces
    assert np.all(m.face_cells[boundary, 1] == -1)
    # the boundary of the box: its six sides' area
    assert m.face_areas[boundary].sum() == pytest.approx(2 * (0.5 + 1.0 + 0.5), rel=1e-14)
    assert "Mesh3D(125 vertices, 64 cells" in repr(m)


def test_what_a_three_dimensional_scene_refuses(small_3d):
    scene, _ = small_3d
    with pytest.raises(hemivem.InputError, match="the mesh given is two-dimensional"):
        hemivem.solve(scene, mesh=hemivem.Mesh.generate("squares", 2))
    with pytest.raises(hemivem.InputError, match="condense takes two-dimensional scenes"):
        hemivem.condense(scene)


def test_a_plane_scene_keeps_two_columns(small_scene):
    small_scene.set("mesh.n", 4)
    r = hemivem.solve(small_scene)
    assert small_scene.dimension == 2 and r.dimension == 2 and r.converged
    assert r.displacement.shape == (r.mesh.num_vertices, 2) and r.mesh.vertices.shape[1] == 2
    assert isinstance(r.mesh, hemivem.Mesh)
    assert r.contact.normal.shape == (len(r.contact), 2) and "z" not in r.contact.columns
    assert len(r.contact_force) == 2 and r.json()["dimension"] == 2
    assert r.indicators.shape == (r.mesh.num_elements,)
    assert "dimension" not in repr(r)


def test_a_three_dimensional_result_has_its_error_estimate(small_3d):
    _, r = small_3d
    e = r.error_estimate
    assert e is not None and e["energy"] > 0.0 and e["norm"] > 0.0
    assert e["relative"] == pytest.approx(e["energy"] / e["norm"], rel=1e-14)
    assert e["parts"]["friction"] == 0.0
    eta = r.indicators
    assert eta.shape == (r.mesh.num_cells,) and not eta.flags.writeable
    assert float(np.sum(eta ** 2)) == pytest.approx(e["energy"] ** 2, rel=1e-12)
    assert "estimate" in r.timings


def test_a_solid_held_by_its_foundation_names_the_motion():
    # a block between rollers on its four sides, on a linear foundation: held vertically by it alone
    r = hemivem.solve(ROOT / "scenes" / "block-between-rollers-3d.toml")
    assert r.converged
    assert len(r.held_by_contact) == 1 and "translation along (0, 0, 1)" in r.held_by_contact[0]
    assert r.json()["held_by_contact"] == r.held_by_contact
    # every contact node settles by the pressure over the stiffness
    assert np.allclose(r.contact.u_nu, 2.0 / 50.0, rtol=0, atol=1e-10)


def test_a_solid_on_a_mesh_of_ones_own(small_3d):
    scene, r = small_3d
    # the Result's own mesh again: the same solve, bit for bit
    again = hemivem.solve(scene, mesh=r.mesh, linear="eigen")
    assert again.energy == r.energy
    assert np.array_equal(again.displacement, r.displacement)
    # a generated mesh of the same box
    box = r.mesh.bounding_box
    m = hemivem.Mesh3D.generate("tetrahedra", [2, 2, 2], box)
    t = hemivem.solve(scene, mesh=m, linear="eigen")
    assert t.converged and t.mesh.num_cells == m.num_cells
    with pytest.raises(TypeError, match="hemivem.Mesh or a hemivem.Mesh3D"):
        hemivem.solve(scene, mesh="not a mesh")


def test_a_solid_path_settles_by_the_load_over_the_stiffness():
    # the block between rollers on a linear foundation: uniaxial strain, u_nu = t * 2 / 50 at
    # every contact node and step, the foundation carrying 2 t on an area of 3
    scene = ROOT / "scenes" / "block-between-rollers-3d.toml"
    r = hemivem.solve_path(scene, steps=4, frames=2)
    assert r.dimension == 3 and r.converged and len(r.path) == 4 and r.path.converged
    np.testing.assert_allclose(r.path.t, [0.25, 0.5, 0.75, 1.0], rtol=0, atol=1e-15)
    for step in r.path:
        assert step.converged and len(step.contact_force) == 3 and len(step.applied_load) == 3
        np.testing.assert_allclose(step.contact.u_nu, 0.04 * step.t, rtol=0, atol=1e-10)
        assert step.contact_force[2] == pytest.approx(6.0 * step.t, rel=1e-9)
        assert "z" in step.contact.columns
    frames = [s.index for s in r.path if s.displacement is not None]
    assert frames[-1] == 4 and len(frames) == 2
    assert r.path[-1].displacement.shape == (r.mesh.num_vertices, 3)
    static = hemivem.solve(scene)
    np.testing.assert_allclose(r.displacement, static.displacement, rtol=0, atol=1e-10 * np.abs(static.displacement).max())
    assert r.path.json()["steps"][-1]["contact_force"][2] == pytest.approx(6.0, rel=1e-9)


def test_an_adaptive_solve_of_a_solid(small_3d):
    _, first = small_3d
    scene = hemivem.Scene.from_toml(EXAMPLE_3D)
    scene.set("mesh.n", 4)
    scene.set("adapt.max_steps", 3)
    scene.set("adapt.target", 0.001)
    r = hemivem.solve(scene, linear="eigen")
    a = r.adapt
    assert a["stopped"] == "max_steps"
    steps = a["steps"]
    assert len(steps) == 3
    assert steps[0]["potential_energy"] == pytest.approx(first.energy, rel=1e-10)
    assert steps[-1]["unknowns"] > steps[0]["unknowns"]
    assert steps[-1]["estimate"] < steps[0]["estimate"]
    assert r.mesh.num_cells == steps[-1]["elements"]
    assert r.indicators.shape == (r.mesh.num_cells,)
    assert r.displacement.shape == (r.mesh.num_vertices, 3)


def test_friction_on_a_solid_has_vectors_in_the_tangent_plane():
    # Tresca's law of bound g on the length of u_tau: a stuck node has u_tau = 0 and a friction
    # force inside the disc of radius g w; a slipping one the force g w along its u_tau
    r = hemivem.solve(ROOT / "scenes" / "friction-block-3d.toml")
    assert r.converged
    t, g = r.contact, 0.8
    n = len(t)
    assert t.u_tau.shape == (n, 3) and t.friction_force.shape == (n, 3) and t.friction_traction.shape == (n, 3)
    np.testing.assert_allclose(np.einsum("ij,ij->i", t.u_tau, t.normal), 0.0, atol=1e-15)
    np.testing.assert_allclose(np.einsum("ij,ij->i", t.friction_force, t.normal), 0.0, atol=1e-15)
    np.testing.assert_allclose(t.friction_traction, t.friction_force / t.weight[:, None], rtol=1e-14, atol=0)
    force = np.linalg.norm(t.friction_force, axis=1)
    stick, slip = t.friction_state == "stick", t.friction_state == "slip"
    assert stick.any() and slip.any() and (stick | slip).all()
    assert not t.u_tau[stick].any()
    assert (force[stick] <= g * t.weight[stick] * (1 + 1e-10)).all()
    np.testing.assert_allclose(force[slip], g * t.weight[slip], rtol=1e-10)
    direction = t.u_tau[slip] / np.linalg.norm(t.u_tau[slip], axis=1)[:, None]
    np.testing.assert_allclose(t.friction_force[slip], force[slip][:, None] * direction, rtol=0, atol=1e-10 * g)
    j = r.json()
    assert j["friction"]["nodes"] == {"stick": int(stick.sum()), "slip": int(slip.sum())}
    assert len(j["contact"][0]["u_tau"]) == 3

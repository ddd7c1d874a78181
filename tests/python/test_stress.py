"""Cell stresses where users look for them: Result.stress, stress.csv, result.json's "stress"
and the summary's stress line, plane and solid. The stresses of a linear displacement (the
patch test: VEM reproduces it exactly) are Hooke's law of its strain, computed here; von Mises
by its formula; the file, the document and the summary against the arrays."""

import json
import pathlib
import re

import numpy as np
import pytest

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]

YOUNG, POISSON = 200.0, 0.3
# u = G x with a constant gradient G: a uniform strain, exact for the lowest-order VEM
GRADIENT_2D = np.array([[1.0e-3, 4.0e-4], [-2.0e-4, -6.0e-4]])
GRADIENT_3D = np.array([[1.0e-3, 4.0e-4, -3.0e-4], [-2.0e-4, -6.0e-4, 5.0e-4], [7.0e-4, 1.0e-4, 2.0e-4]])


def lame(young, nu):
    return young * nu / ((1 + nu) * (1 - 2 * nu)), young / (2 * (1 + nu))


def hooke(gradient, lam, mu):
    strain = 0.5 * (gradient + gradient.T)
    return lam * np.trace(strain) * np.eye(len(gradient)) + 2 * mu * strain


def expression(row, names):
    return " + ".join(f"({g!r})*{x}" for g, x in zip(row, names))


def linear_scene_2d(model, generator="voronoi"):
    ux, uy = (expression(GRADIENT_2D[i], "xy") for i in range(2))
    return f"""
schema_version = 1
title = "uniform strain"
[mesh]
generator = "{generator}"
n = 6
[material]
E = {YOUNG}
nu = {POISSON}
model = "{model}"
[[dirichlet]]
side = ["left", "right", "top", "bottom"]
value = ["{ux}", "{uy}"]
"""


def linear_scene_3d():
    value = ", ".join(f'"{expression(GRADIENT_3D[i], "xyz")}"' for i in range(3))
    return f"""
schema_version = 1
title = "uniform strain"
[mesh]
generator = "tetrahedra"
n = [2, 2, 2]
domain = [0.0, 1.0, 0.0, 0.5, 0.0, 1.0]
[material]
E = {YOUNG}
nu = {POISSON}
[[dirichlet]]
side = ["x0", "x1", "y0", "y1", "z0", "z1"]
value = [{value}]
"""


def von_mises(t):
    """von Mises of rows xx, yy, zz, yz, xz, xy (a plane's yz = xz = 0)."""
    xx, yy, zz, yz, xz, xy = t.T
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3 * (yz**2 + xz**2 + xy**2))


def full_tensor(stress):
    """The (n, 6) rows xx, yy, zz, yz, xz, xy of a StressTable."""
    t = stress.tensor
    if t.shape[1] == 6:
        return t
    z = np.zeros(len(t))
    return np.column_stack([t[:, 0], t[:, 1], t[:, 2], z, z, t[:, 3]])


@pytest.mark.parametrize("model", ["plane-strain", "plane-stress"])
def test_uniform_strain_gives_hookes_stress_in_every_cell_of_a_plane(model):
    r = hemivem.solve(linear_scene_2d(model), linear="eigen")
    s = r.stress
    n = r.mesh.num_elements
    assert s.components == ("xx", "yy", "zz", "xy")
    assert s.tensor.shape == (n, 4) and s.von_mises.shape == (n,) and s.centroids.shape == (n, 2)
    assert s.tensor.dtype == np.float64 and len(s) == n
    lam, mu = lame(YOUNG, POISSON)
    if model == "plane-stress":
        lam = 2 * lam * mu / (lam + 2 * mu)
    sigma = hooke(GRADIENT_2D, lam, mu)
    zz = lam * np.trace(GRADIENT_2D) if model == "plane-strain" else 0.0
    expected = np.array([sigma[0, 0], sigma[1, 1], zz, sigma[0, 1]])
    scale = np.abs(expected).max()
    assert np.abs(s.tensor - expected).max() <= 1e-10 * scale
    assert np.abs(s.von_mises - von_mises(full_tensor(s))).max() <= 1e-14 * scale
    assert np.array_equal(s.centroids, r.mesh.centroids)


def test_uniform_strain_gives_hookes_stress_in_every_cell_of_a_solid():
    r = hemivem.solve(linear_scene_3d(), linear="eigen")
    assert r.dimension == 3
    s = r.stress
    n = r.mesh.num_cells
    assert s.components == ("xx", "yy", "zz", "yz", "xz", "xy")
    assert s.tensor.shape == (n, 6) and s.von_mises.shape == (n,) and s.centroids.shape == (n, 3)
    sigma = hooke(GRADIENT_3D, *lame(YOUNG, POISSON))
    expected = np.array([sigma[0, 0], sigma[1, 1], sigma[2, 2], sigma[1, 2], sigma[0, 2], sigma[0, 1]])
    scale = np.abs(expected).max()
    assert np.abs(s.tensor - expected).max() <= 1e-10 * scale
    assert np.abs(s.von_mises - von_mises(s.tensor)).max() <= 1e-14 * scale
    assert np.array_equal(s.centroids, r.mesh.centroids)


def read_csv(path):
    lines = path.read_text().splitlines()
    return lines[0].split(","), np.array([[float(v) for v in line.split(",")] for line in lines[1:]])


def summary_peak(report):
    m = re.search(r"^  stress        max von Mises (\S+) in cell (\d+), centroid \(([^)]*)\)$", report, re.M)
    assert m, report
    return float(m.group(1)), int(m.group(2)), [float(x) for x in m.group(3).split(",")]


def check_files_and_summary(r, folder):
    """stress.csv equals the arrays (shortest round-trip text: exactly); result.json's stress
    and the summary's line name the largest von Mises stress and its cell."""
    s = r.stress
    dim = r.dimension
    written = [p.name for p in r.write(folder)]
    assert "stress.csv" in written
    header, rows = read_csv(folder / "stress.csv")
    axes = ["x", "y", "z"][:dim]
    assert header == ["cell", *axes, *("s" + c for c in s.components), "von_mises"]
    assert np.array_equal(rows[:, 0], np.arange(len(s)))
    assert np.array_equal(rows[:, 1 : 1 + dim], s.centroids)
    assert np.array_equal(rows[:, 1 + dim : -1], s.tensor)
    assert np.array_equal(rows[:, -1], s.von_mises)
    cell = int(np.argmax(s.von_mises))
    assert s.max_cell == cell and s.max_von_mises == s.von_mises.max()
    j = json.loads((folder / "result.json").read_text())
    assert j["schema"] == "hemivem-result/26"
    assert j["stress"] == {"max_von_mises": s.von_mises.max(), "cell": cell, "centroid": list(s.centroids[cell])}
    assert r.json()["stress"] == j["stress"]
    value, printed_cell, centroid = summary_peak(r.full_report())
    assert printed_cell == cell
    assert value == pytest.approx(s.von_mises.max(), rel=1e-5)  # printed to 6 digits
    assert centroid == pytest.approx(list(s.centroids[cell]), rel=1e-5, abs=1e-12)


def test_files_and_summary_of_a_plane_solve(tmp_path):
    r = hemivem.solve(_small_default())
    check_files_and_summary(r, tmp_path / "out")


def _small_default():
    s = hemivem.Scene.default()
    s.set("mesh.n", 12)
    return s


def test_files_and_summary_of_a_solid_solve(tmp_path):
    s = hemivem.Scene.from_file(ROOT / "scenes" / "example-4.1-3d.toml")
    s.set("mesh.n", [3, 3, 2])
    r = hemivem.solve(s)
    check_files_and_summary(r, tmp_path / "out")


def test_stress_csv_is_an_output_chosen_like_the_others(tmp_path):
    s = _small_default()
    assert "stress-csv" in s.get("output.write")  # on by default, as every CSV
    s.set("output.write", ["result-json", "displacement-csv"])
    r = hemivem.solve(s)
    written = sorted(p.name for p in r.write(tmp_path / "out"))
    assert written == ["displacement.csv", "result.json", "scene.toml"]
    assert "stress.csv" not in json.loads((tmp_path / "out" / "result.json").read_text())["files"]
    s.set("output.write", ["stress-csv"])
    assert [p.name for p in hemivem.solve(s).write(tmp_path / "only")] == ["stress.csv", "scene.toml"]


def test_the_command_writes_and_prints_the_same(tmp_path, run_command):
    scene = tmp_path / "scene.toml"
    _small_default().write(scene)
    out = tmp_path / "cli"
    p = run_command("solve", scene, "--out", out)
    r = hemivem.solve(scene)
    assert (out / "stress.csv").read_text() == _written(r, tmp_path / "py", "stress.csv")
    value, cell, _ = summary_peak(p.stdout)
    assert cell == r.stress.max_cell and value == pytest.approx(r.stress.max_von_mises, rel=1e-5)
    assert "stress.csv" in p.stdout


def _written(r, folder, name):
    r.write(folder)
    return (folder / name).read_text()

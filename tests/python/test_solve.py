"""hemivem.solve against the command `hemivem solve`: the same numbers and the same files."""

import csv
import json
import pathlib
import threading
import time

import numpy as np
import pytest

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]

PAIRS = [("cholmod", "ssn"), ("eigen", "bundle-dca"), ("mumps", "nlopt-mma"), ("cholmod", "ceres-active-set")]


def built_pairs():
    engines = hemivem.available_engines()
    return [(l, m) for l, m in PAIRS if l in engines["linear"] and m in engines["minimizer"]]


@pytest.mark.parametrize("linear,minimizer", built_pairs())
def test_result_equals_command(tmp_path, run_command, small_scene, linear, minimizer):
    out = tmp_path / "cmd"
    run_command("solve", "--n", 16, "--linear", linear, "--minimizer", minimizer, "--out", out, "-q")
    expected = json.loads((out / "result.json").read_text())
    r = hemivem.solve(small_scene, linear=linear, minimizer=minimizer)
    assert r.status == expected["status"] == "converged"
    assert r.converged and r.linear == expected["backends"]["linear"] and r.minimizer == expected["backends"]["minimizer"]
    u_cmd = np.array([n["u_nu"] for n in expected["contact"]])
    assert r.contact.u_nu.shape == u_cmd.shape
    assert np.max(np.abs(r.contact.u_nu - u_cmd)) <= 1e-12 * np.max(np.abs(u_cmd))
    assert list(r.contact.state) == [n["state"] for n in expected["contact"]]
    assert r.contact.vertex.tolist() == [n["vertex"] for n in expected["contact"]]
    assert r.energy == pytest.approx(expected["potential_energy"], rel=1e-12)
    assert r.iterations == expected["iterations"]
    assert r.stages == expected["stages"]
    with open(out / "displacement.csv") as f:
        rows = list(csv.DictReader(f))
    u = np.array([[float(row["ux"]), float(row["uy"])] for row in rows])
    assert np.max(np.abs(r.displacement - u)) <= 1e-12 * np.max(np.abs(u))


def test_write_gives_the_files_of_the_command(tmp_path, run_command, small_scene):
    out = tmp_path / "cmd"
    run_command("solve", "--n", 16, "--linear", "cholmod", "--out", out, "-q")
    r = hemivem.solve(small_scene, linear="cholmod")
    written = r.write(tmp_path / "py")
    assert sorted(p.name for p in written) == sorted(p.name for p in out.iterdir())
    for name in ["contact.csv", "displacement.csv", "stress.csv", "scene.toml"]:
        assert (tmp_path / "py" / name).read_text() == (out / name).read_text(), name
    mine = json.loads((tmp_path / "py" / "result.json").read_text())
    theirs = json.loads((out / "result.json").read_text())
    for doc in (mine, theirs):
        doc.pop("timings")
        doc["options"].pop("scene")  # the command's file name: <default> for both
    hist_py = (tmp_path / "py" / "history.csv").read_text().splitlines()
    hist_cmd = (out / "history.csv").read_text().splitlines()
    assert [line.rsplit(",", 1)[0] for line in hist_py] == [line.rsplit(",", 1)[0] for line in hist_cmd]
    assert mine == theirs
    assert r.json()["contact"] == theirs["contact"]


def test_write_some_files_and_refuse_unknown(tmp_path, small_scene):
    r = hemivem.solve(small_scene, linear="eigen")
    assert [p.name for p in r.write(tmp_path / "a", files=["result.json"])] == ["result.json"]
    with pytest.raises(hemivem.InputError):
        r.write(tmp_path / "b", files=["nonsense.txt"])


def test_arrays_shapes_dtypes_and_order(small_scene):
    r = hemivem.solve(small_scene)
    mesh = r.mesh
    d = r.displacement
    assert d.shape == (mesh.num_vertices, 2) and d.dtype == np.float64
    assert d.flags.c_contiguous and not d.flags.writeable
    assert d.base is not None  # a view of the result's memory, not a copy
    t = r.contact
    n = len(t)
    assert n == 15
    for name in ["x", "y", "u_nu", "law_force", "reaction", "pressure", "gap", "weight"]:
        assert t[name].shape == (n,) and t[name].dtype == np.float64, name
    assert t.vertex.dtype == np.int32 and t.normal.shape == (n, 2)
    assert t.state.dtype.kind == "U" and set(t.state) <= {"at-gap", "at-minus-gap", "in-contact", "separated"}
    assert np.allclose(t.pressure * t.weight, t.law_force + t.reaction, rtol=1e-14, atol=0)
    assert np.array_equal(t.u_nu, r.a)
    assert np.allclose(mesh.vertices[t.vertex][:, 1], 0.0)
    assert r.a.shape == (n,) and r.history["primal"].dtype == np.float64
    assert set(r.timings) >= {"mesh", "assembly", "condensation", "minimize", "back_substitution", "total"}
    assert isinstance(r.certificate, hemivem.Certificate) and r.certificate.converged


def test_no_contact_is_one_linear_solve():
    s = hemivem.Scene.from_toml(ROOT / "scenes" / "linear-elastic.toml")
    r = hemivem.solve(s)
    assert r.converged and r.stages == ["assembly", "linear_solve", "estimate"] and len(r.contact) == 0 and r.reduced is None
    assert r.certificate.dual < 1e-10


def test_engine_parameters_as_keywords(small_scene):
    r = hemivem.solve(small_scene, minimizer="ssn", armijo=1e-3)
    assert r.converged
    assert r.scene.get("solver.parameters.armijo") == 1e-3
    with pytest.raises(hemivem.InputError) as e:
        hemivem.solve(small_scene, minimizer="ssn", foo=1)
    assert "unknown parameter 'foo'; ssn knows armijo" in str(e.value)
    with pytest.raises(hemivem.InputError) as e:
        hemivem.solve(small_scene, max_backtracks=2.5)
    assert "max_backtracks" in str(e.value) and "must be an integer" in str(e.value)


def test_solve_releases_the_gil(small_scene):
    s = small_scene.copy()
    s.set("mesh.n", 128)
    done = []
    t = threading.Thread(target=lambda: done.append(hemivem.solve(s, linear="eigen")))
    ticks = 0
    t.start()
    while t.is_alive():
        ticks += 1
        time.sleep(0.001)
    t.join()
    assert done and done[0].converged
    assert ticks > 20  # the main thread ran while the solve did


def test_ctrl_c_stops_a_solve(small_scene):
    import _thread

    s = small_scene.copy()
    s.set("mesh.n", 256)
    timer = threading.Timer(0.2, _thread.interrupt_main)
    timer.start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        hemivem.solve(s, linear="eigen", minimizer="nlopt-mma")
    timer.cancel()
    assert time.perf_counter() - t0 < 60


def test_reports_are_the_commands_summary(tmp_path, run_command, small_scene):
    p = run_command("solve", "--n", 16, "--linear", "cholmod", "--out", tmp_path / "cmd")
    printed = p.stdout.splitlines()
    r = hemivem.solve(small_scene, linear="cholmod")
    full = r.full_report().splitlines()
    # the command prints its title, the full report, then the files it wrote
    assert printed[0].startswith("hemivem solve: ") and printed[len(full) + 1].startswith("  wrote ")
    for mine, theirs in zip(full, printed[1 : len(full) + 1]):
        if mine.startswith("  time [s]"):  # the same stages, other seconds
            assert [w for w in mine.split() if w.isalpha()] == [w for w in theirs.split() if w.isalpha()]
        else:
            assert mine == theirs
    brief = r.brief_report()
    assert brief.startswith(f"converged (certificate: primal {r.certificate.primal:.3e}, dual {r.certificate.dual:.3e}")
    assert f"{r.iterations} iterations, energy " in brief and brief.endswith(" s") and "\n" not in brief

"""hemivem.check, hemivem.study and hemivem.bench give the numbers of `hemivem check --json`,
`hemivem study --json` and `hemivem bench --json` (app::run_check, run_study, run_bench): the
module and the command are two routes to one computation, compared here number by number."""

import json
import math
import os

import numpy as np
import pytest

import hemivem

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def same(a, b, rel=1e-9):
    if a is None or b is None:
        return a is None and b is None
    return math.isclose(a, b, rel_tol=rel, abs_tol=1e-300)


def test_check_is_the_commands_check(run_command, small_scene):
    others = [m for m in hemivem.available_engines()["minimizer"] if m != "ssn"]
    pairs = [("eigen", "ssn")] + [("eigen", m) for m in others[:1]]
    r = hemivem.check(small_scene, tolerance=1e-10, pairs=pairs)
    cmd = json.loads(run_command("check", "--n", "16", "--tol", "1e-10", "--json").stdout)
    assert r["schema"] == cmd["schema"] == "hemivem-check/5"
    assert r["unique"] and r["exit_code"] == 0
    by_label = {(p["linear"], p["minimizer"]): p for p in cmd["pairs"]}
    for p in r["pairs"]:
        c = by_label[(p["linear"], p["minimizer"])]
        assert p["status"] == c["status"]
        assert p["iterations"] == c["iterations"]
        assert same(p["potential_energy"], c["potential_energy"])
        assert p["displacement"].shape == (2 * 17 * 17,)
    assert same(r["reference"]["max_abs_u"], cmd["reference"]["max_abs_u"])
    d = r["differences"]
    assert isinstance(d, np.ndarray) and d.shape == (len(r["pairs"]), len(r["pairs"]))
    # the matrix is the displacements' difference, relative to the reference's max|u|
    if len(r["pairs"]) > 1:
        u0, u1 = r["pairs"][0]["displacement"], r["pairs"][1]["displacement"]
        assert same(d[0, 1], np.max(np.abs(u0 - u1)) / r["reference"]["max_abs_u"], 1e-12)


def test_check_runs_the_full_space_route_with_every_krylov_engine(small_scene):
    # the default pairs: every condensed pair built and each Krylov engine with ssn; mumps-mpi
    # runs under an MPI launcher only
    r = hemivem.check(small_scene)
    labels = [(p["linear"], p["minimizer"]) for p in r["pairs"]]
    krylov = hemivem.available_engines()["krylov"]
    assert "eigen-cg" in krylov
    for engine in krylov:
        assert [m for linear, m in labels if linear == engine] == ["ssn"]
    assert not any(linear == "mumps-mpi" for linear, _ in labels)
    for p in r["pairs"]:
        assert p["route"] == ("full_space" if p["linear"] in krylov else "condensed")
    assert r["exit_code"] == 0 and r["unique"] and r["refused"] == [], r["verdict"]
    reference = r["pairs"][labels.index(("eigen", "ssn"))]
    scale = np.abs(reference["displacement"]).max()
    for engine in krylov:
        full = r["pairs"][labels.index((engine, "ssn"))]
        assert full["converged"] and full["max_difference"] < 1e-6
        assert np.abs(full["displacement"] - reference["displacement"]).max() <= 1e-6 * scale
    with pytest.raises(hemivem.InputError) as e:
        hemivem.check(small_scene, pairs=[("mumps-mpi", "ssn")])
    assert e.value.where == "pairs"


def test_check_solves_a_body_held_by_its_contact_alone_on_both_routes():
    # a block held vertically by its contact alone: the full-space pair solves it as the
    # condensed pair does, and agrees with it
    scene = hemivem.Scene.from_toml(os.path.join(ROOT, "scenes", "block-between-rollers.toml"))
    scene.set("mesh.n", [8, 2])
    r = hemivem.check(scene, pairs=[("eigen", "ssn"), ("eigen-cg", "ssn")])
    assert r["exit_code"] == 0, r["verdict"]
    assert r["pairs"][0]["converged"] and r["pairs"][1]["converged"], r["pairs"][1]["message"]
    assert r["pairs"][1]["route"] == "full_space"
    assert r["refused"] == []
    assert r["differences"][0, 1] <= 1e-8


def test_check_refuses_an_agree_that_is_not_positive():
    with pytest.raises(hemivem.InputError) as e:
        hemivem.check(agree=0.0, pairs=[("eigen", "ssn")])
    assert e.value.where == "agree"


def test_study_is_the_commands_study(run_command, tmp_path):
    r = hemivem.study(n=[4, 8], ref=16, out=tmp_path / "py")
    cmd = json.loads(run_command("study", "--n", "4,8", "--ref", "16", "--out", tmp_path / "cmd",
                                 "--json").stdout)
    assert r["schema"] == cmd["schema"] == "hemivem-study/2"
    assert same(r["reference"]["energy_norm"], cmd["reference"]["energy_norm"])
    assert [row["n"] for row in r["rows"]] == [row["n"] for row in cmd["rows"]] == [4, 8]
    for a, b in zip(r["rows"], cmd["rows"]):
        for key in ("h", "error", "rate", "paper", "independent", "estimate", "effectivity"):
            assert same(a[key], b[key]), key
    assert np.allclose(r["error"], [row["error"] for row in cmd["rows"]], rtol=1e-9, atol=0)
    assert list(r["h"]) == [0.25, 0.125]
    # the files are the command's, but for the seconds
    written = json.loads((tmp_path / "py" / "study.json").read_text())
    assert written["rows"][1]["error"] == r["rows"][1]["error"]
    assert "study.csv" in r["files"]


def test_study_refuses_sizes_that_do_not_nest():
    with pytest.raises(hemivem.InputError) as e:
        hemivem.study(n=[3], ref=16)
    assert e.value.where == "n"


def test_bench_is_the_commands_bench(run_command, tmp_path):
    # a condensed pair and the full-space route's (eigen-cg with ssn), as the command's rows
    r = hemivem.bench(n=[4, 8], ref=16, levels=1, pairs=[("eigen", "ssn"), ("eigen-cg", "ssn")])
    cmd = json.loads(run_command("bench", "--n", "4,8", "--ref", "16", "--levels", "1", "--out",
                                 tmp_path, "--json").stdout)
    assert r["schema"] == cmd["schema"] == "hemivem-bench/6"
    rows = {(c["linear"], c["minimizer"], c["n"]): c for c in cmd["rows"]}
    assert len(r["rows"]) == 4
    for row in r["rows"]:
        c = rows[(row["linear"], row["minimizer"], row["n"])]
        assert row["status"] == c["status"] == "converged"
        assert row["iterations"] == c["iterations"]
        assert row["route"] == c["route"] == ("full_space" if row["linear"] == "eigen-cg" else "condensed")
        assert same(row["error"], c["error"], 1e-6)
        if row["route"] == "full_space":  # timed by its own stages
            assert row["seconds"]["posing"] > 0 and row["seconds"]["full_space"] > 0
            assert row["seconds"]["condensation"] == 0
    assert r["reference"]["n"] == cmd["reference"]["n"] == 16
    assert same(r["reference"]["max_abs_u"], cmd["reference"]["max_abs_u"])
    ru, cu = r["refinement"]["uniform"], cmd["refinement"]["uniform"]
    assert len(ru) == len(cu) == 2
    for a, b in zip(ru, cu):
        assert a["unknowns"] == b["unknowns"]
        assert same(a["potential_energy"], b["potential_energy"])
        assert same(a["estimate"], b["estimate"])


COULOMB_PATH = "[path]\nt = [0.5, 1.0, 1.5]\nframes = 3\n"


def test_check_compares_a_coulomb_path_at_every_step_as_solve_path_solves_it(coulomb_scene):
    scene = coulomb_scene(4, COULOMB_PATH)
    r = hemivem.check(scene, pairs=[("eigen", "ssn")])
    assert r["exit_code"] == 0, r["verdict"]
    assert [s["t"] for s in r["path"]["steps"]] == [0.5, 1.0, 1.5]
    pair = r["pairs"][0]
    alone = hemivem.solve_path(scene, t=[0.5, 1.0, 1.5], frames=3)
    for step, u in zip(alone.path, pair["path_displacements"]):
        scale = np.abs(step.displacement).max()
        np.testing.assert_allclose(u, step.displacement.reshape(-1), rtol=0, atol=1e-10 * scale)
    np.testing.assert_array_equal(pair["displacement"], pair["path_displacements"][-1])


def test_bench_measures_a_coulomb_path_at_its_last_step(coulomb_scene):
    r = hemivem.bench(coulomb_scene(4, COULOMB_PATH), n=[4], ref=8, levels=1, pairs=[("eigen", "ssn")])
    assert r["path"]["steps"] == 3
    assert r["rows"][0]["error"] > 0
    assert r["refinement"]["adaptive"]["stopped"] == "not_run"


def test_a_study_whose_figure_fails_is_a_user_warning(tmp_path, monkeypatch):
    fake = tmp_path / "bin" / "gnuplot"
    fake.parent.mkdir()
    fake.write_text("#!/bin/sh\necho 'broken on purpose' >&2\nexit 1\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{fake.parent}:{os.environ['PATH']}")
    expected = "figure not drawn: study.png: gnuplot failed (exit status 1): broken on purpose"
    with pytest.warns(UserWarning, match="figure not drawn: study.png"):
        s = hemivem.study(n=[2, 4], ref=8, out=str(tmp_path / "out"))
    assert s["warnings"] == [expected]
    assert s["files"] == ["study.csv", "study.json"]
    assert json.loads((tmp_path / "out" / "study.json").read_text())["warnings"] == [expected]
    assert len(s["h"]) == 2, "the numbers are returned all the same"

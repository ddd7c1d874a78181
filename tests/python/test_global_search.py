"""The global search from Python: solve(search="global") against `hemivem solve --global`,
minimize(search="global") against exact enumeration (tests/test_nonconvex.cpp) and against
`hemivem minimize --global`, progress, Ctrl-C and the errors of its fields."""

import _thread
import json
import math

import numpy as np
import pytest

import hemivem

# F at the global minimum of Example 4.1 on 6 x 6 squares with the sawtooth law, by
# enumeration of every face of the box (tests/test_nonconvex.cpp,
# GlobalSearch.Example41WithTheSawtoothLawAgainstEnumeration)
GLOBAL_MINIMUM = -0.0186541


@pytest.fixture()
def sawtooth_scene():
    """Example 4.1 on 6 x 6 squares with the sawtooth law: several critical points."""
    s = hemivem.Scene.default()
    s.update({"mesh.n": 6, "contact.law": "sawtooth"})
    return s


def close(a, b):
    return abs(a - b) <= 1e-12 * max(abs(a), abs(b))


def test_global_solve_equals_command(tmp_path, run_command, sawtooth_scene):
    out = tmp_path / "cmd"
    run_command("solve", "--n", 6, "--set", 'contact.law="sawtooth"', "--global", "--out", out, "-q")
    expected = json.loads((out / "result.json").read_text())
    assert expected["search"]["kind"] == "global" and len(expected["critical_points"]) >= 2

    r = hemivem.solve(sawtooth_scene, search="global")
    assert r.converged and r.search == expected["search"]
    assert r.minimizer == expected["backends"]["minimizer"]
    assert close(r.energy, expected["potential_energy"])
    points = r.critical_points
    assert len(points) == len(expected["critical_points"])
    for k, (mine, theirs) in enumerate(zip(points, expected["critical_points"])):
        assert close(mine.reduced_objective, theirs["reduced_objective"]), k
        assert close(mine.potential_energy, theirs["potential_energy"]), k
        assert mine.starts == theirs["starts"] and mine.engines == theirs["engines"], k
        assert mine.certificate.primal == theirs["certificate"]["primal"], k
        assert mine.certificate.dual == theirs["certificate"]["dual"], k
    # lowest first; the solution is the first; every point is certified by the reduced problem
    objectives = [p.reduced_objective for p in points]
    assert objectives == sorted(objectives)
    assert points[0].potential_energy == r.energy and np.array_equal(points[0].a, r.a)
    for p in points:
        assert p.a.shape == (r.reduced.size,) and p.a.dtype == np.float64 and not p.a.flags.writeable
        assert r.reduced.certificate(p.a).converged
        assert r.reduced.energy(p.a) == pytest.approx(p.reduced_objective, rel=1e-12)
    # the same through the scene key, and the same result.json as the command's but for timings
    # (and the scene's file name, <default> for both)
    s = sawtooth_scene.copy()
    s.set("solver.search", "global")
    again = hemivem.solve(s)
    assert [p.reduced_objective for p in again.critical_points] == objectives
    again.write(tmp_path / "py")
    mine = json.loads((tmp_path / "py" / "result.json").read_text())
    for doc in (mine, expected):
        doc.pop("timings")
        doc["options"].pop("scene")
    assert mine == expected


def test_critical_points_outlive_the_result(sawtooth_scene):
    r = hemivem.solve(sawtooth_scene, search="global")
    points = r.critical_points
    a = points[1].a
    expected = a.copy()
    del r, points
    import gc

    gc.collect()
    assert np.array_equal(a, expected)


def test_local_search_has_one_kind_and_no_critical_points(sawtooth_scene):
    r = hemivem.solve(sawtooth_scene)
    assert r.search == {"kind": "local"} and r.critical_points == []
    assert r.json()["search"] == {"kind": "local"} and r.json()["critical_points"] == []
    assert hemivem.minimize(r.reduced).critical_points == []


def test_global_minimize_reaches_the_global_minimum(sawtooth_scene):
    p = hemivem.condense(sawtooth_scene)
    assert p.uniqueness_margin < 0
    m = hemivem.minimize(p, search="global")
    assert m.converged and abs(m.objective - GLOBAL_MINIMUM) <= 5e-7
    # bundle-dca alone, from the default start, stops at a higher critical point (certified)
    local = hemivem.minimize(p, "bundle-dca")
    assert local.converged and p.certificate(local.a).converged
    assert local.objective > m.objective + 1e-5
    # every critical point found is certified, lowest first; a reduced problem alone has no
    # potential energy
    points = m.critical_points
    assert len(points) >= 2 and np.array_equal(points[0].a, m.a)
    assert points[0].reduced_objective == m.objective
    assert [q.reduced_objective for q in points] == sorted(q.reduced_objective for q in points)
    for q in points:
        assert p.certificate(q.a).converged and q.potential_energy is None and q.starts >= 1
        assert set(q.engines) <= set(hemivem.available_engines()["minimizer"])
    # the local minimum bundle-dca stopped at is one of them
    assert any(np.max(np.abs(q.a - local.a)) <= 1e-6 * np.max(np.abs(local.a)) for q in points)
    # the search's first engine is the one named
    first = hemivem.minimize(p, "bundle-dca", search="global", max_starts=4)
    assert len(first.history["iteration"]) == 4
    assert first.critical_points and "bundle-dca" in first.critical_points[0].engines


def test_global_minimize_equals_command(tmp_path, run_command, sawtooth_scene):
    red = tmp_path / "red"
    run_command("solve", "--n", 6, "--set", 'contact.law="sawtooth"', "--out", tmp_path / "out",
                "--export-reduced", red, "-q")
    cmd = run_command("minimize", red, "--global", "--max-starts", 20, "--seed", 3, "--json")
    expected = json.loads(cmd.stdout)
    m = hemivem.minimize(hemivem.ReducedProblem.read(red), search="global", max_starts=20, seed=3)
    assert close(m.objective, expected["reduced_objective"])
    assert len(m.critical_points) == len(expected["critical_points"])
    for mine, theirs in zip(m.critical_points, expected["critical_points"]):
        assert close(mine.reduced_objective, theirs["reduced_objective"])
        assert mine.starts == theirs["starts"] and mine.engines == theirs["engines"]
    assert np.max(np.abs(m.a - np.array(expected["a"]))) <= 1e-12 * np.max(np.abs(m.a))


def test_engines_keyword(sawtooth_scene):
    p = hemivem.condense(sawtooth_scene)
    m = hemivem.minimize(p, search="global", engines=["ceres-active-set"], max_starts=6)
    assert len(m.history["iteration"]) == 6
    assert {e for q in m.critical_points for e in q.engines} <= {"ssn", "ceres-active-set"}
    r = hemivem.solve(sawtooth_scene, search="global", engines=["bundle-dca"], max_starts=4)
    assert r.search["engines"] == ["ssn", "bundle-dca"]
    assert r.scene.get("solver.search_engines") == ["bundle-dca"]
    with pytest.raises(hemivem.InputError, match="unknown minimizer 'newton'"):
        hemivem.minimize(p, search="global", engines=["newton"])
    with pytest.raises(hemivem.InputError, match="solver.search_engines"):
        hemivem.solve(sawtooth_scene, search="global", engines=["newton"])


def test_budget_and_seed_keywords(sawtooth_scene):
    r = hemivem.solve(sawtooth_scene, search="global", max_starts=5, time_budget=30, seed=7)
    assert r.search["max_starts"] == 5 and r.search["time_budget"] == 30.0 and r.search["seed"] == 7
    assert r.scene.get("solver.search") == "global" and r.scene.get("solver.seed") == 7
    assert len(r.history["iteration"]) == 5  # one record per local run


def test_progress_after_every_local_run(sawtooth_scene):
    p = hemivem.condense(sawtooth_scene)
    seen = []
    m = hemivem.minimize(p, search="global", max_starts=12, progress=seen.append)
    assert [g.run for g in seen] == list(range(1, 13)) and all(g.max_runs == 12 for g in seen)
    assert seen[0].engine == "ssn" and seen[0].start == "given"
    assert seen[-1].lowest == m.objective and seen[-1].critical_points == len(m.critical_points)
    assert list(m.history["reduced_objective"]) == [g.objective for g in seen]
    assert seen[0].lowest == seen[0].objective if seen[0].certified else math.isnan(seen[0].lowest)

    def fail(g):
        if g.run == 2:
            raise RuntimeError("from progress")

    with pytest.raises(RuntimeError, match="from progress"):
        hemivem.minimize(p, search="global", progress=fail)
    runs = []
    r = hemivem.solve(sawtooth_scene, search="global", max_starts=6, progress=lambda g: runs.append(g.run))
    assert runs == list(range(1, 7)) and r.converged


def test_ctrl_c_stops_a_global_search(sawtooth_scene):
    p = hemivem.condense(sawtooth_scene)
    for call in (lambda progress: hemivem.minimize(p, search="global", progress=progress),
                 lambda progress: hemivem.solve(sawtooth_scene, search="global", progress=progress)):
        seen = []

        def interrupt(g):
            seen.append(g.run)
            if g.run == 3:
                _thread.interrupt_main()  # Ctrl-C, seen after the next local run

        with pytest.raises(KeyboardInterrupt):
            call(interrupt)
        assert seen == [1, 2, 3]


@pytest.mark.parametrize(
    "call,message",
    [
        (lambda s, p: hemivem.solve(s, search="globl"),
         "--set solver.search: unknown search 'globl'; did you mean 'global'?"),
        (lambda s, p: hemivem.solve(s, search="global", max_starts=0),
         "--set solver.max_starts: must be between 1 and 1000000, got 0"),
        (lambda s, p: hemivem.solve(s, search="global", time_budget=0),
         "--set solver.time_budget: must be a finite number of seconds > 0"),
        (lambda s, p: s.set("solver.search", "globl"), "--set solver.search: unknown search 'globl'"),
        (lambda s, p: hemivem.solve(s, progress=print), "progress: only a global search"),
        (lambda s, p: hemivem.minimize(p, search="globl"),
         "search: unknown search 'globl'; did you mean 'global'? (expected one of: local, global)"),
        (lambda s, p: hemivem.minimize(p, search="global", max_starts=0),
         "global search: max_starts: must be >= 1, got 0"),
        (lambda s, p: hemivem.minimize(p, search="global", time_budget=-1.0),
         "global search: time_budget: must be > 0, got -1"),
        (lambda s, p: hemivem.minimize(p, search="global", seed=-1), "global search: seed: must be >= 0, got -1"),
        (lambda s, p: hemivem.minimize(p, search="global", callback=print), "callback: a global search reports"),
        (lambda s, p: hemivem.minimize(p, progress=print), "progress: only a global search"),
    ],
)
def test_search_errors_name_the_field(sawtooth_scene, call, message):
    p = hemivem.ReducedProblem(np.eye(2), [1.0, 1.0], [1.0, 1.0], [1.0, 1.0], law="sawtooth")
    with pytest.raises(hemivem.InputError) as e:
        call(sawtooth_scene, p)
    assert str(e.value).startswith(message)

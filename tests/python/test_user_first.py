"""What a user reaches for first: an import that says what it needs, keywords that conflict
refused by name, and the engines Python can run."""

import os
import subprocess
import sys

import pytest

import hemivem


def test_import_without_numpy_fails_at_once_saying_what_to_install():
    package_parent = os.path.dirname(os.path.dirname(hemivem.__file__))
    code = "import sys\nsys.modules['numpy'] = None\nimport hemivem\n"
    env = dict(os.environ, PYTHONPATH=package_parent)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert p.returncode != 0
    last = p.stderr.strip().splitlines()[-1]
    assert last.startswith("ModuleNotFoundError: hemivem needs NumPy"), p.stderr
    assert "python3-numpy" in last and sys.executable in last
    # and with NumPy the same interpreter imports it
    ok = subprocess.run([sys.executable, "-c", "import hemivem"], capture_output=True, text=True, env=env)
    assert ok.returncode == 0, ok.stderr


def small_scene():
    s = hemivem.Scene.default()
    s.set("mesh.n", 6)
    return s


def test_solve_path_refuses_steps_with_t():
    with pytest.raises(hemivem.InputError, match="not both") as e:
        hemivem.solve_path(small_scene(), steps=3, t=[0.5, 1])
    assert e.value.where == "steps, t"


def test_solve_path_steps_or_t_replace_the_scenes_own():
    s = small_scene()
    s.set("path.t", [0.5, 1.0])
    assert len(hemivem.solve_path(s, steps=3).path) == 3
    s = small_scene()
    s.set("path.steps", 4)
    r = hemivem.solve_path(s, t=[0.25, 1.0])
    assert list(r.path.t) == [0.25, 1.0]


def test_keep_reduced_with_a_path_or_an_adaptive_solve_is_refused():
    for key in ("adapt.max_steps", "path.steps"):
        s = small_scene()
        s.set(key, 2)
        with pytest.raises(hemivem.InputError, match="no one reduced problem") as e:
            hemivem.solve(s, keep_reduced=True)
        assert e.value.where == "keep_reduced"
        assert hemivem.solve(s).reduced is None  # left out: none kept, no error
    assert hemivem.solve(small_scene()).reduced is not None
    assert hemivem.solve(small_scene(), keep_reduced=False).reduced is None


@pytest.mark.parametrize("keyword", [{"max_starts": 4}, {"time_budget": 5.0}, {"seed": 2}, {"engines": ["ssn"]}])
def test_global_search_keywords_with_a_local_search_are_refused(keyword):
    name = next(iter(keyword))
    with pytest.raises(hemivem.InputError, match="global search only") as e:
        hemivem.solve(small_scene(), **keyword)
    assert e.value.where == name
    p = hemivem.condense(small_scene())
    with pytest.raises(hemivem.InputError, match="global search only") as e:
        hemivem.minimize(p, **keyword)
    assert e.value.where == name


def test_global_search_keywords_name_every_one_given():
    with pytest.raises(hemivem.InputError) as e:
        hemivem.solve(small_scene(), seed=2, max_starts=3)
    assert e.value.where == "max_starts, seed"


def test_global_search_keywords_with_a_global_search_are_taken():
    r = hemivem.solve(small_scene(), search="global", max_starts=2, seed=3)
    assert r.search["kind"] == "global" and r.search["max_starts"] == 2 and r.search["seed"] == 3
    s = small_scene()
    s.set("solver.search", "global")
    assert hemivem.solve(s, max_starts=2).search["max_starts"] == 2
    m = hemivem.minimize(hemivem.condense(small_scene()), search="global", max_starts=2)
    assert m.critical_points


def test_available_engines_are_those_python_runs(run_command):
    engines = hemivem.available_engines()
    assert "mumps-mpi" not in engines["linear"]
    assert engines["fastest_linear"] in engines["linear"]
    for linear in engines["linear"]:  # each one listed runs
        assert hemivem.solve(small_scene(), linear=linear).converged, linear
    for linear in engines["command_only"]:  # each one set apart is refused, by name
        with pytest.raises(hemivem.InputError, match="not inside Python"):
            hemivem.solve(small_scene(), linear=linear)
    # together they are the engines the command was built with
    listed = run_command("backends").stdout
    built = []
    for label in ("linear engines:", "krylov engines (the full-space route):"):
        line = next(l for l in listed.splitlines() if l.startswith(label))
        built += line[len(label):].split()
    assert sorted(built) == sorted(engines["linear"] + engines["krylov"] + engines["command_only"])

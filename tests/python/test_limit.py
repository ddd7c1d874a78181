"""hemivem.limit gives limit.json of `hemivem bench --limit` (app::run_limit): the rows are checked
against the counts of their meshes and against their own numbers, since the timings of two runs
differ."""

import json
import pathlib

import pytest

import hemivem

EXAMPLE_3D = pathlib.Path(__file__).resolve().parents[2] / "scenes" / "example-4.1-3d.toml"

STAGES = ("mesh", "setup", "assembly", "condensation", "condition", "minimize", "back_substitution", "post_process",
          "release", "estimate", "result_json", "margin", "outputs")


def needs_cholmod():
    if "cholmod" not in hemivem.available_engines()["linear"]:
        pytest.skip("the cholmod engine was not built")


def check_row(row):
    """What a row holds whatever the machine's speed: positive times, the faster ordering, and
    ratios that are the quotients of the row's own numbers."""
    assert row["status"] == "converged"
    assert set(row["stages"]) == set(STAGES)
    assert all(row["stages"][k] >= 0.0 for k in STAGES)
    limit = row["limit"]
    assert limit["plain_assembly"] > 0.0 and limit["factorization"] > 0.0 and limit["factor_bytes"] > 0.0
    assert limit["ordering"] in ("amd", "metis")
    (other, other_seconds), = limit["other_orderings"].items()
    assert other != limit["ordering"]
    factor = limit["analysis"] + limit["factorization"]
    assert factor <= other_seconds
    solve = row["solve"]
    # the solve's wall time holds its stages up to result.json
    assert solve >= sum(row["stages"][k] for k in STAGES[:8]) * (1 - 1e-12)
    r = row["ratios"]
    assert r["solve_over_limit"] == pytest.approx(solve / (limit["plain_assembly"] + factor), rel=1e-12)
    assert r["assembly_over_plain"] == pytest.approx(row["stages"]["assembly"] / limit["plain_assembly"], rel=1e-12)
    assert r["condensation_over_factorization"] == pytest.approx(row["stages"]["condensation"] / factor, rel=1e-12)
    assert r["peak_rss_over_factor_and_matrix"] == pytest.approx(
        row["peak_rss_bytes"] / (limit["factor_bytes"] + limit["matrix_bytes"]), rel=1e-12)


def test_limit_of_a_plane_scene(small_scene):
    needs_cholmod()
    # a solve first: this process has run OpenMP's threads before the measurement forks
    solved = hemivem.solve(small_scene, linear="cholmod")
    d = hemivem.limit(small_scene, n=[16, 8, 16], repeat=2)
    assert d["schema"] == "hemivem-bench-limit/4"
    assert d["linear"] == "cholmod" and d["minimizer"] == "ssn" and d["repeat"] == 2
    json.dumps(d)  # a plain dict of JSON values
    assert [row["n"] for row in d["rows"]] == [8, 16]  # increasing, each once
    for row in d["rows"]:
        n = row["n"]
        # Example 4.1: x = 0 and x = 1 clamped, every other dof free; the contact nodes off them
        assert row["dofs"] == 2 * (n + 1) * (n - 1)
        assert row["contact_nodes"] == n - 1
        check_row(row)
    # the row at the scene's own size is the solve of the scene
    assert d["rows"][1]["dofs"] == solved.json()["mesh"]["dofs"]
    assert d["rows"][1]["contact_nodes"] == len(solved.a)


def test_limit_of_a_solid_on_cubes():
    needs_cholmod()
    s = hemivem.Scene.from_toml(EXAMPLE_3D)
    s.set("mesh.domain", [0, 1, 0, 1, 0, 1])
    d = hemivem.limit(s, n=[4])
    (row,) = d["rows"]
    # 4^3 boxes, x = 0 and x = 1 clamped: 3 (n + 1)^2 (n - 1) dofs; the bottom's nodes off them
    assert row["n"] == 4 and row["dofs"] == 3 * 5 * 5 * 3 and row["contact_nodes"] == 5 * 3
    check_row(row)


def test_limit_refuses_what_it_cannot_measure(small_scene):
    needs_cholmod()
    small_scene.set("mesh.generator", "voronoi")
    with pytest.raises(hemivem.InputError) as e:
        hemivem.limit(small_scene, n=[8])
    assert e.value.where == "mesh.generator" and "squares" in str(e.value)
    with pytest.raises(hemivem.InputError) as e:
        hemivem.limit(n=[8], repeat=0)
    assert e.value.where == "repeat"
    with pytest.raises(hemivem.InputError) as e:
        hemivem.limit(n=[0])
    assert e.value.where == "n"

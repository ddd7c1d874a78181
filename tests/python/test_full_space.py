"""The full-space route from Python: a Krylov engine given as `linear` solves the problem the
condensed route solves, to the same displacement, nothing factorized (docs/full-space.md)."""

import json
import pathlib

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


def test_the_petsc_engines_are_refused_by_name_as_command_only():
    engines = hemivem.available_engines()
    for name in ("petsc-gamg", "petsc-hypre"):
        assert name not in engines["krylov"]
        with pytest.raises(hemivem.InputError, match=name):
            hemivem.solve(hemivem.Scene.default(), linear=name)


def test_a_path_on_the_full_space_route_is_the_condensed_routes(coulomb_scene):
    t = [0.5, 1.0, 1.5, 2.0]
    condensed = hemivem.solve_path(coulomb_scene(), t=t, frames=4, linear="eigen")
    full = hemivem.solve_path(coulomb_scene(), t=t, frames=4, linear="eigen-cg")
    assert condensed.path.converged and full.path.converged
    for a, b in zip(condensed.path, full.path):
        u0, u1 = np.asarray(a.displacement), np.asarray(b.displacement)
        assert np.max(np.abs(u1 - u0)) <= 1e-8 * np.max(np.abs(u0))
    result = json.loads(full.to_json())
    assert result["stages"][:3] == ["assembly", "posing", "path"]
    assert result["backends"]["linear"] == "eigen-cg"


def test_auto_takes_the_full_space_route_where_the_condensed_one_does_not_fit(monkeypatch):
    # Example 4.1 on 128 x 128 squares: an estimated 81 MiB on the condensed route, 70 MiB on
    # the full-space route with eigen-cg (the Krylov engine Python runs)
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

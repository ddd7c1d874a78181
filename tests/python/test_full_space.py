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

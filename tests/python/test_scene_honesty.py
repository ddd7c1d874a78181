"""What Python users give is what is used: a path for a scene, contradictory updates refused,
law.clarke on arrays, meshes that would lose their regions, MeshError.where."""

import numpy as np
import pytest

import hemivem


SCENE = """schema_version = 1
[mesh]
n = 6
[clamped]
side = ["left", "right"]
[[loads.traction]]
side = "top"
value = [0, -8]
[contact]
side = "bottom"
"""


def test_solve_accepts_a_path(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    expected = hemivem.solve(hemivem.Scene.from_file(path))
    for given in (path, str(path)):
        r = hemivem.solve(given)
        np.testing.assert_array_equal(r.displacement, expected.displacement)
    with pytest.raises(TypeError, match="takes a Scene, a path"):
        hemivem.solve(42)


def test_update_refuses_contradictions_as_the_file_reader_does():
    s = hemivem.Scene.default()
    with pytest.raises(hemivem.InputError, match="not used with mesh.file") as e:
        s.update({"mesh.n": 8, "mesh.file": "x.msh"})
    assert e.value.where == "set mesh.n" or "mesh.n" in e.value.where
    assert s == hemivem.Scene.default()


def test_set_none_removes_a_key():
    s = hemivem.Scene.default()
    s.update({"contact.gap": None, "contact.obstacle.shape": "plane", "contact.obstacle.point": [0.5, -0.01],
              "contact.obstacle.normal": [0, 1]})
    assert s.get("contact.obstacle.shape") == "plane"
    with pytest.raises(KeyError):
        s.get("contact.gap")


def test_a_scene_without_supports_is_announced():
    s = hemivem.Scene.from_string(SCENE.replace('[clamped]\nside = ["left", "right"]\n', ""), "free.toml")
    assert any("no [clamped] and no [[dirichlet]]" in w for w in s.warnings())


def test_clarke_takes_arrays():
    law = hemivem.contact_law("paper")
    r = np.array([[-0.1, 0.0], [0.5, 1.0]])
    lo, hi = law.clarke(r)
    assert lo.shape == hi.shape == r.shape
    for i in range(2):
        for j in range(2):
            assert (lo[i, j], hi[i, j]) == law.clarke(float(r[i, j]))
    assert isinstance(law.clarke(0.5)[0], float)


def test_write_poly2d_refuses_to_drop_regions_and_groups(tmp_path):
    mesh = hemivem.Mesh.from_arrays([[0, 0], [1, 0], [1, 1], [0, 1]], [0, 3, 6], [0, 1, 2, 0, 2, 3], regions=[0, 2])
    with pytest.raises(hemivem.InputError, match="region ids.*drop=True"):
        mesh.write_poly2d(tmp_path / "m.poly2d")
    assert not (tmp_path / "m.poly2d").exists()
    mesh.write_poly2d(tmp_path / "m.poly2d", drop=True)
    assert hemivem.Mesh.read(tmp_path / "m.poly2d").num_elements == 2
    plain = hemivem.Mesh.generate("squares", 2)
    plain.write_poly2d(tmp_path / "p.poly2d")


def test_mesh_error_names_the_element():
    # element 1 is clockwise
    with pytest.raises(hemivem.MeshError) as e:
        hemivem.Mesh.from_arrays([[0, 0], [1, 0], [1, 1], [0, 1]], [0, 3, 6], [0, 1, 2, 0, 3, 2])
    assert e.value.where == "element 1", e.value.where


def test_a_mesh_is_given_to_a_scene():
    scene = hemivem.Scene.from_toml(SCENE)
    mesh = hemivem.Mesh.generate("voronoi", 6)
    given = hemivem.solve(scene, mesh=mesh)
    scene.set("mesh.generator", "voronoi")
    built = hemivem.solve(scene)
    assert given.status == "converged"
    np.testing.assert_array_equal(given.displacement, built.displacement)
    assert given.energy == built.energy
    assert given.json()["mesh"]["description"] == "a mesh given by the caller"
    # the mesh of a result, solved again with another law
    again = hemivem.solve(scene, mesh=given.mesh, minimizer="bundle-dca")
    assert again.displacement.shape == given.displacement.shape
    with pytest.raises(TypeError, match="mesh must be a hemivem.Mesh"):
        hemivem.solve(scene, mesh="squares")

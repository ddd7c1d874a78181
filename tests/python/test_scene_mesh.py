"""Scenes (files, text, dicts, overrides, errors) and meshes (generators, readers, arrays)."""

import pathlib

import numpy as np
import pytest

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_scene_from_file_text_and_round_trip():
    s = hemivem.Scene.from_toml(ROOT / "scenes" / "hertz.toml")
    assert s.source.endswith("hertz.toml")
    again = hemivem.Scene.from_toml(s.to_toml())
    assert again == s and again.source == "<string>"
    assert hemivem.Scene.from_toml(str(ROOT / "scenes" / "hertz.toml")) == s
    assert hemivem.Scene() == hemivem.Scene.default()
    assert "Example 4.1" in repr(hemivem.Scene.default())


def test_set_get_update_copy():
    s = hemivem.Scene.default()
    t = s.copy()
    s.set("contact.gap", 0.01)
    assert s.get("contact.gap") == 0.01 and t.get("contact.gap") == 0.02
    s.update({"contact.law": "kinked", "mesh.n": [8, 4], "mesh.generator": "voronoi"})
    assert s.get("contact.law") == "kinked" and s.get("mesh.n") == [8, 4]
    assert s.mesh_description == "voronoi n=[8, 4]"
    assert s.get("loads.traction[0].value") == [0.0, -8.0]
    with pytest.raises(KeyError):
        s.get("contact.nothing")


def test_scene_from_dict_equals_overrides():
    d = hemivem.Scene.from_dict({"mesh": {"n": 16}, "solver": {"tolerance": 1e-9}})
    s = hemivem.Scene.default()
    s.update({"mesh.n": 16, "solver.tolerance": 1e-9})
    assert d.get("mesh.n") == 16 and d.get("solver.tolerance") == 1e-9
    assert d.get("schema_version") == 1 and not d.has_contact  # as a file without [contact]
    assert d == hemivem.Scene.from_toml("schema_version = 1\n[mesh]\nn = 16\n[solver]\ntolerance = 1e-9\n")
    assert hemivem.Scene.from_dict({"title": "t", "mesh": {"n": 16}}).title == "t"
    full = hemivem.Scene.from_dict(s.to_dict())
    assert full == s and full.source == "<dict>"


def test_bad_key_raises_input_error_with_the_commands_message(tmp_path, run_command):
    s = hemivem.Scene.default()
    with pytest.raises(hemivem.InputError) as e:
        s.set("contact.gapp", 0.1)
    assert isinstance(e.value, ValueError)
    assert str(e.value) == "--set contact.gapp: unknown key 'gapp' in [contact]; did you mean 'gap'?"
    assert e.value.where == "--set contact.gapp"
    assert e.value.detail == "unknown key 'gapp' in [contact]; did you mean 'gap'?"
    cmd = run_command("solve", "--set", "contact.gapp=0.1", "--out", tmp_path / "x", check=False)
    assert cmd.returncode == 2 and str(e.value) in cmd.stderr
    assert s.get("contact.gap") == 0.02  # unchanged by the refused override

    f = tmp_path / "bad.toml"
    f.write_text('schema_version = 1\ntitle = "t"\n[contact]\ngapp = 0.1\n')
    with pytest.raises(hemivem.InputError) as e:
        hemivem.Scene.from_toml(f)
    assert e.value.where == f"{f}:4"
    assert str(e.value) == f"{f}:4: unknown key 'gapp' in [contact]; did you mean 'gap'?"
    with pytest.raises(hemivem.InputError, match=r"<dict>.*unknown key 'gapp' in \[contact\]"):
        hemivem.Scene.from_dict({"schema_version": 1, "contact": {"gapp": 0.1}})
    with pytest.raises(hemivem.InputError, match=r"has no TOML form"):
        hemivem.Scene.default().set("contact.gap", object())


def test_bad_engine_name(small_scene):
    with pytest.raises(hemivem.InputError) as e:
        hemivem.solve(small_scene, linear="pardiso")
    built = ", ".join(hemivem.available_engines()["linear"])
    assert str(e.value).endswith(f"unknown linear engine 'pardiso'; available: {built}")
    with pytest.raises(hemivem.InputError, match="unknown minimizer 'foo'; available: ssn"):
        hemivem.solve(small_scene, minimizer="foo")
    with pytest.raises(hemivem.InputError, match="pardiso"):
        hemivem.condense(small_scene, linear="pardiso")


def test_errors_hierarchy():
    assert issubclass(hemivem.InputError, ValueError) and issubclass(hemivem.InputError, hemivem.Error)
    assert issubclass(hemivem.MeshError, hemivem.InputError)
    assert issubclass(hemivem.NumericalError, hemivem.Error) and issubclass(hemivem.NumericalError, ArithmeticError)
    assert issubclass(hemivem.Error, RuntimeError)


def test_generators_and_arrays():
    for kind in hemivem.mesh_generators():
        m = hemivem.Mesh.generate(kind, 4, domain=(0.0, 2.0, 0.0, 1.0))
        assert m.vertices.shape == (m.num_vertices, 2) and m.vertices.dtype == np.float64
        assert m.vertices.flags.c_contiguous and not m.vertices.flags.writeable
        assert m.offsets.dtype == np.int32 and m.offsets.shape == (m.num_elements + 1,)
        assert m.indices.dtype == np.int32 and m.indices.shape == (m.offsets[-1],)
        assert m.edges.shape == (m.num_edges, 2) and m.edge_elements.shape == (m.num_edges, 2)
        assert m.areas.sum() == pytest.approx(2.0, rel=1e-12), kind
        assert np.all(m.edge_elements[m.boundary_edges, 1] == -1)
        assert m.bounding_box == (0.0, 2.0, 0.0, 1.0)
    sq = hemivem.Mesh.generate("squares", 2)
    assert sq.offsets.tolist() == [0, 4, 8, 12, 16]
    assert sq.element(0).tolist() == [0, 1, 4, 3]
    poly = hemivem.Mesh.generate("voronoi", 6, polygon=[[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], seed=3)
    assert poly.areas.sum() == pytest.approx(3.0, rel=1e-12) and "edge0" in poly.edge_groups


def test_mesh_round_trips_through_arrays_and_files(tmp_path):
    m = hemivem.Mesh.generate("voronoi", 6, seed=5)
    again = hemivem.Mesh.from_arrays(m.vertices, m.offsets, m.indices, regions=m.regions)
    for name in ["vertices", "offsets", "indices", "edges", "edge_elements", "boundary_edges", "areas", "centroids"]:
        assert np.array_equal(getattr(again, name), getattr(m, name)), name
    assert again.elements == m.elements
    m.write_poly2d(tmp_path / "m.poly2d", comments=["from a test"])
    read = hemivem.Mesh.read(tmp_path / "m.poly2d")
    assert np.array_equal(read.vertices, m.vertices) and np.array_equal(read.indices, m.indices)
    sutton = ROOT.parent / "shared" / "meshes" / "sutton-voronoi.poly2d"
    if sutton.is_file():
        assert hemivem.Mesh.read(sutton).num_elements > 0
    msh = hemivem.Mesh.read(ROOT / "scenes" / "meshes" / "half-disk.msh")
    assert msh.edge_groups and msh.num_elements > 0


def test_mesh_from_arrays_refuses_bad_input(tmp_path):
    v = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    ok = hemivem.Mesh(v, [0, 4], [0, 1, 2, 3])
    assert ok.num_elements == 1 and ok.h == pytest.approx(np.sqrt(2.0))
    bad = v.copy()
    bad[2, 0] = np.nan
    with pytest.raises(hemivem.InputError) as e:
        hemivem.Mesh.from_arrays(bad, [0, 4], [0, 1, 2, 3])
    assert str(e.value) == "vertices: vertices[2, 0] = nan is not finite"
    with pytest.raises(hemivem.MeshError) as e:
        hemivem.Mesh.from_arrays(v, [0, 4], [0, 3, 2, 1])  # clockwise
    assert e.value.element == 0 and "clockwise" in str(e.value)
    with pytest.raises(hemivem.InputError, match="the last offset is 3, but there are 4 indices"):
        hemivem.Mesh.from_arrays(v, [0, 3], [0, 1, 2, 3])
    with pytest.raises(hemivem.InputError, match="expected integers"):
        hemivem.Mesh.from_arrays(v, [0, 4], [0.0, 1.0, 2.0, 3.0])
    (tmp_path / "bad.poly2d").write_text("vertices 3\n0 0\n1 0\nnan 1\nelements 1\n3 0 1 2\n")
    with pytest.raises(hemivem.InputError) as e:
        hemivem.Mesh.read(tmp_path / "bad.poly2d")
    assert e.value.where == f"{tmp_path / 'bad.poly2d'}:4"

"""Several contact parts ([[contact]], docs/contact-parts.md) from Python: the scene as a dict
and back, overrides by part, the contact table's part column against the command's files."""

import csv
import json
import pathlib

import numpy as np
import pytest

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]
BRACKET = ROOT / "scenes" / "bracket-two-contacts.toml"


def two_parts():
    return {
        "mesh": {"generator": "squares", "n": [16, 8], "domain": [0.0, 1.0, 0.0, 0.5]},
        "clamped": {"side": "left"},
        "contact": [
            {"name": "support", "side": "bottom", "law": "paper", "gap": 0.02},
            {
                "name": "indenter",
                "side": "top",
                "law": "zero",
                "constraint": "one-sided",
                "obstacle": {"shape": "circle", "center": [0.7, 0.72], "radius": 0.25},
            },
        ],
    }


def test_a_list_of_contact_tables_is_parts_and_round_trips():
    s = hemivem.Scene.from_dict(two_parts())
    d = s.to_dict()
    assert isinstance(d["contact"], list) and len(d["contact"]) == 2
    assert [p["name"] for p in d["contact"]] == ["support", "indenter"]
    assert d["contact"][1]["obstacle"]["shape"] == "circle"
    assert s.get("contact[1].constraint") == "one-sided"
    again = hemivem.Scene.from_dict(d)
    assert again.to_toml() == s.to_toml()
    assert "[[contact]]" in s.to_toml()


def test_overrides_name_their_part():
    s = hemivem.Scene.from_dict(two_parts())
    s.set("contact[0].gap", 0.01)
    assert s.get("contact[0].gap") == 0.01
    assert s.get("contact[1].law") == "zero"
    with pytest.raises(hemivem.InputError, match=r"contact\[1\]\.gap"):
        s.set("contact.gap", 0.03)
    bad = two_parts()
    bad["contact"][1]["name"] = "support"
    with pytest.raises(hemivem.InputError, match="has the name 'support' already"):
        hemivem.Scene.from_dict(bad)


def test_the_contact_table_names_each_nodes_part():
    r = hemivem.solve(hemivem.Scene.from_dict(two_parts()), linear="eigen")
    assert r.converged
    parts = r.contact.part
    assert parts.shape == r.contact.u_nu.shape
    assert set(parts.tolist()) == {"support", "indenter"}
    top = r.contact.y > 0.25
    assert (parts[top] == "indenter").all() and (parts[~top] == "support").all()
    # the indenter pushes (compression only), and the forces balance
    assert (r.contact.pressure[top] >= -1e-12).all()
    assert r.json()["forces"]["balance_residual"] < 1e-10
    assert [n["part"] for n in r.json()["contact"]] == parts.tolist()


def test_the_shipped_scene_matches_the_command(tmp_path, run_command):
    out = tmp_path / "cmd"
    run_command("solve", BRACKET, "--set", "mesh.n=[32, 16]", "--linear", "eigen", "--out", out, "-q")
    scene = hemivem.Scene.from_file(BRACKET)
    scene.set("mesh.n", [32, 16])
    r = hemivem.solve(scene, linear="eigen")
    with open(out / "contact.csv") as f:
        rows = list(csv.DictReader(f))
    assert [row["part"] for row in rows] == r.contact.part.tolist()
    u_nu = np.array([float(row["u_nu"]) for row in rows])
    assert np.max(np.abs(r.contact.u_nu - u_nu)) <= 1e-12 * np.max(np.abs(u_nu))
    expected = json.loads((out / "result.json").read_text())
    assert [n["part"] for n in expected["contact"]] == r.contact.part.tolist()

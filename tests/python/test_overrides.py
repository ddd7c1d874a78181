"""Overrides of arrays of tables (docs/reference/scenes.md, "Overrides"): "key[+]" appends one
table, replacing a whole array is allowed and reported in the warnings."""
import hemivem

ROLLER = """
schema_version = 1
[mesh]
generator = "squares"
n = 4
[material]
E = 1.0
nu = 0.3
[clamped]
side = ["left", "right"]
[[dirichlet]]
side = "bottom"
ux = 0.0
[[loads.traction]]
side = "top"
value = [0.0, -1.0]
[contact]
side = "bottom"
law = "paper"
"""

NOTICE = ("--set dirichlet replaced the whole array [[dirichlet]]: its 1 table by 2 "
          "(to add one table instead: --set 'dirichlet[+]={...}')")


def sides(scene):
    """The sides of each [[dirichlet]] of the scene, each as a list."""
    return [d["side"] if isinstance(d["side"], list) else [d["side"]] for d in scene.get("dirichlet")]


def test_append_keeps_the_scenes_own_table():
    s = hemivem.Scene.from_string(ROLLER)
    s.set("dirichlet[+]", {"side": "top", "ux": 0.0})
    assert sides(s) == [["bottom"], ["top"]]
    assert s.warnings() == []
    assert hemivem.solve(s).warnings == []


def test_replacing_the_array_is_a_warning_of_the_scene_and_of_the_result():
    s = hemivem.Scene.from_string(ROLLER)
    s.set("dirichlet", [{"side": "top", "ux": 0.0}, {"side": "top", "uy": 0.0}])
    assert sides(s) == [["top"], ["top"]]
    assert NOTICE in s.warnings()
    assert NOTICE in hemivem.solve(s).warnings

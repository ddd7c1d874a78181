"""hemivem: elastic contact with nonmonotone laws (hemivariational inequalities) by the
virtual element method, from Python.

The same C++ libraries as the `hemivem` command, with NumPy arrays:

    import hemivem
    r = hemivem.solve(hemivem.Scene.default())          # Example 4.1 of Feng, Han, Huang (2021)
    print(r.status, r.certificate, r.energy)
    r.contact.u_nu, r.displacement                      # NumPy arrays
    r.write("out/solve")                                # the files of `hemivem solve`

    r3 = hemivem.solve("scenes/example-4.1-3d.toml")    # a three-dimensional scene
    r3.dimension, r3.displacement.shape                 # 3, (num_vertices, 3)

    p = hemivem.condense(hemivem.Scene.default(), linear="cholmod")
    p.S, p.c, p.w, p.g                                  # the reduced problem
    m = hemivem.minimize(p, "ssn")
    p.certificate(my_point)                             # judge any point by the same rule
    g = hemivem.minimize(p, search="global")            # the lowest of several critical points
    g.critical_points                                   # every certified one found

Documentation: python/README.md.
"""

import os as _os
import sys as _sys
import tomllib as _tomllib

try:
    import numpy as _numpy  # noqa: F401
except ImportError as _error:
    raise ModuleNotFoundError(
        f"hemivem needs NumPy, which this Python ({_sys.executable}) cannot import ({_error}). "
        "For Debian's /usr/bin/python3 install the package python3-numpy "
        "(sudo apt-get install python3-numpy); in a virtual environment made with "
        "--system-site-packages it comes from there, in another one install numpy into it "
        "(python -m pip install numpy).",
        name="numpy",
    ) from None

from ._hemivem import (  # noqa: F401
    __version__,
    Certificate,
    CertifiedPoint,
    ContactLaw,
    ContactTable,
    CriticalPoint,
    Error,
    InputError,
    InternalError,
    Iteration,
    Mesh,
    Mesh3D,
    MeshError,
    MinimizerResult,
    NumericalError,
    Path,
    PathStep,
    ReducedProblem,
    Result,
    Scene,
    SearchProgress,
    StressTable,
    available_engines,
    bench,
    check,
    condense,
    contact_law,
    contact_laws,
    limit,
    mesh_generators,
    minimize,
    solve,
    study,
)
from . import _scene_dict

__all__ = [
    "Certificate",
    "CertifiedPoint",
    "ContactLaw",
    "ContactTable",
    "CriticalPoint",
    "Error",
    "InputError",
    "InternalError",
    "Iteration",
    "Mesh",
    "Mesh3D",
    "MeshError",
    "MinimizerResult",
    "NumericalError",
    "Path",
    "PathStep",
    "ReducedProblem",
    "Result",
    "Scene",
    "SearchProgress",
    "StressTable",
    "available_engines",
    "bench",
    "check",
    "condense",
    "contact_law",
    "contact_laws",
    "limit",
    "mesh_generators",
    "minimize",
    "solve",
    "solve_path",
    "study",
]


def _input_error(message, where):
    e = InputError(f"{where}: {message}" if where else message)
    e.where = where
    e.detail = message
    return e


def _toml_value(value, where):
    try:
        return _scene_dict.toml_value(value, where)
    except _scene_dict.TomlValueError as e:
        raise _input_error(str(e), e.where) from None


def _from_toml(path_or_text):
    """A scene from a file or from TOML text.

    A pathlib.Path (any os.PathLike) is a file; a str is TOML text when it holds a newline,
    '=' or '[', and a file name otherwise. InputError naming file:line and the key for every
    defect (unknown keys come with the nearest valid one)."""
    if isinstance(path_or_text, _os.PathLike):
        return Scene.from_file(path_or_text)
    if not isinstance(path_or_text, str):
        raise TypeError(f"Scene.from_toml takes a path or TOML text, not {type(path_or_text).__name__}")
    if any(c in path_or_text for c in "\n=["):
        return Scene.from_string(path_or_text)
    return Scene.from_file(path_or_text)


def _from_dict(document, name="<dict>"):
    """A scene from a nested dict with the keys of a scene file (docs/reference/scenes.md), e.g.

        Scene.from_dict({"mesh": {"n": 16}, "contact": {"side": "bottom", "gap": 0.01}})

    The dict reads as a scene file would: keys left out take the defaults of docs/reference/scenes.md
    (a scene without a "contact" table has no contact); schema_version defaults to the
    version this library reads. Validated as a file is: InputError naming the key."""
    if isinstance(document, dict) and "schema_version" not in document:
        document = {"schema_version": Scene.default().get("schema_version"), **document}
    try:
        text = _scene_dict.to_toml(document)
    except _scene_dict.TomlValueError as e:
        raise _input_error(str(e), e.where) from None
    return Scene.from_string(text, name)


def _override(key, value):
    # None removes the key, as `--set key=` does
    return f"{key}=" if value is None else f"{key}={_toml_value(value, key)}"


def _set(self, key, value):
    """Sets one key, as `hemivem solve --set key=value`: scene.set("contact.gap", 0.01).

    The value is a Python bool, number, str, list or dict (written as TOML); None removes the
    key (as `--set key=`), e.g. the gap before an obstacle is given. The scene is validated as
    a whole; InputError naming the key (and the nearest valid key) otherwise."""
    if not isinstance(key, str) or not key:
        raise _input_error("the key must be a non-empty dotted name such as 'contact.gap'", "set")
    self._apply_overrides([_override(key, value)])


def _update(self, values):
    """Sets several keys at once ({"contact.law": "kinked", "contact.parameters.sigma": 0.5}),
    validated together: the order does not matter. None removes a key; keys that contradict
    each other (mesh.file with mesh.n) are refused as in a scene file."""
    self._apply_overrides([_override(k, v) for k, v in dict(values).items()])


def _to_dict(self):
    """The scene as a nested dict (the TOML of to_toml(), every key written)."""
    return _tomllib.loads(self.to_toml())


def _get(self, key):
    """The value of a dotted key of to_dict(): scene.get("contact.gap"), scene.get("mesh.n"),
    scene.get("loads.traction[0].value"). KeyError when there is no such key."""
    node = self.to_dict()
    for part in key.split("."):
        name, _, rest = part.partition("[")
        try:
            node = node[name]
            while rest:
                index, _, rest = rest.partition("]")
                node = node[int(index)]
                rest = rest.lstrip("[")
        except (KeyError, IndexError, TypeError, ValueError):
            raise KeyError(f"the scene has no key '{key}'") from None
    return node


Scene.from_toml = staticmethod(_from_toml)
Scene.from_dict = staticmethod(_from_dict)
Scene.set = _set
Scene.update = _update
Scene.to_dict = _to_dict
Scene.get = _get


def solve_path(scene=None, *, steps=None, t=None, frames=None, **keywords):
    """Solves a scene along a loading path (docs/paths.md), as `hemivem solve` does for a scene
    with a [path] table: each step the static problem at its load factor, started from the step
    before, with friction acting on the slip of each step. Returns the Result of the last step,
    whose `path` holds every step (a Path: iterate over its PathStep objects, each with its
    certificate, contact table, slip, forces and, for a frame, its displacement).

    scene: as hemivem.solve takes it (a Scene, a path to a scene file, TOML text or None for
    the default). steps (load factors k/steps), t (a list of increasing load factors) and
    frames (how many steps keep their displacement) set the [path] table, steps or t replacing
    the scene's own steps or t; a scene without one gets [path] with its defaults (10 steps).
    steps and t together are an InputError naming both. Further keywords are hemivem.solve's."""
    if scene is None:
        scene = Scene.default()
    elif not isinstance(scene, Scene):
        scene = Scene.from_toml(scene)
    else:
        scene = Scene.from_string(scene.to_toml(), scene.source)
    if steps is not None and t is not None:
        raise _input_error(
            "give either steps (load factors k / steps) or t (the load factors one by one), not both",
            "steps, t")
    values = {}
    if steps is not None:
        values["path.steps"] = steps
    if t is not None:
        values["path.t"] = [float(x) for x in t]
    if frames is not None:
        values["path.frames"] = frames
    if not values and "path" not in scene.to_dict():
        values["path.steps"] = 10
    if values:
        scene.update(values)
    return solve(scene, **keywords)

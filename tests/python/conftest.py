"""pytest fixtures of the Python module's tests (python/README.md, "Tests").

The module is imported from PYTHONPATH (scripts/test.sh sets it to <build>/python); the
command `hemivem` the results are compared with is <build>/drivers/hemivem, where <build> is
HEMIVEM_BUILD_DIR (default: the folder above the imported package, i.e. <build>)."""

import os
import pathlib
import signal
import subprocess

import pytest

import hemivem

ROOT = pathlib.Path(__file__).resolve().parents[2]

# A process started in the background by a shell inherits SIGINT ignored, and Python then raises
# no KeyboardInterrupt: Ctrl-C is restored as an interactive session has it, for the tests that
# interrupt a solve.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def build_dir():
    env = os.environ.get("HEMIVEM_BUILD_DIR")
    if env:
        return pathlib.Path(env).resolve()
    # <build>/python/hemivem/__init__.py
    return pathlib.Path(hemivem.__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def hemivem_command():
    exe = build_dir() / "drivers" / "hemivem"
    if not exe.is_file():
        pytest.fail(f"the command {exe} is missing: build it, or set HEMIVEM_BUILD_DIR")
    return exe


@pytest.fixture(scope="session")
def run_command(hemivem_command):
    def run(*args, check=True):
        p = subprocess.run([str(hemivem_command), *map(str, args)], capture_output=True, text=True)
        if check and p.returncode != 0:
            raise AssertionError(f"hemivem {' '.join(map(str, args))} exited {p.returncode}: {p.stderr}")
        return p

    return run


@pytest.fixture()
def small_scene():
    """Example 4.1 on 16 x 16 squares."""
    s = hemivem.Scene.default()
    s.set("mesh.n", 16)
    return s


COULOMB_SCENE = """schema_version = 1
[mesh]
n = {n}
[clamped]
side = ["left", "right"]
[[loads.traction]]
side = "top"
value = ["4*max(t - 1, 0)", "-8*min(t, 1)"]
[contact]
side = "bottom"
gap = 0.02
[contact.friction]
law = "coulomb"
coefficient = 0.3
"""


@pytest.fixture(scope="session")
def coulomb_scene():
    """The unit square pressed to t = 1 and sheared after, on a gap of 0.02 with Coulomb's
    friction (mu = 0.3): the scene's text on n x n squares, `extra` (e.g. a [path]) appended."""
    def scene(n=8, extra=""):
        return COULOMB_SCENE.format(n=n) + extra
    return scene

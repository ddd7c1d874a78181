"""Meshes far from unit size and polygons too thin to mesh, from Python: errors, not crashes."""

import subprocess
import sys

import pytest

import hemivem


@pytest.mark.parametrize("size", [1e110, 1e-110])
def test_cgal_generators_mesh_far_from_unit_size(size):
    # run in a child: on failure CGAL killed the interpreter with SIGFPE or SIGSEGV
    code = (
        "import hemivem\n"
        f"L = {size!r}\n"
        "v = hemivem.Mesh.generate('voronoi', 4, domain=(0.0, L, 0.0, L))\n"
        "t = hemivem.Mesh.generate('triangles', 4, polygon=[[0, 0], [L, 0], [L, L], [0, L]])\n"
        "assert v.num_elements == 16 and t.num_elements > 0\n"
        "assert abs(v.areas.sum() - L * L) <= 1e-12 * L * L and abs(t.areas.sum() - L * L) <= 1e-12 * L * L\n"
        "assert v.vertices.max() == L and t.vertices.max() == L\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr


def test_thin_spike_is_an_input_error():
    spike = [[0, 0], [1, 0], [1, 1], [0.5, 1], [0.5000000000001, 100], [0.4999999999999, 1], [0, 1]]
    with pytest.raises(hemivem.InputError, match="feature of width"):
        hemivem.Mesh.generate("triangles", 4, polygon=spike)

"""Solves from several Python threads at once, with every linear engine built: each thread gets
the answer a lone solve gives (MUMPS, which keeps global state, is called by one thread at a
time). mumps-mpi runs across processes started by mpirun and is refused inside Python."""

import threading

import numpy as np
import pytest

import hemivem


# mumps-mpi is refused inside Python (test_mumps_mpi_is_refused_inside_python)
ENGINES = [e for e in hemivem.available_engines()["linear"] if e != "mumps-mpi"]


def _scene():
    s = hemivem.Scene.default()
    s.set("mesh.n", 20)
    return s


@pytest.mark.parametrize("linear", ENGINES)
def test_four_threads_solve_alike(linear):
    s = _scene()
    expected = hemivem.solve(s, linear=linear)
    assert expected.converged
    results, errors = [None] * 4, []

    def run(k):
        try:
            for _ in range(3):
                results[k] = hemivem.solve(s, linear=linear)
        except BaseException as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    for r in results:
        assert r.converged
        np.testing.assert_allclose(r.displacement, expected.displacement, rtol=0, atol=1e-12)


@pytest.mark.parametrize("linear", ENGINES)
def test_threads_condense_and_minimize(linear):
    s = _scene()
    expected = hemivem.minimize(hemivem.condense(s, linear=linear))
    out, errors = [None] * 4, []

    def run(k):
        try:
            out[k] = hemivem.minimize(hemivem.condense(s, linear=linear))
        except BaseException as e:  # pragma: no cover
            errors.append(e)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    for r in out:
        np.testing.assert_allclose(r.a, expected.a, rtol=0, atol=1e-12)


def test_mumps_mpi_is_refused_inside_python():
    with pytest.raises(hemivem.InputError, match="mumps-mpi.*not inside Python"):
        hemivem.solve(_scene(), linear="mumps-mpi")
    with pytest.raises(hemivem.InputError, match="not inside Python"):
        hemivem.condense(_scene(), linear="mumps_mpi")
    with pytest.raises(hemivem.InputError, match="not inside Python"):
        hemivem.solve(hemivem.Scene.from_string("schema_version = 1\n[solver]\nlinear = \"mumps-mpi\"\n", "mpi.toml"))

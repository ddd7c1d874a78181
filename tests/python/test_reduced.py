"""The reduced problem: condense, files of --export-reduced, minimize, the certificate,
lifetimes."""

import gc

import numpy as np
import pytest

import hemivem


def test_exported_reduced_problem_equals_condense(tmp_path, run_command, small_scene):
    run_command("solve", "--n", 16, "--linear", "cholmod", "--out", tmp_path / "out", "--export-reduced", tmp_path / "red", "-q")
    files = hemivem.ReducedProblem.read(tmp_path / "red")
    p = hemivem.condense(small_scene, linear="cholmod")
    assert p.S.shape == (15, 15) and p.S.dtype == np.float64 and p.S.flags.f_contiguous and not p.S.flags.writeable
    assert np.array_equal(files.S, p.S)  # written with 17 digits: exact
    assert np.array_equal(files.c, p.c) and np.array_equal(files.w, p.w) and np.array_equal(files.g, p.g)
    assert files.law.name == p.law.name == "paper" and files.constraint == p.constraint == "box"
    r = hemivem.solve(small_scene, linear="cholmod")
    assert np.array_equal(r.reduced.S, p.S) and np.array_equal(r.reduced.c, p.c)


def test_minimize_and_back_substitute_equal_solve(small_scene):
    p = hemivem.condense(small_scene, linear="eigen")
    r = hemivem.solve(small_scene, linear="eigen")
    m = hemivem.minimize(p, "ssn")
    assert m.converged and m.status == "converged"
    assert np.max(np.abs(m.a - r.a)) <= 1e-12 * np.max(np.abs(r.a))
    u = p.back_substitute(m.a)
    assert u.shape == r.displacement.shape
    assert np.max(np.abs(u - r.displacement)) <= 1e-12 * np.max(np.abs(r.displacement))
    assert p.energy(m.a) == pytest.approx(m.objective, rel=1e-14)
    assert p.contact_vertices.tolist() == r.contact.vertex.tolist()


def test_every_minimizer_is_judged_by_the_certificate(small_scene):
    p = hemivem.condense(small_scene)
    for name in hemivem.available_engines()["minimizer"]:
        m = hemivem.minimize(p, name)
        c = p.certificate(m.a)
        assert m.converged and c.converged, name
        assert c.primal == m.certificate.primal and c.dual == m.certificate.dual, name
    # a point that is not a solution is not certified, and a non-finite one has infinite residuals
    assert not p.certificate(np.zeros(p.size)).converged
    c = p.certificate(np.full(p.size, np.nan))
    assert c.primal == np.inf and c.dual == np.inf
    cp = p.certify(hemivem.minimize(p).a)
    assert cp.converged and cp.a.shape == (p.size,) and np.all(np.abs(cp.a) <= p.g)


def test_minimize_options_start_and_callback(small_scene):
    p = hemivem.condense(small_scene)
    seen = []
    m = hemivem.minimize(p, "bundle-dca", start=p.g, callback=lambda it: seen.append(it.iteration) or len(seen) < 2)
    assert m.status == "stopped by callback" and seen == [1, 2]
    m = hemivem.minimize(p, "ssn", max_iterations=0, start=np.zeros(p.size))
    assert m.status == "iteration limit" and not m.converged
    with pytest.raises(hemivem.InputError) as e:
        hemivem.minimize(p, "ssn", armijo=2.0)
    assert "ssn" in str(e.value) and "armijo" in str(e.value)
    with pytest.raises(hemivem.InputError) as e:
        hemivem.minimize(p, "ssn", start=np.zeros(p.size + 1))
    assert "the start has size 16, the problem 15" in str(e.value)

    def fail(it):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        hemivem.minimize(p, "bundle-dca", callback=fail)


def test_ctrl_c_between_iterations(small_scene):
    import _thread

    p = hemivem.condense(small_scene)
    seen = []

    def interrupt(it):
        seen.append(it.iteration)
        if it.iteration == 2:
            _thread.interrupt_main()  # Ctrl-C, seen by the minimizer before its next iteration

    with pytest.raises(KeyboardInterrupt):
        hemivem.minimize(p, "bundle-dca", callback=interrupt)
    assert seen == [1, 2]


def test_reduced_problem_from_arrays():
    S = np.array([[2.0, -1.0], [-1.0, 2.0]])
    p = hemivem.ReducedProblem(S, c=[1.0, 0.0], w=[1.0, 1.0], g=[0.1, 0.1], law="zero", constraint="box")
    m = hemivem.minimize(p)
    assert m.converged and np.allclose(m.a, [0.1, 0.05], rtol=0, atol=1e-14)
    assert p.uniqueness_margin == pytest.approx(1.0)
    assert p.lower.tolist() == [-0.1, -0.1] and p.upper.tolist() == [0.1, 0.1]
    with pytest.raises(hemivem.InputError, match="has no factorization"):
        p.back_substitute(m.a)


@pytest.mark.parametrize(
    "kwargs,message",
    [
        ({"c": [1.0, np.inf]}, r"c: c\[1\] = inf is not finite"),
        ({"w": [1.0, np.nan]}, r"w: w\[1\] = nan is not finite"),
        ({"S": [[1.0, np.nan], [0.0, 1.0]]}, r"S: S\[0, 1\] = nan is not finite"),
        ({"S": [[1.0, 0.5], [0.0, 1.0]]}, r"S: S is not symmetric"),
        ({"w": [1.0, 0.0]}, r"w: w\[1\] = 0\.0+ must be > 0"),
        ({"g": [0.1]}, r"inconsistent sizes"),
    ],
)
def test_reduced_problem_refuses_bad_arrays(kwargs, message):
    args = {"S": np.eye(2), "c": [1.0, 0.0], "w": [1.0, 1.0], "g": [0.1, 0.1]}
    args.update(kwargs)
    with pytest.raises(hemivem.InputError, match=message) as e:
        hemivem.ReducedProblem(**args)
    assert isinstance(e.value, ValueError)


def test_reduced_problem_outlives_the_factorization(small_scene):
    p = hemivem.condense(small_scene, linear="cholmod")
    S, c, mesh = p.S, p.c, p.mesh
    S_copy, c_copy = S.copy(), c.copy()
    u = p.back_substitute(hemivem.minimize(p).a)
    del p
    gc.collect()
    assert np.array_equal(S, S_copy) and np.array_equal(c, c_copy)  # the views keep the problem alive
    assert mesh.vertices.shape == u.shape
    # the copy a Result keeps: its factorization ended inside solve()
    r = hemivem.solve(small_scene)
    reduced = r.reduced
    del r
    gc.collect()
    m = hemivem.minimize(reduced)
    assert m.converged and reduced.certificate(m.a).converged


def test_result_outlives_its_scene_and_views_outlive_the_result():
    s = hemivem.Scene.default()
    s.set("mesh.n", 8)
    r = hemivem.solve(s)
    del s
    gc.collect()
    assert r.converged and r.scene.get("mesh.n") == 8
    d, mesh = r.displacement, r.mesh
    d_copy = d.copy()
    del r
    gc.collect()
    assert np.array_equal(d, d_copy) and mesh.num_vertices == d.shape[0]
    assert mesh.vertices.shape == (81, 2)


def test_laws():
    law = hemivem.contact_law("paper")
    assert law.name == "paper" and law.alpha == pytest.approx(20.0)
    r = np.linspace(-0.05, 0.05, 11)
    assert law.value(r).shape == r.shape
    assert law.value(r, part="j1") - law.value(r, part="j2") == pytest.approx(law.value(r), abs=1e-15)
    assert isinstance(law.value(0.01), float)
    with pytest.raises(hemivem.InputError, match="unknown"):
        hemivem.contact_law("nonexistent")
    assert "paper" in hemivem.contact_laws()

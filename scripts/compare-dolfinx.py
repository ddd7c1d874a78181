#!/usr/bin/env python3
"""Times hemivem's full-space route against DOLFINx + PETSc SNES VI on the same 3D contact problem.

The problem is scenes/example-4.1-3d.toml: the block [0, 1] x [0, 0.5] x [0, 1] (E, nu, the
traction on its top, the clamped sides x = 0 and x = 1, the contact law and the gap are read from
the scene), on n x n x n hexahedral cells (cells of 1/n x 0.5/n x 1/n), in contact on its bottom
face through the law j(u_nu) with the box constraint |u_nu| <= g, u_nu = -u_z there.

For each n given it runs, each engine `--repeat` times (default 2), keeping the fastest run:

- hemivem, `hemivem solve SCENE --set 'mesh.n=[n, n, n]' --set 'output.write=["result-json"]'
  --linear petsc-gamg|petsc-hypre -q`: the projected semismooth Newton iteration in the whole
  displacement space, its systems solved by PETSc's CG with GAMG (the rigid motions as the
  near-null space) or hypre's BoomerAMG;
- DOLFINx 0.5 (this script run again as a worker): Q1 elements on the same hexahedra, the same
  potential energy with the law as a nodal (lumped) term, w_i = the bottom area around vertex i,
  solved by PETSc's SNES `vinewtonrsls` (the reduced-space active-set Newton method for
  variational inequalities) with the bounds -g <= u_z <= g on the bottom vertices, the law's
  derivative in the residual and its second derivative (one of the one-sided ones at the law's
  breakpoints, where j' has kinks) on the Jacobian's diagonal, SNES VI's default backtracking line search (`--linesearch`
  chooses others: `basic` takes the full projected Newton step), and KSP CG with GAMG or
  BoomerAMG set as hemivem sets them.

Both codes run one thread (OMP_NUM_THREADS=1) and stop on the same test: the largest force
out of balance (the residual, less the reactions of the coordinates held at a bound) is at most
`--tol` (1e-10, hemivem's default) times the force scale max(|b|, |A u|, the contact forces),
maximum norms. DOLFINx's CG is given hemivem's relative tolerance: the square of that relative
residual, kept in [1e-12, 1e-4]. GAMG runs with PETSc's `-matptap_via rap` and
`-pc_gamg_reuse_interpolation`, BoomerAMG with `-pc_hypre_boomeramg_strong_threshold 0.5`, as in
hemivem. SNES VI solves each Newton system on the submatrix of the inactive unknowns (block size
1 once a bottom unknown is held: GAMG aggregates unknowns, not vertices, and BoomerAMG sees one
function, where hemivem's systems keep the block size 3); the near-null space (the six rigid
motions, restricted to those unknowns and orthonormalised) is set on each such submatrix, through
a Jacobian whose submatrices are made here. PETSc 3.18's GAMG stops when SNES VI's system changes
size (see --as-shipped); the script gives the KSP a new GAMG then.

The whole process is timed by /usr/bin/time (elapsed seconds, peak resident memory); the
solve alone is hemivem's `full_space` timing and the time of DOLFINx's SNESSolve. The energies
differ by the difference of the discretisations (hemivem's virtual elements against Q1 finite
elements on the same cells), not by the solvers: the relative difference of the potential
energies and the largest |u_z| on the bottom of each are printed.

Needs /usr/bin/time and DOLFINx 0.5 for Python (Debian: `apt-get install python3-dolfinx`, which
brings petsc4py for PETSc 3.18). hemivem is the binary named by the environment variable
HEMIVEM_BINARY, or else build/drivers/hemivem of this repository.

Usage:
    /usr/bin/python3 scripts/compare-dolfinx.py 16 24 32
    /usr/bin/python3 scripts/compare-dolfinx.py 16 --law zero        # the box constraint alone
    /usr/bin/python3 scripts/compare-dolfinx.py 24 --engines gamg --linesearch bt,basic --json out.json

Options (--help): --law paper|zero (the scene's law, or none: the box constraint alone),
--engines gamg,hypre, --linesearch bt,basic,..., --repeat N, --tol T, --timeout S (per run),
--out DIR (where the runs write), --json FILE (every number, as JSON), --as-shipped (no new
GAMG for SNES VI's changed systems: PETSc 3.18 then stops at the first change of size).
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(REPO, "scenes", "example-4.1-3d.toml")
TIME = "/usr/bin/time"
ENGINES = {"gamg": "petsc-gamg", "hypre": "petsc-hypre"}


# --------------------------------------------------------------------------------------------
# The problem, read from the scene


def paper_law():
    """The law (4.7) of Feng, Han and Huang (2021) as pieces of j on (-inf, 0], (0, 0.01],
    (0.01, 0.02), [0.02, inf): breakpoints and the coefficients of j (lowest degree first)."""
    return [0.0, 0.01, 0.02], [[0.0, 0.0, 0.0], [0.0, 0.0, 30.0], [-0.004, 0.8, -10.0], [0.012, -0.8, 30.0]]


def zero_law():
    return [], [[0.0, 0.0, 0.0]]


def read_problem(scene_path, law):
    """The data of the scene that the DOLFINx model needs, checked to be what it implements."""
    if tomllib is None:
        sys.exit("compare-dolfinx: reading the scene needs Python >= 3.11 (tomllib)")
    with open(scene_path, "rb") as f:
        s = tomllib.load(f)
    problems = []
    domain = s["mesh"].get("domain")
    if s["mesh"].get("generator") != "cubes" or domain is None or len(domain) != 6:
        problems.append("mesh: generator 'cubes' with a domain [x0, x1, y0, y1, z0, z1]")
    clamped = s.get("clamped", {}).get("side")
    if sorted(clamped if isinstance(clamped, list) else [clamped]) != ["x0", "x1"]:
        problems.append("clamped.side = ['x0', 'x1']")
    tractions = s.get("loads", {}).get("traction", [])
    if len(tractions) != 1 or tractions[0].get("side") not in ("top", ["top"]):
        problems.append("one traction, on the top")
    if any(v != 0.0 for v in s.get("loads", {}).get("body_force", [0.0, 0.0, 0.0])):
        problems.append("no body force")
    c = s.get("contact", {})
    if c.get("side") not in ("bottom", ["bottom"]) or c.get("constraint") != "box":
        problems.append("contact on the bottom with constraint = 'box'")
    if c.get("law_origin", "body") != "body" or "friction" in c:
        problems.append("contact.law_origin = 'body', no friction")
    scene_law = c.get("law", "paper")
    if law == "paper" and scene_law != "paper":
        problems.append("contact.law = 'paper' (or --law zero)")
    if s.get("material", {}).get("stabilization", "2mu") != "2mu" or "plane" in s.get("material", {}):
        problems.append("the default material")
    if problems:
        sys.exit("compare-dolfinx: the scene " + scene_path + " is not the problem modelled here: " + "; ".join(problems))
    breaks, pieces = paper_law() if law == "paper" else zero_law()
    return {
        "domain": domain,
        "E": float(s["material"]["E"]),
        "nu": float(s["material"]["nu"]),
        "traction": [float(v) for v in tractions[0]["value"]],
        "gap": float(c["gap"]),
        "law": law,
        "breaks": breaks,
        "pieces": pieces,
    }


# --------------------------------------------------------------------------------------------
# The DOLFINx worker: one solve, its numbers written as JSON


def law_functions(np, breaks, pieces):
    """Vectorised j, j' and j'' of a piecewise-quadratic law. A point on a breakpoint takes the
    piece on its left (the pieces' intervals are (b_(k-1), b_k]), as (4.7) is written."""
    breaks = np.asarray(breaks, dtype=float)
    coef = np.asarray(pieces, dtype=float)

    def piece(r):
        return np.searchsorted(breaks, r, side="left")

    def j(r):
        c = coef[piece(r)]
        return c[:, 0] + c[:, 1] * r + c[:, 2] * r * r

    def dj(r):
        c = coef[piece(r)]
        return c[:, 1] + 2.0 * c[:, 2] * r

    def d2j(r):
        return 2.0 * coef[piece(r)][:, 2]

    return j, dj, d2j


def worker(args):
    t_start = time.perf_counter()
    import numpy as np
    from mpi4py import MPI
    from petsc4py import PETSc
    import ufl
    from dolfinx import fem, mesh
    import dolfinx.fem.petsc as fem_petsc

    PETSc.Log.begin()
    t_imported = time.perf_counter()
    p = read_problem(args.scene, args.law)
    n = args.n
    x0, x1, y0, y1, z0, z1 = p["domain"]
    comm = MPI.COMM_SELF

    msh = mesh.create_box(comm, [np.array([x0, y0, z0]), np.array([x1, y1, z1])], [n, n, n],
                          mesh.CellType.hexahedron)
    tdim = msh.topology.dim
    V = fem.VectorFunctionSpace(msh, ("Lagrange", 1))
    bs = V.dofmap.index_map_bs
    nodes = V.dofmap.index_map.size_local
    ndofs = nodes * bs
    xyz = V.tabulate_dof_coordinates()[:nodes]
    scale = max(x1 - x0, y1 - y0, z1 - z0)
    eps_x = 1e-8 * scale

    clamped_nodes = np.flatnonzero((np.abs(xyz[:, 0] - x0) < eps_x) | (np.abs(xyz[:, 0] - x1) < eps_x))
    bottom_nodes = np.flatnonzero((np.abs(xyz[:, 2] - z0) < eps_x) & (np.abs(xyz[:, 0] - x0) >= eps_x)
                                  & (np.abs(xyz[:, 0] - x1) >= eps_x))
    zdofs = bs * bottom_nodes + 2
    clamped_dofs = (bs * clamped_nodes[:, None] + np.arange(bs)[None, :]).ravel().astype(np.int32)
    bc = fem.dirichletbc(np.zeros(bs, dtype=PETSc.ScalarType), clamped_nodes.astype(np.int32), V)

    top = mesh.locate_entities_boundary(msh, tdim - 1, lambda x: np.isclose(x[2], z1))
    bottom = mesh.locate_entities_boundary(msh, tdim - 1, lambda x: np.isclose(x[2], z0))
    facets = np.concatenate([top, bottom]).astype(np.int32)
    tags = np.concatenate([np.full(len(top), 1, np.int32), np.full(len(bottom), 2, np.int32)])
    order = np.argsort(facets)
    facet_tags = mesh.meshtags(msh, tdim - 1, facets[order], tags[order])
    ds = ufl.Measure("ds", domain=msh, subdomain_data=facet_tags, metadata={"quadrature_degree": 2})
    dx = ufl.Measure("dx", domain=msh, metadata={"quadrature_degree": 2})

    E, nu = p["E"], p["nu"]
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    u = ufl.TrialFunction(V)
    v = ufl.TestFunction(V)

    def eps(w):
        return ufl.sym(ufl.grad(w))

    def sigma(w):
        return lam * ufl.tr(eps(w)) * ufl.Identity(3) + 2 * mu * eps(w)

    t_forms = time.perf_counter()
    a = fem.form(ufl.inner(sigma(u), eps(v)) * dx)
    L = fem.form(ufl.inner(fem.Constant(msh, np.array(p["traction"], dtype=PETSc.ScalarType)), v) * ds(1))
    W = fem.form(ufl.inner(fem.Constant(msh, np.array([0.0, 0.0, 1.0], dtype=PETSc.ScalarType)), v) * ds(2))
    t_forms = time.perf_counter() - t_forms

    A = fem_petsc.assemble_matrix(a, bcs=[bc])
    A.assemble()
    A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    f = fem_petsc.assemble_vector(L)
    fem_petsc.apply_lifting(f, [a], bcs=[[bc]])
    f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    fem_petsc.set_bc(f, [bc])
    wvec = fem_petsc.assemble_vector(W)
    weights = wvec.getArray(readonly=True)[zdofs].copy()
    wvec.destroy()
    fa = f.getArray(readonly=True).copy()

    modes = np.zeros((ndofs, 6))
    X, Y, Z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    for k in range(3):
        modes[k::3, k] = 1.0
    modes[0::3, 3], modes[1::3, 3] = -Y, X
    modes[1::3, 4], modes[2::3, 4] = -Z, Y
    modes[0::3, 5], modes[2::3, 5] = Z, -X

    def near_null_space(rows):
        q, _ = np.linalg.qr(modes[rows])
        vectors = []
        for k in range(q.shape[1]):
            vec = PETSc.Vec().createSeq(q.shape[0], comm=comm)
            vec.setArray(q[:, k])
            vectors.append(vec)
        return PETSc.NullSpace().create(vectors=vectors, comm=comm)

    A.setNearNullSpace(near_null_space(np.arange(ndofs)))

    j, dj, d2j = law_functions(np, p["breaks"], p["pieces"])
    g = p["gap"]
    diag = np.zeros(len(zdofs))
    diag_vec = A.createVecLeft()

    fresh_gamg = [0]
    last_size = [None]

    class InactiveSubmatrices:
        """The Jacobian given to SNES: products by A, and the submatrices that SNES VI solves on
        carrying the rigid motions restricted to their unknowns as their near-null space.

        PETSc 3.18's GAMG cannot be set up again on a matrix of another size after SNES VI's
        KSPReset (PCReset_GAMG leaves the multigrid levels of the old size: "Cannot change local
        size of Amat after use"; PETSc 3.19.4 resets them). Unless --as-shipped, the KSP is given a
        new GAMG when the size changes, which is what that reset does in later versions."""

        def mult(self, mat, x, y):
            A.mult(x, y)

        def createSubMatrix(self, mat, isrow, iscol, submat):
            rows = isrow.getIndices()
            if args.pc == "gamg" and not args.as_shipped and last_size[0] not in (None, len(rows)):
                pc.setType(PETSc.PC.Type.NONE)
                pc.setType(PETSc.PC.Type.GAMG)
                pc.setGAMGType("agg")
                pc.setFromOptions()
                fresh_gamg[0] += 1
            last_size[0] = len(rows)
            if len(rows) == ndofs and np.array_equal(rows, np.arange(ndofs)):
                return A
            sub = A.createSubMatrix(isrow, iscol)
            sub.setOption(PETSc.Mat.Option.SYMMETRIC, True)
            sub.setNearNullSpace(near_null_space(rows))
            return sub

    J = PETSc.Mat().createPython([ndofs, ndofs], InactiveSubmatrices(), comm=comm)
    J.setUp()
    J.setOption(PETSc.Mat.Option.SYMMETRIC, True)

    def contact_force(xa):
        r = -xa[zdofs]
        return -weights * dj(r)

    def residual(snes, x, F):
        A.mult(x, F)
        xa = x.getArray(readonly=True)
        Fa = F.getArray(readonly=True) - fa
        Fa[zdofs] += contact_force(xa) - diag * xa[zdofs]
        F.setArray(Fa)

    def jacobian(snes, x, Jmat, Pmat):
        xa = x.getArray(readonly=True)
        new = weights * d2j(-xa[zdofs])
        change = np.zeros(ndofs)
        change[zdofs] = new - diag
        diag[:] = new
        diag_vec.setArray(change)
        A.setDiagonal(diag_vec, addv=PETSc.InsertMode.ADD_VALUES)

    lower = np.full(ndofs, PETSc.NINFINITY)
    upper = np.full(ndofs, PETSc.INFINITY)
    lower[zdofs], upper[zdofs] = -g, g
    xl = PETSc.Vec().createSeq(ndofs, comm=comm)
    xl.setArray(lower)
    xu = PETSc.Vec().createSeq(ndofs, comm=comm)
    xu.setArray(upper)

    opts = PETSc.Options()
    opts["matptap_via"] = "rap"
    opts["snes_linesearch_type"] = args.linesearch
    if args.pc == "gamg":
        opts["pc_gamg_reuse_interpolation"] = "true"
    else:
        opts["pc_hypre_boomeramg_strong_threshold"] = "0.5"

    snes = PETSc.SNES().create(comm)
    snes.setType("vinewtonrsls")
    Fvec = A.createVecLeft()
    snes.setFunction(residual, Fvec)
    snes.setJacobian(jacobian, J, J)
    snes.setVariableBounds(xl, xu)
    ksp = snes.getKSP()
    ksp.setType("cg")
    ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
    pc = ksp.getPC()
    if args.pc == "gamg":
        pc.setType("gamg")
        pc.setGAMGType("agg")
    else:
        pc.setType("hypre")
        pc.setHYPREType("boomeramg")
    ksp.setTolerances(rtol=1e-4, atol=0.0, max_it=10000)
    snes.setTolerances(max_it=args.max_it)

    history = []
    ksp_per_step = []
    ksp_total = [0]

    def certificate(x, F):
        xa = x.getArray(readonly=True)
        r = F.getArray(readonly=True).copy()
        held = ((xa <= lower + 1e-8) & (r > 0)) | ((xa >= upper - 1e-8) & (r < 0))
        reactions = np.abs(r[held]).max() if held.any() else 0.0
        r[held] = 0.0
        c = contact_force(xa)
        Ax = F.getArray(readonly=True) + fa
        Ax[zdofs] -= c
        force_scale = max(np.abs(fa).max(), np.abs(Ax).max(), np.abs(c).max() if len(c) else 0.0, reactions)
        return np.abs(r).max() / force_scale, int(np.count_nonzero(held)), force_scale

    def converged(snes, its, norms):
        x = snes.getSolution()
        F = snes.getFunction()[0]
        rel, held, _ = certificate(x, F)
        if its > 0:
            lits = snes.getLinearSolveIterations()
            ksp_per_step.append(lits - ksp_total[0])
            ksp_total[0] = lits
        history.append({"iteration": its, "relative_residual": rel, "at_bound": held,
                        "function_norm": norms[2]})
        if not math.isfinite(rel):
            return PETSc.SNES.ConvergedReason.DIVERGED_FNORM_NAN
        if rel <= args.tol:
            return PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS
        if its >= args.max_it:
            return PETSc.SNES.ConvergedReason.DIVERGED_MAX_IT
        ksp.setTolerances(rtol=min(max(rel * rel, 1e-12), 1e-4))
        return PETSc.SNES.ConvergedReason.CONVERGED_ITERATING

    snes.setConvergenceTest(converged)
    snes.setFromOptions()
    ksp.setFromOptions()
    t_setup = time.perf_counter() - t_imported

    x = A.createVecRight()
    x.set(0.0)
    t0 = time.perf_counter()
    snes.solve(None, x)
    t_solve = time.perf_counter() - t0

    reason = snes.getConvergedReason()
    reason_names = {getattr(PETSc.SNES.ConvergedReason, k): k for k in dir(PETSc.SNES.ConvergedReason)
                    if not k.startswith("_")}
    F = snes.getFunction()[0]
    residual(snes, x, F)
    rel, held, force_scale = certificate(x, F)
    xa = x.getArray(readonly=True)
    Ax = F.getArray(readonly=True) + fa
    Ax[zdofs] -= contact_force(xa)
    energy = 0.5 * float(xa @ Ax) - float(fa @ xa) + float(weights @ j(-xa[zdofs]))
    uz = xa[zdofs]
    inside = (uz > -g + 1e-8) & (uz < g - 1e-8)
    pieces_used = {}
    if len(p["breaks"]):
        k = np.searchsorted(np.asarray(p["breaks"]), -uz[inside], side="left")
        pieces_used = {str(int(i)): int(c) for i, c in zip(*np.unique(k, return_counts=True))}

    def event_time(name):
        try:
            return PETSc.Log.Event(name).getPerfInfo()["time"]
        except Exception:
            return None

    out = {
        "n": n,
        "pc": args.pc,
        "law": args.law,
        "vertices": msh.topology.index_map(0).size_local,
        "cells": msh.topology.index_map(tdim).size_local,
        "dofs": ndofs,
        "unknowns": ndofs - len(clamped_dofs),
        "contact_nodes": len(zdofs),
        "contact_area": float(weights.sum()),
        "snes_reason": reason_names.get(reason, str(reason)),
        "converged": bool(reason > 0 and rel <= args.tol),
        "snes_iterations": snes.getIterationNumber(),
        "ksp_iterations": snes.getLinearSolveIterations(),
        "ksp_per_step": ksp_per_step,
        "function_evaluations": snes.getFunctionEvaluations() if hasattr(snes, "getFunctionEvaluations") else None,
        "history": history,
        "relative_residual": rel,
        "force_scale": force_scale,
        "at_bound": held,
        "inside_by_piece": pieces_used,
        "potential_energy": energy,
        "max_abs_uz_bottom": float(np.abs(uz).max()) if len(uz) else 0.0,
        "max_abs_uz": float(np.abs(xa[2::3]).max()),
        "load_work": float(fa @ xa),
        "law_energy": float(weights @ j(-xa[zdofs])),
        "time_import": t_imported - t_start,
        "time_forms": t_forms,
        "time_setup": t_setup,
        "time_solve": t_solve,
        "time_pcsetup": event_time("PCSetUp"),
        "time_kspsolve": event_time("KSPSolve"),
        "time_in_python": time.perf_counter() - t_start,
        "fresh_gamg": fresh_gamg[0],
        "linesearch": args.linesearch,
    }
    with open(args.json, "w") as fjson:
        json.dump(out, fjson, indent=1)


# --------------------------------------------------------------------------------------------
# The driver: runs, timings, the table


def timed(cmd, env, timeout, time_file):
    """Runs cmd under /usr/bin/time: (return code, elapsed s, user + system s, peak kB, stderr)."""
    full = [TIME, "-o", time_file, "-f", "%e %U %S %M", *cmd]
    try:
        p = subprocess.run(full, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, None, None, None, f"timed out after {timeout} s"
    with open(time_file) as f:
        line = [ln for ln in f.read().splitlines() if ln.strip()][-1].split()
    return p.returncode, float(line[0]), float(line[1]) + float(line[2]), int(line[3]), p.stderr


def run_hemivem(binary, n, engine, law, tol, out, timeout, env):
    folder = os.path.join(out, f"hemivem-{engine}-{law}-n{n}")
    shutil.rmtree(folder, ignore_errors=True)
    cmd = [binary, "solve", SCENE, "--set", f"mesh.n=[{n}, {n}, {n}]", "--set", 'output.write=["result-json"]',
           "--linear", ENGINES[engine], "-q", "--out", folder]
    if law == "zero":
        cmd += ["--set", 'contact.law="zero"']
    if tol != 1e-10:
        cmd += ["--tol", repr(tol)]
    rc, elapsed, cpu, peak, err = timed(cmd, env, timeout, folder + ".time")
    row = {"command": " ".join(cmd), "elapsed": elapsed, "cpu": cpu, "peak_kB": peak, "returncode": rc}
    if rc != 0:
        row["error"] = err.strip()[-2000:]
        return row
    with open(os.path.join(folder, "result.json")) as f:
        r = json.load(f)
    msg = r.get("message", "")
    words = msg.split()
    krylov = next((int(words[i - 1]) for i, w in enumerate(words) if w.startswith(ENGINES[engine]) and i > 0), None)
    contact = r.get("contact") or []
    row.update({
        "status": r["status"],
        "converged": r["converged"],
        "message": msg,
        "newton": r["iterations"],
        "cg": krylov,
        "vertices": r["mesh"]["vertices"],
        "cells": r["mesh"]["elements"],
        "unknowns": r["mesh"]["dofs"],
        "contact_nodes": len(contact),
        "potential_energy": r["potential_energy"],
        "certificate_dual": r["certificate"]["dual"],
        "max_abs_uz_bottom": max((abs(c["u_nu"]) for c in contact), default=0.0),
        "time_solve": r["timings"]["full_space"],
        "time_preconditioner": r["timings"].get("preconditioner"),
        "time_krylov": r["timings"].get("krylov"),
        "time_total_reported": r["timings"]["total"],
    })
    return row


def run_dolfinx(n, pc, linesearch, args, out, env):
    law = args.law
    result = os.path.join(out, f"dolfinx-{pc}-{linesearch}-{law}-n{n}.json")
    if os.path.exists(result):
        os.remove(result)
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", "--n", str(n), "--pc", pc, "--law", law,
           "--linesearch", linesearch, "--tol", repr(args.tol), "--max-it", str(args.max_it), "--scene", SCENE,
           "--result", result]
    if args.as_shipped:
        cmd.append("--as-shipped")
    rc, elapsed, cpu, peak, err = timed(cmd, env, args.timeout, result + ".time")
    row = {"command": "OMP_NUM_THREADS=1 " + " ".join(cmd), "elapsed": elapsed, "cpu": cpu, "peak_kB": peak,
           "returncode": rc}
    if rc != 0 or not os.path.exists(result):
        row["error"] = (err or "").strip()[-2000:]
        return row
    with open(result) as f:
        row.update(json.load(f))
    return row


def fastest(runs):
    good = [r for r in runs if r.get("elapsed") is not None and "error" not in r]
    best = min(good, key=lambda r: r["elapsed"]) if good else runs[-1]
    best["elapsed_runs"] = [r.get("elapsed") for r in runs]
    return best


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def failure(r):
    lines = [ln for ln in r.get("error", "").splitlines() if ln.strip() and "INFO:" not in ln]
    keep = [ln for ln in lines if "Cannot" in ln or "Error" in ln or "error" in ln or "timed out" in ln]
    return " | ".join((keep or lines)[-3:])


def cell(r, solver):
    if "error" in r:
        return "failed"
    mb = r["peak_kB"] / 1024.0
    if solver == "hemivem":
        return f"{r['elapsed']:.2f} ({r['time_solve']:.2f}) / {mb:.0f} / {r['newton']} / {fmt(r['cg'], 'd')}"
    mark = "" if r.get("converged") else " NOT CONVERGED: " + r.get("snes_reason", "")
    return (f"{r['elapsed']:.2f} ({r['time_solve']:.2f}) / {mb:.0f} / {r['snes_iterations']} / "
            f"{r['ksp_iterations']}{mark}")


def ratio(d, h):
    if "error" in h or "error" in d:
        return "-"
    return f"{d['elapsed'] / h['elapsed']:.2f} ({d['time_solve'] / h['time_solve']:.2f})"


def print_tables(rows, engines, searches, law):
    print()
    print(f"Example 4.1 in 3D (scenes/example-4.1-3d.toml), law '{law}', n x n x n cells. Each entry: whole process "
          "[s] (solve alone [s]) / peak memory [MB] / Newton (SNES) iterations / CG (KSP) iterations, the fastest "
          "of the runs; ratio: DOLFINx time / hemivem time, whole process (solve alone).")
    head = ["n", "unknowns", "preconditioner", "hemivem"]
    for ls in searches:
        head += [f"DOLFINx SNES VI, line search {ls}", "ratio"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for row in rows:
        for e in engines:
            h = row["hemivem"][e]
            line = [str(row["n"]), str(row.get("unknowns", "-")), e, cell(h, "hemivem")]
            for ls in searches:
                d = row["dolfinx"][e][ls]
                line += [cell(d, "dolfinx"), ratio(d, h)]
            print("| " + " | ".join(line) + " |")
    print()
    print("Energies (hemivem's virtual elements against DOLFINx's Q1 elements on the same cells: they differ by the "
          "discretisation) and largest |u_z| on the bottom")
    head = ["n", "preconditioner", "hemivem energy", "hemivem max|u_z|", "hemivem dual residual"]
    for ls in searches:
        head += [f"DOLFINx ({ls}) energy", "relative difference", "max|u_z|", "relative residual", "at the bound"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for row in rows:
        for e in engines:
            h = row["hemivem"][e]
            if "error" in h:
                print(f"| {row['n']} | {e} | " + " | ".join(["-"] * (len(head) - 2)) + " |")
                continue
            he = h["potential_energy"]
            line = [str(row["n"]), e, f"{he:.10g}", f"{h['max_abs_uz_bottom']:.6g}", f"{h['certificate_dual']:.2e}"]
            for ls in searches:
                d = row["dolfinx"][e][ls]
                if "error" in d:
                    line += ["-"] * 5
                    continue
                de = d["potential_energy"]
                line += [f"{de:.10g}", f"{(de - he) / abs(he):.3e}", f"{d['max_abs_uz_bottom']:.6g}",
                         f"{d['relative_residual']:.2e}", str(d["at_bound"])]
            print("| " + " | ".join(line) + " |")
    print()
    print("Where the solve's time goes: preconditioner set-ups / Krylov solves [s]; DOLFINx's KSP iterations per "
          "SNES iteration, residual evaluations")
    for row in rows:
        for e in engines:
            h = row["hemivem"][e]
            text = f"  n = {row['n']} {e}: hemivem " + ("failed" if "error" in h else
                   f"{fmt(h['time_preconditioner'], '.2f')} / {fmt(h['time_krylov'], '.2f')}")
            for ls in searches:
                d = row["dolfinx"][e][ls]
                text += f"; DOLFINx {ls} " + (failure(d) if "error" in d else
                        f"{fmt(d['time_pcsetup'], '.2f')} / {fmt(d['time_kspsolve'], '.2f')}, {d['ksp_per_step']}, "
                        f"{d['function_evaluations']} (before the solve {d['time_setup']:.2f} s after "
                        f"{d['time_import']:.2f} s of imports)")
            print(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sizes", nargs="*", type=int, default=[16, 24, 32], help="cells per side n (default 16 24 32)")
    ap.add_argument("--law", choices=["paper", "zero"], default="paper",
                    help="the scene's law, or zero: the box constraint alone")
    ap.add_argument("--engines", default="gamg,hypre", help="preconditioners, comma-separated: gamg, hypre")
    ap.add_argument("--linesearch", default="bt",
                    help="SNES line searches for DOLFINx, comma-separated (bt, SNES VI's default; basic: full "
                         "projected steps; l2; cp)")
    ap.add_argument("--repeat", type=int, default=2, help="runs of each measurement; the fastest is kept")
    ap.add_argument("--tol", type=float, default=1e-10, help="relative residual at which both stop")
    ap.add_argument("--max-it", type=int, default=100, help="DOLFINx's largest number of SNES iterations")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds a run may take")
    ap.add_argument("--out", default=None, help="folder of the runs (default: a new temporary folder)")
    ap.add_argument("--json", default=None, help="write every number to this file")
    ap.add_argument("--as-shipped", action="store_true",
                    help="give SNES VI's KSP no new GAMG when the inactive set changes size (PETSc 3.18 then stops)")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--n", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--pc", choices=list(ENGINES), help=argparse.SUPPRESS)
    ap.add_argument("--scene", default=SCENE, help=argparse.SUPPRESS)
    ap.add_argument("--result", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        args.json = args.result
        worker(args)
        return

    binary = os.environ.get("HEMIVEM_BINARY") or os.path.join(REPO, "build", "drivers", "hemivem")
    if not os.access(binary, os.X_OK):
        sys.exit(f"compare-dolfinx: no hemivem at {binary} (build it, or set HEMIVEM_BINARY)")
    if not os.access(TIME, os.X_OK):
        sys.exit(f"compare-dolfinx: {TIME} is needed (Debian: apt-get install time)")
    probe = subprocess.run([sys.executable, "-c", "import dolfinx, petsc4py; print(dolfinx.__version__)"],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        sys.exit("compare-dolfinx: DOLFINx is not importable by " + sys.executable +
                 " (Debian: apt-get install python3-dolfinx; run with /usr/bin/python3)")
    engines = [e.strip() for e in args.engines.split(",") if e.strip()]
    for e in engines:
        if e not in ENGINES:
            sys.exit(f"compare-dolfinx: unknown preconditioner '{e}' (gamg, hypre)")
    searches = [ls.strip() for ls in args.linesearch.split(",") if ls.strip()]
    read_problem(SCENE, args.law)
    out = args.out or tempfile.mkdtemp(prefix="compare-dolfinx-")
    os.makedirs(out, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS="1")

    print(f"hemivem: {binary}; DOLFINx {probe.stdout.strip()} ({sys.executable}); runs in {out}")
    print("load average before the runs: %.2f %.2f %.2f" % os.getloadavg())
    rows = []
    for n in args.sizes:
        row = {"n": n, "hemivem": {}, "dolfinx": {}}
        for e in engines:
            runs = []
            for _ in range(args.repeat):
                runs.append(run_hemivem(binary, n, e, args.law, args.tol, out, args.timeout, env))
                if "error" in runs[-1]:
                    break
            h = row["hemivem"][e] = fastest(runs)
            print(f"n = {n} hemivem {ENGINES[e]}: " + (failure(h) if "error" in h else
                  f"{h['elapsed_runs']} s, {h['message']}, energy {h['potential_energy']:.12g}"), flush=True)
            row["dolfinx"][e] = {}
            for ls in searches:
                runs = []
                for _ in range(args.repeat):
                    runs.append(run_dolfinx(n, e, ls, args, out, env))
                    if "error" in runs[-1]:
                        break
                d = row["dolfinx"][e][ls] = fastest(runs)
                print(f"n = {n} DOLFINx {e} {ls}: " + (failure(d) if "error" in d else
                      f"{d['elapsed_runs']} s, {d['snes_reason']}, {d['snes_iterations']} SNES / "
                      f"{d['ksp_iterations']} KSP iterations, energy {d['potential_energy']:.12g}, relative "
                      f"residual {d['relative_residual']:.2e}"), flush=True)
                if "error" not in h and "error" not in d:
                    differ = {k: (h[k], d[k]) for k in ("vertices", "cells", "unknowns", "contact_nodes")
                              if h[k] != d[k]}
                    if differ:
                        print(f"  the meshes differ (hemivem, DOLFINx): {differ}")
            if "error" not in h:
                row["unknowns"] = h["unknowns"]
        rows.append(row)
    print("load average after the runs: %.2f %.2f %.2f" % os.getloadavg())
    print_tables(rows, engines, searches, args.law)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"law": args.law, "engines": engines, "linesearch": searches, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()

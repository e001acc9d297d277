# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The condensed active set: the loop's answer from one factorization.

References from outside the condensed code: the ``"active-set"`` loop (a factorization
and solve of each active set's saddle point), PETSc's count of numeric factorizations,
and for the selected entries of the inverse, columns of the inverse from plain solves.
"""

import re

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import pytest

from dolfinx_contact_s2s.mumps import inverse_block
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.hertz.study import HertzCase, hertz_model

comm = MPI.COMM_WORLD


def _max(values):
    return comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def _factorizations():
    """Numeric factorizations so far in this process (Cholesky and LU)."""
    return sum(
        PETSc.Log.Event(name).getPerfInfo()["count"]
        for name in ("MatCholFctrNum", "MatLUFactorNum")
    )


def _solve(model, algorithm, loads, **options):
    pair = model.pair()
    PETSc.Log.begin()
    with UnilateralContactProblem(
        model.a,
        model.L,
        [pair],
        model.bcs,
        petsc_options_prefix=f"cond_{algorithm.replace('-', '_')}_",
        algorithm=algorithm,
        max_iterations=100,
        **options,
    ) as problem:
        # The assembly's checks factorize too (once per assembly, as every solve does).
        before = _factorizations()
        problem.assemble()
        checks = _factorizations() - before
        problem.solve(loads)
        n = pair.Q.dofmap.index_map.size_local
        nu = model.V.dofmap.index_map.size_local * model.V.dofmap.index_map_bs
        sets = [
            [tuple(tuple(s.tolist()) for s in it.active_sets) for it in step.iterations]
            for step in problem.history.steps
        ]
        return {
            "u": problem.u[0].x.array[:nu].copy(),
            "lam": problem.multipliers[0].x.array[:n].copy(),
            "active": problem.active[0].x.array[:n].copy(),
            "sets": sets,
            "factorizations": _factorizations() - before - 2 * checks,
        }


@pytest.mark.parametrize(
    "degree, cell", [(1, "triangle"), (1, "quadrilateral"), (2, "quadrilateral")]
)
def test_same_sets_and_answer_as_the_loop(degree, cell):
    """Hertz over two load steps: every active set, the pressure and u as the loop's.

    The cylinder is held by contact alone (its stiffness is singular), which a Schur
    complement on the multipliers could not handle; the loop factorizes every active
    set's saddle point, the condensed solve the tied one once.
    """
    model = hertz_model(HertzCase(degree=degree, cell=cell, elements_across=12))
    loads = [0.4, 1.0]
    loop = _solve(model, "active-set", loads)
    condensed = _solve(model, "condensed-active-set", loads)
    assert condensed["sets"] == loop["sets"]
    assert _max(condensed["active"] - loop["active"]) == 0.0
    assert _max(condensed["lam"] - loop["lam"]) <= 1e-10 * _max(loop["lam"])
    assert _max(condensed["u"] - loop["u"]) <= 1e-10 * _max(loop["u"])
    iterations = sum(len(step) for step in loop["sets"])
    assert iterations > 4  # the premise: many sets, each a factorization in the loop
    assert loop["factorizations"] >= iterations
    assert condensed["factorizations"] == 1


def _inverse_columns(A, rows):
    """Columns ``rows`` of the inverse of ``A`` at ``rows``, by one solve each."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    e, y = A.createVecs()
    start, end = A.getOwnershipRange()
    block = np.zeros((rows.size, rows.size))
    for k, row in enumerate(rows):
        e.set(0.0)
        if start <= row < end:
            e.setValue(row, 1.0)
        e.assemble()
        ksp.solve(e, y)
        mine = (rows >= start) & (rows < end)
        part = np.zeros(rows.size)
        part[mine] = y.array_r[rows[mine] - start]
        block[:, k] = comm.allreduce(part)
    ksp.destroy()
    e.destroy()
    y.destroy()
    return block


@pytest.mark.parametrize("factorization", ["cholesky", "lu"])
def test_inverse_block_against_solves(factorization):
    """MUMPS's selected entries of the inverse equal columns of plain solves.

    A nonsymmetric matrix for LU (the block is of the inverse, not of its transpose)
    and a symmetric indefinite one for Cholesky (:math:`LDL^T`), rows spread over the
    processes.
    """
    n, rng = 60, np.random.default_rng(3)
    dense = rng.standard_normal((n, n)) + n * np.eye(n)
    if factorization == "cholesky":
        dense = dense + dense.T
        dense[n - 10 :, n - 10 :] = 0.0  # a saddle point's zero block
    A = PETSc.Mat().createAIJ([n, n], comm=comm)
    A.setUp()
    start, end = A.getOwnershipRange()
    for i in range(start, end):
        A.setValues(i, np.arange(n, dtype=PETSc.IntType), dense[i])
    A.assemble()
    A.setOption(PETSc.Mat.Option.SYMMETRIC, factorization == "cholesky")
    rows = np.array([2, 7, 31, 50, 55, 59], dtype=np.int64)
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType(factorization)
    ksp.getPC().setFactorSolverType("mumps")
    b, x = A.createVecs()
    b.set(1.0)
    ksp.solve(b, x)  # a solve first, as the function asks for
    block = inverse_block(ksp.getPC().getFactorMatrix(), rows)
    reference = _inverse_columns(A, rows)
    assert np.abs(block - reference).max() <= 1e-12 * np.abs(reference).max()
    assert (
        np.abs(block - np.linalg.inv(dense)[np.ix_(rows, rows)]).max()
        <= 1e-12 * np.abs(reference).max()
    )
    ksp.solve(b, x)  # the factor still solves
    r = b.duplicate()
    A.mult(x, r)
    r.axpy(-1.0, b)
    assert r.norm() <= 1e-12 * b.norm()
    for obj in (ksp, A, b, x, r):
        obj.destroy()


@pytest.mark.parametrize(
    "options, pattern",
    [
        (
            {"petsc_options": {"pc_type": "jacobi", "ksp_type": "gmres"}},
            "needs a MUMPS factorization",
        ),
        ({"kind": "nest"}, "needs kind='aij'"),
    ],
)
def test_needs_a_mumps_factorization(options, pattern):
    """Another solver or a nested matrix: a clear error on every rank, not a wrong answer."""
    model = hertz_model(HertzCase(elements_across=4))
    message = None
    try:
        _solve(model, "condensed-active-set", [1.0], **options)
    except ValueError as error:
        message = str(error)
    messages = comm.allgather(message)
    assert all(m is not None and re.search(pattern, m) for m in messages), messages


def test_iterative_loop_starts_warm():
    """The Schur field split's active-set solves start from the previous solution.

    A Hertz scene held by a prescribed indentation (GAMG needs each body held): the
    iterative loop (GMRES, rtol 1e-11) ends on the active set and pressure of the
    condensed direct solve (MUMPS), with its later solves started warm.
    """
    import dolfinx
    import ufl

    from dolfinx_contact_s2s.fieldsplit import iterative_options, use_schur_complement

    case = HertzCase(elements_across=12)
    model = hertz_model(case)
    V, scene = model.V, model.scene
    top = scene.facet_tags.find(scene.tags["upper_top"])
    top_y = dolfinx.fem.locate_dofs_topological(V.sub(1), 1, top)
    depth = dolfinx.fem.Constant(V.mesh, -(case.a**2) / case.R1)
    bcs = [*model.bcs, dolfinx.fem.dirichletbc(depth, top_y, V.sub(1))]
    L = ufl.inner(dolfinx.fem.Constant(V.mesh, np.zeros(2)), ufl.TestFunction(V)) * ufl.dx
    out = {}
    for solver in ("iterative", "direct"):
        pair = model.pair()
        options = {"algorithm": "condensed-active-set"}
        if solver == "iterative":
            options = {
                "petsc_options": iterative_options(spaces=1, schur="mass"),
                "kind": "nest",
                "tolerance": 1e-6,
            }
        with UnilateralContactProblem(
            model.a, L, [pair], bcs, petsc_options_prefix=f"warm_{solver}_", **options
        ) as problem:
            if solver == "iterative":
                use_schur_complement(problem)
            problem.solve()
            n = pair.Q.dofmap.index_map.size_local
            out[solver] = (
                problem.multipliers[0].x.array[:n].copy(),
                problem.active[0].x.array[:n].copy(),
                problem.history.iterations,
                problem.solver.getInitialGuessNonzero(),
            )
    (lam_it, active_it, solves, warm), (lam, active, _, _) = out["iterative"], out["direct"]
    assert solves > 2 and warm  # the premise: several active sets, started warm
    assert _max(active_it - active) == 0.0
    assert _max(lam_it - lam) <= 1e-6 * _max(lam)


def test_refuses_newtons_linearized_system():
    """Finite deformation: the system changes in every Newton iteration, a clear error.

    The frozen first iteration of a step is a linear problem the condensed solve takes;
    the full tangent's is refused on every rank, not solved with a wrong expansion.
    """
    from dolfinx_contact_s2s.finite import NonlinearContactProblem
    from paper.large_sliding import SlidingScene

    scene = SlidingScene(1)
    message = None
    try:
        with NonlinearContactProblem(
            scene.F,
            scene.u,
            [scene.pair()],
            scene.bcs,
            petsc_options_prefix="cond_nl_",
            algorithm="condensed-active-set",
        ) as problem:
            problem.solve()
    except ValueError as error:
        message = str(error)
    messages = comm.allgather(message)
    assert all(m is not None and "solves linear bodies" in m for m in messages), messages

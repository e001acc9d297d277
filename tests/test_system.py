# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The direct saddle-point solve: LDL^T where the system is symmetric, K stored once.

References from outside the code: the patch test's uniform pressure, LU against
LDL^T (two factorizations), a dense NumPy check of symmetry and a dense NumPy solve
of the gathered system.
"""

import logging

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import ufl
from test_system_checks import MATERIALS, max_pressure_error, readme_problem

from dolfinx_contact_s2s import contact_pairs, contact_surface
from dolfinx_contact_s2s.la import gather_dense, is_symmetric
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper import scenes
from paper.hertz.study import HertzCase, hertz_model

comm = MPI.COMM_WORLD
EPS = np.finfo(float).eps


def solution(problem: LinearContactProblem) -> np.ndarray:
    """The whole solution vector (displacements and multipliers), on every process."""
    return np.concatenate(comm.allgather(problem.x.array_r.copy()))


def test_symmetry_check_agrees_with_dense():
    """is_symmetric on K: symmetric elasticity yes, with a convection term no (dense check)."""
    with readme_problem(prefix="sym_") as problem:
        V = problem.spaces[0]
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        beta = dolfinx.fem.Constant(V.mesh, np.array([1.0, 0.5]))
        for form, expected in (
            (problem.a[0], True),
            (dolfinx.fem.form(ufl.inner(ufl.grad(u) * beta, v) * ufl.dx), False),
        ):
            K = dolfinx.fem.petsc.assemble_matrix(form)
            K.assemble()
            dense = gather_dense(K)
            asymmetry = np.max(np.abs(dense - dense.T)) / np.max(np.sum(np.abs(dense), axis=1))
            assert (asymmetry < 1e3 * EPS) == expected
            assert is_symmetric(K) == expected
            K.destroy()


def lu_solution(A: PETSc.Mat, b: PETSc.Vec) -> np.ndarray:
    """MUMPS LU of ``A`` applied to ``b``, by a KSP of the test's own."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    x = A.createVecRight()
    ksp.solve(b, x)
    assert ksp.getConvergedReason() > 0
    out = np.concatenate(comm.allgather(x.array_r.copy()))
    x.destroy()
    ksp.destroy()
    return out


@pytest.mark.parametrize("degree", [1, 2])
def test_ldlt_is_the_default_and_matches_lu_on_the_patch_test(degree):
    """Symmetric default: MUMPS Cholesky (LDL^T), the same solution as LU to round-off."""
    with readme_problem(prefix=f"ldlt_{degree}_", degree=degree) as problem:
        problem.solve()
        assert problem.symmetric
        assert problem.solver.getPC().getType() == "cholesky"
        assert problem.solver.getPC().getFactorSolverType() == "mumps"
        # The patch test: a uniform unit pressure (Eq. 18 with the paper's data).
        assert max_pressure_error(problem) < 1e-10
        x = solution(problem)
        reference = lu_solution(problem.A, problem.b)
    scale = np.max(np.abs(reference))
    assert np.max(np.abs(x - reference)) < 1e3 * EPS * scale


def test_database_pc_type_beats_the_symmetric_default():
    options = PETSc.Options()
    options["dbpc_pc_type"] = "lu"
    try:
        with readme_problem(prefix="dbpc_") as problem:
            problem.solve()
            assert problem.symmetric
            assert problem.solver.getPC().getType() == "lu"
    finally:
        options.delValue("dbpc_pc_type")


def convected_problem(prefix, petsc_options=None):
    """The README problem with a convection-like (nonsymmetric) term in the lower body."""
    scene = scenes.patch_test(comm, elements=(10, 7))
    a, L, bcs, surfaces = [], [], [], {}
    for name, body in scene.bodies.items():
        V = dolfinx.fem.functionspace(body.mesh, ("Lagrange", 1, (2,)))
        a_body, _, v = MATERIALS[name].forms(V)
        if name == "lower":
            beta = dolfinx.fem.Constant(body.mesh, np.array([0.3, 0.2]))
            a_body += ufl.inner(ufl.grad(ufl.TrialFunction(V)) * beta, v) * ufl.dx
        ds = ufl.Measure("ds", domain=body.mesh, subdomain_data=body.facet_tags)
        t = dolfinx.fem.Constant(body.mesh, np.array([0.0, -1.0 if name == "upper" else 0.0]))
        a.append(a_body)
        L.append(ufl.inner(t, v) * ds(scenes.TOP))
        left = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, body.facet_tags.find(scenes.LEFT))
        bcs.append(dolfinx.fem.dirichletbc(0.0, left, V.sub(0)))
        if name == "lower":
            bottom = body.facet_tags.find(scenes.BOTTOM)
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(1), 1, bottom)
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(1)))
        surfaces[name] = contact_surface(V, body.facet_tags, body.contact)
    pairs = contact_pairs(surfaces["upper"], surfaces["lower"])
    return LinearContactProblem(
        a, L, pairs, bcs, petsc_options_prefix=prefix, petsc_options=petsc_options
    )


def test_nonsymmetric_form_falls_back_to_lu(caplog):
    """A convection term: LU by default (logged), the dense solution; forced LDL^T fails."""
    with caplog.at_level(logging.INFO, logger="dolfinx_contact_s2s.problem"):
        with convected_problem("conv_") as problem:
            problem.solve()
            assert not problem.symmetric
            assert problem.solver.getPC().getType() == "lu"
            x = solution(problem)
            A = gather_dense(problem.A)
            b = np.concatenate(comm.allgather(problem.b.array_r.copy()))
            assert np.max(np.abs(A - A.T)) > 1e-3 * np.max(np.abs(A))
            reference = np.linalg.solve(A, b)
            assert np.max(np.abs(x - reference)) < 1e-10 * np.max(np.abs(reference))
    if comm.rank == 0:
        assert "not symmetric" in caplog.text
    # LDL^T would use one triangle of a nonsymmetric matrix: the residual check refuses it.
    with convected_problem("conv_chol_", {"pc_type": "cholesky"}) as problem:
        with pytest.raises(RuntimeError, match="cannot be trusted"):
            problem.solve()


def test_stiffness_is_stored_once():
    """kind='aij': K only inside A after assembly; the copy taken out is the assembled K."""
    with readme_problem(prefix="once_") as problem:
        problem.solve()
        with pytest.raises(RuntimeError, match="stiffness_matrix"):
            problem.stiffness  # noqa: B018
        for i, (a, bcs) in enumerate(zip(problem.a, problem.bcs_by_space, strict=True)):
            K = dolfinx.fem.petsc.assemble_matrix(a, bcs=bcs)
            K.assemble()
            copy = problem.stiffness_matrix(i)
            assert np.array_equal(gather_dense(copy), gather_dense(K))
            d = problem.stiffness_diagonal(i)
            assert np.array_equal(d.array_r, K.getDiagonal().array_r)
            for obj in (K, copy, d):
                obj.destroy()
    with readme_problem(prefix="once_nest_", kind="nest") as problem:
        problem.assemble()
        assert len(problem.stiffness) == 2


@pytest.mark.parametrize("algorithm", ["active-set", "penalty"])
def test_hertz_ldlt_matches_lu(algorithm):
    """Hertz, semismooth Newton (and penalty): LDL^T and LU give the same contact answer.

    Every active-set system is symmetric (an inactive multiplier loses its column with
    its row): checked on the last one, against its dense transpose.
    """
    case = HertzCase(elements_across=10, algorithm=algorithm)
    results = []
    for name, options in (("ldlt", None), ("lu", {"pc_type": "lu"})):
        model = hertz_model(case, comm)
        with UnilateralContactProblem(
            model.a,
            model.L,
            [model.pair()],
            model.bcs,
            petsc_options_prefix=f"hertz_{algorithm}_{name}_",
            petsc_options=options,
            algorithm=algorithm,
            max_iterations=100,
        ) as problem:
            _, (lam,) = problem.solve()
            assert problem.symmetric
            A = gather_dense(problem.A)
            assert np.max(np.abs(A - A.T)) <= 10 * EPS * np.max(np.abs(A))
            if algorithm == "active-set":
                assert problem.solver.getPC().getType() == ("lu" if options else "cholesky")
            n = lam.function_space.dofmap.index_map.size_local
            results.append(
                (
                    np.concatenate(comm.allgather(lam.x.array[:n].copy())),
                    problem.history.iterations,
                )
            )
    (lam_ldlt, it_ldlt), (lam_lu, it_lu) = results
    assert it_ldlt == it_lu
    assert np.max(np.abs(lam_ldlt - lam_lu)) < 1e-9 * np.max(np.abs(lam_lu))


def test_symmetry_check_sees_couplings_between_processes():
    """An asymmetric entry coupling the first and the last row, whichever process owns them."""
    n = 8
    for value, expected in ((1.0, False), (0.0, True)):
        A = PETSc.Mat().createAIJ([n, n], nnz=(2, 2), comm=comm)
        start, end = A.getOwnershipRange()
        for i in range(start, end):
            A.setValue(i, i, 2.0)
        if start == 0:
            A.setValue(0, n - 1, value)
        if end == n:
            A.setValue(n - 1, 0, 0.0)
        A.assemble()
        dense = gather_dense(A)
        assert np.array_equal(dense, dense.T) == expected
        assert is_symmetric(A) == expected
        A.destroy()

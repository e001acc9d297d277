# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Every solve checks itself: the defects of issue [4/8], built the way a user builds them.

Each test is the README example with one thing a user gets wrong, or one option a user
sets; the expected outcome is a correct answer or a clear exception on every rank.
"""

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import Material, contact_pairs, contact_surface
from dolfinx_contact_s2s.analysis.dense import solvability
from dolfinx_contact_s2s.problem import LinearContactProblem
from paper import scenes
from paper.blocks import block_problem

comm = MPI.COMM_WORLD
MATERIALS = {"lower": Material(E=1.0, nu=0.3), "upper": Material(E=3.0, nu=0.2)}


def readme_problem(
    *,
    elements=(10, 7),
    degree=1,
    support=True,
    contactor="upper",
    method="segment-to-segment",
    prefix="checks_",
    **kwargs,
):
    """The README example; ``support=False`` forgets the lower block's vertical support."""
    scene = scenes.patch_test(comm, elements=elements)
    a, L, bcs, surfaces = [], [], [], {}
    for name, body in scene.bodies.items():
        V = dolfinx.fem.functionspace(body.mesh, ("Lagrange", degree, (2,)))
        a_body, _, v = MATERIALS[name].forms(V)
        ds = ufl.Measure("ds", domain=body.mesh, subdomain_data=body.facet_tags)
        t = dolfinx.fem.Constant(body.mesh, np.array([0.0, -1.0 if name == "upper" else 0.0]))
        a.append(a_body)
        L.append(ufl.inner(t, v) * ds(scenes.TOP))
        left = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, body.facet_tags.find(scenes.LEFT))
        bcs.append(dolfinx.fem.dirichletbc(0.0, left, V.sub(0)))
        if name == "lower" and support:
            bottom = body.facet_tags.find(scenes.BOTTOM)
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(1), 1, bottom)
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(1)))
        surfaces[name] = contact_surface(V, body.facet_tags, body.contact)
    target = "lower" if contactor == "upper" else "upper"
    pairs = contact_pairs(surfaces[contactor], surfaces[target], method=method)
    return LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix=prefix, **kwargs)


def max_pressure_error(problem):
    lam = problem.multipliers[0]
    owned = lam.function_space.dofmap.index_map.size_local
    local = float(np.max(np.abs(lam.x.array[:owned] - 1.0), initial=0.0))
    return comm.allreduce(local, op=MPI.MAX)


def test_readme_problem_passes_the_patch_test():
    with readme_problem() as problem:
        problem.solve()
        assert max_pressure_error(problem) < 1e-10
        assert problem.residual() < 1e-12


def test_floating_body_raises_naming_it():
    """Without its vertical support the lower block floats: raise, naming body and motion."""
    with readme_problem(support=False) as problem:
        with pytest.raises(ValueError, match="rigid motion") as info:
            problem.solve()
    message = str(info.value)
    # Space 0 is the lower block; it can only translate vertically.
    assert "space 0" in message
    assert "translation" in message


def test_redundant_constraints_raise():
    """Node-to-segment at the contactor's Gauss points over-constrains the finer surface.

    The dense SVD of B (Eq. 35, an independent implementation) says the same.
    """
    with readme_problem(contactor="lower", method="node-to-segment-gauss") as problem:
        problem.assemble(check=False)
        assert not solvability(problem).solvable
        with pytest.raises(ValueError, match="redundant constraint"):
            problem.solve()


@pytest.mark.parametrize("degree", [1, 2])
def test_two_passes_redundant_together_raise(degree):
    """Two-pass node-to-segment: each pass alone has full row rank; on quadratic elements
    the passes together do not (Eq. 35), and the multipliers of a solve would be
    arbitrary (LU and LDL^T differed by 10x their size). The count is the dense SVD's
    (the stacked B of :func:`solvability`); on linear elements the solve goes through."""
    with readme_problem(method="two-pass node-to-segment", degree=degree) as problem:
        problem.assemble(check=False)
        reference = solvability(problem)
        assert (reference.redundant > 0) == (degree == 2)
        if degree == 1:
            problem.solve()
            assert problem.residual() <= problem.residual_tolerance
            return
        with pytest.raises(ValueError, match="redundant constraint") as info:
            problem.solve()
    message = str(info.value)
    assert f"have {reference.redundant} redundant constraint(s) of {reference.constraints}" in (
        message
    )
    assert "pair 0" in message and "pair 1" in message and "together" in message


def test_petsc_options_reach_the_factorization():
    """MUMPS options given as petsc_options are read by the factor (ICNTL(14) read back)."""
    with readme_problem(prefix="icntl_", petsc_options={"mat_mumps_icntl_14": 200}) as problem:
        problem.solve()
        factor = problem.solver.getPC().getFactorMatrix()
        assert factor.getMumpsIcntl(14) == 200
        assert max_pressure_error(problem) < 1e-10


def test_options_live_with_the_problem_and_are_restored():
    options = PETSc.Options()
    options["scope_ksp_rtol"] = "1e-3"
    problem = readme_problem(prefix="scope_", petsc_options={"ksp_rtol": 1e-9})
    assert options.getReal("scope_ksp_rtol") == pytest.approx(1e-9)
    assert options.getString("scope_pc_type") == "cholesky"  # a default (MUMPS LDL^T)
    problem.destroy()
    assert options.getReal("scope_ksp_rtol") == pytest.approx(1e-3)
    assert not options.hasName("scope_pc_type")
    options.delValue("scope_ksp_rtol")


def test_database_options_beat_the_defaults():
    """Options from the command line or PETSC_OPTIONS under the prefix are honoured."""
    options = PETSc.Options()
    options["cli_ksp_type"] = "gmres"
    options["cli_ksp_rtol"] = "1e-13"
    try:
        with readme_problem(prefix="cli_") as problem:
            problem.solve()
            assert problem.solver.getType() == "gmres"
            # The default factorization of a symmetric system: LDL^T.
            assert problem.solver.getPC().getType() == "cholesky"
            assert max_pressure_error(problem) < 1e-10
    finally:
        options.delValue("cli_ksp_type")
        options.delValue("cli_ksp_rtol")


#: No workspace beyond MUMPS's estimate (ICNTL(14) = 0), and a pivoting threshold (CNTL(1))
#: that delays many pivots of the saddle point's zero block: INFOG(1) = -9. With LU: the
#: 2x2 pivots of the default LDL^T take the zero block without delays.
TIGHT_WORKSPACE = {"pc_type": "lu", "mat_mumps_icntl_14": 0, "mat_mumps_cntl_1": 0.9}


def test_mumps_workspace_error_is_provoked():
    """The options above do make the first factorization fail with INFOG(1) = -9."""
    with readme_problem(prefix="ws0_", degree=2, petsc_options=TIGHT_WORKSPACE) as problem:
        problem.assemble()
        problem.solver.solve(problem.b, problem.x)
        assert problem.solver.getConvergedReason() < 0
        assert problem.solver.getPC().getFactorMatrix().getMumpsInfog(1) == -9


def test_mumps_workspace_error_is_recovered():
    """The solve raises ICNTL(14) and factorizes again: the patch test's answer."""
    with readme_problem(prefix="ws1_", degree=2, petsc_options=TIGHT_WORKSPACE) as problem:
        problem.solve()
        assert problem.solver.getPC().getFactorMatrix().getMumpsIcntl(14) > 0
        assert max_pressure_error(problem) < 1e-10


def test_mumps_workspace_error_names_the_option():
    with readme_problem(
        prefix="ws2_", degree=2, petsc_options=TIGHT_WORKSPACE, workspace_retries=0
    ) as problem:
        with pytest.raises(RuntimeError, match=r"INFOG\(1\) = -9.*mat_mumps_icntl_14"):
            problem.solve()


def test_an_untrustworthy_solve_raises():
    """One Jacobi sweep 'converges' (preonly) to a wrong answer: the residual check raises."""
    options = {"ksp_type": "preonly", "pc_type": "jacobi"}
    with readme_problem(prefix="jacobi_", petsc_options=options) as problem:
        with pytest.raises(RuntimeError, match="cannot be trusted"):
            problem.solve()


def test_krylov_failure_raises():
    options = {"ksp_type": "cg", "pc_type": "none", "ksp_max_it": 2}
    with readme_problem(prefix="cg_", petsc_options=options) as problem:
        with pytest.raises(RuntimeError, match=r"DIVERGED_(MAX_IT|ITS)"):
            problem.solve()


def test_fieldsplit_from_options_on_the_nest():
    """Named fields and rigid modes reach PCFieldSplit; it agrees with MUMPS LU.

    The inf-sup model of Fig. 2 (both blocks clamped, overlapping by 0.01), so that each
    body's K is invertible on its own: FGMRES (right preconditioning, the true residual
    converges) with one block per field.
    """
    options = {
        "ksp_type": "fgmres",
        "ksp_rtol": 1e-12,
        "ksp_max_it": 300,
        "pc_type": "fieldsplit",
        "pc_fieldsplit_type": "additive",
        "fieldsplit_u0_ksp_type": "preonly",
        "fieldsplit_u0_pc_type": "lu",
        "fieldsplit_u1_ksp_type": "preonly",
        "fieldsplit_u1_pc_type": "lu",
        "fieldsplit_lambda0_ksp_type": "preonly",
        "fieldsplit_lambda0_pc_type": "none",
    }
    scene = scenes.inf_sup_model(comm, (5, 3))
    solutions = []
    for kind, prefix, opts in (("nest", "split_", options), ("aij", "direct_", None)):
        problem = block_problem(
            scene,
            (1, 1),
            "upper",
            support="clamped",
            petsc_options_prefix=prefix,
            petsc_options=opts,
            search_radius=0.5,
            kind=kind,
        )
        with problem:
            problem.solve()
            solutions.append(problem.multipliers[0].x.array.copy())
            if kind == "nest":
                assert problem.A.getType() == "nest"
                sub = problem.solver.getPC().getFieldSplitSubKSP()
                assert [k.getOptionsPrefix() for k in sub] == [
                    "split_fieldsplit_u0_",
                    "split_fieldsplit_u1_",
                    "split_fieldsplit_lambda0_",
                ]
                for K in problem.stiffness:
                    assert len(K.getNearNullSpace().getVecs()) == 3  # rigid modes, for GAMG
    scale = np.max(np.abs(solutions[1]))
    assert scale > 0
    assert np.max(np.abs(solutions[0] - solutions[1])) < 1e-8 * scale


def test_pairs_sharing_a_contactor_are_refused():
    scene = scenes.patch_test(comm, elements=(4, 3))
    V = {
        n: dolfinx.fem.functionspace(b.mesh, ("Lagrange", 1, (2,))) for n, b in scene.bodies.items()
    }
    up = contact_surface(V["upper"], scene.upper.facet_tags, scenes.BOTTOM)
    low = contact_surface(V["lower"], scene.lower.facet_tags, scenes.TOP)
    pairs = contact_pairs(up, low) + contact_pairs(up, low)
    a = [MATERIALS[n].forms(V[n])[0] for n in ("lower", "upper")]
    L = [
        ufl.inner(dolfinx.fem.Constant(V[n].mesh, np.zeros(2)), ufl.TestFunction(V[n])) * ufl.dx
        for n in ("lower", "upper")
    ]
    with pytest.raises(ValueError, match="one multiplier field"):
        LinearContactProblem(a, L, pairs, petsc_options_prefix="share_")


def test_prefix_is_mandatory():
    with pytest.raises(ValueError, match="non-empty petsc_options_prefix"):
        readme_problem(prefix="")

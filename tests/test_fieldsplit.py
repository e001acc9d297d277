# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The Schur-complement field split of ``dolfinx_contact_s2s.fieldsplit``.

On the inf-sup model of Fig. 2 (two clamped blocks meshed independently, 10n/7n
quadrilaterals on the contact line, overlapping by 0.01):

- the solution agrees with MUMPS LU;
- the outer iterations are nearly independent of h with the fractional Schur
  approximation (an operator of order -1, like S), and grow like h^(-1/2) with the
  multiplier mass matrix (spectrally equivalent to S only up to H/h), by theory. The
  bound between the two: over a 4x refinement, Krylov iterations proportional to
  sqrt(cond) double when cond grows like 1/h and stay put when it is bounded; the test
  allows the geometric middle, sqrt(2), and requires the mass matrix to exceed it.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.elasticity import Material
from dolfinx_contact_s2s.fieldsplit import (
    SchurComplementSetup,
    iterative_options,
    use_schur_complement,
)
from dolfinx_contact_s2s.problem import LinearContactProblem
from paper import scenes
from paper.blocks import block_problem
from paper.scenes_multi import two_blocks_one_mesh

comm = MPI.COMM_WORLD
LEVELS = (2, 4, 8)
#: Relative agreement with MUMPS LU: the problem's residual tolerance.
TOLERANCE = 1e-8


def _solve(scene, n, solver, schur="fractional"):
    """Solve the clamped two-block model; (iterations, displacements, multiplier)."""
    options = iterative_options(spaces=2, schur=schur) if solver == "iterative" else None
    problem = block_problem(
        scene,
        (1, 1),
        "upper",
        support="clamped",
        petsc_options_prefix=f"it_{solver}_{schur}_",
        petsc_options=options,
        kind="nest" if solver == "iterative" else "aij",
        search_radius=abs(scene.gap) + scene.width / (7 * n),
    )
    with problem:
        if solver == "iterative":
            setup = use_schur_complement(problem)
        problem.solve()  # raises unless the relative residual is below 1e-8
        if solver == "iterative":
            assert [k.getOptionsPrefix() for k in problem.solver.getPC().getFieldSplitSubKSP()] == [
                f"it_{solver}_{schur}_fieldsplit_u_",
                f"it_{solver}_{schur}_fieldsplit_lambda_",
            ]
            setup.destroy()
        its = problem.solver.getIterationNumber()
        u = [f.x.array.copy() for f in problem.u]
        lam = problem.multipliers[0].x.array.copy()
    return its, u, lam


@pytest.fixture(scope="module")
def models():
    return {n: scenes.inf_sup_model(comm, (10 * n, 7 * n)) for n in LEVELS}


def _max(a):
    """Largest |a| over all ranks (a rank may own nothing)."""
    return comm.allreduce(float(np.max(np.abs(a), initial=0.0)), op=MPI.MAX)


def _problem(a, L, pairs, bcs, solver, prefix, spaces):
    """The problem with the iterative solver (a nest, the Schur field split) or MUMPS LU."""
    iterative = solver == "iterative"
    return LinearContactProblem(
        a,
        L,
        pairs,
        bcs,
        petsc_options_prefix=prefix,
        petsc_options=iterative_options(spaces=spaces) if iterative else None,
        kind="nest" if iterative else "aij",
    )


def test_agrees_with_lu_and_iterations_bounded(models):
    iterations = {}
    for n in LEVELS:
        its, u_it, lam_it = _solve(models[n], n, "iterative")
        _, u_lu, lam_lu = _solve(models[n], n, "lu")
        iterations[n] = its
        # Agreement to the residual tolerance of every solve, 1e-8 (measured: 4e-12 in
        # the multiplier, 2e-12 in the displacements; GMRES stops at 1e-11).
        scale = _max(lam_lu)
        assert scale > 0
        assert _max(lam_it - lam_lu) <= TOLERANCE * scale
        for a, b in zip(u_it, u_lu, strict=True):
            assert _max(a - b) <= TOLERANCE * _max(b)
    assert iterations[LEVELS[-1]] <= np.sqrt(2) * iterations[LEVELS[0]], iterations


def test_mass_schur_grows_with_refinement(models):
    """The mass matrix alone is not spectrally equivalent to S: the bound above fails."""
    iterations = {n: _solve(models[n], n, "iterative", "mass")[0] for n in (LEVELS[0], LEVELS[-1])}
    assert iterations[LEVELS[-1]] > np.sqrt(2) * iterations[LEVELS[0]], iterations


def test_one_space_two_bodies():
    """Both blocks in one mesh and space: GAMG on K alone, with the modes of both bodies."""
    scene = two_blocks_one_mesh(comm, (20, 14), cell="quadrilateral")
    part = scene.parts["blocks"]
    V = dolfinx.fem.functionspace(part.mesh, ("Lagrange", 1, (2,)))
    a, _, v = Material(E=1.0, nu=0.3).forms(V)
    L = ufl.inner(dolfinx.fem.Constant(part.mesh, np.zeros(2)), v) * ufl.dx
    fdim = part.mesh.topology.dim - 1
    bottom = dolfinx.fem.locate_dofs_topological(
        V, fdim, part.facet_tags.find(scene.tag("lower", "bottom"))
    )
    top = dolfinx.fem.locate_dofs_topological(
        V, fdim, part.facet_tags.find(scene.tag("upper", "top"))
    )
    bcs = [
        dolfinx.fem.dirichletbc(np.zeros(2), bottom, V),
        dolfinx.fem.dirichletbc(np.array([0.002, -0.01]), top, V),
    ]
    pair = contact_pair(
        contact_surface(V, part.facet_tags, scene.tag("upper", "bottom")),
        contact_surface(V, part.facet_tags, scene.tag("lower", "top")),
    )
    results = []
    for solver in ("iterative", "lu"):
        with _problem(a, L, [pair], bcs, solver, f"one_{solver}_", spaces=1) as problem:
            if solver == "iterative":
                setup = use_schur_complement(problem)
            problem.solve()
            if solver == "iterative":
                u_pc = problem.solver.getPC().getFieldSplitSubKSP()[0].getPC()
                assert u_pc.getType() == "gamg"
                assert len(problem.stiffness[0].getNearNullSpace().getVecs()) == 6
                setup.destroy()
            results.append(problem.multipliers[0].x.array.copy())
    scale = _max(results[1])
    assert scale > 0
    assert _max(results[0] - results[1]) <= TOLERANCE * scale


def test_schur_complement_needs_a_nest_problem():
    """use_schur_complement configures the solver only: the kind is given at construction."""
    scene = scenes.inf_sup_model(comm, (2, 2))
    with block_problem(
        scene,
        (1, 1),
        "upper",
        support="clamped",
        petsc_options_prefix="it_aij_",
        search_radius=0.5,
    ) as problem:
        with pytest.raises(ValueError, match="kind='nest'"):
            use_schur_complement(problem)
        assert problem.kind == "aij"


def test_bad_options():
    with pytest.raises(ValueError, match="schur must be one of"):
        iterative_options(schur="lumped")
    with pytest.raises(ValueError, match="at least one"):
        iterative_options(spaces=0)
    assert callable(SchurComplementSetup())


def _rectangle(x0, y0, nx, ny, tags):
    """A clamped-ready block ``[x0, x0 + 1] x [y0, y0 + 0.5]`` with tagged bottom and top."""
    mesh = dolfinx.mesh.create_rectangle(
        comm,
        [np.array([x0, y0]), np.array([x0 + 1.0, y0 + 0.5])],
        [nx, ny],
        cell_type=dolfinx.mesh.CellType.quadrilateral,
    )
    fdim = mesh.topology.dim - 1
    bottom = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], y0))
    top = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], y0 + 0.5))
    facets = np.concatenate([bottom, top])
    values = np.concatenate([np.full(bottom.size, tags[0]), np.full(top.size, tags[1])])
    order = np.argsort(facets)
    return mesh, dolfinx.mesh.meshtags(mesh, fdim, facets[order], values[order].astype(np.int32))


def test_overhang_inactive_multipliers():
    """A contactor hanging a third over the end of its target: uncovered rows read lambda = 0."""
    bodies = [_rectangle(0.0, 0.0, 21, 10, (1, 2)), _rectangle(1 / 3, 0.49, 15, 7, (3, 4))]
    spaces, a, L, bcs = [], [], [], []
    for (mesh, tags), clamped in zip(bodies, (1, 4), strict=True):
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
        form, _, v = Material(E=1.0, nu=0.3).forms(V)
        spaces.append(V)
        a.append(form)
        L.append(ufl.inner(dolfinx.fem.Constant(mesh, np.zeros(2)), v) * ufl.dx)
        dofs = dolfinx.fem.locate_dofs_topological(V, 1, tags.find(clamped))
        bcs.append(dolfinx.fem.dirichletbc(np.zeros(2), dofs, V))
    pair = contact_pair(
        contact_surface(spaces[1], bodies[1][1], 3),
        contact_surface(spaces[0], bodies[0][1], 2),
        search_radius=0.1,
    )
    results = []
    for solver in ("iterative", "lu"):
        with _problem(a, L, [pair], bcs, solver, f"over_{solver}_", spaces=2) as problem:
            if solver == "iterative":
                setup = use_schur_complement(problem)
            problem.solve()
            uncovered = problem.operators[0].uncovered
            if solver == "iterative":
                setup.destroy()
            results.append(problem.multipliers[0].x.array.copy())
    # The nodes beyond x = 1 of the 15 upper facets (x = 1/3 + k/15, k = 11..15).
    assert uncovered.size == 5
    scale = _max(results[1])
    assert scale > 0
    assert _max(results[0] - results[1]) <= TOLERANCE * scale

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Unilateral contact, Eq. (1): the contact area is an unknown (issue [5/8]).

Every scene has a solution known without the code:

- the patch test of section 3.2 solved as a unilateral problem: every multiplier active
  and the tied answer :math:`\lambda = p`, :math:`\sigma = \mathrm{diag}(0, -p)`;
- a block held by its own supports that sags away from its neighbour under its weight:
  no contact, :math:`\lambda = 0`, and (with :math:`\nu = 0`) the column solution
  :math:`u_y(H) = -\rho g H^2 / (2 E)`, exact in P2;
- two blocks meshed with an overlap :math:`\delta` and clamped at their far ends: pushed
  apart by the uniform pressure :math:`p = \delta / (H_1 / E_1' + H_2 / E_2')`,
  :math:`E' = E / (1 - \nu^2)` (free lateral expansion).
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.compat import geometry_dofmap
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import (
    ALGORITHMS,
    ContactConvergenceError,
    UnilateralContactProblem,
)
from paper.scenes_multi import two_blocks_one_mesh

EPS = np.finfo(np.float64).eps
#: The issue's bound on the patch test solved as a unilateral problem.
BOUND = 1e-10
MATERIAL = Material(E=1.0, nu=0.3)
#: Lagrange-multiplier algorithms: exact complementarity.
EXACT = ("active-set", "snes-vi")


def _multiplier(algorithm, degree):
    """Dual multipliers for the algorithm that needs them, else Lagrange (Eq. 16)."""
    return ("Dual" if algorithm == "dual-active-set" else "Lagrange", degree)


def _bc(V, component, facets):
    dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 1, facets)
    return dolfinx.fem.dirichletbc(dolfinx.default_scalar_type(0), dofs, V.sub(component))


def _blocks(degree=1, cell="triangle", shift=0.0):
    """Two blocks in one mesh (lower tags 1/2/10/4, upper 20/22/23/24), upper moved by shift."""
    scene = two_blocks_one_mesh(MPI.COMM_WORLD, (7, 5), cell=cell, geometry_degree=1)
    part = scene.parts["blocks"]
    if shift:
        # A user's shifted mesh: move the nodes of the upper block's cells (tag 2).
        nodes = np.unique(geometry_dofmap(part.mesh)[part.cell_tags.find(2)])
        part.mesh.geometry.x[nodes, 1] += shift
    V = dolfinx.fem.functionspace(part.mesh, ("Lagrange", degree, (2,)))
    return part, V


def _owned_max(values):
    return MPI.COMM_WORLD.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def _unknowns(V, pair):
    return V.dofmap.index_map.size_global * 2 + pair.Q.dofmap.index_map.size_global


@pytest.mark.parametrize("algorithm", [*EXACT, "dual-active-set"])
@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
@pytest.mark.parametrize("degree", [1, 2])
def test_patch_test_unilateral(algorithm, cell, degree):
    """The patch test as a unilateral problem: all active, the tied answer to 1e-10."""
    part, V = _blocks(degree, cell)
    a, _, v = MATERIAL.forms(V)
    p = 0.75
    ds = ufl.Measure("ds", domain=part.mesh, subdomain_data=part.facet_tags)
    L = -p * v[1] * ds(23)
    bcs = [_bc(V, 0, np.concatenate([part.facet_tags.find(4), part.facet_tags.find(24)]))]
    bcs.append(_bc(V, 1, part.facet_tags.find(1)))
    multiplier = _multiplier(algorithm, degree)

    def pair():
        tags = part.facet_tags
        return contact_pair(
            contact_surface(V, tags, 20), contact_surface(V, tags, 10), multiplier=multiplier
        )

    with LinearContactProblem(a, L, [pair()], bcs, petsc_options_prefix="uni_tied_") as tied:
        (u_tied,), (lam_tied,) = tied.solve()
        u_tied, lam_tied = u_tied.x.array.copy(), lam_tied.x.array.copy()
    pr = pair()
    with UnilateralContactProblem(
        a, L, [pr], bcs, petsc_options_prefix=f"uni_patch_{algorithm}_", algorithm=algorithm
    ) as problem:
        (u,), (lam,) = problem.solve()
        tol = min(BOUND, 100 * EPS * _unknowns(V, pr))
        if algorithm == "dual-active-set":
            tol = BOUND  # CG to rtol 1e-12: the iteration's error, not round-off
        n = pr.Q.dofmap.index_map.size_local
        assert problem.history.steps[-1].converged
        # Every multiplier active: the count of the last iteration is all of them.
        assert (
            problem.history.steps[-1].iterations[-1].active[0] == pr.Q.dofmap.index_map.size_global
        )
        assert _owned_max(problem.active[0].x.array[:n] - 1.0) == 0.0
        assert _owned_max(lam.x.array[:n] - p) <= tol * p
        assert _owned_max(lam.x.array - lam_tied) <= tol * p
        assert _owned_max(u.x.array - u_tied) <= tol * _owned_max(u_tied)


# SNES VI ends this scene with one P2 multiplier at lambda ~ 0 and zero weighted gap
# counted active (a degenerate point of Eq. 1), not with the empty active set.
@pytest.mark.parametrize("algorithm", [a for a in ALGORITHMS if a != "snes-vi"])
def test_separation(algorithm):
    """A block held by its supports sags away under its weight: no contact, no singularity.

    Lower block [0, 1] x [0, 0.5] on rollers (u_y = 0 at the bottom, u_x = 0 on the
    left), weight rho g = 0.3 downward; the upper block clamped at its top. With
    nu = 0 the column solution u_y(H) = -rho g H^2 / (2 E) is exact (with nu > 0 the
    rollers at the bottom bend the top), and P2 reproduces it.
    """
    part, V = _blocks(degree=2)
    material = Material(E=2.0, nu=0.0)
    a, _, v = material.forms(V)
    rho_g, H = 0.3, 0.5
    cells = part.cell_tags
    dx = ufl.Measure("dx", domain=part.mesh, subdomain_data=cells)
    L = -rho_g * v[1] * dx(1)
    tags = part.facet_tags
    bcs = [_bc(V, 0, tags.find(4)), _bc(V, 1, tags.find(1))]
    bcs += [_bc(V, 0, tags.find(23)), _bc(V, 1, tags.find(23))]
    pair = contact_pair(
        contact_surface(V, tags, 20),
        contact_surface(V, tags, 10),
        multiplier=_multiplier(algorithm, 2),
    )
    with UnilateralContactProblem(
        a, L, [pair], bcs, petsc_options_prefix=f"uni_sep_{algorithm}_", algorithm=algorithm
    ) as problem:
        (u,), (lam,) = problem.solve()
        n = pair.Q.dofmap.index_map.size_local
        assert problem.history.steps[-1].iterations[-1].active == (0,)
        assert _owned_max(lam.x.array) == 0.0
        sag = rho_g * H**2 / (2 * material.E)
        # The lower block's top, the upper block's bottom.
        x = V.tabulate_dof_coordinates()
        owned = V.dofmap.index_map.size_local
        top = np.flatnonzero(np.isclose(x[:owned, 1], H))
        uy = u.x.array.reshape(-1, 2)[:owned, 1]
        lower_top = [d for d in top if d in set(V.dofmap.list[cells.find(1)].ravel())]
        err = np.max(np.abs(uy[lower_top] + sag), initial=0.0)
        assert MPI.COMM_WORLD.allreduce(err, op=MPI.MAX) <= 1e-10 * sag
        # The gaps are positive: the weighted gap of mu_j against a gap of `sag`.
        gaps = problem.gaps[0].x.array[:n]
        assert MPI.COMM_WORLD.allreduce(float(np.min(gaps, initial=np.inf)), op=MPI.MIN) > 0


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_overlap_pushed_apart(algorithm):
    """Blocks meshed with an overlap delta, clamped at the far ends, are pushed apart."""
    delta = 1e-3
    part, V = _blocks(degree=1, shift=-delta)
    a, _, v = MATERIAL.forms(V)
    L = ufl.inner(dolfinx.fem.Constant(part.mesh, np.zeros(2)), v) * ufl.dx
    tags = part.facet_tags
    bcs = [_bc(V, 0, tags.find(4)), _bc(V, 0, tags.find(24)), _bc(V, 1, tags.find(1))]
    bcs.append(_bc(V, 1, tags.find(23)))
    pair = contact_pair(
        contact_surface(V, tags, 20),
        contact_surface(V, tags, 10),
        multiplier=_multiplier(algorithm, 1),
    )
    with UnilateralContactProblem(
        a,
        L,
        [pair],
        bcs,
        petsc_options_prefix=f"uni_ovl_{algorithm}_",
        algorithm=algorithm,
        start="gap",
    ) as problem:
        (_u,), (lam,) = problem.solve()
        E_prime = MATERIAL.E / (1 - MATERIAL.nu**2)
        p = delta / (0.5 / E_prime + 0.5 / E_prime)
        n = pair.Q.dofmap.index_map.size_local
        error = _owned_max(lam.x.array[:n] - p) / p
        if algorithm != "penalty":
            assert error <= 1e-8
        else:
            # The penalty lets the blocks overlap by p / eps: the error is O(1 / kappa).
            assert error <= 0.1
            assert error > 1e-8
        assert problem.history.steps[-1].iterations[-1].active[0] == (
            pair.Q.dofmap.index_map.size_global
        )


def test_no_convergence_raises_with_history():
    """A solve that needs more solves than allowed raises on every rank, with its history."""
    part, V = _blocks(degree=1)
    a, _, v = MATERIAL.forms(V)
    dx = ufl.Measure("dx", domain=part.mesh, subdomain_data=part.cell_tags)
    L = -0.3 * v[1] * dx(1)
    tags = part.facet_tags
    bcs = [_bc(V, 0, tags.find(4)), _bc(V, 1, tags.find(1))]
    bcs += [_bc(V, 0, tags.find(23)), _bc(V, 1, tags.find(23))]
    pair = contact_pair(contact_surface(V, tags, 20), contact_surface(V, tags, 10))
    with UnilateralContactProblem(
        a, L, [pair], bcs, petsc_options_prefix="uni_fail_", max_iterations=1
    ) as problem:
        with pytest.raises(ContactConvergenceError, match="did not converge") as info:
            problem.solve()
    history = info.value.history
    assert not history.steps[0].converged
    assert len(history.steps[0].iterations) == 1
    assert "active [" in str(info.value)


def test_repeated_set_above_the_tolerance_raises_at_once():
    """A tolerance below round-off: the set repeats, and the solve says so at once.

    The same active set builds the same system, so the iteration stops at the first
    repeat instead of solving it again until ``max_iterations``.
    """
    V, tags, a, L, bcs = _weighted_lower_block()  # pressed together: a nonzero round-off
    pair = contact_pair(contact_surface(V, tags, 20), contact_surface(V, tags, 10))
    with UnilateralContactProblem(
        a, L, [pair], bcs, petsc_options_prefix="uni_floor_", tolerance=1e-30
    ) as problem:
        with pytest.raises(ContactConvergenceError, match="the active set repeats") as info:
            problem.solve()
    solves = info.value.history.steps[0].iterations
    assert len(solves) < problem.max_iterations
    assert solves[-1].entered == solves[-1].left == 0 and solves[-1].residual > 1e-30


def _weighted_lower_block():
    """The lower block under its own weight (load factor 1: up, onto the clamped upper)."""
    part, V = _blocks(degree=1)
    a, _, v = MATERIAL.forms(V)
    dx = ufl.Measure("dx", domain=part.mesh, subdomain_data=part.cell_tags)
    L = 0.3 * v[1] * dx(1)
    tags = part.facet_tags
    bcs = [_bc(V, 0, tags.find(4)), _bc(V, 1, tags.find(1))]
    bcs += [_bc(V, 0, tags.find(23)), _bc(V, 1, tags.find(23))]
    return V, tags, a, L, bcs


def test_load_steps_start_from_previous_active_set():
    """Load steps: the same answer as one step; a repeated step needs a single solve.

    The lower block's weight points down at the load factor -1 (it sags away from the
    clamped upper block: no contact) and up at +1 (it presses on the upper block).
    """
    V, tags, a, L, bcs = _weighted_lower_block()
    results = []
    for loads in ([1.0], [-1.0, 0.5, 1.0, 1.0]):
        pair = contact_pair(contact_surface(V, tags, 20), contact_surface(V, tags, 10))
        with UnilateralContactProblem(
            a, L, [pair], bcs, petsc_options_prefix="uni_steps_"
        ) as problem:
            (u,), (lam,) = problem.solve(loads)
            results.append((u.x.array.copy(), lam.x.array.copy(), problem.history))
    (u1, l1, _), (u2, l2, history) = results
    assert [s.load for s in history.steps] == [-1.0, 0.5, 1.0, 1.0]
    assert history.steps[0].iterations[-1].active == (0,)
    assert history.steps[-1].iterations[-1].active[0] > 0
    assert len(history.steps[-1].iterations) == 1
    assert _owned_max(u1 - u2) <= 1e-10 * _owned_max(u1)
    assert _owned_max(l1 - l2) <= 1e-10 * _owned_max(l1)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_monitor_sees_every_recorded_iteration(algorithm):
    """``monitor=`` receives each Iteration as it enters the history, in order."""
    V, tags, a, L, bcs = _weighted_lower_block()
    pair = contact_pair(
        contact_surface(V, tags, 20),
        contact_surface(V, tags, 10),
        multiplier=_multiplier(algorithm, 1),
    )
    seen = []

    def monitor(iteration):
        # Called once the iteration is in the history, with the update time so far.
        assert problem.history.steps[-1].iterations[-1] is iteration
        seen.append((iteration, problem.update_seconds))

    with UnilateralContactProblem(
        a,
        L,
        [pair],
        bcs,
        petsc_options_prefix=f"uni_monitor_{algorithm}_".replace("-", "_"),
        algorithm=algorithm,
        monitor=monitor,
    ) as problem:
        problem.solve([0.5, 1.0])
        recorded = [it for step in problem.history.steps for it in step.iterations]
        assert [it for it, _ in seen] == recorded
        times = [t for _, t in seen]
        assert times == sorted(times)
        assert problem.update_seconds >= times[-1] > 0.0


def test_snes_vi_with_uncovered_multipliers():
    """SNES VI on a contactor partly facing no target agrees with the active-set loop.

    Hertz on two quadratic cylinders: the ends of the contactor arc are beyond the search
    radius of the lower arc, so their multipliers carry no constraint (uncovered, held at
    zero, :math:`c_k = 0`). SNES VI scaled their rows of the saddle point by :math:`-c_k
    = 0`: a singular Jacobian, DIVERGED_LINEAR_SOLVE at its first step. The reference is
    the active-set loop, an independent algorithm for the same complementarity problem:
    the same active set, and the same saddle point solved at the end.
    """
    from paper.hertz.study import HertzCase, hertz_model

    case = HertzCase(
        degree=2, cell="quadrilateral", elements_across=6, a=0.1, R2=2.0, far_size=0.25
    )
    model = hertz_model(case)
    out = {}
    for algorithm in EXACT:
        with UnilateralContactProblem(
            model.a,
            model.L,
            [model.pair()],
            model.bcs,
            petsc_options_prefix=f"uni_uncovered_{algorithm}_",
            algorithm=algorithm,
        ) as problem:
            (u,), (lam,) = problem.solve()
            assert problem.operators[0].uncovered.size > 0  # the premise, on every rank
            out[algorithm] = [f.x.array.copy() for f in (u, lam, problem.active[0])]
    (u0, lam0, active0), (u1, lam1, active1) = out["active-set"], out["snes-vi"]
    assert _owned_max(active1 - active0) == 0.0
    assert 0 < _owned_max(lam0)
    assert _owned_max(lam1 - lam0) <= BOUND * _owned_max(lam0)
    assert _owned_max(u1 - u0) <= BOUND * _owned_max(u0)

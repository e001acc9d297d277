# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Rigid obstacles as targets: meshed rigid surfaces and analytic obstacles.

The numbers asserted come from outside the code: the uniform pressure of the patch test
(the load), the uniaxial plane-strain compression of a block by a moved rigid plane,
:math:`\\lambda = E\\delta / ((1 - \\nu^2) H)`, and the rigid motion's formula.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import (
    Material,
    circle_obstacle,
    contact_pair,
    contact_surface,
    obstacle,
    plane_obstacle,
    rigid_surface,
)
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import ALGORITHMS, UnilateralContactProblem

comm = MPI.COMM_WORLD
P = 2.0  # the pressure on the block's top
H = 0.5  # the block's height
MATERIAL = Material(1.0, 0.3)


def _tags(mesh, marks):
    found = [(dolfinx.mesh.locate_entities_boundary(mesh, 1, where), tag) for tag, where in marks]
    facets = np.concatenate([f for f, _ in found]).astype(np.int32)
    values = np.concatenate([np.full(f.size, t, dtype=np.int32) for f, t in found])
    order = np.argsort(facets)
    return dolfinx.mesh.meshtags(mesh, 1, facets[order], values[order])


def rigid_floor(motion=None, centre=None, cell=dolfinx.mesh.CellType.quadrilateral):
    """A rigid mesh below y = 0, wider than the block, meshed unlike it; tag 1 on top."""
    mesh = dolfinx.mesh.create_rectangle(comm, [[-0.2, -0.3], [1.3, 0.0]], [5, 2], cell)
    tags = _tags(mesh, [(1, lambda x: np.isclose(x[1], 0.0))])
    return rigid_surface(mesh, tags, 1, motion=motion, centre=centre)


def block(degree, target, pressure=P, hold_top=False, hold_left=True, multiplier=None):
    """An elastic block [0, 1] x [0, H] on ``target`` (contactor: its bottom, tag 1)."""
    mesh = dolfinx.mesh.create_rectangle(
        comm, [[0.0, 0.0], [1.0, H]], [7, 4], dolfinx.mesh.CellType.triangle
    )
    tags = _tags(
        mesh,
        [
            (1, lambda x: np.isclose(x[1], 0.0)),
            (2, lambda x: np.isclose(x[1], H)),
            (3, lambda x: np.isclose(x[0], 0.0)),
        ],
    )
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a, _, v = MATERIAL.forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.array([0.0, -pressure])), v) * ds(2)
    bcs = []
    if hold_left:
        left = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, tags.find(3))
        bcs.append(dolfinx.fem.dirichletbc(0.0, left, V.sub(0)))
    if hold_top:
        top = dolfinx.fem.locate_dofs_topological(V.sub(1), 1, tags.find(2))
        bcs.append(dolfinx.fem.dirichletbc(0.0, top, V.sub(1)))
    pair = contact_pair(contact_surface(V, tags, 1), target, multiplier=multiplier)
    return a, L, [pair], bcs


def dual_if(algorithm):
    """P1 dual multipliers for the algorithm that needs them, else the default."""
    return ("Dual", 1) if algorithm == "dual-active-set" else None


def max_relative_error(multiplier, exact):
    """max |lambda - exact| / exact over the owned multipliers of every rank."""
    n = multiplier.function_space.dofmap.index_map.size_local
    local = float(np.max(np.abs(multiplier.x.array[:n] - exact), initial=0.0))
    return comm.allreduce(local, op=MPI.MAX) / exact


def targets():
    return {"mesh": rigid_floor, "plane": lambda: plane_obstacle([0.0, 0.0], [0.0, 1.0])}


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("target", ["mesh", "plane"])
@pytest.mark.parametrize("model", ["tied", "unilateral"])
def test_patch_test_on_rigid_plane(degree, target, model):
    """Uniform pressure through a rigid floor: lambda = p to 1e-10, no target unknowns."""
    a, L, pairs, bcs = block(degree, targets()[target]())
    if model == "tied":
        problem = LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix="rigid_patch_")
        solve = problem.solve
    else:
        problem = UnilateralContactProblem(a, L, pairs, bcs, petsc_options_prefix="rigid_patch_")
        solve = lambda: problem.solve([0.5, 1.0])  # noqa: E731
    with problem:
        _, multipliers = solve()
        assert len(problem.spaces) == 1  # the rigid target carries no unknowns
        assert max_relative_error(multipliers[0], P) < 1e-10


@pytest.mark.parametrize("algorithm", [a for a in ALGORITHMS if a != "active-set"])
def test_every_algorithm_on_rigid_plane(algorithm):
    """The other algorithms: exact for SNES-VI and the augmented Lagrangian.

    The pure penalty method leaves a penetration :math:`\\lambda / c` that differs
    along the surface (the scales :math:`c_k` do): only its total force is the load's.
    """
    a, L, pairs, bcs = block(1, rigid_floor(), multiplier=dual_if(algorithm))
    with UnilateralContactProblem(
        a, L, pairs, bcs, algorithm=algorithm, petsc_options_prefix="rigid_alg_"
    ) as problem:
        _, (lam,) = problem.solve([1.0])
        force = comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form(lam * ufl.dx)), op=MPI.SUM
        )
        assert force == pytest.approx(P * 1.0, rel=1e-10)
        if algorithm != "penalty":
            assert max_relative_error(lam, P) < 1e-10


@pytest.mark.parametrize("form", ["scaled", "callable"])
@pytest.mark.parametrize("algorithm", ["active-set", "condensed-active-set"])
def test_moved_rigid_floor_compresses_block(form, algorithm):
    """The floor moved up by delta under a block held at its top: uniaxial plane strain.

    sigma_xx = 0, u_y(H) = 0, u_y(0) = delta: lambda = E delta / ((1 - nu^2) H), at each
    load step (the motion scaled by the load factor, or a callable of it; the condensed
    active set moves the gaps of its one factorization with it), in one solve of two
    load steps and in two solves.
    """
    delta = 0.01
    motion = ((0.0, delta), 0.0) if form == "scaled" else (lambda t: ((0.0, t * delta), 0.0))
    a, L, pairs, bcs = block(2, rigid_floor(motion), pressure=0.0, hold_top=True)
    E, nu = MATERIAL.E, MATERIAL.nu
    with UnilateralContactProblem(
        a, L, pairs, bcs, petsc_options_prefix="rigid_move_", algorithm=algorithm
    ) as pr:
        for loads in ([0.5], [1.0], [0.5, 1.0]):
            _, (lam,) = pr.solve(loads)
            exact = E * loads[-1] * delta / ((1 - nu**2) * H)
            assert max_relative_error(lam, exact) < 1e-10


def test_motion_interpolated_exactly():
    """A translation and a rotation about a centre, at the target's nodes (the formula)."""
    d, theta, c = np.array([0.1, -0.2]), 0.3, np.array([0.5, -0.1])
    surface = rigid_floor(((d[0], d[1]), theta), centre=c)
    for t in (0.5, 1.0):
        u = surface.displacement(t)
        x = surface.V.tabulate_dof_coordinates()[:, :2]
        cos, sin = np.cos(t * theta), np.sin(t * theta)
        R = np.array([[cos, -sin], [sin, cos]])
        exact = t * d + (x - c) @ (R - np.eye(2)).T
        np.testing.assert_allclose(u.x.array.reshape(-1, 2), exact, rtol=0, atol=1e-14)


def test_body_held_by_rigid_obstacle_only_is_named_when_contact_opens():
    """Pulled off the floor, the block (held only by it) must be named, on every rank."""
    a, L, pairs, bcs = block(1, rigid_floor(), pressure=-P)
    with UnilateralContactProblem(a, L, pairs, bcs, petsc_options_prefix="rigid_open_") as pr:
        with pytest.raises((ValueError, RuntimeError), match="body 0 of space 0"):
            pr.solve([1.0])


def test_block_without_side_support_is_named():
    """Frictionless on a rigid plane, nothing holds the block horizontally: named."""
    a, L, pairs, bcs = block(1, plane_obstacle([0.0, 0.0], [0.0, 1.0]), hold_left=False)
    with LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix="rigid_side_") as pr:
        with pytest.raises(ValueError, match=r"body 0 of space 0.*translation along \(1, 0\)"):
            pr.solve()


@pytest.mark.parametrize(
    "wrong, match",
    [
        (lambda: plane_obstacle([0.0, 0.0], [0.0, -1.0]), "face away"),
        (lambda: plane_obstacle([0.0, 1.0], [0.0, 1.0]), "inside it"),
        (lambda: circle_obstacle([0.5, 0.25], 2.0), "inside it"),
    ],
)
def test_obstacle_on_the_wrong_side(wrong, match):
    a, L, pairs, bcs = block(1, wrong())
    with LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix="rigid_wrong_") as pr:
        with pytest.raises(ValueError, match=f"wrong side of obstacle.*{match}"):
            pr.solve()


def test_obstacle_values_of_wrong_shape():
    bad = obstacle(lambda x: x[1], lambda x: np.ones((3, x.shape[1])), name="bad")
    a, L, pairs, bcs = block(1, bad)
    with LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix="rigid_shape_") as pr:
        with pytest.raises(ValueError, match=r"obstacle bad: distance\(x\) must return .*got"):
            pr.solve()


def test_rigid_contactor_is_refused():
    _, _, pairs, _ = block(1, plane_obstacle([0.0, 0.0], [0.0, 1.0]))
    with pytest.raises(ValueError, match=r"cannot be a contactor.*must be deformable"):
        contact_pair(rigid_floor(), pairs[0].contactor)
    with pytest.raises(ValueError, match="cannot be a contactor"):
        contact_pair(plane_obstacle([0.0, 0.0], [0.0, 1.0]), pairs[0].contactor)


@pytest.mark.parametrize(
    "motion, match",
    [
        (lambda t: ((0.0, 0.0, t), 0.0), "translation of shape"),
        (lambda t: (0.0, 0.0, 0.0), r"must be \(translation, angle\)"),
        (((0.0, np.nan), 0.0), "finite"),
    ],
)
def test_motion_of_wrong_shape(motion, match):
    with pytest.raises(ValueError, match=match):
        rigid_floor(motion)

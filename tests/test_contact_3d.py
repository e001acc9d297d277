# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Three-dimensional contact: the patch test of section 3.2 between non-matching blocks.

Two blocks, [0, 1]^2 x [0, 1/2] and [0, 1]^2 x [1/2, 1], meshed independently (tetrahedra
against hexahedra, 3 against 4 cells across, optionally with the nodes moved at random in
the plane of the contact), a uniform pressure p on the top, symmetry conditions on the
planes x = 0 and y = 0 and u_z = 0 at the bottom. The exact solution is uniaxial stress,
u = (nu p x / E, nu p y / E, -p z / E), with the contact pressure p (Eq. 36): composite
segment-to-segment (Eqs. 40-42 on the triangles of the clipped face overlaps, Fig. 15(b)
in 3D) transmits it to round-off, with P1 and P2 and either block as the contactor.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import (
    Material,
    contact_pair,
    contact_surface,
    plane_obstacle,
    rigid_surface,
)
from dolfinx_contact_s2s.analysis.dense import inf_sup_dense
from dolfinx_contact_s2s.analysis.infsup import InfSupTest, inf_sup
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

COMM = MPI.COMM_WORLD
E, NU, P = 1.0, 0.3, 1.0
CELLS = {"tet": dolfinx.mesh.CellType.tetrahedron, "hex": dolfinx.mesh.CellType.hexahedron}
#: Tags: the bottom and top of each block, its side x = 0 and its side y = 0.
BOTTOM, TOP, SIDE_X, SIDE_Y = 1, 2, 3, 4


def block(z0: float, n: int, cell: str, seed: int | None, layers: int = 2):
    """A block [0, 1]^2 x [z0, z0 + 1/2] of ``n`` x ``n`` x ``layers`` cells, tagged.

    With ``seed``, the nodes move in the plane of the contact and the faces stay flat:
    tetrahedra at random (inside the square, by up to a fifth of a cell), hexahedra by a
    graded map of x and of y, so that their faces stay parallelograms. A bilinear face
    that is not a parallelogram has a rational inverse map, which no Gauss rule on the
    pieces integrates exactly (README, 3D: the patch test then holds to the rule's error).
    """
    mesh = dolfinx.mesh.create_box(
        COMM, [[0, 0, z0], [1, 1, z0 + 0.5]], [n, n, layers], CELLS[cell]
    )
    if seed is not None:
        x = mesh.geometry.x
        X, Y = x[:, 0].copy(), x[:, 1].copy()
        if cell == "hex":
            x[:, 0] += 0.1 * np.sin(np.pi * X) * (1 + 0.3 * seed)
            x[:, 1] += 0.07 * np.sin(2 * np.pi * Y) / (1 + seed)
        else:
            inside = (np.minimum(X, Y) > 1e-12) & (np.maximum(X, Y) < 1 - 1e-12)
            # The same motion of a node on every rank that holds it: a function of position.
            x[inside, 0] += 0.2 / n * np.sin(1e3 * (X + 2 * Y) + seed)[inside]
            x[inside, 1] += 0.2 / n * np.sin(3e2 * Y - 5e2 * X + seed)[inside]
    mesh.topology.create_connectivity(2, 3)
    markers = (
        (BOTTOM, lambda x: np.isclose(x[2], z0)),
        (TOP, lambda x: np.isclose(x[2], z0 + 0.5)),
        (SIDE_X, lambda x: np.isclose(x[0], 0.0)),
        (SIDE_Y, lambda x: np.isclose(x[1], 0.0)),
    )
    found = [(dolfinx.mesh.locate_entities_boundary(mesh, 2, f), tag) for tag, f in markers]
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([np.full(f.size, tag, dtype=np.int32) for f, tag in found])
    order = np.argsort(facets, kind="stable")
    return mesh, dolfinx.mesh.meshtags(mesh, 2, facets[order], values[order])


def scene(
    lower: str,
    upper: str,
    degree: int,
    seed: int | None = None,
    cells: tuple[int, int] = (3, 4),
    layers: int = 2,
):
    """Spaces, forms and boundary conditions of the two blocks (the user's own forms)."""
    spaces, a, L, bcs = [], [], [], []
    for z0, n, cell, loaded in ((0.0, cells[0], lower, False), (0.5, cells[1], upper, True)):
        mesh, tags = block(z0, n, cell, seed, layers)
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
        form, _, v = Material(E=E, nu=NU).forms(V)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
        traction = dolfinx.fem.Constant(mesh, np.array([0.0, 0.0, -P if loaded else 0.0]))
        a.append(form)
        L.append(ufl.inner(traction, v) * ds(TOP))
        fixed = [(0, SIDE_X), (1, SIDE_Y)] + ([] if loaded else [(2, BOTTOM)])
        for component, tag in fixed:
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 2, tags.find(tag))
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(component)))
        spaces.append((V, tags))
    return spaces, a, L, bcs


def exact(x):
    """Uniaxial stress under the pressure P: the displacement."""
    return np.stack([NU * P / E * x[0], NU * P / E * x[1], -P / E * x[2]])


def check_exact(us, pressure):
    """Multipliers P and the displacement of uniaxial stress, to round-off (Eq. 36)."""
    worst_p = np.max(np.abs(pressure.x.array - P), initial=0.0)
    worst_u = 0.0
    for u in us:
        expected = dolfinx.fem.Function(u.function_space)
        expected.interpolate(exact)
        worst_u = max(worst_u, float(np.max(np.abs(u.x.array - expected.x.array), initial=0.0)))
    assert COMM.allreduce(worst_p, op=MPI.MAX) <= 1e-10 * P
    assert COMM.allreduce(worst_u, op=MPI.MAX) <= 1e-10 * P / E


@pytest.mark.parametrize("seed", [None, 1])
@pytest.mark.parametrize("contactor", ["upper", "lower"])
@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cells", [("hex", "tet"), ("tet", "hex"), ("tet", "tet"), ("hex", "hex")])
def test_tied_patch_test(cells, degree, contactor, seed):
    """Composite S2S transmits a uniform pressure exactly between non-matching 3D meshes."""
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, seed)
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    pair = contact_pair(upper, lower) if contactor == "upper" else contact_pair(lower, upper)
    with LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="c3d_") as problem:
        us, (pressure,) = problem.solve()
        check_exact(us, pressure)


@pytest.mark.parametrize(
    "cells, degree", [(("hex", "tet"), 1), (("tet", "hex"), 1), (("tet", "hex"), 2)]
)
def test_unilateral_patch_test(cells, degree):
    """The active-set solve closes every constraint and transmits the pressure exactly."""
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, seed=2)
    pair = contact_pair(contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP))
    with UnilateralContactProblem(a, L, [pair], bcs, petsc_options_prefix="u3d_") as problem:
        us, (pressure,) = problem.solve()
        check_exact(us, pressure)


def test_unilateral_refuses_p2_triangle_multipliers():
    """P2 on triangular faces: vertex functions of zero integral, refused on every rank.

    Measured before the check: the active-set solve returned pressures from -5.2 to 8.7
    for the uniform pressure 1, without an error.
    """
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene("hex", "tet", 2, seed=2)
    pair = contact_pair(contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP))
    with pytest.raises(ValueError, match="integrate to zero"):
        UnilateralContactProblem(a, L, [pair], bcs, petsc_options_prefix="u3d_")
    # The remedy the message names: a P1 multiplier on the P2 faces.
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    linear = contact_pair(upper, lower, multiplier=("Lagrange", 1))
    with UnilateralContactProblem(a, L, [linear], bcs, petsc_options_prefix="u3d_") as problem:
        us, (pressure,) = problem.solve()
        check_exact(us, pressure)
    # Tied contact needs no sign and passes the patch test with the same pair.
    with LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="c3d_") as problem:
        us, (pressure,) = problem.solve()
        check_exact(us, pressure)


def test_what_faces_do_not_have_is_refused():
    """Only composite segment-to-segment against meshed deformable targets, on faces."""
    (V_lo, t_lo), (V_up, t_up) = scene("hex", "tet", 1)[0]
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    for options in (
        {"method": "node-to-segment"},
        {"quadrature": "gauss"},
        {"multiplier": ("DG", 0)},
    ):
        with pytest.raises(NotImplementedError, match="on the faces of 3D meshes"):
            contact_pair(upper, lower, **options)
    with pytest.raises(NotImplementedError, match="2D meshes only"):
        contact_pair(upper, plane_obstacle([0.0, 0.0, 0.5], [0.0, 0.0, 1.0]))
    with pytest.raises(NotImplementedError, match="2D meshes only"):
        rigid_surface(V_lo.mesh, t_lo, TOP)
    with pytest.raises(ValueError, match="axis"):
        contact_pair(upper, lower, axisymmetric=True)


#: Largest |d log beta / d log h| of a stable discretization over the finer levels: the
#: criterion of the 2D tables (paper/infsup.py, STABLE_SLOPE).
STABLE_SLOPE = 0.3


@pytest.mark.parametrize(
    "cells, degree", [(("hex", "tet"), 1), (("tet", "hex"), 1), (("hex", "tet"), 2)]
)
def test_inf_sup_is_bounded(cells, degree):
    """Eq. (27) in 3D: beta*_h of composite S2S stays away from zero as h halves and more.

    Levels of n (upper, contactor) and n + 1 (lower) cells across, n / 2 layers deep, so
    the cells keep their shape; no pressure modes (Eq. 32), MUMPS's Schur complement
    and SLEPc's back-substitutions against the dense eigenproblem of Eq. (30) on the first
    two levels, and the log-log
    slope of beta*_h over the last three levels below the 2D tables' criterion (measured:
    slopes 0.15, 0.03 and 0.19; beta*_h from 0.21 to 0.40).
    """
    levels, betas = (2, 4, 6, 8), []
    for n in levels:
        ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, None, (n + 1, n), n // 2)
        pair = contact_pair(contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP))
        with LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="is3d_") as problem:
            result = inf_sup(problem, 1.0 / n)
            assert result.pressure_modes == 0 and result.beta > 0
            if n <= 4:
                dense = inf_sup_dense(problem, 1.0 / n, full=False)
                assert result.beta == pytest.approx(dense.beta, rel=1e-8)
                slepc = InfSupTest(problem, 1.0 / n, schur=False)  # SLEPc, back-substitutions
                assert slepc.solve().beta == pytest.approx(dense.beta, rel=1e-8)
                slepc.destroy()
        betas.append(result.beta)
    slope = np.polyfit(np.log(1.0 / np.array(levels[1:])), np.log(betas[1:]), 1)[0]
    assert abs(slope) < STABLE_SLOPE, (betas, slope)

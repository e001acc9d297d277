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

import numpy as np
import pytest
import scipy.sparse
from partition_keys import dof_perm, keys, match, matrix_difference, matrix_entries

from dolfinx_contact_s2s import (
    contact_pair,
    contact_pairs,
    contact_surface,
    plane_obstacle,
    rigid_surface,
)
from dolfinx_contact_s2s.analysis.dense import inf_sup_dense
from dolfinx_contact_s2s.analysis.infsup import InfSupTest, inf_sup
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.blocks3d import BOTTOM, COMM, TOP, E, P, errors, scene


def check_exact(us, pressure):
    """Multipliers P and the displacement of uniaxial stress, to round-off (Eq. 36)."""
    worst_p, worst_u = errors(us, pressure)
    assert worst_p <= 1e-10 * P
    assert worst_u <= 1e-10 * P / E


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


@pytest.mark.parametrize("contactor", ["upper", "lower"])
@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cells", [("hex", "hex"), ("tet", "hex")])
def test_warped_faces_patch_test(cells, degree, contactor):
    """Hexahedra moved at random: faces that are not parallelograms, still exact.

    Their inverse maps are rational, so the polynomial degree of the rule misses the
    patch test (measured 5e-7 with Q1); the pair raises the rule until the faces' own
    shape-function integrals are exact to round-off (``contact_rule.face_rule``).
    """
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, seed=3, warp=True)
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    pair = contact_pair(upper, lower) if contactor == "upper" else contact_pair(lower, upper)
    assert pair.rule_degree > 4 * degree  # Above the polynomial degree (Q_k: 2k).
    with LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="w3d_") as problem:
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
    """Composite segment-to-segment and single-pass node-to-segment against meshed
    deformable targets, on faces; tributary node weights but on P2 triangles."""
    (V_lo, t_lo), (V_up, t_up) = scene("hex", "tet", 1)[0]
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    for options in (
        {"method": "node-to-node"},
        {"method": "node-to-segment-gauss"},
        {"method": "intermediate-surface"},
        {"quadrature": "gauss"},
        {"multiplier": ("DG", 0)},
    ):
        with pytest.raises(NotImplementedError, match="on the faces of 3D meshes"):
            contact_pair(upper, lower, **options)
    with pytest.raises(NotImplementedError, match="two-pass"):
        contact_pairs(upper, lower, method="two-pass node-to-segment")
    with pytest.raises(ValueError, match="one multiplier on every contactor node"):
        contact_pair(upper, lower, method="node-to-segment", multiplier=("Lagrange", 2))
    (_, _), (V_p2, t_p2) = scene("hex", "tet", 2)[0]
    with pytest.raises(ValueError, match=r"tributary area .* is zero"):
        contact_pair(
            contact_surface(V_p2, t_p2, BOTTOM), lower, method="node-to-segment", weight="tributary"
        )
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


def _solution(comm, kind, cells, degree):
    """Pressures and active set keyed by the multiplier's coordinates, on ``comm``."""
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(
        *cells, degree, seed=1, comm=comm, tilt=1.5 if kind is UnilateralContactProblem else 0.5
    )
    pair = contact_pair(contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP))
    with kind(a, L, [pair], bcs, petsc_options_prefix="r3d_") as problem:
        _, (pressure,) = problem.solve()
        n = pressure.function_space.dofmap.index_map.size_local
        x = pressure.function_space.tabulate_dof_coordinates()[:n]
        active = problem.active[0].x.array[:n] if kind is UnilateralContactProblem else None
        values = pressure.x.array[:n]
    keys = np.concatenate(comm.allgather(np.round(x, 12)))
    order = np.lexsort(keys.T)
    gathered = np.concatenate(comm.allgather(values))[order]
    flags = None if active is None else np.concatenate(comm.allgather(active))[order]
    return keys[order], gathered, flags


@pytest.mark.parametrize("kind", [LinearContactProblem, UnilateralContactProblem])
@pytest.mark.parametrize("cells, degree", [(("hex", "tet"), 1), (("tet", "hex"), 2)])
def test_ranks_agree(kind, cells, degree):
    """1, 2 and 3 ranks against one: the pressures to 1e-10 and the active sets exactly.

    Under a pressure P (1 - tilt x) on the top (no closed form): tied, and unilateral with
    the contact opening where the load pulls (tilt 1.5).
    """
    if COMM.size == 1:
        pytest.skip("compares a run on several ranks with one on one rank")
    x, pressure, active = _solution(COMM, kind, cells, degree)
    x1, pressure1, active1 = _solution(MPI.COMM_SELF, kind, cells, degree)
    np.testing.assert_array_equal(x, x1)
    np.testing.assert_allclose(pressure, pressure1, rtol=0, atol=1e-10 * np.abs(pressure1).max())
    if active is not None:
        np.testing.assert_array_equal(active, active1)
        assert 0 < np.count_nonzero(active1) < active1.size  # the contact opened in part


def _coupling(comm, cells, degree, method, sizes):
    """B of the pair on ``comm`` (Eq. 40): keys and entries, gathered on every rank.

    Also, on one rank, the number of terms of each entry and the sum of their sizes.
    """
    wide = sizes[1] != (1.0, 1.0)
    seed, across = (None, (4, 6)) if wide else (1, (3, 4))
    ((V_lo, t_lo), (V_up, t_up)), _, _, _ = scene(
        *cells, degree, seed, across, comm=comm, sizes=sizes
    )
    pair = contact_pair(
        contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP), method=method
    )
    op = assemble_coupling(pair)
    out = {"q": keys(pair.Q, None), "uncovered": op.uncovered.copy()}
    for V, B in op.blocks:
        out["lower" if V is V_lo else "upper"] = (keys(V, None), matrix_entries(B))
    op.destroy()
    if comm.size == 1:
        for b in pair.coupling_blocks():
            for body, cols, values in (
                ("upper", b.cols_contactor, b.values_contactor),
                ("lower", b.cols_target, b.values_target),
            ):
                rows = np.broadcast_to(b.rows[:, :, None], values.shape).reshape(-1)
                cols = np.broadcast_to(cols[:, None, :], values.shape).reshape(-1)
                out.setdefault(f"terms {body}", []).append((rows, cols, values.reshape(-1)))
    return out


@pytest.mark.parametrize(
    "cells, degree, method, sizes",
    [
        (("hex", "tet"), 1, "segment-to-segment", ((1.0, 1.0), (1.0, 1.0))),
        (("tet", "hex"), 2, "segment-to-segment", ((1.0, 1.0), (1.0, 1.0))),
        (("tet", "hex"), 1, "segment-to-segment", ((1.0, 1.0), (1.2, 1.2))),
        (("hex", "tet"), 2, "node-to-segment", ((1.0, 1.0), (1.0, 1.0))),
    ],
    ids=["hex-tet-P1", "tet-hex-P2", "tet-hex-P1-overhang", "hex-tet-P2-nts"],
)
def test_same_coupling_on_any_number_of_ranks(cells, degree, method, sizes):
    """1, 2 and 3 ranks against one: the same B, entry by entry, and uncovered rows.

    Rows and columns keyed by the coordinates of the multiplier and displacement nodes
    (and the component), which no partition changes. Each entry is a sum of m terms (the
    pieces of face overlaps, or the nodes, counted below: up to about 90); the partition
    changes the order of the sum and, through the multiplier cells' vertex order, the
    round-off of each term: at most about m eps sum |t| (recursive summation), bounded
    by m_max eps max(sum |t|). Measured on 2 and 3 ranks: up to 4.4 eps max |B| (1e-15
    relative), 1-5% of the bound.
    """
    if COMM.size == 1:
        pytest.skip("compares a run on several ranks with one on one rank")
    world = _coupling(COMM, cells, degree, method, sizes)
    serial = _coupling(MPI.COMM_SELF, cells, degree, method, sizes)
    q = match(world["q"], serial["q"])
    np.testing.assert_array_equal(np.sort(q[world["uncovered"]]), serial["uncovered"])
    eps = np.finfo(np.float64).eps
    for body in ("upper", "lower"):
        columns = dof_perm(match(world[body][0], serial[body][0]), 3)
        difference = matrix_difference(world[body][1], serial[body][1], q, columns)
        rows, cols, values = (np.concatenate(a) for a in zip(*serial[f"terms {body}"], strict=True))
        shape = (q.size, columns.size)
        count = scipy.sparse.csr_matrix((np.ones(values.size), (rows, cols)), shape=shape)
        size = scipy.sparse.csr_matrix((np.abs(values), (rows, cols)), shape=shape)
        bound = count.max() * eps * size.max()
        assert difference.max() <= bound, (body, difference.max(), bound)

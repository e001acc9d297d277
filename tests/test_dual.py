# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Dual (biorthogonal) P1 and P2 multipliers: ``multiplier=("Dual", k)``.

On a straight edge the dual basis satisfies :math:`\int_e \psi_i \mu_j = \delta_{ij}
\int_e \mu_j` (Wohlmuth; P1: :math:`\psi_i = 2\mu_i - \mu_j`), so the contactor's
block of :math:`\mathbf B` is diagonal in the nodes wherever the target covers the
contactor, with the integrals of the Lagrange basis on the diagonal (P1: half the
lengths of the edges at a vertex; P2: a sixth of them at a vertex, two thirds of the
edge at its midpoint). References from outside the code:
the patch test's constant pressure, the tributary lengths of the mesh, the paper's
stability criterion on the model of Fig. 2, and Hertz.
"""

from mpi4py import MPI

import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.la import gather_dense
from paper import scenes
from paper.blocks import block_problem, block_spaces, block_surfaces

comm = MPI.COMM_WORLD
DUAL = ("Dual", 1)


def _max(values):
    return comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def _global_coordinates(V):
    """Coordinates of every (blocked) dof of ``V`` by global index, on every rank."""
    imap = V.dofmap.index_map
    n = imap.size_local
    x = V.tabulate_dof_coordinates()[:n, :2]
    index = imap.local_to_global(np.arange(n, dtype=np.int32))
    out = np.zeros((imap.size_global, 2))
    for i, xi in comm.allgather((index, x)):
        out[i] = xi
    return out


def _patch_problem(elements, cell, p, prefix, degree=1):
    """Non-matching blocks, the upper one pressed by p and held by contact vertically."""
    scene = scenes.patch_test(comm, elements, cell=cell)
    return block_problem(
        scene,
        (degree, degree),
        "upper",
        support="rollers",
        pressure=p,
        petsc_options_prefix=prefix,
        multiplier=("Dual", degree),
    )


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cell", ["quadrilateral", "triangle"])
@pytest.mark.parametrize("elements", [(3, 5), (7, 4), (6, 11)])
def test_patch_test(cell, elements, degree):
    """Non-matching blocks under a uniform pressure: every dual multiplier equals p."""
    p = 0.75
    with _patch_problem(elements, cell, p, "dual_patch_", degree) as problem:
        _, (lam,) = problem.solve()
        n = lam.function_space.dofmap.index_map.size_local
        assert _max(lam.x.array[:n] - p) <= 1e-10 * p


def _integral(x, k, degree):
    r""":math:`\\int \\mu_k` on the sorted nodes ``x`` of a straight line (P1 or P2)."""
    step = degree  # the edges' ends: every node (P1), every other node (P2)
    if degree == 2 and k % 2 == 1:
        return 2.0 / 3.0 * (x[k + 1] - x[k - 1])
    left = x[k] - x[k - step] if k >= step else 0.0
    right = x[k + step] - x[k] if k + step < x.size else 0.0
    return (left + right) / (2.0 if degree == 1 else 6.0)


@pytest.mark.parametrize("degree", [1, 2])
def test_contactor_block_is_diagonal(degree):
    """Each dual multiplier row of B touches its own node only: :math:`\\int \\mu_k`.

    Both blocks of :func:`paper.scenes.patch_test` span the same width, so the target
    covers the whole contactor: row k of the contactor's block is nonzero only at the
    vertical displacement of node k, where it is :math:`\\pm\\int \\mu_k` (closed form on
    the nodes, :func:`_integral`), and the Lagrange multipliers' is not diagonal.
    """
    scene = scenes.patch_test(comm, (5, 7), cell="quadrilateral")
    spaces = block_spaces(scene, (degree, degree))
    surfaces = block_surfaces(scene, spaces)
    for multiplier in (("Dual", degree), ("Lagrange", degree)):
        pair = contact_pair(surfaces["upper"], surfaces["lower"], multiplier=multiplier)
        op = assemble_coupling(pair)
        B = gather_dense(op.block(spaces["upper"]))
        op.destroy()
        rows = _global_coordinates(pair.Q)[:, 0]
        cols = _global_coordinates(spaces["upper"])
        off = diagonal = 0.0
        for k, xk in enumerate(rows):
            node = np.isclose(cols[:, 0], xk) & np.isclose(cols[:, 1], cols[:, 1].min())
            own = np.flatnonzero(np.repeat(node, 2) & np.tile([False, True], node.size))
            others = np.setdiff1d(np.flatnonzero(B[k]), own)
            off = max(off, float(np.max(np.abs(B[k, others]), initial=0.0)))
            diagonal = max(diagonal, abs(B[k, own[0]]))
            if multiplier[0] == "Dual":
                x = np.sort(rows)
                expected = _integral(x, int(np.searchsorted(x, xk)), degree)
                assert abs(B[k, own[0]]) == pytest.approx(expected, rel=1e-12)
        if multiplier[0] == "Dual":
            assert off <= 1e-14
        else:
            assert off > 0.1 * diagonal  # the reference: mu_i mu_j couples neighbours


@pytest.mark.parametrize("degree", [1, 2])
def test_inf_sup_stable(degree):
    """The paper's stability test (Eq. 29, model of Fig. 2) passes: beta bounded in h."""
    from paper.infsup import FIT_FROM, InfSupCase, run_case, verdicts

    levels = (FIT_FROM, FIT_FROM + 1, 2 * FIT_FROM)
    for family in ("10n/7n", "5n/(2n+1)"):
        case = InfSupCase(multiplier=("Dual", degree), degree=degree, family=family)
        rec = run_case(comm, case, levels, full=False, dense_limit=0)
        verdict = verdicts(rec["levels"])
        assert verdict["solvable"] and verdict["stable"], (family, verdict)
        betas = [level["beta"] for level in rec["levels"]]
        assert min(betas) > 0.5 * max(betas) > 0


def test_hertz():
    """Hertz (a/R = 5%), P1 at 20 elements across: the half-width and peak within 0.7%
    and 0.5% (the tolerances of the Lagrange multipliers' study), and the L2 pressure
    error falls from 10 to 20 across."""
    from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
    from paper.hertz.exact import measure
    from paper.hertz.study import HertzCase, hertz_model

    errors = []
    for n in (10, 20):
        case = HertzCase(elements_across=n)
        model = hertz_model(case)
        tags, ft = model.scene.tags, model.scene.facet_tags
        pair = contact_pair(
            contact_surface(model.V, ft, tags["contactor"]),
            contact_surface(model.V, ft, tags["target"]),
            multiplier=DUAL,
        )
        with UnilateralContactProblem(
            model.a, model.L, [pair], model.bcs, petsc_options_prefix="dual_hertz_"
        ) as problem:
            problem.solve()
            m = measure(problem.multipliers[0], case.exact)
        errors.append(m.pressure_l2_error)
    assert abs(m.a / case.exact.a - 1) < 0.007
    assert abs(m.p0 / case.exact.p0 - 1) < 0.005
    assert errors[1] < errors[0]


def test_unilateral_condensed_matches_the_saddle_point():
    """``algorithm="dual-active-set"`` (CG + GAMG on each active set's condensed system):
    the saddle-point loop's active sets, iterations and pressure (Hertz, 10 across)."""
    from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
    from paper.hertz.study import HertzCase, hertz_model

    model = hertz_model(HertzCase(elements_across=10))
    tags, ft = model.scene.tags, model.scene.facet_tags
    pair = contact_pair(
        contact_surface(model.V, ft, tags["contactor"]),
        contact_surface(model.V, ft, tags["target"]),
        multiplier=DUAL,
    )
    results = []
    for algorithm in ("active-set", "dual-active-set"):
        with UnilateralContactProblem(
            model.a,
            model.L,
            [pair],
            model.bcs,
            algorithm=algorithm,
            petsc_options_prefix=f"dual_{algorithm[0]}_",
        ) as problem:
            problem.solve()
            lam = problem.multipliers[0].x.array.copy()
            active = problem.active[0].x.array.copy()
            results.append((lam, active, len(problem.history.steps[0].iterations)))
    (lam, active, its), (lam_c, active_c, its_c) = results
    assert np.array_equal(active, active_c) and its == its_c > 1
    assert 0 < comm.allreduce(int(active.sum())) < comm.allreduce(active.size)
    assert _max(lam_c - lam) <= 1e-8 * _max(lam)


@pytest.mark.parametrize(
    "options, match",
    [
        ({"multiplier": ("Dual", 2)}, "dual multipliers are implemented as"),
        ({"multiplier": DUAL, "method": "node-to-segment"}, "dual multipliers are implemented as"),
        ({"multiplier": DUAL, "quadrature": "gauss"}, "dual multipliers are implemented as"),
    ],
)
def test_unsupported(options, match):
    """Dual multipliers other than P1 composite segment-to-segment: a clear error."""
    scene = scenes.patch_test(comm, (3, 4), cell="triangle")
    surfaces = block_surfaces(scene, block_spaces(scene, (1, 1)))
    with pytest.raises(ValueError, match=match):
        contact_pair(surfaces["upper"], surfaces["lower"], **options)


def test_curved_contactor_refused():
    """P2 geometry (curved facets): the constant biorthogonal combination does not hold."""
    scene = scenes.patch_test(comm, (3, 4), cell="triangle", geometry_degree=2)
    spaces = block_spaces(scene, (2, 2))
    surfaces = block_surfaces(scene, spaces)
    with pytest.raises(ValueError, match="straight contactor facets"):
        contact_pair(surfaces["upper"], surfaces["lower"], multiplier=("Dual", 2))


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cell", ["quadrilateral", "triangle"])
def test_condensed_solve_matches_the_saddle_point(cell, degree):
    """CG + GAMG on T^T K T: the saddle point's u and lambda, and the patch test's p.

    The reference is the direct solve of Eq. (18) with the same dual multipliers; the
    condensed solve eliminates the multipliers and the contactor's normal displacements
    (the upper block is held vertically by contact alone).
    """
    from dolfinx_contact_s2s.condensation import DualCondensation

    p = 0.75
    with _patch_problem((12, 17), cell, p, "dual_cond_", degree) as problem:
        problem.solve()
        ref_u = [f.x.array.copy() for f in problem.u]
        ref_lam = problem.multipliers[0].x.array.copy()
        condensation = DualCondensation(problem, petsc_options_prefix="dual_cg_")
        try:
            condensation.solve()  # checks the saddle point's residual itself
            assert 0 < condensation.iterations < 60
            assert condensation.ksp.getType() == "cg"
        finally:
            condensation.destroy()
        for f, r in zip(problem.u, ref_u, strict=True):
            assert _max(f.x.array - r) <= 1e-9 * _max(r)
        lam = problem.multipliers[0].x.array
        assert _max(lam - ref_lam) <= 1e-9 * p
        n = problem.multipliers[0].function_space.dofmap.index_map.size_local
        assert _max(lam[:n] - p) <= 1e-9 * p


def test_condensation_refuses_what_it_cannot_eliminate():
    """Lagrange multipliers, or a target covering a contactor facet in part: clear errors.

    In the overhang scene the target's end cuts a contactor facet: the dual basis is
    biorthogonal over whole facets only, so that facet's rows touch each other's node.
    """
    from test_overhang_p2 import overhang_problem

    from dolfinx_contact_s2s.condensation import DualCondensation

    scene = scenes.patch_test(comm, (3, 4), cell="triangle")
    with block_problem(
        scene, (1, 1), "upper", support="rollers", pressure=1.0, petsc_options_prefix="dual_no_"
    ) as problem:
        with pytest.raises(ValueError, match=r"multiplier=\('Dual', k\) on every pair"):
            DualCondensation(problem, petsc_options_prefix="dual_no_cg_")

    with overhang_problem(8, multiplier=DUAL) as problem:
        message = None
        try:
            DualCondensation(problem, petsc_options_prefix="dual_over_cg_")
        except ValueError as error:
            message = str(error)
    messages = comm.allgather(message)
    assert all(m is not None and "block of B diagonal" in m for m in messages), messages


def _blocks_3d(kinds, degree, **options):
    """The 3D patch-test blocks of :mod:`paper.blocks3d`, the upper one the contactor."""
    from dolfinx_contact_s2s.problem import LinearContactProblem
    from paper.blocks3d import BOTTOM, TOP, scene

    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*kinds, degree, **options)
    pair = contact_pair(
        contact_surface(V_up, t_up, BOTTOM),
        contact_surface(V_lo, t_lo, TOP),
        multiplier=("Dual", degree),
    )
    return LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="dual3d_")


@pytest.mark.parametrize(
    "cells, degree",
    [(("hex", "tet"), 1), (("tet", "tet"), 1), (("tet", "hex"), 1), (("tet", "hex"), 2)],
)
def test_patch_test_3d(cells, degree):
    """Triangle and (rectangular) quadrilateral faces, P1 and Q2: the uniform pressure and
    uniaxial stress to round-off, by the saddle point and by CG + GAMG on the condensed
    system (which checks that the contactor's block of B is diagonal)."""
    from dolfinx_contact_s2s.condensation import DualCondensation
    from paper.blocks3d import E, P, errors

    with _blocks_3d(cells, degree, seed=1) as problem:
        for solve in ("saddle point", "condensed"):
            if solve == "saddle point":
                problem.solve()
            else:
                condensation = DualCondensation(problem, petsc_options_prefix="dual3d_cg_")
                try:
                    condensation.solve()
                    assert 0 < condensation.iterations < 100
                finally:
                    condensation.destroy()
            worst_p, worst_u = errors(problem.u, problem.multipliers[0])
            assert worst_p <= 1e-10 * P and worst_u <= 1e-10 * P / E, solve


@pytest.mark.parametrize(
    "cells, degree, options, match",
    [
        (("hex", "tet"), 2, {}, "zero integral"),
        (("hex", "hex"), 1, {"seed": 3, "warp": True}, "not a parallelogram"),
    ],
    ids=["P2-triangles", "warped-quadrilaterals"],
)
def test_refused_on_faces(cells, degree, options, match):
    """P2 triangles (vertex functions of zero integral: no dual partner) and faces that
    are not parallelograms (no constant combination): a clear error on every rank."""
    with pytest.raises(ValueError, match=match):
        _blocks_3d(cells, degree, **options)


@pytest.mark.parametrize("cells", [("hex", "tet"), ("tet", "hex")])
def test_inf_sup_stable_3d(cells):
    """Eq. (27) in 3D with dual P1 multipliers on triangle and square faces: beta*_h
    bounded on four levels (the log-log slope below the 2D tables' criterion), as the
    Lagrange multipliers' (``tests/test_contact_3d.py``)."""
    from dolfinx_contact_s2s.analysis.infsup import inf_sup
    from paper.infsup import STABLE_SLOPE

    levels, betas = (2, 4, 6, 8), []
    for n in levels:
        with _blocks_3d(cells, 1, cells=(n + 1, n), layers=n // 2) as problem:
            result = inf_sup(problem, 1.0 / n)
            assert result.pressure_modes == 0 and result.beta > 0
            betas.append(result.beta)
    slope = np.polyfit(np.log(1.0 / np.array(levels[1:])), np.log(betas[1:]), 1)[0]
    assert abs(slope) < STABLE_SLOPE, (betas, slope)


@pytest.mark.parametrize("cells, degree", [(("hex", "tet"), 1), (("tet", "hex"), 2)])
def test_unilateral_patch_test_3d(cells, degree):
    """``algorithm="dual-active-set"`` in 3D: every constraint closes and the pressure and
    uniaxial stress are transmitted to CG's accuracy (rtol 1e-12)."""
    from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
    from paper.blocks3d import BOTTOM, TOP, E, P, errors, scene

    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, seed=2)
    pair = contact_pair(
        contact_surface(V_up, t_up, BOTTOM),
        contact_surface(V_lo, t_lo, TOP),
        multiplier=("Dual", degree),
    )
    with UnilateralContactProblem(
        a, L, [pair], bcs, petsc_options_prefix="dual3d_u_", algorithm="dual-active-set"
    ) as problem:
        us, (pressure,) = problem.solve()
        worst_p, worst_u = errors(us, pressure)
        assert worst_p <= 1e-10 * P and worst_u <= 1e-10 * P / E
        assert problem.history.steps[-1].converged

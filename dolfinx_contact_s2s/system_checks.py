# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The checks of a contact system (Eq. 18), at set-up and after every solve.

At set-up: consistent forms and Dirichlet conditions, finite mesh coordinates and finite
:math:`\mathbf K` and :math:`\mathbf F`, pairs on the problem's spaces with one pair per
contactor, the support of every body (Eq. 33) and the rank of the constraints (Eq. 35).
After a solve: the relative residual, else the normwise backward error
(:func:`check_solve`). Each raises on every rank with the cause named. Package-internal:
used by :class:`~dolfinx_contact_s2s.system.ContactSystem`.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import logging
import typing
from collections.abc import Callable, Sequence

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s import checks
from dolfinx_contact_s2s.assemble import CouplingOperator
from dolfinx_contact_s2s.checks.advice import unsupported_error
from dolfinx_contact_s2s.la import backward_error, is_symmetric
from dolfinx_contact_s2s.options import solver_failure
from dolfinx_contact_s2s.pair import ContactPair

__all__ = [
    "BACKWARD_TOLERANCE",
    "all_symmetric",
    "backward_error",
    "bcs_by_space",
    "check_coordinates",
    "check_finite",
    "check_forms",
    "check_pairs",
    "check_redundancy",
    "check_ring_weights",
    "check_solve",
    "check_support",
    "relative_residual",
]

# Under the name of the problem module, where these messages were always logged.
logger = logging.getLogger("dolfinx_contact_s2s.problem")

#: Largest normwise backward error (:func:`backward_error`) that trusts a solve whose
#: relative residual is above ``residual_tolerance``: 256 machine epsilons, the round-off
#: of a backward-stable factorization (MUMPS at a Young's modulus ratio of :math:`10^6`:
#: 0.5; a Jacobi sweep taken for a solve: 0.15).
BACKWARD_TOLERANCE = 256 * float(np.finfo(np.float64).eps)

SpaceIndex = Callable[[dolfinx.fem.FunctionSpace], int]


def _dof_coordinates(Q: dolfinx.fem.FunctionSpace) -> npt.NDArray[np.floating]:
    """Coordinates of every global dof of a scalar space, on every process."""
    imap = Q.dofmap.index_map
    x = Q.tabulate_dof_coordinates()[: imap.size_local]
    out = np.zeros((imap.size_global, 3))
    for start, xs in Q.mesh.comm.allgather((imap.local_range[0], x)):
        out[start : start + xs.shape[0]] = xs
    return out


def check_forms(a: list[ufl.Form], L: list[ufl.Form], kind: str) -> list[dolfinx.fem.FunctionSpace]:
    """The displacement space of each pair of forms; raise for inconsistent forms or kind."""
    if len(a) != len(L) or not a:
        raise ValueError("give one bilinear and one linear form per displacement space")
    if kind not in ("aij", "nest"):
        raise ValueError(f"kind must be 'aij' or 'nest', not {kind!r}")
    spaces: list[dolfinx.fem.FunctionSpace] = []
    for ai, Li in zip(a, L, strict=True):
        test, trial = (arg.ufl_function_space() for arg in ai.arguments())
        if test is not trial or Li.arguments()[0].ufl_function_space() is not test:
            raise ValueError("each a and L must share one displacement space")
        if any(test is V for V in spaces):
            raise ValueError("each displacement space may carry only one form a")
        spaces.append(test)
    return spaces


def _contains(V: dolfinx.fem.FunctionSpace, bc: dolfinx.fem.DirichletBC) -> bool:
    # bc.function_space is a C++ space in some DOLFINx versions, a Python one in others.
    W = bc.function_space
    return V._cpp_object.contains(getattr(W, "_cpp_object", W))


def bcs_by_space(
    spaces: Sequence[dolfinx.fem.FunctionSpace], bcs: Sequence[dolfinx.fem.DirichletBC]
) -> list[list[dolfinx.fem.DirichletBC]]:
    """The Dirichlet conditions of each space; raise if one is on none of them."""
    out = [[bc for bc in bcs if _contains(V, bc)] for V in spaces]
    if sum(len(b) for b in out) != len(bcs):
        raise ValueError("a Dirichlet condition is on none of the problem's spaces")
    return out


def check_coordinates(spaces: Sequence[dolfinx.fem.FunctionSpace]) -> None:
    """Raise on every rank if a mesh has a node with NaN or infinite coordinates."""
    for i, V in enumerate(spaces):
        geometry = V.mesh.geometry
        owned = geometry.x[: geometry.index_map().size_local]
        local = int(np.count_nonzero(~np.all(np.isfinite(owned), axis=1)))
        count = V.mesh.comm.allreduce(local, op=MPI.SUM)
        if count:
            raise ValueError(
                f"the mesh of space {i} has {count} node(s) with NaN or infinite "
                "coordinates; check the mesh (mesh.geometry.x) and how it was built or moved"
            )


def check_pairs(pairs: Sequence[ContactPair], space_index: SpaceIndex) -> None:
    """Raise if a surface is on no space of the problem, or two pairs share a contactor.

    Rigid targets (:mod:`~dolfinx_contact_s2s.obstacles`) carry no unknowns: exempt.
    """
    seen: dict[tuple[int, int], int] = {}
    for j, pair in enumerate(pairs):
        for surface in (pair.contactor, *pair.targets):
            if not surface.rigid:
                space_index(surface.V)
        key = (id(pair.contactor.V.mesh), pair.contactor.tag)
        if key in seen:
            raise ValueError(
                f"pairs {seen[key]} and {j} share the contactor surface (tag "
                f"{pair.contactor.tag}): a contactor carries one multiplier field, so give "
                "all its targets to one pair, contact_pair(contactor, [target_a, target_b])"
            )
        seen[key] = j
    checks.check_cover(pairs)


def all_symmetric(stiffness: Sequence[PETSc.Mat]) -> bool:
    r"""Whether every assembled :math:`\mathbf K` is symmetric (collective); logs which not."""
    flags = [is_symmetric(K) for K in stiffness]
    if not all(flags):
        spaces = ", ".join(str(i) for i, f in enumerate(flags) if not f)
        logger.info(
            "K of space(s) %s is not symmetric: the saddle point is factorized by LU, not LDL^T",
            spaces,
        )
    return all(flags)


def check_finite(stiffness: Sequence[PETSc.Mat], loads: Sequence[PETSc.Vec]) -> None:
    r"""Raise on every rank if some :math:`\mathbf K` or :math:`\mathbf F` is not finite.

    A NaN or infinite material value, load or coefficient of the user's forms would
    otherwise reach the factorization, which fails on some ranks only, or not at all.
    """
    for i, (K, F) in enumerate(zip(stiffness, loads, strict=True)):
        # Norms are collective and the same on every rank.
        for name, norm, form in (
            ("stiffness matrix K", K.norm(PETSc.NormType.FROBENIUS), "a"),
            ("load vector F", F.norm(), "L"),
        ):
            if not np.isfinite(norm):
                raise ValueError(
                    f"the {name} of space {i} has NaN or infinite entries: check the "
                    f"material parameters, coefficients and constants of the form "
                    f"{form}[{i}] (and the Dirichlet values)"
                )


def _constraints(
    operators: Sequence[CouplingOperator], space_index: SpaceIndex
) -> list[list[tuple[int, PETSc.Mat]]]:
    return [[(space_index(V), B) for V, B in op.blocks] for op in operators]


def check_support(
    spaces: Sequence[dolfinx.fem.FunctionSpace],
    stiffness: Sequence[PETSc.Mat],
    masks: Sequence[PETSc.Vec],
    operators: Sequence[CouplingOperator],
    space_index: SpaceIndex,
    labels: Sequence[typing.Any],
) -> checks.SupportGram:
    r"""Raise if a rigid motion meets no support (Eq. 33); else the support's Gram data.

    Returns:
        The support data, kept: a unilateral iteration checks its active sets against it
        (without :math:`\mathbf K`).
    """
    check_ring_weights(spaces, stiffness, masks, operators, space_index)
    constraints = _constraints(operators, space_index)
    support = checks.support_gram(
        list(spaces), list(stiffness), list(masks), constraints, labels=list(labels)
    )
    motions = support.motions([op.inactive for op in operators])
    if motions:
        raise unsupported_error(motions, support)
    return support


def check_ring_weights(
    spaces: Sequence[dolfinx.fem.FunctionSpace],
    stiffness: Sequence[PETSc.Mat],
    masks: Sequence[PETSc.Vec],
    operators: Sequence[CouplingOperator],
    space_index: SpaceIndex,
) -> None:
    r"""Raise if a pair's ``axisymmetric`` contradicts the forms of its bodies.

    Read from :math:`\mathbf K` (:func:`~dolfinx_contact_s2s.checks.ring.translation_residuals`):
    axisymmetric forms store energy in a radial translation only, plane forms in none.
    Forms that store energy in both (an elastic foundation) are not judged.
    """
    tol = checks.RING_TOLERANCE
    verdicts: dict[int, str | None] = {}
    for op in operators:
        pair = op.pair
        for surface in (pair.contactor, *(t for t in pair.targets if not t.rigid)):
            i = space_index(surface.V)
            if i not in verdicts:
                bs = spaces[i].dofmap.index_map_bs
                r = checks.translation_residuals(stiffness[i], masks[i], bs) if bs == 2 else None
                if r is None or r[1] > tol:
                    verdicts[i] = None
                elif r[0] > 100 * tol:
                    verdicts[i] = "axisymmetric"
                else:
                    verdicts[i] = "plane" if r[0] <= tol else None
            if verdicts[i] is None or (verdicts[i] == "axisymmetric") == pair.axisymmetric:
                continue
            stores = "stores" if verdicts[i] == "axisymmetric" else "stores no"
            plane = "axisymmetric" if pair.axisymmetric else "strain"
            raise ValueError(
                f"contact surface {surface.tag} is on a body whose forms are {verdicts[i]} "
                f"(a radial translation {stores} energy), but its pair has "
                f"axisymmetric={pair.axisymmetric}: the multiplier would be the pressure "
                "times 2 pi r, or divided by it. Make the pair with contact_pair(..., "
                f"axisymmetric={not pair.axisymmetric}), or the forms with "
                f"Material(plane={plane!r})"
            )


def check_redundancy(
    pairs: Sequence[ContactPair],
    operators: Sequence[CouplingOperator],
    masks: list[PETSc.Vec],
    space_index: SpaceIndex,
) -> None:
    """Raise if the constraints of the pairs are redundant (Eq. 35), naming the pairs."""
    constraints = _constraints(operators, space_index)
    inactive = [op.inactive for op in operators]
    if not constraints:
        return

    def redundancy(which: list[int]) -> checks.Redundancy:
        return checks.joint_redundant_constraints(
            [constraints[j] for j in which], masks, [inactive[j] for j in which]
        )

    report = redundancy(list(range(len(constraints))))
    if report.redundant == 0:
        return
    # Name the culprit: a pair alone, else two pairs that share a space.
    groups = [[j] for j in range(len(constraints))] if len(constraints) > 1 else []
    groups += [
        [i, j]
        for i in range(len(constraints))
        for j in range(i + 1, len(constraints))
        if {s for s, _ in constraints[i]} & {s for s, _ in constraints[j]}
    ]
    for which in groups:
        found = redundancy(which)
        if found.redundant > 0:
            raise _redundancy_error(pairs, which, found, constraints, masks, inactive)
    raise _redundancy_error(
        pairs, list(range(len(constraints))), report, constraints, masks, inactive
    )


def _redundancy_error(
    pairs: Sequence[ContactPair],
    which: list[int],
    report: checks.Redundancy,
    constraints: list[list[tuple[int, PETSc.Mat]]],
    masks: list[PETSc.Vec],
    inactive: list[npt.NDArray[np.int64]],
) -> ValueError:
    """The error for redundant constraints of the pairs ``which`` (Eq. 35)."""
    named = ""
    if report.active <= 2000:
        rows = checks.joint_redundant_multipliers(
            [constraints[j] for j in which], masks, [inactive[j] for j in which]
        )
        x = [_dof_coordinates(pairs[j].Q) for j in which]
        label = (lambda k: f"pair {which[k]} ") if len(which) > 1 else (lambda k: "")
        named = (
            " Dependent multipliers, at: "
            + "; ".join(
                ", ".join(f"{label(k)}({x[k][r, 0]:.4g}, {x[k][r, 1]:.4g})" for k, r in group[:4])
                for group in rows[:5]
            )
            + "."
        )
    names = " and ".join(
        f"pair {j} ({pairs[j].method}, contactor tag {pairs[j].contactor.tag})" for j in which
    )
    together = (
        " together, though each alone has full row rank (two passes constrain the same "
        "motion twice)"
        if len(which) > 1
        else ""
    )
    return ValueError(
        f"{names} {'have' if len(which) > 1 else 'has'} {report.redundant} redundant "
        f"constraint(s) of {report.active} ({report.zero} act only on Dirichlet "
        f"dofs){together}: B has no full row rank (Eq. 35), so the multipliers are not "
        f"determined.{named} Choose a stable discretization (segment-to-segment with a "
        "continuous multiplier, section 5)."
    )


def relative_residual(A: PETSc.Mat, b: PETSc.Vec, x: PETSc.Vec) -> float:
    r"""Relative residual :math:`\|\mathbf b - \mathbf A \mathbf x\|_2 / \|\mathbf b\|_2`."""
    r = b.duplicate()
    A.mult(x, r)
    r.aypx(-1.0, b)
    rnorm, bnorm = r.norm(), b.norm()
    r.destroy()
    return rnorm / bnorm if bnorm > 0 else rnorm


def check_solve(
    A: PETSc.Mat,
    b: PETSc.Vec,
    x: PETSc.Vec,
    residual_tolerance: float,
    solver: PETSc.KSP,
    prefix: str,
) -> None:
    r"""Raise unless the solve is trusted: a small relative residual, else backward error.

    The relative residual :math:`\|\mathbf r\| / \|\mathbf b\|` alone fails a
    backward-stable direct solve whenever :math:`\|\mathbf b\| \ll \|\mathbf
    A\|\|\mathbf x\|`: with a Young's modulus ratio of :math:`10^6` between the
    README's bodies, MUMPS leaves :math:`\|\mathbf r\|/\|\mathbf b\| = 1.4 \cdot
    10^{-8}` (P2) while the normwise backward error :func:`backward_error` is 0.5
    machine epsilons. Such a solution is the exact one of a system within round-off of
    Eq. (18), and its accuracy is the conditioning's
    (:func:`~dolfinx_contact_s2s.analysis.roundoff.round_off_bound`). A solve is therefore
    trusted when either measure is small. A wrong factorization (:math:`LDL^T` of a
    nonsymmetric matrix) or a preconditioner sweep taken for a solve leave a backward
    error many orders above :data:`BACKWARD_TOLERANCE` and still raise; singular
    models are caught before the solve (Eqs. 33 and 35). The componentwise
    (Oettli-Prager) backward error was not chosen: it reached 1000 machine epsilons
    on good solves at a contrast of :math:`10^{-6}` (rows of tiny
    :math:`|\mathbf A||\mathbf x|`), too close to a usable tolerance.

    Args:
        A: The matrix.
        b: The right-hand side.
        x: The solution.
        residual_tolerance: Largest relative residual trusted without the backward error.
        solver: The solver, for the failure text.
        prefix: Its options prefix, for the failure text.
    """
    residual = relative_residual(A, b, x)
    if residual <= residual_tolerance:
        return
    backward = backward_error(A, b, x)
    if backward <= BACKWARD_TOLERANCE:
        logger.info(
            "relative residual %.2e > %.0e, but backward error %.2e <= %.2e: trusted",
            residual,
            residual_tolerance,
            backward,
            BACKWARD_TOLERANCE,
        )
        return
    raise RuntimeError(
        f"the contact solve cannot be trusted: relative residual {residual:.2e} > "
        f"{residual_tolerance:.0e} and normwise backward error {backward:.2e} > "
        f"{BACKWARD_TOLERANCE:.1e}. The saddle-point matrix is (nearly) singular "
        "or too ill-conditioned for this solver (check the supports, the element "
        "quality and nu close to 1/2), or an iterative solver stopped early "
        f"({solver_failure(solver, prefix)})."
    )

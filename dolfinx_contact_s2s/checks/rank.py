# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Redundant constraints (Eqs. 34-35): the row rank of B, exactly, from an inertia."""

from __future__ import annotations

import typing
from collections.abc import Sequence
from dataclasses import dataclass

from petsc4py import PETSc

import numpy as np
import numpy.typing as npt
import scipy.linalg
import scipy.sparse
import scipy.sparse.csgraph

from dolfinx_contact_s2s.checks.linalg import echelon, owned_rows
from dolfinx_contact_s2s.la import gather_dense

__all__ = [
    "REDUNDANT_TOL",
    "Redundancy",
    "joint_redundant_constraints",
    "joint_redundant_multipliers",
    "redundant_constraints",
    "redundant_multipliers",
]

REDUNDANT_TOL: float = 1e-12
r"""Eigenvalue of :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` (unit rows) below which a
row is dependent: singular values below :math:`10^{-6}`."""


@dataclass(frozen=True)
class Redundancy:
    """Rank deficiency of the active constraint rows of a pair (Eq. 35).

    Attributes:
        active: Number of active rows.
        zero: Active rows that vanish once the Dirichlet dofs are removed.
        dependent: Further rows linearly dependent on the others.
    """

    active: int
    zero: int
    dependent: int

    @property
    def redundant(self) -> int:
        """Rows to remove for full row rank: ``zero + dependent``."""
        return self.zero + self.dependent

    @property
    def rank(self) -> int:
        """Row rank of the active, Dirichlet-eliminated constraint matrix."""
        return self.active - self.redundant


def _masks(
    blocks: Sequence[PETSc.Mat], dirichlet_masks: Sequence[PETSc.Vec | None] | None
) -> list[PETSc.Vec | None]:
    if dirichlet_masks is None:
        return [None] * len(blocks)
    if len(dirichlet_masks) != len(blocks):
        raise ValueError("One Dirichlet mask per block is needed.")
    return list(dirichlet_masks)


def _scaled_blocks(
    blocks: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec | None],
    inactive: npt.ArrayLike | None,
    tol: float,
) -> tuple[list[PETSc.Mat], npt.NDArray[np.bool_], npt.NDArray[np.bool_]]:
    """Copies of the blocks with Dirichlet columns removed and kept rows of unit length.

    Returns the copies and, for the owned rows, which are kept and which vanished with
    the Dirichlet columns (inactive rows are neither; their copies are zero).
    """
    if len(blocks) == 0:
        raise ValueError("A constraint needs at least one block.")
    start, end = blocks[0].getOwnershipRange()
    for B in blocks:
        if B.getOwnershipRange() != (start, end):
            raise ValueError("All blocks of a constraint need the same row layout.")
    active = owned_rows(blocks[0], inactive)
    n = end - start
    full = np.zeros(n)
    eliminated = np.zeros(n)
    scaled = []
    for B, mask in zip(blocks, dirichlet_masks, strict=True):
        indptr, _, data = B.getValuesCSR()
        rows = np.repeat(np.arange(n), np.diff(indptr))
        full += np.bincount(rows, weights=data * data, minlength=n)
        Bc = B.copy()
        if mask is not None:
            Bc.diagonalScale(R=mask)
        indptr, _, data = Bc.getValuesCSR()
        rows = np.repeat(np.arange(n), np.diff(indptr))
        eliminated += np.bincount(rows, weights=data * data, minlength=n)
        scaled.append(Bc)
    zero = active & (eliminated <= tol * full)
    kept = active & ~zero
    scale = blocks[0].createVecLeft()
    scale.array[:] = 0.0
    scale.array[kept] = 1.0 / np.sqrt(eliminated[kept])
    for Bc in scaled:
        Bc.diagonalScale(L=scale)
    scale.destroy()
    return scaled, kept, zero


@dataclass
class _Gram:
    r"""Unit-row :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` of stacked constraints.

    Attributes:
        matrix: The Gram matrix (AIJ); its owned rows are those of each constraint in turn.
        kept: Owned rows that take part (active, not vanished).
        zero: Owned active rows that vanished with the Dirichlet columns.
        origin: (constraint, global row of the constraint) of each owned row.
        active: Number of active rows (all processes).
        num_zero: Number of vanished rows (all processes).
    """

    matrix: PETSc.Mat
    kept: npt.NDArray[np.bool_]
    zero: npt.NDArray[np.bool_]
    origin: npt.NDArray[np.int64]
    active: int
    num_zero: int


def _stacked_gram(
    constraints: Sequence[Sequence[tuple[int, PETSc.Mat]]],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None,
    inactive: Sequence[npt.ArrayLike | None] | None,
    tol: float,
) -> _Gram:
    """The Gram matrix of the rows of all ``constraints`` stacked (see the public API)."""
    if len(constraints) == 0:
        raise ValueError("At least one constraint is needed.")
    inactive = [None] * len(constraints) if inactive is None else list(inactive)
    if len(inactive) != len(constraints):
        raise ValueError("One set of inactive rows per constraint is needed.")
    scaled: list[dict[int, PETSc.Mat]] = []
    kept, zero, origin = [], [], []
    for c, (blocks, rows) in enumerate(zip(constraints, inactive, strict=True)):
        spaces = [s for s, _ in blocks]
        if len(set(spaces)) != len(spaces):
            raise ValueError(f"constraint {c} has two blocks on one space.")
        masks = [None if dirichlet_masks is None else dirichlet_masks[s] for s in spaces]
        copies, k, z = _scaled_blocks([B for _, B in blocks], masks, rows, tol)
        scaled.append(dict(zip(spaces, copies, strict=True)))
        kept.append(k)
        zero.append(z)
        start, end = blocks[0][1].getOwnershipRange()
        origin.append(np.column_stack([np.full(end - start, c), np.arange(start, end)]))
    grams: list[list[PETSc.Mat | None]] = []
    for left in scaled:
        grams.append([])
        for right in scaled:
            G = None
            for s in left.keys() & right.keys():
                P = left[s].matTransposeMult(right[s])
                if G is None:
                    G = P
                else:
                    G.axpy(1.0, P, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
                    P.destroy()
            grams[-1].append(G)
    for copies in scaled:
        for Bc in copies.values():
            Bc.destroy()
    comm = constraints[0][0][1].getComm()
    if len(grams) == 1:
        matrix = grams[0][0]
    else:
        nest = PETSc.Mat().createNest(grams, comm=comm)
        matrix = nest.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())
        nest.destroy()
        for row in grams:
            for G in row:
                if G is not None:
                    G.destroy()
    assert matrix is not None
    kept_all, zero_all = np.concatenate(kept), np.concatenate(zero)
    mpi = comm.tompi4py()
    active = sum(
        mpi.allreduce(int(np.count_nonzero(owned_rows(blocks[0][1], rows))))
        for blocks, rows in zip(constraints, inactive, strict=True)
    )
    return _Gram(
        matrix,
        kept_all,
        zero_all,
        np.concatenate(origin).astype(np.int64),
        active,
        mpi.allreduce(int(np.count_nonzero(zero_all))),
    )


def _dependent_rows(gram: _Gram, tol: float) -> int:
    """Eigenvalues of the kept block below ``tol``: negative pivots of ``G - tol I``."""
    matrix = gram.matrix
    comm = matrix.getComm().tompi4py()
    if comm.allreduce(int(np.count_nonzero(gram.kept))) == 0:
        return 0
    shift = matrix.createVecLeft()
    shift.array[:] = np.where(gram.kept, -tol, 1.0)
    matrix.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
    matrix.setDiagonal(shift, addv=PETSc.InsertMode.ADD_VALUES)
    matrix.assemble()
    matrix.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    ksp = PETSc.KSP().create(comm)
    ksp.setOptionsPrefix("dolfinx_contact_s2s_redundancy_")
    ksp.setOperators(matrix)
    ksp.setType(PETSc.KSP.Type.PREONLY)
    pc = ksp.getPC()
    pc.setType(PETSc.PC.Type.CHOLESKY)
    pc.setFactorSolverType("mumps")
    pc.setFactorSetUpSolverType()
    factor = pc.getFactorMatrix()
    factor.setMumpsIcntl(13, 1)  # no ScaLAPACK on the root node: exact inertia
    factor.setMumpsIcntl(24, 0)  # no null pivot detection: every pivot is counted
    pc.setUp()
    negative = int(comm.bcast(factor.getMumpsInfog(12), root=0))
    ksp.destroy()
    shift.destroy()
    return negative


def joint_redundant_constraints(
    constraints: Sequence[Sequence[tuple[int, PETSc.Mat]]],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None = None,
    inactive: Sequence[npt.ArrayLike | None] | None = None,
    *,
    tol: float = REDUNDANT_TOL,
) -> Redundancy:
    r"""Count the redundant rows of several pairs' constraints together (Eqs. 34-35).

    Each pair may have full row rank while the stacked :math:`[\mathbf B_1; \mathbf B_2]`
    has not: the two passes of a two-pass method both constrain the same motion. The
    Gram matrix of the stacked unit rows has the blocks :math:`\sum_s \tilde{\mathbf
    B}_{is}\tilde{\mathbf B}_{js}^T` over the spaces :math:`s` both pairs constrain;
    its inertia is counted as in :func:`redundant_constraints`.

    Args:
        constraints: Per pair, ``(space index, block)`` of each space it constrains.
        dirichlet_masks: Per space, 1 at free and 0 at Dirichlet dofs (or ``None``).
        inactive: Per pair, global indices of the rows to ignore (or ``None``).
        tol: :math:`\tau`, see :data:`REDUNDANT_TOL`.

    Returns:
        The counts over all pairs, the same on every process.
    """
    gram = _stacked_gram(constraints, dirichlet_masks, inactive, tol)
    try:
        dependent = _dependent_rows(gram, tol)
    finally:
        gram.matrix.destroy()
    return Redundancy(gram.active, gram.num_zero, dependent)


def redundant_constraints(
    blocks: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None = None,
    inactive: npt.ArrayLike | None = None,
    *,
    tol: float = REDUNDANT_TOL,
) -> Redundancy:
    r"""Count the redundant rows of a pair's active constraint matrix (Eqs. 34-35).

    :math:`\tilde{\mathbf B} = [\mathbf B_1\mathbf D_1, \mathbf B_2\mathbf D_2, \dots]`
    with the inactive rows removed and the others scaled to unit length; the dependent
    rows are the eigenvalues of :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` below
    ``tol``, counted as the negative pivots of the MUMPS :math:`\mathbf L\mathbf D
    \mathbf L^T` factorization of :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T - \tau
    \mathbf I` (exact inertia: ``ICNTL(13) = 1``, no ScaLAPACK root). The columns of the
    blocks need not be concatenated: :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T =
    \sum_s \tilde{\mathbf B}_s\tilde{\mathbf B}_s^T`.

    Args:
        blocks: The pair's constraint blocks (AIJ, one per displacement space, the same
            row layout), not Dirichlet-eliminated.
        dirichlet_masks: Per block, 1 at free and 0 at Dirichlet columns (or ``None``).
        inactive: Global indices of the rows to ignore (each process may pass any
            subset; their union is used).
        tol: :math:`\tau`, see :data:`REDUNDANT_TOL`.

    Returns:
        The counts, the same on every process.
    """
    return joint_redundant_constraints(
        [list(enumerate(blocks))], _masks(blocks, dirichlet_masks), [inactive], tol=tol
    )


def redundant_multipliers(
    blocks: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None = None,
    inactive: npt.ArrayLike | None = None,
    *,
    tol: float = REDUNDANT_TOL,
    max_rows: int = 2000,
) -> list[npt.NDArray[np.int64]]:
    r"""Name the redundant multipliers of a small constraint matrix (Eqs. 34-35).

    Dense eigen-decomposition of the gathered unit-row
    :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` of :func:`redundant_constraints`: every
    null vector (left null vector of :math:`\tilde{\mathbf B}`) is a linear dependency
    between rows. The null space is given in reduced echelon form, so that independent
    dependencies (two duplicated rows in different places) come out separately.

    Args:
        blocks: As for :func:`redundant_constraints`.
        dirichlet_masks: As for :func:`redundant_constraints`.
        inactive: As for :func:`redundant_constraints`.
        tol: :math:`\tau`, see :data:`REDUNDANT_TOL`.
        max_rows: Refuse larger matrices (dense work grows as rows cubed).

    Returns:
        One array per redundant row: the global row (multiplier) indices involved in a
        dependency, the largest coefficient first, entries below :math:`10^{-6}` of the
        largest left out. Rows that vanish after the Dirichlet elimination come first,
        alone. Its length is :attr:`Redundancy.redundant`. The same on every process.
    """
    named = joint_redundant_multipliers(
        [list(enumerate(blocks))],
        _masks(blocks, dirichlet_masks),
        [inactive],
        tol=tol,
        max_rows=max_rows,
    )
    return [rows[:, 1].copy() for rows in named]


def joint_redundant_multipliers(
    constraints: Sequence[Sequence[tuple[int, PETSc.Mat]]],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None = None,
    inactive: Sequence[npt.ArrayLike | None] | None = None,
    *,
    tol: float = REDUNDANT_TOL,
    max_rows: int = 2000,
) -> list[npt.NDArray[np.int64]]:
    r"""Name the redundant multipliers of several small constraints together.

    Args:
        constraints: As for :func:`joint_redundant_constraints`.
        dirichlet_masks: As for :func:`joint_redundant_constraints`.
        inactive: As for :func:`joint_redundant_constraints`.
        tol: :math:`\tau`, see :data:`REDUNDANT_TOL`.
        max_rows: Refuse more rows in all (dense work grows as rows cubed).

    Returns:
        As :func:`redundant_multipliers`, with each multiplier given as a row
        ``(pair, global row of the pair)`` of an array of shape ``(k, 2)``.
    """
    rows = sum(blocks[0][1].getSize()[0] for blocks in constraints)
    if rows > max_rows:
        raise ValueError(f"{rows} constraint rows: more than max_rows={max_rows}.")
    gram = _stacked_gram(constraints, dirichlet_masks, inactive, tol)
    comm = gram.matrix.getComm().tompi4py()
    dense = gather_dense(gram.matrix)
    gram.matrix.destroy()
    kept = np.concatenate(comm.allgather(gram.kept))
    zero = np.concatenate(comm.allgather(gram.zero))
    origin = np.concatenate(comm.allgather(gram.origin))
    result: list[npt.NDArray[np.int64]] | None = None
    if comm.rank == 0:
        result = [origin[[i]] for i in np.flatnonzero(zero)]
        index = np.flatnonzero(kept)
        if index.size > 0:
            eigenvalues, vectors = scipy.linalg.eigh(dense[np.ix_(index, index)])
            null = eigenvalues < tol
            if null.any():
                for z in echelon(vectors[:, null]):
                    big = np.abs(z) >= 1e-6 * np.abs(z).max()
                    order = np.argsort(-np.abs(z[big]), kind="stable")
                    result.append(origin[index[big][order]])
    return typing.cast(list, comm.bcast(result, root=0))

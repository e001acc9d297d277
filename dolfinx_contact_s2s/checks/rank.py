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
from dolfinx_contact_s2s.petsc import gather_dense

__all__ = ["REDUNDANT_TOL", "Redundancy", "redundant_constraints", "redundant_multipliers"]

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


def _scaled_gram(
    blocks: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None,
    inactive: npt.ArrayLike | None,
    tol: float,
) -> tuple[PETSc.Mat, npt.NDArray[np.bool_], npt.NDArray[np.bool_], int, int]:
    r"""Unit-row :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T`, the kept and zero rows."""
    if len(blocks) == 0:
        raise ValueError("A constraint needs at least one block.")
    comm = blocks[0].getComm().tompi4py()
    start, end = blocks[0].getOwnershipRange()
    for B in blocks:
        if B.getOwnershipRange() != (start, end):
            raise ValueError("All blocks of a constraint need the same row layout.")
    active = owned_rows(blocks[0], inactive)
    n = end - start
    full = np.zeros(n)
    eliminated = np.zeros(n)
    scaled = []
    for B, mask in zip(blocks, _masks(blocks, dirichlet_masks), strict=True):
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
    gram = None
    for Bc in scaled:
        Bc.diagonalScale(L=scale)
        P = Bc.matTransposeMult(Bc)
        if gram is None:
            gram = P
        else:
            gram.axpy(1.0, P, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            P.destroy()
        Bc.destroy()
    scale.destroy()
    assert gram is not None
    num_active = comm.allreduce(int(np.count_nonzero(active)))
    num_zero = comm.allreduce(int(np.count_nonzero(zero)))
    return gram, kept, zero, num_active, num_zero


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
    gram, kept, _, num_active, num_zero = _scaled_gram(blocks, dirichlet_masks, inactive, tol)
    comm = gram.getComm().tompi4py()
    if comm.allreduce(int(np.count_nonzero(kept))) == 0:
        gram.destroy()
        return Redundancy(num_active, num_zero, 0)
    shift = gram.createVecLeft()
    shift.array[:] = np.where(kept, -tol, 1.0)
    gram.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
    gram.setDiagonal(shift, addv=PETSc.InsertMode.ADD_VALUES)
    gram.assemble()
    gram.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    ksp = PETSc.KSP().create(comm)
    ksp.setOptionsPrefix("dolfinx_contact_s2s_redundancy_")
    ksp.setOperators(gram)
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
    gram.destroy()
    return Redundancy(num_active, num_zero, negative)


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
    rows = blocks[0].getSize()[0]
    if rows > max_rows:
        raise ValueError(f"{rows} constraint rows: more than max_rows={max_rows}.")
    gram, kept, zero, _, _ = _scaled_gram(blocks, dirichlet_masks, inactive, tol)
    comm = gram.getComm().tompi4py()
    dense = gather_dense(gram)
    gram.destroy()
    kept_all = np.concatenate(comm.allgather(kept))
    zero_all = np.concatenate(comm.allgather(zero))
    result: list[npt.NDArray[np.int64]] | None = None
    if comm.rank == 0:
        result = [np.array([i], dtype=np.int64) for i in np.flatnonzero(zero_all)]
        index = np.flatnonzero(kept_all)
        if index.size > 0:
            eigenvalues, vectors = scipy.linalg.eigh(dense[np.ix_(index, index)])
            null = eigenvalues < tol
            if null.any():
                for z in echelon(vectors[:, null]):
                    big = np.abs(z) >= 1e-6 * np.abs(z).max()
                    order = np.argsort(-np.abs(z[big]), kind="stable")
                    result.append(index[big][order].astype(np.int64))
    return typing.cast(list, comm.bcast(result, root=0))

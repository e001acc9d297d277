# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Small sparse and dense linear algebra shared by the checks."""

from __future__ import annotations

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import numpy.typing as npt
import scipy.linalg
import scipy.sparse
import scipy.sparse.csgraph

__all__ = ["csr_rows", "echelon", "owned_rows", "petsc_vector", "unit_rows"]


def csr_rows(A: PETSc.Mat, columns: int) -> scipy.sparse.csr_matrix:
    """Owned rows of a PETSc AIJ matrix with global column indices."""
    indptr, indices, data = A.getValuesCSR()
    return scipy.sparse.csr_matrix((data, indices, indptr), shape=(indptr.size - 1, columns))


def owned_rows(A: PETSc.Mat, inactive: npt.ArrayLike | None) -> npt.NDArray[np.bool_]:
    """Owned rows of ``A`` not listed as inactive on any process."""
    comm = A.getComm().tompi4py()
    start, end = A.getOwnershipRange()
    active = np.ones(end - start, dtype=np.bool_)
    listed = np.zeros(0, dtype=np.int64) if inactive is None else np.asarray(inactive, np.int64)
    listed = np.unique(np.concatenate(comm.allgather(listed.ravel())))
    listed = listed[(listed >= start) & (listed < end)]
    active[listed - start] = False
    return active


def unit_rows(A: scipy.sparse.csr_matrix, norms2: npt.NDArray) -> scipy.sparse.csr_matrix:
    """Rows of ``A`` scaled to unit length (``norms2``: their squared norms; zero rows stay)."""
    keep = norms2 > 0.0
    scale = np.zeros(norms2.size)
    scale[keep] = 1.0 / np.sqrt(norms2[keep])
    return scipy.sparse.diags(scale) @ A


def echelon(Z: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    """Reduced row echelon form of the rows of ``Z.T`` (a canonical basis of its span)."""
    A = Z.T.copy()
    k, n = A.shape
    r = 0
    for col in range(n):
        if r == k:
            break
        p = r + int(np.argmax(np.abs(A[r:, col])))
        if abs(A[p, col]) <= 1e-8:
            continue
        A[[r, p]] = A[[p, r]]
        A[r] /= A[r, col]
        for i in range(k):
            if i != r:
                A[i] -= A[i, col] * A[r]
        r += 1
    A[np.abs(A) < 1e-12 * np.abs(A).max(initial=0.0)] = 0.0
    return A


def petsc_vector(comm: MPI.Comm, values: npt.NDArray[np.floating], bs: int) -> PETSc.Vec:
    """An MPI vector holding the owned ``values`` (block size ``bs``)."""
    vec = PETSc.Vec().createMPI((values.size, PETSc.DETERMINE), bsize=bs, comm=comm)
    vec.array[:] = values
    return vec

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Small linear-algebra helpers on PETSc objects: dense gather, symmetry test, ``y += t B u``."""

from __future__ import annotations

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import numpy.typing as npt

__all__ = ["SYMMETRY_TOLERANCE", "add_scaled", "gather_dense", "is_symmetric", "plain_vector"]


def add_scaled(B: PETSc.Mat, u: PETSc.Vec, t: float, y: PETSc.Vec) -> None:
    """``y += t B u``."""
    w = B.createVecLeft()
    B.mult(u, w)
    y.axpy(t, w)
    w.destroy()


def plain_vector(nest: PETSc.Mat) -> PETSc.Vec:
    """An MPI vector in the row layout of a ``MatNest`` (the nest reads it by index sets)."""
    n, N = nest.getSizes()[0]
    return PETSc.Vec().createMPI((n, N), comm=nest.getComm())


def gather_dense(A: PETSc.Mat) -> npt.NDArray[np.floating]:
    """A distributed matrix as a dense array on every process (for small reference checks)."""
    start, _ = A.getOwnershipRange()
    indptr, indices, data = A.getValuesCSR()
    parts = A.getComm().tompi4py().allgather((start, indptr, indices, data))
    D = np.zeros(A.getSize())
    for start, indptr, indices, data in parts:
        rows = start + np.repeat(np.arange(indptr.size - 1), np.diff(indptr))
        D[rows, indices] += data
    return D


#: Relative tolerance of :func:`is_symmetric`: far above the round-off of an assembled
#: symmetric form, far below any asymmetry that matters to a solve.
SYMMETRY_TOLERANCE = 1e-10


def is_symmetric(A: PETSc.Mat, rtol: float = SYMMETRY_TOLERANCE) -> bool:
    r"""Whether :math:`|a_{ij} - a_{ji}| \le` ``rtol`` :math:`\|\mathbf A\|_\infty` everywhere.

    Each process checks the block of its own rows and columns entry by entry
    (``MatIsSymmetric``, the structure included, no communication); the couplings
    between processes by a random probe, :math:`|\mathbf y^T (\mathbf A - \mathbf
    A^T) \mathbf x| \le` ``rtol`` :math:`\|\mathbf A\|_\infty \|\mathbf x\|
    \|\mathbf y\|` (two products; PETSc's parallel ``MatIsSymmetric`` gathers the
    off-process rows, 13 times the serial cost on 2 processes). A form is the same
    on every element, so an asymmetric form shows in every block. Collective; the
    same answer on every process.
    """
    scale = A.norm(PETSc.NormType.INFINITY)
    if scale == 0.0:
        return True
    comm = A.getComm().tompi4py()
    if comm.size == 1:
        return bool(A.isSymmetric(rtol * scale))
    local = bool(A.getDiagonalBlock().isSymmetric(rtol * scale))
    x, y = A.createVecs()
    rng = np.random.default_rng(comm.rank)
    x.array[:] = rng.uniform(-1.0, 1.0, x.getLocalSize())
    y.array[:] = rng.uniform(-1.0, 1.0, y.getLocalSize())
    Ax, Ay = A.createVecLeft(), A.createVecLeft()
    A.mult(x, Ax)
    A.mult(y, Ay)
    probe = abs(y.dot(Ax) - x.dot(Ay)) <= rtol * scale * x.norm() * y.norm()
    for v in (x, y, Ax, Ay):
        v.destroy()
    return bool(comm.allreduce(local, op=MPI.LAND)) and bool(probe)

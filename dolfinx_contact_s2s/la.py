# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Small linear-algebra helpers on PETSc objects.

Dense gather, symmetry test, ``y += t B u``, and a matrix that keeps its nonzero pattern
(and so its factorization) across assemblies.
"""

from __future__ import annotations

import typing

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import numpy.typing as npt

__all__ = [
    "SYMMETRY_TOLERANCE",
    "KeptPattern",
    "add_scaled",
    "backward_error",
    "contains_pattern",
    "gather_dense",
    "indicator",
    "is_symmetric",
    "owned_vector",
    "plain_vector",
]


def add_scaled(B: PETSc.Mat, u: PETSc.Vec, t: float, y: PETSc.Vec) -> None:
    """``y += t B u``."""
    w = B.createVecLeft()
    B.mult(u, w)
    y.axpy(t, w)
    w.destroy()


def backward_error(
    A: PETSc.Mat, b: PETSc.Vec, x: PETSc.Vec, residual: PETSc.Vec | None = None
) -> float:
    r"""Normwise backward error of a solution ``x`` of :math:`\mathbf A \mathbf x = \mathbf b`.

    :math:`\eta = \|\mathbf b - \mathbf A\mathbf x\|_\infty / (\|\mathbf A\|_\infty
    \|\mathbf x\|_\infty + \|\mathbf b\|_\infty)` (Rigal-Gaches), the smallest relative
    normwise perturbation of :math:`\mathbf A` and :math:`\mathbf b` of which ``x`` is the
    exact solution. Collective. ``inf`` for a ``"nest"`` matrix.

    Args:
        A: The matrix.
        b: The right-hand side.
        x: The solution.
        residual: If given, filled with :math:`\mathbf b - \mathbf A\mathbf x`.
    """
    if A.getType() == PETSc.Mat.Type.NEST:
        return float("inf")
    r = b.duplicate() if residual is None else residual
    A.mult(x, r)
    r.aypx(-1.0, b)
    inf = PETSc.NormType.INFINITY
    rnorm = r.norm(inf)
    if residual is None:
        r.destroy()
    scale = A.norm(inf) * x.norm(inf) + b.norm(inf)
    return rnorm / scale if scale > 0 else rnorm


def plain_vector(nest: PETSc.Mat) -> PETSc.Vec:
    """An MPI vector in the row layout of a ``MatNest`` (the nest reads it by index sets)."""
    n, N = nest.getSizes()[0]
    return PETSc.Vec().createMPI((n, N), comm=nest.getComm())


def owned_vector(V: typing.Any, values: npt.NDArray[np.floating]) -> PETSc.Vec:
    """A PETSc vector in the owned layout of the space ``V`` holding a copy of ``values``."""
    n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
    return PETSc.Vec().createWithArray(np.array(values[:n]), comm=V.mesh.comm)


def indicator(template: PETSc.Vec, off: npt.NDArray[np.int64]) -> PETSc.Vec:
    """A vector of ``template``'s layout: 1, and 0 at the global indices ``off``."""
    v = template.duplicate()
    v.set(1.0)
    start, end = v.getOwnershipRange()
    v.array[off[(off >= start) & (off < end)] - start] = 0.0
    return v


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


def _pattern_keys(A: PETSc.Mat) -> npt.NDArray[np.int64]:
    """The owned nonzeros of an AIJ matrix as sorted ``local row * N + global column``."""
    indptr, indices, _ = A.getValuesCSR()
    rows = np.repeat(np.arange(indptr.size - 1, dtype=np.int64), np.diff(indptr))
    return np.sort(rows * A.getSize()[1] + indices.astype(np.int64))


def _inside(keys: npt.NDArray[np.int64] | None, A: PETSc.Mat) -> bool:
    """Whether ``A``'s pattern is within the keys (None: other sizes); collective."""
    inside = keys is not None and bool(np.isin(_pattern_keys(A), keys, assume_unique=True).all())
    return bool(A.getComm().tompi4py().allreduce(inside, op=MPI.LAND))


def contains_pattern(P: PETSc.Mat, A: PETSc.Mat) -> bool:
    """Whether every stored entry of ``A`` is a stored entry of ``P`` (collective; AIJ)."""
    return _inside(_pattern_keys(P) if P.getSizes() == A.getSizes() else None, A)


class KeptPattern:
    """One AIJ matrix object whose nonzero pattern only grows, for a factorization to keep.

    A KSP given the same matrix object with the same pattern refactors numerically on
    the same factor object (PETSc's ``SAME_NONZERO_PATTERN``); a new matrix object makes
    a new factor. A new MUMPS instance on more than one process can leak MPI
    communicators (a bare petsc4py loop: about five per instance, PETSc 3.22 and 3.25),
    and a long run then stalls: a Newton step of moving contact (a new coupling every
    iteration) uses one pattern, the union of its iterations' patterns.

    :meth:`take` copies a freshly built matrix into the kept one; :meth:`renew` lets
    the next :meth:`take` start from that matrix's own pattern if it is not contained
    (a new load step: the union stays a step's, so the fill does not grow with the slide).
    """

    def __init__(self) -> None:
        """Nothing kept yet."""
        self.matrix: PETSc.Mat | None = None
        self._keys: npt.NDArray[np.int64] | None = None  # the kept matrix's pattern
        #: Whether no :meth:`take` came since :meth:`renew` (or the start).
        self.fresh = True
        #: Patterns made by :meth:`take` (new matrix objects), for tests and benchmarks.
        self.patterns = 0

    def renew(self) -> None:
        """The next :meth:`take` may replace the pattern instead of growing it."""
        self.fresh = True

    def take(self, A: PETSc.Mat, ksp: PETSc.KSP | None = None) -> PETSc.Mat:
        """The kept matrix with the values of ``A`` (collective); ``A`` is destroyed.

        Returns the same object as before if its pattern contains ``A``'s, otherwise a
        new one: ``A`` itself after :meth:`renew`, else the union of both patterns.
        ``ksp`` (the solver of the kept matrix) is reset if the sizes change.
        """
        P = self.matrix
        same = P is not None and P.getSizes() == A.getSizes()
        if P is not None and not same and ksp is not None:
            ksp.reset()
        if P is not None and _inside(self._keys if same else None, A):
            P.zeroEntries()
            P.axpy(1.0, A, PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
            A.destroy()
            self.fresh = False
            return P
        if P is not None and not self.fresh and same:
            union = P.copy()
            union.zeroEntries()
            union.axpy(1.0, A, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            A.destroy()
            A = union
        self.destroy()
        self.matrix, self.fresh, self._keys = A, False, _pattern_keys(A)
        self.patterns += 1
        return A

    def destroy(self) -> None:
        """Destroy the kept matrix."""
        if self.matrix is not None:
            self.matrix.destroy()
        self.matrix, self._keys = None, None

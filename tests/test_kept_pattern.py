# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""One matrix object and one MUMPS factorization kept across assemblies (:class:`KeptPattern`).

The values are checked against SciPy's dense solve of the same matrices; the kept
factorization by the factor object's identity (a new MUMPS instance on several processes
leaks MPI communicators in some flows, and a long run of new instances stalls).
"""

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import scipy.linalg

from dolfinx_contact_s2s.la import KeptPattern, contains_pattern, gather_dense

N = 24


def _matrix(comm, entries):
    """An N x N AIJ matrix from a dict ``{(i, j): value}`` (the owned rows set here)."""
    A = PETSc.Mat().createAIJ([N, N], comm=comm)
    A.setPreallocationNNZ((N, N))
    start, end = A.getOwnershipRange()
    for (i, j), v in entries.items():
        if start <= i < end:
            A.setValue(i, j, v)
    A.assemble()
    return A


def _tridiagonal(scale, extra=()):
    """A nonsymmetric, well-conditioned tridiagonal matrix, with ``extra`` entries."""
    entries = {(i, i): 4.0 * scale + i for i in range(N)}
    entries.update({(i, i + 1): -1.0 for i in range(N - 1)})
    entries.update({(i + 1, i): -2.0 * scale for i in range(N - 1)})
    entries.update({(i, j): 0.5 for i, j in extra})
    return entries


def _solve(ksp, A):
    b = A.createVecLeft()
    b.array[:] = np.arange(*b.getOwnershipRange(), dtype=float) + 1.0
    x = A.createVecRight()
    ksp.solve(b, x)
    dense = gather_dense(A)
    exact = scipy.linalg.solve(dense, np.arange(N, dtype=float) + 1.0)
    start, end = x.getOwnershipRange()
    error = np.max(np.abs(x.array_r - exact[start:end]), initial=0.0)
    b.destroy()
    x.destroy()
    return A.getComm().tompi4py().allreduce(error, op=MPI.MAX) / np.max(np.abs(exact))


def _ksp(comm):
    ksp = PETSc.KSP().create(comm)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    return ksp


def test_contains_pattern():
    comm = MPI.COMM_WORLD
    A = _matrix(comm, _tridiagonal(1.0))
    B = _matrix(comm, _tridiagonal(2.0, extra=[(0, N - 1)]))
    C = _matrix(comm, {(i, i): 1.0 for i in range(N)})
    assert contains_pattern(B, A) and contains_pattern(A, C) and contains_pattern(A, A)
    assert not contains_pattern(A, B)
    for M in (A, B, C):
        M.destroy()


def test_kept_factorization_values_and_identity():
    """Values: SciPy's dense solve of each matrix; the factor: the same object in a pattern."""
    comm = MPI.COMM_WORLD
    eps = np.finfo(float).eps
    kept, ksp = KeptPattern(), _ksp(comm)

    def step(entries):
        ksp.setOperators(kept.take(_matrix(comm, entries)))
        error = _solve(ksp, kept.matrix)
        assert error < 1e3 * N * eps
        return ksp.getPC().getFactorMatrix().handle

    first = step(_tridiagonal(1.0))
    # Other values, the same pattern, then a subset of it (a diagonal): numeric only.
    assert step(_tridiagonal(3.0)) == first
    assert step({(i, i): 2.0 + i for i in range(N)}) == first
    assert kept.patterns == 1
    # A new entry within a step: the union, with the new matrix's values exactly.
    grown = _tridiagonal(2.0, extra=[(0, N - 1), (N - 1, 0)])
    step(grown)
    assert kept.patterns == 2
    assert np.array_equal(gather_dense(kept.matrix), gather_dense(_matrix(comm, grown)))
    union_nnz = kept.matrix.getInfo(PETSc.Mat.InfoType.GLOBAL_SUM)["nz_used"]
    # After renew, a pattern outside the union replaces it: the fill does not pile up.
    kept.renew()
    step(_tridiagonal(1.0, extra=[(1, N - 2)]))
    assert kept.patterns == 3
    nnz = kept.matrix.getInfo(PETSc.Mat.InfoType.GLOBAL_SUM)["nz_used"]
    assert nnz == 3 * N - 2 + 1 < union_nnz
    # After renew, a pattern inside the kept one is still refactored numerically.
    handle = ksp.getPC().getFactorMatrix().handle
    kept.renew()
    assert step(_tridiagonal(5.0)) == handle
    ksp.destroy()
    kept.destroy()

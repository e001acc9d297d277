# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""MUMPS's Schur complement (ICNTL(19)) and selected entries of the inverse (ICNTL(30)).

petsc4py (3.22 to 3.25) does not expose ``MatFactorSetSchurIS``,
``MatFactorCreateSchurComplement`` and ``MatMumpsGetInverseTranspose``: a thin ctypes
binding to the PETSc library that petsc4py itself loaded, through the objects' handles.
"""

from __future__ import annotations

import ctypes
import typing

from petsc4py import PETSc

import numpy as np
import numpy.typing as npt

__all__ = ["inverse_block", "schur_complement", "set_schur_indices"]


def _petsc_library() -> ctypes.CDLL:
    """The PETSc shared library petsc4py runs on (found in this process's mappings)."""
    global _LIBRARY
    if _LIBRARY is None:
        with open("/proc/self/maps") as maps:
            paths = {line.split()[-1] for line in maps if "libpetsc" in line and ".so" in line}
        if not paths:
            raise RuntimeError("the PETSc shared library is not loaded in this process")
        library = ctypes.CDLL(sorted(paths)[0])
        for name, argtypes in {
            "MatFactorSetSchurIS": [ctypes.c_void_p, ctypes.c_void_p],
            "MatFactorCreateSchurComplement": [
                ctypes.c_void_p,
                ctypes.POINTER(ctypes.c_void_p),
                ctypes.POINTER(ctypes.c_int),
            ],
            "MatDenseGetArrayRead": [ctypes.c_void_p, ctypes.POINTER(ctypes.c_void_p)],
            "MatDenseRestoreArrayRead": [ctypes.c_void_p, ctypes.POINTER(ctypes.c_void_p)],
            "MatDenseGetLDA": [ctypes.c_void_p, ctypes.c_void_p],
            "MatGetSize": [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p],
            "MatDestroy": [ctypes.POINTER(ctypes.c_void_p)],
            "MatMumpsGetInverseTranspose": [ctypes.c_void_p, ctypes.c_void_p],
        }.items():
            function = getattr(library, name)
            function.argtypes = argtypes
            function.restype = ctypes.c_int
        _LIBRARY = library
    return _LIBRARY


_LIBRARY: ctypes.CDLL | None = None


def _call(name: str, *args: typing.Any) -> None:
    code = getattr(_petsc_library(), name)(*args)
    if code != 0:
        raise RuntimeError(f"{name} failed with PETSc error code {code}")


def set_schur_indices(F: PETSc.Mat, rows: PETSc.IS) -> None:
    """Ask a MUMPS factor, before its factorization, for the Schur complement on ``rows``.

    MUMPS's ICNTL(19) through ``MatFactorSetSchurIS``. In parallel PETSc wants the
    whole (centralized) Schur complement on process 0: ``rows`` must be empty elsewhere.
    """
    _call("MatFactorSetSchurIS", F.handle, rows.handle)


def schur_complement(F: PETSc.Mat) -> npt.NDArray[np.floating]:
    r"""The dense Schur complement of a factorized MUMPS matrix, on every process.

    With the rows :math:`s` set by :func:`set_schur_indices` and :math:`f` the others,
    :math:`\mathbf A_{ss} - \mathbf A_{sf} \mathbf A_{ff}^{-1} \mathbf A_{fs}` in the
    order of ``rows``. Symmetric factorizations (MUMPS returns one triangle) are
    symmetrized. Collective.
    """
    comm = F.getComm().tompi4py()
    S = ctypes.c_void_p()
    status = ctypes.c_int()
    _call("MatFactorCreateSchurComplement", F.handle, ctypes.byref(S), ctypes.byref(status))
    try:
        m, n, lda = (np.zeros(1, dtype=PETSc.IntType) for _ in range(3))
        _call("MatGetSize", S, m.ctypes.data, n.ctypes.data)
        _call("MatDenseGetLDA", S, lda.ctypes.data)
        size, ld = int(m[0]), int(lda[0])
        local = np.zeros((size, size))
        if size:
            pointer = ctypes.c_void_p()
            _call("MatDenseGetArrayRead", S, ctypes.byref(pointer))
            buffer = ctypes.cast(pointer, ctypes.POINTER(ctypes.c_double * (ld * size))).contents
            # Column-major with leading dimension lda.
            local = np.frombuffer(buffer, dtype=np.float64).reshape(size, ld)[:, :size].T.copy()
            _call("MatDenseRestoreArrayRead", S, ctypes.byref(pointer))
    finally:
        _call("MatDestroy", ctypes.byref(S))
    # Process 0 holds it (centralized); the others an empty matrix.
    dense = comm.bcast(local if comm.rank == 0 else None, root=0)
    lower, upper = np.tril(dense, -1), np.triu(dense, 1)
    if lower.any() != upper.any():
        # A symmetric factorization returns one triangle.
        dense = lower + lower.T + upper + upper.T + np.diag(np.diag(dense))
    return dense


def inverse_block(F: PETSc.Mat, rows: npt.NDArray[np.int64]) -> npt.NDArray[np.floating]:
    r"""The block :math:`(\mathbf A^{-1})_{ss}` of a factorized MUMPS matrix, on every process.

    MUMPS's selected entries of the inverse (ICNTL(30)): sparse right-hand sides whose
    solves touch only the paths of the elimination tree they need (363 x 363 entries of
    a factor of 491,575 unknowns: 0.06 s against 2.3 s for the factorization). In parallel
    the factor must have solved once before: PETSc makes the scatter of a distributed
    solution at the first solve, and a first solve after this call hangs. Collective.

    Args:
        F: The factor (LU or Cholesky), after a solve.
        rows: The rows :math:`s` (global, sorted, the same on every process).
    """
    comm = F.getComm().tompi4py()
    size, m = F.getSize()[0], rows.size
    own = size if comm.rank == 0 else 0
    indptr = np.zeros(own + 1, dtype=PETSc.IntType)
    indices = np.zeros(0, dtype=PETSc.IntType)
    if comm.rank == 0:
        counts = np.zeros(size, dtype=PETSc.IntType)
        counts[rows] = m
        indptr[1:] = np.cumsum(counts)
        indices = np.tile(rows, m).astype(PETSc.IntType)
    # The requested entries on process 0: its diagonal block is the whole matrix.
    pattern = PETSc.Mat().createAIJ(
        [[own, size], [own, size]], csr=(indptr, indices, np.zeros(indices.size)), comm=comm
    )
    saved = {k: F.getMumpsIcntl(k) for k in (20, 21, 30)}
    try:
        _call("MatMumpsGetInverseTranspose", F.handle, pattern.handle)
    finally:
        for k, v in saved.items():  # ICNTL(30) left at 1 makes the next solve fail
            F.setMumpsIcntl(k, v)
    block = None
    if comm.rank == 0:
        # Row r_i of the pattern holds (A^{-T})_{r_i r_j}: the block of A^{-1}, transposed.
        block = pattern.getValuesCSR()[2].reshape(m, m).T.copy()
    pattern.destroy()
    return comm.bcast(block, root=0)

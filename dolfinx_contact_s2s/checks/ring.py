# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Whether a body's stiffness is axisymmetric: the radial translation stores energy.

A plane model (strain or stress) stores no energy in a rigid translation, in any
direction. An axisymmetric one (:math:`2\pi r` weight, hoop strain :math:`u_r/r`)
stores none in an axial translation, but a radial one stretches every ring. So the rows
of :math:`\mathbf K \mathbf t` away from Dirichlet dofs tell the two apart, from the
assembled matrix alone, whatever forms the user wrote. A pair whose ``axisymmetric``
flag contradicts its bodies' forms gives a plausible answer wrong by the factor
:math:`2\pi r`: this check names it.
"""

from __future__ import annotations

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np

__all__ = ["RING_TOLERANCE", "translation_residuals"]

#: Relative row sum of :math:`\mathbf K \mathbf t` below which a translation stores no
#: energy (round-off of a row of :math:`\mathbf K` is about :math:`10^{-15}` of it).
RING_TOLERANCE = 1e-11


def translation_residuals(K: PETSc.Mat, mask: PETSc.Vec, bs: int) -> np.ndarray | None:
    r"""Largest :math:`|(\mathbf K \mathbf t_d)_i| / \max_i K_{ii}` per direction (collective).

    Over the free rows ``i`` that couple to no Dirichlet dof (there a rigid translation
    of the free dofs alone is one of the whole body). The same array on every process.

    Args:
        K: The stiffness with Dirichlet rows and columns zeroed (unit diagonal).
        mask: 1 at free dofs, 0 at Dirichlet dofs (owned layout).
        bs: The displacement's block size.

    Returns:
        ``bs`` values, or None where no such row exists (a mesh too small to tell).
    """
    comm = K.getComm().tompi4py()
    indptr, indices, data = K.getValuesCSR()
    pattern = PETSc.Mat().createAIJ(
        size=K.getSizes(), csr=(indptr, indices, np.ones_like(data)), comm=K.getComm()
    )
    pattern.assemble()
    fixed, touched = mask.duplicate(), mask.duplicate()
    fixed.array[:] = 1.0 - mask.array_r
    pattern.mult(fixed, touched)
    interior = (mask.array_r > 0.5) & (touched.array_r == 0.0)
    diagonal = K.getDiagonal()
    scale = comm.allreduce(float(np.max(np.abs(diagonal.array_r), initial=0.0)), op=MPI.MAX)
    count = comm.allreduce(int(np.count_nonzero(interior)))
    t, y = K.createVecRight(), K.createVecLeft()
    residuals = np.zeros(bs)
    for d in range(bs):
        t.array[:] = 0.0
        t.array[d::bs] = 1.0
        K.mult(t, y)
        residuals[d] = float(np.max(np.abs(y.array_r[interior]), initial=0.0))
    for obj in (pattern, fixed, touched, diagonal, t, y):
        obj.destroy()
    largest = np.empty_like(residuals)
    comm.Allreduce(residuals, largest, op=MPI.MAX)
    if count == 0 or scale == 0.0:
        return None
    return largest / scale

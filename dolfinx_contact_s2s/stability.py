# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Solvability of a contact discretization (section 3.1, Eqs. 33-35).

Eq. (18) is solvable when :math:`\mathbf K` is positive definite on the kernel of
:math:`\mathbf B` (Eq. 33: a properly supported structure) and :math:`\mathbf B` has full
row rank (Eqs. 34-35): otherwise some multipliers are not determined, and a direct
solver returns arbitrary values for them. This module needs petsc4py.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import scipy.linalg

from dolfinx_contact_s2s.petsc import ContactProblem, gather_dense

__all__ = ["Solvability", "constraint_matrix", "solvability"]


@dataclass(frozen=True)
class Solvability:
    r"""Rank of the constraint matrix (Eq. 35).

    Attributes:
        constraints: Number :math:`n` of active multipliers.
        rank: Numerical rank of :math:`\mathbf B`.
        condition: :math:`\sigma_{max} / \sigma_{min}` of :math:`\mathbf B` (infinite if
            rank deficient).
    """

    constraints: int
    rank: int
    condition: float = np.inf

    @property
    def redundant(self) -> int:
        r"""Number of redundant constraints, :math:`n - \mathrm{rank}(\mathbf B)`."""
        return self.constraints - self.rank

    @property
    def solvable(self) -> bool:
        r"""Whether :math:`\mathrm{rank}(\mathbf B) = n` (Eq. 35)."""
        return self.redundant == 0


def constraint_matrix(problem: ContactProblem) -> npt.NDArray[np.floating]:
    r"""The active rows of :math:`\mathbf B` as a dense array on every process.

    Columns are the displacement dofs of the bodies in order; Dirichlet columns are zero.
    Meant for small problems (reference computations and tests).
    """
    sizes = [V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces]
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    rows = []
    for pair, (B_c, B_t) in zip(problem.pairs, problem.constraints, strict=True):
        n = pair.Q.dofmap.index_map.size_global
        B = np.zeros((n, offsets[-1]))
        for Bi, V in ((B_c, pair.contactor.V), (B_t, pair.target.V)):
            i = next(k for k, W in enumerate(problem.spaces) if W is V)
            B[:, offsets[i] : offsets[i + 1]] += gather_dense(Bi)
        rows.append(np.delete(B, pair.inactive, axis=0))
    return np.vstack(rows)


def solvability(problem: ContactProblem) -> Solvability:
    r"""Rank of :math:`\mathbf B` by a dense SVD (Eq. 35).

    The rank counts singular values above :math:`\sigma_{max} \max(n, m)\,\epsilon`.
    """
    B = constraint_matrix(problem)
    s = scipy.linalg.svdvals(B)
    tol = (s.max(initial=0.0)) * max(B.shape) * np.finfo(float).eps
    rank = int(np.count_nonzero(s > tol))
    condition = s.max() / s.min() if rank == B.shape[0] and rank > 0 else np.inf
    return Solvability(B.shape[0], rank, float(condition))

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Solvability and stability of a contact discretization (section 3.1).

Eq. (18) is solvable when :math:`\mathbf K` is positive definite on the kernel of
:math:`\mathbf B` (Eq. 33: a properly supported structure) and :math:`\mathbf B` has full
row rank (Eqs. 34-35): otherwise some multipliers are not determined, and a direct
solver returns arbitrary values for them. It is stable when, in addition, the inf-sup
values of Eqs. (22) and (26)-(27) stay bounded away from zero as the mesh is refined:
:func:`inf_sup_dense` evaluates them as the paper states them, :class:`InfSupTest` for
large meshes (:mod:`dolfinx_contact_s2s.analysis.infsup`). Both work on any
:class:`~dolfinx_contact_s2s.problem.LinearContactProblem` through its public API; a
problem that is not yet assembled is assembled without the solvability checks that
these functions are there to quantify. This module needs petsc4py.
"""

from __future__ import annotations

from dataclasses import dataclass

from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import scipy.linalg
import ufl

from dolfinx_contact_s2s.assemble import multiplier_mass
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.problem import LinearContactProblem

__all__ = [
    "InfSup",
    "Solvability",
    "assembled",
    "constraint_matrix",
    "dirichlet_free",
    "dual_norm_matrix",
    "h1_norm_form",
    "inf_sup_dense",
    "norm_matrices",
    "solvability",
    "stack_pairs",
]


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


def assembled(problem: LinearContactProblem) -> LinearContactProblem:
    """``problem``, assembled without the solvability checks if it is not yet."""
    if problem.A is None:
        problem.assemble(check=False)
    return problem


def constraint_matrix(problem: LinearContactProblem) -> npt.NDArray[np.floating]:
    r"""The active rows of :math:`\mathbf B` as a dense array on every process.

    Columns are the displacement dofs of the spaces in order; Dirichlet columns are
    zero. Meant for small problems (reference computations and tests).
    """
    assembled(problem)
    sizes = [V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces]
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    rows = []
    for pair, op, blocks in zip(problem.pairs, problem.operators, problem.constraints, strict=True):
        B = np.zeros((pair.Q.dofmap.index_map.size_global, offsets[-1]))
        for i, Bi in blocks:
            B[:, offsets[i] : offsets[i + 1]] += gather_dense(Bi)
        rows.append(np.delete(B, op.inactive, axis=0))
    return np.vstack(rows)


def solvability(problem: LinearContactProblem) -> Solvability:
    r"""Rank of :math:`\mathbf B` by a dense SVD (Eq. 35).

    The rank counts singular values above :math:`\sigma_{max} \max(n, m)\,\epsilon`.
    """
    B = constraint_matrix(problem)
    s = scipy.linalg.svdvals(B)
    tol = (s.max(initial=0.0)) * max(B.shape) * np.finfo(float).eps
    rank = int(np.count_nonzero(s > tol))
    condition = s.max() / s.min() if rank == B.shape[0] and rank > 0 else np.inf
    return Solvability(B.shape[0], rank, float(condition))


# --- The inf-sup test (Eqs. 26-32) -------------------------------------------------


def h1_norm_form(V: dolfinx.fem.FunctionSpace) -> ufl.Form:
    r"""The :math:`H^1` inner product :math:`\int \nabla u : \nabla v + u \cdot v` (Eq. 28)."""
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    return (ufl.inner(ufl.grad(u), ufl.grad(v)) + ufl.inner(u, v)) * ufl.dx


def _traction_scale(pair: ContactPair) -> npt.NDArray[np.floating]:
    """Factors taking the multipliers of ``pair`` to traction values (all dofs, global)."""
    n = pair.Q.dofmap.index_map.size_global
    if not pair.nodal or pair.weight != "unit":
        return np.ones(n)
    M = multiplier_mass(pair)  # diag(1 / w)
    d = gather_dense(M).diagonal().copy()
    M.destroy()
    return d


def dual_norm_matrix(pair: ContactPair) -> npt.NDArray[np.floating]:
    r"""Dense :math:`\mathbf T` of the dual norm of Eqs. (21)-(22), over all multipliers.

    :math:`\mathbf M^T \mathbf T \mathbf M = \|\mu_h\|^2_{-1/2,\Gamma}`.

    The supremum of Eq. (21) is taken over the continuous Lagrange functions
    :math:`W` of degree :math:`s + 2` on the multiplier's mesh (:math:`s` its degree).
    :math:`W` holds a bubble of each element for every moment of the multiplier, so the
    supremum over :math:`W` is equivalent to the one over :math:`H^{1/2}(\Gamma)` with
    constants independent of :math:`h` (a Fortin argument). :math:`\|w\|_{1/2,\Gamma}`
    is the interpolation norm :math:`[L^2, H^1]_{1/2}`: with :math:`\mathbf A \Phi =
    \mathbf M \Phi \Lambda` the :math:`H^1` and :math:`L^2` matrices of :math:`W`,
    :math:`\|w\|^2_{1/2} = \mathbf w^T \mathbf M \Phi \Lambda^{1/2} \Phi^T \mathbf M
    \mathbf w`, whose inverse is :math:`\Phi \Lambda^{-1/2} \Phi^T`, so that
    :math:`\mathbf T = \mathbf F \Phi \Lambda^{-1/2} \Phi^T \mathbf F^T` with
    :math:`F_{ij} = \int_\Gamma \mu_i w_j`. Node-based multipliers are read as the
    continuous traction field through their values. Dense: for reference computations.
    """
    mesh = pair.Q.mesh
    W = dolfinx.fem.functionspace(mesh, ("Lagrange", pair.multiplier_degree + 2))
    w, v = ufl.TrialFunction(W), ufl.TestFunction(W)
    q = ufl.TestFunction(pair.Q)
    forms = [
        (ufl.inner(ufl.grad(w), ufl.grad(v)) + ufl.inner(w, v)) * ufl.dx,
        ufl.inner(w, v) * ufl.dx,
        ufl.inner(w, q) * ufl.dx,
    ]
    A, M, F = (_dense_form(f) for f in forms)
    lam, phi = scipy.linalg.eigh(A, M)
    F *= _traction_scale(pair)[:, None]
    X = F @ phi
    return (X / np.sqrt(lam)) @ X.T


def _dense_form(form: ufl.Form) -> npt.NDArray[np.floating]:
    A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(form))
    A.assemble()
    D = gather_dense(A)
    A.destroy()
    return D


@dataclass(frozen=True)
class InfSup:
    r"""Result of the inf-sup test of Eqs. (26)-(32) (and Eq. 22).

    Attributes:
        beta: :math:`\beta^*_h` of Eq. (27): the square root of the smallest non-zero
            eigenvalue of Eq. (30), or 0 where pressure modes exist.
        pressure_modes: :math:`k_{pm}` of Eq. (32).
        constraints: :math:`n`, the number of active multipliers.
        displacements: :math:`m`, the number of free displacement unknowns.
        h: The element size of Eqs. (26) and (31).
        beta_full: :math:`\beta_h` of Eq. (22) with the :math:`H^{-1/2}` dual norm of
            the multiplier, if computed.
        eigenvalues: The smallest non-zero eigenvalues of Eq. (30) found.
        solves: Back-substitutions with the saddle-point factorization (scalable path).
    """

    beta: float
    pressure_modes: int
    constraints: int
    displacements: int
    h: float
    beta_full: float | None = None
    eigenvalues: tuple[float, ...] = ()
    solves: int = 0

    @property
    def solvable(self) -> bool:
        r"""No pressure modes: :math:`\mathbf B` has full rank (Eq. 35)."""
        return self.pressure_modes == 0


def dirichlet_free(problem: LinearContactProblem) -> npt.NDArray[np.bool_]:
    """Global mask of the displacement unknowns without a Dirichlet condition."""
    masks = []
    for i in range(len(problem.spaces)):
        keep = problem.dirichlet_mask(i)
        masks.append(np.concatenate(problem.comm.allgather(keep.array_r.copy())) > 0.5)
        keep.destroy()
    return np.concatenate(masks)


def norm_matrices(problem: LinearContactProblem, norm: str) -> list[PETSc.Mat]:
    r""":math:`\mathbf S` of Eq. (28) per space, Dirichlet rows and columns unit.

    The caller must ``destroy()`` them.
    """
    if norm == "energy":
        assembled(problem)
        return [problem.stiffness_matrix(i) for i in range(len(problem.spaces))]
    if norm != "H1":
        raise ValueError(f"norm must be 'H1' or 'energy', not {norm!r}")
    out = []
    for V, bcs in zip(problem.spaces, problem.bcs_by_space, strict=True):
        S = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(h1_norm_form(V)), bcs=bcs)
        S.assemble()
        out.append(S)
    return out


def inf_sup_dense(
    problem: LinearContactProblem,
    h: float,
    *,
    norm: str = "H1",
    full: bool = True,
    zero_tolerance: float = 1e-10,
) -> InfSup:
    r"""The inf-sup test exactly as Eqs. (26)-(32) state it, with dense matrices.

    :math:`\mathbf G = \mathbf B^T \mathbf P^{-1} \mathbf B / h` (Eq. 31) and
    :math:`\mathbf G \phi = \lambda \mathbf S \phi` (Eq. 30) on the :math:`m` free
    displacement unknowns; an eigenvalue counts as zero below ``zero_tolerance``
    times the largest. With :math:`k - 1` zero eigenvalues, :math:`k_{pm} = k - (m - n
    + 1)` (Eq. 32); :math:`\beta^*_h = \sqrt{\lambda_k}` if :math:`k_{pm} = 0`, else 0.

    With ``full``, also :math:`\beta_h` of Eq. (22): the smallest :math:`\lambda` of
    :math:`\mathbf B \mathbf S^{-1} \mathbf B^T \mathbf M = \lambda \mathbf T \mathbf M`
    with :math:`\mathbf T` from :func:`dual_norm_matrix` (the supremum over
    :math:`\mathbf V` of Eq. 22 is :math:`\sqrt{\mathbf M^T \mathbf B \mathbf S^{-1}
    \mathbf B^T \mathbf M}`).

    Args:
        problem: The contact problem (its spaces, Dirichlet conditions and pairs).
        h: Element size.
        norm: ``"H1"`` (Eq. 28) or ``"energy"`` (:math:`\mathbf S = \mathbf K`, Eq. 23).
        full: Whether to compute :math:`\beta_h` of Eq. (22) too.
        zero_tolerance: Relative size below which an eigenvalue is zero.

    Meant for small meshes: the cost is cubic in :math:`m`.
    """
    B = constraint_matrix(problem)
    free = dirichlet_free(problem)
    S_blocks = norm_matrices(problem, norm)
    S = scipy.linalg.block_diag(*[gather_dense(Si) for Si in S_blocks])
    for Si in S_blocks:
        Si.destroy()
    S = S[np.ix_(free, free)]
    B = B[:, free]
    P = stack_pairs(problem, lambda pair: _gather_matrix(multiplier_mass(pair)))
    n, m = B.shape
    G = B.T @ np.linalg.solve(P, B) / h
    lam = scipy.linalg.eigh(G, S, eigvals_only=True)
    zeros = int(np.count_nonzero(lam <= zero_tolerance * lam[-1]))
    k = zeros + 1
    k_pm = k - (m - n + 1)
    beta = float(np.sqrt(lam[zeros])) if k_pm == 0 else 0.0
    beta_full = None
    if full:
        if k_pm == 0:
            T = stack_pairs(problem, dual_norm_matrix)
            Sigma = B @ scipy.linalg.cho_solve(scipy.linalg.cho_factor(S), B.T)
            beta_full = float(np.sqrt(scipy.linalg.eigh(Sigma, T, eigvals_only=True)[0]))
        else:
            beta_full = 0.0
    return InfSup(beta, k_pm, n, m, h, beta_full, tuple(float(x) for x in lam[zeros : zeros + 4]))


def _gather_matrix(A: PETSc.Mat) -> npt.NDArray[np.floating]:
    D = gather_dense(A)
    A.destroy()
    return D


def stack_pairs(problem: LinearContactProblem, matrix) -> npt.NDArray[np.floating]:
    """Block diagonal over the pairs of a per-pair dense matrix, active rows only."""
    blocks = []
    for pair, op in zip(problem.pairs, assembled(problem).operators, strict=True):
        D = matrix(pair)
        keep = np.setdiff1d(np.arange(D.shape[0]), op.inactive)
        blocks.append(D[np.ix_(keep, keep)])
    return scipy.linalg.block_diag(*blocks)

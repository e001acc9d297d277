# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""How accurate a solve of Eq. (18) can be: a round-off bound from the conditioning.

The computed solution :math:`\hat{\mathbf x}` of :math:`\mathbf A\mathbf x = \mathbf b`
is the exact solution of a system perturbed componentwise by the backward error
(Oettli-Prager)

.. math::
    \omega = \max_i \frac{|\mathbf b - \mathbf A\hat{\mathbf x}|_i}
    {(|\mathbf A||\hat{\mathbf x}| + |\mathbf b|)_i},

so that, to first order, every unknown is within

.. math::
    |\delta x_i| \le \omega\,\bigl(|\mathbf A^{-1}|\,(|\mathbf A||\hat{\mathbf x}| +
    |\mathbf b|)\bigr)_i

of the exact solution of Eq. (18). On a row where :math:`(|\mathbf A||\hat{\mathbf x}| +
|\mathbf b|)_i` is itself round-off (its unknowns vanish, as :math:`u_x` at
:math:`\nu = 0`), :math:`\|\mathbf A_{i:}\|_\infty\|\hat{\mathbf x}\|_\infty` is added
to it (Arioli, Demmel and Duff, 1989), or :math:`\omega` would be of order 1. The
largest of these over the unknowns of one field (a space, a pair's multiplier) is
:math:`\|\mathbf P\,|\mathbf A^{-1}|\,\mathrm{diag}(\mathbf g)\|_\infty` with
:math:`\mathbf P` the field's rows: a 1-norm of a linear operator, estimated by
Higham's block estimator (:func:`scipy.sparse.linalg.onenormest`) from solves with the problem's own
factorization. The estimator can underestimate (rarely by more than a factor 3, hence
:data:`SAFETY`), and the residual's own round-off sets a floor :math:`\omega \ge
\epsilon`. Material contrast, element-size ratio, the scale of the scene and near
incompressibility all enter through :math:`|\mathbf A^{-1}||\mathbf A|`: a patch-test
error within the bound is round-off, one above it is a defect of the discretization.

For reports, :attr:`RoundOff.condition` is the normwise 1-norm condition number of the
equilibrated :math:`\mathbf D\mathbf A\mathbf D`, :math:`D_{ii} = \max_j
|A_{ij}|^{-1/2}` (one sweep of Ruiz's scaling).
"""

from __future__ import annotations

from dataclasses import dataclass

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import scipy.sparse.linalg

from dolfinx_contact_s2s.problem import LinearContactProblem

__all__ = ["RoundOff", "round_off_bound"]

#: Factor covering the 1-norm estimator's underestimate.
SAFETY: float = 3.0


@dataclass(frozen=True)
class RoundOff:
    r"""The round-off bound of one solve.

    Attributes:
        condition: :math:`\kappa_1(\mathbf D\mathbf A\mathbf D)`, the estimated
            condition number of the equilibrated saddle point.
        backward_error: :math:`\omega` (at least :math:`\epsilon`).
        displacement: Per space, the bound on :math:`\max_i |\delta u_i|`.
        multiplier: Per pair, the bound on :math:`\max_i |\delta\lambda_i|`.
    """

    condition: float
    backward_error: float
    displacement: list[float]
    multiplier: list[float]


def _equilibration(A: PETSc.Mat) -> PETSc.Vec:
    r""":math:`D_{ii} = \max_j |A_{ij}|^{-1/2}` (1 for a zero row)."""
    indptr, _, values = A.getValuesCSR()
    rows = np.repeat(np.arange(indptr.size - 1), np.diff(indptr))
    big = np.zeros(indptr.size - 1)
    np.maximum.at(big, rows, np.abs(values))
    d = A.createVecLeft()
    d.array[:] = 1.0 / np.sqrt(np.where(big > 0.0, big, 1.0))
    return d


def _absolute(A: PETSc.Mat) -> PETSc.Mat:
    r""":math:`|\mathbf A|`, entrywise."""
    indptr, cols, values = A.getValuesCSR()
    return PETSc.Mat().createAIJ(A.getSizes(), csr=(indptr, cols, np.abs(values)), comm=A.getComm())


class _Estimator:
    """1-norms of operators built from solves with a factorized ``A`` (collective)."""

    def __init__(self, A: PETSc.Mat, ksp: PETSc.KSP):
        self.comm = A.getComm().tompi4py()
        self.ksp = ksp
        self.n = A.getSize()[0]
        self.start, self.end = A.getOwnershipRange()
        self.rhs, self.sol = A.createVecRight(), A.createVecRight()

    def destroy(self) -> None:
        self.rhs.destroy()
        self.sol.destroy()

    def solve(self, v: np.ndarray, transpose: bool) -> np.ndarray:
        """``inv(A) v`` (or ``inv(A)^T v``) of local arrays."""
        self.rhs.array[:] = v
        (self.ksp.solveTranspose if transpose else self.ksp.solve)(self.rhs, self.sol)
        return self.sol.array_r.copy()

    def norm1(self, left: np.ndarray, right: np.ndarray) -> float:
        r""":math:`\|\mathrm{diag}(l)\,\mathbf A^{-T}\mathrm{diag}(r)\|_1`.

        ``l`` and ``r`` are this process's parts; the norm is the largest
        :math:`r_j (|\mathbf A^{-1}| l)_j`.
        """
        s, e = self.start, self.end

        def columns(f):
            def apply(v: np.ndarray) -> np.ndarray:
                v = np.asarray(v)
                one = v.ndim == 1
                out = [
                    np.concatenate(self.comm.allgather(f(c[s:e])))
                    for c in (v[:, None] if one else v).T
                ]
                return out[0] if one else np.column_stack(out)

            return apply

        op = scipy.sparse.linalg.LinearOperator(
            (self.n, self.n),
            matvec=columns(lambda v: left * self.solve(right * v, True)),
            rmatvec=columns(lambda v: right * self.solve(left * v, False)),
            dtype=np.float64,
        )
        # SciPy's estimator draws random columns from NumPy's legacy global generator:
        # the same seed on every process keeps the collective solves in step; the
        # caller's state is restored.
        state = np.random.get_state()  # noqa: NPY002
        try:
            np.random.seed(20010101)  # noqa: NPY002
            return float(scipy.sparse.linalg.onenormest(op, t=min(2, self.n)))
        finally:
            np.random.set_state(state)  # noqa: NPY002


def round_off_bound(problem: LinearContactProblem, safety: float = SAFETY) -> RoundOff:
    r"""The round-off bound of the last solve of ``problem`` (see the module).

    Collective. Uses the problem's factorization (a few solves and transposed solves per
    field); call after :meth:`~dolfinx_contact_s2s.problem.LinearContactProblem.solve`.

    Args:
        problem: A solved problem (``kind="aij"``, a direct solver).
        safety: Factor on the estimated norms.

    Returns:
        The condition estimate, the backward error and the bounds on the displacements
        and multipliers.
    """
    A, b, x, ksp = problem.A, problem.b, problem.x, problem.solver
    if A is None or b is None or x is None:
        raise ValueError("round_off_bound needs a solved problem: call solve() first.")
    if A.getType() == PETSc.Mat.Type.NEST:
        raise ValueError("round_off_bound needs the assembled saddle point (kind='aij').")
    comm = A.getComm().tompi4py()
    eps = np.finfo(np.float64).eps
    # Oettli-Prager backward error.
    absolute = _absolute(A)
    g = A.createVecLeft()
    ax = A.createVecLeft()
    # |A||x|, not |A x| or |A| x: with cancellation either can vanish on a row whose
    # residual is round-off, and omega would be 1.
    magnitude = x.copy()
    magnitude.abs()
    absolute.mult(magnitude, ax)
    magnitude_r = magnitude.array_r.copy()
    magnitude.destroy()
    g.array[:] = ax.array_r + np.abs(b.array_r)
    A.mult(x, ax)
    r = np.abs(b.array_r - ax.array_r)
    # A row whose (|A||x| + |b|)_i is itself round-off (its unknowns are exactly zero,
    # e.g. u_x at nu = 0) gets the normwise ||A_i|| ||x|| (Arioli, Demmel & Duff 1989),
    # or its residual's round-off alone would make omega of order 1.
    ones = A.createVecRight()
    ones.set(1.0)
    absolute.mult(ones, ax)
    ones.destroy()
    reach = ax.array_r * comm.allreduce(float(np.max(magnitude_r, initial=0.0)), op=MPI.MAX)
    tau = 1000 * A.getSize()[0] * eps * (reach + np.abs(b.array_r))
    small = (g.array_r <= tau) & (r > 0)
    g.array[small] += reach[small]
    local = r / np.where(g.array_r > 0, g.array_r, 1.0)
    omega = max(eps, comm.allreduce(float(np.max(local, initial=0.0)), op=MPI.MAX))
    absolute.destroy()
    ax.destroy()

    estimator = _Estimator(A, ksp)
    try:
        d = _equilibration(A)
        ones = np.ones(d.getLocalSize())
        scaled = A.copy()
        scaled.diagonalScale(d, d)
        norm = scaled.norm(PETSc.NormType.NORM_1)
        scaled.destroy()
        # inv(DAD) = D^-1 inv(A) D^-1: its 1-norm is that of diag(1/d) A^-T diag(1/d).
        condition = norm * estimator.norm1(1.0 / d.array_r, 1.0 / d.array_r)
        d.destroy()
        bounds = []
        for is_ in problem.fields.values():
            mask = np.zeros(ones.size)
            mask[is_.getIndices() - estimator.start] = 1.0
            bounds.append(safety * omega * estimator.norm1(g.array_r.copy(), mask))
    finally:
        estimator.destroy()
        g.destroy()
    nspaces = len(problem.spaces)
    return RoundOff(float(condition), float(omega), bounds[:nspaces], bounds[nspaces:])

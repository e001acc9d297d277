# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The ``"condensed-active-set"`` algorithm: every active set from one factorization.

For linear bodies the saddle points of the active-set iterations (Eq. 18 with the
inactive multipliers set to zero) differ from the tied one, :math:`\mathbf M \mathbf x
= \mathbf b` with every covered multiplier a constraint, only in the rows and columns of
the inactive multipliers :math:`\mathcal I`. The system of an active set is the tied one
with a free slack :math:`\mathbf t` on the gap rows of :math:`\mathcal I` and
:math:`\boldsymbol\lambda_{\mathcal I} = 0`:

.. math::
    \mathbf x = \mathbf x_0 + \mathbf M^{-1} \mathbf P_{\mathcal I} \mathbf t, \qquad
    \mathbf W_{\mathcal I \mathcal I} \mathbf t = -\boldsymbol\lambda_{0,\mathcal I},
    \qquad \boldsymbol\lambda_{\mathcal A} = \boldsymbol\lambda_{0,\mathcal A} +
    \mathbf W_{\mathcal A \mathcal I} \mathbf t, \qquad \tilde{\mathbf g}_{\mathcal I} =
    -\mathbf t, \quad \tilde{\mathbf g}_{\mathcal A} = 0,

with :math:`\mathbf x_0` the tied solution at the step's load and :math:`\mathbf W =
(\mathbf M^{-1})_{\lambda\lambda}` the multiplier block of the inverse, computed once by
MUMPS's selected entries of the inverse (ICNTL(30)). Unlike a Schur complement on the
multipliers, this needs no inverse of :math:`\mathbf K`: a body held by contact alone
(the Hertz cylinder) is fine. :math:`\mathbf W_{\mathcal I \mathcal I}` is singular
exactly when the active set leaves a body free, which the support check of every active
set (Eq. 33) reports first.

So the iterations of ``"active-set"`` (the same sets, updates and tolerance) cost a
dense solve each instead of a factorization; a load step costs two solves with the one
factor (the tied solution, and the expansion :math:`\mathbf M^{-1}(\mathbf b +
\mathbf P_{\mathcal I} \mathbf t)` of the converged set). The checks are those of
``"active-set"``: the residual of every solve, the support of every active set, and at
the end of a step the complementarity residual of the multipliers and of the weighted
gaps :math:`\mathbf B \mathbf U + \mathbf G` of the expanded displacement, which the
dense iteration does not see.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import typing

import numpy as np
import numpy.typing as npt
import scipy.linalg

from dolfinx_contact_s2s.la import add_scaled
from dolfinx_contact_s2s.mumps import inverse_block
from dolfinx_contact_s2s.options import mumps_factor
from dolfinx_contact_s2s.unilateral.active_set import iterate
from dolfinx_contact_s2s.unilateral.history import LoadStep
from dolfinx_contact_s2s.unilateral.iteration import ContactIteration

__all__ = ["MAX_MULTIPLIERS", "CondensedActiveSet"]

#: Most multipliers (over all pairs): :math:`\mathbf W` is dense on every process
#: (5,000: 200 MB), and an iteration solves with up to all of it (:math:`4 \cdot 10^{10}`
#: flops).
MAX_MULTIPLIERS = 5_000


class CondensedActiveSet:
    """The factorized tied system of one assembly and its condensed active-set steps.

    Made once per :meth:`~.UnilateralContactProblem.solve`, after the assembly (which
    builds the tied system at load 1); :meth:`solve_step` serves every load step.
    Call :meth:`destroy`.
    """

    def __init__(self, run: ContactIteration):
        """Check the solver and keep the tied right-hand side at load 1.

        Raises:
            ValueError: On every rank, if the solver is not a MUMPS factorization or
                there are more than :data:`MAX_MULTIPLIERS` multipliers.
        """
        self.run = run
        system = self.system = run.system
        self.comm = system.comm
        assert system.A is not None and system.b is not None
        pc = system.solver.getPC()
        if pc.getType() not in ("lu", "cholesky") or pc.getFactorSolverType() != "mumps":
            raise ValueError(
                "the 'condensed-active-set' algorithm needs a MUMPS factorization "
                f"(pc_type 'cholesky' or 'lu', not {pc.getType()!r}, with "
                "pc_factor_mat_solver_type 'mumps'): use 'active-set' with other solvers"
            )
        if system.linearized:
            raise ValueError(
                "the 'condensed-active-set' algorithm solves linear bodies: finite "
                "deformation changes the system in every Newton iteration (use 'active-set')"
            )
        names = [f"lambda{j}" for j in range(len(system.pairs))]
        #: Per pair, the owned global rows of its multipliers in the system.
        self.rows = [system.fields[name].getIndices().astype(np.int64) for name in names]
        #: All multiplier rows, sorted: the order of :attr:`W`.
        self.order = np.sort(np.concatenate(self.comm.allgather(np.concatenate(self.rows))))
        if self.order.size > MAX_MULTIPLIERS:
            raise ValueError(
                f"{self.order.size} multipliers: the 'condensed-active-set' algorithm "
                f"stores a dense block of the inverse on them, at most {MAX_MULTIPLIERS}; "
                "use 'active-set'"
            )
        self.positions = [np.searchsorted(self.order, r) for r in self.rows]
        self.symmetric = pc.getType() == "cholesky"
        self.b1 = system.b.copy()  # the tied right-hand side at load 1
        self.W: npt.NDArray[np.floating] | None = None
        self.lam0 = np.zeros(self.order.size)

    def destroy(self) -> None:
        """Destroy the stored right-hand side."""
        self.b1.destroy()

    # --- the tied solves --------------------------------------------------------------

    def _gather(self, values: typing.Sequence[npt.NDArray]) -> npt.NDArray:
        """Per pair owned values to one array in the order of :attr:`W`, on every rank."""
        out = np.zeros(self.order.size, dtype=np.asarray(values[0]).dtype)
        pieces = self.comm.allgather(
            (np.concatenate(self.positions), np.concatenate([np.asarray(v) for v in values]))
        )
        for positions, v in pieces:
            out[positions] = v
        return out

    def _owned(self, values: npt.NDArray) -> list[npt.NDArray]:
        return [values[p].copy() for p in self.positions]

    def _solve_tied(self, step: LoadStep, slack: npt.NDArray[np.floating]) -> None:
        r"""Solve the tied system at the step's load, ``slack`` added to its gap rows.

        The right-hand side as :meth:`~dolfinx_contact_s2s.system.ContactSystem.build`
        makes it: :math:`t \mathbf F` and :math:`\mathbf G(t) + t \mathbf B \mathbf U_D`,
        the rigid targets' motions at the load included.
        """
        system, load = self.system, step.load
        system.load = load  # the weighted gaps read it (the rigid targets' motions)
        b = system.b
        assert b is not None
        b.array[:] = load * self.b1.getArray(readonly=True)
        start = b.getOwnershipRange()[0]
        for j, op in enumerate(system.operators):
            G = op.gap(load)
            for V, B in op.blocks:
                add_scaled(B, system.values[system.space_index(V)], load, G)
            values = G.array_r + slack[self.positions[j]]
            values[self.run.complementarity.pinned(j)] = 0.0
            b.array[self.rows[j] - start] = values
            G.destroy()
        self.run.solve_linear(step)

    # --- the iteration --------------------------------------------------------------

    def _dense(self, active: npt.NDArray[np.bool_]) -> tuple[npt.NDArray, npt.NDArray]:
        r""":math:`\boldsymbol\lambda` and the slack :math:`\mathbf t` of an active set."""
        assert self.W is not None
        lam, slack = self.lam0.copy(), np.zeros(self.order.size)
        if self.comm.rank == 0:
            free = np.flatnonzero(~active & ~self.pinned)
            if free.size:
                slack[free] = scipy.linalg.solve(
                    self.W[np.ix_(free, free)],
                    -self.lam0[free],
                    assume_a="sym" if self.symmetric else "gen",
                )
                lam += self.W[:, free] @ slack[free]
            lam[~active] = 0.0
        return self.comm.bcast((lam, slack), root=0)

    def solve_step(
        self, run: ContactIteration, step: LoadStep, active: list[npt.NDArray[np.bool_]]
    ) -> list[npt.NDArray[np.bool_]]:
        r"""The iterations of ``"active-set"`` on :math:`\mathbf W`, then the expansion.

        Args:
            run: The solve's shared state (the one this object was made with).
            step: The load step; its iterations are appended.
            active: Per pair, the first active set (owned multipliers).

        Returns:
            The converged active set.

        Raises:
            ContactConvergenceError: As ``"active-set"``, and if the expanded solution
                does not satisfy the complementarity conditions to the tolerance.
        """
        comp = run.complementarity
        self._solve_tied(step, np.zeros(self.order.size))
        self.lam0 = self._gather(comp.lambdas())
        if self.W is None:
            self.pinned = self._gather([comp.pinned(j) for j in range(len(self.rows))])
            with self.system.timed("solve"):
                F = mumps_factor(self.system.solver)
                assert F is not None
                self.W = inverse_block(F, self.order)
        found: list[tuple[npt.NDArray, npt.NDArray]] = []

        def evaluate(active: list[npt.NDArray[np.bool_]]) -> tuple[list, float]:
            run.check_active_support(step, comp.released(active))
            with self.system.timed("solve"):
                lam, slack = self._dense(self._gather(active))
            found[:] = [(lam, slack)]
            return comp.evaluate(self._owned(lam), self._owned(-slack))

        return iterate(run, step, active, evaluate, lambda: self._expand(step, *found[-1]))

    def _expand(self, step: LoadStep, lam: npt.NDArray, slack: npt.NDArray) -> None:
        r"""Solve for :math:`\mathbf U` of the converged set; check Eq. (1) on it."""
        system, comp = self.system, self.run.complementarity
        self._solve_tied(step, slack)
        for f, values in zip(system.multipliers, self._owned(lam), strict=True):
            f.x.array[: values.size] = values  # exactly zero where inactive
            f.x.scatter_forward()
        _, residual = comp.evaluate(comp.lambdas(), comp.weighted_gaps())
        if residual > self.run.tolerance:
            self.run.fail(
                f"at load {step.load:g} the condensed multipliers and the expanded "
                f"displacement leave a complementarity residual {residual:.2e} above the "
                f"tolerance {self.run.tolerance:.1e} (Eq. 1 on B U + G): the tied system "
                "is too ill-conditioned for the tolerance (use 'active-set')"
            )

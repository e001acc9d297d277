# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The ``"snes-vi"`` algorithm: PETSc's reduced-space variational-inequality Newton method.

The mixed complementarity problem of the active-set method handed to
``SNESVINEWTONRSLS`` with the bounds :math:`\lambda \ge 0` and free displacements
(:class:`SnesVIStep`).

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import typing

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.unilateral.complementarity import owned_indices
from dolfinx_contact_s2s.unilateral.history import LoadStep
from dolfinx_contact_s2s.unilateral.iteration import ContactIteration

__all__ = ["SnesVIStep", "snes_options", "solve_step"]


def snes_options(max_iterations: int) -> dict[str, typing.Any]:
    """Solver defaults of the ``"snes-vi"`` algorithm, besides the linear solver's."""
    # Full semismooth Newton steps: backtracking (bt) stalls on Hertz, l2 halves
    # its steps for hundreds of iterations, cp stops out of balance (README).
    return {
        "snes_type": "vinewtonrsls",
        "snes_linesearch_type": "basic",
        "snes_max_it": max_iterations,
    }


def _part(v: PETSc.Vec, is_: PETSc.IS) -> npt.NDArray[np.floating]:
    """A copy of the owned entries of ``v`` at ``is_``."""
    sub = v.getSubVector(is_)
    values = sub.array_r.copy()
    v.restoreSubVector(is_, sub)
    return values


def _norm(comm: MPI.Comm, values: npt.NDArray[np.floating]) -> float:
    """Euclidean norm of a vector whose owned entries are ``values`` on each process."""
    return float(np.sqrt(comm.allreduce(float(values @ values))))


_SNES_REASONS = {
    getattr(PETSc.SNES.ConvergedReason, name): name
    for name in dir(PETSc.SNES.ConvergedReason)
    if name.startswith(("DIVERGED", "CONVERGED"))
}


class SnesVIStep:
    r"""One load step by PETSc's ``SNESVINEWTONRSLS``.

    :math:`F(\mathbf x) = \mathbf S (\mathbf A \mathbf x - \mathbf b)` with
    :math:`\mathbf S = \mathrm{diag}(\mathbf I, -c)`: the displacement rows are the
    equilibrium of Eq. (18), the multiplier rows :math:`c_j \tilde g_j`; with the
    bounds :math:`0 \le \lambda` (displacements free) the variational inequality is
    exactly Eq. (1). The Jacobian :math:`\mathbf S \mathbf A` is constant. The start
    is a saddle-point solve with the given active set (projected onto
    :math:`\lambda \ge 0`); convergence is tested as for ``"active-set"``
    (:meth:`converged`). Call :meth:`solve`, then :meth:`destroy`.
    """

    def __init__(self, run: ContactIteration, step: LoadStep, active: list[npt.NDArray[np.bool_]]):
        """Solve the start and set up the function, Jacobian and bounds.

        Args:
            run: The solve's shared state.
            step: The load step; its iterations are appended.
            active: Per pair, the first active set (owned multipliers).
        """
        self.run, self.step = run, step
        system, comp = run.system, run.complementarity
        self.system, self.comp = system, comp
        system.build(comp.released(active), load=step.load)
        run.solve_linear(step)
        assert system.x is not None
        self.x = system.x.copy()
        system.build(None, load=step.load)
        assert system.A is not None and system.b is not None
        nb = len(system.spaces)
        self.lambda_sets = list(system.fields.values())[nb:]
        self.S, self.lower, self.upper = (system.b.duplicate() for _ in range(3))
        self.S.set(1.0)
        self.lower.set(PETSc.NINFINITY)
        self.upper.set(PETSc.INFINITY)
        for is_, c in zip(self.lambda_sets, comp.scales, strict=True):
            # c = 0 at the inactive multipliers (uncovered, duplicates), whose rows of A
            # read lambda_k = 0: scaled by -1, not 0, which left the Jacobian singular.
            scale = np.where(c.array_r != 0.0, -c.array_r, -1.0)
            for vec, values in ((self.S, scale), (self.lower, 0.0)):
                sub = vec.getSubVector(is_)
                sub.array[:] = values
                vec.restoreSubVector(is_, sub)
        self.J = system.A.copy()
        self.J.diagonalScale(self.S)
        # S A is not symmetric: the default factorization is LU here.
        self.J.setOption(PETSc.Mat.Option.SYMMETRIC, False)
        if system.options.get("pc_type") == "cholesky":
            system.options.set_default("pc_type", "lu")
        # The semismooth VI types add to the diagonal, absent from the multiplier block.
        self.J.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
        self.Sb = system.b.copy()
        self.Sb.pointwiseMult(self.Sb, self.S)
        self.f, self.work = system.b.duplicate(), system.b.duplicate()
        self.u_rows = PETSc.IS().createGeneral(
            np.concatenate([is_.getIndices() for is_ in list(system.fields.values())[:nb]]),
            comm=system.comm,
        )
        self.jx, self.xu = system.b.duplicate(), system.b.duplicate()
        self.accepted = False
        self.floating: list[npt.NDArray[np.int64]] | None = None
        self.state = [a.copy() for a in active]

    def function(self, snes: PETSc.SNES | None, x: PETSc.Vec, f: PETSc.Vec) -> None:
        r""":math:`F(\mathbf x) = \mathbf S \mathbf A \mathbf x - \mathbf S \mathbf b`."""
        self.J.mult(x, f)
        f.axpy(-1.0, self.Sb)

    def converged(self, snes: PETSc.SNES, it: int, norms: tuple) -> int:
        """The convergence test: complementarity and equilibrium, as for ``"active-set"``."""
        run, comp, comm = self.run, self.comp, self.system.comm
        x, work = snes.getSolution(), self.work
        self.function(None, x, work)
        lam, gaps = [], []
        for is_, c in zip(self.lambda_sets, comp.scales, strict=True):
            lam.append(_part(x, is_))
            cg = _part(work, is_)
            gaps.append(np.divide(cg, c.array_r, out=np.zeros_like(cg), where=c.array_r != 0))
        z, residual = comp.evaluate(lam, gaps)
        # The same rule as the active-set loop, hysteresis against round-off included.
        new, entered, left = comp.update(self.state, z)
        run.record(self.step, new, entered, left, residual)
        self.state[:] = new
        released = comp.released(new)
        if comp.free_motions(released):
            self.floating = released  # reported after the solve, with the motions
            return PETSc.SNES.ConvergedReason.DIVERGED_FUNCTION_DOMAIN
        # PETSc's VI solver leaves the multipliers it holds at their bound out of its
        # Newton system: if they leave a body free, the next step is singular (and its
        # iterate arbitrary: it can show any active set).
        held = self._held(x, work)
        if comp.free_motions(held):
            self.floating = held
            return PETSc.SNES.ConvergedReason.DIVERGED_FUNCTION_DOMAIN
        # Equilibrium relative to the larger of the loads and the elastic forces K U.
        x.copy(self.xu)
        for is_ in self.lambda_sets:
            sub = self.xu.getSubVector(is_)
            sub.set(0.0)
            self.xu.restoreSubVector(is_, sub)
        self.J.mult(self.xu, self.jx)
        scale = max(
            _norm(comm, _part(self.Sb, self.u_rows)),
            _norm(comm, _part(self.jx, self.u_rows)),
            np.finfo(float).tiny,
        )
        equilibrium = _norm(comm, _part(work, self.u_rows)) / scale
        self.accepted = residual <= run.tolerance and equilibrium <= self.system.residual_tolerance
        if self.accepted:
            return PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS
        if it >= snes.getTolerances()[3]:
            return PETSc.SNES.ConvergedReason.DIVERGED_MAX_IT
        return PETSc.SNES.ConvergedReason.ITERATING

    def _held(self, x: PETSc.Vec, f: PETSc.Vec) -> list[npt.NDArray[np.int64]]:
        r"""Per pair, the global multipliers the next Newton system leaves out.

        The rule of PETSc's ``SNESVIGetActiveSetIS`` at the lower bound 0:
        :math:`\lambda_i \le 10^{-8}` and :math:`F_i \ge 0`.
        """
        return [
            owned_indices(op.G, (_part(x, is_) <= 1e-8) & (_part(f, is_) >= 0.0))
            for op, is_ in zip(self.comp.operators, self.lambda_sets, strict=True)
        ]

    def solve(self) -> list[npt.NDArray[np.bool_]]:
        """Run the SNES; the converged active set, the solution scattered to the system.

        Raises:
            ContactConvergenceError: If the SNES stops without meeting the tests.
        """
        run, step, system = self.run, self.step, self.system
        snes = PETSc.SNES().create(system.comm)
        try:
            snes.setOptionsPrefix(system.options.prefix)
            snes.setFunction(self.function, self.f)
            snes.setJacobian(lambda snes, x, J, P: None, self.J)
            snes.setType("vinewtonrsls")
            snes.setTolerances(max_it=run.max_iterations)
            system.options.apply(snes)
            snes.setVariableBounds(self.lower, self.upper)
            snes.setConvergenceTest(self.converged)
            with system.timed("solve"):
                snes.solve(None, self.x)
            reason = snes.getConvergedReason()
            if reason > 0 and not self.accepted:
                # PETSc's VI solver can stop on its own tests (its line search, say),
                # which do not see the equilibrium: measured on Hertz with the cp line
                # search, stopped with 3% out of balance.
                run.fail(
                    f"SNES ({snes.getType()}) stopped at load {step.load:g} "
                    f"({_SNES_REASONS.get(reason, reason)}) after "
                    f"{snes.getIterationNumber()} iterations without meeting the "
                    "complementarity and equilibrium tests (try algorithm='active-set')"
                )
            if reason <= 0:
                # A body that floats once its contact opens makes the Newton systems
                # singular: say so rather than suggest more iterations. Seen by the
                # complementarity test's set, or at the end by the multipliers PETSc's
                # VI solver holds at their bound (they carry no force).
                if self.floating is None:  # global indices, as released(): a rank's own rows
                    self.floating = [
                        owned_indices(op.G, _part(self.x, is_) <= 0.0)
                        for op, is_ in zip(self.comp.operators, self.lambda_sets, strict=True)
                    ]
                run.check_active_support(step, self.floating)
                run.fail(
                    f"SNES ({snes.getType()}) did not converge at load {step.load:g}: "
                    f"{_SNES_REASONS.get(reason, reason)} after {snes.getIterationNumber()} "
                    "iterations (try more snes_max_it, "
                    "or algorithm='active-set')"
                )
            step.converged = True
            assert system.x is not None
            self.x.copy(system.x)
            system.scatter()
            return self.state
        finally:
            snes.destroy()

    def destroy(self) -> None:
        """Destroy the vectors, matrices and index sets of the step."""
        for obj in (
            self.x,
            self.S,
            self.lower,
            self.upper,
            self.J,
            self.Sb,
            self.f,
            self.work,
            self.jx,
            self.xu,
            self.u_rows,
        ):
            obj.destroy()


def solve_step(
    run: ContactIteration, step: LoadStep, active: list[npt.NDArray[np.bool_]]
) -> list[npt.NDArray[np.bool_]]:
    """One load step by ``SNESVINEWTONRSLS`` (:class:`SnesVIStep`); the converged active set."""
    solver = SnesVIStep(run, step, active)
    try:
        return solver.solve()
    finally:
        solver.destroy()

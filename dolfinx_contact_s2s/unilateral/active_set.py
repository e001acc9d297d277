# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The ``"active-set"`` algorithm: semismooth Newton on the complementarity function.

The primal-dual active set method on :math:`C_j = \lambda_j - \max(0, \lambda_j - c_j
\tilde g_j)`: for linear elastic bodies every iteration is one saddle-point solve of
Eq. (18) with the inactive multipliers set to zero, and the iteration ends when the
active set repeats, which makes :math:`C = 0` up to round-off.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.condensation import DualCondensation
from dolfinx_contact_s2s.system import ContactSystem
from dolfinx_contact_s2s.unilateral.history import LoadStep
from dolfinx_contact_s2s.unilateral.iteration import ContactIteration

__all__ = ["iterate", "solve_step"]


def solve_step(
    run: ContactIteration, step: LoadStep, active: list[npt.NDArray[np.bool_]], dual: bool = False
) -> list[npt.NDArray[np.bool_]]:
    """Semismooth Newton (primal-dual active set) iterations of one load step.

    Args:
        run: The solve's shared state.
        step: The load step; its iterations are appended.
        active: Per pair, the first active set (owned multipliers).
        dual: Condense each active set's saddle point to a symmetric positive definite
            system on the displacements and solve it by CG + GAMG (``"dual-active-set"``,
            :class:`~dolfinx_contact_s2s.condensation.DualCondensation`: the inactive
            multipliers have no row of B; options under the problem's prefix + ``dual_``).

    Returns:
        The converged active set.

    Raises:
        ContactConvergenceError: If the iteration does not converge, or the active set
            repeats with the residual above the tolerance.
    """
    system, comp = run.system, run.complementarity
    previous: list[npt.NDArray[np.floating]] = []

    def evaluate(active: list[npt.NDArray[np.bool_]]) -> tuple[list, float]:
        released = comp.released(active)
        system.build(released, load=step.load)
        run.check_active_support(step, released)
        if dual:
            condensation = DualCondensation(
                system, petsc_options_prefix=f"{system.options.prefix}dual_"
            )
            try:  # from the previous set's solution: 8-14% fewer CG iterations (Hertz)
                condensation.solve(previous[-1] if previous else None)
            except RuntimeError as error:
                run.fail(f"solve {len(step.iterations) + 1} at load {step.load:g}: {error}")
            finally:
                condensation.destroy()
        else:
            _warm_start(system, previous[-1] if previous else None)
            run.solve_linear(step)
        assert system.x is not None
        previous[:] = [system.x.getArray(readonly=True).copy()]
        return comp.evaluate(comp.lambdas(), comp.weighted_gaps())

    return iterate(run, step, active, evaluate)


def iterate(
    run: ContactIteration,
    step: LoadStep,
    active: list[npt.NDArray[np.bool_]],
    evaluate: Callable[[list[npt.NDArray[np.bool_]]], tuple[list, float]],
    finish: Callable[[], None] | None = None,
) -> list[npt.NDArray[np.bool_]]:
    r"""The active-set updates around ``evaluate(active) -> (z, residual)``.

    ``evaluate`` solves for an active set and returns :math:`z = \lambda - c \tilde g`
    and the complementarity residual; ``finish()`` runs once the set has converged.
    """
    comp = run.complementarity
    for _ in range(run.max_iterations):
        z, residual = evaluate(active)
        new, entered, left = comp.update(active, z)
        run.record(step, active, entered, left, residual)
        if entered == 0 and left == 0 and residual <= run.tolerance:
            if finish is not None:
                finish()
            step.converged = True
            return active
        if entered == 0 and left == 0:
            # The same set builds the same system: another solve would repeat this one.
            run.fail(
                f"solve {len(step.iterations)} at load {step.load:g}: the active set repeats "
                f"but the complementarity residual {residual:.2e} is above the tolerance "
                f"{run.tolerance:.1e}, and solving the same system again cannot lower it: "
                "the linear solves are not accurate enough for the tolerance (a tolerance "
                "below round-off, an approximate factorization, a loose iterative rtol)"
            )
        active = new
    run.fail(
        f"the active-set iteration did not converge in {run.max_iterations} solves "
        f"at load {step.load:g} (raise max_iterations, or take smaller load steps)"
    )


def _warm_start(system: ContactSystem, previous: npt.NDArray[np.floating] | None) -> None:
    """An iterative solver starts from the previous active set's solution.

    The active sets of consecutive iterations differ in a few rows: their solutions are
    close, and a Krylov method started there needs fewer iterations to the same
    ``rtol`` (measured against the right-hand side), if not many: 5% fewer GMRES
    iterations over the 6 and 13 active sets of a Hertz scene pressed by a prescribed
    displacement (Schur field split, 3,808 and 31,944 unknowns: 175 against 185, 669
    against 701). A direct solve ignores it.
    """
    if previous is None or system.solver.getType() == "preonly" or system.x is None:
        return
    if previous.size == system.x.getLocalSize():
        system.x.array[:] = previous
        system.solver.setInitialGuessNonzero(True)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""What every contact algorithm shares: the system, its complementarity, the history.

A :class:`ContactIteration` is made for one
:meth:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem.solve`; the algorithms
(:mod:`.active_set`, :mod:`.snes_vi`, :mod:`.penalty`) receive it with each load step,
and record every linear solve, check the support of an active set and report a failure
through it.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import logging
import typing
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.system import ContactSystem
from dolfinx_contact_s2s.unilateral.complementarity import Complementarity
from dolfinx_contact_s2s.unilateral.history import (
    ContactConvergenceError,
    ContactHistory,
    Iteration,
    LoadStep,
)

__all__ = ["ContactIteration"]

# Under the name of the unilateral package, where these messages were always logged.
logger = logging.getLogger("dolfinx_contact_s2s.unilateral")


@dataclass
class ContactIteration:
    """The state one unilateral solve shares with its algorithm.

    Attributes:
        system: The assembled saddle-point system.
        complementarity: Its complementarity conditions.
        algorithm: Name of the algorithm (for the history and the log).
        max_iterations: Largest number of linear solves per load step (of Uzawa
            updates, for the augmented Lagrangian).
        tolerance: Largest relative complementarity residual of a converged solve.
        monitor: Called with every recorded :class:`~.history.Iteration`, or None.
        history: The history of this solve.
    """

    system: ContactSystem
    complementarity: Complementarity
    algorithm: str
    max_iterations: int
    tolerance: float
    monitor: Callable[[Iteration], None] | None = None
    history: ContactHistory = field(init=False)

    def __post_init__(self) -> None:
        """Start an empty history."""
        self.history = ContactHistory(self.algorithm)

    def record(
        self,
        step: LoadStep,
        active: list[npt.NDArray[np.bool_]],
        entered: int,
        left: int,
        residual: float,
        outer: int = 0,
        stick: list[npt.NDArray[np.bool_]] | None = None,
    ) -> None:
        """Append the solve with the active set ``active`` to ``step``, log it, monitor it.

        With friction, ``stick`` holds the sticking multipliers of every pair.
        """
        counts, sets = self.complementarity.counts(active)
        sticking, stick_sets = self.complementarity.counts(stick) if stick else ((), ())
        iteration = Iteration(counts, entered, left, residual, sets, outer, sticking, stick_sets)
        step.iterations.append(iteration)
        logger.info(
            "contact %s, load %g, solve %d: active %s (stick %s), +%d -%d, residual %.2e",
            self.algorithm,
            step.load,
            len(step.iterations),
            counts,
            sticking,
            entered,
            left,
            residual,
        )
        if self.monitor is not None:
            self.monitor(iteration)

    def fail(self, message: str) -> typing.NoReturn:
        """Raise :class:`~.history.ContactConvergenceError` with the history."""
        raise ContactConvergenceError(message, self.history)

    def check_active_support(self, step: LoadStep, released: list[npt.NDArray[np.int64]]) -> None:
        """Raise if the active set leaves a body free (Eq. 33 on the active rows only).

        A body held by contact alone floats once its contact opens: its system is
        singular, and a direct solver returns arbitrary displacements (or, with no load
        on it, cycles between active sets until ``max_iterations``).
        """
        motions = self.complementarity.free_motions(released)
        if motions:
            lines = "\n".join(f"  - {m.describe()}" for m in motions)
            self.fail(
                f"solve {len(step.iterations) + 1} at load {step.load:g}: the active set "
                "leaves these rigid motions free, held by contact alone and the contact "
                f"open (Eq. 33):\n{lines}\nHold every body by a Dirichlet condition (a "
                "body held by contact alone makes the system singular once it opens), "
                "start from start='tied', or take smaller load steps."
            )

    def solve_linear(self, step: LoadStep) -> None:
        """Solve the current saddle point; a failure becomes a contact error with history."""
        try:
            self.system.solve()
        except RuntimeError as error:
            self.fail(
                f"solve {len(step.iterations) + 1} at load {step.load:g} failed: {error}\n"
                "An active set that leaves a body held by contact alone makes the system "
                "singular: start from start='tied', prescribe a displacement, or take "
                "smaller load steps."
            )

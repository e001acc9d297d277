# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The record of a unilateral contact solve: its iterations, load steps and failure.

Every linear solve of a contact iteration is an :class:`Iteration`; the solves of one
load factor make a :class:`LoadStep`, and the steps of one
:meth:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem.solve` a
:class:`ContactHistory`. A solve that does not converge raises
:class:`ContactConvergenceError` with its history.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

__all__ = ["ContactConvergenceError", "ContactHistory", "Iteration", "LoadStep", "Update"]


@dataclass(frozen=True)
class Iteration:
    r"""One linear solve of a contact iteration.

    Attributes:
        active: Number of active multipliers of each pair (over all processes).
        entered: Multipliers that became active at this solve's update.
        left: Multipliers that became inactive at this solve's update.
        residual: Lagrange-multiplier algorithms: :math:`\max_j |C_j|` over all pairs,
            relative to the larger of :math:`\max|\lambda|` and :math:`\max|c \tilde
            g|`. Penalty algorithms: the change of :math:`\lambda` since the previous
            solve, relative to :math:`\max|\lambda|`.
        active_sets: Per pair, the global indices of this process's active multipliers
            in this solve.
        outer: Uzawa update this solve belongs to (augmented Lagrangian), else 0.
        stick: Friction: per pair, the active multipliers that stick (over all
            processes; the others of :attr:`active` slip); empty without friction.
        stick_sets: Friction: per pair, the global indices of this process's sticking
            multipliers in this solve.
    """

    active: tuple[int, ...]
    entered: int
    left: int
    residual: float
    active_sets: tuple[npt.NDArray[np.int64], ...]
    outer: int = 0
    stick: tuple[int, ...] = ()
    stick_sets: tuple[npt.NDArray[np.int64], ...] = ()


@dataclass(frozen=True)
class Update:
    r"""One Uzawa update :math:`\lambda \leftarrow \max(0, \lambda - c \tilde g)`.

    Attributes:
        outer: Its number (the :attr:`Iteration.outer` of its solves).
        change: Relative change of :math:`\lambda` at the update.
        rate: Contraction rate, the change over the previous update's (below 1 when the
            iteration converges); ``None`` for the first update.
        penalty_factor: The factor the penalty had been raised by
            (:mod:`~dolfinx_contact_s2s.unilateral.uzawa`) when its solves ran.
    """

    outer: int
    change: float
    rate: float | None
    penalty_factor: float


@dataclass
class LoadStep:
    """The iterations of one load factor."""

    load: float
    iterations: list[Iteration] = field(default_factory=list)
    updates: list[Update] = field(default_factory=list)
    converged: bool = False
    seconds: float = 0.0


@dataclass
class ContactHistory:
    """Iterations of every load step of a :meth:`UnilateralContactProblem.solve`."""

    algorithm: str
    steps: list[LoadStep] = field(default_factory=list)

    @property
    def iterations(self) -> int:
        """Linear solves over all load steps."""
        return sum(len(step.iterations) for step in self.steps)

    def describe(self) -> str:
        """The history as text: per step and solve, the active sets and residuals."""
        lines = [f"algorithm {self.algorithm!r}, {self.iterations} solves"]
        for step in self.steps:
            state = "converged" if step.converged else "NOT converged"
            lines.append(f"  load {step.load:g}: {state} after {len(step.iterations)} solves")
            for k, it in enumerate(step.iterations):
                outer = f" (update {it.outer})" if it.outer else ""
                lines.append(
                    f"    {k}{outer}: active {list(it.active)}, +{it.entered} -{it.left}, "
                    f"residual {it.residual:.2e}"
                    + (f", stick {list(it.stick)}" if it.stick else "")
                )
            for u in step.updates:
                rate = "" if u.rate is None else f", rate {u.rate:.3g}"
                rate += f", penalty x{u.penalty_factor:g}" if u.penalty_factor != 1.0 else ""
                lines.append(f"    update {u.outer}: change {u.change:.2e}{rate}")
        return "\n".join(lines)


class ContactConvergenceError(RuntimeError):
    """A unilateral contact solve that did not converge; raised on every process."""

    def __init__(self, message: str, history: ContactHistory):
        """Keep the history (:attr:`history`) and append it to the message."""
        super().__init__(f"{message}\n{history.describe()}")
        self.history = history

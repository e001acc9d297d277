# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The outer (Uzawa) iteration of the augmented Lagrangian: its rate, its stop, its penalty.

An Uzawa update :math:`\lambda \leftarrow \max(0, \lambda - c \tilde g)` contracts the
multiplier error by a factor :math:`\rho < 1` that falls as the penalty :math:`c`
grows (for a fixed active set, :math:`\rho = 1 / (1 + c s)` with :math:`s` the
contact stiffness seen by a multiplier). The relative change :math:`\delta_k` of
:math:`\lambda` at update :math:`k` measures :math:`\rho \approx \delta_k /
\delta_{k-1}`, and the error left after the update is about :math:`\delta_k \rho / (1 -
\rho)`: a change below the tolerance is not an error below it when :math:`\rho` is near
1 (measured: :math:`\kappa = 1` on the quadrilateral/triangle patch test stopped at
:math:`\rho = 0.7` with a pressure error of :math:`3.8 \cdot 10^{-10}` against a
tolerance of :math:`10^{-10}`).

:class:`UzawaMonitor` records :math:`\rho` of every update in the history (the
:attr:`~dolfinx_contact_s2s.unilateral.history.LoadStep.updates` of each load step),
stops when both the change and the estimated error are below the tolerance, and raises
the penalty tenfold (at most :data:`MAX_STIFFENING` times in all) when an update
contracts by more than :data:`SLOW_RATE`: a poor rate means the penalty is small against
the contact stiffness, and a larger one costs nothing but conditioning.
"""

from __future__ import annotations

import logging

from petsc4py import PETSc

from dolfinx_contact_s2s.unilateral.history import LoadStep, Update

__all__ = ["MAX_STIFFENING", "SLOW_RATE", "STIFFENING", "UzawaMonitor"]

logger = logging.getLogger(__name__)

#: A contraction rate above this makes :class:`UzawaMonitor` raise the penalty.
SLOW_RATE = 0.5
#: Factor on the penalty at each raise.
STIFFENING = 10.0
#: Largest product of the raises (a larger penalty only worsens the conditioning of the
#: penalized solves, whose residual every solve checks).
MAX_STIFFENING = 100.0


class UzawaMonitor:
    """Rate, stop and penalty of the Uzawa updates of one load step."""

    def __init__(self, tolerance: float):
        r"""Watch the updates of one load step.

        Args:
            tolerance: Largest relative change of :math:`\lambda`, and largest estimated
                relative error, of a converged iteration.
        """
        self.tolerance = float(tolerance)
        self.changes: list[float] = []
        self.rates: list[float] = []
        #: Product of the factors applied to the penalty so far.
        self.stiffening = 1.0

    @property
    def rate(self) -> float | None:
        """Contraction rate of the last update (``None`` before the second)."""
        return self.rates[-1] if self.rates else None

    def update(self, step: LoadStep, change: float, scales: PETSc.Vec) -> bool:
        r"""Record an update's change of :math:`\lambda`; return whether the iteration stops.

        Appends the :class:`~dolfinx_contact_s2s.unilateral.history.Update` with its
        contraction rate to ``step.updates``, and multiplies ``scales`` (:math:`c`) by
        :data:`STIFFENING` when the rate is above :data:`SLOW_RATE` and the iteration
        goes on. The same on every process:
        ``change`` is.

        Args:
            step: The :class:`~dolfinx_contact_s2s.unilateral.LoadStep` of the update.
            change: Relative change of :math:`\lambda` at this update.
            scales: The penalty :math:`c` of every multiplier (changed in place).
        """
        rate = None
        if self.changes and self.changes[-1] > 0.0:
            rate = change / self.changes[-1]
            self.rates.append(rate)
        self.changes.append(change)
        outer = step.iterations[-1].outer if step.iterations else len(step.updates) + 1
        step.updates.append(Update(outer, change, rate, self.stiffening))
        # The error left is about change * rate / (1 - rate) for a rate near 1.
        # A rate of 1 or more at a change below the tolerance is round-off: no estimate.
        error = change
        if rate is not None and rate < 1.0:
            error = change * max(1.0, rate / (1.0 - rate))
        if change <= self.tolerance and error <= self.tolerance:
            return True
        if rate is not None and rate > SLOW_RATE and self.stiffening * STIFFENING <= MAX_STIFFENING:
            self.stiffening *= STIFFENING
            scales.scale(STIFFENING)
            logger.info(
                "augmented Lagrangian: contraction %.2f per update: penalty x%g (x%g in all)",
                rate,
                STIFFENING,
                self.stiffening,
            )
        return False

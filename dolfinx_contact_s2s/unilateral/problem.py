# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The unilateral contact problem (Eq. 1) and its load steps.

:class:`UnilateralContactProblem` holds a
:class:`~dolfinx_contact_s2s.system.ContactSystem` (by composition, through
:class:`~dolfinx_contact_s2s.problem.ContactProblemBase`), assembles it with the
complementarity parameters (:mod:`.complementarity`) and runs the chosen algorithm
(:mod:`.active_set`, :mod:`.snes_vi`, :mod:`.penalty`) over the load factors.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import time
import typing
from collections.abc import Callable, Sequence

from petsc4py import PETSc

import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.checks.inputs import check_inequality_multipliers
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.problem import ContactProblemBase
from dolfinx_contact_s2s.system import DEFAULT_OPTIONS
from dolfinx_contact_s2s.unilateral import active_set, condensed, penalty, snes_vi
from dolfinx_contact_s2s.unilateral.complementarity import Complementarity, given_active
from dolfinx_contact_s2s.unilateral.history import ContactHistory, Iteration, LoadStep
from dolfinx_contact_s2s.unilateral.iteration import ContactIteration

__all__ = ["ALGORITHMS", "DEFAULT_PENALTY", "STARTS", "UnilateralContactProblem"]

#: The solution algorithms (see the package docstring).
ALGORITHMS = (
    "active-set",
    "condensed-active-set",
    "dual-active-set",
    "snes-vi",
    "penalty",
    "augmented-lagrangian",
)

#: First active set of the first load step: the multipliers of the nearest points
#: (smallest initial gap, and every penetration; then the next nearest until the set
#: transmits a force, :math:`\sum_k \int \mu_k w > 0`, which a P2 vertex on the axis of an
#: axisymmetric model alone does not), every multiplier (the tied problem of
#: Eq. 18, always supported when the model passed its checks), or the penetrating ones
#: (negative weighted gap at zero displacement).
STARTS = ("nearest", "tied", "gap")

#: Default factor :math:`\kappa` of :math:`\varepsilon = \kappa \bar E / h`, by algorithm.
DEFAULT_PENALTY = {
    "active-set": 1.0,
    "condensed-active-set": 1.0,
    "dual-active-set": 1.0,
    "snes-vi": 1.0,
    "penalty": 100.0,
    # 100, not 10: a quadrilateral/triangle patch test took 17 updates at 10, 8 at 100.
    "augmented-lagrangian": 100.0,
}


class UnilateralContactProblem(ContactProblemBase):
    r"""Linear elastic bodies in frictionless unilateral contact (Eq. 1).

    The problem of :class:`~dolfinx_contact_s2s.problem.LinearContactProblem` (the same
    public attributes, read from the :class:`~dolfinx_contact_s2s.system.ContactSystem` it
    holds), with the tied rows of Eq. (18) replaced by the conditions of Eq. (1) on the
    weighted gaps.
    :meth:`solve` takes a list of load factors (each scales the loads ``L`` and the
    Dirichlet values; the gaps :math:`g_0` stay) and starts every step from the
    previous step's active set.

    After :meth:`solve`: :attr:`u`, :attr:`multipliers` (the contact pressure, zero
    where the surfaces separate), :attr:`active` (1 on the active multipliers),
    :attr:`gaps` (the weighted gaps :math:`\tilde g_j`) and :attr:`history`.

    Every solve checks itself: the support and rank checks at assembly, the residual of
    every linear solve, and at the end the complementarity residual
    :math:`\max_j |C_j| \le` ``tolerance`` (relative). A solve that does not converge
    within ``max_iterations`` raises :class:`ContactConvergenceError` on every process,
    with its history. A ``monitor`` sees every linear solve as it is recorded.
    """

    signed_conditions = True

    def __init__(
        self,
        a: ufl.Form | Sequence[ufl.Form],
        L: ufl.Form | Sequence[ufl.Form],
        pairs: Sequence[ContactPair],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        *,
        algorithm: str = "active-set",
        start: str = "nearest",
        penalty: float | None = None,
        max_iterations: int = 50,
        tolerance: float = 1e-10,
        monitor: Callable[[Iteration], None] | None = None,
        **options: typing.Any,
    ):
        r"""Set up the problem: the arguments of ``LinearContactProblem`` and these.

        Args:
            a: Bilinear form of each displacement space.
            L: Linear form of each displacement space.
            pairs: Contact pairs.
            bcs: Dirichlet conditions.
            algorithm: One of :data:`ALGORITHMS`.
            start: First active set, one of :data:`STARTS`.
            penalty: Factor :math:`\kappa` of :math:`\varepsilon = \kappa \bar E / h`;
                defaults to :data:`DEFAULT_PENALTY` of the algorithm.
            max_iterations: Largest number of linear solves per load step (of Uzawa
                updates, for the augmented Lagrangian).
            tolerance: Largest relative complementarity residual of a converged solve;
                for the augmented Lagrangian, also the largest relative change of
                :math:`\lambda` at the last update (and of its estimated error,
                :mod:`~dolfinx_contact_s2s.unilateral.uzawa`).
            monitor: Called as ``monitor(iteration)`` with every
                :class:`~dolfinx_contact_s2s.unilateral.history.Iteration` once it is
                recorded in :attr:`history` (after its linear solve and the active-set
                update), e.g. to log or time the iterations; collective calls inside it
                must be made on every process.
            options: The keyword arguments of
                :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`:
                ``petsc_options_prefix`` (required; the KSP of every linear solve, with
                ``"snes-vi"`` also the SNES), ``petsc_options``, ``kind`` (``"aij"`` or
                ``"nest"``; not with ``"snes-vi"``, which extracts reduced matrices),
                ``residual_tolerance`` (of every linear solve), ``workspace_retries``,
                ``form_compiler_options``, ``jit_options``.

        Raises:
            ValueError: For an unknown algorithm or start, or a bad parameter, or a
                multiplier basis with functions of zero integral (P2 on triangular faces).
            TypeError: If ``a``, ``L``, ``pairs`` or ``bcs`` is not what it should be.
        """
        if algorithm not in ALGORITHMS:
            raise ValueError(f"algorithm must be one of {ALGORITHMS}, not {algorithm!r}")
        if start not in STARTS:
            raise ValueError(f"start must be one of {STARTS}, not {start!r}")
        if algorithm in ALGORITHMS[1:4] and options.get("kind", "aij") != "aij":
            raise ValueError(f"the {algorithm!r} algorithm needs kind='aij'")
        if penalty is None:
            penalty = DEFAULT_PENALTY[algorithm]
        if not (penalty > 0 and np.isfinite(penalty)):
            raise ValueError(f"penalty must be positive and finite, not {penalty}")
        if int(max_iterations) < 1 or not tolerance > 0:
            raise ValueError("need max_iterations >= 1 and tolerance > 0")
        self.algorithm = algorithm
        self.start = start
        self.penalty = float(penalty)
        self.max_iterations = int(max_iterations)
        self.tolerance = float(tolerance)
        self._monitor = monitor
        super().__init__(a, L, pairs, bcs, **options)
        self.active = [dolfinx.fem.Function(p.Q, name=f"active{j}") for j, p in enumerate(pairs)]
        self.gaps = [dolfinx.fem.Function(p.Q, name=f"gap{j}") for j, p in enumerate(pairs)]
        self.history = ContactHistory(algorithm)
        self._complementarity: Complementarity | None = None
        try:
            check_inequality_multipliers(pairs)
            if algorithm == "dual-active-set" and not all(getattr(p, "dual", 0) for p in pairs):
                raise ValueError(
                    "the 'dual-active-set' algorithm needs multiplier=('Dual', k) on every pair"
                )
        except ValueError:
            self.destroy()
            raise

    def solver_defaults(self) -> dict[str, typing.Any]:
        """The defaults of every linear solve; with ``"snes-vi"`` also the SNES's."""
        defaults = dict(DEFAULT_OPTIONS)
        if self.algorithm == "snes-vi":
            defaults |= snes_vi.snes_options(self.max_iterations)
        return defaults

    @property
    def scales(self) -> list[PETSc.Vec]:
        r"""Per pair, :math:`c_j` (zero at the pair's inactive multipliers); set at assembly."""
        return [] if self._complementarity is None else self._complementarity.scales

    @property
    def update_seconds(self) -> float:
        """Wall time (s, this process) of the active-set bookkeeping since the last assembly.

        The weighted gaps, the complementarity function, the active-set updates, the
        released multipliers and the first active set
        (:class:`~dolfinx_contact_s2s.unilateral.complementarity.Complementarity`); the
        stages of :attr:`timings` exclude it.
        """
        return 0.0 if self._complementarity is None else self._complementarity.seconds

    def assemble(self, check: bool = True) -> None:
        """Assemble as :meth:`LinearContactProblem.assemble`, and the scales :math:`c_j`."""
        self.system.assemble(check)
        if self._complementarity is not None:
            self._complementarity.destroy()
        self._complementarity = Complementarity(self.system, self.penalty, self.tolerance)

    # --- solve ------------------------------------------------------------------------

    def solve(
        self,
        load_factors: Sequence[float] = (1.0,),
        *,
        active: Sequence[Callable | npt.NDArray[np.bool_] | None] | None = None,
    ) -> tuple[list[dolfinx.fem.Function], list[dolfinx.fem.Function]]:
        """Assemble, then solve the contact problem at every load factor in turn.

        Args:
            load_factors: Factors on the loads and Dirichlet values, solved in order,
                each starting from the previous one's active set.
            active: The first active set, one entry per pair, instead of ``start``
                (e.g. a previous solution's, on a refined mesh): a callable
                ``marker(x) -> bool`` of the multiplier nodes' coordinates ``x``
                ``(3, n)`` (as :func:`dolfinx.fem.locate_dofs_geometrical`), a boolean
                array over the pair's owned multiplier dofs, or ``None`` (``start``).
                Only a first guess: the iteration and its checks are unchanged.

        Returns:
            The displacement of every space and the contact pressure of every pair, at
            the last load factor.

        Raises:
            ValueError: On every rank, if the model is singular (see :meth:`assemble`), or
                ``active`` has not one entry per pair of the right size.
            RuntimeError: On every rank, if a linear solve fails.
            ContactConvergenceError: On every rank, if a load step does not converge.
        """
        loads = [float(t) for t in load_factors]
        if not loads or not all(np.isfinite(loads)):
            raise ValueError("give at least one finite load factor")
        given = given_active(self.pairs, self.comm, active)
        self.assemble()
        assert self._complementarity is not None
        comp = self._complementarity
        run = ContactIteration(
            self.system,
            comp,
            self.algorithm,
            self.max_iterations,
            self.tolerance,
            self._monitor,
        )
        self.history = run.history
        # One factorization for every step: made here, with the tied system assembled.
        condensed_run = None
        if self.algorithm == "condensed-active-set":
            condensed_run = condensed.CondensedActiveSet(run)
        step_solver: Callable[..., list[npt.NDArray[np.bool_]]] = {
            "active-set": active_set.solve_step,
            "condensed-active-set": getattr(condensed_run, "solve_step", None),
            "dual-active-set": lambda *args: active_set.solve_step(*args, dual=True),
            "snes-vi": snes_vi.solve_step,
            "penalty": penalty.solve_step,
            "augmented-lagrangian": lambda *args: penalty.solve_step(*args, augmented=True),
        }[self.algorithm]
        active: list[npt.NDArray[np.bool_]] | None = None
        try:
            for t in loads:
                step = LoadStep(t)
                self.history.steps.append(step)
                begin = time.perf_counter()
                if active is None:
                    active = comp.first_active(t, self.start, given)
                active = step_solver(run, step, active)
                step.seconds = time.perf_counter() - begin
        finally:
            if condensed_run is not None:
                condensed_run.destroy()
        assert active is not None
        self._finish(comp, active)
        return self.u, self.multipliers

    def _finish(self, comp: Complementarity, active: list[npt.NDArray[np.bool_]]) -> None:
        for f, a in zip(self.active, active, strict=True):
            f.x.array[:] = 0.0
            f.x.array[: a.size] = a
            f.x.scatter_forward()
        for f, g in zip(self.gaps, comp.weighted_gaps(), strict=True):
            f.x.array[: g.size] = g
            f.x.scatter_forward()

    def destroy(self) -> None:
        """Destroy the PETSc objects and remove the problem's options from the database."""
        if self._complementarity is not None:
            self._complementarity.destroy()
        super().destroy()

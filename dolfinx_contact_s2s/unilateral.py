# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Frictionless unilateral contact: an unknown contact area (Eq. 1).

The contact conditions of Eq. (1), :math:`g \ge 0`, :math:`\lambda \ge 0`,
:math:`g \lambda = 0`, are imposed on the weighted gaps of the coupling (Eqs. 15 and
17), one per multiplier dof :math:`j`:

.. math::
    \tilde g_j = \int_{\Gamma_C} \mu_j \left[(\mathbf u_C - \mathbf u_T^*) \cdot
    \mathbf N + g_0\right] d\Gamma = (\mathbf B \mathbf U + \mathbf G)_j, \qquad
    \lambda_j \ge 0, \quad \tilde g_j \ge 0, \quad \lambda_j \tilde g_j = 0,

with every discretization of the coupling. Four algorithms share one interface
(:class:`UnilateralContactProblem`):

- ``"active-set"``: semismooth Newton on the complementarity function
  :math:`C_j = \lambda_j - \max(0, \lambda_j - c_j \tilde g_j)` (the primal-dual active
  set method). For linear elastic bodies every iteration is one saddle-point solve of
  Eq. (18) with the inactive multipliers set to zero, and the iteration ends when the
  active set repeats, which makes :math:`C = 0` up to round-off.
- ``"snes-vi"``: the same mixed complementarity problem handed to PETSc's reduced-space
  variational-inequality Newton method (``SNESVINEWTONRSLS``) with the bounds
  :math:`\lambda \ge 0` and free displacements.
- ``"penalty"``: :math:`\lambda_j = c_j \max(0, -\tilde g_j)` from the penetration, no
  multiplier unknowns in the solve; the error falls like :math:`1/\varepsilon`.
- ``"augmented-lagrangian"``: Uzawa updates
  :math:`\lambda_j \leftarrow \max(0, \lambda_j - c_j \tilde g_j)` around penalty solves,
  until :math:`\lambda` stops changing: the Lagrange solution for any :math:`\varepsilon`.

The parameter :math:`c_j = \varepsilon_j / m_j` turns a weighted gap into a pressure:
:math:`m_j` is the row sum of the multiplier's mass (Eq. 29: the integral of
:math:`\mu_j`, or the tributary length of a node) and :math:`\varepsilon_j = \kappa
\bar E / h_j` a stiffness per length, with :math:`\bar E` the median diagonal entry of
the free stiffness, :math:`h_j = (\int \mu_j)^2 / \int \mu_j^2` (proportional to the
contactor's facet size around :math:`j`: :math:`1.5 h` for P1) and :math:`\kappa` the
``penalty`` factor.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import logging
import time
import typing
from collections.abc import Sequence
from dataclasses import dataclass, field

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.assemble import multiplier_mass
from dolfinx_contact_s2s.options import solver_failure
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.problem import LinearContactProblem

# h2: the Uzawa updates' rate, stop and adaptive penalty live in uzawa.py
from dolfinx_contact_s2s.uzawa import UzawaMonitor

__all__ = [
    "ALGORITHMS",
    "DEFAULT_PENALTY",
    "STARTS",
    "ContactConvergenceError",
    "ContactHistory",
    "Iteration",
    "LoadStep",
    "UnilateralContactProblem",
]

logger = logging.getLogger(__name__)

#: The solution algorithms (see the module docstring).
ALGORITHMS = ("active-set", "snes-vi", "penalty", "augmented-lagrangian")

#: First active set of the first load step: the multipliers of the nearest points
#: (smallest initial gap, and every penetration), every multiplier (the tied problem of
#: Eq. 18, always supported when the model passed its checks), or the penetrating ones
#: (negative weighted gap at zero displacement).
STARTS = ("nearest", "tied", "gap")

#: Default factor :math:`\kappa` of :math:`\varepsilon = \kappa \bar E / h`, by algorithm.
DEFAULT_PENALTY = {
    "active-set": 1.0,
    "snes-vi": 1.0,
    "penalty": 100.0,
    # h2: 100, not 10: the quadrilateral/triangle patch test took 17 updates at 10, 8 at 100
    "augmented-lagrangian": 100.0,
}


@dataclass(frozen=True)
class Iteration:
    r"""One linear solve of a contact iteration.

    Attributes:
        active: Number of active multipliers of each pair (over all processes).
        entered: Multipliers that became active at this solve's update.
        left: Multipliers that became inactive at this solve's update.
        residual: Lagrange-multiplier algorithms: :math:`\\max_j |C_j|` over all pairs,
            relative to the larger of :math:`\\max|\\lambda|` and :math:`\\max|c \\tilde
            g|`. Penalty algorithms: the change of :math:`\\lambda` since the previous
            solve, relative to :math:`\\max|\\lambda|`.
        active_sets: Per pair, the global indices of this process's active multipliers
            in this solve.
        outer: Uzawa update this solve belongs to (augmented Lagrangian), else 0.
        rate: On the last solve of an Uzawa update from the second on, the update's
            contraction rate: its relative change of :math:`\\lambda` over the previous
            update's (below 1 when the iteration converges); else ``None``.
        penalty_factor: On the last solve of an Uzawa update, the factor the penalty had
            been raised by (:mod:`~dolfinx_contact_s2s.uzawa`) when it was solved.
    """

    active: tuple[int, ...]
    entered: int
    left: int
    residual: float
    active_sets: tuple[npt.NDArray[np.int64], ...]
    outer: int = 0
    # h2: the contraction rate of an Uzawa update, and its penalty factor
    rate: float | None = None
    penalty_factor: float = 1.0


@dataclass
class LoadStep:
    """The iterations of one load factor."""

    load: float
    iterations: list[Iteration] = field(default_factory=list)
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
                # h2: the contraction rate of the update (and its penalty factor)
                rate = "" if it.rate is None else f", rate {it.rate:.3g}"
                rate += f", penalty x{it.penalty_factor:g}" if it.penalty_factor != 1.0 else ""
                lines.append(
                    f"    {k}{outer}: active {list(it.active)}, +{it.entered} -{it.left}, "
                    f"residual {it.residual:.2e}{rate}"
                )
        return "\n".join(lines)


class ContactConvergenceError(RuntimeError):
    """A unilateral contact solve that did not converge; raised on every process."""

    def __init__(self, message: str, history: ContactHistory):
        """Keep the history (:attr:`history`) and append it to the message."""
        super().__init__(f"{message}\n{history.describe()}")
        self.history = history


def _owned_indices(v: PETSc.Vec, mask: npt.NDArray[np.bool_]) -> npt.NDArray[np.int64]:
    """Global indices of the owned entries of ``v`` where ``mask`` holds."""
    start = v.getOwnershipRange()[0]
    return (start + np.flatnonzero(mask)).astype(np.int64)


class UnilateralContactProblem(LinearContactProblem):
    r"""Linear elastic bodies in frictionless unilateral contact (Eq. 1).

    The problem of :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`, with the
    tied rows of Eq. (18) replaced by the conditions of Eq. (1) on the weighted gaps.
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
    with its history.
    """

    def __init__(
        self,
        a: ufl.Form | Sequence[ufl.Form],
        L: ufl.Form | Sequence[ufl.Form],
        pairs: Sequence[ContactPair],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        *,
        petsc_options_prefix: str,
        petsc_options: dict[str, typing.Any] | None = None,
        algorithm: str = "active-set",
        start: str = "nearest",
        penalty: float | None = None,
        max_iterations: int = 50,
        tolerance: float = 1e-10,
        kind: str = "aij",
        residual_tolerance: float = 1e-8,
        form_compiler_options: dict | None = None,
        jit_options: dict | None = None,
    ):
        r"""Set up the problem; the arguments of ``LinearContactProblem`` and these.

        Args:
            a: Bilinear form of each displacement space.
            L: Linear form of each displacement space.
            pairs: Contact pairs.
            bcs: Dirichlet conditions.
            petsc_options_prefix: Non-empty prefix of the solver's options (the KSP of
                every linear solve; with ``"snes-vi"`` also the SNES).
            petsc_options: Options under the prefix.
            algorithm: One of :data:`ALGORITHMS`.
            start: First active set, one of :data:`STARTS`.
            penalty: Factor :math:`\\kappa` of :math:`\varepsilon = \\kappa \bar E / h`;
                defaults to :data:`DEFAULT_PENALTY` of the algorithm.
            max_iterations: Largest number of linear solves per load step (of Uzawa
                updates, for the augmented Lagrangian).
            tolerance: Largest relative complementarity residual of a converged solve;
                for the augmented Lagrangian, also the largest relative change of
                :math:`\\lambda` at the last update.
            kind: ``"aij"`` or ``"nest"`` (not with ``"snes-vi"``, which extracts
                reduced matrices).
            residual_tolerance: Largest relative residual of every linear solve.
            form_compiler_options: Passed to :func:`dolfinx.fem.form`.
            jit_options: Passed to :func:`dolfinx.fem.form`.

        Raises:
            ValueError: For an unknown algorithm or start, or a bad parameter.
        """
        if algorithm not in ALGORITHMS:
            raise ValueError(f"algorithm must be one of {ALGORITHMS}, not {algorithm!r}")
        if start not in STARTS:
            raise ValueError(f"start must be one of {STARTS}, not {start!r}")
        if algorithm == "snes-vi" and kind != "aij":
            raise ValueError("the 'snes-vi' algorithm needs kind='aij'")
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
        super().__init__(
            a,
            L,
            pairs,
            bcs,
            petsc_options_prefix=petsc_options_prefix,
            petsc_options=petsc_options,
            kind=kind,
            residual_tolerance=residual_tolerance,
            form_compiler_options=form_compiler_options,
            jit_options=jit_options,
        )
        self.active = [dolfinx.fem.Function(p.Q, name=f"active{j}") for j, p in enumerate(pairs)]
        self.gaps = [dolfinx.fem.Function(p.Q, name=f"gap{j}") for j, p in enumerate(pairs)]
        self.history = ContactHistory(algorithm)
        #: Per pair, :math:`c_j` (zero at the pair's inactive multipliers); set at assembly.
        self.scales: list[PETSc.Vec] = []

    def _default_options(self) -> dict[str, typing.Any]:
        options = super()._default_options()
        if self.algorithm == "snes-vi":
            # Full semismooth Newton steps: backtracking (bt) stalls on Hertz, l2 halves
            # its steps for hundreds of iterations, cp stops out of balance (README).
            options |= {
                "snes_type": "vinewtonrsls",
                "snes_linesearch_type": "basic",
                "snes_max_it": self.max_iterations,
            }
        return options

    # --- parameters -----------------------------------------------------------------

    def _stiffness_scale(self) -> float:
        """Median diagonal entry of the stiffness over the free dofs of all spaces."""
        local = []
        for i, mask in enumerate(self._masks):
            d = self.stiffness_diagonal(i)
            local.append(d.array_r[mask.array_r > 0])
            d.destroy()
        values = np.concatenate(self.comm.allgather(np.concatenate(local)))
        values = values[values > 0]
        if values.size == 0:
            raise ValueError("the stiffness has no positive diagonal entry on a free dof")
        return float(np.median(values))

    def _scale(self, j: int, E: float) -> PETSc.Vec:
        r""":math:`c_k = \kappa \bar E / (h_k m_k)` of pair ``j``, zero at its inactive dofs."""
        pair, op = self.pairs[j], self.operators[j]
        Q = pair.Q
        mu = ufl.TestFunction(Q)
        mass = dolfinx.fem.petsc.assemble_matrix(
            dolfinx.fem.form(ufl.TrialFunction(Q) * mu * ufl.dx)
        )
        mass.assemble()
        squares = mass.getDiagonal()
        lengths = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(mu * ufl.dx))
        lengths.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        P = multiplier_mass(pair)
        m = P.createVecLeft()
        P.getRowSum(m)
        c = op.G.duplicate()
        n = c.getLocalSize()
        integral, square, m_loc = lengths.array_r[:n], squares.array_r[:n], m.array_r
        with np.errstate(divide="ignore", invalid="ignore"):
            # A length proportional to the facets around k, on any (curved) geometry.
            h_k = np.where(square > 0, integral**2 / square, 0.0)
            values = np.where((h_k > 0) & (m_loc > 0), self.penalty * E / (h_k * m_loc), 0.0)
        c.array[:] = values
        start = c.getOwnershipRange()[0]
        off = op.inactive[(op.inactive >= start) & (op.inactive < start + n)] - start
        c.array[off] = 0.0
        if self.comm.allreduce(int(np.count_nonzero(values[np.setdiff1d(np.arange(n), off)] <= 0))):
            raise ValueError(f"pair {j}: a multiplier with no facet size or mass")
        for obj in (mass, squares, lengths, P, m):
            obj.destroy()
        return c

    def assemble(self, check: bool = True) -> None:
        """Assemble as :meth:`LinearContactProblem.assemble`, and the scales :math:`c_j`."""
        super().assemble(check)
        for c in self.scales:
            c.destroy()
        self._stiffness = self._stiffness_scale()
        self.scales = [self._scale(j, self._stiffness) for j in range(len(self.pairs))]

    # --- the pieces of every algorithm ------------------------------------------------

    def _pinned(self, j: int) -> npt.NDArray[np.bool_]:
        """Owned multipliers of pair ``j`` that carry no constraint."""
        op = self.operators[j]
        start, end = op.G.getOwnershipRange()
        mask = np.zeros(end - start, dtype=bool)
        mask[op.inactive[(op.inactive >= start) & (op.inactive < end)] - start] = True
        return mask

    def _weighted_gaps(self) -> list[npt.NDArray[np.floating]]:
        r"""Owned :math:`\tilde g = \mathbf B \mathbf U + \mathbf G` of every pair from :attr:`u`.

        :attr:`u` holds the Dirichlet values already scaled by the load factor.
        """
        out = []
        for op in self.operators:
            g = op.G.copy()
            for V, B in op.blocks:
                B.multAdd(self.u[self.space_index(V)].x.petsc_vec, g, g)
            out.append(g.array_r.copy())
            g.destroy()
        return out

    def _initial_gaps(self, load: float) -> list[npt.NDArray[np.floating]]:
        r""":math:`\tilde g` at zero free displacement (the Dirichlet values scaled by ``load``)."""
        out = []
        for op in self.operators:
            g = op.G.copy()
            for V, B in op.blocks:
                self._add_scaled(B, self._values[self.space_index(V)], load, g)
            out.append(g.array_r.copy())
            g.destroy()
        return out

    def _lambdas(self) -> list[npt.NDArray[np.floating]]:
        return [
            lam.x.array[: op.G.getLocalSize()].copy()
            for lam, op in zip(self.multipliers, self.operators, strict=True)
        ]

    def _complementarity(
        self, lam: list[npt.NDArray[np.floating]], gaps: list[npt.NDArray[np.floating]]
    ) -> tuple[list[npt.NDArray[np.floating]], float]:
        r""":math:`z = \lambda - c \tilde g` per pair and the relative residual of :math:`C`."""
        z, worst, scale = [], 0.0, 0.0
        for j, (lj, gj) in enumerate(zip(lam, gaps, strict=True)):
            cg = self.scales[j].array_r * gj
            zj = lj - cg
            zj[self._pinned(j)] = -np.inf
            z.append(zj)
            C = lj - np.maximum(0.0, np.where(np.isfinite(zj), zj, 0.0))
            C[self._pinned(j)] = 0.0
            worst = max(worst, float(np.max(np.abs(C), initial=0.0)))
            scale = max(
                scale,
                float(np.max(np.abs(lj), initial=0.0)),
                float(np.max(np.abs(cg[~self._pinned(j)]), initial=0.0)),
            )
        worst = self.comm.allreduce(worst, op=MPI.MAX)
        scale = self.comm.allreduce(scale, op=MPI.MAX)
        return z, (worst / scale if scale > 0 else worst)

    def _update(
        self, active: list[npt.NDArray[np.bool_]], z: list[npt.NDArray[np.floating]]
    ) -> tuple[list[npt.NDArray[np.bool_]], int, int]:
        """The next active set, with a hysteresis of ``tolerance / 2`` against round-off."""
        scale = max(
            (float(np.max(np.abs(zj[np.isfinite(zj)]), initial=0.0)) for zj in z), default=0.0
        )
        tau = 0.5 * self.tolerance * self.comm.allreduce(scale, op=MPI.MAX)
        new = [np.where(a, zj > -tau, zj > tau) for a, zj in zip(active, z, strict=True)]
        entered = sum(int(np.count_nonzero(n & ~a)) for n, a in zip(new, active, strict=True))
        left = sum(int(np.count_nonzero(a & ~n)) for n, a in zip(new, active, strict=True))
        return new, self.comm.allreduce(entered), self.comm.allreduce(left)

    def _record(
        self,
        step: LoadStep,
        active: list[npt.NDArray[np.bool_]],
        entered: int,
        left: int,
        residual: float,
        outer: int = 0,
    ) -> None:
        counts = tuple(self.comm.allreduce(int(np.count_nonzero(a))) for a in active)
        sets = tuple(_owned_indices(op.G, a) for op, a in zip(self.operators, active, strict=True))
        step.iterations.append(Iteration(counts, entered, left, residual, sets, outer))
        logger.info(
            "contact %s, load %g, solve %d: active %s, +%d -%d, residual %.2e",
            self.algorithm,
            step.load,
            len(step.iterations),
            counts,
            entered,
            left,
            residual,
        )

    def _first_active(self, load: float) -> list[npt.NDArray[np.bool_]]:
        pinned = [self._pinned(j) for j in range(len(self.pairs))]
        if self.start == "tied":
            return [~p for p in pinned]
        # c g~ at zero displacement: a pressure, comparable over all multipliers.
        cg = [c.array_r * g for c, g in zip(self.scales, self._initial_gaps(load), strict=True)]
        if self.start == "gap":
            return [(v < 0) & ~p for v, p in zip(cg, pinned, strict=True)]
        # "nearest": the penetrating multipliers and those within 1e-8 h of the smallest gap.
        local = min(
            (float(np.min(v[~p], initial=np.inf)) for v, p in zip(cg, pinned, strict=True)),
            default=np.inf,
        )
        smallest = self.comm.allreduce(local, op=MPI.MIN)
        near = smallest + 1e-8 * self.penalty * self._stiffness
        return [((v < 0) | (v <= near)) & ~p for v, p in zip(cg, pinned, strict=True)]

    def _released(self, active: list[npt.NDArray[np.bool_]]) -> list[npt.NDArray[np.int64]]:
        return [
            _owned_indices(op.G, ~a & ~self._pinned(j))
            for j, (op, a) in enumerate(zip(self.operators, active, strict=True))
        ]

    def _fail(self, message: str) -> typing.NoReturn:
        raise ContactConvergenceError(message, self.history)

    def _free_motions(self, released: list[npt.NDArray[np.int64]]) -> list:
        """The rigid motions the contact rows left active do not hold (collective)."""
        if self._support is None:
            return []
        inactive = [
            np.union1d(op.inactive, r) for op, r in zip(self.operators, released, strict=True)
        ]
        return self._support.motions(inactive)

    def _check_active_support(self, step: LoadStep, released: list[npt.NDArray[np.int64]]) -> None:
        """Raise if the active set leaves a body free (Eq. 33 on the active rows only).

        A body held by contact alone floats once its contact opens: its system is
        singular, and a direct solver returns arbitrary displacements (or, with no load
        on it, cycles between active sets until ``max_iterations``).
        """
        motions = self._free_motions(released)
        if motions:
            lines = "\n".join(f"  - {m.describe()}" for m in motions)
            self._fail(
                f"solve {len(step.iterations) + 1} at load {step.load:g}: the active set "
                "leaves these rigid motions free, held by contact alone and the contact "
                f"open (Eq. 33):\n{lines}\nHold every body by a Dirichlet condition (a "
                "body held by contact alone makes the system singular once it opens), "
                "start from start='tied', or take smaller load steps."
            )

    def _solve_linear(self, step: LoadStep) -> None:
        """Solve the current saddle point; a failure becomes a contact error with history."""
        try:
            self._solve_system()
        except RuntimeError as error:
            self._fail(
                f"solve {len(step.iterations) + 1} at load {step.load:g} failed: {error}\n"
                "An active set that leaves a body held by contact alone makes the system "
                "singular: start from start='tied', prescribe a displacement, or take "
                "smaller load steps."
            )

    # --- solve ------------------------------------------------------------------------

    def solve(
        self, load_factors: Sequence[float] = (1.0,)
    ) -> tuple[list[dolfinx.fem.Function], list[dolfinx.fem.Function]]:
        """Assemble, then solve the contact problem at every load factor in turn.

        Args:
            load_factors: Factors on the loads and Dirichlet values, solved in order,
                each starting from the previous one's active set.

        Returns:
            The displacement of every space and the contact pressure of every pair, at
            the last load factor.

        Raises:
            ValueError: On every rank, if the model is singular (see :meth:`assemble`).
            RuntimeError: On every rank, if a linear solve fails.
            ContactConvergenceError: On every rank, if a load step does not converge.
        """
        loads = [float(t) for t in load_factors]
        if not loads or not all(np.isfinite(loads)):
            raise ValueError("give at least one finite load factor")
        self.assemble()
        self.history = ContactHistory(self.algorithm)
        active: list[npt.NDArray[np.bool_]] | None = None
        run = {
            "active-set": self._active_set,
            "snes-vi": self._snes_vi,
            "penalty": self._penalty,
            "augmented-lagrangian": self._penalty,
        }[self.algorithm]
        for t in loads:
            step = LoadStep(t)
            self.history.steps.append(step)
            begin = time.perf_counter()
            if active is None:
                active = self._first_active(t)
            active = run(step, active)
            step.seconds = time.perf_counter() - begin
        assert active is not None
        self._finish(active)
        return self.u, self.multipliers

    def _finish(self, active: list[npt.NDArray[np.bool_]]) -> None:
        for f, a in zip(self.active, active, strict=True):
            f.x.array[:] = 0.0
            f.x.array[: a.size] = a
            f.x.scatter_forward()
        for f, g in zip(self.gaps, self._weighted_gaps(), strict=True):
            f.x.array[: g.size] = g
            f.x.scatter_forward()

    def _active_set(
        self, step: LoadStep, active: list[npt.NDArray[np.bool_]]
    ) -> list[npt.NDArray[np.bool_]]:
        """Semismooth Newton (primal-dual active set) iterations of one load step."""
        for _ in range(self.max_iterations):
            released = self._released(active)
            self._build_system(released, load=step.load)
            self._check_active_support(step, released)
            self._solve_linear(step)
            z, residual = self._complementarity(self._lambdas(), self._weighted_gaps())
            new, entered, left = self._update(active, z)
            self._record(step, active, entered, left, residual)
            if entered == 0 and left == 0 and residual <= self.tolerance:
                step.converged = True
                return active
            active = new
        self._fail(
            f"the active-set iteration did not converge in {self.max_iterations} solves "
            f"at load {step.load:g} (raise max_iterations, or take smaller load steps)"
        )

    # --- SNES VI ----------------------------------------------------------------------

    def _snes_vi(
        self, step: LoadStep, active: list[npt.NDArray[np.bool_]]
    ) -> list[npt.NDArray[np.bool_]]:
        r"""One load step by PETSc's ``SNESVINEWTONRSLS``.

        :math:`F(\mathbf x) = \mathbf S (\mathbf A \mathbf x - \mathbf b)` with
        :math:`\mathbf S = \mathrm{diag}(\mathbf I, -c)`: the displacement rows are the
        equilibrium of Eq. (18), the multiplier rows :math:`c_j \tilde g_j`; with the
        bounds :math:`0 \le \lambda` (displacements free) the variational inequality is
        exactly Eq. (1). The Jacobian :math:`\mathbf S \mathbf A` is constant. The start
        is a saddle-point solve with the given active set (projected onto
        :math:`\lambda \ge 0`); convergence is tested as for ``"active-set"``.
        """
        self._build_system(self._released(active), load=step.load)
        self._solve_linear(step)
        assert self.x is not None
        x = self.x.copy()
        self._build_system(None, load=step.load)
        assert self.A is not None and self.b is not None
        nb = len(self.spaces)
        lambda_sets = list(self.fields.values())[nb:]
        S, lower, upper = (self.b.duplicate() for _ in range(3))
        S.set(1.0)
        lower.set(PETSc.NINFINITY)
        upper.set(PETSc.INFINITY)
        for is_, c in zip(lambda_sets, self.scales, strict=True):
            # c = 0 at the inactive multipliers (uncovered, duplicates), whose rows of A
            # read lambda_k = 0: scaled by -1, not 0, which left the Jacobian singular.
            scale = np.where(c.array_r != 0.0, -c.array_r, -1.0)
            for vec, values in ((S, scale), (lower, 0.0)):
                sub = vec.getSubVector(is_)
                sub.array[:] = values
                vec.restoreSubVector(is_, sub)
        J = self.A.copy()
        J.diagonalScale(S)
        # S A is not symmetric: the default factorization is LU here.
        J.setOption(PETSc.Mat.Option.SYMMETRIC, False)
        if self.options.get("pc_type") == "cholesky":
            self.options.set_default("pc_type", "lu")
        # The semismooth VI types add to the diagonal, absent from the multiplier block.
        J.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
        Sb = self.b.copy()
        Sb.pointwiseMult(Sb, S)
        f, work = self.b.duplicate(), self.b.duplicate()
        u_rows = PETSc.IS().createGeneral(
            np.concatenate([is_.getIndices() for is_ in list(self.fields.values())[:nb]]),
            comm=self.comm,
        )
        jx, xu = self.b.duplicate(), self.b.duplicate()

        def function(snes: PETSc.SNES | None, x: PETSc.Vec, f: PETSc.Vec) -> None:
            J.mult(x, f)
            f.axpy(-1.0, Sb)

        accepted: list[bool] = [False]
        floating: list[typing.Any] = [None]

        def converged(snes: PETSc.SNES, it: int, norms: tuple) -> int:
            x = snes.getSolution()
            function(None, x, work)
            lam, gaps = [], []
            for is_, c in zip(lambda_sets, self.scales, strict=True):
                lam.append(_part(x, is_))
                cg = _part(work, is_)
                gaps.append(np.divide(cg, c.array_r, out=np.zeros_like(cg), where=c.array_r != 0))
            z, residual = self._complementarity(lam, gaps)
            # The same rule as the active-set loop, hysteresis against round-off included.
            new, entered, left = self._update(state, z)
            self._record(step, new, entered, left, residual)
            state[:] = new
            released = self._released(new)
            if self._free_motions(released):
                floating[0] = released  # reported after the solve, with the motions
                return PETSc.SNES.ConvergedReason.DIVERGED_FUNCTION_DOMAIN
            # Equilibrium relative to the larger of the loads and the elastic forces K U.
            x.copy(xu)
            for is_ in lambda_sets:
                sub = xu.getSubVector(is_)
                sub.set(0.0)
                xu.restoreSubVector(is_, sub)
            J.mult(xu, jx)
            scale = max(
                _norm(self.comm, _part(Sb, u_rows)),
                _norm(self.comm, _part(jx, u_rows)),
                np.finfo(float).tiny,
            )
            equilibrium = _norm(self.comm, _part(work, u_rows)) / scale
            accepted[0] = residual <= self.tolerance and equilibrium <= self.residual_tolerance
            if accepted[0]:
                return PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS
            if it >= snes.getTolerances()[3]:
                return PETSc.SNES.ConvergedReason.DIVERGED_MAX_IT
            return PETSc.SNES.ConvergedReason.ITERATING

        state = [a.copy() for a in active]
        snes = PETSc.SNES().create(self.comm)
        try:
            snes.setOptionsPrefix(self.options.prefix)
            snes.setFunction(function, f)
            snes.setJacobian(lambda snes, x, J, P: None, J)
            snes.setType("vinewtonrsls")
            snes.setTolerances(max_it=self.max_iterations)
            self.options.apply(snes)
            snes.setVariableBounds(lower, upper)
            snes.setConvergenceTest(converged)
            with self._timed("solve"):
                snes.solve(None, x)
            reason = snes.getConvergedReason()
            if reason > 0 and not accepted[0]:
                # PETSc's VI solver can stop on its own tests (its line search, say),
                # which do not see the equilibrium: measured on Hertz with the cp line
                # search, stopped with 3% out of balance.
                self._fail(
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
                if floating[0] is None:
                    floating[0] = [
                        np.flatnonzero(_part(x, is_) <= 0.0).astype(np.int64) for is_ in lambda_sets
                    ]
                self._check_active_support(step, floating[0])
                self._fail(
                    f"SNES ({snes.getType()}) did not converge at load {step.load:g}: "
                    f"{_SNES_REASONS.get(reason, reason)} after {snes.getIterationNumber()} "
                    "iterations (try more snes_max_it, "
                    "or algorithm='active-set')"
                )
            step.converged = True
            x.copy(self.x)
            self._scatter()
            return state
        finally:
            snes.destroy()
            for obj in (x, S, lower, upper, J, Sb, f, work, jx, xu, u_rows):
                obj.destroy()

    # --- penalty and augmented Lagrangian --------------------------------------------

    def _penalty(
        self, step: LoadStep, active: list[npt.NDArray[np.bool_]]
    ) -> list[npt.NDArray[np.bool_]]:
        r"""Penalty solves, within Uzawa updates for the augmented Lagrangian.

        With :math:`\mathbf C` the masked coupling (so that :math:`\tilde g = \mathbf C
        \mathbf U + \hat{\mathbf G}`), :math:`\lambda^k` the current multiplier (zero
        for the penalty method) and :math:`\mathcal A = \{j: \lambda^k_j - c_j \tilde g_j
        > 0\}`, each solve is the Newton step of the penalized energy

        .. math:: (\mathbf K + \mathbf C^T \mathbf W_{\mathcal A} \mathbf C) \mathbf U =
            \mathbf F + \mathbf C^T (\lambda^k_{\mathcal A} - \mathbf W_{\mathcal A}
            \hat{\mathbf G}), \qquad \mathbf W = \mathrm{diag}(c),

        repeated until :math:`\mathcal A` repeats; then :math:`\lambda \leftarrow
        \max(0, \lambda^k - c \tilde g)`.
        """
        self._build_system(None, load=step.load)
        assert self.A is not None and self.b is not None
        nb = len(self.spaces)
        names = list(self.fields)
        A = self.A if self.kind == "aij" else self.A.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())
        rows = [
            PETSc.IS().createGeneral(
                np.concatenate([self.fields[n].getIndices() for n in part]).astype(np.int32),
                comm=self.comm,
            )
            for part in (names[:nb], names[nb:])
        ]
        K = A.createSubMatrix(rows[0], rows[0])
        minus_C = A.createSubMatrix(rows[1], rows[0])
        F = self.b.getSubVector(rows[0]).copy()
        G = self.b.getSubVector(rows[1]).copy()
        c = G.duplicate()
        c.array[:] = np.concatenate([s.array_r for s in self.scales])
        lam = G.duplicate()
        lam.set(0.0)
        augmented = self.algorithm == "augmented-lagrangian"
        if augmented:
            lam.array[:] = np.concatenate(self._lambdas())
        sizes = [s.getLocalSize() for s in self.scales]
        pinned = np.concatenate([self._pinned(j) for j in range(len(self.pairs))])
        U, rhs, g, w, work = (
            K.createVecRight(),
            F.duplicate(),
            G.duplicate(),
            G.duplicate(),
            F.duplicate(),
        )
        ksp = PETSc.KSP().create(self.comm)
        owned: list[typing.Any] = [K, minus_C, F, G, c, lam, U, rhs, g, w, work, ksp, *rows]
        if A is not self.A:
            owned.append(A)
        flat = np.concatenate(active)
        split = np.cumsum(sizes)[:-1]
        last = lam.array_r.copy()
        # h2: rate, stop and adaptive penalty of the Uzawa updates
        monitor = UzawaMonitor(self.tolerance)
        try:
            for outer in range(1, self.max_iterations + 1 if augmented else 2):
                for _ in range(self.max_iterations):
                    # No penalty stiffness off the active set: a body held by contact
                    # alone floats there (Eq. 33 on the active rows).
                    self._check_active_support(step, self._released(np.split(flat, split)))
                    # W = diag(c) on the active set; P = K + (-C)^T W (-C).
                    w.array[:] = np.where(flat, c.array_r, 0.0)
                    WC = minus_C.copy()
                    WC.diagonalScale(w)
                    P = minus_C.transposeMatMult(WC)
                    P.axpy(1.0, K, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
                    # rhs = F - (-C)^T (lambda_A) + (-C)^T (W G).
                    w.array[:] = np.where(flat, lam.array_r, 0.0) - w.array_r * G.array_r
                    minus_C.multTranspose(w, work)
                    F.copy(rhs)
                    rhs.axpy(-1.0, work)

                    def configure(P: PETSc.Mat = P) -> None:
                        ksp.setOperators(P)
                        self.options.apply(ksp)

                    configure()
                    with self._timed("solve"):
                        self._solve_retrying(ksp, configure, rhs, U)
                        self._check_linear(ksp, P, rhs, U)
                    WC.destroy()
                    P.destroy()
                    minus_C.mult(U, g)
                    g.aypx(-1.0, G)
                    z = lam.array_r - c.array_r * g.array_r
                    z[pinned] = -np.inf
                    lam_new = np.where(np.isfinite(z), np.maximum(z, 0.0), 0.0)
                    residual = _relative_change(self.comm, lam_new, last)
                    last = lam_new
                    nxt, entered, left = self._update(np.split(flat, split), np.split(z, split))
                    self._record(step, np.split(flat, split), entered, left, residual, outer)
                    if entered == 0 and left == 0:
                        break
                    flat = np.concatenate(nxt)
                else:
                    self._fail(
                        f"the penalty iteration did not converge in {self.max_iterations} "
                        f"solves at load {step.load:g}"
                    )
                change = _relative_change(self.comm, lam_new, lam.array_r)
                lam.array[:] = lam_new
                # h2: the monitor records the rate, raises c when it is poor, decides the stop
                if not augmented or monitor.update(step, change, c):
                    step.converged = True
                    break
            else:
                self._fail(
                    f"the augmented Lagrangian did not converge in {self.max_iterations} "
                    f"updates at load {step.load:g}"
                )
            offset = 0
            for u in self.u:
                n = u.x.petsc_vec.getLocalSize()
                u.x.array[:n] = U.array_r[offset : offset + n]
                u.x.scatter_forward()
                offset += n
            parts = np.split(lam.array_r, np.cumsum(sizes)[:-1])
            for f, part in zip(self.multipliers, parts, strict=True):
                f.x.array[: part.size] = part
                f.x.scatter_forward()
            return np.split(flat, np.cumsum(sizes)[:-1])
        finally:
            for obj in owned:
                obj.destroy()

    def _check_linear(self, ksp: PETSc.KSP, P: PETSc.Mat, rhs: PETSc.Vec, U: PETSc.Vec) -> None:
        """Raise unless the KSP converged with a small relative residual."""
        if ksp.getConvergedReason() < 0:
            raise RuntimeError(
                "the penalty solve failed: " + solver_failure(ksp, self.options.prefix)
            )
        r = rhs.duplicate()
        P.mult(U, r)
        r.aypx(-1.0, rhs)
        rel = r.norm() / max(rhs.norm(), np.finfo(float).tiny)
        r.destroy()
        if not rel <= self.residual_tolerance:
            raise RuntimeError(
                f"the penalty solve cannot be trusted: relative residual {rel:.2e} > "
                f"{self.residual_tolerance:.0e}"
            )


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


def _relative_change(
    comm: MPI.Comm, new: npt.NDArray[np.floating], old: npt.NDArray[np.floating]
) -> float:
    r""":math:`\\max|new - old| / \\max|new|` over all processes (0 if both vanish)."""
    change = comm.allreduce(float(np.max(np.abs(new - old), initial=0.0)), op=MPI.MAX)
    size = comm.allreduce(float(np.max(np.abs(new), initial=0.0)), op=MPI.MAX)
    return change / size if size > 0 else change

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Frictional contact (Coulomb) with Lagrange multipliers, in 2D and 3D, over load steps.

:class:`FrictionalContactProblem` holds a
:class:`~dolfinx_contact_s2s.system.ContactSystem` (through
:class:`~dolfinx_contact_s2s.problem.ContactProblemBase`), the normal complementarity of
Eq. (1) (:class:`~dolfinx_contact_s2s.unilateral.complementarity.Complementarity`) and
the tangential field (:class:`~dolfinx_contact_s2s.friction.coulomb.CoulombFriction`),
and runs the semismooth Newton (primal-dual active set) iteration on both.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import time
import typing
from collections.abc import Callable, Sequence

from mpi4py import MPI

import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s import checks, system_checks
from dolfinx_contact_s2s.checks.inputs import check_inequality_multipliers
from dolfinx_contact_s2s.friction.coulomb import CoulombFriction
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.problem import ContactProblemBase
from dolfinx_contact_s2s.unilateral.complementarity import (
    Complementarity,
    given_active,
    owned_indices,
)
from dolfinx_contact_s2s.unilateral.history import ContactHistory, Iteration, LoadStep
from dolfinx_contact_s2s.unilateral.iteration import ContactIteration
from dolfinx_contact_s2s.unilateral.problem import STARTS

__all__ = ["FrictionalContactProblem"]


def _check(mu: float, pairs: Sequence[ContactPair], name: str = "friction coefficient mu") -> str:
    """What is wrong with the friction input on this process ('' if nothing)."""
    if not (isinstance(mu, (int, float, np.floating)) and np.isfinite(mu) and mu >= 0):
        return f"the {name} must be a finite number >= 0, not {mu!r}"
    for pair in pairs:
        if pair.obstacles or any(getattr(t, "rigid", False) for t in pair.targets):
            return "friction is implemented against meshed deformable targets only"
    try:
        check_inequality_multipliers(pairs)
    except ValueError as error:
        return str(error)
    return ""


class FrictionalContactProblem(ContactProblemBase):
    r"""Linear elastic bodies in unilateral contact with Coulomb friction (2D and 3D).

    The conditions of Eq. (1) on the weighted gaps :math:`\tilde g` (Eq. 17), and per
    multiplier node Coulomb's law on the weighted tangential slip increments
    :math:`\tilde s` of each load step (Eq. 40 with the contactor's tangent
    :math:`\mathbf T = (-n_{C,y}, n_{C,x})` in place of :math:`\mathbf N`, in 3D the
    orthonormal tangents :math:`\mathbf T_1 = \mathbf a \times \mathbf N / |\mathbf a
    \times \mathbf N|`, :math:`\mathbf T_2 = \mathbf N \times \mathbf T_1`, measured from
    the previous step's solution, so that the answer depends on the load path):
    :math:`|\lambda_t| \le \mu \lambda_n`, :math:`\tilde s = 0` where
    :math:`|\lambda_t| < \mu \lambda_n`, :math:`\lambda_t = \mu \lambda_n \tilde s /
    |\tilde s|` where it slips (:mod:`~dolfinx_contact_s2s.friction.coulomb`).
    :math:`\lambda_n` is the contact pressure, :math:`\lambda_t` the shear the contactor
    exerts on the target along :math:`\mathbf T` (in 3D its components along
    :math:`\mathbf T_1, \mathbf T_2`; in the multiplier space of :math:`\lambda_n`). The
    answer does not depend on the axis :math:`\mathbf a` (``tangent_axis``), only the
    components of :math:`\lambda_t` do. Every iteration is one (unsymmetric) saddle-point solve with
    the inactive, stick and slip sets of the previous one; a load step ends when the
    sets and slip directions repeat and both complementarity residuals are below
    ``tolerance``.

    After :meth:`solve`: :attr:`u`, :attr:`multipliers` (:math:`\lambda_n`),
    :attr:`tangential` (:math:`\lambda_t`; in 3D two per pair, along :math:`\mathbf T_1`
    and :math:`\mathbf T_2` of the axes :attr:`tangent_axes`), :attr:`active`,
    :attr:`gaps` (the weighted gaps :math:`\tilde g_j`),
    :attr:`stick` (1 on the sticking multipliers) and :attr:`history` (its iterations
    count the active and sticking multipliers of every pair). A load step that does not
    converge within ``max_iterations`` raises
    :class:`~dolfinx_contact_s2s.unilateral.ContactConvergenceError` on every process,
    with the sets of every iteration.
    """

    signed_conditions = True

    def __init__(
        self,
        a: ufl.Form | Sequence[ufl.Form],
        L: ufl.Form | Sequence[ufl.Form],
        pairs: Sequence[ContactPair],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        *,
        mu: float,
        slip_bound: float | None = None,
        tangent_axis: npt.ArrayLike | None = None,
        start: str = "nearest",
        penalty: float = 1.0,
        max_iterations: int = 50,
        tolerance: float = 1e-10,
        monitor: Callable[[Iteration], None] | None = None,
        **options: typing.Any,
    ):
        r"""Set up the problem: the arguments of ``UnilateralContactProblem`` and ``mu``.

        Args:
            a: Bilinear form of each displacement space.
            L: Linear form of each displacement space.
            pairs: Contact pairs (plane, axisymmetric or 3D; meshed deformable targets).
            bcs: Dirichlet conditions.
            mu: Coulomb's friction coefficient :math:`\mu \ge 0`.
            slip_bound: Tresca's law instead: the given bound :math:`g \ge 0` of
                :math:`|\lambda_t|` (a shear stress) in place of :math:`\mu \lambda_n`.
            tangent_axis: In 3D, the axis :math:`\mathbf a` of the tangent basis (default:
                the Cartesian axis least aligned with each contactor's mean normal,
                :func:`~dolfinx_contact_s2s.friction.coulomb.tangent_axis`).
            start: First active set, one of
                :data:`~dolfinx_contact_s2s.unilateral.STARTS`; it sticks.
            penalty: Factor :math:`\kappa` of the complementarity parameters
                :math:`c_j` (normal and tangential).
            max_iterations: Largest number of linear solves per load step.
            tolerance: Largest relative complementarity residual of a converged step.
            monitor: Called with every recorded iteration.
            options: ``petsc_options_prefix`` (required) and the other keyword arguments
                of :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`. The
                default factorization is LU: the system is unsymmetric.

        Raises:
            ValueError: On every rank, for :math:`\mu` negative, NaN or infinite, a bad
                parameter, ``kind="nest"``, a rigid-target pair, or a tangent basis that
                degenerates on a contact surface.
        """
        if options.get("kind", "aij") != "aij":
            raise ValueError("friction needs kind='aij' (an unsymmetric system, factorized)")
        if start not in STARTS:
            raise ValueError(f"start must be one of {STARTS}, not {start!r}")
        if not (penalty > 0 and np.isfinite(penalty)):
            raise ValueError(f"penalty must be positive and finite, not {penalty}")
        if int(max_iterations) < 1 or not tolerance > 0:
            raise ValueError("need max_iterations >= 1 and tolerance > 0")
        self.start, self.penalty = start, float(penalty)
        self.max_iterations, self.tolerance = int(max_iterations), float(tolerance)
        self._monitor = monitor
        self._friction: CoulombFriction | None = None
        self._complementarity: Complementarity | None = None
        self._support: tuple[checks.SupportGram, list] | None = None
        super().__init__(a, L, pairs, bcs, **options)
        bound = "" if slip_bound is None else _check(slip_bound, [], "slip bound")
        problems = [m for m in self.comm.allgather(bound or _check(mu, pairs)) if m]
        if problems:
            self.destroy()
            raise ValueError(problems[0])
        self.mu, self.slip_bound, self.tangent_axis = float(mu), slip_bound, tangent_axis
        self.active = [dolfinx.fem.Function(p.Q, name=f"active{j}") for j, p in enumerate(pairs)]
        self.stick = [dolfinx.fem.Function(p.Q, name=f"stick{j}") for j, p in enumerate(pairs)]
        self.gaps = [dolfinx.fem.Function(p.Q, name=f"gap{j}") for j, p in enumerate(pairs)]
        self.tangential: list[dolfinx.fem.Function] = []
        self.tangent_axes: list[npt.NDArray[np.float64] | None] = []
        self.history = ContactHistory("coulomb")

    def solver_defaults(self) -> dict[str, typing.Any]:
        """The defaults of every linear solve: MUMPS LU (the system is unsymmetric)."""
        return {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}

    def assemble(self, check: bool = True) -> None:
        r"""Assemble the system, the complementarity parameters and the tangential coupling.

        With ``check``, the support of every body (Eq. 33) counts the tangential rows too
        if :math:`\mu > 0` (a body held by sticking contact), and the rank check
        (Eq. 35) is the normal one; the support is kept to check the sets of every solve.
        """
        system = self.system
        system.assemble(check=False)
        for old in (self._complementarity, self._friction):
            if old is not None:
                old.destroy()
        self._complementarity = Complementarity(system, self.penalty, self.tolerance)
        self._friction = CoulombFriction(system, self.mu, self.slip_bound, self.tangent_axis)
        self.tangential = self._friction.multipliers
        self.tangent_axes = self._friction.axes
        if check:
            held = self.mu > 0 or bool(self.slip_bound)
            ops = system.operators + (self._friction.operators if held else [])
            K = [system.stiffness_matrix(i) for i in range(len(self.spaces))]
            labels = [checks.connected_components(V.mesh)[0] for V in self.spaces]
            try:
                gram = system_checks.check_support(
                    self.spaces, K, system.masks, ops, system.space_index, labels
                )
                self._support = (gram, labels)
                system_checks.check_redundancy(
                    system.pairs, system.operators, system.masks, system.space_index
                )
            finally:
                for k in K:
                    k.destroy()

    def solve(
        self,
        load_factors: Sequence[float] = (1.0,),
        *,
        restart: bool = True,
        mu: float | None = None,
        after: FrictionalContactProblem | None = None,
        active: Sequence[Callable | npt.NDArray[np.bool_] | None] | None = None,
    ) -> tuple[list[dolfinx.fem.Function], list[dolfinx.fem.Function], list[dolfinx.fem.Function]]:
        r"""Assemble, then solve the load steps in turn, each slipping from the previous one.

        Args:
            load_factors: Factors on the loads and Dirichlet values, solved in order.
            restart: Start from rest (zero displacement, the ``start`` set); ``False``
                continues the previous solve (its solution and sets) under the loads and
                Dirichlet values as they are now: a load path of several shapes (say a
                normal load, then a tangential one), changed between the solves.
            mu: The friction coefficient of these steps (default: the problem's ``mu``),
                e.g. 0 for a frictionless normal load before a tangential one.
            after: Continue another problem's last solve instead, on the same spaces
                and pairs with other Dirichlet conditions (say a symmetry condition
                that held a body while it was frictionless, released).
            active: From rest, the first active set instead of ``start``, as in
                :meth:`UnilateralContactProblem.solve
                <dolfinx_contact_s2s.unilateral.UnilateralContactProblem.solve>` (e.g. a
                previous solution's on a refined mesh); it sticks.

        Returns:
            The displacement of every space, and :math:`\lambda_n` and
            :math:`\lambda_t` of every pair, at the last load factor.

        Raises:
            ValueError: On every rank, if the model is singular, a factor not finite,
                ``active`` has not one entry per pair of the right size, or ``after`` is
                unsolved or has other spaces or pairs.
            ContactConvergenceError: On every rank, if a load step does not converge, or
                if the slip of a solve leaves free a body that only friction holds (its
                tangential load exceeds :math:`\mu` times its normal load), naming it.
        """
        loads = [float(t) for t in load_factors]
        if not loads or not all(np.isfinite(loads)):
            raise ValueError("give at least one finite load factor")
        problems = [m for m in self.comm.allgather(_check(self.mu if mu is None else mu, [])) if m]
        if problems:
            raise ValueError(problems[0])
        if active is not None and (not restart or after is not None):
            raise ValueError("active is a first guess from rest: not with restart=False or after")
        if after is not None and not (
            len(after.pairs) == len(self.pairs)
            and all(p is q for p, q in zip(after.pairs, self.pairs, strict=False))
            and all(V is W for V, W in zip(after.spaces, self.spaces, strict=False))
            and after._friction is not None
        ):
            raise ValueError(
                "after= continues a solved problem on the same spaces and pairs: build "
                "this problem with the other one's pair objects, after its solve"
            )
        given = given_active(self.pairs, self.comm, active)
        source = (self if after is None else after)._friction
        state = None if (restart and after is None) or source is None else source.state()
        self.assemble()
        comp, friction = self._complementarity, self._friction
        assert comp is not None and friction is not None
        friction.set_coefficient(self.mu if mu is None else mu)
        active = None if state is None else friction.restore(state)
        run = ContactIteration(
            self.system, comp, "coulomb", self.max_iterations, self.tolerance, self._monitor
        )
        self.history = run.history
        for t in loads:
            step = LoadStep(t)
            self.history.steps.append(step)
            begin = time.perf_counter()
            if active is None:
                active = comp.first_active(t, self.start, given)
            friction.start(active)  # every step's first solve: the active multipliers stick
            for _ in range(self.max_iterations):
                stick = [s.copy() for s in friction.stick]
                self.system.build(comp.released(active), load=t, extra=friction)
                run.solve_linear(step)
                friction.scatter()
                z, normal = comp.evaluate(comp.lambdas(), comp.weighted_gaps())
                new, entered, left = comp.update(active, z)
                changed, tangential = friction.update(z, new, comp.scales, self.tolerance)
                run.record(step, active, entered, left, max(normal, tangential), stick=stick)
                active = new
                if entered == left == changed == 0 and max(normal, tangential) <= self.tolerance:
                    step.converged = True
                    break
                self._check_slip(run, step, active)
            else:
                run.fail(
                    f"the frictional active-set iteration did not converge in "
                    f"{self.max_iterations} solves at load {t:g} (raise max_iterations, "
                    "or take smaller load steps)"
                )
            friction.accept()
            step.seconds = time.perf_counter() - begin
        gaps = comp.weighted_gaps()
        for fs, sets in ((self.active, active), (self.stick, friction.stick), (self.gaps, gaps)):
            for f, a in zip(fs, sets, strict=True):
                f.x.array[:] = 0.0
                f.x.array[: a.size] = a
                f.x.scatter_forward()
        return self.u, self.multipliers, self.tangential

    def _check_slip(self, run: ContactIteration, step: LoadStep, active: list) -> None:
        """Raise if the next sets free a body: by slip where sticking holds it, or open (Eq. 33).

        Else the next solve is singular: a direct solver returns arbitrary displacements
        and the sets cycle.
        """
        comp, friction = self._complementarity, self._friction
        if self._support is None or comp is None or friction is None:
            return
        (gram, labels), pairs = self._support, self.system.pairs
        normal = [
            np.union1d(op.inactive, r)
            for op, r in zip(self.system.operators, comp.released(active), strict=True)
        ]

        def free(stick: list) -> list:  # per pair; its tangential operators are consecutive
            ops, nd = enumerate(friction.operators), friction.directions
            return gram.motions(normal + [owned_indices(op.G, ~stick[i // nd]) for i, op in ops])

        motions = free(friction.stick)
        if not motions:
            return
        if len(free(active)) >= len(motions):  # the contact opened: slip is not to blame
            lines = "\n".join(f"  - {m.describe()}" for m in motions)
            run.fail(
                f"solve {len(step.iterations)} at load {step.load:g}: the active set leaves "
                f"these rigid motions free, held by contact alone and the contact open (Eq. "
                f"33):\n{lines}\nHold every body by a Dirichlet condition, or take smaller "
                "load steps."
            )
        m, body = motions[0], motions[0].motions[0].body()
        roles = [
            f"the {role} of pair {j}"
            for j, pair in enumerate(pairs)
            for role, s in (("contactor", pair.contactor), *(("target", t) for t in pair.targets))
            if self.comm.allreduce(
                self.system.space_index(s.V) == m.space
                and bool(np.any(labels[m.space][s.cells] == m.component)),
                op=MPI.LOR,
            )
        ]
        limit = (
            f"mu = {friction.mu:g} times its normal load"
            if self.slip_bound is None
            else f"the slip bound {self.slip_bound:g} times its contact surface"
        )
        run.fail(
            f"solve {len(step.iterations)} at load {step.load:g}: {body} ({', '.join(roles)}) "
            f"slips on every active multiplier and nothing else holds it tangentially "
            f"({m.description} is free): the tangential load on it exceeds {limit}. Hold it by "
            "a Dirichlet condition or lower that load (if it should stick: smaller load steps)."
        )

    def destroy(self) -> None:
        """Destroy the PETSc objects and remove the problem's options from the database."""
        for obj in (self._complementarity, self._friction):
            if obj is not None:
                obj.destroy()
        super().destroy()

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Finite deformation: the user's nonlinear bodies in contact on the current configuration.

Newton's method on the residual :math:`\mathbf R(\mathbf u) - \mathbf B(\mathbf
u)^T \Lambda = \mathbf 0` with the contact conditions of Eq. (15) (tied) or Eq. (1)
(unilateral) on the gap of the current configuration. In every iteration the contact
surfaces are placed at :math:`X + \mathbf u_k`
(:meth:`~dolfinx_contact_s2s.surface.ContactSurface.set_displacement`): the candidates
are searched again, the sub-segments (2D) or overlap polygons (3D) and the coupling
:math:`\mathbf B_k` of Eq. (40) rebuilt there, and the gap linearized at
:math:`\mathbf u_k`, :math:`\mathbf G(\mathbf U) \approx \mathbf G_k + \mathbf B_k
(\mathbf U - \mathbf u_k)`. The linear problem of the iteration,

.. math::
    \mathbf J(\mathbf u_k)\, \mathbf U - \mathbf B_k^T \Lambda
    = \mathbf J(\mathbf u_k)\, \mathbf u_k - \mathbf R(\mathbf u_k),

is the problem of :class:`~dolfinx_contact_s2s.problem.LinearContactProblem` (tied) or
:class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem` (its active-set loop
starting from the previous iteration's set) in the total displacement :math:`\mathbf U`,
with the user's Dirichlet conditions as they are, and every check of those solves.

With ``linearization="full"`` (the default) Newton's matrix also holds the change of the
contact terms with :math:`\mathbf u` (the normals, the projections and the sub-segment
ends): :math:`\mathbf J - \mathbf H_k` in the displacement rows, :math:`\mathbf H_k =
\partial (\mathbf B^T \Lambda_k) / \partial \mathbf u`, and the gap's derivative
:math:`\mathbf D_k` in the multiplier rows
(:class:`~dolfinx_contact_s2s.finite.tangent.ContactTangent`: central differences of each
group's integrals, about :math:`10^{-10}` relative); Newton then converges
quadratically where the coupling is smooth (flat surfaces sliding; measured orders on
curved faceted ones: README). The first iteration of a step, which moves to its new
loads, leaves them out, and so does one whose contact set cycles with them. A
multiplier whose support a target covers only in part keeps its row of :math:`\mathbf B_k`
(:attr:`~dolfinx_contact_s2s.assemble.CouplingOperator.partial`): its weighted gap is
the gap times the covered length, whose derivative would extrapolate it through zero
at the end of a target's reach. ``"frozen"``: every iteration without them (linear
convergence where surfaces slide).
:attr:`step` records every iteration's residuals and the measured order.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import logging
import math
import time
import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from mpi4py import MPI
from petsc4py import PETSc

import basix
import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl

from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.finite.tangent import ContactTangent
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import ContactConvergenceError, UnilateralContactProblem

__all__ = ["NewtonIteration", "NonlinearContactProblem", "NonlinearConvergenceError"]

logger = logging.getLogger("dolfinx_contact_s2s.finite")


@dataclass
class NewtonIteration:
    r"""One Newton iteration of :class:`NonlinearContactProblem`.

    Attributes:
        residual: :math:`\|\mathbf R - \mathbf B^T \Lambda\|_\infty` on the free dofs
            at the iteration's start, relative to the force scale (:attr:`scale`).
        scale: The force scale: the largest of :math:`|\mathbf R|` on all dofs
            (reactions included) and :math:`|\mathbf B^T \Lambda|`.
        gap: The largest weighted gap of an active multiplier relative to the
            contactor's size, at the iteration's start (:meth:`residual`).
        increment: :math:`\|\mathbf U - \mathbf u_k\|_\infty` of its solve.
        active: Active multipliers after its solve (all pairs, all processes).
        changed: Multipliers whose active state its solve changed.
        solves: Linear solves of its contact iteration.
        seconds: Its wall time (process 0).
        frozen: Whether its matrix left out the coupling's change (the first iteration
            of a step; one whose contact set cycled with it; ``"frozen"``).
        damping: The fraction of its step taken (halved while the step inverts cells).
    """

    residual: float
    scale: float
    gap: float
    increment: float = math.nan
    active: int = 0
    changed: int = 0
    solves: int = 0
    seconds: float = 0.0
    frozen: bool = False
    damping: float = 1.0


@dataclass
class NewtonStep:
    """The iterations of one :meth:`NonlinearContactProblem.solve`."""

    iterations: list[NewtonIteration] = field(default_factory=list)
    converged: bool = False

    @property
    def orders(self) -> list[float]:
        r"""Measured orders :math:`\log(r_{k+1}/r_k) / \log(r_k/r_{k-1})` of the residuals.

        Only where they mean one: from falling residuals :math:`r_{k-1} > r_k > r_{k+1}`
        of Newton iterations (with the tangent) that left the contact set alone, with
        :math:`r_{k+1}` above a hundred times the last residual (the round-off floor of
        a converged step).
        """
        its = self.iterations
        r = [it.residual for it in its]
        floor = 100 * r[-1] if self.converged else 0.0
        return [
            math.log(r[k + 1] / r[k]) / math.log(r[k] / r[k - 1])
            for k in range(1, len(r) - 1)
            if r[k - 1] > r[k] > r[k + 1] > floor
            and not (its[k - 1].changed or its[k].changed or its[k - 1].frozen or its[k].frozen)
        ]

    def describe(self) -> str:
        """One line per iteration: residual, increment, active set and solves."""
        return "\n".join(
            f"  {k}: residual {it.residual:.3e}, gap {it.gap:.1e}, increment {it.increment:.1e}, "
            f"active {it.active} (changed {it.changed}), {it.solves} solves"
            for k, it in enumerate(self.iterations)
        )


class NonlinearConvergenceError(RuntimeError):
    """Newton's method did not converge; the step's iterations are in :attr:`step`."""

    def __init__(self, message: str, step: NewtonStep):
        """Keep the step's history."""
        super().__init__(message + "\n" + step.describe())
        self.step = step


def _size(surface: typing.Any, comm: MPI.Comm) -> float:
    """The largest extent of a surface's cells' nodes over all processes."""
    x = surface.reference.coords.reshape(-1, surface.reference.coords.shape[2])
    low, high = x.min(axis=0, initial=np.inf), x.max(axis=0, initial=-np.inf)
    comm.Allreduce(MPI.IN_PLACE, low, op=MPI.MIN)
    comm.Allreduce(MPI.IN_PLACE, high, op=MPI.MAX)
    return float(np.max(high - low))


def _as_list(x: typing.Any) -> list:
    return list(x) if isinstance(x, (list, tuple)) else [x]


class NonlinearContactProblem:
    r"""Bodies with the user's residual forms, in contact on the current configuration.

    Shaped like :class:`dolfinx.fem.petsc.NonlinearProblem`: residual forms
    :math:`F_i(\mathbf u_i; \mathbf v_i)` (any UFL energy's derivative, e.g. a
    compressible neo-Hookean solid, or a linear form), the unknown functions
    :math:`\mathbf u_i` (updated in place), optional Jacobians (default
    :func:`ufl.derivative`), the contact pairs and Dirichlet conditions on the total
    displacement. Load steps are the user's: change the loads and Dirichlet values, then
    call :meth:`solve` again; each solve starts from the current :math:`\mathbf u_i`.

    Every iteration checks its linear solve as the linear problems do; a Newton step that
    would invert a cell (:math:`\det F \le 0` at a vertex or Gauss point) is halved, and an
    inverted start raises, naming the cell; a solve that does not converge raises
    :class:`NonlinearConvergenceError` with its iterations (:attr:`step`).
    """

    def __init__(
        self,
        F: ufl.Form | Sequence[ufl.Form],
        u: dolfinx.fem.Function | Sequence[dolfinx.fem.Function],
        pairs: Sequence[ContactPair],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        *,
        J: ufl.Form | Sequence[ufl.Form] | None = None,
        contact: str = "unilateral",
        linearization: str = "full",
        max_iterations: int = 25,
        rtol: float = 1e-10,
        atol: float = 0.0,
        monitor: Callable[[NewtonIteration], None] | None = None,
        **options: typing.Any,
    ):
        r"""Set up the linear problem of an iteration (collective).

        Args:
            F: Residual form of each displacement space (``F_i(u_i; v_i)``).
            u: The displacement of each space, the unknowns (their values are the start).
            pairs: Contact pairs between surfaces of these spaces, made on the reference
                configuration.
            bcs: Dirichlet conditions on the total displacement.
            J: Jacobian of each ``F_i``; default ``ufl.derivative(F_i, u_i)``.
            contact: ``"unilateral"`` (Eq. 1, the active-set loop) or ``"tied"``.
            linearization: ``"full"``: the change of the contact terms with
                :math:`\mathbf u` in Newton's matrix
                (:class:`~dolfinx_contact_s2s.finite.tangent.ContactTangent`; meshed
                targets, not ``"intermediate-surface"``); ``"frozen"``: the coupling of
                each iteration without its change (linear convergence where surfaces
                slide).
            max_iterations: Largest number of Newton iterations of a solve.
            rtol: Converged when the residual relative to the force scale is at most
                ``rtol`` (or at most ``atol`` absolute), the gap residual relative to the
                contactor's size at most ``rtol``, and the active set did not change.
            atol: Absolute residual tolerance.
            monitor: Called with every :class:`NewtonIteration` once it is recorded.
            options: Keyword arguments of the linear problem
                (:class:`~dolfinx_contact_s2s.problem.LinearContactProblem`, or
                :class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem`):
                ``petsc_options_prefix`` (required), ``petsc_options``,
                ``residual_tolerance``, ``tolerance``, ...

        Raises:
            ValueError: For an unknown ``contact``, bad tolerances, or forms and
                functions that do not match.
        """
        if contact not in ("unilateral", "tied"):
            raise ValueError(f"contact must be 'unilateral' or 'tied', not {contact!r}")
        if linearization not in ("full", "frozen"):
            raise ValueError(f"linearization must be 'full' or 'frozen', not {linearization!r}")
        local = all(
            p.method != "intermediate-surface"
            and not p.obstacles
            and not any(t.rigid for t in p.targets)
            for p in pairs
        )
        if linearization == "full" and not local:
            raise ValueError(
                "linearization='full' needs pairs whose groups depend on their two cells "
                "only (not 'intermediate-surface', no rigid or analytic targets); use "
                "linearization='frozen'"
            )
        F, self.u = _as_list(F), _as_list(u)
        if len(F) != len(self.u):
            raise ValueError("give one residual form per displacement function")
        J = [None] * len(F) if J is None else _as_list(J)
        if len(J) != len(F):
            raise ValueError("give one Jacobian per residual form")
        du = [ufl.TrialFunction(ui.function_space) for ui in self.u]
        J = [
            ufl.derivative(Fi, ui, d) if Ji is None else Ji
            for Fi, ui, d, Ji in zip(F, self.u, du, J, strict=True)
        ]
        L = [ufl.action(Ji, ui) - Fi for Ji, ui, Fi in zip(J, self.u, F, strict=True)]
        self.contact = contact
        self.max_iterations = int(max_iterations)
        self.rtol, self.atol = float(rtol), float(atol)
        self._monitor = monitor
        kind = UnilateralContactProblem if contact == "unilateral" else LinearContactProblem
        self.problem: LinearContactProblem | UnilateralContactProblem = kind(
            J, L, pairs, bcs, **options
        )
        if any(
            ui.function_space is not V for ui, V in zip(self.u, self.problem.spaces, strict=True)
        ):
            self.problem.destroy()
            raise ValueError("each residual form's test function must be in its u's space")
        self._F = [dolfinx.fem.form(Fi) for Fi in F]
        spaces = self.problem.spaces
        self._surfaces = [
            (s, next(i for i, V in enumerate(spaces) if V is s.V))
            for p in self.problem.pairs
            for s in (p.contactor, *p.targets)
            if not s.rigid
        ]
        self._jacobians = [self._det_form(ui) for ui in self.u]
        # One factorization per load step, not per iteration (KeptPattern: a new MUMPS
        # instance on several processes can leak communicators).
        self.problem.system.keep_pattern()
        self.tangent: ContactTangent | None = None
        if linearization == "full":
            self.tangent = ContactTangent(self.problem.system)
        self.step = NewtonStep()
        self._sizes = [_size(p.contactor, self.comm) for p in self.problem.pairs]

    @staticmethod
    def _det_form(u: dolfinx.fem.Function) -> dolfinx.fem.Expression:
        r""":math:`\det(I + \nabla u)` at the cells' vertices and Gauss points of degree 2p.

        Not the midpoint only: on quadratic cells det F varies, and a cell inverted at a
        quadrature point of the forms gives them NaN.
        """
        mesh = u.function_space.mesh
        cell = basix.CellType[mesh.topology.cell_name()]
        degree = u.function_space.element.basix_element.degree
        points, _ = basix.make_quadrature(cell, 2 * degree)
        points = np.vstack([basix.geometry(cell), points])
        gdim = mesh.geometry.dim
        return dolfinx.fem.Expression(ufl.det(ufl.Identity(gdim) + ufl.grad(u)), points)

    @property
    def comm(self) -> MPI.Comm:
        """The communicator of the meshes."""
        return self.problem.comm

    @property
    def pairs(self) -> list[ContactPair]:
        """The contact pairs."""
        return self.problem.pairs

    @property
    def multipliers(self) -> list[dolfinx.fem.Function]:
        """The contact pressure of every pair (the Cauchy traction on the contactor)."""
        return self.problem.multipliers

    @property
    def active(self) -> list[dolfinx.fem.Function]:
        """Every pair's active flags (1 on an active multiplier dof, 0 elsewhere)."""
        return self.problem.active

    def place(self) -> None:
        r"""Place every contact surface at :math:`X + \mathbf u` (collective)."""
        for surface, i in self._surfaces:
            surface.set_displacement(self.u[i])

    def _inverted(self) -> list:
        """Per process, up to three (space, local cell) with det F <= 0 (collective)."""
        bad = []
        for i, (ui, expression) in enumerate(zip(self.u, self._jacobians, strict=True)):
            mesh = ui.function_space.mesh
            n = mesh.topology.index_map(mesh.topology.dim).size_local
            det = expression.eval(mesh, np.arange(n, dtype=np.int32)).reshape(n, -1)
            cells = np.flatnonzero(~np.all(det > 0.0, axis=1))
            bad += [(i, int(c)) for c in cells[:3]]
        return self.comm.allgather(bad)

    def check_cells(self) -> None:
        r"""Raise on every rank if some cell has :math:`\det F \le 0` (:meth:`_det_form`)."""
        found = self._inverted()
        if any(found):
            raise ValueError(
                "the displacement inverts cells (det F <= 0): "
                + "; ".join(
                    f"process {r}: space {i} local cell {c}"
                    for r, cells in enumerate(found)
                    for i, c in cells
                )
                + "; take a smaller load step"
            )

    def residual(self) -> tuple[float, float, float]:
        r"""The residuals at :math:`\mathbf u` and the multipliers (collective).

        With the coupling assembled on surfaces placed at :math:`\mathbf u` (call
        :meth:`place` first): the force residual :math:`\mathbf R(\mathbf u) - \sum_j
        \mathbf B_j(\mathbf u)^T \Lambda_j` on the free dofs, relative to the force
        scale (the largest of :math:`|\mathbf R|`, reactions included, and of the contact
        forces); the scale; and the gap residual: the largest weighted gap
        :math:`|\tilde g_j| / \int \mu_j` of an active multiplier (of a penetrating
        inactive one), relative to the contactor's size.
        """
        problem, comm = self.problem, self.comm
        forces = []
        for Fi in self._F:
            R = dolfinx.fem.petsc.assemble_vector(Fi)
            R.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            forces.append(R)
        contact = [R.duplicate() for R in forces]
        for c in contact:
            c.set(0.0)
        gap = 0.0
        for j, (pair, lam) in enumerate(zip(problem.pairs, problem.multipliers, strict=True)):
            op = assemble_coupling(pair)
            g = op.G.copy()  # G(u) - B(u) u: the gap at u is g + B u
            for V, B in op.blocks:
                i = problem.space_index(V)
                y = B.createVecRight()
                B.multTranspose(lam.x.petsc_vec, y)
                contact[i].array[: y.getLocalSize()] += y.array_r
                B.multAdd(self.u[i].x.petsc_vec, g, g)
                y.destroy()
            n = g.getLocalSize()
            lengths = np.maximum(pair.multiplier_integrals(), pair.multiplier_supports())
            values = g.array_r / np.where(lengths > 0, lengths, 1.0)
            if self.contact == "tied":
                active = np.ones(n, dtype=bool)
                start = g.getOwnershipRange()[0]
                inside = op.inactive[(op.inactive >= start) & (op.inactive < start + n)]
                active[inside - start] = False
            else:
                active = problem.active[j].x.array[:n] > 0.5
            worst = np.where(active, np.abs(values), np.maximum(0.0, -values))
            gap = max(gap, float(np.max(worst, initial=0.0)) / self._sizes[j])
            g.destroy()
            op.destroy()
        largest, scale = 0.0, 0.0
        for i, (R, c) in enumerate(zip(forces, contact, strict=True)):
            scale = max(scale, R.norm(PETSc.NormType.INFINITY), c.norm(PETSc.NormType.INFINITY))
            R.axpy(-1.0, c)
            mask = problem.dirichlet_mask(i)
            R.pointwiseMult(R, mask)
            largest = max(largest, R.norm(PETSc.NormType.INFINITY))
            for v in (mask, c):
                v.destroy()
            R.destroy()
        gap = comm.allreduce(gap, op=MPI.MAX)
        return (largest / scale if scale > 0 else largest), scale, gap

    def _active(self) -> np.ndarray:
        if self.contact == "tied":
            return np.zeros(0, dtype=bool)
        n = [f.function_space.dofmap.index_map.size_local for f in self.problem.active]
        active = self.problem.active
        return np.concatenate([f.x.array[:k] > 0.5 for f, k in zip(active, n, strict=True)])

    def _linear_solve(self, active: list | None, frozen: bool) -> tuple[list | None, int]:
        """The linear problem of an iteration; returns its active set and its solves."""
        system = self.problem.system
        if frozen or self.tangent is None:
            system.set_linearization()
        else:
            self.tangent.update(self.u)
            system.set_linearization(self.tangent.coupling, self.tangent)
        if isinstance(self.problem, UnilateralContactProblem):
            self.problem.solve([1.0], active=active)
            active = [
                f.x.array[: f.function_space.dofmap.index_map.size_local] > 0.5
                for f in self.problem.active
            ]
            return active, self.problem.history.iterations
        self.problem.assemble()
        system.solve()
        return active, 1

    def _update(self, start: list, new: list, multipliers: list) -> float:
        """Move :attr:`u` to the solve's ``new`` values, halving the step while it inverts cells.

        The multipliers are moved by the same fraction (from their ``multipliers``
        before the solve). Returns the fraction; raises (:meth:`check_cells`) below 1/64.
        """
        alpha = 1.0
        while True:
            for ui, u0, u1 in zip(self.u, start, new, strict=True):
                ui.x.array[:] = u0 + alpha * (u1 - u0)
            if not any(self._inverted()):
                break
            if alpha < 1 / 64:
                self.check_cells()
            alpha /= 2
        if alpha < 1.0:
            logger.info("Newton step damped by %g: the full step inverts cells", alpha)
            for f, lam0 in zip(self.problem.multipliers, multipliers, strict=True):
                f.x.array[:] = lam0 + alpha * (f.x.array - lam0)
        return alpha

    def solve(
        self, tangent_first: bool = False, iterations: int | None = None
    ) -> tuple[list[dolfinx.fem.Function], list[dolfinx.fem.Function]]:
        """Newton's method from the current :attr:`u` (collective).

        Args:
            tangent_first: The first iteration with the coupling's change too (for a
                start near the solution under the same loads; by default it is left out).
            iterations: Stop after this many iterations, converged or not, without an
                error (:attr:`step` holds the residual they reached): to measure the
                iteration itself. Default ``None``: up to ``max_iterations``, then
                :class:`NonlinearConvergenceError`.

        Returns:
            The displacements (the functions ``u``, updated) and the multipliers.

        Raises:
            ValueError: On every rank, if an iterate inverts a cell, or a linear problem
                is singular.
            RuntimeError: On every rank, if a linear solve fails.
            NonlinearConvergenceError: On every rank, if the residual is not within the
                tolerances after ``max_iterations`` iterations.
        """
        self.step = step = NewtonStep()
        comm, problem = self.comm, self.problem
        if problem.system.kept is not None:
            problem.system.kept.renew()
        active: list | None = None
        changed = -1
        limit = self.max_iterations if iterations is None else int(iterations)
        for _ in range(limit + 1):
            begin = time.perf_counter()
            self.check_cells()
            self.place()
            residual, scale, gap = self.residual()
            it = NewtonIteration(residual, scale, gap)
            step.iterations.append(it)
            small = residual <= self.rtol or residual * scale <= self.atol
            if changed == 0 and small and gap <= self.rtol:
                step.converged = True
                break
            if len(step.iterations) > limit:
                break
            before = self._active()
            start = [ui.x.array.copy() for ui in self.u]
            multipliers = [f.x.array.copy() for f in problem.multipliers]
            # The first iteration of a step moves to its new loads with the last state's
            # coupling: far from the solution the tangent's unsymmetric terms can make
            # the active-set iteration cycle (a P2 block slid by three elements at once).
            it.frozen = self.tangent is None or (len(step.iterations) == 1 and not tangent_first)
            try:
                active, it.solves = self._linear_solve(active, it.frozen)
            except ContactConvergenceError:
                if it.frozen:
                    raise
                logger.info("the contact set cycles with the tangent: this iteration without")
                it.frozen = True
                active, it.solves = self._linear_solve(active, True)
            after = self._active()
            it.active = comm.allreduce(int(np.count_nonzero(after)))
            changed = comm.allreduce(
                int(np.count_nonzero(before != after)) if before.size == after.size else 1
            )
            it.changed = changed
            increment = 0.0
            for ui, Ui in zip(self.u, problem.u, strict=True):
                dofmap = ui.function_space.dofmap
                n = dofmap.index_map.size_local * dofmap.index_map_bs
                change = np.max(np.abs(Ui.x.array[:n] - ui.x.array[:n]), initial=0.0)
                increment = max(increment, float(change))
            it.increment = comm.allreduce(increment, op=MPI.MAX)
            it.damping = self._update(start, [U.x.array for U in problem.u], multipliers)
            it.seconds = comm.bcast(time.perf_counter() - begin, root=0)
            if self._monitor is not None:
                self._monitor(it)
        if not step.converged and iterations is None:
            raise NonlinearConvergenceError(
                f"Newton's method did not converge in {self.max_iterations} iterations "
                f"(residual {step.iterations[-1].residual:.3e}, rtol {self.rtol:g}); take "
                "smaller load steps",
                step,
            )
        return self.u, self.multipliers

    def destroy(self) -> None:
        """Destroy the linear problem's PETSc objects and return the surfaces to X."""
        for surface, _ in self._surfaces:
            surface.set_displacement(None)
        if self.tangent is not None:
            self.tangent.destroy()
        self.problem.destroy()

    def __enter__(self) -> NonlinearContactProblem:
        """Use as a context manager."""
        return self

    def __exit__(self, *exc: object) -> None:
        """Destroy on exit."""
        self.destroy()

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

Linearized exactly: the bodies (:math:`\mathbf J = \partial \mathbf R / \partial \mathbf
u` from UFL) and the gap's change along the current normals (:math:`\mathbf B_k`). Left
out: the change of :math:`\mathbf B` itself (of the normals, the projections and the
sub-segment ends) with :math:`\mathbf u`. Where those vanish (flat surfaces, where a
motion along the surface changes no normal gap) Newton converges quadratically;
elsewhere linearly, at a rate that falls with the step: :attr:`history` records the
residual of every iteration and its measured order.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import math
import time
import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl

from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

__all__ = ["NewtonIteration", "NonlinearContactProblem", "NonlinearConvergenceError"]


@dataclass
class NewtonIteration:
    r"""One Newton iteration of :class:`NonlinearContactProblem`.

    Attributes:
        residual: :math:`\|\mathbf R - \mathbf B^T \Lambda\|_\infty` on the free dofs
            at the iteration's start, relative to the force scale (:attr:`scale`).
        scale: The force scale: the largest of :math:`|\mathbf R|` on all dofs
            (reactions included) and :math:`|\mathbf B^T \Lambda|`.
        increment: :math:`\|\mathbf U - \mathbf u_k\|_\infty` of its solve.
        active: Active multipliers after its solve (all pairs, all processes).
        changed: Multipliers whose active state its solve changed.
        solves: Linear solves of its contact iteration.
        seconds: Its wall time (process 0).
    """

    residual: float
    scale: float
    increment: float = math.nan
    active: int = 0
    changed: int = 0
    solves: int = 0
    seconds: float = 0.0


@dataclass
class NewtonStep:
    """The iterations of one :meth:`NonlinearContactProblem.solve`."""

    iterations: list[NewtonIteration] = field(default_factory=list)
    converged: bool = False

    @property
    def orders(self) -> list[float]:
        r"""Measured orders :math:`\log(r_{k+1}/r_k) / \log(r_k/r_{k-1})` of the residuals."""
        r = [it.residual for it in self.iterations]
        return [
            math.log(r[k + 1] / r[k]) / math.log(r[k] / r[k - 1])
            for k in range(1, len(r) - 1)
            if r[k + 1] > 0 and r[k] > 0 and r[k - 1] > 0 and r[k] != r[k - 1]
        ]

    def describe(self) -> str:
        """One line per iteration: residual, increment, active set and solves."""
        return "\n".join(
            f"  {k}: residual {it.residual:.3e}, increment {it.increment:.3e}, "
            f"active {it.active} (changed {it.changed}), {it.solves} solves"
            for k, it in enumerate(self.iterations)
        )


class NonlinearConvergenceError(RuntimeError):
    """Newton's method did not converge; the step's iterations are in :attr:`step`."""

    def __init__(self, message: str, step: NewtonStep):
        """Keep the step's history."""
        super().__init__(message + "\n" + step.describe())
        self.step = step


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

    Every iteration checks its linear solve as the linear problems do; the step checks
    that no cell is inverted (:math:`\det F \le 0` raises, naming the cell) and raises
    :class:`NonlinearConvergenceError` with its history if it does not converge.
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
            max_iterations: Largest number of Newton iterations of a solve.
            rtol: Converged when the residual relative to the force scale is at most
                ``rtol`` (or at most ``atol`` absolute) and the active set did not change.
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
        if int(max_iterations) < 1 or not (rtol >= 0 and atol >= 0 and rtol + atol > 0):
            raise ValueError("need max_iterations >= 1 and rtol, atol >= 0, not both zero")
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
        self.step = NewtonStep()

    @staticmethod
    def _det_form(u: dolfinx.fem.Function) -> tuple[dolfinx.fem.Function, dolfinx.fem.Expression]:
        r""":math:`\det(I + \nabla u)` at the cells' midpoints (a DG0 function and its rule)."""
        mesh = u.function_space.mesh
        W = dolfinx.fem.functionspace(mesh, ("DG", 0))
        points = W.element.interpolation_points
        points = points() if callable(points) else points
        gdim = mesh.geometry.dim
        expression = dolfinx.fem.Expression(ufl.det(ufl.Identity(gdim) + ufl.grad(u)), points)
        return dolfinx.fem.Function(W), expression

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

    def place(self) -> None:
        r"""Place every contact surface at :math:`X + \mathbf u` (collective)."""
        for surface, i in self._surfaces:
            surface.set_displacement(self.u[i])

    def check_cells(self) -> None:
        r"""Raise on every rank if some cell has :math:`\det F \le 0` at its midpoint."""
        bad = []
        for i, (det, expression) in enumerate(self._jacobians):
            det.interpolate(expression)
            n = det.function_space.dofmap.index_map.size_local
            cells = np.flatnonzero(~(det.x.array[:n] > 0.0))
            bad += [(i, int(c)) for c in cells[:3]]
        found = self.comm.allgather(bad)
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

    def residual(self) -> tuple[float, float]:
        r"""The residual on the free dofs at :math:`\mathbf u` and the multipliers.

        :math:`\mathbf R(\mathbf u) - \sum_j \mathbf B_j(\mathbf u)^T \Lambda_j`, the
        coupling assembled on surfaces placed at :math:`\mathbf u` (call :meth:`place`
        first). Returns the largest entry relative to the force scale, and the scale
        (collective).
        """
        problem = self.problem
        forces = []
        for Fi in self._F:
            R = dolfinx.fem.petsc.assemble_vector(Fi)
            R.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            forces.append(R)
        contact = [R.duplicate() for R in forces]
        for c in contact:
            c.set(0.0)
        for pair, lam in zip(problem.pairs, problem.multipliers, strict=True):
            op = assemble_coupling(pair)
            for V, B in op.blocks:
                i = problem.space_index(V)
                y = B.createVecRight()
                B.multTranspose(lam.x.petsc_vec, y)
                contact[i].array[: y.getLocalSize()] += y.array_r
                y.destroy()
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
        return (largest / scale if scale > 0 else largest), scale

    def _active(self) -> np.ndarray:
        if self.contact == "tied":
            return np.zeros(0, dtype=bool)
        n = [f.function_space.dofmap.index_map.size_local for f in self.problem.active]
        active = self.problem.active
        return np.concatenate([f.x.array[:k] > 0.5 for f, k in zip(active, n, strict=True)])

    def solve(self) -> tuple[list[dolfinx.fem.Function], list[dolfinx.fem.Function]]:
        """Newton's method from the current :attr:`u` (collective).

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
        active: list | None = None
        changed = -1
        for _ in range(self.max_iterations + 1):
            begin = time.perf_counter()
            self.check_cells()
            self.place()
            residual, scale = self.residual()
            it = NewtonIteration(residual, scale)
            step.iterations.append(it)
            if changed == 0 and (residual <= self.rtol or residual * scale <= self.atol):
                step.converged = True
                break
            if len(step.iterations) > self.max_iterations:
                break
            before = self._active()
            if isinstance(problem, UnilateralContactProblem):
                problem.solve([1.0], active=active)
                active = [
                    f.x.array[: f.function_space.dofmap.index_map.size_local] > 0.5
                    for f in problem.active
                ]
                it.solves = problem.history.iterations
            else:
                problem.assemble()
                problem.system.solve()
                it.solves = 1
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
                ui.x.array[:] = Ui.x.array
            it.increment = comm.allreduce(increment, op=MPI.MAX)
            it.seconds = comm.bcast(time.perf_counter() - begin, root=0)
            if self._monitor is not None:
                self._monitor(it)
        if not step.converged:
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
        self.problem.destroy()

    def __enter__(self) -> NonlinearContactProblem:
        """Use as a context manager."""
        return self

    def __exit__(self, *exc: object) -> None:
        """Destroy on exit."""
        self.destroy()

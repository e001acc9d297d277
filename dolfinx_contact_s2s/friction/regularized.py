# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Regularized (penalty) Coulomb friction: the cheap alternative to the multipliers.

:class:`RegularizedFrictionProblem`: no multiplier among the unknowns; its error against
:class:`~dolfinx_contact_s2s.friction.FrictionalContactProblem` falls like :math:`1/\kappa`.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import numbers
import time
import typing
from collections.abc import Callable, Sequence

from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.checks.inputs import check_inequality_multipliers
from dolfinx_contact_s2s.friction.coulomb import CoulombFriction
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.problem import ContactProblemBase
from dolfinx_contact_s2s.unilateral.complementarity import Complementarity
from dolfinx_contact_s2s.unilateral.history import ContactHistory, Iteration, LoadStep
from dolfinx_contact_s2s.unilateral.iteration import ContactIteration

__all__ = ["RegularizedFrictionProblem"]

_Functions = list[dolfinx.fem.Function]


def _check(mu: typing.Any, penalty: typing.Any, pairs: Sequence[ContactPair]) -> str:
    """What is wrong with the input on this process ('' if nothing); collective."""
    try:
        check_inequality_multipliers(pairs)  # collective: first, on every rank
    except ValueError as error:
        return str(error)
    for name, value, least in (("friction coefficient mu", mu, 0.0), ("penalty", penalty, 1e-300)):
        if not (isinstance(value, numbers.Real) and np.isfinite(value) and value >= least):
            return f"the {name} must be a finite number {'>' if least else '>='} 0, not {value!r}"
    if any(p.axisymmetric or p.obstacles or any(t.rigid for t in p.targets) for p in pairs):
        return "regularized friction takes plane (2D) and 3D pairs of meshed deformable bodies"
    return ""


class RegularizedFrictionProblem(ContactProblemBase):
    r"""Linear elastic bodies in contact with regularized (penalty) Coulomb friction.

    Per multiplier node :math:`j` of a pair (2D and 3D), :math:`\lambda_{n,j} = c_j
    \max(0, -\tilde g_j)` and the return mapping :math:`\lambda_{t,j} = \lambda^*_j
    \min(1, \mu \lambda_{n,j} / |\lambda^*_j|)` of :math:`\lambda^*_j =
    \lambda^{\mathrm{prev}}_{t,j} + c_j \Delta \tilde s_j` (stick inside Coulomb's disk,
    slip on its rim): :math:`\tilde g = \mathbf B \mathbf U + \mathbf G` (Eq. 17),
    :math:`\Delta \tilde s = \mathbf B_t (\mathbf U - \mathbf U_{\mathrm{prev}})` the
    weighted slip of the load step, :math:`c_j = \kappa \bar E / \int \mu_j h` with
    :math:`h` the contactor's facet size and :math:`\bar E` the median diagonal entry of
    the free stiffness (a uniform penetration or slip of a uniform mesh is a uniform
    traction: the patch tests pass). Shear and slip carry over the load steps.

    A step solves :math:`\mathbf K \mathbf U - \mathbf F - \mathbf B^T \lambda_n +
    \mathbf B_t^T \lambda_t = 0` by Newton's method (PETSc SNES) with the tangent
    :math:`\mathbf K + \mathbf C^T \mathbf D \mathbf C` (:math:`\mathbf C` both rows
    stacked, :math:`\mathbf D` the tractions' derivative per node). As in the Lagrange
    solver, a node slipping along :math:`\xi` that turns round sticks first: it decides
    by :math:`z = (1 - \theta) \mu \lambda_n \xi + \theta \lambda^*`, :math:`\theta =
    \min(1, 1/\kappa)` (the Lagrange
    solver's :math:`\lambda_t + c \tilde s`), not :math:`\lambda^*` (with P2, weighted
    slips change sign at the edge of a stick zone: Newton diverged). A step converges
    when the residual relative to the largest of :math:`\mathbf F`, :math:`\mathbf K
    \mathbf U` and the contact forces is below ``tolerance``, or, the sets repeating, the
    Newton step below :math:`\sqrt{\mathrm{tolerance}}` relative (a large penalty's
    residual stays at its round-off); else it raises
    :class:`~dolfinx_contact_s2s.unilateral.ContactConvergenceError` on every process.
    No support check: a body held by nothing fails the solve.

    After :meth:`solve`: :attr:`u`, :attr:`multipliers` (:math:`\lambda_n`),
    :attr:`tangential` (:math:`\lambda_t`; in 3D two per pair, along the tangents of
    :attr:`tangent_axes`), :attr:`active`, :attr:`stick` and :attr:`history` (per Newton
    iteration, the first at the step's start).
    """

    def __init__(
        self,
        a: ufl.Form | Sequence[ufl.Form],
        L: ufl.Form | Sequence[ufl.Form],
        pairs: Sequence[ContactPair],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        *,
        mu: float,
        penalty: float = 100.0,
        tangent_axis: npt.ArrayLike | None = None,
        max_iterations: int = 50,
        tolerance: float = 1e-12,
        monitor: Callable[[Iteration], None] | None = None,
        **options: typing.Any,
    ):
        r"""Set up the problem.

        Args:
            a: Bilinear form of each displacement space.
            L: Linear form of each displacement space.
            pairs: Contact pairs (2D or 3D, meshed deformable targets).
            bcs: Dirichlet conditions.
            mu: Coulomb's friction coefficient :math:`\mu \ge 0`.
            penalty: The factor :math:`\kappa` of :math:`c_j`.
            tangent_axis: In 3D, the axis of the tangent basis (as the Lagrange solver's).
            max_iterations: Largest number of Newton steps per load step.
            tolerance: Largest relative residual of a converged step.
            monitor: Called with every recorded iteration.
            options: ``petsc_options_prefix`` (required; the SNES and its KSP) and the
                other options of :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`.

        Raises:
            ValueError: On every rank, for ``mu`` or ``penalty`` negative, NaN, infinite or
                no number, ``kind="nest"``, or an axisymmetric or rigid-target pair.
        """
        self.max_iterations, self.tolerance = int(max_iterations), float(tolerance)
        self._comp: Complementarity | None = None
        self._friction: CoulombFriction | None = None
        super().__init__(a, L, pairs, bcs, **options)
        local = _check(mu, penalty, pairs)
        if not local and (self.kind != "aij" or self.max_iterations < 1 or not tolerance > 0):
            local = "need kind='aij', max_iterations >= 1 and tolerance > 0"
        problems = [m for m in self.comm.allgather(local) if m]
        if problems:
            self.destroy()
            raise ValueError(problems[0])
        self.mu, self.penalty, self.tangent_axis = float(mu), float(penalty), tangent_axis
        self.active = [dolfinx.fem.Function(p.Q, name=f"active{j}") for j, p in enumerate(pairs)]
        self.stick = [dolfinx.fem.Function(p.Q, name=f"stick{j}") for j, p in enumerate(pairs)]
        self.tangential: _Functions = []
        self.tangent_axes: list[npt.NDArray[np.float64] | None] = []
        self.history, self._monitor = ContactHistory("penalty-coulomb"), monitor
        self._scales, self._state = np.zeros(0), None

    def solver_defaults(self) -> dict[str, typing.Any]:
        """Full Newton steps, MUMPS LU (the tangent is unsymmetric where nodes slip)."""
        solver = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}
        newton = {"snes_type": "newtonls", "snes_linesearch_type": "basic"}
        return solver | newton | {"snes_max_it": self.max_iterations}

    def assemble(self) -> None:
        r"""Assemble the system, the tangential coupling and :math:`c_j` of every pair."""
        self.system.assemble(check=False)
        for old in (self._comp, self._friction):
            if old is not None:
                old.destroy()
        self._comp = comp = Complementarity(self.system, self.penalty, self.tolerance)
        self._friction = CoulombFriction(self.system, self.mu, None, self.tangent_axis)
        self.tangential, self.tangent_axes = self._friction.multipliers, self._friction.axes
        scales = []
        for j, pair in enumerate(self.pairs):
            W = dolfinx.fem.functionspace(pair.Q.mesh, ("DG", 0))
            h, cells = dolfinx.fem.Function(W), np.arange(W.dofmap.list.shape[0], dtype=np.int32)
            h.x.array[W.dofmap.list[:, 0]] = pair.Q.mesh.h(pair.Q.mesh.topology.dim, cells)
            v = dolfinx.fem.petsc.assemble_vector(
                dolfinx.fem.form(ufl.TestFunction(pair.Q) * h * ufl.dx)
            )
            v.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            scale = self.penalty * comp.stiffness / np.where(v.array_r > 0, v.array_r, np.inf)
            scales.append(np.where(comp.pinned(j), 0.0, scale))
            v.destroy()
        self._scales = np.concatenate(scales)

    def solve(
        self,
        load_factors: Sequence[float] = (1.0,),
        *,
        restart: bool = True,
        mu: float | None = None,
    ) -> tuple[_Functions, _Functions, _Functions]:
        r"""Assemble, then solve the load steps in turn, each slipping from the previous one.

        Args:
            load_factors: Factors on the loads and Dirichlet values, solved in order.
            restart: Start from rest; ``False`` continues the previous solve (its
                displacement, shear and slip) under the loads as they are now.
            mu: The friction coefficient of these steps (default: the problem's ``mu``).

        Returns:
            The displacement of every space, :math:`\lambda_n` and :math:`\lambda_t` of
            every pair, at the last load factor.

        Raises:
            ValueError: On every rank, for a factor not finite or a bad ``mu``.
            ContactConvergenceError: On every rank, if a load step does not converge.
        """
        loads = [float(t) for t in load_factors]
        if not loads or not all(np.isfinite(loads)):
            raise ValueError("give at least one finite load factor")
        mu = self.mu if mu is None else mu
        problems = [m for m in self.comm.allgather(_check(mu, self.penalty, [])) if m]
        if problems:
            raise ValueError(problems[0])
        state = None if restart else self._state
        self.assemble()
        comp, friction = self._comp, self._friction
        assert comp is not None and friction is not None
        run = ContactIteration(
            self.system, comp, "penalty-coulomb", self.max_iterations, self.tolerance, self._monitor
        )
        self.history = run.history
        if state is not None:
            friction.restore(state[4])  # the previous solution: where the slip starts
        for t in loads:
            step = LoadStep(t)
            self.history.steps.append(step)
            begin = time.perf_counter()
            first = None if state else np.concatenate(comp.first_active(t, "nearest"))
            law = (friction, self._scales, float(mu), min(1.0, 1 / self.penalty))
            newton = _Newton(run, step, law)
            try:
                state = (*newton.solve(state, first), friction.state())
            finally:
                newton.destroy()
            step.seconds = time.perf_counter() - begin
        assert state is not None
        self._state = state
        split = np.cumsum([f.x.petsc_vec.getLocalSize() for f in self.multipliers])[:-1]
        for fs, values in ((self.active, state[2]), (self.stick, state[3])):
            for f, v in zip(fs, np.split(values, split), strict=True):
                f.x.array[:] = 0.0
                f.x.array[: v.size] = v
                f.x.scatter_forward()
        return self.u, self.multipliers, self.tangential

    def destroy(self) -> None:
        """Destroy the PETSc objects and remove the problem's options from the database."""
        for obj in (self._comp, self._friction):
            if obj is not None:
                obj.destroy()
        super().destroy()


class _Newton:
    r"""One load step: SNES on :math:`\mathbf K \mathbf U - \mathbf F + \mathbf C^T y`.

    :math:`\mathbf C \mathbf U + r` is :math:`\tilde g` of every pair, then
    :math:`\Delta \tilde s` of every pair per tangent; :math:`y = (-\lambda_n,
    \lambda_t)`. The nodes of all pairs (owned) are concatenated.
    """

    def __init__(self, run: ContactIteration, step: LoadStep, law: tuple) -> None:
        r"""Build the system with the tangential rows, take its blocks apart.

        ``law``: the tangential field, :math:`c_j`, :math:`\mu` and :math:`\theta`.
        """
        self.run, self.step, self.system = run, step, run.system
        friction, self.c, self.mu, self.theta = law
        self.friction, self.nd = friction, friction.directions
        system, comp, nd, npairs = run.system, run.complementarity, self.nd, len(run.system.pairs)
        comm = system.comm
        # The Lagrange solver's rows with every node sticking: B_t U = B_t U_prev - t B_t U_D.
        friction.start([~comp.pinned(j) for j in range(npairs)])
        system.build(None, load=step.load, extra=friction)
        assert system.A is not None and system.b is not None
        self.sizes = [system.fields[f"lambda{j}"].getLocalSize() for j in range(npairs)]
        N, groups = sum(self.sizes), ([f"u{i}" for i in range(len(system.spaces))], [])
        groups[1].extend([f"lambda{j}" for j in range(npairs)])
        groups[1].extend(friction.names[j * nd + k] for k in range(nd) for j in range(npairs))
        indices = [np.concatenate([system.fields[k].getIndices() for k in ks]) for ks in groups]
        self.rows = [PETSc.IS().createGeneral(i.astype(PETSc.IntType), comm) for i in indices]
        self.K = system.A.createSubMatrix(self.rows[0], self.rows[0])
        self.C = system.A.createSubMatrix(self.rows[1], self.rows[0])
        subs = [system.b.getSubVector(s) for s in self.rows]
        self.F, self.r = (v.copy() for v in subs)
        for s, v in zip(self.rows, subs, strict=True):
            system.b.restoreSubVector(s, v)
        sign = self.r.duplicate()  # the rows -B U = G + t B U_D (normal), B_t U = ... (tangent)
        sign.array[:] = np.repeat([-1.0, 1.0], [N, nd * N])
        self.C.diagonalScale(sign)
        self.r.pointwiseMult(self.r, sign)
        self.r.scale(-1.0)
        sign.destroy()
        self.x, self.f, self.kx, self.cy = (self.K.createVecRight() for _ in range(4))
        self.w, self.y, self.y_law = (self.r.duplicate() for _ in range(3))
        self.xi, self.D = np.zeros((N, nd)), np.ones((N, nd + 1, nd + 1))
        D = self._tangent()
        product = D.PtAP(self.C)
        self.J = self.K.copy()  # with the pattern of every Jacobian
        self.J.axpy(1.0, product, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        for obj in (D, product):
            obj.destroy()

    def _tangent(self) -> PETSc.Mat:
        r""":math:`\mathbf D` from the node blocks :attr:`D` (AIJ, rows of :math:`\mathbf C`)."""
        N, k = self.D.shape[:2]
        start, size = self.C.getOwnershipRange()[0], self.C.getSize()[0]
        cols = start + np.arange(k)[None, :] * N + np.arange(N)[:, None]  # (N, k)
        indptr = np.arange(0, k * k * N + 1, k, dtype=PETSc.IntType)
        indices = np.tile(cols, (k, 1)).ravel().astype(PETSc.IntType)
        csr = (indptr, indices, self.D.transpose(1, 0, 2).ravel())  # rows component-major
        return PETSc.Mat().createAIJ([[k * N, size]] * 2, csr=csr, comm=self.system.comm)

    def function(self, snes: PETSc.SNES, x: PETSc.Vec, f: PETSc.Vec) -> None:
        """The residual at ``x`` (decided as the class docstring says) and :attr:`D`."""
        self.C.mult(x, self.w)
        W = (self.w.array_r + self.r.array_r).reshape(self.nd + 1, -1)
        g, s, c, mu, nd, forced = W[0], W[1:].T, self.c, self.mu, self.nd, self.forced
        active = forced if forced is not None else (g < 0) & (c > 0)  # from rest: a chosen set
        lam_n = np.where(active, -c * g, 0.0)
        trial, bound = self.previous + c[:, None] * s, mu * lam_n
        theta = np.where(np.einsum("pk,pk->p", self.xi, trial) < 0, self.theta, 1.0)
        z = (1 - theta)[:, None] * bound[:, None] * self.xi + theta[:, None] * trial
        size, length = np.linalg.norm(z, axis=1), np.linalg.norm(trial, axis=1)
        stick = active & (mu > 0) if forced is not None else active & (bound > 0) & (size <= bound)
        slip = active & ~stick & (bound > 0)
        xi = z / np.where(size > 0, size, 1.0)[:, None]
        model = np.where(stick[:, None], trial, np.where(slip, bound, 0.0)[:, None] * xi)
        ratio = np.where(active, np.minimum(1, bound / np.maximum(length, 1e-300)), 0)
        law = trial * ratio[:, None]
        # D: d(-lambda_n)/dg = c; stick: d lambda_t/ds = c; slip: d(b z/|z|) = xi db +
        # b/|z| P dz, P = I - xi xi^T, dz = (1 - theta) xi_p db + theta c ds, db = -mu c dg.
        beta = np.where(slip, bound / np.where(size > 0, size, 1.0), 0.0)
        P = np.eye(nd)[None] - np.einsum("pk,pl->pkl", xi, xi)
        turn = xi + (beta * (1 - theta))[:, None] * np.einsum("pkl,pl->pk", P, self.xi)
        self.D[:] = 0.0
        self.D[:, 0, 0] = c * active
        self.D[:, 1:, 0] = -(mu * c * slip)[:, None] * turn
        self.D[:, 1:, 1:] = c[:, None, None] * (
            stick[:, None, None] * np.eye(nd) + (beta * theta)[:, None, None] * P
        )
        self.law = (law, lam_n, active, active & (length <= bound) & (bound > 0))
        self.sets = (active, stick, np.where(slip[:, None], xi, 0.0))
        self.K.mult(x, self.kx)
        self.kx.axpy(-1.0, self.F)
        norms = []
        for y, tractions in ((self.y_law, law), (self.y, model)):  # the law's, then the model's
            y.array[:] = np.concatenate([-lam_n, tractions.T.ravel()])
            self.C.multTranspose(y, self.cy)
            self.kx.copy(f)
            f.axpy(1.0, self.cy)
            norms.append((f.norm(), self.cy.norm()))
        self.norm, self.scale = norms[0][0], max(self.F.norm(), self.kx.norm(), norms[0][1])
        self.was_forced, self.forced = forced is not None, None

    def jacobian(self, snes: PETSc.SNES, x: PETSc.Vec, J: PETSc.Mat, P: PETSc.Mat) -> None:
        r""":math:`\mathbf K + \mathbf C^T \mathbf D \mathbf C` at the last residual."""
        D = self._tangent()
        product = D.PtAP(self.C)
        J.zeroEntries()
        for M in (self.K, product):
            J.axpy(1.0, M, PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
        for obj in (D, product):
            obj.destroy()

    def converged(self, snes: PETSc.SNES, it: int, norms: tuple) -> int:
        """Record the iteration; the tests of :class:`RegularizedFrictionProblem`."""
        residual, run, comm = self.norm / self.scale, self.run, self.system.comm
        (active, stick, self.xi), (was_active, was_stick) = self.sets, self.last
        entered = comm.allreduce(int(np.sum(active & ~was_active)))
        left = comm.allreduce(int(np.sum(was_active & ~active)))
        same = comm.allreduce(int(np.sum(stick != was_stick))) + entered + left == 0
        split = np.cumsum(self.sizes)[:-1]
        stuck = np.split(stick, split)
        run.record(self.step, np.split(active, split), entered, left, residual, stick=stuck)
        self.last = (active, stick)
        small = it > 0 and same and norms[1] <= np.sqrt(run.tolerance) * norms[0]
        self.accepted = not self.was_forced and (residual <= run.tolerance or small)
        if self.accepted:
            return PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS
        if it >= snes.getTolerances()[3]:
            return PETSc.SNES.ConvergedReason.DIVERGED_MAX_IT
        return PETSc.SNES.ConvergedReason.ITERATING

    def solve(self, state: tuple | None, first: npt.NDArray[np.bool_] | None) -> tuple:
        r"""Newton from ``state`` (else from rest, the active set ``first``); the new state.

        The state: the owned displacement (rows of :math:`\mathbf K`), :math:`\lambda_t`,
        the nodes in contact and sticking.
        """
        nd, system, run, N = self.nd, self.system, self.run, sum(self.sizes)
        if state is None:
            state = (np.zeros(self.x.getLocalSize()), np.zeros((N, nd)), first, first)
        self.x.array[:] = state[0]
        self.previous, self.forced, self.last, self.accepted = state[1], first, state[2:4], False
        snes = PETSc.SNES().create(system.comm)
        try:
            snes.setFunction(self.function, self.f)
            snes.setJacobian(self.jacobian, self.J)
            system.options.apply(snes)
            snes.setConvergenceTest(self.converged)
            with system.timed("solve"):
                snes.solve(None, self.x)
            if snes.getConvergedReason() <= 0 or not self.accepted:
                run.fail(
                    f"the regularized friction's Newton iteration did not converge at load "
                    f"{self.step.load:g} (SNES reason {snes.getConvergedReason()}): take "
                    "smaller load steps, or hold every body by a Dirichlet condition"
                )
        finally:
            snes.destroy()
        self.step.converged = True
        lam_t, lam_n, active, stick = self.law
        ends = np.cumsum([0, *(u.x.petsc_vec.getLocalSize() for u in system.u)])
        out = [(u, self.x.array_r[a:b]) for u, a, b in zip(system.u, ends, ends[1:], strict=False)]
        split = np.cumsum(self.sizes)[:-1]
        out += zip(system.multipliers, np.split(lam_n, split), strict=True)
        for k in range(nd):
            out += zip(self.friction.multipliers[k::nd], np.split(lam_t[:, k], split), strict=True)
        for f, v in out:
            f.x.array[: v.size] = v
            f.x.scatter_forward()
        self.friction.accept()  # the solution: where the next step's slip starts
        return self.x.array_r.copy(), lam_t, active, stick

    def destroy(self) -> None:
        """Destroy the PETSc objects of the step."""
        for obj in (*self.rows, self.K, self.C, self.F, self.r, self.x, self.f, self.kx):
            obj.destroy()
        for obj in (self.cy, self.w, self.y, self.y_law, self.J):
            obj.destroy()

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Coulomb's law on the weighted tangential slip increments: the tangential field.

Per multiplier :math:`j` of a pair, with the tangential couplings :math:`\mathbf B_t`
(Eq. 40 with a tangent of the contactor in place of :math:`\mathbf N`: in 2D
:math:`\mathbf T`, on faces :math:`\mathbf T_1, \mathbf T_2` of
:func:`~dolfinx_contact_s2s.kernels.face_backend.tangents`), the weighted slip increment
of the load step :math:`\tilde s_j = (\mathbf B_t (\mathbf U - \mathbf
U_{\mathrm{prev}}))_j` (the contactor relative to the target, measured from the previous
step's solution; one component per tangent) and :math:`\lambda_{t,j}`, the shear the
contactor exerts on the target (its components along the tangents), the complementarity
function of Hüeber, Stadler and Wohlmuth

.. math:: C_{t,j} = \lambda_{t,j} - \frac{b_j\, z_j}{\max(b_j, |z_j|)}, \qquad
    z_j = \lambda_{t,j} + c_j \tilde s_j, \qquad b_j = \mu \max(0, \lambda_{n,j} - c_j
    \tilde g_j),

is zero exactly when :math:`|\lambda_t| \le \mu \lambda_n`, :math:`\tilde s = 0` where
:math:`|\lambda_t| < \mu \lambda_n` (stick) and :math:`\lambda_t = \mu \lambda_n \tilde
s / |\tilde s|` where it slips. Each step of the iteration, on the sets of the current
iterate, is linear: :math:`\tilde s_j = 0` on the sticking multipliers,
:math:`\lambda_{t,j} = \mu \xi_j \lambda_{n,j}` on the slipping ones with the slip
direction :math:`\xi_j = z_j / |z_j|` of the iterate (in 2D a sign; on faces a unit
vector in the tangent plane, whose change is linearized too: the rows of
:meth:`CoulombFriction.__call__`), and :math:`\lambda_{t,j} = 0` off the active set.
:class:`CoulombFriction` adds these rows, and the columns :math:`\mathbf B_t^T
\lambda_t` of the bodies' equilibrium, to the saddle point of a
:class:`~dolfinx_contact_s2s.system.ContactSystem` (``build(extra=...)``).

On faces the tangent basis is the orthonormal frame :math:`\mathbf T_1 = \mathbf a
\times \mathbf N / |\mathbf a \times \mathbf N|`, :math:`\mathbf T_2 = \mathbf N
\times \mathbf T_1` at every point, from one axis :math:`\mathbf a` per pair
(:func:`tangent_axis`). Coulomb's law is the same in every orthonormal basis of the
tangent plane (the disk :math:`|\lambda_t| \le b` and the direction of the slip turn
with it), so the answer does not depend on :math:`\mathbf a`; only the components of
:math:`\lambda_t` do.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.assemble import CouplingOperator, assemble_coupling
from dolfinx_contact_s2s.kernels import polygon
from dolfinx_contact_s2s.la import add_scaled
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.system import ContactSystem

__all__ = ["CoulombFriction", "tangent_axis"]

#: Smallest :math:`|\mathbf a \times \mathbf N|` of a tangent basis (:func:`tangent_axis`).
DEGENERATE = 0.1


def tangent_axis(pair: ContactPair, axis: npt.ArrayLike | None = None) -> npt.NDArray[np.float64]:
    r"""The axis :math:`\mathbf a` of the tangent basis of a pair on faces (collective).

    By default the Cartesian axis least aligned with the contactor's mean normal: a
    surface that turns by less than about 84 degrees from its mean plane has a tangent
    basis everywhere.

    Raises:
        ValueError: On every rank, if :math:`|\mathbf a \times \mathbf N| <` 0.1 at a
            geometry node of a contactor face (the frame degenerates there).
    """
    surface, comm = pair.contactor, pair.contactor.comm
    data = surface.data
    K = data.coefficients.shape[1] if len(data) else 0
    points = polygon.face_element(K).points if K else np.zeros((0, 2))
    rows = np.repeat(np.arange(len(data), dtype=np.int32), len(points))
    xi = np.tile(points, (len(data), 1))
    normals = surface.outward_normals(data, rows, xi) if rows.size else np.zeros((0, 3))
    if axis is None:
        mean = comm.allreduce(normals.sum(axis=0), op=MPI.SUM)
        axis = np.eye(3)[int(np.argmin(np.abs(mean)))]
    a = np.asarray(axis, dtype=np.float64).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)) or np.linalg.norm(a) == 0:
        raise ValueError(f"the tangent basis' axis must be a nonzero 3-vector, not {axis!r}")
    a = a / np.linalg.norm(a)
    sines = np.linalg.norm(np.cross(a, normals), axis=1)
    worst = comm.allreduce(float(sines.min(initial=np.inf)), op=MPI.MIN)
    if worst < DEGENERATE:
        raise ValueError(
            f"the tangent basis of friction degenerates on contact surface {surface.tag}: its "
            f"normal comes within {np.degrees(np.arcsin(worst)):.1f} degrees of the axis "
            f"{np.array2string(a, precision=3)} (|a x N| = {worst:.3g} < {DEGENERATE}). Give "
            "tangent_axis= an axis across the surface, or split the surface into parts "
            "that each turn less than 80 degrees"
        )
    return a


def _diagonal(like: PETSc.Vec, values: npt.NDArray[np.floating]) -> PETSc.Mat:
    """A diagonal AIJ matrix in the layout of ``like`` with the owned ``values``."""
    d = like.duplicate()
    d.array[:] = values
    D = PETSc.Mat().createAIJ(
        [[like.getLocalSize(), like.getSize()]] * 2, nnz=(1, 0), comm=like.getComm()
    )
    D.setDiagonal(d)
    D.assemble()
    d.destroy()
    return D


class CoulombFriction:
    r"""The tangential multipliers of every pair of an assembled system, and their sets.

    Attributes:
        directions: The tangents per multiplier: 1 in 2D, 2 on faces.
        axes: Per pair on faces, the axis of its tangent basis (:func:`tangent_axis`).
        operators: Per pair and tangent (pair-major), the coupling :math:`\mathbf B_t`.
        multipliers: Per pair and tangent, :math:`\lambda_t` (a function on the pair's
            ``Q``), named ``lambda_t{j}`` in 2D, ``lambda_t{j}_1`` and ``lambda_t{j}_2``
            on faces.
        mu: The friction coefficient.
        stick: Per pair, the owned sticking multipliers of the next build.
        signs: Per pair, the slip directions :math:`\xi_j` ``(n, directions)`` of the
            slipping multipliers of the next build (zero elsewhere).
        active: Per pair, the owned active multipliers (normal) of the next build.
    """

    def __init__(
        self,
        system: ContactSystem,
        mu: float,
        slip_bound: float | None = None,
        axis: npt.ArrayLike | None = None,
    ):
        r"""Assemble the tangential coupling of every pair of the assembled ``system``.

        With ``slip_bound`` :math:`g`, Tresca's law: :math:`b_j = g` where
        :math:`\lambda_{n,j} - c_j \tilde g_j > 0`, and :math:`\lambda_t = g \xi_j` on the
        slipping multipliers; ``mu`` is not used. ``axis``: of the tangent basis on faces
        (default: :func:`tangent_axis`'s).
        """
        self.system = system
        self.mu, self.slip_bound = float(mu), slip_bound
        pairs = system.pairs
        self.directions = nd = pairs[0].contactor.facet_dim if pairs else 1
        self.axes = [tangent_axis(p, axis) if nd == 2 else None for p in pairs]
        self.operators: list[CouplingOperator] = [
            assemble_coupling(p, k + 1, a)
            for p, a in zip(pairs, self.axes, strict=True)
            for k in range(nd)
        ]
        self.names = [
            f"lambda_t{j}" if nd == 1 else f"lambda_t{j}_{k + 1}"
            for j in range(len(pairs))
            for k in range(nd)
        ]
        self.multipliers = [
            dolfinx.fem.Function(pairs[i // nd].Q, name=name) for i, name in enumerate(self.names)
        ]
        self.pinned = [self._pinned(op) for op in self.operators]
        self.start([np.zeros(op.G.getLocalSize(), dtype=bool) for op in self.operators[::nd]])
        # The previous step's solution, owned values of every space (zero at the start).
        self.previous = [np.zeros(u.x.petsc_vec.getLocalSize()) for u in system.u]
        self._objects: list = []

    def _pinned(self, op: CouplingOperator) -> npt.NDArray[np.bool_]:
        r"""Owned rows of ``op`` that meet no free dof: the motion along it is prescribed.

        Their multiplier carries no constraint (the Dirichlet reaction holds the shear):
        it is zero, and its row is the identity (else the saddle point is singular, e.g.
        :math:`\mathbf T_1` along :math:`z` under :math:`u_z = 0` everywhere).
        """
        n = op.G.getLocalSize()
        largest = np.zeros((2, n))  # per row: the largest entry, and on a free dof
        for V, B in op.blocks:
            free = B.copy()
            free.diagonalScale(None, self.system.masks[self.system.space_index(V)])
            for k, M in enumerate((B, free)):
                ai, _, values = M.getValuesCSR()
                rows = np.repeat(np.arange(n), np.diff(ai))
                np.maximum.at(largest[k], rows, np.abs(values))
            free.destroy()
        # Round-off of the tangents (1e-17 on a direction held by Dirichlet conditions).
        return largest[1] <= 1e-12 * largest[0]

    def destroy(self) -> None:
        """Destroy the PETSc objects."""
        for obj in self._objects:
            obj.destroy()
        self._objects = []
        for op in self.operators:
            op.destroy()

    def accept(self) -> None:
        """The current solution becomes the previous step's (the start of the slip)."""
        self.previous = [u.x.petsc_vec.array_r.copy() for u in self.system.u]

    def _vec(self, values: npt.NDArray[np.floating]) -> PETSc.Vec:
        return PETSc.Vec().createWithArray(values.copy(), comm=self.system.comm)

    def set_coefficient(self, mu: float) -> None:
        """The friction coefficient of the next builds and updates."""
        self.mu = float(mu)

    def state(self) -> tuple[list, ...]:
        """Copies of the previous solution, the active and sticking sets and the signs."""
        parts = (self.previous, self.active, self.stick, self.signs)
        return tuple([a.copy() for a in part] for part in parts)

    def restore(self, state: tuple[list, ...]) -> list[npt.NDArray[np.bool_]]:
        """Continue from another assembly's :meth:`state`; returns the active set."""
        self.previous, self.active, self.stick, self.signs = state
        return [a.copy() for a in self.active]

    def start(self, active: list[npt.NDArray[np.bool_]]) -> None:
        """The sets of the first solve: every active multiplier sticks."""
        self.active = [a.copy() for a in active]
        self.stick = [a.copy() for a in active]
        self.signs = [np.zeros((a.size, self.directions)) for a in active]
        # beta P of the slip rows' Newton step and c_j (update), zero for the first solve.
        self.curvature = [np.zeros((a.size, self.directions, self.directions)) for a in active]
        self.scales = [np.zeros(a.size) for a in active]

    def tractions(self) -> list[npt.NDArray[np.floating]]:
        r"""Per pair, the owned :math:`\lambda_t` ``(n, directions)``."""
        nd = self.directions
        return [
            np.stack([f.x.array[: a.size] for f in self.multipliers[j * nd : (j + 1) * nd]], 1)
            for j, a in enumerate(self.active)
        ]

    def slips(self) -> list[npt.NDArray[np.floating]]:
        r"""Per pair, owned :math:`\tilde s = \mathbf B_t (\mathbf U - \mathbf U_p)` (n, nd)."""
        out = []
        for op in self.operators:
            s = op.G.duplicate()
            s.set(0.0)
            for V, B in op.blocks:
                i = self.system.space_index(V)
                du = self._vec(self.system.u[i].x.petsc_vec.array_r - self.previous[i])
                B.multAdd(du, s, s)
                du.destroy()
            out.append(s.array_r.copy())
            s.destroy()
        nd = self.directions
        return [np.stack(out[j : j + nd], axis=1) for j in range(0, len(out), nd)]

    def __call__(self, blocks: list, rhs: list, names: list) -> None:
        r"""Append the rows and columns of :math:`\lambda_t` (``ContactSystem.build(extra=)``).

        The rows of pair :math:`j`'s tangent :math:`k`, with the sets and directions of
        the last :meth:`update`: stick, :math:`\tilde s_{j,k} = 0`; slip, the Newton step
        of :math:`C_t` on faces (:math:`\beta = b_j / |z_j|`, :math:`P = I - \xi_j
        \xi_j^T`)

        .. math:: \big((I - \beta P) \lambda_{t,j} - \beta c_j P \tilde s_j\big)_k
            - \mu \xi_{j,k} \lambda_{n,j} = 0,

        which is :math:`\lambda_{t,j} = \mu \xi_j \lambda_{n,j}` in 2D (:math:`P = 0`);
        off the active set :math:`\lambda_{t,j} = 0`.
        """
        for obj in self._objects:
            obj.destroy()
        self._objects = []
        system, nd = self.system, self.directions
        nb, npairs, nt = len(system.spaces), len(self.active), len(self.operators)
        total = len(blocks) + nt
        for row in blocks:
            row.extend([None] * nt)
        blocks.extend([[None] * total for _ in range(nt)])
        keep = self._objects.extend
        for j in range(npairs):
            ops = self.operators[j * nd : (j + 1) * nd]
            stick, slip = self.stick[j], self.active[j] & ~self.stick[j]
            on = ops[0].G.duplicate()
            on.array[:] = self.active[j]
            # Per tangent l: B_l (t U_D) - B_l U_prev, the right side of s_l = 0.
            shifts = []
            for op in ops:
                g = op.G.duplicate()
                g.set(0.0)
                for V, B in op.blocks:
                    i = system.space_index(V)
                    prev = self._vec(self.previous[i])
                    B.multAdd(prev, g, g)
                    add_scaled(B, system.values[i], -system.load, g)
                    prev.destroy()
                shifts.append(g)
            keep([on, *shifts])
            curve = slip[:, None, None] * self.curvature[j]
            for k, op in enumerate(ops):
                f = nb + npairs + j * nd + k
                # W_kl: the weights of s_l in row k.
                pin = self.pinned[j * nd + k]
                W = [
                    ~pin * (np.eye(nd)[k, m] * stick - self.scales[j] * curve[:, k, m])
                    for m in range(nd)
                ]
                g = op.G.duplicate()
                g.array[:] = sum(w * h.array_r for w, h in zip(W, shifts, strict=True))
                for V, _ in op.blocks:
                    i = system.space_index(V)
                    rows = None
                    for w, other in zip(W, ops, strict=True):
                        scaled, weights = other.block(V).copy(), self._vec(w)
                        scaled.diagonalScale(weights, system.masks[i])
                        weights.destroy()
                        if rows is None:
                            rows = scaled
                        else:
                            rows.axpy(1.0, scaled, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
                            scaled.destroy()
                    columns = op.block(V).copy()
                    columns.diagonalScale(on, system.masks[i])
                    blocks[f][i] = rows
                    blocks[i][f] = columns.transpose(PETSc.Mat())
                    keep([rows, columns, blocks[i][f]])
                for m in range(nd):
                    diagonal = np.eye(nd)[k, m] * (~stick | pin) - ~pin * curve[:, k, m]
                    blocks[f][nb + npairs + j * nd + m] = _diagonal(op.G, diagonal)
                    keep([blocks[f][nb + npairs + j * nd + m]])
                # Slip: - mu xi lambda_n (Tresca: the right side g xi).
                xi = ~pin * slip * self.signs[j][:, k]
                if self.slip_bound is not None:
                    g.array[:] += self.slip_bound * xi
                rhs.append(g)
                mu = 0.0 if self.slip_bound is not None else self.mu
                blocks[f][nb + j] = _diagonal(op.G, -mu * xi)
                keep([g, blocks[f][nb + j]])
                names.append(self.names[j * nd + k])

    def scatter(self) -> None:
        r"""Copy :math:`\lambda_t` of the system's solution into :attr:`multipliers`."""
        x = self.system.x
        assert x is not None
        for name, lam in zip(self.names, self.multipliers, strict=True):
            is_ = self.system.fields[name]
            sub = x.getSubVector(is_)
            lam.x.array[: sub.getLocalSize()] = sub.array_r
            x.restoreSubVector(is_, sub)
            lam.x.scatter_forward()

    def update(
        self,
        z: list[npt.NDArray[np.floating]],
        active: list[npt.NDArray[np.bool_]],
        scales: list[PETSc.Vec],
        tolerance: float,
    ) -> tuple[int, float]:
        r"""The next stick set and slip directions, and the relative residual of :math:`C_t`.

        Args:
            z: Per pair, :math:`\lambda_n - c \tilde g` (``-inf`` at pinned multipliers).
            active: Per pair, the next active set (normal).
            scales: Per pair, :math:`c_j`.
            tolerance: The solve's tolerance; the sets' hysteresis is half of it.

        Returns:
            The number of multipliers whose stick/slip state or slip direction changes
            (over all processes), and :math:`\max |C_t|` relative to the largest of
            :math:`|\lambda_t|`, :math:`|c \tilde s|` and :math:`b`.
        """
        comm: MPI.Comm = self.system.comm
        parts = []
        for j, (lam, s) in enumerate(zip(self.tractions(), self.slips(), strict=True)):
            zn = np.where(np.isfinite(z[j]), z[j], 0.0)
            g = self.slip_bound
            bound = self.mu * np.maximum(0.0, zn) if g is None else np.where(zn > 0, g, 0.0)
            cs = scales[j].array_r[:, None] * s
            parts.append((lam, lam + cs, bound, cs))
        scale = max(
            (
                float(np.max(np.abs(np.concatenate([a.ravel() for a in p])), initial=0.0))
                for p in parts
            ),
            default=0.0,
        )
        scale = comm.allreduce(scale, op=MPI.MAX)
        tau, worst, changed = 0.5 * tolerance * scale, 0.0, 0
        for j, (lam, zt, bound, _) in enumerate(parts):
            size = np.linalg.norm(zt, axis=1)
            xi = zt / np.where(size > 0, size, 1.0)[:, None]
            projected = xi * np.minimum(size, bound)[:, None]
            worst = max(worst, float(np.max(np.abs(lam - projected), initial=0.0)))
            was = self.stick[j] & self.active[j]
            stick = active[j] & (bound > 0) & (size < bound + np.where(was, tau, -tau))
            # A slip that turns round at once sticks first (else it cycles between the two).
            stick |= active[j] & (bound > 0) & (np.einsum("pk,pk->p", self.signs[j], zt) < 0)
            signs = np.where((stick | ~active[j])[:, None], 0.0, xi)
            beta = np.clip(bound / np.where(size > 0, size, np.inf), 0.0, 1.0)
            projector = np.eye(self.directions) - np.einsum("pk,pl->pkl", signs, signs)
            self.curvature[j] = beta[:, None, None] * projector
            self.scales[j] = scales[j].array_r.copy()
            # Without a bound (mu = 0, or no pressure) the direction changes no row.
            turned = (np.linalg.norm(signs - self.signs[j], axis=1) > np.sqrt(tolerance)) & (
                bound > 0
            )
            changed += int(np.count_nonzero((stick != was) | turned))
            self.stick[j], self.signs[j], self.active[j] = stick, signs, active[j].copy()
        worst = comm.allreduce(worst, op=MPI.MAX)
        return comm.allreduce(changed), (worst / scale if scale > 0 else worst)

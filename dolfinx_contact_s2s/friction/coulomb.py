# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Coulomb's law on the weighted tangential slip increments: the tangential field.

Per multiplier :math:`j` of a pair, with the tangential coupling :math:`\mathbf B_t`
(Eq. 40 with the contactor's tangent :math:`\mathbf T` in place of :math:`\mathbf N`),
the weighted slip increment of the load step
:math:`\tilde s_j = (\mathbf B_t (\mathbf U - \mathbf U_{\mathrm{prev}}))_j` (the
contactor relative to the target along :math:`\mathbf T`, measured from the previous
step's solution) and :math:`\lambda_{t,j}`, the shear the contactor exerts on the target
along :math:`\mathbf T`, the complementarity function of Hüeber, Stadler and Wohlmuth

.. math:: C_{t,j} = \lambda_{t,j} - \max(-b_j, \min(b_j, \lambda_{t,j} + c_j \tilde s_j)),
    \qquad b_j = \mu \max(0, \lambda_{n,j} - c_j \tilde g_j),

is zero exactly when :math:`|\lambda_t| \le \mu \lambda_n`, :math:`\tilde s = 0` where
:math:`|\lambda_t| < \mu \lambda_n` (stick) and :math:`\lambda_t = \mu \lambda_n \tilde
s / |\tilde s|` where it slips. Its semismooth Newton step, on the sets of the current
iterate, is linear: :math:`\tilde s_j = 0` on the sticking multipliers,
:math:`\lambda_{t,j} = \mu \xi_j \lambda_{n,j}` on the slipping ones with
:math:`\xi_j = \mathrm{sign}(\lambda_{t,j} + c_j \tilde s_j)`, and :math:`\lambda_{t,j} = 0`
off the active set. :class:`CoulombFriction` adds these rows, and the columns
:math:`\mathbf B_t^T \lambda_t` of the bodies' equilibrium, to the saddle point of a
:class:`~dolfinx_contact_s2s.system.ContactSystem` (``build(extra=...)``).

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.assemble import CouplingOperator, assemble_coupling
from dolfinx_contact_s2s.la import add_scaled
from dolfinx_contact_s2s.system import ContactSystem

__all__ = ["CoulombFriction"]


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
        operators: Per pair, the tangential coupling :math:`\mathbf B_t`.
        multipliers: Per pair, :math:`\lambda_t` (a function on the pair's ``Q``).
        mu: The friction coefficient.
        stick: Per pair, the owned sticking multipliers of the next build.
        signs: Per pair, :math:`\xi_j` of the slipping multipliers of the next build.
        active: Per pair, the owned active multipliers (normal) of the next build.
    """

    def __init__(self, system: ContactSystem, mu: float, slip_bound: float | None = None):
        r"""Assemble the tangential coupling of every pair of the assembled ``system``.

        With ``slip_bound`` :math:`g`, Tresca's law: :math:`b_j = g` where
        :math:`\lambda_{n,j} - c_j \tilde g_j > 0`, and :math:`\lambda_t = g \xi_j` on the
        slipping multipliers; ``mu`` is not used.
        """
        self.system = system
        self.mu, self.slip_bound = float(mu), slip_bound
        self.operators: list[CouplingOperator] = [
            assemble_coupling(pair, tangential=True) for pair in system.pairs
        ]
        self.multipliers = [
            dolfinx.fem.Function(p.Q, name=f"lambda_t{j}") for j, p in enumerate(system.pairs)
        ]
        self.start([np.zeros(op.G.getLocalSize(), dtype=bool) for op in self.operators])
        # The previous step's solution, owned values of every space (zero at the start).
        self.previous = [np.zeros(u.x.petsc_vec.getLocalSize()) for u in system.u]
        self._objects: list = []

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
        self.signs = [np.zeros(a.size) for a in active]

    def slips(self) -> list[npt.NDArray[np.floating]]:
        r"""Per pair, the owned :math:`\tilde s = \mathbf B_t (\mathbf U - \mathbf U_p)`."""
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
        return out

    def __call__(self, blocks: list, rhs: list, names: list) -> None:
        r"""Append the rows and columns of :math:`\lambda_t` (``ContactSystem.build(extra=)``)."""
        for obj in self._objects:
            obj.destroy()
        self._objects = []
        system, npairs = self.system, len(self.operators)
        nb, total = len(system.spaces), len(blocks) + npairs
        for row in blocks:
            row.extend([None] * npairs)
        blocks.extend([[None] * total for _ in range(npairs)])
        for j, op in enumerate(self.operators):
            f, stick = nb + npairs + j, self.stick[j]
            on, fixed = op.G.duplicate(), op.G.duplicate()
            on.array[:] = self.active[j]
            fixed.array[:] = stick
            # Stick: B_t (U_free + t U_D) = B_t U_prev; the columns carry every active one.
            g = op.G.duplicate()
            g.set(0.0)
            for V, B in op.blocks:
                i = system.space_index(V)
                prev = self._vec(self.previous[i])
                B.multAdd(prev, g, g)
                add_scaled(B, system.values[i], -system.load, g)
                rows, columns = B.copy(), B.copy()
                rows.diagonalScale(fixed, system.masks[i])
                columns.diagonalScale(on, system.masks[i])
                blocks[f][i] = rows
                blocks[i][f] = columns.transpose(PETSc.Mat())
                self._objects.extend([prev, rows, columns, blocks[i][f]])
            g.pointwiseMult(g, fixed)
            # Slip: lambda_t - mu xi lambda_n = 0 (Tresca: lambda_t = g xi); else lambda_t = 0.
            blocks[f][f] = _diagonal(op.G, (~stick).astype(float))
            slip = (self.active[j] & ~stick) * self.signs[j]
            if self.slip_bound is not None:
                g.array[:] += self.slip_bound * slip
            rhs.append(g)
            mu = 0.0 if self.slip_bound is not None else self.mu
            blocks[f][nb + j] = _diagonal(op.G, -mu * slip)
            self._objects.extend([on, fixed, g, blocks[f][f], blocks[f][nb + j]])
            names.append(f"lambda_t{j}")

    def scatter(self) -> None:
        r"""Copy :math:`\lambda_t` of the system's solution into :attr:`multipliers`."""
        x = self.system.x
        assert x is not None
        for j, lam in enumerate(self.multipliers):
            is_ = self.system.fields[f"lambda_t{j}"]
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
        r"""The next stick set and signs, and the relative residual of :math:`C_t`.

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
        for j, s in enumerate(self.slips()):
            lam = self.multipliers[j].x.array[: s.size]
            zn = np.where(np.isfinite(z[j]), z[j], 0.0)
            g = self.slip_bound
            bound = self.mu * np.maximum(0.0, zn) if g is None else np.where(zn > 0, g, 0.0)
            cs = scales[j].array_r * s
            parts.append((lam, lam + cs, bound, cs))
        scale = max(
            (float(np.max(np.abs(np.concatenate(p)), initial=0.0)) for p in parts), default=0.0
        )
        scale = comm.allreduce(scale, op=MPI.MAX)
        tau, worst, changed = 0.5 * tolerance * scale, 0.0, 0
        for j, (lam, zt, bound, _) in enumerate(parts):
            worst = max(worst, float(np.max(np.abs(lam - np.clip(zt, -bound, bound)), initial=0)))
            was = self.stick[j] & self.active[j]
            stick = active[j] & (bound > 0) & (np.abs(zt) < bound + np.where(was, tau, -tau))
            # A slip that turns round at once sticks first (else it cycles between the two).
            stick |= active[j] & (bound > 0) & (self.signs[j] * np.sign(zt) < 0)
            signs = np.where(stick | ~active[j], 0.0, np.sign(zt))
            changed += int(np.count_nonzero((stick != was) | (signs != self.signs[j])))
            self.stick[j], self.signs[j], self.active[j] = stick, signs, active[j].copy()
        worst = comm.allreduce(worst, op=MPI.MAX)
        return comm.allreduce(changed), (worst / scale if scale > 0 else worst)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The complementarity function of Eq. (1) on the weighted gaps, and the active set.

For one assembly of a :class:`~dolfinx_contact_s2s.system.ContactSystem`,
:class:`Complementarity` holds the parameters :math:`c_j = \varepsilon_j / m_j` and
gives the weighted gaps :math:`\tilde g = \mathbf B \mathbf U + \mathbf G` (Eqs. 15 and
17), :math:`z = \lambda - c \tilde g`, the relative residual of
:math:`C_j = \lambda_j - \max(0, z_j)`, the next active set (with a hysteresis against
round-off), the first active set of a solve and the rigid motions an active set leaves
free (Eq. 33 on the active rows).

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import contextlib
import time
import typing
from collections.abc import Iterator

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.assemble import multiplier_mass
from dolfinx_contact_s2s.system import ContactSystem, add_scaled

__all__ = ["Complementarity", "given_active", "owned_indices"]


def owned_indices(v: PETSc.Vec, mask: npt.NDArray[np.bool_]) -> npt.NDArray[np.int64]:
    """Global indices of the owned entries of ``v`` where ``mask`` holds."""
    start = v.getOwnershipRange()[0]
    return (start + np.flatnonzero(mask)).astype(np.int64)


def given_active(
    pairs: typing.Sequence, comm: MPI.Comm, active: typing.Sequence | None
) -> list[npt.NDArray[np.bool_] | None] | None:
    """The owned first active set of every pair from a solve's ``active=`` (collective).

    Each entry: a marker ``f(x) -> bool`` of the multiplier nodes' coordinates ``(3, n)``,
    a boolean array over the pair's owned multiplier dofs, or ``None``.

    Raises:
        ValueError: On every rank, without one entry per pair of the right size.
    """
    if active is None:
        return None
    out: list[npt.NDArray[np.bool_] | None] = []
    problem = ""
    if len(active) != len(pairs):
        problem = f"active needs one entry per pair ({len(pairs)}), not {len(active)}"
    for pair, given in zip(pairs, active, strict=False):
        n = pair.Q.dofmap.index_map.size_local * pair.Q.dofmap.index_map_bs
        if given is None:
            out.append(None)
            continue
        if callable(given):
            x = pair.Q.tabulate_dof_coordinates()[:n]
            given = given(x.T.copy())
        mask = np.asarray(given)
        if mask.shape != (n,) and not problem:
            problem = f"an active set has shape {mask.shape}, not ({n},) (owned dofs)"
        out.append(mask.astype(bool) if mask.shape == (n,) else None)
    message = [m for m in comm.allgather(problem) if m]
    if message:
        raise ValueError(message[0])
    return out


class Complementarity:
    r"""The complementarity conditions of Eq. (1) of one assembled system.

    Attributes:
        scales: Per pair, :math:`c_j` (zero at the pair's inactive multipliers).
        resultants: Per pair, the owned :math:`\\int \\mu_k w\\, ds` (:math:`w = 2\\pi r`
            in axisymmetry, else 1): the force a unit multiplier :math:`k` transmits.
        stiffness: :math:`\bar E`, the median diagonal entry of the free stiffness.
        seconds: Wall time (s, this process) spent in :meth:`weighted_gaps`,
            :meth:`evaluate`, :meth:`update`, :meth:`released` and :meth:`first_active`:
            the active-set bookkeeping of the iterations.
    """

    def __init__(self, system: ContactSystem, penalty: float, tolerance: float):
        r"""Compute :math:`c_j` of every pair of the assembled ``system``.

        Args:
            system: The assembled system.
            penalty: Factor :math:`\kappa` of :math:`\varepsilon = \kappa \bar E / h`.
            tolerance: Relative tolerance of the complementarity residual; the active
                set's hysteresis is half of it.

        Raises:
            ValueError: If the stiffness has no positive diagonal entry on a free dof, or
                a multiplier has no facet size or mass.
        """
        self.system = system
        self.comm: MPI.Comm = system.comm
        self.operators = system.operators
        self.penalty = float(penalty)
        self.tolerance = float(tolerance)
        self.seconds = 0.0
        self.stiffness = self._stiffness_scale()
        self.resultants: list[npt.NDArray[np.floating]] = []
        self.scales: list[PETSc.Vec] = [
            self._scale(j, self.stiffness) for j in range(len(system.pairs))
        ]

    @contextlib.contextmanager
    def _timed(self) -> Iterator[None]:
        begin = time.perf_counter()
        try:
            yield
        finally:
            self.seconds += time.perf_counter() - begin

    def destroy(self) -> None:
        """Destroy the scales."""
        for c in self.scales:
            c.destroy()
        self.scales = []

    # --- parameters -----------------------------------------------------------------

    def _stiffness_scale(self) -> float:
        """Median diagonal entry of the stiffness over the free dofs of all spaces."""
        local = []
        for i, mask in enumerate(self.system.masks):
            d = self.system.stiffness_diagonal(i)
            local.append(d.array_r[mask.array_r > 0])
            d.destroy()
        values = np.concatenate(self.comm.allgather(np.concatenate(local)))
        values = values[values > 0]
        if values.size == 0:
            raise ValueError("the stiffness has no positive diagonal entry on a free dof")
        return float(np.median(values))

    def _scale(self, j: int, E: float) -> PETSc.Vec:
        r""":math:`c_k = \kappa \bar E / (h_k m_k)` of pair ``j``, zero at its inactive dofs."""
        pair, op = self.system.pairs[j], self.operators[j]
        Q = pair.Q
        mu = ufl.TestFunction(Q)
        mass = dolfinx.fem.petsc.assemble_matrix(
            dolfinx.fem.form(ufl.TrialFunction(Q) * mu * ufl.dx)
        )
        mass.assemble()
        squares = mass.getDiagonal()
        lengths = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(mu * ufl.dx))
        lengths.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        weight = 2 * np.pi * ufl.SpatialCoordinate(Q.mesh)[0] if pair.axisymmetric else 1.0
        forces = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(mu * weight * ufl.dx))
        forces.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self.resultants.append(forces.array_r[: op.G.getLocalSize()].copy())
        forces.destroy()
        P = multiplier_mass(pair)
        m = P.createVecLeft()
        P.getRowSum(m)
        if pair.axisymmetric:
            # In axisymmetry the row sum int mu_k 2 pi r ds of a P2 vertex on the axis is
            # zero: its value was round-off (measured: 1.6e-11 against 2.6e-4 at the next
            # vertex, h = 0.005), positive or negative by chance, and a positive one made
            # c_k 1e7 times its neighbours' (3.8e14): c_k times the round-off of its
            # weighted gap was a complementarity residual of 1e-8 that no active set
            # lowers. The absolute row sum sum_l |P_kl| >= |int mu_k 2 pi r ds| measures the
            # multiplier's support instead, positive with the diagonal; for multipliers
            # without negative lobes (P1) it is the row sum.
            indptr, _, values = P.getValuesCSR()
            counts = np.diff(indptr)
            sums = np.zeros(counts.size)
            rows = np.repeat(np.arange(counts.size), counts)
            np.add.at(sums, rows, np.abs(values))
            m.array[:] = sums
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

    # --- gaps and the complementarity function ----------------------------------------

    def pinned(self, j: int) -> npt.NDArray[np.bool_]:
        """Owned multipliers of pair ``j`` that carry no constraint."""
        op = self.operators[j]
        start, end = op.G.getOwnershipRange()
        mask = np.zeros(end - start, dtype=bool)
        mask[op.inactive[(op.inactive >= start) & (op.inactive < end)] - start] = True
        return mask

    def weighted_gaps(self) -> list[npt.NDArray[np.floating]]:
        r"""Owned :math:`\tilde g = \mathbf B \mathbf U + \mathbf G` of every pair from ``u``.

        The system's ``u`` holds the Dirichlet values already scaled by the load factor.
        """
        with self._timed():
            out = []
            for op in self.operators:
                g = op.gap(self.system.load)
                for V, B in op.blocks:
                    B.multAdd(self.system.u[self.system.space_index(V)].x.petsc_vec, g, g)
                out.append(g.array_r.copy())
                g.destroy()
            return out

    def initial_gaps(self, load: float) -> list[npt.NDArray[np.floating]]:
        r""":math:`\tilde g` at zero free displacement (the Dirichlet values scaled by ``load``)."""
        out = []
        for op in self.operators:
            g = op.gap(load)
            for V, B in op.blocks:
                add_scaled(B, self.system.values[self.system.space_index(V)], load, g)
            out.append(g.array_r.copy())
            g.destroy()
        return out

    def lambdas(self) -> list[npt.NDArray[np.floating]]:
        """Owned values of the system's multipliers, per pair."""
        return [
            lam.x.array[: op.G.getLocalSize()].copy()
            for lam, op in zip(self.system.multipliers, self.operators, strict=True)
        ]

    def evaluate(
        self, lam: list[npt.NDArray[np.floating]], gaps: list[npt.NDArray[np.floating]]
    ) -> tuple[list[npt.NDArray[np.floating]], float]:
        r""":math:`z = \lambda - c \tilde g` per pair and the relative residual of :math:`C`."""
        with self._timed():
            z, worst, scale = [], 0.0, 0.0
            for j, (lj, gj) in enumerate(zip(lam, gaps, strict=True)):
                cg = self.scales[j].array_r * gj
                zj = lj - cg
                zj[self.pinned(j)] = -np.inf
                z.append(zj)
                C = lj - np.maximum(0.0, np.where(np.isfinite(zj), zj, 0.0))
                C[self.pinned(j)] = 0.0
                worst = max(worst, float(np.max(np.abs(C), initial=0.0)))
                scale = max(
                    scale,
                    float(np.max(np.abs(lj), initial=0.0)),
                    float(np.max(np.abs(cg[~self.pinned(j)]), initial=0.0)),
                )
            worst = self.comm.allreduce(worst, op=MPI.MAX)
            scale = self.comm.allreduce(scale, op=MPI.MAX)
            return z, (worst / scale if scale > 0 else worst)

    # --- the active set -------------------------------------------------------------

    def update(
        self, active: list[npt.NDArray[np.bool_]], z: list[npt.NDArray[np.floating]]
    ) -> tuple[list[npt.NDArray[np.bool_]], int, int]:
        """The next active set, with a hysteresis of ``tolerance / 2`` against round-off."""
        with self._timed():
            scale = max(
                (float(np.max(np.abs(zj[np.isfinite(zj)]), initial=0.0)) for zj in z),
                default=0.0,
            )
            tau = 0.5 * self.tolerance * self.comm.allreduce(scale, op=MPI.MAX)
            new = [np.where(a, zj > -tau, zj > tau) for a, zj in zip(active, z, strict=True)]
            entered = sum(int(np.count_nonzero(n & ~a)) for n, a in zip(new, active, strict=True))
            left = sum(int(np.count_nonzero(a & ~n)) for n, a in zip(new, active, strict=True))
            return new, self.comm.allreduce(entered), self.comm.allreduce(left)

    def first_active(
        self, load: float, start: str, given: list[npt.NDArray[np.bool_] | None] | None = None
    ) -> list[npt.NDArray[np.bool_]]:
        """The first active set of a solve: ``start`` (one of ``STARTS``), or ``given``.

        ``given`` (:func:`given_active`) replaces the start's set of every pair it has
        an entry for; pinned multipliers stay out.
        """
        first = self._start_set(load, start)
        if given is None:
            return first
        return [
            a if g is None else g & ~self.pinned(j)
            for j, (a, g) in enumerate(zip(first, given, strict=True))
        ]

    def _start_set(self, load: float, start: str) -> list[npt.NDArray[np.bool_]]:
        with self._timed():
            pinned = [self.pinned(j) for j in range(len(self.operators))]
            if start == "tied":
                return [~p for p in pinned]
            # c g~ at zero displacement: a pressure, comparable over all multipliers.
            cg = [c.array_r * g for c, g in zip(self.scales, self.initial_gaps(load), strict=True)]
            if start == "gap":
                return [(v < 0) & ~p for v, p in zip(cg, pinned, strict=True)]
            # "nearest": the penetrating multipliers and those within 1e-8 h of the smallest gap,
            # then the next nearest until the set transmits a force. A P2 vertex on the axis
            # (axisymmetry) has a zero resultant, int mu_k 2 pi r ds = 0: alone, it holds
            # nothing, and the first solve of a body held by contact would be singular. In
            # the plane every multiplier has a positive resultant: the set is the nearest.
            total = self.comm.allreduce(sum(float(np.sum(np.abs(f))) for f in self.resultants))
            chosen = [(v < 0) & ~p for v, p in zip(cg, pinned, strict=True)]
            candidates = [~p for p in pinned]  # first the smallest of all: as before
            while True:
                local = min(
                    (
                        float(np.min(v[c], initial=np.inf))
                        for v, c in zip(cg, candidates, strict=True)
                    ),
                    default=np.inf,
                )
                smallest = self.comm.allreduce(local, op=MPI.MIN)
                if not np.isfinite(smallest):
                    return chosen
                near = smallest + 1e-8 * self.penalty * self.stiffness
                chosen = [
                    c | ((v <= near) & ~p) for v, p, c in zip(cg, pinned, chosen, strict=True)
                ]
                force = self.comm.allreduce(
                    sum(float(np.sum(f[c])) for f, c in zip(self.resultants, chosen, strict=True))
                )
                if force > 1e-8 * total:
                    return chosen
                candidates = [~p & ~c for p, c in zip(pinned, chosen, strict=True)]

    def released(self, active: list[npt.NDArray[np.bool_]]) -> list[npt.NDArray[np.int64]]:
        """Per pair, the global constrained multipliers of this process not in ``active``."""
        with self._timed():
            return [
                owned_indices(op.G, ~a & ~self.pinned(j))
                for j, (op, a) in enumerate(zip(self.operators, active, strict=True))
            ]

    def counts(
        self, active: list[npt.NDArray[np.bool_]]
    ) -> tuple[tuple[int, ...], tuple[npt.NDArray[np.int64], ...]]:
        """Active multipliers per pair (over all processes), and this process's indices."""
        counts = tuple(self.comm.allreduce(int(np.count_nonzero(a))) for a in active)
        sets = tuple(owned_indices(op.G, a) for op, a in zip(self.operators, active, strict=True))
        return counts, sets

    def free_motions(self, released: list[npt.NDArray[np.int64]]) -> list:
        """The rigid motions the contact rows left active do not hold (collective)."""
        support = self.system.support
        if support is None:
            return []
        inactive = [
            np.union1d(op.inactive, r) for op, r in zip(self.operators, released, strict=True)
        ]
        return support.motions(inactive)

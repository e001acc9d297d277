# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The change of the contact terms with the displacement: Newton's tangent of contact.

With the surfaces placed at :math:`X + \mathbf u_k`, the contact force
:math:`\mathbf B(\mathbf u)^T \Lambda` and the weighted gap :math:`\mathbf G(\mathbf u)`
change with :math:`\mathbf u` through the normals, the projections and the sub-segment
ends (Eq. 40 at the current configuration). Newton's matrix needs
:math:`\mathbf H_k = \partial (\mathbf B^T \Lambda_k) / \partial \mathbf u` (the
displacement rows get :math:`\mathbf J - \mathbf H_k`) and :math:`\mathbf D_k = \partial
\mathbf G / \partial \mathbf u` (the multiplier rows; :math:`\mathbf D_k = \mathbf B_k`
only where the surfaces match and touch).

How they are computed: every group of the composite quadrature (a sub-segment in 2D, the
overlap of two faces in 3D) depends on the nodes of its two facets only. So moving the
displacement at node :math:`k` (component :math:`d`) of *every* facet of one surface by
:math:`\pm h` (its cell's :math:`k`-th node on edges, whose groups carry the cell's
dofs; the face's :math:`k`-th on faces, whose groups carry the face's) and integrating
again gives, group by group, the derivatives with respect to that dof of that group's
facet: :math:`4 n d` integrations per surface (:math:`n` nodes per cell or face),
whatever the mesh size, by central differences (:math:`h = 10^{-6}` of the median
facet size; measured against moving one dof at a time and assembling the whole coupling
again: 3.5e-10 relative). Groups are matched by their multiplier rows and their two
facets' dofs. Any pair whose groups depend on their two facets only: segment-to-segment
and the node-based methods (a node and its target facet), not the intermediate surface;
the analytic derivatives (Popp et al. 2009) would remove the :math:`10^{-10}`.
"""

from __future__ import annotations

import typing

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.assemble import CouplingOperator, assemble_coupling, coo_matrix
from dolfinx_contact_s2s.face_basis import face_nodes

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.system import ContactSystem

__all__ = ["ContactTangent"]


def _global_to_local(imap) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int32]]:
    """Sorted global indices of the local (owned and ghost) entries, and their positions."""
    n = imap.size_local + imap.num_ghosts
    globals_ = imap.local_to_global(np.arange(n, dtype=np.int32)).astype(np.int64)
    order = np.argsort(globals_)
    return globals_[order], order.astype(np.int32)


class ContactTangent:
    r"""The tangent :math:`\mathbf H_k`, :math:`\mathbf D_k` of a system's pairs, and its terms.

    Installed with :meth:`~dolfinx_contact_s2s.system.ContactSystem.set_linearization`
    (``coupling=tangent.coupling, extra=tangent``): every assembly's coupling has the rows
    :math:`\mathbf D_k` (:meth:`coupling`), and every saddle point it builds gets
    :math:`-\mathbf H_k` in its displacement blocks (Dirichlet rows and columns masked),
    :math:`-\mathbf H_k (\mathbf u_k - \mathbf U_D)` on the right, and its force columns
    back to :math:`\mathbf B_k^T` (:meth:`__call__`). Call :meth:`update` before each
    assembly.
    """

    def __init__(self, system: ContactSystem, step: float = 1e-6):
        """Keep the system; :meth:`update` computes the tangent."""
        self.system = system
        self.step = float(step)
        self.blocks: dict[tuple[int, int], PETSc.Mat] = {}
        self.u: list[npt.NDArray[np.floating]] = []
        self._objects: list[typing.Any] = []
        self._K: dict[int, PETSc.Mat] = {}
        self._E: dict[tuple[int, int], PETSc.Mat] = {}
        # The next build is the first after an assembly (update precedes every one).
        self._fresh = False

    def _surfaces(self) -> list:
        seen: dict[int, typing.Any] = {}
        for pair in self.system.pairs:
            for s in (pair.contactor, *pair.targets):
                if not s.rigid:
                    seen.setdefault(id(s), s)
        return list(seen.values())

    def _groups(self, lam: list) -> list[tuple]:
        """Per pair and target: its index and surfaces, and each group's key and values.

        The values of a group: the contact forces on its contactor's and its target's cell
        dofs, and its weighted gaps (rows: its multipliers).
        """
        out = []
        for j, (pair, (glob, pos, values)) in enumerate(zip(self.system.pairs, lam, strict=True)):
            for target, b in zip(pair.targets, pair.coupling_blocks(), strict=False):
                mu = values[pos[np.searchsorted(glob, b.rows)]]
                forces = (
                    np.einsum("sk,skc->sc", mu, b.values_contactor),
                    np.einsum("sk,skc->sc", mu, b.values_target),
                    b.gap,
                )
                keys = np.concatenate([b.rows, b.cols_contactor, b.cols_target], axis=1)
                out.append((j, (pair.contactor, target), keys, forces))
        return out

    def update(self, u: list) -> None:
        r"""The tangent at ``u`` (where the surfaces are placed) and the system's multipliers.

        Collective. ``u``: the displacement functions of the system's spaces.
        """
        system = self.system
        comm: MPI.Comm = system.comm
        lam = []
        for pair, f in zip(system.pairs, system.multipliers, strict=True):
            f.x.scatter_forward()
            glob, pos = _global_to_local(pair.Q.dofmap.index_map)
            lam.append((glob, pos, f.x.array))
        entries: dict[tuple[int, int], list] = {}
        for surface in self._surfaces():
            base = surface.data
            extent = np.ptp(base.coords, axis=1).max(axis=1) if len(base) else np.zeros(0)
            h = self.step * max(comm.allgather(float(np.median(extent)) if extent.size else 0.0))
            # Node k of a group's columns: the facet's k-th displacement node (the columns
            # are the facet's dofs, face_nodes).
            W = surface.node_weights  # u at the geometry nodes from u at V's nodes
            nodes = face_nodes(surface)[base.local_facet]
            for k in range(nodes.shape[1]):
                shift = W.T[nodes[:, k]]  # (facets, geometry nodes): moving u at node k
                for d in range(base.coords.shape[2]):
                    evaluations = []
                    try:
                        for sign in (1.0, -1.0):
                            coords = base.coords.copy()
                            coords[:, :, d] += sign * h * shift
                            surface.data = surface.geometry(coords)
                            evaluations.append(self._groups(lam))
                    finally:
                        surface.data = base
                    self._differences(surface, (k, d), h, evaluations, entries)
        self._assemble(entries)
        self.u = [ui.x.petsc_vec.array_r.copy() for ui in u]
        self._fresh = True

    def _differences(
        self, surface: typing.Any, node: tuple[int, int], h: float, evaluations: list, entries: dict
    ) -> None:
        """Add the groups' central differences to the entries of ``H`` and ``D``.

        Entries are keyed by (rows, columns): ``("u", i)`` the forces on space ``i``,
        ``("lambda", j)`` the gaps of pair ``j``; columns the moved surface's space.
        """
        k, d = node
        index = self.system.space_index
        bs = surface.V.dofmap.index_map_bs
        for (j, (contactor, target), kp, fp), (_, _, km, fm) in zip(*evaluations, strict=True):
            if surface is not contactor and surface is not target:
                continue
            keys, inverse = np.unique(np.concatenate([kp, km]), axis=0, return_inverse=True)
            inverse = inverse.reshape(-1)
            nc, nt = fp[0].shape[1], fp[1].shape[1]
            nk = keys.shape[1] - nc - nt
            rows_of = (keys[:, nk : nk + nc], keys[:, nk + nc :], keys[:, :nk])
            moved = rows_of[0] if surface is contactor else rows_of[1]
            owners = (("u", index(contactor.V)), ("u", index(target.V)), ("lambda", j))
            for side, owner in enumerate(owners):
                df = np.zeros((keys.shape[0], fp[side].shape[1]))
                np.add.at(df, inverse[: len(kp)], fp[side])
                np.add.at(df, inverse[len(kp) :], -fm[side])
                df /= 2 * h
                columns = np.repeat(moved[:, k * bs + d], rows_of[side].shape[1])
                entries.setdefault((owner, index(surface.V)), []).append(
                    (rows_of[side].reshape(-1), columns, df.reshape(-1))
                )

    def _assemble(self, entries: dict) -> None:
        """``H`` and ``D`` from their entries (off-process rows sent to their owners)."""
        for M in self.blocks.values():
            M.destroy()
        self.blocks = {}
        system, comm = self.system, self.system.comm
        # Every process makes every block some process has entries of (collective).
        present = sorted(set().union(*comm.allgather(set(entries))))
        for (kind, i), j in present:
            parts = entries.get(((kind, i), j), [])
            r, c, v = (
                np.concatenate([p[k] for p in parts]) if parts else np.zeros(0) for k in range(3)
            )
            V = system.spaces[j]
            R = system.spaces[i] if kind == "u" else system.pairs[i].Q
            part = (r[:, None].astype(np.int64), c[:, None].astype(np.int64), v[:, None, None])
            M = coo_matrix(
                comm,
                [part],
                R.dofmap.index_map,
                V.dofmap.index_map,
                V.dofmap.index_map_bs,
                row_bs=R.dofmap.index_map_bs,
            )
            self.blocks[((kind, i), j)] = M

    def coupling(self, pair: typing.Any) -> CouplingOperator:
        r"""The coupling of ``pair`` with Newton's rows: :math:`\mathbf D_k` for the rows.

        The gap linearized exactly: :math:`\mathbf G_k + \mathbf D_k (\mathbf U -
        \mathbf u_k)`, so the operator's blocks are :math:`\mathbf D_k` and its gap
        :math:`\mathbf G_k - \mathbf D_k \mathbf u_k`; the differences :math:`\mathbf
        E = \mathbf D_k - \mathbf B_k` are kept for the force columns (:meth:`__call__`).
        """
        system = self.system
        j = next(k for k, p in enumerate(system.pairs) if p is pair)
        op = assemble_coupling(pair)
        for V, B in op.blocks:
            i = system.space_index(V)
            D = self.blocks.get((("lambda", j), i))
            if D is None:
                continue
            E = D.copy()
            E.axpy(-1.0, B, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            # A partly covered multiplier keeps its row B_k: its weighted gap is the gap
            # times the covered length, and linearizing the length (a sliver at the end of
            # the target's reach) extrapolates it through zero while the bodies are apart.
            keep = E.createVecLeft()
            keep.set(1.0)
            lo, hi = keep.getOwnershipRange()
            keep.array[op.partial[(op.partial >= lo) & (op.partial < hi)] - lo] = 0.0
            E.diagonalScale(keep, None)
            keep.destroy()
            u = PETSc.Vec().createWithArray(self.u[i].copy(), comm=system.comm)
            y = E.createVecLeft()
            E.mult(u, y)
            op.G.axpy(-1.0, y)
            B.axpy(1.0, E, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            for v in (u, y):
                v.destroy()
            if (j, i) in self._E:
                self._E[(j, i)].destroy()
            self._E[(j, i)] = E
        return op

    def __call__(self, blocks: list, rhs: list, names: list) -> None:
        r"""Make a saddle point being built Newton's: :math:`-\mathbf H_k`, :math:`\mathbf B_k^T`.

        The displacement rows get :math:`-\mathbf H_k` (Dirichlet rows and columns
        masked) and :math:`-\mathbf H_k (\mathbf u_k - \mathbf U_D)` on the right; the
        force columns, built from the operator's :math:`\mathbf D_k`, get back
        :math:`\mathbf B_k^T` (:math:`+\mathbf E^T` on the active multipliers, which
        the unit diagonal of the inactive ones tells).
        """
        for obj in self._objects:
            obj.destroy()
        self._objects = []
        system = self.system
        masks, values, load = system.masks, system.values, system.load
        nb = len(system.spaces)
        for ((kind, i), j), M in self.blocks.items():
            if kind != "u":
                continue
            # The right side takes every column: -H_k (u_k - U_D) on the Dirichlet dofs
            # is the change of the contact force as they move to their values U_D (zero
            # once they hold them, in every iteration after a step's first).
            Hr = M.copy()
            Hr.diagonalScale(masks[i], None)
            w = PETSc.Vec().createWithArray(self.u[j].copy(), comm=system.comm)
            w.axpy(-load, values[j])
            y = Hr.createVecLeft()
            Hr.mult(w, y)
            rhs[i].axpy(-1.0, y)
            Hm = M.copy()
            Hm.diagonalScale(masks[i], masks[j])
            self._objects += [w, y, Hr]
            if blocks[i][j] is None:
                Hm.scale(-1.0)
                blocks[i][j] = Hm
                self._objects.append(Hm)
                continue
            base = blocks[i][j]
            if i == j:
                # K: kept from the first build after an assembly, since later builds
                # take it out of the previous matrix, which held K - H.
                if self._fresh or j not in self._K:
                    if j in self._K:
                        self._K[j].destroy()
                    self._K[j] = base.copy()
                base = self._K[j]
            S = base.copy()
            S.axpy(-1.0, Hm, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            blocks[i][j] = S
            self._objects += [Hm, S]
        for (j, i), E in self._E.items():
            active = E.createVecLeft()
            active.set(1.0)
            D = blocks[nb + j][nb + j]
            if D is not None:
                active.axpy(-1.0, D.getDiagonal())
            Em = E.copy()
            Em.diagonalScale(active, masks[i])
            Et = Em.transpose(PETSc.Mat())
            S = blocks[i][nb + j].copy()
            S.axpy(1.0, Et, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            blocks[i][nb + j] = S
            self._objects += [active, Em, Et, S]
        self._fresh = False

    def destroy(self) -> None:
        """Destroy the PETSc objects."""
        owned = list(self.blocks.values()) + list(self._K.values()) + list(self._E.values())
        for obj in self._objects + owned:
            obj.destroy()
        self._objects, self.blocks, self._K, self._E = [], {}, {}, {}

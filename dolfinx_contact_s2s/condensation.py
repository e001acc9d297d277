# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Tied contact with dual multipliers as a symmetric positive definite system.

With dual multipliers (``multiplier=("Dual", k)``, :class:`~.multiplier.MultiplierSpace`)
the contactor's block of :math:`\mathbf B` is diagonal in the nodes where the target
covers the contactor: each constraint row :math:`k` of :math:`\mathbf B \mathbf U +
\mathbf G = 0` (Eq. 18) has one entry :math:`B_{ks}` on a displacement of its own node
that no other row touches (its *slave* :math:`s(k)`, the component of the node's
normal-facing displacement with the largest entry). So

.. math::
    u_{s(k)} = -\Big(G_k + \sum_{j \ne s(k)} B_{kj} u_j\Big) / B_{ks},
    \qquad \mathbf U = \mathbf T \tilde{\mathbf U} + \mathbf c,

eliminates the multipliers and the slaves: :math:`\mathbf T^T \mathbf K \mathbf T
\tilde{\mathbf U} = \mathbf T^T (\mathbf F - \mathbf K \mathbf c)` is symmetric positive
definite (the slave positions carry an identity), solved by CG with GAMG (each body's
rigid modes, zero at the slaves, as the near-null space). The multipliers follow from
the slave rows of the equilibrium, :math:`\lambda_k = (\mathbf K \mathbf U - \mathbf
F)_{s(k)} / B_{ks}`, and the whole saddle point of Eq. (18) is checked with them.

A row that touches another row's slave (a contactor facet the target covers in part:
the dual basis is biorthogonal over whole facets only) is refused with a clear error.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import typing

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.checks.bodies import orthonormal_nullspace
from dolfinx_contact_s2s.options import PETScOptions, solver_failure
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.system import ContactSystem
from dolfinx_contact_s2s.system_checks import check_solve

__all__ = ["DEFAULT_OPTIONS", "DualCondensation"]

#: Defaults of the condensed solve: CG with GAMG. GAMG's default threshold (0: every
#: connection aggregated) let the iterations grow with the mesh (K of the P13 blocks alone:
#: 18, 20, 23, 27 from 15,414 to 957,684 unknowns); dropping connections weaker than 1% of
#: the strongest keeps them nearly level (17, 18, 19, 20) at the same time per iteration.
DEFAULT_OPTIONS = {
    "ksp_type": "cg",
    "pc_type": "gamg",
    "pc_gamg_threshold": 0.01,
    "ksp_rtol": 1e-12,
    "ksp_max_it": 1000,
}

#: A row touching another row's slave by more than this fraction of its largest entry
#: is not diagonal.
DIAGONAL_TOLERANCE = 1e-12


def _owned_is(fields: list[PETSc.IS], comm: MPI.Comm) -> PETSc.IS:
    indices = np.concatenate([f.getIndices() for f in fields]).astype(PETSc.IntType)
    return PETSc.IS().createGeneral(indices, comm=comm)


class DualCondensation:
    """The tied problem of dual multipliers solved on the displacements alone.

    Call :meth:`solve`, then read the problem's ``u`` and ``multipliers``; call
    :meth:`destroy` (the problem stays the caller's).
    """

    def __init__(
        self,
        problem: LinearContactProblem | ContactSystem,
        *,
        petsc_options_prefix: str,
        petsc_options: dict[str, typing.Any] | None = None,
    ):
        """Assemble ``problem`` and condense it.

        Args:
            problem: A tied problem (``kind="aij"``) whose pairs all have dual multipliers,
                assembled here; or a system already built (the ``"dual-active-set"``
                algorithm's, whose inactive multipliers have no row of B).
            petsc_options_prefix: Prefix of the condensed solver's options.
            petsc_options: Options under it (defaults: :data:`DEFAULT_OPTIONS`).

        Raises:
            ValueError: On every rank, for another problem or multiplier, or a constraint
                row that touches another row's slave.
        """
        built = isinstance(problem, ContactSystem)
        if not built and type(problem) is not LinearContactProblem:
            raise ValueError("the dual condensation solves tied contact (LinearContactProblem)")
        if not all(getattr(p.multiplier, "dual", False) for p in problem.pairs):
            raise ValueError("the dual condensation needs multiplier=('Dual', k) on every pair")
        system = self.system = problem if built else problem.system
        self.comm: MPI.Comm = system.comm
        if not built:
            problem.assemble()
        A = system.A
        if A is None or A.getType() == PETSc.Mat.Type.NEST:
            raise ValueError("the dual condensation needs kind='aij'")
        names = list(system.fields)
        nb = len(system.spaces)
        self.u_is = _owned_is([system.fields[n] for n in names[:nb]], self.comm)
        self.lam_is = _owned_is([system.fields[n] for n in names[nb:]], self.comm)
        a_start = A.getOwnershipRange()[0]
        #: The system's local row of each owned displacement and multiplier, in order.
        self.u_rows = self.u_is.getIndices() - a_start
        self.lam_rows = self.lam_is.getIndices() - a_start
        self.reduced = PETSc.Vec().createMPI(
            (self.u_is.getLocalSize(), self.u_is.getSize()), comm=self.comm
        )
        B = A.createSubMatrix(self.lam_is, self.u_is)
        B.scale(-1.0)  # the system's rows are -B U = G
        sub = system.b.getSubVector(self.lam_is)
        G = sub.copy()
        system.b.restoreSubVector(self.lam_is, sub)
        try:
            self.slaves = self._slaves(B, G)
        except ValueError:
            for obj in (self.reduced, self.u_is, self.lam_is):
                obj.destroy()
            raise
        finally:
            B.destroy()
            G.destroy()
        # T maps the reduced unknowns to the system's (zero multipliers): T^T A T is
        # T^T K T without a copy of K (1.7 GB at 8 million unknowns).
        self.T, self.c = self._transform()
        self.Kt = A.ptap(self.T)
        identity = self._slave_diagonal()
        self.Kt.axpy(1.0, identity, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        identity.destroy()
        self.Kt.setNearNullSpace(self._near_nullspace())
        self.options = PETScOptions(petsc_options_prefix, petsc_options, DEFAULT_OPTIONS)
        self.ksp = PETSc.KSP().create(self.comm)
        self.ksp.setOperators(self.Kt)
        self.options.apply(self.ksp)

    # --- the slaves and the transformation --------------------------------------------

    def _slaves(self, B: PETSc.Mat, G: PETSc.Vec) -> dict[str, npt.NDArray]:
        """Each constraint row's slave, entry, other columns and values, on every rank."""
        start = B.getOwnershipRange()[0]
        indptr, cols, vals = B.getValuesCSR()
        candidates = self._contactor_columns()
        rows, slave, diag, gap, other_cols, other_vals, counts = [], [], [], [], [], [], []
        for r in range(indptr.size - 1):
            c, v = cols[indptr[r] : indptr[r + 1]], vals[indptr[r] : indptr[r + 1]]
            if v.size == 0 or not np.any(v):
                continue  # a pinned multiplier: no constraint
            # The slave is a displacement of the contactor surface: at its ends a target
            # node can carry as large an entry.
            i = int(np.argmax(np.where(np.isin(c, candidates), np.abs(v), -1.0)))
            rows.append(start + r)
            slave.append(int(c[i]))
            diag.append(float(v[i]))
            gap.append(float(G.array_r[r]))
            keep = np.arange(v.size) != i
            other_cols.append(c[keep])
            other_vals.append(v[keep])
            counts.append(int(np.count_nonzero(keep)))
        parts = self.comm.allgather(
            (
                rows,
                slave,
                diag,
                gap,
                counts,
                np.concatenate(other_cols or [np.zeros(0)]),
                np.concatenate(other_vals or [np.zeros(0)]),
            )
        )
        out = {k: [] for k in ("rows", "slave", "diag", "gap", "counts", "cols", "vals")}
        for part in parts:
            for key, value in zip(out, part, strict=True):
                out[key].append(np.asarray(value))
        data = {k: np.concatenate(v) if v else np.zeros(0) for k, v in out.items()}
        for key in ("slave", "counts", "cols"):
            data[key] = data[key].astype(np.int64)
        problem = ""
        if np.unique(data["slave"]).size != data["slave"].size:
            problem = "two constraint rows share their largest displacement"
        touched = np.isin(data["cols"], data["slave"])
        scale = np.repeat(np.abs(data["diag"]), data["counts"])
        if np.any(touched & (np.abs(data["vals"]) > DIAGONAL_TOLERANCE * scale)):
            problem = "a constraint row touches another row's slave displacement"
        if problem:
            raise ValueError(
                f"the dual condensation needs the contactor's block of B diagonal: {problem} "
                "(a contactor facet the target covers in part, or two pairs on one node); "
                "solve the saddle point instead (problem.solve())"
            )
        return data

    def _contactor_columns(self) -> npt.NDArray[np.int64]:
        """Displacement columns of every contactor surface's nodes, sorted, on every rank."""
        system = self.system
        sizes = [system.fields[n].getLocalSize() for n in list(system.fields)[: len(system.spaces)]]
        offsets = np.concatenate([[0], np.cumsum(sizes)]) + self.reduced.getOwnershipRange()[0]
        mine = []
        for pair in system.pairs:
            V = pair.contactor.V
            i, bs = system.space_index(V), V.dofmap.index_map_bs
            fdim = V.mesh.topology.dim - 1
            blocks = dolfinx.fem.locate_dofs_topological(V, fdim, pair.contactor.tagged_facets)
            dofs = (bs * blocks[:, None] + np.arange(bs)).reshape(-1)
            mine.append(offsets[i] + dofs[dofs < sizes[i]])
        return np.unique(np.concatenate(self.comm.allgather(np.concatenate(mine))))

    def _transform(self) -> tuple[PETSc.Mat, PETSc.Vec]:
        r""":math:`\mathbf T` and :math:`\mathbf c` from the reduced unknowns to the system's.

        The identity on the displacements but the slaves, the slave rows of the
        elimination, no entry on the multiplier rows; :math:`\mathbf c` in the system's
        layout.
        """
        d, A = self.slaves, self.system.A
        assert A is not None
        start, end = self.reduced.getOwnershipRange()
        owned = (d["slave"] >= start) & (d["slave"] < end)
        free = np.ones(end - start, bool)
        free[d["slave"][owned] - start] = False
        free = np.flatnonzero(free)
        entry = np.repeat(np.arange(d["slave"].size), d["counts"])  # each entry's row k
        mine = owned[entry]
        k = entry[mine]
        rows = self.u_rows[np.concatenate([free, d["slave"][k] - start])]
        cols = np.concatenate([start + free, d["cols"][mine]])
        values = np.concatenate([np.ones(free.size), -d["vals"][mine] / d["diag"][k]])
        order = np.lexsort((cols, rows))
        n = A.getLocalSize()[0]
        indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))])
        # The reduced unknowns are nodes' displacement vectors: GAMG aggregates by nodes.
        bs = {V.dofmap.index_map_bs for V in self.system.spaces}
        T = PETSc.Mat().createAIJ(
            [A.getSizes()[0], self.reduced.getSizes()],
            bsize=(1, bs.pop() if len(bs) == 1 else 1),
            csr=(
                indptr.astype(PETSc.IntType),
                cols[order].astype(PETSc.IntType),
                values[order],
            ),
            comm=self.comm,
        )
        T.assemble()
        c = A.createVecRight()
        c.set(0.0)
        k = np.flatnonzero(owned)
        c.array[self.u_rows[d["slave"][k] - start]] = -d["gap"][k] / d["diag"][k]
        return T, c

    def _slave_diagonal(self) -> PETSc.Mat:
        """The identity on the slave positions (zero rows and columns of the product)."""
        start, end = self.reduced.getOwnershipRange()
        ones = self.reduced.duplicate()
        ones.set(0.0)
        mine = self.slaves["slave"][(self.slaves["slave"] >= start) & (self.slaves["slave"] < end)]
        ones.array[mine - start] = 1.0
        D = PETSc.Mat().createAIJ([self.reduced.getSizes()] * 2, nnz=(1, 0), comm=self.comm)
        D.setDiagonal(ones)
        D.assemble()
        ones.destroy()
        return D

    def _near_nullspace(self) -> PETSc.NullSpace:
        """Each body's rigid modes in the displacement layout, zero at the slaves."""
        start, end = self.reduced.getOwnershipRange()
        mine = self.slaves["slave"][(self.slaves["slave"] >= start) & (self.slaves["slave"] < end)]
        modes: list[PETSc.Vec] = []
        offset = 0
        for i, ns in enumerate(self.system.near_nullspaces):
            size = self.system.fields[list(self.system.fields)[i]].getLocalSize()
            for v in ns.getVecs():
                w = self.reduced.duplicate()
                w.set(0.0)
                w.array[offset : offset + size] = v.array_r[:size]
                w.array[mine - start] = 0.0
                modes.append(w)
            offset += size
        return orthonormal_nullspace(modes, self.comm)

    # --- the solve ----------------------------------------------------------------------

    @property
    def iterations(self) -> int:
        """CG iterations of the last solve."""
        return self.ksp.getIterationNumber()

    def solve(self, guess: npt.NDArray[np.floating] | None = None) -> None:
        """Solve the condensed system, recover the multipliers, check Eq. (18).

        Args:
            guess: The system's local solution array of a nearby problem (the previous
                active set's) to start CG from: its displacements, zero at the slaves.

        Raises:
            RuntimeError: On every rank, if CG fails or the saddle point's residual is
                too large.
        """
        system = self.system
        A, b = system.A, system.b
        assert A is not None and b is not None and system.x is not None
        rhs = A.createVecLeft()
        A.mult(self.c, rhs)
        rhs.aypx(-1.0, b)  # F - K c on the displacements (T has no multiplier rows)
        reduced, x = self.T.createVecRight(), self.T.createVecRight()
        self.T.multTranspose(rhs, reduced)
        if guess is not None and guess.size == system.x.getLocalSize():
            start, end = self.reduced.getOwnershipRange()
            slaves = self.slaves["slave"]
            x.array[:] = guess[self.u_rows]
            x.array[slaves[(slaves >= start) & (slaves < end)] - start] = 0.0
            self.ksp.setInitialGuessNonzero(True)
        with system.timed("solve"):
            self.ksp.solve(reduced, x)
        if self.ksp.getConvergedReason() < 0:
            raise RuntimeError(
                "the condensed solve failed: " + solver_failure(self.ksp, self.options.prefix)
            )
        u = system.x
        self.T.multAdd(x, self.c, u)
        A.mult(u, rhs)
        rhs.axpy(-1.0, b)  # K U - F: B^T lambda at the slaves
        d = self.slaves
        start, end = self.reduced.getOwnershipRange()
        values = np.zeros(d["rows"].size)
        mine = (d["slave"] >= start) & (d["slave"] < end)
        values[mine] = rhs.array_r[self.u_rows[d["slave"][mine] - start]] / d["diag"][mine]
        self.comm.Allreduce(MPI.IN_PLACE, values, op=MPI.SUM)
        lo = self.comm.exscan(self.lam_rows.size) or 0
        owned = (d["rows"] >= lo) & (d["rows"] < lo + self.lam_rows.size)
        u.array[self.lam_rows[(d["rows"][owned] - lo).astype(np.int64)]] = values[owned]
        check_solve(A, b, u, system.residual_tolerance, self.ksp, self.options.prefix)
        system.scatter()
        for v in (rhs, reduced, x):
            v.destroy()

    def destroy(self) -> None:
        """Destroy the condensed system and its solver; remove its options."""
        for obj in (self.ksp, self.Kt, self.T, self.c, self.reduced, self.u_is, self.lam_is):
            obj.destroy()
        self.options.clear()

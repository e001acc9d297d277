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

from dolfinx_contact_s2s.options import PETScOptions, solver_failure
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.system_checks import check_solve

__all__ = ["DEFAULT_OPTIONS", "DualCondensation"]

#: Defaults of the condensed solve: CG with GAMG.
DEFAULT_OPTIONS = {"ksp_type": "cg", "pc_type": "gamg", "ksp_rtol": 1e-12, "ksp_max_it": 1000}

#: A row touching another row's slave by more than this fraction of its largest entry
#: is not diagonal.
DIAGONAL_TOLERANCE = 1e-12


def _copy_part(v: PETSc.Vec, is_: PETSc.IS) -> PETSc.Vec:
    """A copy of the part of ``v`` on ``is_``; the caller destroys it."""
    sub = v.getSubVector(is_)
    out = sub.copy()
    v.restoreSubVector(is_, sub)
    return out


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
        problem: LinearContactProblem,
        *,
        petsc_options_prefix: str,
        petsc_options: dict[str, typing.Any] | None = None,
    ):
        """Assemble ``problem`` and condense it.

        Args:
            problem: A tied problem (``kind="aij"``) whose pairs all have dual multipliers.
            petsc_options_prefix: Prefix of the condensed solver's options.
            petsc_options: Options under it (defaults: :data:`DEFAULT_OPTIONS`).

        Raises:
            ValueError: On every rank, for another problem or multiplier, or a constraint
                row that touches another row's slave.
        """
        if type(problem) is not LinearContactProblem:
            raise ValueError("the dual condensation solves tied contact (LinearContactProblem)")
        if not all(getattr(p.multiplier, "dual", False) for p in problem.pairs):
            raise ValueError("the dual condensation needs multiplier=('Dual', k) on every pair")
        self.problem = problem
        system = self.system = problem.system
        self.comm: MPI.Comm = system.comm
        problem.assemble()
        A = system.A
        if A is None or A.getType() == PETSc.Mat.Type.NEST:
            raise ValueError("the dual condensation needs kind='aij'")
        names = list(system.fields)
        nb = len(system.spaces)
        self.u_is = _owned_is([system.fields[n] for n in names[:nb]], self.comm)
        self.lam_is = _owned_is([system.fields[n] for n in names[nb:]], self.comm)
        self.K = A.createSubMatrix(self.u_is, self.u_is)
        B = A.createSubMatrix(self.lam_is, self.u_is)
        B.scale(-1.0)  # the system's rows are -B U = G
        self.F, G = (_copy_part(system.b, is_) for is_ in (self.u_is, self.lam_is))
        try:
            self.slaves = self._slaves(B, G)
        except ValueError:
            for obj in (self.K, self.F, self.u_is, self.lam_is):
                obj.destroy()
            raise
        finally:
            B.destroy()
            G.destroy()
        self.T, self.c = self._transform()
        self.Kt = self.K.ptap(self.T)
        identity = self._slave_diagonal()
        self.Kt.axpy(1.0, identity, PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        identity.destroy()
        self.Kt.setNearNullSpace(self._near_nullspace())
        # K lives in the system's matrix too: the solve applies it from there (1.7 GB of
        # 16 at 8 million unknowns).
        self.K.destroy()
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
        data["slave"] = data["slave"].astype(np.int64)
        data["counts"] = data["counts"].astype(np.int64)
        data["cols"] = data["cols"].astype(np.int64)
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
        offsets = np.concatenate([[0], np.cumsum(sizes)]) + self.K.getOwnershipRange()[0]
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
        r""":math:`\mathbf T` (identity but the slave rows) and :math:`\mathbf c`."""
        d = self.slaves
        start, end = self.K.getOwnershipRange()
        n = end - start
        offsets = np.concatenate([[0], np.cumsum(d["counts"])])
        owner_of = {int(s): k for k, s in enumerate(d["slave"]) if start <= s < end}
        indptr, indices, values = [0], [], []
        c = self.K.createVecRight()
        for i in range(start, end):
            k = owner_of.get(i)
            if k is None:
                indices.append(np.array([i]))
                values.append(np.array([1.0]))
            else:
                lo, hi = offsets[k], offsets[k + 1]
                order = np.argsort(d["cols"][lo:hi])
                indices.append(d["cols"][lo:hi][order])
                values.append(-d["vals"][lo:hi][order] / d["diag"][k])
                c.array[i - start] = -d["gap"][k] / d["diag"][k]
            indptr.append(indptr[-1] + indices[-1].size)
        T = PETSc.Mat().createAIJ(
            [[n, self.K.getSize()[0]], [n, self.K.getSize()[1]]],
            csr=(
                np.asarray(indptr, dtype=PETSc.IntType),
                np.concatenate(indices).astype(PETSc.IntType),
                np.concatenate(values),
            ),
            comm=self.comm,
        )
        T.assemble()
        return T, c

    def _slave_diagonal(self) -> PETSc.Mat:
        """The identity on the slave positions (zero rows and columns of the product)."""
        start, end = self.K.getOwnershipRange()
        ones = self.K.createVecRight()
        mine = self.slaves["slave"][(self.slaves["slave"] >= start) & (self.slaves["slave"] < end)]
        ones.array[mine - start] = 1.0
        D = PETSc.Mat().createAIJ(self.K.getSizes(), nnz=(1, 0), comm=self.comm)
        D.setDiagonal(ones)
        D.assemble()
        ones.destroy()
        return D

    def _near_nullspace(self) -> PETSc.NullSpace:
        """Each body's rigid modes in the displacement layout, zero at the slaves."""
        start, end = self.K.getOwnershipRange()
        mine = self.slaves["slave"][(self.slaves["slave"] >= start) & (self.slaves["slave"] < end)]
        modes: list[PETSc.Vec] = []
        offset = 0
        for i, ns in enumerate(self.system.near_nullspaces):
            size = self.system.fields[list(self.system.fields)[i]].getLocalSize()
            for v in ns.getVecs():
                w = self.K.createVecRight()
                w.array[offset : offset + size] = v.array_r[:size]
                w.array[mine - start] = 0.0
                modes.append(w)
            offset += size
        for i, v in enumerate(modes):
            for _ in range(2):
                for u in modes[:i]:
                    v.axpy(-u.dot(v), u)
            v.normalize()
        nullspace = PETSc.NullSpace().create(vectors=modes, comm=self.comm)
        for v in modes:
            v.destroy()
        return nullspace

    # --- the solve ----------------------------------------------------------------------

    @property
    def iterations(self) -> int:
        """CG iterations of the last solve."""
        return self.ksp.getIterationNumber()

    def solve(self) -> None:
        """Solve the condensed system, recover the multipliers, check Eq. (18).

        Raises:
            RuntimeError: On every rank, if CG fails or the saddle point's residual is
                too large.
        """
        system = self.system
        rhs = self._stiffness_times(self.c)
        rhs.aypx(-1.0, self.F)  # F - K c
        reduced, x = self.T.createVecRight(), self.T.createVecRight()
        self.T.multTranspose(rhs, reduced)
        with system.timed("solve"):
            self.ksp.solve(reduced, x)
        if self.ksp.getConvergedReason() < 0:
            raise RuntimeError(
                "the condensed solve failed: " + solver_failure(self.ksp, self.options.prefix)
            )
        u = self.c.copy()
        self.T.multAdd(x, u, u)
        residual = self._stiffness_times(u)
        residual.axpy(-1.0, self.F)  # K U - F: B^T lambda at the slaves
        lam = _copy_part(system.b, self.lam_is)
        lam.set(0.0)
        start = residual.getOwnershipRange()[0]
        d = self.slaves
        values = np.zeros(d["rows"].size)
        mine = (d["slave"] >= start) & (d["slave"] < start + residual.getLocalSize())
        values[mine] = residual.array_r[d["slave"][mine] - start] / d["diag"][mine]
        self.comm.Allreduce(MPI.IN_PLACE, values, op=MPI.SUM)
        lo, hi = lam.getOwnershipRange()
        owned = (d["rows"] >= lo) & (d["rows"] < hi)
        lam.array[(d["rows"][owned] - lo).astype(np.int64)] = values[owned]
        assert system.x is not None and system.A is not None and system.b is not None
        for is_, v in ((self.u_is, u), (self.lam_is, lam)):
            sub = system.x.getSubVector(is_)
            sub.array[:] = v.array_r
            system.x.restoreSubVector(is_, sub)
        check_solve(
            system.A, system.b, system.x, system.residual_tolerance, self.ksp, self.options.prefix
        )
        system.scatter()
        for v in (rhs, reduced, x, u, residual, lam):
            v.destroy()

    def _stiffness_times(self, v: PETSc.Vec) -> PETSc.Vec:
        r""":math:`\mathbf K v` through the system's matrix; the caller destroys it."""
        A = self.system.A
        assert A is not None
        full, out = A.createVecs()
        full.set(0.0)
        sub = full.getSubVector(self.u_is)
        sub.array[:] = v.array_r
        full.restoreSubVector(self.u_is, sub)
        A.mult(full, out)
        result = _copy_part(out, self.u_is)
        full.destroy()
        out.destroy()
        return result

    def destroy(self) -> None:
        """Destroy the condensed system and its solver; remove its options."""
        for obj in (self.ksp, self.Kt, self.T, self.c, self.F, self.u_is, self.lam_is):
            obj.destroy()
        self.options.clear()

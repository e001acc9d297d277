# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""PETSc assembly of the coupling block and the saddle-point contact problem (Eq. 18).

This module needs petsc4py and must be imported explicitly, as ``dolfinx.fem.petsc``.
"""

from __future__ import annotations

import typing
from collections.abc import Sequence
from dataclasses import dataclass

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.coupling import ContactPair

__all__ = [
    "UNCOVERED_TOLERANCE",
    "ContactProblem",
    "CouplingOperator",
    "assemble_coupling",
    "gather_dense",
    "multiplier_mass",
]

_DEFAULT_OPTIONS = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}


def _to_owners(
    comm: MPI.Comm, rows: npt.NDArray[np.int64], payload: list[npt.NDArray], row_starts: npt.NDArray
) -> tuple[npt.NDArray[np.int64], list[npt.NDArray]]:
    """Send entries to the processes that own their rows (``row_starts``: ownership offsets)."""
    owner = np.searchsorted(row_starts, rows, side="right") - 1
    order = np.argsort(owner, kind="stable")
    send_counts = np.bincount(owner, minlength=comm.size).astype(np.int64)
    recv_counts = np.empty_like(send_counts)
    comm.Alltoall(send_counts, recv_counts)
    out = []
    for array in [rows, *payload]:
        array = np.ascontiguousarray(array[order])
        received = np.empty(int(recv_counts.sum()), dtype=array.dtype)
        comm.Alltoallv([array, send_counts], [received, recv_counts])
        out.append(received)
    return out[0], out[1:]


def _coo_matrix(
    comm: MPI.Comm,
    parts: Sequence[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.floating]]],
    row_map: dolfinx.common.IndexMap,
    col_map: dolfinx.common.IndexMap,
    col_bs: int,
) -> PETSc.Mat:
    """Distributed AIJ matrix, the sum of local blocks ``(rows, cols, values)``.

    Each part holds blocks ``values[s, i, j]`` at ``(rows[s, i], cols[s, j])``.
    Entries may belong to rows owned by other processes: they are sent to their
    owners, duplicates are summed, and the matrix is created from its exact CSR
    structure.
    """
    flat_i, flat_j, flat_v = [], [], []
    for rows, cols, values in parts:
        nr, nc = rows.shape[1], cols.shape[1]
        flat_i.append(np.broadcast_to(rows[:, :, None], (rows.shape[0], nr, nc)).reshape(-1))
        flat_j.append(np.broadcast_to(cols[:, None, :], (cols.shape[0], nr, nc)).reshape(-1))
        flat_v.append(values.reshape(-1))
    i = np.concatenate(flat_i).astype(np.int64)
    j = np.concatenate(flat_j).astype(np.int64)
    row_starts = np.array(comm.allgather(row_map.local_range[0]) + [row_map.size_global])
    i, (j, v) = _to_owners(comm, i, [j, np.concatenate(flat_v)], row_starts)
    start = row_map.local_range[0]
    n_cols = col_map.size_global * col_bs
    keys, inverse = np.unique((i - start) * n_cols + j, return_inverse=True)
    data = np.bincount(inverse.reshape(-1), weights=v, minlength=keys.size)
    local_rows, indices = np.divmod(keys, n_cols)
    indptr = np.searchsorted(local_rows, np.arange(row_map.size_local + 1))
    A = PETSc.Mat().createAIJ(
        [
            [row_map.size_local, row_map.size_global],
            [col_map.size_local * col_bs, n_cols],
        ],
        csr=(
            indptr.astype(PETSc.IntType),
            indices.astype(PETSc.IntType),
            data.astype(PETSc.ScalarType),
        ),
        comm=comm,
    )
    A.assemble()
    return A


#: A multiplier is uncovered when the part of its support that faces a target carries at
#: most this fraction of its integral.
UNCOVERED_TOLERANCE = 1e-10


@dataclass
class CouplingOperator:
    r"""The assembled coupling of a contact pair (Eqs. 17 and 40).

    With :math:`b(\mathbf v, \mu)` the linear part of Eq. (17),

    .. math:: b(\mathbf v, \mu) = \mathbf M^T \sum_s \mathbf B_s \mathbf V_s,
        \qquad \mathbf G = \int_{\Gamma_C} \mu\, g_0,

    summed over the distinct displacement spaces :math:`s` of the contactor and its
    targets. The caller must :meth:`destroy` the operator.

    Attributes:
        pair: The contact pair.
        blocks: ``(V, B_V)`` for each distinct displacement space ``V`` (contactor's
            first): rows the multiplier dofs of ``pair.Q``, columns the (unrolled) dofs
            of ``V``, values the sum of the contactor and target contributions on ``V``.
        G: The gap vector, in ``pair.Q``'s layout.
        uncovered: Global multiplier dofs whose support faces no target: the integral
            of :math:`\mu_k` over the covered part is at most
            :data:`UNCOVERED_TOLERANCE` times its integral. Sorted, on every process.
    """

    pair: ContactPair
    blocks: list[tuple[dolfinx.fem.FunctionSpace, PETSc.Mat]]
    G: PETSc.Vec
    uncovered: npt.NDArray[np.int64]

    @property
    def inactive(self) -> npt.NDArray[np.int64]:
        """Multipliers to set to zero: the pair's duplicates and the uncovered ones."""
        return np.union1d(self.pair.duplicates, self.uncovered).astype(np.int64)

    def block(self, V: dolfinx.fem.FunctionSpace) -> PETSc.Mat | None:
        """The block of space ``V`` (identity by ``is``), or None."""
        return next((B for W, B in self.blocks if W is V), None)

    def destroy(self) -> None:
        """Destroy the PETSc matrices and vector."""
        for _, B in self.blocks:
            B.destroy()
        self.G.destroy()


def _uncovered(pair: ContactPair, rows: list, coverage: list) -> npt.NDArray[np.int64]:
    """Global multiplier dofs with no coverage (see :class:`CouplingOperator`)."""
    Q = pair.Q
    comm = pair.contactor.comm
    imap = Q.dofmap.index_map
    covered = PETSc.Vec().createMPI([imap.size_local, imap.size_global], comm=comm)
    covered.setValues(
        np.concatenate([r.reshape(-1) for r in rows]).astype(PETSc.IntType),
        np.concatenate([c.reshape(-1) for c in coverage]),
        addv=PETSc.InsertMode.ADD_VALUES,
    )
    covered.assemble()
    support = dolfinx.fem.assemble_vector(
        dolfinx.fem.form(ufl.TestFunction(Q) * ufl.dx(domain=Q.mesh))
    )
    support.scatter_reverse(dolfinx.la.InsertMode.add)
    n = imap.size_local
    none = covered.array_r <= UNCOVERED_TOLERANCE * np.abs(support.array[:n])
    covered.destroy()
    mine = imap.local_range[0] + np.flatnonzero(none).astype(np.int64)
    return np.concatenate(comm.allgather(mine)).astype(np.int64)


def assemble_coupling(pair: ContactPair) -> CouplingOperator:
    r"""Assemble the coupling of a contact pair with global indices (collective).

    The rows are the multiplier dofs of ``pair.Q``; there is one matrix per distinct
    displacement space, so a contactor and a target in one mesh and space give one
    block holding both contributions (Eq. 40, summed).

    Args:
        pair: The contact pair.

    Returns:
        The :class:`CouplingOperator`. The caller must ``destroy()`` it.

    Raises:
        ValueError: On every rank, if the contactor faces none of its targets.
    """
    groups = pair.coupling_blocks()
    comm = pair.contactor.comm
    if comm.allreduce(sum(b.rows.shape[0] for b in groups), op=MPI.SUM) == 0:
        raise ValueError(
            "the contactor and target surfaces never face each other within the search "
            f"radius {pair.search_radius:g}: there is nothing to integrate"
        )
    q_map = pair.Q.dofmap.index_map
    spaces: list[dolfinx.fem.FunctionSpace] = []
    parts: list[list] = []

    def add(V: dolfinx.fem.FunctionSpace, part: tuple) -> None:
        # Identity, not equality: the same space must give one summed block.
        for k, W in enumerate(spaces):
            if W is V:
                parts[k].append(part)
                return
        spaces.append(V)
        parts.append([part])

    for b in groups:
        add(pair.contactor.V, (b.rows, b.cols_contactor, b.values_contactor))
        add(b.target.V, (b.rows, b.cols_target, b.values_target))
    blocks = [
        (V, _coo_matrix(comm, p, q_map, V.dofmap.index_map, V.dofmap.index_map_bs))
        for V, p in zip(spaces, parts, strict=True)
    ]
    G = PETSc.Vec().createMPI([q_map.size_local, q_map.size_global], comm=comm)
    for b in groups:
        G.setValues(
            b.rows.reshape(-1).astype(PETSc.IntType),
            b.gap.reshape(-1),
            addv=PETSc.InsertMode.ADD_VALUES,
        )
    G.assemble()
    uncovered = _uncovered(pair, [b.rows for b in groups], [b.coverage for b in groups])
    return CouplingOperator(pair, blocks, G, uncovered)


def _lumped(pair: ContactPair, M: PETSc.Mat) -> PETSc.Mat:
    """Diagonal of row sums of ``M`` (the tributary lengths of the nodes)."""
    w = M.createVecLeft()
    M.getRowSum(w)
    D = PETSc.Mat().createAIJ([M.getSizes()[0]] * 2, nnz=(1, 0), comm=M.getComm())
    if pair.weight == "unit":
        # The multiplier is the node's force w_i t_i: ||t||^2 = sum_i mu_i^2 / w_i.
        w.reciprocal()
    D.setDiagonal(w)
    D.assemble()
    w.destroy()
    return D


def multiplier_mass(pair: ContactPair) -> PETSc.Mat:
    r"""The matrix :math:`\mathbf P` of Eq. (29), over all multipliers of ``pair``.

    :math:`\mathbf M^T \mathbf P \mathbf M = \|\mu_h\|^2_{0,\Gamma}`; inactive
    multipliers are included.

    The multiplier of the segment-to-segment methods and of the intermediate surface is
    a function on its mesh: :math:`\mathbf P` is its mass matrix. Node-based methods
    (Eqs. 37-39, ``pair.nodal``) collocate the traction at the nodes, each standing for
    its tributary length :math:`w^i`: :math:`\mathbf P` is the lumped mass matrix, or
    its inverse when the multiplier is the nodal force (``weight="unit"``). The caller
    must ``destroy()`` it.
    """
    Q = pair.Q
    p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
    M = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(ufl.inner(p, q) * ufl.dx))
    M.assemble()
    if not pair.nodal:
        return M
    D = _lumped(pair, M)
    M.destroy()
    return D


def _active_rows(pair: ContactPair, G: PETSc.Vec) -> PETSc.Vec:
    """1 for the active multipliers of a pair, 0 for those in ``pair.inactive``."""
    active = G.duplicate()
    active.set(1.0)
    active.setValues(
        pair.inactive.astype(PETSc.IntType),
        np.zeros(pair.inactive.size),
        addv=PETSc.InsertMode.INSERT_VALUES,
    )
    active.assemble()
    return active


def _space(form: ufl.Form) -> dolfinx.fem.FunctionSpace:
    return form.arguments()[0].ufl_function_space()


def _contains(V: dolfinx.fem.FunctionSpace, bc: dolfinx.fem.DirichletBC) -> bool:
    # bc.function_space is a C++ space in some DOLFINx versions, a Python one in others.
    W = bc.function_space
    return V._cpp_object.contains(getattr(W, "_cpp_object", W))


class ContactProblem:
    r"""Linear elastic bodies tied by Lagrange-multiplier contact on a known contact surface.

    Assembles and solves Eq. (18) in the form

    .. math::
        \begin{bmatrix} \mathbf K & -\mathbf B^T \\ -\mathbf B & \mathbf 0 \end{bmatrix}
        \begin{Bmatrix} \mathbf U \\ \mathbf \Lambda \end{Bmatrix} =
        \begin{Bmatrix} \mathbf F \\ \mathbf G \end{Bmatrix},

    which is Eq. (15) with every constraint active: :math:`a(\mathbf u, \mathbf v) -
    b(\mathbf v, \lambda) = (\mathbf f, \mathbf v)` and a zero gap :math:`b(\mathbf u,
    \mu) + \int \mu g_0 = 0`, so that :math:`\lambda` is the contact pressure,
    positive in compression. The matrix is built as a ``MatNest`` (bodies, then pairs)
    and converted to AIJ for a direct solver; :attr:`fields` holds the index sets of
    the blocks for field-split preconditioners.

    Dirichlet conditions are applied to :math:`\mathbf K` as in
    :func:`dolfinx.fem.petsc.assemble_matrix` (unit diagonal); their columns in
    :math:`\mathbf B` are removed and their values moved to :math:`\mathbf G`.
    """

    def __init__(
        self,
        a: Sequence[ufl.Form],
        L: Sequence[ufl.Form],
        pairs: Sequence[ContactPair],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        *,
        petsc_options_prefix: str,
        petsc_options: dict[str, typing.Any] | None = None,
        form_compiler_options: dict | None = None,
        jit_options: dict | None = None,
    ):
        """Assemble the saddle-point system.

        Args:
            a: Bilinear form of each body (its arguments define the body's space).
            L: Linear form of each body.
            pairs: Contact pairs between the bodies' spaces.
            bcs: Dirichlet conditions on any of the bodies.
            petsc_options_prefix: Prefix of the solver's options database entries.
            petsc_options: Options set under the prefix; if not given, MUMPS LU
                (``ksp_type=preonly``, ``pc_type=lu``, ``pc_factor_mat_solver_type=mumps``).
                Command-line options under the prefix apply too.
            form_compiler_options: Passed to :func:`dolfinx.fem.form`.
            jit_options: Passed to :func:`dolfinx.fem.form`.
        """
        if len(a) != len(L):
            raise ValueError("one bilinear and one linear form per body are needed")
        self.spaces = [_space(ai) for ai in a]
        comm = self.spaces[0].mesh.comm
        opts = {"form_compiler_options": form_compiler_options, "jit_options": jit_options}
        self._a = [dolfinx.fem.form(ai, **opts) for ai in a]
        self._L = [dolfinx.fem.form(Li, **opts) for Li in L]
        self.pairs = list(pairs)

        def body(V: dolfinx.fem.FunctionSpace) -> int:
            for i, W in enumerate(self.spaces):
                if W is V:
                    return i
            raise ValueError("a contact pair's surface is not on any body of the problem")

        self._body_bcs = [[bc for bc in bcs if _contains(V, bc)] for V in self.spaces]
        nb, npairs = len(self.spaces), len(self.pairs)
        blocks: list[list[PETSc.Mat | None]] = [[None] * (nb + npairs) for _ in range(nb + npairs)]
        self._K = []
        self._F = []
        for i, (ai, Li, bci) in enumerate(zip(self._a, self._L, self._body_bcs, strict=True)):
            K = dolfinx.fem.petsc.assemble_matrix(ai, bcs=bci)
            K.assemble()
            F = dolfinx.fem.petsc.assemble_vector(Li)
            dolfinx.fem.petsc.apply_lifting(F, [ai], bcs=[bci])
            F.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            dolfinx.fem.petsc.set_bc(F, bci)
            blocks[i][i] = K
            self._K.append(K)
            self._F.append(F)

        self._G = []
        self._B = []
        self.constraints: list[tuple[PETSc.Mat, PETSc.Mat]] = []
        for j, pair in enumerate(self.pairs):
            op = assemble_coupling(pair)
            G = op.G
            active = _active_rows(pair, G)
            G.pointwiseMult(G, active)
            for V, Bi in op.blocks:
                i = body(V)
                x_bc, keep = self._dirichlet_vectors(i)
                # -B U = G with U = U_free + U_D  =>  -B U_free = G + B U_D.
                Bi.diagonalScale(active, None)
                Bi.multAdd(x_bc, G, G)
                Bi.diagonalScale(None, keep)
                Bi.scale(-1.0)
                Bt = PETSc.Mat()
                Bi.transpose(Bt)
                blocks[nb + j][i] = Bi
                blocks[i][nb + j] = Bt
                self._B.extend([Bi, Bt])
                x_bc.destroy()
                keep.destroy()
            self.constraints.append(
                (blocks[nb + j][body(pair.contactor.V)], blocks[nb + j][body(pair.target.V)])
            )
            if pair.inactive.size:
                # Inactive multipliers: the row reads lambda_i = 0.
                D = PETSc.Mat().createAIJ(
                    [[G.getLocalSize(), G.getSize()]] * 2, nnz=(1, 0), comm=comm
                )
                inactive = active.duplicate()
                inactive.set(1.0)
                inactive.axpy(-1.0, active)
                D.setDiagonal(inactive)
                D.assemble()
                blocks[nb + j][nb + j] = D
                self._B.append(D)
                inactive.destroy()
            active.destroy()
            self._G.append(G)

        self._nest = PETSc.Mat().createNest(blocks, comm=comm)
        self._nest.assemble()
        self.fields = list(self._nest.getNestISs()[0])
        self.A = self._nest.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())

        self.b = self.A.createVecLeft()
        for is_, v in zip(self.fields, self._F + self._G, strict=True):
            sub = self.b.getSubVector(is_)
            sub.array[:] = v.array_r[: sub.getLocalSize()]
            self.b.restoreSubVector(is_, sub)
        self.x = self.A.createVecRight()

        self.u = [dolfinx.fem.Function(V, name=f"u{i}") for i, V in enumerate(self.spaces)]
        self.pressure = [
            dolfinx.fem.Function(p.Q, name=f"pressure{j}") for j, p in enumerate(self.pairs)
        ]

        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setOperators(self.A)
        self.ksp.setOptionsPrefix(petsc_options_prefix)
        self.A.setOptionsPrefix(petsc_options_prefix)
        # Set the options, apply them, and take them out of the global database again.
        # Defaults yield to the command line; explicit petsc_options do not.
        options = PETSc.Options()
        given = petsc_options if petsc_options is not None else _DEFAULT_OPTIONS
        added = []
        for k, v in given.items():
            name = f"{petsc_options_prefix}{k}"
            if petsc_options is None and options.hasName(name):
                continue
            options[name] = v
            added.append(name)
        self.ksp.setFromOptions()
        self.A.setFromOptions()
        for name in added:
            options.delValue(name)

    def _dirichlet_vectors(self, i: int) -> tuple[PETSc.Vec, PETSc.Vec]:
        """Dirichlet values of body ``i`` and a 0/1 mask of its free dofs (owned layout)."""
        V = self.spaces[i]
        bcs = self._body_bcs[i]
        values = dolfinx.fem.Function(V)
        keep = dolfinx.fem.Function(V)
        keep.x.array[:] = 1.0
        for bc in bcs:
            bc.set(values.x.array)
            dofs, _ = bc.dof_indices()
            keep.x.array[dofs] = 0.0
        n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        x_bc = PETSc.Vec().createWithArray(values.x.array[:n].copy(), comm=V.mesh.comm)
        mask = PETSc.Vec().createWithArray(keep.x.array[:n].copy(), comm=V.mesh.comm)
        return x_bc, mask

    def solve(self) -> tuple[list[dolfinx.fem.Function], list[dolfinx.fem.Function]]:
        """Solve Eq. (18).

        Returns:
            The displacement of every body and the contact pressure of every pair.

        Raises:
            RuntimeError: On every rank, if the solver does not converge.
        """
        self.ksp.solve(self.b, self.x)
        reason = self.ksp.getConvergedReason()
        if reason < 0:
            raise RuntimeError(f"the contact solve failed to converge (KSP reason {reason})")
        for is_, f in zip(self.fields, self.u + self.pressure, strict=True):
            sub = self.x.getSubVector(is_)
            f.x.array[: sub.getLocalSize()] = sub.array_r
            self.x.restoreSubVector(is_, sub)
            f.x.scatter_forward()
        return self.u, self.pressure

    def contact_forces(self) -> list[dolfinx.fem.Function]:
        r"""Nodal contact force on every body, :math:`\sum_j \mathbf B_{j,i}^T \Lambda_j`.

        Call after :meth:`solve`. Dirichlet dofs carry no contact force.
        """
        forces = []
        nb = len(self.spaces)
        for i, V in enumerate(self.spaces):
            f = dolfinx.fem.Function(V, name=f"contact_force{i}")
            for j, lam in enumerate(self.pressure):
                block = self._nest.getNestSubMatrix(i, nb + j)
                if block.handle == 0:
                    continue
                y = block.createVecLeft()
                block.mult(lam.x.petsc_vec, y)
                f.x.array[: y.getLocalSize()] -= y.array_r
                y.destroy()
            f.x.scatter_forward()
            forces.append(f)
        return forces

    def destroy(self) -> None:
        """Destroy the PETSc objects held by the problem."""
        for obj in [
            self.ksp,
            self.A,
            self._nest,
            self.b,
            self.x,
            *self._K,
            *self._F,
            *self._G,
            *self._B,
        ]:
            obj.destroy()


def gather_dense(A: PETSc.Mat) -> npt.NDArray[np.floating]:
    """A distributed matrix as a dense array on every process (for small reference checks)."""
    start, _ = A.getOwnershipRange()
    indptr, indices, data = A.getValuesCSR()
    parts = A.getComm().tompi4py().allgather((start, indptr, indices, data))
    D = np.zeros(A.getSize())
    for start, indptr, indices, data in parts:
        rows = start + np.repeat(np.arange(indptr.size - 1), np.diff(indptr))
        D[rows, indices] += data
    return D

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""PETSc assembly of a pair's coupling operator (Eqs. 17, 40) and multiplier mass (Eq. 29).

Functions only: the operator is assembled once and never modified in place; the
problems of :mod:`dolfinx_contact_s2s.problem` apply Dirichlet conditions and inactive
rows to copies. This module needs petsc4py and must be imported explicitly, as
``dolfinx.fem.petsc``.
"""

from __future__ import annotations

import typing
import weakref
from collections.abc import Sequence
from dataclasses import dataclass, field

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.compat import geometry_dofmap
from dolfinx_contact_s2s.kernels import KernelBackend, numpy_backend
from dolfinx_contact_s2s.multiplier import MultiplierSpace, cell_rows
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.quadrature import interval_rule

__all__ = [
    "UNCOVERED_TOLERANCE",
    "CooPattern",
    "CouplingOperator",
    "assemble_coupling",
    "coo_matrix",
    "multiplier_mass",
]


def _owners(
    comm: MPI.Comm, rows: npt.NDArray[np.int64], row_starts: npt.NDArray
) -> tuple[npt.NDArray | None, npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """How entries go to the processes owning their rows: order, send and receive counts."""
    rank = comm.rank
    outside = (rows < row_starts[rank]) | (rows >= row_starts[rank + 1])
    if not outside.any():
        # All rows are this process's own (the usual case): no search, no reordering.
        order = None
        send_counts = np.zeros(comm.size, dtype=np.int64)
        send_counts[rank] = rows.size
    else:
        # Searched for the others' rows only; a stable sort of small integers (radix).
        small = np.int16 if comm.size <= np.iinfo(np.int16).max else np.int64
        owner = np.full(rows.size, rank, dtype=small)
        owner[outside] = np.searchsorted(row_starts, rows[outside], side="right") - 1
        order = None if np.all(owner[:-1] <= owner[1:]) else np.argsort(owner, kind="stable")
        send_counts = np.bincount(owner, minlength=comm.size).astype(np.int64)
    recv_counts = np.empty_like(send_counts)
    comm.Alltoall(send_counts, recv_counts)
    return order, send_counts, recv_counts


def _send(comm: MPI.Comm, plan: tuple | None, arrays: list[npt.NDArray]) -> list[npt.NDArray]:
    """The entries ``arrays`` sent as :func:`_owners` planned (unchanged on one process)."""
    if plan is None:
        return arrays
    order, send_counts, recv_counts = plan
    out = []
    for array in arrays:
        array = np.ascontiguousarray(array if order is None else array[order])
        received = np.empty(int(recv_counts.sum()), dtype=array.dtype)
        comm.Alltoallv([array, send_counts], [received, recv_counts])
        out.append(received)
    return out


class CooPattern:
    """The structure of a :func:`coo_matrix` call, reused by later calls with the same indices.

    DOLFINx assembles a form into a matrix whose sparsity it keeps. A contact pair's
    indices (which dofs meet on which piece) change only when its pieces do: a call
    whose index arrays equal the kept ones on every process only sends its values and
    sums them into the kept slots of the CSR structure. The recorded call's index arrays
    are kept, not copied: they must not be modified. On several processes the pattern
    also keeps a matrix of the structure (where petsc4py has PETSc's COO assembly), whose
    duplicate takes the values: creating a distributed matrix from CSR arrays costs ten
    times as much (its communication pattern is built again).
    """

    def __init__(self) -> None:
        """An empty pattern: the next call records its structure."""
        self.keys: list[tuple[npt.NDArray, npt.NDArray]] = []
        self.sizes: list = []
        self.plan: tuple | None = None
        self.slots = np.zeros(0, dtype=np.int64)
        self.csr: tuple[npt.NDArray, npt.NDArray] = (np.zeros(1, PETSc.IntType),) * 2
        self.template: PETSc.Mat | None = None

    def record(self, comm: MPI.Comm, sizes: list, start: int, csr: tuple) -> None:
        """Keep the structure ``csr`` (local rows from global row ``start``; collective)."""
        if self.template is not None:
            self.template.destroy()
            self.template = None
        self.csr, self.sizes = csr, sizes
        if comm.size > 1 and hasattr(PETSc.Mat, "setPreallocationCOO"):
            indptr, indices = csr
            rows = start + np.repeat(np.arange(indptr.size - 1), np.diff(indptr))
            T = PETSc.Mat().create(comm=comm)
            T.setSizes(sizes)
            T.setType(PETSc.Mat.Type.AIJ)
            T.setPreallocationCOO(rows.astype(PETSc.IntType), indices)
            T.setValuesCOO(np.zeros(indices.size, dtype=PETSc.ScalarType))
            T.assemble()
            self.template = T

    def matches(self, comm: MPI.Comm, parts: Sequence[tuple], sizes: list) -> bool:
        """Whether every process's ``parts`` have the recorded index arrays (collective)."""
        same = (
            sizes == self.sizes
            and len(self.keys) == len(parts)
            and all(
                np.array_equal(r, kr) and np.array_equal(c, kc)
                for (r, c, _), (kr, kc) in zip(parts, self.keys, strict=False)
            )
        )
        return comm.allreduce(same, op=MPI.LAND)


def coo_matrix(
    comm: MPI.Comm,
    parts: Sequence[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.floating]]],
    row_map: dolfinx.common.IndexMap,
    col_map: dolfinx.common.IndexMap,
    col_bs: int,
    backend: KernelBackend = numpy_backend,
    row_bs: int = 1,
    pattern: CooPattern | None = None,
) -> PETSc.Mat:
    """Distributed AIJ matrix, the sum of local blocks ``(rows, cols, values)`` (collective).

    Each part holds blocks ``values[s, i, j]`` at ``(rows[s, i], cols[s, j])``, global
    (unrolled) indices of the maps with block sizes ``row_bs`` and ``col_bs``.
    Entries may belong to rows owned by other processes: they are sent to their
    owners, duplicates are summed (the kernel backend's ``coo_to_csr``), and the
    matrix is created from its exact CSR structure. With a ``pattern`` whose indices
    match, the structure is the pattern's; otherwise it is recorded in it.
    """

    def joined(arrays: list[npt.NDArray]) -> npt.NDArray:
        return arrays[0] if len(arrays) == 1 else np.concatenate(arrays)

    values = joined([np.ravel(v) for _, _, v in parts])
    start, n_rows = row_map.local_range[0] * row_bs, row_map.size_local * row_bs
    sizes = [
        [n_rows, row_map.size_global * row_bs],
        [col_map.size_local * col_bs, col_map.size_global * col_bs],
    ]
    if pattern is not None and pattern.matches(comm, parts, sizes):
        (v,) = _send(comm, pattern.plan, [values])
        data = np.bincount(pattern.slots, weights=v, minlength=pattern.csr[1].size)
        return _aij(comm, sizes, (*pattern.csr, data), pattern.template)
    flat_i, flat_j = [], []
    for rows, cols, _ in parts:
        nr, nc = rows.shape[1], cols.shape[1]
        flat_i.append(np.broadcast_to(rows[:, :, None], (rows.shape[0], nr, nc)).reshape(-1))
        flat_j.append(np.broadcast_to(cols[:, None, :], (cols.shape[0], nr, nc)).reshape(-1))
    i = joined(flat_i).astype(np.int64, copy=False)
    j = joined(flat_j).astype(np.int64, copy=False)
    plan = None
    if comm.size > 1:
        starts = comm.allgather(start)
        plan = _owners(comm, i, np.array(starts + [row_map.size_global * row_bs]))
    i, j, v = _send(comm, plan, [i, j, values])
    local_i = i - start if start else i
    indptr, indices, data = backend.coo_to_csr(n_rows, local_i, j, v)
    csr = (indptr.astype(PETSc.IntType), indices.astype(PETSc.IntType))
    if pattern is None:
        return _aij(comm, sizes, (*csr, data))
    pattern.keys = [(r, c) for r, c, _ in parts]
    pattern.plan = plan
    pattern.record(comm, sizes, start, csr)
    slots = backend.csr_slots(indptr, indices, local_i, j)
    pattern.slots = slots.astype(np.int32) if indices.size < 2**31 else slots
    return _aij(comm, sizes, (*csr, data), pattern.template)


def _aij(comm: MPI.Comm, sizes: list, csr: tuple, template: PETSc.Mat | None = None) -> PETSc.Mat:
    """The assembled AIJ matrix of local CSR arrays with sorted columns.

    On one process PETSc uses the arrays in place (the matrix keeps them alive; the
    structure's arrays are shared with a pattern, which never modifies them); on several,
    a duplicate of the pattern's ``template`` takes the values (COO in CSR order), else
    PETSc copies the arrays into a new matrix.
    """
    indptr, indices, data = csr
    data = np.ascontiguousarray(data, dtype=PETSc.ScalarType)
    if comm.size == 1:
        A = PETSc.Mat().createAIJWithArrays(sizes, (indptr, indices, data), comm=comm)
    elif template is not None:
        A = template.duplicate(copy=False)
        A.setValuesCOO(data)
    else:
        A = PETSc.Mat().createAIJ(sizes, csr=(indptr, indices, data), comm=comm)
    A.assemble()
    return A


_PATTERNS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()

#: A multiplier is uncovered when the part of its support that faces a target carries at
#: most this fraction of its integral.
UNCOVERED_TOLERANCE = 1e-10

#: A facet of a multiplier's support is partly covered when the part of it that faces a
#: target is shorter than its length by more than this fraction.
PARTLY_COVERED_TOLERANCE = 1e-8


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
            of :math:`\mu_k` (:math:`\mu_k^2` on faces and quadratic edges) over the
            covered part is at most :data:`UNCOVERED_TOLERANCE` times its integral.
            Sorted, on every process.
        rigid: ``(surface, B_T)`` for each rigid target
            (:class:`~dolfinx_contact_s2s.obstacles.RigidSurface`): its block, kept out of
            the saddle point; it moves the gap (:meth:`gap`).
        groups: The multiplier dofs and the coverage of every group, from which
            :attr:`partial` is computed when first read.
        unsigned: Global multiplier dofs of quadratic edges, covered, whose integral over
            their covered part is not positive (a vertex function whose edge a target
            covers up to 3/4 away from it): kept by tied contact, whose rows only need
            to be independent; unilateral and frictional contact, whose conditions read
            the sign of :math:`\int \mu_k g`, leave them out (:class:`ContactSystem`
            ``signed=True``). Sorted, on every process.
    """

    pair: ContactPair
    blocks: list[tuple[dolfinx.fem.FunctionSpace, PETSc.Mat]]
    G: PETSc.Vec
    uncovered: npt.NDArray[np.int64]
    rigid: list[tuple[typing.Any, PETSc.Mat]] = field(default_factory=list)
    groups: tuple[list, list] | None = field(default=None, repr=False)
    unsigned: npt.NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, np.int64))
    _partial: npt.NDArray[np.int64] | None = field(default=None, init=False, repr=False)

    @property
    def partial(self) -> npt.NDArray[np.int64]:
        """Global multiplier dofs with a facet of their support partly facing a target.

        The end of a target's reach: a facet that faces a target over part of its length
        only (edges of segment-to-segment with a composite rule, else empty). Sorted, on
        every process. Computed when first read (collective: read it on every process),
        as only Newton's tangent needs it: every assembly took 38% longer for it (P1,
        10,000 facets).
        """
        if self._partial is None:
            self._partial = (
                np.zeros(0, np.int64)
                if self.groups is None
                else _partly_covered(self.pair, *self.groups)
            )
        return self._partial

    def gap(self, load: float = 1.0) -> PETSc.Vec:
        r"""The gap at load factor ``load``; the caller destroys it.

        :math:`\mathbf G + \sum \mathbf B_T \mathbf U_T(t)` over the rigid targets'
        prescribed motions :math:`\mathbf U_T(t)`.
        """
        G = self.G.copy()
        for surface, B in self.rigid:
            u = surface.displacement(load)
            n = B.getLocalSize()[1]
            # Owned values in a vector destroyed here: a ghosted vector left to the
            # garbage collector could be destroyed on one rank inside another collective.
            U = PETSc.Vec().createWithArray(u.x.array[:n].copy(), comm=G.getComm())
            B.multAdd(U, G, G)
            U.destroy()
        return G

    @property
    def inactive(self) -> npt.NDArray[np.int64]:
        """Multipliers to set to zero: the pair's duplicates and the uncovered ones."""
        return np.union1d(self.pair.duplicates, self.uncovered).astype(np.int64)

    def block(self, V: dolfinx.fem.FunctionSpace) -> PETSc.Mat | None:
        """The block of space ``V`` (identity by ``is``), or None."""
        return next((B for W, B in self.blocks if W is V), None)

    def destroy(self) -> None:
        """Destroy the PETSc matrices and vector."""
        for _, B in self.blocks + self.rigid:
            B.destroy()
        self.G.destroy()


def _uncovered(
    pair: ContactPair, rows: list, coverage: list, supports: npt.NDArray[np.floating]
) -> npt.NDArray[np.int64]:
    """Global multiplier dofs whose ``coverage`` is at most a fraction of ``supports``."""
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
    none = covered.array_r <= UNCOVERED_TOLERANCE * supports
    covered.destroy()
    mine = imap.local_range[0] + np.flatnonzero(none).astype(np.int64)
    return np.concatenate(comm.allgather(mine)).astype(np.int64)


def _partly_covered(pair: ContactPair, rows: list, coverage: list) -> npt.NDArray[np.int64]:
    """Global multiplier dofs with a partly covered facet (see :class:`CouplingOperator`)."""
    cs, C = pair.contactor, pair.contactor.data
    imap = pair.Q.dofmap.index_map
    marks = PETSc.Vec().createMPI([imap.size_local, imap.size_global], comm=cs.comm)
    n = len(C)
    composite = pair.method == "segment-to-segment" and pair.quadrature.startswith("composite")
    if cs.facet_dim == 1 and composite and n:
        facets = cell_rows(pair.multiplier, np.arange(n, dtype=np.int32))
        xi, w = interval_rule("gauss", 4)
        points = np.repeat(np.arange(n, dtype=np.int32), xi.size)
        _, dx = cs.backend.evaluate(C.coefficients, points, np.tile(xi, n))
        lengths = (np.linalg.norm(dx, axis=1).reshape(n, -1) * w).sum(axis=1)
        # A group's length is the sum of its coverage (the multiplier is a partition of
        # unity); groups are matched to their facet by their multiplier dofs.
        keys, inverse = np.unique(np.concatenate([facets, *rows]), axis=0, return_inverse=True)
        inverse = inverse.reshape(-1)
        spans = np.concatenate([np.zeros(0), *(c.sum(axis=1) for c in coverage)])
        covered = np.bincount(inverse[n:], spans, minlength=len(keys))[inverse[:n]]
        partial = facets[covered < (1 - PARTLY_COVERED_TOLERANCE) * lengths].reshape(-1)
        marks.setValues(
            partial.astype(PETSc.IntType), np.ones(partial.size), addv=PETSc.InsertMode.ADD_VALUES
        )
    marks.assemble()
    mine = imap.local_range[0] + np.flatnonzero(marks.array_r > 0).astype(np.int64)
    marks.destroy()
    return np.concatenate(cs.comm.allgather(mine)).astype(np.int64)


def assemble_coupling(
    pair: ContactPair, tangential: int = 0, axis: npt.ArrayLike | None = None
) -> CouplingOperator:
    r"""Assemble the coupling of a contact pair with global indices (collective).

    The rows are the multiplier dofs of ``pair.Q``; there is one matrix per distinct
    displacement space, so a contactor and a target in one mesh and space give one
    block holding both contributions (Eq. 40, summed).

    Args:
        pair: The contact pair.
        tangential: The tangential coupling of friction instead, with a zero gap: its
            tangent 1 (2D), 1 or 2 (3D) of
            :meth:`~dolfinx_contact_s2s.pair.ContactPair.coupling_blocks`.
        axis: The axis of the tangent basis on faces.

    Returns:
        The :class:`CouplingOperator`. The caller must ``destroy()`` it.

    Raises:
        ValueError: On every rank, if the contactor faces none of its targets.
    """
    faces = pair.contactor.facet_dim == 2
    if tangential and (pair.obstacles or tangential > 1 + faces or (faces and axis is None)):
        raise ValueError("tangential coupling: meshed targets, T (2D), T1, T2 of an axis (3D)")
    tangent = (
        (None if axis is None else np.asarray(axis, float), tangential) if tangential else None
    )
    groups = pair.coupling_blocks(tangent)
    comm = pair.contactor.comm
    backend = pair.contactor.backend
    if comm.allreduce(sum(b.rows.shape[0] for b in groups), op=MPI.SUM) == 0:
        targets = ", ".join(str(t.tag) for t in (*pair.targets, *pair.obstacles))
        raise ValueError(
            "the contactor and target surfaces never face each other within the search "
            f"radius (contactor tag {pair.contactor.tag}, target tag(s) {targets}): there is "
            "nothing to integrate. Check which side is which (their outward normals must "
            "oppose), or pass a larger search_radius= to contact_pair (now "
            f"{pair.search_radius:g})"
        )
    q_map = pair.Q.dofmap.index_map
    spaces: list[dolfinx.fem.FunctionSpace] = []
    parts: list[list] = []
    rigid: list[typing.Any] = []
    rigid_parts: list[list] = []

    def add(V: typing.Any, part: tuple, spaces: list, parts: list) -> None:
        # Identity, not equality: the same space must give one summed block.
        for k, W in enumerate(spaces):
            if W is V:
                parts[k].append(part)
                return
        spaces.append(V)
        parts.append([part])

    for b in groups:
        add(pair.contactor.V, (b.rows, b.cols_contactor, b.values_contactor), spaces, parts)
        if getattr(b.target, "analytic", False):
            continue  # no target unknowns and no motion: the gap holds all
        part = (b.rows, b.cols_target, b.values_target)
        if b.target.rigid:
            add(b.target, part, rigid, rigid_parts)
        else:
            add(b.target.V, part, spaces, parts)

    # The structures of this pair's blocks, reused while its pieces stay the same.
    patterns = _PATTERNS.setdefault(pair, {})

    def matrix(V: dolfinx.fem.FunctionSpace, p: list, key: tuple) -> PETSc.Mat:
        pattern = patterns.setdefault((*key, tangential), CooPattern())
        imap, bs = V.dofmap.index_map, V.dofmap.index_map_bs
        return coo_matrix(comm, p, q_map, imap, bs, backend, pattern=pattern)

    blocks = [(V, matrix(V, parts[k], ("mesh", k))) for k, V in enumerate(spaces)]
    rigid_blocks = [(t, matrix(t.V, rigid_parts[k], ("rigid", k))) for k, t in enumerate(rigid)]
    G = PETSc.Vec().createMPI([q_map.size_local, q_map.size_global], comm=comm)
    for b in groups:
        G.setValues(
            b.rows.reshape(-1).astype(PETSc.IntType),
            b.gap.reshape(-1),
            addv=PETSc.InsertMode.ADD_VALUES,
        )
    G.assemble()
    if not tangential:
        _linearize(pair, blocks, G)
    rows, coverage = [b.rows for b in groups], [b.coverage for b in groups]
    uncovered = _uncovered(pair, rows, coverage, pair.multiplier_supports())
    # Quadratic edges: the integral of mu_k over its covered part, against the whole's.
    signed = [b.coverage if b.signed is None else b.signed for b in groups]
    unsigned = np.zeros(0, np.int64)
    if pair.squared_coverage and pair.contactor.facet_dim == 1:
        nonpositive = _uncovered(pair, rows, signed, pair.multiplier_integrals())
        unsigned = np.setdiff1d(nonpositive, uncovered).astype(np.int64)
    return CouplingOperator(pair, blocks, G, uncovered, rigid_blocks, (rows, signed), unsigned)


def _linearize(pair: ContactPair, blocks: list, G: PETSc.Vec) -> None:
    r"""``G -= B_V u_V`` for the spaces whose surfaces are placed at :math:`X + u_V`.

    The gap of the total displacement :math:`\mathbf U` linearized at the placement
    (:meth:`~dolfinx_contact_s2s.surface.ContactSurface.set_displacement`).
    """
    comm = pair.contactor.comm
    surfaces = [pair.contactor] + [t for t in pair.targets if not t.rigid]
    if all(s.placement is None for s in surfaces):
        return  # set_displacement is collective: the same on every rank
    for V, B in blocks:
        placed = [s.placement for s in surfaces if s.V is V]
        some = any(p is not None for p in placed)
        same = all(p is not None and np.array_equal(p, placed[0]) for p in placed)
        if not comm.allreduce(some, op=MPI.LOR):
            continue
        if not comm.allreduce(same, op=MPI.LAND):
            raise ValueError(
                "the surfaces of a pair on one displacement space are placed at different "
                "displacements: call set_displacement(u) on each with the same u"
            )
        n = B.getLocalSize()[1]
        u = PETSc.Vec().createWithArray(np.array(placed[0][:n]), comm=comm)
        shift = G.duplicate()
        B.mult(u, shift)
        G.axpy(-1.0, shift)
        for v in (u, shift):
            v.destroy()


def _dual_mass(space: MultiplierSpace) -> PETSc.Mat:
    r"""The mass of the dual basis :math:`\psi_k` (collective; the caller destroys it).

    Facet by facet (:math:`\psi_k` is discontinuous between facets): :math:`|\det J|`
    times :attr:`~dolfinx_contact_s2s.multiplier.MultiplierSpace.dual_mass` (affine
    facets), summed by :func:`coo_matrix`.
    """
    Q, mesh = space.Q, space.Q.mesh
    tdim = mesh.topology.dim
    cells = mesh.topology.index_map(tdim).size_local
    x = mesh.geometry.x[geometry_dofmap(mesh)[:cells, : tdim + 1]]
    J = np.stack([x[:, i] - x[:, 0] for i in range(1, tdim + 1)], axis=2)
    scales = np.sqrt(np.linalg.det(np.einsum("cgi,cgj->cij", J, J)))
    local = Q.dofmap.list[:cells]
    dofs = Q.dofmap.index_map.local_to_global(local.reshape(-1)).reshape(local.shape)
    blocks = scales[:, None, None] * space.dual_mass
    imap = Q.dofmap.index_map
    return coo_matrix(mesh.comm, [(dofs, dofs, blocks)], imap, imap, 1)


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
    its inverse when the multiplier is the nodal force (``weight="unit"``). Dual
    multipliers (:attr:`~dolfinx_contact_s2s.multiplier.MultiplierSpace.dual`): the mass
    of the dual basis. In
    axisymmetry (``pair.axisymmetric``) every integral carries :math:`2\pi r`,
    :math:`r = x_0` of the multiplier's mesh: the norm over the 3D surface. The caller
    must ``destroy()`` it.
    """
    Q = pair.Q
    p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
    w = 2 * np.pi * ufl.SpatialCoordinate(Q.mesh)[0] if pair.axisymmetric else 1.0
    if getattr(pair.multiplier, "dual", False):
        return _dual_mass(pair.multiplier)
    M = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(ufl.inner(p, q) * w * ufl.dx))
    M.assemble()
    if not pair.nodal:
        return M
    D = _lumped(pair, M)
    M.destroy()
    return D

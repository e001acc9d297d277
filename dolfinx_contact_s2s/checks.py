# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Diagnostics run before Eq. (18) is solved: floating bodies and redundant constraints.

The saddle point problem of Eq. (18),

.. math::
    \begin{bmatrix} \mathbf K & -\mathbf B^T \\ -\mathbf B & \mathbf 0 \end{bmatrix}
    \begin{bmatrix} \mathbf U \\ \mathbf\Lambda \end{bmatrix} =
    \begin{bmatrix} \mathbf F \\ \mathbf G \end{bmatrix},

is solvable only if (Eq. 33) :math:`\mathbf V^T\mathbf K\mathbf V > 0` for every
:math:`\mathbf V \ne 0` in the kernel of :math:`\mathbf B` -- the ellipticity of Eq. (19)
on the constrained space, "a properly supported structure" -- and (Eqs. 34-35)
:math:`\mathbf B` has full row rank. A direct solver does not always notice when either
fails: it returns displacements of :math:`10^{13}` for a floating body, or multipliers
that change by orders of magnitude with the number of processes for a rank-deficient
:math:`\mathbf B`. The functions here detect both cases, with a cost linear in the
number of degrees of freedom:

* :func:`unsupported_motions` (Eq. 33). An elastic body is stiff against every motion
  except its rigid motions (:func:`rigid_body_modes`, one set per connected component
  of the mesh, :func:`connected_components`), so Eq. (33) fails iff some combination
  :math:`\mathbf R\alpha` of rigid modes vanishes at every Dirichlet dof, is not
  resisted by any active contact row, and costs no energy in the user's form (which
  may contain springs). With every row of :math:`\mathbf R_D` and of
  :math:`\mathbf B\mathbf R` scaled to unit size and the energy measured relative to
  :math:`k_{max} h` (see the function), the motions are the eigenvectors of the small
  Gram matrix :math:`\mathbf G = \mathbf G_D + \mathbf G_B + \mathbf G_K` (order
  :math:`3c` in 2D, :math:`6c` in 3D for :math:`c` bodies) whose eigenvalues lie below
  :data:`UNSUPPORTED_TOL` :math:`\cdot\max(1, \lambda_{max})`. :math:`10^{-10}` is far
  above round-off (that of the normalized sums, :math:`\epsilon` times their trace;
  that of the elastic energy of a rigid mode, measured :math:`10^{-14}` for
  :math:`6\cdot 10^5` nodes in 2D and :math:`5\cdot 10^{-15}` for :math:`6\cdot 10^4`
  in 3D, growing as :math:`h^{-1}`) and far below the support a single Dirichlet dof
  or contact row gives (of order one): a motion resisted :math:`10^{10}` times less
  than that makes Eq. (18) as ill-conditioned as a floating body, and is reported as
  one. A spring of stiffness :math:`k` per unit area of the boundary of a body of unit
  size counts as a support while :math:`k h / E \gtrsim 10^{-10}`.
* :func:`redundant_constraints` (Eqs. 34-35). With the active rows of
  :math:`\tilde{\mathbf B} = \mathbf B\mathbf D` (Dirichlet columns removed) scaled to
  unit length, the number of dependent rows is the number of eigenvalues of
  :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` below :data:`REDUNDANT_TOL`
  :math:`= 10^{-12}` (singular values of :math:`\tilde{\mathbf B}` below
  :math:`10^{-6}`), counted exactly and for any size as the number of negative pivots
  of an :math:`\mathbf L\mathbf D\mathbf L^T` factorization of
  :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T - \tau\mathbf I` (Sylvester's law of
  inertia, MUMPS). Rows that vanish after the Dirichlet elimination (norm below
  :math:`\sqrt\tau` times their norm before it) are redundant by definition and
  counted separately. The round-off of the unit-row Gram matrix is
  :math:`\epsilon` times the number of overlapping rows, four orders of magnitude below
  :math:`\tau`. :func:`redundant_multipliers` names the dependent rows of small
  problems.

Every function is collective on the communicator of its arguments and returns the same
result on every process. The module needs petsc4py and is imported explicitly.
"""

from __future__ import annotations

import typing
from collections.abc import Sequence
from dataclasses import dataclass

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.la
import numpy as np
import numpy.typing as npt
import scipy.linalg
import scipy.sparse
import scipy.sparse.csgraph

from dolfinx_contact_s2s._compat import geometry_dofmap

__all__ = [
    "REDUNDANT_TOL",
    "UNSUPPORTED_TOL",
    "Redundancy",
    "RigidMotion",
    "UnsupportedMotion",
    "connected_components",
    "near_nullspace",
    "redundant_constraints",
    "redundant_multipliers",
    "rigid_body_modes",
    "unsupported_motions",
]

UNSUPPORTED_TOL: float = 1e-10
"""Relative eigenvalue of the normalized Gram matrix below which a rigid motion is free."""

REDUNDANT_TOL: float = 1e-12
r"""Eigenvalue of :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` (unit rows) below which a
row is dependent: singular values below :math:`10^{-6}`."""

_INT64_MAX = np.iinfo(np.int64).max


# --------------------------------------------------------------------------------------
# Connected components and rigid body modes
# --------------------------------------------------------------------------------------


def connected_components(mesh: dolfinx.mesh.Mesh) -> tuple[npt.NDArray[np.int32], int]:
    """Label the connected components (bodies) of a mesh.

    Two cells are connected when they share a vertex. Components are found on each
    process, merged across processes through the vertices they share (an exchange of
    the interface vertices only), and numbered by the smallest input (file) index of
    their geometry nodes: the labels do not depend on the partition, and a body meshed
    first in Gmsh gets the lowest label. Works with and without ghost cells.

    Args:
        mesh: The mesh.

    Returns:
        The component of every local cell (owned, then ghost) and the number of
        components over all processes.
    """
    comm = mesh.comm
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim, 0)
    c2v = mesh.topology.connectivity(tdim, 0)
    cell_map, vertex_map = mesh.topology.index_map(tdim), mesh.topology.index_map(0)
    nc = cell_map.size_local + cell_map.num_ghosts
    nv_owned = vertex_map.size_local
    nv = nv_owned + vertex_map.num_ghosts
    offsets = np.asarray(c2v.offsets[: nc + 1], dtype=np.int64)
    vertices = np.asarray(c2v.array[: offsets[-1]], dtype=np.int64)
    cells = np.repeat(np.arange(nc, dtype=np.int64), np.diff(offsets))
    graph = scipy.sparse.coo_matrix(
        (np.ones(vertices.size, dtype=np.int8), (cells, nc + vertices)), shape=(nc + nv, nc + nv)
    ).tocsr()
    _, local = scipy.sparse.csgraph.connected_components(graph, directed=False)

    # Local components holding cells, numbered 0..k-1; vertices take their cells' number.
    used, cell_component = np.unique(local[:nc], return_inverse=True)
    k = used.size
    renumber = np.full(local.max(initial=-1) + 1, -1, dtype=np.int64)
    renumber[used] = np.arange(k)
    vertex_component = renumber[local[nc:]]
    offset = comm.exscan(k) or 0
    total = comm.allreduce(k)

    # Owner's component of every ghost vertex: the edges between local components.
    owner = dolfinx.la.vector(vertex_map, 1, dtype=np.int64)
    owner.array[:] = -1
    owned_component = vertex_component[:nv_owned]
    owner.array[:nv_owned] = np.where(owned_component >= 0, offset + owned_component, -1)
    owner.scatter_forward()
    mine = vertex_component[nv_owned:]
    theirs = owner.array[nv_owned:nv]
    keep = (mine >= 0) & (theirs >= 0)
    edges = np.unique(np.stack([offset + mine[keep], theirs[keep]], axis=1), axis=0)
    edges = np.concatenate([e.reshape(-1, 2) for e in comm.allgather(edges)])

    # Partition-independent key of each local component: its smallest input node index.
    nodes = geometry_dofmap(mesh)[:nc]
    cell_key = np.asarray(mesh.geometry.input_global_indices, dtype=np.int64)[nodes].min(axis=1)
    key = np.full(k, _INT64_MAX, dtype=np.int64)
    np.minimum.at(key, cell_component, cell_key)
    keys = np.concatenate(comm.allgather(key))

    merged = scipy.sparse.coo_matrix(
        (np.ones(len(edges), dtype=np.int8), (edges[:, 0], edges[:, 1])), shape=(total, total)
    )
    count, root = scipy.sparse.csgraph.connected_components(merged, directed=False)
    root_key = np.full(count, _INT64_MAX, dtype=np.int64)
    np.minimum.at(root_key, root, keys)
    label = np.empty(count, dtype=np.int32)
    label[np.argsort(root_key, kind="stable")] = np.arange(count, dtype=np.int32)
    return label[root[offset + cell_component]], int(count)


@dataclass(frozen=True)
class _Bodies:
    """The connected components of a vector space, seen from its owned dofs."""

    comm: MPI.Comm
    bs: int
    count: int
    labels: npt.NDArray[np.int32]  # component of each owned dof block
    x: npt.NDArray[np.floating]  # coordinates of the owned dof blocks, (n, bs)
    centroid: npt.NDArray[np.floating]  # (count, bs)
    size: npt.NDArray[np.floating]  # RMS distance of the nodes from the centroid, (count,)
    nodes: npt.NDArray[np.floating]  # number of nodes, (count,)
    lower: npt.NDArray[np.floating]  # bounding boxes, (count, bs)
    upper: npt.NDArray[np.floating]

    @property
    def modes(self) -> int:
        """Rigid modes per component."""
        return {1: 1, 2: 3, 3: 6}[self.bs]

    def values(self) -> npt.NDArray[np.floating]:
        """Rigid modes of its component at each owned dof, (n * bs, modes)."""
        n, bs, m = self.labels.size, self.bs, self.modes
        values = np.zeros((n, bs, m))
        values[:, np.arange(bs), np.arange(bs)] = 1.0
        d = (self.x - self.centroid[self.labels]) / self.size[self.labels, None]
        if bs == 2:
            values[:, 0, 2], values[:, 1, 2] = -d[:, 1], d[:, 0]
        elif bs == 3:
            for a in range(3):
                b, c = (a + 1) % 3, (a + 2) % 3
                values[:, b, 3 + a], values[:, c, 3 + a] = -d[:, c], d[:, b]
        return values.reshape(n * bs, m)

    def matrix(self, offset: int, columns: int) -> scipy.sparse.csr_matrix:
        """Owned rows of the rigid modes, columns ``offset + component * modes + mode``."""
        values = self.values()
        m = self.modes
        rows = np.repeat(np.arange(values.shape[0]), m)
        dof_labels = np.repeat(self.labels, self.bs)
        cols = offset + (dof_labels[:, None] * m + np.arange(m)[None, :]).ravel()
        R = scipy.sparse.csr_matrix(
            (values.ravel(), (rows, cols)), shape=(values.shape[0], columns)
        )
        R.eliminate_zeros()
        return R


def _bodies(V: dolfinx.fem.FunctionSpace, labels: npt.NDArray[np.int32] | None) -> _Bodies:
    mesh = V.mesh
    comm = mesh.comm
    bs = V.dofmap.index_map_bs
    if bs not in (1, 2, 3):
        raise ValueError(f"Rigid modes need a vector space of block size 1, 2 or 3, not {bs}.")
    if labels is None:
        labels, count = connected_components(mesh)
    else:
        labels = np.asarray(labels, dtype=np.int32)
        count = comm.allreduce(int(labels.max(initial=-1)) + 1, op=MPI.MAX)
    imap = V.dofmap.index_map
    n = imap.size_local
    dofs = np.asarray(V.dofmap.list)[: labels.size]
    block_label = np.full(n + imap.num_ghosts, -1, dtype=np.int32)
    block_label[dofs.ravel()] = np.repeat(labels, dofs.shape[1])
    owned = block_label[:n]
    if comm.allreduce(int(np.count_nonzero(owned < 0))) > 0:
        raise ValueError("Some owned dofs of the space lie in no labelled cell.")
    x = V.tabulate_dof_coordinates()[:n, :bs].astype(np.float64)

    counts = comm.allreduce(np.bincount(owned, minlength=count).astype(np.float64))
    sums = np.zeros((count, bs))
    np.add.at(sums, owned, x)
    centroid = comm.allreduce(sums) / np.maximum(counts, 1.0)[:, None]
    d2 = np.sum((x - centroid[owned]) ** 2, axis=1)
    size = np.sqrt(
        comm.allreduce(np.bincount(owned, weights=d2, minlength=count)) / np.maximum(counts, 1.0)
    )
    size[size <= 0.0] = 1.0
    lower = np.full((count, bs), np.inf)
    upper = np.full((count, bs), -np.inf)
    np.minimum.at(lower, owned, x)
    np.maximum.at(upper, owned, x)
    comm.Allreduce(MPI.IN_PLACE, lower, op=MPI.MIN)
    comm.Allreduce(MPI.IN_PLACE, upper, op=MPI.MAX)
    return _Bodies(comm, bs, count, owned, x, centroid, size, counts, lower, upper)


def _vector(comm: MPI.Comm, values: npt.NDArray[np.floating], bs: int) -> PETSc.Vec:
    vec = PETSc.Vec().createMPI((values.size, PETSc.DETERMINE), bsize=bs, comm=comm)
    vec.array[:] = values
    return vec


def rigid_body_modes(
    V: dolfinx.fem.FunctionSpace, labels: npt.NDArray[np.int32] | None = None
) -> list[PETSc.Vec]:
    """Rigid body modes of every body (connected component) of a vector Lagrange space.

    Per component, in this order: the translations along the axes, then the rotations
    about the component's centroid (one in 2D, about the x, y and z axes in 3D), scaled
    to unit root-mean-square displacement per node (a rotation is divided by the RMS
    distance of the component's nodes from its centroid). The modes of component
    ``c`` are ``modes[c * m:(c + 1) * m]`` with ``m`` = 1, 3 or 6 in 1D, 2D, 3D.

    Args:
        V: Vector Lagrange space (block size = geometric dimension).
        labels: Component of each local cell, :func:`connected_components` if not given.

    Returns:
        Vectors in the PETSc layout of ``V`` (owned dofs, unrolled block size, as
        :func:`dolfinx.fem.petsc.create_vector`). The caller destroys them.
    """
    bodies = _bodies(V, labels)
    values = bodies.values()
    dof_labels = np.repeat(bodies.labels, bodies.bs)
    modes = []
    for c in range(bodies.count):
        inside = dof_labels == c
        for j in range(bodies.modes):
            modes.append(_vector(bodies.comm, np.where(inside, values[:, j], 0.0), bodies.bs))
    return modes


def near_nullspace(
    V: dolfinx.fem.FunctionSpace, labels: npt.NDArray[np.int32] | None = None
) -> PETSc.NullSpace:
    """Orthonormalized rigid body modes as a near-nullspace for algebraic multigrid.

    Args:
        V: Vector Lagrange space.
        labels: Component of each local cell, :func:`connected_components` if not given.

    Returns:
        A null space for :meth:`petsc4py.PETSc.Mat.setNearNullSpace`, with the modes of
        :func:`rigid_body_modes` orthonormalized by modified Gram-Schmidt (twice). The
        caller destroys it.
    """
    modes = rigid_body_modes(V, labels)
    for i, v in enumerate(modes):
        for _ in range(2):
            for u in modes[:i]:
                v.axpy(-u.dot(v), u)
        if v.normalize() <= 0.0:
            raise RuntimeError(f"Rigid mode {i} of the space is zero.")
    nullspace = PETSc.NullSpace().create(vectors=modes, comm=V.mesh.comm)
    for v in modes:
        v.destroy()
    return nullspace


# --------------------------------------------------------------------------------------
# Unsupported rigid motions (Eq. 33)
# --------------------------------------------------------------------------------------


def _fmt(values: npt.ArrayLike) -> str:
    values = np.atleast_1d(np.asarray(values, dtype=np.float64))
    return "(" + ", ".join(f"{v + 0.0:.4g}" for v in values) + ")"


@dataclass(frozen=True)
class RigidMotion:
    r"""Rigid motion of one body.

    :math:`\mathbf u(\mathbf x) = \mathbf t + \omega\times(\mathbf x - \mathbf c)`.

    Attributes:
        space: Index of the displacement space.
        component: Connected component (body) of the space's mesh.
        coefficients: Coefficients of the component's modes of :func:`rigid_body_modes`.
        translation: :math:`\mathbf t`, the displacement of the centroid.
        rotation: :math:`\omega` (one value in 2D, a vector in 3D, none in 1D) per unit
            length.
        centroid: :math:`\mathbf c`, the centroid of the component's nodes.
        bounding_box: Lower and upper corner of the component's nodes, shape ``(2, gdim)``.
        description: "translation along (0, 1)", "rotation about (0.5, 0.25)", ...
    """

    space: int
    component: int
    coefficients: npt.NDArray[np.floating]
    translation: npt.NDArray[np.floating]
    rotation: npt.NDArray[np.floating]
    centroid: npt.NDArray[np.floating]
    bounding_box: npt.NDArray[np.floating]
    description: str

    def displacement(self, x: npt.ArrayLike) -> npt.NDArray[np.floating]:
        """The motion's displacement at points ``x`` of shape ``(num_points, gdim)``."""
        d = np.atleast_2d(np.asarray(x, dtype=np.float64))[:, : self.translation.size]
        d = d - self.centroid
        u = np.tile(self.translation, (d.shape[0], 1))
        if self.translation.size == 2:
            u += self.rotation[0] * np.stack([-d[:, 1], d[:, 0]], axis=1)
        elif self.translation.size == 3:
            u += np.cross(self.rotation, d)
        return u

    def body(self) -> str:
        """The body in words: space, component and bounding box."""
        box = np.array(self.bounding_box, dtype=np.float64)
        box[np.abs(box) <= 1e-12 * max(np.abs(box).max(initial=0.0), 1e-300)] = 0.0
        box_text = " x ".join(f"[{lo + 0.0:.4g}, {hi + 0.0:.4g}]" for lo, hi in box.T.tolist())
        return f"body {self.component} of space {self.space} (nodes in {box_text})"


def _describe(t: npt.NDArray, w: npt.NDArray, c: npt.NDArray, size: float) -> str:
    scale = np.linalg.norm(t) + np.linalg.norm(w) * size
    if np.linalg.norm(w) * size <= 1e-8 * scale:
        return f"translation along {_fmt(t / np.linalg.norm(t))}"
    if t.size == 2:
        point = c + np.array([-t[1], t[0]]) / w[0]
        if np.linalg.norm(point - c) <= 1e3 * size:
            return f"rotation about {_fmt(point)}"
        return (
            f"translation along {_fmt(t / np.linalg.norm(t))} combined with a rotation "
            f"about {_fmt(c)}"
        )
    axis = w / np.linalg.norm(w)
    point = c + np.cross(w, t) / np.dot(w, w)
    along = np.dot(t, axis)
    text = f"rotation about the axis {_fmt(axis)} through {_fmt(point)}"
    if abs(along) > 1e-8 * scale:
        text += f" with a translation of {along + 0.0:.4g} along it"
    if np.linalg.norm(point - c) > 1e3 * size:
        text = f"translation along {_fmt(t / np.linalg.norm(t))} combined with a rotation"
    return text


@dataclass(frozen=True)
class UnsupportedMotion:
    """A combination of rigid motions resisted by nothing (Eq. 33 fails).

    Attributes:
        motions: The bodies that move, largest motion first (several when bodies are
            tied to each other by constraints but not to the ground).
        eigenvalue: Its normalized stiffness, below the threshold.
    """

    motions: tuple[RigidMotion, ...]
    eigenvalue: float

    @property
    def space(self) -> int:
        """Space index of the body that moves most."""
        return self.motions[0].space

    @property
    def component(self) -> int:
        """Component (body) label of the body that moves most."""
        return self.motions[0].component

    @property
    def description(self) -> str:
        """Description of the motion of the body that moves most."""
        return self.motions[0].description

    @property
    def coefficients(self) -> npt.NDArray[np.floating]:
        """Rigid mode coefficients of the body that moves most."""
        return self.motions[0].coefficients

    def displacement(self, x: npt.ArrayLike) -> npt.NDArray[np.floating]:
        """Displacement of the body that moves most at points ``x``."""
        return self.motions[0].displacement(x)

    def describe(self) -> str:
        """Text for an error message: which body can move how."""
        first, *others = self.motions
        text = f"{first.body()} can move freely: {first.description}"
        for other in others:
            text += f"; together with {other.body()}: {other.description}"
        return text


def _csr(A: PETSc.Mat, columns: int) -> scipy.sparse.csr_matrix:
    """Owned rows of a PETSc AIJ matrix with global column indices."""
    indptr, indices, data = A.getValuesCSR()
    return scipy.sparse.csr_matrix((data, indices, indptr), shape=(indptr.size - 1, columns))


def _petsc_aij(
    comm: MPI.Comm, A: scipy.sparse.csr_matrix, row_sizes: tuple[int, int], col_sizes: tuple
) -> PETSc.Mat:
    A = A.tocsr()
    A.sort_indices()
    M = PETSc.Mat().createAIJ(
        size=(row_sizes, col_sizes),
        csr=(A.indptr.astype(PETSc.IntType), A.indices.astype(PETSc.IntType), A.data),
        comm=comm,
    )
    M.assemble()
    return M


def _owned_rows(A: PETSc.Mat, inactive: npt.ArrayLike | None) -> npt.NDArray[np.bool_]:
    """Owned rows of ``A`` not listed as inactive on any process."""
    comm = A.getComm().tompi4py()
    start, end = A.getOwnershipRange()
    active = np.ones(end - start, dtype=np.bool_)
    listed = np.zeros(0, dtype=np.int64) if inactive is None else np.asarray(inactive, np.int64)
    listed = np.unique(np.concatenate(comm.allgather(listed.ravel())))
    listed = listed[(listed >= start) & (listed < end)]
    active[listed - start] = False
    return active


def _unit_rows(A: scipy.sparse.csr_matrix, norms2: npt.NDArray) -> scipy.sparse.csr_matrix:
    keep = norms2 > 0.0
    scale = np.zeros(norms2.size)
    scale[keep] = 1.0 / np.sqrt(norms2[keep])
    return scipy.sparse.diags(scale) @ A


def unsupported_motions(
    spaces: Sequence[dolfinx.fem.FunctionSpace],
    stiffness: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec],
    constraints: Sequence[Sequence[tuple[int, PETSc.Mat]]],
    inactive: Sequence[npt.ArrayLike | None],
    *,
    labels: Sequence[npt.NDArray[np.int32] | None] | None = None,
    tol: float = UNSUPPORTED_TOL,
) -> list[UnsupportedMotion]:
    r"""Rigid motions of the bodies that nothing resists (Eq. 33 fails).

    A combination :math:`\mathbf R\alpha` of the rigid modes of all bodies
    (:func:`rigid_body_modes`) is unsupported iff it vanishes at the Dirichlet dofs,
    :math:`\mathbf B\mathbf R\alpha = 0` on the active multiplier rows of every pair,
    and :math:`(\mathbf R\alpha)^T\mathbf K(\mathbf R\alpha) = 0`. These are the null
    vectors of :math:`\mathbf G = \mathbf G_D + \mathbf G_B + \mathbf G_K` with

    * :math:`\mathbf G_D = \sum_{j \in D} \mathbf r_j\mathbf r_j^T/|\mathbf r_j|^2`, the
      rows :math:`\mathbf r_j` of :math:`\mathbf R` at the Dirichlet dofs;
    * :math:`\mathbf G_B = \sum_i \mathbf b_i\mathbf b_i^T/w_i` with
      :math:`\mathbf b_i = (\mathbf B\mathbf R)_i` and
      :math:`w_i = \sum_j B_{ij}^2|\mathbf r_j|^2`: scale-free, and (Cauchy-Schwarz)
      a row whose :math:`\mathbf b_i` is round-off stays round-off instead of being
      blown up to unit length;
    * :math:`\mathbf G_K = \mathbf S\mathbf R_f^T\mathbf K\mathbf R_f\mathbf S / k_{max}`
      with :math:`\mathbf R_f` the modes with Dirichlet rows zeroed, :math:`k_{max}`
      the largest diagonal entry of :math:`\mathbf K` at a free dof and
      :math:`S_{jj} = n^{1/(2d)}/|\mathbf R_{:j}|` for a mode of a body with :math:`n`
      nodes in dimension :math:`d`: the Rayleigh quotient of the motion relative to
      :math:`k_{max} h`, :math:`h \sim n^{-1/d}` (between the stiffest dof,
      :math:`k_{max}`, and the softest elastic mode, :math:`\sim k_{max} h^2`, of a body
      of unit size).

    :math:`\mathbf G` is block diagonal over groups of bodies coupled by constraints;
    each group's eigenvalues below ``tol * max(1, largest eigenvalue of the group)``
    give its unsupported motions, reported in a reduced echelon basis (a free body gives
    its translations along the axes and its rotation about its centroid). The work is
    :math:`O(\text{dofs})` sparse products plus dense algebra of the order of
    :math:`\mathbf G`.

    Args:
        spaces: Displacement spaces (vector Lagrange).
        stiffness: Assembled :math:`\mathbf K_i` of each space, Dirichlet rows and
            columns replaced by a unit diagonal (as
            ``dolfinx.fem.petsc.assemble_matrix(a, bcs=bcs)``).
        dirichlet_masks: Per space, 1 at free dofs and 0 at Dirichlet dofs.
        constraints: Per contact pair, its blocks ``(space index, B)`` with ``B`` the
            pair's multipliers by the space's dofs (not Dirichlet-eliminated).
        inactive: Per pair, global indices of the multiplier rows to ignore (each
            process may pass any subset; their union is used), or ``None``.
        labels: Per space, the component of each local cell (default
            :func:`connected_components` of the space's mesh).
        tol: Relative eigenvalue threshold.

    Returns:
        The unsupported motions, the same on every process; empty if Eq. (33) holds.
    """
    if len(spaces) == 0:
        return []
    comm = spaces[0].mesh.comm
    bodies = [_bodies(V, None if labels is None else labels[s]) for s, V in enumerate(spaces)]
    offsets = np.cumsum([0] + [b.count * b.modes for b in bodies])
    N = int(offsets[-1])
    col_sizes = (N if comm.rank == 0 else 0, N)
    G = np.zeros((2, N, N))  # G_D + G_B, G_K

    R_local = [b.matrix(int(offsets[s]), N) for s, b in enumerate(bodies)]
    R_petsc, q_petsc = [], []
    colnorm2 = np.zeros(N)
    kmax = []
    for s, R in enumerate(R_local):
        n = R.shape[0]
        fixed = dirichlet_masks[s].array_r[:n] < 0.5
        free = ~fixed
        rownorm2 = np.asarray(R.multiply(R).sum(axis=1)).ravel()
        colnorm2 += np.asarray(R.multiply(R).sum(axis=0)).ravel()
        RD = _unit_rows(R[fixed], rownorm2[fixed])
        G[0] += (RD.T @ RD).toarray()
        # Energy of the motions over the free dofs.
        Rf = scipy.sparse.diags(free.astype(np.float64)) @ R
        Rf_petsc = _petsc_aij(comm, Rf, (n, PETSc.DETERMINE), col_sizes)
        K = stiffness[s]
        KR = K.matMult(Rf_petsc)
        G[1] += (Rf.T @ _csr(KR, N)).toarray()
        KR.destroy()
        Rf_petsc.destroy()
        diag = K.getDiagonal()
        kmax.append(comm.allreduce(float(diag.array_r[:n][free].max(initial=0.0)), op=MPI.MAX))
        diag.destroy()
        R_petsc.append(_petsc_aij(comm, R, (n, PETSc.DETERMINE), col_sizes))
        q_petsc.append(_vector(comm, rownorm2, 1))

    for p, pair in enumerate(constraints):
        if len(pair) == 0:
            continue
        BR = None
        w = None
        for s, B in pair:
            P = B.matMult(R_petsc[s])
            part = _csr(P, N)
            P.destroy()
            indptr, indices, data = B.getValuesCSR()
            B2 = PETSc.Mat().createAIJ(
                size=B.getSizes(), csr=(indptr, indices, data * data), comm=comm
            )
            B2.assemble()
            wv = B2.createVecLeft()
            B2.mult(q_petsc[s], wv)
            w = wv.array_r.copy() if w is None else w + wv.array_r
            BR = part if BR is None else BR + part
            wv.destroy()
            B2.destroy()
        assert BR is not None and w is not None
        active = _owned_rows(pair[0][1], inactive[p] if p < len(inactive) else None)
        Bn = _unit_rows(BR[active], w[active])
        G[0] += (Bn.T @ Bn).toarray()
    for M in R_petsc:
        M.destroy()
    for v in q_petsc:
        v.destroy()

    G = comm.allreduce(G)
    colnorm2 = comm.allreduce(colnorm2)
    nodes = np.concatenate([np.repeat(b.nodes, b.modes) ** (0.5 / b.bs) for b in bodies])
    S = nodes / np.sqrt(np.where(colnorm2 > 0.0, colnorm2, 1.0))
    for s in range(len(spaces)):
        cols = slice(offsets[s], offsets[s + 1])
        if kmax[s] > 0.0:
            G[1][cols] /= kmax[s]
    G = G[0] + S[:, None] * G[1] * S[None, :]
    G = comm.bcast(0.5 * (G + G.T), root=0)  # identical input: identical results
    return _null_motions(G, bodies, tol)


def _echelon(Z: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    """Reduced row echelon form of the rows of ``Z.T`` (a canonical basis of its span)."""
    A = Z.T.copy()
    k, n = A.shape
    r = 0
    for col in range(n):
        if r == k:
            break
        p = r + int(np.argmax(np.abs(A[r:, col])))
        if abs(A[p, col]) <= 1e-8:
            continue
        A[[r, p]] = A[[p, r]]
        A[r] /= A[r, col]
        for i in range(k):
            if i != r:
                A[i] -= A[i, col] * A[r]
        r += 1
    A[np.abs(A) < 1e-12 * np.abs(A).max(initial=0.0)] = 0.0
    return A


def _null_motions(
    G: npt.NDArray[np.floating], bodies: list[_Bodies], tol: float
) -> list[UnsupportedMotion]:
    # Columns -> (space, component); group the components coupled in G.
    owners = [(s, c) for s, b in enumerate(bodies) for c in range(b.count) for _ in range(b.modes)]
    keys = sorted(set(owners))
    index = {key: i for i, key in enumerate(keys)}
    column_body = np.array([index[o] for o in owners], dtype=np.int64)
    rows, cols = np.nonzero(G)
    coupling = scipy.sparse.coo_matrix(
        (np.ones(rows.size, dtype=np.int8), (column_body[rows], column_body[cols])),
        shape=(len(keys), len(keys)),
    )
    _, group = scipy.sparse.csgraph.connected_components(coupling, directed=False)
    motions = []
    for g in np.unique(group):
        columns = np.flatnonzero(group[column_body] == g)
        eigenvalues, vectors = scipy.linalg.eigh(G[np.ix_(columns, columns)])
        null = eigenvalues < tol * max(1.0, float(eigenvalues[-1]))
        if not null.any():
            continue
        for alpha in _echelon(vectors[:, null]):
            alpha = alpha / np.linalg.norm(alpha)
            stiffness = float(alpha @ G[np.ix_(columns, columns)] @ alpha)
            parts = []
            for key in sorted({owners[j] for j in columns}):
                s, c = key
                b = bodies[s]
                local = np.array([j for j in range(columns.size) if owners[columns[j]] == key])
                coeff = alpha[local]
                size = np.linalg.norm(coeff)
                if size <= 1e-8:
                    continue
                t = coeff[: b.bs].copy()
                w = coeff[b.bs :] / b.size[c]
                parts.append(
                    (
                        -size,
                        RigidMotion(
                            space=s,
                            component=c,
                            coefficients=coeff,
                            translation=t,
                            rotation=w,
                            centroid=b.centroid[c],
                            bounding_box=np.stack([b.lower[c], b.upper[c]]),
                            description=_describe(t, w, b.centroid[c], float(b.size[c])),
                        ),
                    )
                )
            parts.sort(key=lambda item: item[0])
            motions.append(UnsupportedMotion(tuple(m for _, m in parts), stiffness))
    return motions


# --------------------------------------------------------------------------------------
# Redundant constraints (Eqs. 34-35)
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Redundancy:
    """Rank deficiency of the active constraint rows of a pair (Eq. 35).

    Attributes:
        active: Number of active rows.
        zero: Active rows that vanish once the Dirichlet dofs are removed.
        dependent: Further rows linearly dependent on the others.
    """

    active: int
    zero: int
    dependent: int

    @property
    def redundant(self) -> int:
        """Rows to remove for full row rank: ``zero + dependent``."""
        return self.zero + self.dependent

    @property
    def rank(self) -> int:
        """Row rank of the active, Dirichlet-eliminated constraint matrix."""
        return self.active - self.redundant


def _masks(
    blocks: Sequence[PETSc.Mat], dirichlet_masks: Sequence[PETSc.Vec | None] | None
) -> list[PETSc.Vec | None]:
    if dirichlet_masks is None:
        return [None] * len(blocks)
    if len(dirichlet_masks) != len(blocks):
        raise ValueError("One Dirichlet mask per block is needed.")
    return list(dirichlet_masks)


def _scaled_gram(
    blocks: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None,
    inactive: npt.ArrayLike | None,
    tol: float,
) -> tuple[PETSc.Mat, npt.NDArray[np.bool_], npt.NDArray[np.bool_], int, int]:
    r"""Unit-row :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T`, the kept and zero rows."""
    if len(blocks) == 0:
        raise ValueError("A constraint needs at least one block.")
    comm = blocks[0].getComm().tompi4py()
    start, end = blocks[0].getOwnershipRange()
    for B in blocks:
        if B.getOwnershipRange() != (start, end):
            raise ValueError("All blocks of a constraint need the same row layout.")
    active = _owned_rows(blocks[0], inactive)
    n = end - start
    full = np.zeros(n)
    eliminated = np.zeros(n)
    scaled = []
    for B, mask in zip(blocks, _masks(blocks, dirichlet_masks), strict=True):
        indptr, _, data = B.getValuesCSR()
        rows = np.repeat(np.arange(n), np.diff(indptr))
        full += np.bincount(rows, weights=data * data, minlength=n)
        Bc = B.copy()
        if mask is not None:
            Bc.diagonalScale(R=mask)
        indptr, _, data = Bc.getValuesCSR()
        rows = np.repeat(np.arange(n), np.diff(indptr))
        eliminated += np.bincount(rows, weights=data * data, minlength=n)
        scaled.append(Bc)
    zero = active & (eliminated <= tol * full)
    kept = active & ~zero
    scale = blocks[0].createVecLeft()
    scale.array[:] = 0.0
    scale.array[kept] = 1.0 / np.sqrt(eliminated[kept])
    gram = None
    for Bc in scaled:
        Bc.diagonalScale(L=scale)
        P = Bc.matTransposeMult(Bc)
        if gram is None:
            gram = P
        else:
            gram.axpy(1.0, P, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            P.destroy()
        Bc.destroy()
    scale.destroy()
    assert gram is not None
    num_active = comm.allreduce(int(np.count_nonzero(active)))
    num_zero = comm.allreduce(int(np.count_nonzero(zero)))
    return gram, kept, zero, num_active, num_zero


def redundant_constraints(
    blocks: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None = None,
    inactive: npt.ArrayLike | None = None,
    *,
    tol: float = REDUNDANT_TOL,
) -> Redundancy:
    r"""Count the redundant rows of a pair's active constraint matrix (Eqs. 34-35).

    :math:`\tilde{\mathbf B} = [\mathbf B_1\mathbf D_1, \mathbf B_2\mathbf D_2, \dots]`
    with the inactive rows removed and the others scaled to unit length; the dependent
    rows are the eigenvalues of :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` below
    ``tol``, counted as the negative pivots of the MUMPS :math:`\mathbf L\mathbf D
    \mathbf L^T` factorization of :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T - \tau
    \mathbf I` (exact inertia: ``ICNTL(13) = 1``, no ScaLAPACK root). The columns of the
    blocks need not be concatenated: :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T =
    \sum_s \tilde{\mathbf B}_s\tilde{\mathbf B}_s^T`.

    Args:
        blocks: The pair's constraint blocks (AIJ, one per displacement space, the same
            row layout), not Dirichlet-eliminated.
        dirichlet_masks: Per block, 1 at free and 0 at Dirichlet columns (or ``None``).
        inactive: Global indices of the rows to ignore (each process may pass any
            subset; their union is used).
        tol: :math:`\tau`, see :data:`REDUNDANT_TOL`.

    Returns:
        The counts, the same on every process.
    """
    gram, kept, _, num_active, num_zero = _scaled_gram(blocks, dirichlet_masks, inactive, tol)
    comm = gram.getComm().tompi4py()
    if comm.allreduce(int(np.count_nonzero(kept))) == 0:
        gram.destroy()
        return Redundancy(num_active, num_zero, 0)
    shift = gram.createVecLeft()
    shift.array[:] = np.where(kept, -tol, 1.0)
    gram.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
    gram.setDiagonal(shift, addv=PETSc.InsertMode.ADD_VALUES)
    gram.assemble()
    gram.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    ksp = PETSc.KSP().create(comm)
    ksp.setOptionsPrefix("dolfinx_contact_s2s_redundancy_")
    ksp.setOperators(gram)
    ksp.setType(PETSc.KSP.Type.PREONLY)
    pc = ksp.getPC()
    pc.setType(PETSc.PC.Type.CHOLESKY)
    pc.setFactorSolverType("mumps")
    pc.setFactorSetUpSolverType()
    factor = pc.getFactorMatrix()
    factor.setMumpsIcntl(13, 1)  # no ScaLAPACK on the root node: exact inertia
    factor.setMumpsIcntl(24, 0)  # no null pivot detection: every pivot is counted
    pc.setUp()
    negative = int(comm.bcast(factor.getMumpsInfog(12), root=0))
    ksp.destroy()
    shift.destroy()
    gram.destroy()
    return Redundancy(num_active, num_zero, negative)


def _gather_dense(A: PETSc.Mat) -> npt.NDArray[np.floating]:
    start, _ = A.getOwnershipRange()
    indptr, indices, data = A.getValuesCSR()
    parts = A.getComm().tompi4py().allgather((start, indptr, indices, data))
    D = np.zeros(A.getSize())
    for first, ip, ind, val in parts:
        rows = first + np.repeat(np.arange(ip.size - 1), np.diff(ip))
        D[rows, ind] += val
    return D


def redundant_multipliers(
    blocks: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec | None] | None = None,
    inactive: npt.ArrayLike | None = None,
    *,
    tol: float = REDUNDANT_TOL,
    max_rows: int = 2000,
) -> list[npt.NDArray[np.int64]]:
    r"""Name the redundant multipliers of a small constraint matrix (Eqs. 34-35).

    Dense eigen-decomposition of the gathered unit-row
    :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` of :func:`redundant_constraints`: every
    null vector (left null vector of :math:`\tilde{\mathbf B}`) is a linear dependency
    between rows. The null space is given in reduced echelon form, so that independent
    dependencies (two duplicated rows in different places) come out separately.

    Args:
        blocks: As for :func:`redundant_constraints`.
        dirichlet_masks: As for :func:`redundant_constraints`.
        inactive: As for :func:`redundant_constraints`.
        tol: :math:`\tau`, see :data:`REDUNDANT_TOL`.
        max_rows: Refuse larger matrices (dense work grows as rows cubed).

    Returns:
        One array per redundant row: the global row (multiplier) indices involved in a
        dependency, the largest coefficient first, entries below :math:`10^{-6}` of the
        largest left out. Rows that vanish after the Dirichlet elimination come first,
        alone. Its length is :attr:`Redundancy.redundant`. The same on every process.
    """
    rows = blocks[0].getSize()[0]
    if rows > max_rows:
        raise ValueError(f"{rows} constraint rows: more than max_rows={max_rows}.")
    gram, kept, zero, _, _ = _scaled_gram(blocks, dirichlet_masks, inactive, tol)
    comm = gram.getComm().tompi4py()
    dense = _gather_dense(gram)
    gram.destroy()
    kept_all = np.concatenate(comm.allgather(kept))
    zero_all = np.concatenate(comm.allgather(zero))
    result: list[npt.NDArray[np.int64]] | None = None
    if comm.rank == 0:
        result = [np.array([i], dtype=np.int64) for i in np.flatnonzero(zero_all)]
        index = np.flatnonzero(kept_all)
        if index.size > 0:
            eigenvalues, vectors = scipy.linalg.eigh(dense[np.ix_(index, index)])
            null = eigenvalues < tol
            if null.any():
                for z in _echelon(vectors[:, null]):
                    big = np.abs(z) >= 1e-6 * np.abs(z).max()
                    order = np.argsort(-np.abs(z[big]), kind="stable")
                    result.append(index[big][order].astype(np.int64))
    return typing.cast(list, comm.bcast(result, root=0))

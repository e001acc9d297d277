# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Bodies: the connected components of a mesh and their rigid-body modes."""

from __future__ import annotations

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

from dolfinx_contact_s2s.checks.linalg import petsc_vector
from dolfinx_contact_s2s.compat import geometry_dofmap

__all__ = [
    "Bodies",
    "body_set",
    "connected_components",
    "near_nullspace",
    "orthonormal_nullspace",
    "rigid_body_modes",
]

_INT64_MAX = np.iinfo(np.int64).max


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
class Bodies:
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


def _reduce_by(
    labels: npt.NDArray[np.int32],
    values: npt.NDArray[np.floating],
    count: int,
    ufunc: np.ufunc,
    fill: float,
) -> npt.NDArray[np.floating]:
    """``ufunc`` over the rows of ``values`` of each label (``fill`` where none)."""
    out = np.full((count, values.shape[1]), fill)
    if labels.size == 0:
        return out
    order = np.argsort(labels, kind="stable")
    sorted_labels = labels[order]
    starts = np.flatnonzero(np.r_[True, sorted_labels[1:] != sorted_labels[:-1]])
    out[sorted_labels[starts]] = ufunc.reduceat(values[order], starts, axis=0)
    return out


def body_set(V: dolfinx.fem.FunctionSpace, labels: npt.NDArray[np.int32] | None) -> Bodies:
    """The bodies of ``V``: components, their nodes, centroids, sizes and boxes."""
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
    sums = np.column_stack(
        [np.bincount(owned, weights=x[:, k], minlength=count) for k in range(bs)]
    )
    centroid = comm.allreduce(sums) / np.maximum(counts, 1.0)[:, None]
    d2 = np.sum((x - centroid[owned]) ** 2, axis=1)
    size = np.sqrt(
        comm.allreduce(np.bincount(owned, weights=d2, minlength=count)) / np.maximum(counts, 1.0)
    )
    size[size <= 0.0] = 1.0
    lower = _reduce_by(owned, x, count, np.minimum, np.inf)
    upper = _reduce_by(owned, x, count, np.maximum, -np.inf)
    comm.Allreduce(MPI.IN_PLACE, lower, op=MPI.MIN)
    comm.Allreduce(MPI.IN_PLACE, upper, op=MPI.MAX)
    return Bodies(comm, bs, count, owned, x, centroid, size, counts, lower, upper)


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
    bodies = body_set(V, labels)
    values = bodies.values()
    dof_labels = np.repeat(bodies.labels, bodies.bs)
    modes = []
    for c in range(bodies.count):
        inside = dof_labels == c
        for j in range(bodies.modes):
            modes.append(petsc_vector(bodies.comm, np.where(inside, values[:, j], 0.0), bodies.bs))
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
    return orthonormal_nullspace(rigid_body_modes(V, labels), V.mesh.comm)


def orthonormal_nullspace(modes: list[PETSc.Vec], comm: MPI.Comm) -> PETSc.NullSpace:
    """The null space of ``modes`` orthonormalized by modified Gram-Schmidt (twice).

    The modes are destroyed. Raises ``RuntimeError`` if one lies in the span of the others.
    """
    for i, v in enumerate(modes):
        for _ in range(2):
            for u in modes[:i]:
                v.axpy(-u.dot(v), u)
        if v.normalize() <= 0.0:
            raise RuntimeError(f"Rigid mode {i} of the space is zero.")
    nullspace = PETSc.NullSpace().create(vectors=modes, comm=comm)
    for v in modes:
        v.destroy()
    return nullspace

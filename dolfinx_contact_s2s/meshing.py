# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Gmsh helpers for building contact scenes: a reader, a session, and the true boundary.

Gmsh builds the geometry on one rank; :func:`model_to_mesh` distributes it (as
``dolfinx.io.gmsh.model_to_mesh`` does since DOLFINx 0.10, ``gmshio`` before), and
refuses a model that mixes triangles and quadrilaterals with a clear error instead of
DOLFINx 0.9's MPI abort.

A refined mesh (:func:`dolfinx.mesh.refine`) puts its new boundary nodes on the chords of
the old facets: on a curved contact surface it converges to the polygon's answer.
:func:`snap_boundary` moves the nodes of tagged facets onto the true geometry with a
projection the user gives, :func:`gmsh_projection` is that projection for a live Gmsh
model (``gmsh.model.getClosestPoint`` on the entities of each physical group).
DOLFINx refines only linear geometry, whose chords misplace a curved contact surface by
:math:`h^2/(8R)` between the nodes: quadratic displacements see those kinks (a P2
multiplier's peak off by several percent), so :func:`curved_mesh` lifts a refined mesh to
a quadratic geometry with its midside nodes on the true geometry.
"""

from __future__ import annotations

import contextlib
import typing
from collections.abc import Iterator

from mpi4py import MPI

import basix.ufl
import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.compat import (
    blocked_sub_element,
    create_mesh_in_place,
    geometry_dofmap,
    gmsh_model_to_mesh,
)

__all__ = [
    "Projection",
    "curved_mesh",
    "gmsh_projection",
    "gmsh_session",
    "model_to_mesh",
    "snap_boundary",
]

#: ``project(tag, points) -> points``: the points ``(n, 3)`` of facets tagged ``tag`` moved
#: onto the true geometry, or ``None`` to leave that tag's nodes where they are. Called on
#: every process, for every tag value of the facet tags in the same order (it may be
#: collective).
Projection = typing.Callable[[int, npt.NDArray[np.floating]], npt.NDArray[np.floating] | None]


def model_to_mesh(
    model: typing.Any,
    comm: MPI.Comm,
    rank: int = 0,
    gdim: int = 2,
    *,
    partitioner: typing.Callable | None = None,
) -> tuple[dolfinx.mesh.Mesh, dolfinx.mesh.MeshTags, dolfinx.mesh.MeshTags]:
    """DOLFINx's Gmsh reader, whatever its version: ``(mesh, cell_tags, facet_tags)``.

    Args:
        model: The Gmsh model (``gmsh.model``), built on ``rank``.
        comm: Communicator to distribute the mesh over.
        rank: Rank that holds the model.
        gdim: Geometric dimension.
        partitioner: Cell partitioner of :func:`dolfinx.mesh.create_mesh`, called as
            ``partitioner(comm, nparts, cell_types, cells)`` on every process with the
            cells it holds (vertex indices into the model's nodes, Gmsh tag minus one);
            it returns each cell's destination rank as an adjacency list. None:
            DOLFINx's graph partitioner.
    """
    return gmsh_model_to_mesh(model, comm, rank, gdim, partitioner)


@contextlib.contextmanager
def gmsh_session() -> Iterator[typing.Any]:
    """A Gmsh session: initialized here unless the caller already did, quiet."""
    import gmsh

    started = not gmsh.isInitialized()
    if started:
        gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        yield gmsh
    finally:
        if started:
            gmsh.finalize()


def snap_boundary(
    mesh: dolfinx.mesh.Mesh, facet_tags: dolfinx.mesh.MeshTags, project: Projection
) -> int:
    """Move the geometry nodes of the tagged facets onto the true geometry (collective).

    Every node of a facet tagged ``tag`` goes to ``project(tag, x)``; a node on facets
    of two tags goes to the mean of its projections. A node is moved on every process
    that holds it, also where the tagged facet is another process's. Call it on a
    refined mesh before making its function spaces and contact surfaces.

    Args:
        mesh: A mesh with a linear coordinate element (what :func:`dolfinx.mesh.refine`
            makes).
        facet_tags: Its facet tags.
        project: The :data:`Projection` of the tags.

    Returns:
        The number of nodes moved (over all processes), by more than 1e-12 of the mesh size.

    Raises:
        NotImplementedError: On every process, for a curved (higher-order) geometry.
        ValueError: On every process, if ``project`` returns the wrong shape.
    """
    degree = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element()).degree
    if degree != 1:
        raise NotImplementedError(f"snap_boundary needs a linear geometry, not degree {degree}")
    comm, gdim, fdim = mesh.comm, mesh.geometry.dim, mesh.topology.dim - 1
    mesh.topology.create_connectivity(fdim, mesh.topology.dim)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (gdim,)))
    move = dolfinx.fem.Function(V)
    count = dolfinx.fem.Function(dolfinx.fem.functionspace(mesh, ("Lagrange", 1)))
    x = V.tabulate_dof_coordinates()
    bad = ""
    for tag in _tag_values(comm, facet_tags):
        dofs = dolfinx.fem.locate_dofs_topological(V, fdim, facet_tags.find(tag))
        target = project(tag, x[dofs].copy())
        if target is None:
            continue
        target = np.asarray(target, dtype=x.dtype)
        if target.shape != (dofs.size, 3):
            shape = f"shape {target.shape}, not ({dofs.size}, 3)"
            bad = bad or f"project({tag}, points) returned {shape}"
            continue
        move.x.array.reshape(-1, gdim)[dofs] += (target - x[dofs])[:, :gdim]
        count.x.array[dofs] += 1.0
    message = [m for m in comm.allgather(bad) if m]
    if message:
        raise ValueError(message[0])
    for f in (move, count):
        f.x.scatter_reverse(dolfinx.la.InsertMode.add)
    n = count.x.array[: count.function_space.dofmap.index_map.size_local]
    owned = move.x.array.reshape(-1, gdim)[: n.size]
    owned[n > 0] /= n[n > 0, None]
    size = max(float(np.ptp(mesh.geometry.x, axis=0).max()), 1e-300)
    moved = int(np.count_nonzero(np.linalg.norm(owned, axis=1) > 1e-12 * size))
    move.x.scatter_forward()
    # Linear geometry: the P1 dofs of a cell and its geometry nodes are the same points.
    cells = V.dofmap.list
    nodes = geometry_dofmap(mesh)[: cells.shape[0]]
    unique, first = np.unique(nodes.reshape(-1), return_index=True)
    mesh.geometry.x[unique, :gdim] += move.x.array.reshape(-1, gdim)[cells.reshape(-1)[first]]
    return comm.allreduce(moved)


def _tag_values(comm: MPI.Comm, tags: dolfinx.mesh.MeshTags) -> list[int]:
    """The tag values of every process, sorted (a projection is called for all, in order)."""
    return sorted({int(t) for part in comm.allgather(np.unique(tags.values)) for t in part})


def curved_mesh(
    mesh: dolfinx.mesh.Mesh,
    cell_tags: dolfinx.mesh.MeshTags,
    facet_tags: dolfinx.mesh.MeshTags,
    project: Projection | None = None,
) -> tuple[dolfinx.mesh.Mesh, dolfinx.mesh.MeshTags, dolfinx.mesh.MeshTags]:
    """The mesh with a quadratic geometry, its midside nodes on the true geometry (collective).

    The nodes of the new geometry are the dofs of a quadratic Lagrange space on ``mesh``;
    the midside nodes of the facets tagged ``tag`` (edges of triangles, faces of
    tetrahedra) go to ``project(tag, x)``, the others stay on the straight edges. Every
    cell stays on its process, and the tags are carried over (a facet by its cell and
    its local index). Use it on a refined, snapped mesh (:func:`snap_boundary`) before
    making quadratic spaces on a curved contact surface;
    :func:`~dolfinx_contact_s2s.unilateral.refine_contact_zone` does so with
    ``geometry_degree=2``.

    Args:
        mesh: A mesh of triangles or tetrahedra with a linear coordinate element (what
            :func:`dolfinx.mesh.refine` makes). The new mesh has no ghost cells; its
            cells are the 6- or 10-node cells of DOLFINx's (Basix's) node order,
            vertices then edges, as the dofs of the quadratic space.
        cell_tags: Its cell tags.
        facet_tags: Its facet tags.
        project: The :data:`Projection` of the facet tags (``None``: straight edges).

    Returns:
        The new mesh, its cell tags and its facet tags.

    Raises:
        NotImplementedError: On every process, for another mesh.
        ValueError: On every process, if ``project`` returns the wrong shape.
    """
    comm, tdim, gdim = mesh.comm, mesh.topology.dim, mesh.geometry.dim
    fdim, num_cells = tdim - 1, mesh.topology.index_map(mesh.topology.dim).size_local
    degree = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element()).degree
    cell = mesh.topology.cell_name()
    if cell not in ("triangle", "tetrahedron") or degree != 1:
        raise NotImplementedError(
            f"curved_mesh lifts triangle or tetrahedron meshes of linear geometry, not a "
            f"{mesh.topology.cell_name()} mesh of geometry degree {degree}"
        )
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2, (gdim,)))
    x = V.tabulate_dof_coordinates()
    for dim in (0, fdim):
        mesh.topology.create_connectivity(dim, tdim)
    mesh.topology.create_connectivity(fdim, 0)
    bad = ""
    for tag in _tag_values(comm, facet_tags) if project is not None else []:
        facets = facet_tags.find(tag)
        vertices = dolfinx.mesh.compute_incident_entities(mesh.topology, facets, fdim, 0)
        mid = np.setdiff1d(
            dolfinx.fem.locate_dofs_topological(V, fdim, facets),
            dolfinx.fem.locate_dofs_topological(V, 0, vertices),
        )
        assert project is not None
        moved = project(tag, x[mid].copy())
        if moved is None:
            continue
        moved = np.asarray(moved, dtype=x.dtype)
        if moved.shape != (mid.size, 3):
            bad = bad or f"project({tag}, points) returned shape {moved.shape}, not ({mid.size}, 3)"
            continue
        x[mid] = moved
    message = [m for m in comm.allgather(bad) if m]
    if message:
        raise ValueError(message[0])

    dofs = V.dofmap.index_map
    cells = dofs.local_to_global(V.dofmap.list[:num_cells].reshape(-1)).reshape(num_cells, -1)
    element = basix.ufl.element("Lagrange", cell, 2, shape=(gdim,))
    new, parent = create_mesh_in_place(
        comm, cells, np.ascontiguousarray(x[: dofs.size_local, :gdim]), ufl.Mesh(element)
    )

    values = np.full(num_cells + mesh.topology.index_map(tdim).num_ghosts, -1, dtype=np.int32)
    values[cell_tags.indices] = cell_tags.values
    tagged = np.flatnonzero(values[parent] >= 0).astype(np.int32)
    new_cell_tags = dolfinx.mesh.meshtags(new, tdim, tagged, values[parent][tagged])

    # A facet by one of its cells and its index there: DOLFINx keeps a cell's vertex order.
    child = np.empty(num_cells, dtype=np.int32)
    child[parent] = np.arange(parent.size, dtype=np.int32)
    mesh.topology.create_connectivity(tdim, fdim)
    new.topology.create_entities(fdim)
    new.topology.create_connectivity(tdim, fdim)
    new.topology.create_connectivity(fdim, tdim)
    f2c = mesh.topology.connectivity(fdim, tdim)
    c2f = mesh.topology.connectivity(tdim, fdim).array.reshape(-1, tdim + 1)
    new_c2f = new.topology.connectivity(tdim, fdim).array.reshape(-1, tdim + 1)
    # The lowest cell of a facet is an owned one where there is one (ghosts come last);
    # a facet of ghost cells only is tagged on the process that owns them.
    lowest = np.minimum.reduceat(f2c.array, f2c.offsets[:-1])
    c = lowest[facet_tags.indices]
    kept = c < num_cells
    f, c = facet_tags.indices[kept], c[kept]
    local = np.argmax(c2f[c] == f[:, None], axis=1)
    facets = new_c2f[child[c], local].astype(np.int32)
    facets, first = np.unique(facets, return_index=True)
    new_facet_tags = dolfinx.mesh.meshtags(new, fdim, facets, facet_tags.values[kept][first])
    return new, new_cell_tags, new_facet_tags


def gmsh_projection(comm: MPI.Comm, rank: int = 0, dim: int | None = None) -> Projection:
    """The :data:`Projection` onto the live Gmsh model of ``rank`` (its physical groups).

    The points of every process are sent to ``rank``, moved there to the closest point
    (``gmsh.model.getClosestPoint``) of the entities of the physical group ``tag`` of
    dimension ``dim``, and sent back. The model must still be open when the projection is
    called (keep the :func:`gmsh_session` around the refinement). A tag with no physical
    group is left alone.

    Args:
        comm: Communicator of the mesh.
        rank: Rank that holds the model.
        dim: Dimension of the facets' physical groups (default: the model's dimension
            minus one).
    """

    def project(tag: int, points: npt.NDArray[np.floating]) -> npt.NDArray[np.floating] | None:
        gathered = comm.gather(points, root=rank)
        out = None
        if comm.rank == rank:
            import gmsh

            d = gmsh.model.getDimension() - 1 if dim is None else dim
            entities = (
                list(gmsh.model.getEntitiesForPhysicalGroup(d, tag))
                if any(g == (d, tag) for g in gmsh.model.getPhysicalGroups(d))
                else []
            )
            if entities:
                assert gathered is not None
                allpoints = np.concatenate([p.reshape(-1, 3) for p in gathered])
                best = np.full(allpoints.shape, np.nan)
                dist = np.full(allpoints.shape[0], np.inf)
                for entity in entities:
                    if allpoints.size == 0:
                        break
                    closest = np.reshape(
                        gmsh.model.getClosestPoint(d, int(entity), allpoints.reshape(-1))[0],
                        (-1, 3),
                    )
                    r = np.linalg.norm(closest - allpoints, axis=1)
                    better = r < dist
                    best[better], dist[better] = closest[better], r[better]
                sizes = np.cumsum([0] + [p.shape[0] for p in gathered])
                out = [best[sizes[k] : sizes[k + 1]] for k in range(comm.size)]
        if not comm.bcast(out is not None, root=rank):
            return None
        return comm.scatter(out, root=rank)

    return project

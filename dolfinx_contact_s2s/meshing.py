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
"""

from __future__ import annotations

import contextlib
import typing
from collections.abc import Iterator

from mpi4py import MPI

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import blocked_sub_element, geometry_dofmap, gmsh_model_to_mesh

__all__ = ["Projection", "gmsh_projection", "gmsh_session", "model_to_mesh", "snap_boundary"]

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
    tags = sorted({int(t) for part in comm.allgather(np.unique(facet_tags.values)) for t in part})
    bad = ""
    for tag in tags:
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

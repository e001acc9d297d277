# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Differences between DOLFINx 0.9, 0.10 and 0.11, in one place (public: scenes use them too)."""

from __future__ import annotations

import math
import typing

import dolfinx
import numpy as np
import numpy.typing as npt

__all__ = [
    "DOLFINX_VERSION",
    "blocked_sub_element",
    "create_mesh_in_place",
    "create_petsc_vector",
    "geometry_dofmap",
    "gmsh_model_to_mesh",
    "refine_marked",
    "submesh_parent_entities",
    "tabulate",
]

DOLFINX_VERSION: tuple[int, int] = tuple(  # type: ignore[assignment]
    int(p) for p in dolfinx.__version__.split(".")[:2]
)


def gmsh_model_to_mesh(
    model: typing.Any,
    comm: typing.Any,
    rank: int,
    gdim: int,
    partitioner: typing.Callable | None = None,
) -> tuple:
    """Distribute a Gmsh model held on ``rank`` over ``comm``.

    Args:
        model: The Gmsh model (``gmsh.model``), built on ``rank``.
        comm: Communicator to distribute the mesh over.
        rank: Rank that holds the model.
        gdim: Geometric dimension.
        partitioner: Cell partitioner of :func:`dolfinx.mesh.create_mesh`, called as
            ``partitioner(comm, nparts, cell_types, cells)`` (None: DOLFINx's default).

    Returns:
        ``(mesh, cell_tags, facet_tags)``, whichever DOLFINx reader is present
        (``dolfinx.io.gmshio`` up to 0.9, ``dolfinx.io.gmsh`` from 0.10).

    Raises:
        ValueError: On every rank, if the physical groups of the cells mix cell types
            (DOLFINx 0.9's reader aborts MPI on such a model, 0.11's makes a mixed mesh).
    """
    mixed = _mixed_cell_types(model) if comm.rank == rank else ""
    mixed = comm.bcast(mixed, root=rank)
    if mixed:
        raise ValueError(
            f"the Gmsh model mixes {mixed} cells: one mesh needs one cell type; recombine "
            "every surface into quadrilaterals (gmsh.model.mesh.setRecombine) or none"
        )
    if DOLFINX_VERSION >= (0, 10):
        from dolfinx.io import gmsh as _gmsh

        data = _gmsh.model_to_mesh(model, comm, rank, gdim=gdim, partitioner=partitioner)
        return data.mesh, data.cell_tags, data.facet_tags
    from dolfinx.io import gmshio as _gmshio

    return _gmshio.model_to_mesh(model, comm, rank, gdim=gdim, partitioner=partitioner)


def _mixed_cell_types(model: typing.Any) -> str:
    """The names of the cell types of the model's highest physical groups, if several."""
    groups = model.getPhysicalGroups()
    if not groups:
        return ""
    dim = max(d for d, _ in groups)
    types: set[int] = set()
    for d, tag in groups:
        if d == dim:
            for entity in model.getEntitiesForPhysicalGroup(d, tag):
                types.update(int(t) for t in model.mesh.getElementTypes(d, int(entity)))
    if len(types) < 2:
        return ""
    names = sorted({model.mesh.getElementProperties(t)[0] for t in types})
    return " and ".join(f"'{name}'" for name in names)


def submesh_parent_entities(entity_map: typing.Any, num_cells: int) -> npt.NDArray[np.int32]:
    """Parent-mesh entity of each of the first ``num_cells`` submesh cells.

    Args:
        entity_map: Second value returned by :func:`dolfinx.mesh.create_submesh`
            (an array up to 0.9, an ``EntityMap`` from 0.10).
        num_cells: Number of submesh cells (owned and ghost) to map.
    """
    if isinstance(entity_map, np.ndarray):
        return entity_map[:num_cells].astype(np.int32)
    cells = np.arange(num_cells, dtype=np.int32)
    return np.asarray(entity_map.sub_topology_to_topology(cells, inverse=False), dtype=np.int32)


def blocked_sub_element(element: typing.Any) -> typing.Any:
    """Scalar Basix-UFL element of a (possibly blocked) Basix-UFL element."""
    if getattr(element, "block_size", 1) > 1 or hasattr(element, "sub_element"):
        sub = getattr(element, "sub_element", None)
        if sub is None:
            sub = element.sub_elements[0]
        return sub
    return element


def geometry_dofmap(mesh: typing.Any) -> npt.NDArray[np.int32]:
    """Geometry dofmap of a mesh with one coordinate element (``dofmaps[0]`` from 0.10)."""
    dofmaps = getattr(mesh.geometry, "dofmaps", None)
    if isinstance(dofmaps, list):
        return dofmaps[0]
    return mesh.geometry.dofmap


def refine_marked(
    mesh: typing.Any, edges: npt.NDArray[np.int32], tags: typing.Sequence[typing.Any] = ()
) -> tuple[typing.Any, list[typing.Any]]:
    """Split the given edges of a simplex mesh (collective) and carry tags over.

    :func:`dolfinx.mesh.refine` keeps every refined cell on its parent's process
    (``partitioner=None``, in 0.9 and 0.11 alike; 0.11's default would also rebuild a
    ghost layer that the parent maps do not cover). The parent cells and facets it
    returns map ``tags`` (cell or facet tags of ``mesh``) to the new mesh with
    :func:`dolfinx.mesh.transfer_meshtag`.

    Args:
        mesh: A mesh of triangles or tetrahedra with a linear coordinate element.
        edges: Process-local indices of the edges to split (DOLFINx adds the edges
            needed to keep the mesh conforming).
        tags: Mesh tags of ``mesh`` (of its cells or facets) to transfer.

    Returns:
        The refined mesh and the tags on it, in the order of ``tags``.
    """
    tdim = mesh.topology.dim
    mesh.topology.create_entities(1)
    option = dolfinx.mesh.RefinementOption.parent_cell_and_facet
    # No redistribution and no ghost cells (0.9's only way; from 0.10 the default rebuilds
    # a ghost layer, whose cells the parent map does not cover: transfer_meshtag fails).
    new, parent_cell, parent_facet = dolfinx.mesh.refine(
        mesh, edges, partitioner=None, option=option
    )
    out = []
    for tag in tags:
        new.topology.create_entities(tag.dim)
        if tag.dim == tdim - 1:
            new.topology.create_connectivity(tdim - 1, tdim)
        facet = parent_facet if tag.dim == tdim - 1 else None
        out.append(dolfinx.mesh.transfer_meshtag(tag, new, parent_cell, facet))
    return new, out


def _stay(comm: typing.Any, nparts: int, cell_types: typing.Any, cells: typing.Any) -> typing.Any:
    """Cell partitioner that keeps every cell on the process that gives it."""
    count = np.asarray(cells[0]).size // dolfinx.cpp.mesh.cell_num_vertices(cell_types[0])
    adj = dolfinx.graph.adjacencylist(np.full(count, comm.rank, dtype=np.int32))
    return getattr(adj, "_cpp_object", adj)  # a Python wrapper from DOLFINx 0.10


def create_mesh_in_place(
    comm: typing.Any, cells: npt.NDArray[np.int64], x: npt.NDArray[np.floating], domain: typing.Any
) -> tuple[typing.Any, npt.NDArray[np.int64]]:
    """:func:`dolfinx.mesh.create_mesh` with every cell kept on the process that gives it.

    Args:
        comm: Communicator.
        cells: Global node indices of this process's cells (DOLFINx's node order).
        x: Coordinates ``(n, gdim)`` of the nodes this process numbers (consecutive
            global indices, process by process).
        domain: The :class:`ufl.Mesh` of the coordinate element.

    Returns:
        The mesh, and for each of its cells the row of ``cells`` it was made from
        (DOLFINx reorders the cells of a process).
    """
    if DOLFINX_VERSION >= (0, 10):
        mesh = dolfinx.mesh.create_mesh(comm, cells, domain, x, _stay)
    else:
        mesh = dolfinx.mesh.create_mesh(comm, cells, x, domain, _stay)
    original = mesh.topology.original_cell_index
    original = np.asarray(original[0] if isinstance(original, list) else original, np.int64)
    offset = comm.exscan(cells.shape[0]) if comm.size > 1 else 0
    num = mesh.topology.index_map(mesh.topology.dim).size_local
    return mesh, original[:num] - (offset or 0)


def tabulate(element, derivatives: int, X: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    """Tabulate a scalar Basix-UFL element, also at zero points.

    Returns:
        Array ``(num_derivatives, num_points, num_dofs)``.
    """
    X = np.ascontiguousarray(X, dtype=np.float64)
    if X.shape[0] == 0:
        count = math.comb(derivatives + X.shape[1], derivatives)
        return np.zeros((count, 0, element.dim))
    return element.tabulate(derivatives, X)


def create_petsc_vector(V: dolfinx.fem.FunctionSpace) -> typing.Any:
    """A ghosted PETSc vector of ``V`` (the API moved in DOLFINx 0.10; needs petsc4py)."""
    if DOLFINX_VERSION >= (0, 10):
        from dolfinx.fem import petsc

        return petsc.create_vector(V)
    return dolfinx.la.create_petsc_vector(V.dofmap.index_map, V.dofmap.index_map_bs)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Gmsh helpers for building contact scenes: DOLFINx's reader whatever its version, a session.

Gmsh builds the geometry on one rank; :func:`model_to_mesh` distributes it (as
``dolfinx.io.gmsh.model_to_mesh`` does since DOLFINx 0.10, ``gmshio`` before), and
refuses a model that mixes triangles and quadrilaterals with a clear error instead of
DOLFINx 0.9's MPI abort.
"""

from __future__ import annotations

import contextlib
import typing
from collections.abc import Iterator

from mpi4py import MPI

import dolfinx

from dolfinx_contact_s2s.compat import gmsh_model_to_mesh

__all__ = ["gmsh_session", "model_to_mesh"]


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

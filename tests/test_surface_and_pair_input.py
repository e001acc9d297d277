# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Bad input raises a clear Python exception on every rank."""

import types

from mpi4py import MPI

import basix.ufl
import dolfinx
import dolfinx.graph
import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from paper.scenes import BOTTOM, TOP, patch_test


@pytest.fixture(scope="module")
def scene():
    return patch_test(MPI.COMM_WORLD, (4, 3))


def _space(body, degree=1):
    return dolfinx.fem.functionspace(body.mesh, ("Lagrange", degree, (2,)))


def test_missing_tag(scene):
    with pytest.raises(ValueError, match="no facet of the mesh carries contact tag 42"):
        contact_surface(_space(scene.upper), scene.upper.facet_tags, 42)


def test_empty_tag(scene):
    mesh = scene.upper.mesh
    empty = dolfinx.mesh.meshtags(mesh, 1, [], [])
    with pytest.raises(ValueError, match="no facet of the mesh carries contact tag 1"):
        contact_surface(_space(scene.upper), empty, 1)


def test_cell_tags_are_not_facet_tags(scene):
    with pytest.raises(ValueError, match="must mark facets"):
        contact_surface(_space(scene.upper), scene.upper.cell_tags, 1)


def test_scalar_space(scene):
    V = dolfinx.fem.functionspace(scene.upper.mesh, ("Lagrange", 1))
    with pytest.raises(ValueError, match="vector-valued"):
        contact_surface(V, scene.upper.facet_tags, BOTTOM)


def test_contactor_equal_to_target(scene):
    V = _space(scene.upper)
    s = contact_surface(V, scene.upper.facet_tags, BOTTOM)
    with pytest.raises(ValueError, match="must differ from its target"):
        contact_pair(s, s)
    with pytest.raises(ValueError, match="must differ from its target"):
        contact_pair(s, contact_surface(V, scene.upper.facet_tags, BOTTOM))


def test_surfaces_not_facing(scene):
    # Both top surfaces have upward normals: they can never touch.
    upper_top = contact_surface(_space(scene.upper), scene.upper.facet_tags, TOP)
    lower_top = contact_surface(_space(scene.lower), scene.lower.facet_tags, TOP)
    with pytest.raises(ValueError, match="never face each other"):
        assemble_coupling(contact_pair(upper_top, lower_top))


def test_surfaces_out_of_reach(scene):
    upper = contact_surface(_space(scene.upper), scene.upper.facet_tags, BOTTOM)
    lower = contact_surface(_space(scene.lower), scene.lower.facet_tags, TOP)
    far = patch_test(MPI.COMM_WORLD, (4, 3), gap=5.0)
    far_upper = contact_surface(_space(far.upper), far.upper.facet_tags, BOTTOM)
    assemble_coupling(contact_pair(upper, lower))  # in reach: fine
    with pytest.raises(ValueError, match="never face each other"):
        assemble_coupling(contact_pair(far_upper, lower))


def _halves_mesh(comm, n=4):
    """Unit square of n x n quadrilaterals, cells below y = 1/2 on rank 0, the rest on rank 1.

    No ghost cells: on two ranks the interior line y = 1/2 is the partition boundary.
    """
    if comm.rank == 0:
        xs = np.linspace(0.0, 1.0, n + 1)
        X, Y = np.meshgrid(xs, xs)
        x = np.stack([X.ravel(), Y.ravel()], axis=1)
        v = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)  # v[j, i] at (x_i, y_j)
        cells = np.stack(
            [v[:-1, :-1].ravel(), v[:-1, 1:].ravel(), v[1:, :-1].ravel(), v[1:, 1:].ravel()],
            axis=1,
        ).astype(np.int64)
    else:
        x, cells = np.empty((0, 2)), np.empty((0, 4), dtype=np.int64)

    def partitioner(comm, nparts, *args):
        # The cells arrive on rank 0 in the order above: row by row from y = 0.
        local = np.asarray(args[-1][0]).size // 4
        dest = np.where(np.arange(local) < n * n // 2, 0, 1) % nparts
        adj = dolfinx.graph.adjacencylist(dest.astype(np.int32))
        return getattr(adj, "_cpp_object", adj)  # a Python wrapper from DOLFINx 0.10

    e = basix.ufl.element("Lagrange", "quadrilateral", 1, shape=(2,))
    return dolfinx.mesh.create_mesh(comm, cells=cells, x=x, e=e, partitioner=partitioner)


def test_interior_facets_rejected_on_every_partition():
    """A tagged interior line is rejected, also where it is the partition boundary.

    On two ranks without ghost cells every tagged facet has a single local cell, so
    counting local cells (the former check) would have taken the line for boundary.
    """
    comm = MPI.COMM_WORLD
    mesh = _halves_mesh(comm)
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)
    facets = dolfinx.mesh.locate_entities(mesh, tdim - 1, lambda x: np.isclose(x[1], 0.5))
    tags = dolfinx.mesh.meshtags(mesh, tdim - 1, facets, np.full(facets.size, 5, dtype=np.int32))
    f_to_c = mesh.topology.connectivity(tdim - 1, tdim)
    links = f_to_c.offsets[facets + 1] - f_to_c.offsets[facets]
    if comm.size == 2:
        assert comm.allreduce(facets.size) > 0 and np.all(links == 1)
    with pytest.raises(ValueError, match="must be on the boundary"):
        contact_surface(_space(scene_like(mesh)), tags, 5)


def scene_like(mesh):
    """A stand-in body holding only a mesh (for :func:`_space`)."""
    return types.SimpleNamespace(mesh=mesh)


def test_mesh_moved_after_the_surfaces_were_created():
    """A user shifts a body after creating its surface: a clear error, not the old geometry."""
    scene = patch_test(MPI.COMM_WORLD, (4, 3))
    V_upper, V_lower = _space(scene.upper), _space(scene.lower)
    upper = contact_surface(V_upper, scene.upper.facet_tags, BOTTOM)
    lower = contact_surface(V_lower, scene.lower.facet_tags, TOP)
    assemble_coupling(contact_pair(upper, lower)).destroy()
    assert not upper.moved() and not lower.moved()

    scene.upper.mesh.geometry.x[:, 0] += 0.01  # every rank moves its nodes
    assert upper.moved() and not lower.moved()
    with pytest.raises(ValueError, match="moved after the surface was created"):
        assemble_coupling(contact_pair(upper, lower))

    # Surfaces created after the move see the new geometry: the contactor's facets start
    # 0.01 further right, as the node coordinates do.
    moved = contact_surface(V_upper, scene.upper.facet_tags, BOTTOM)
    op = assemble_coupling(contact_pair(moved, lower))
    shift = moved.data.coords[:, :, 0] - upper.data.coords[:, :, 0]
    assert np.allclose(shift, 0.01, rtol=0, atol=1e-15)
    op.destroy()

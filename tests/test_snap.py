# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Refined boundary nodes moved onto the true geometry: an analytic projection and Gmsh's.

A disk of radius 1 meshed by Gmsh and refined everywhere: the new boundary nodes lie on
chords (inside the circle) until snap_boundary moves them onto it. The geometry must be
the same on every process: the area DOLFINx integrates over the cells of each process
equals the area of the polygon of the gathered boundary nodes.
"""

import math

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import gmsh_projection, gmsh_session, model_to_mesh, snap_boundary
from dolfinx_contact_s2s.compat import refine_marked

CIRCLE = 7


def _refined_disk(gmsh):
    gmsh.model.add("disk")
    if MPI.COMM_WORLD.rank == 0:
        disk = gmsh.model.occ.addDisk(0, 0, 0, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(2, [disk], 1)
        curves = [c for _, c in gmsh.model.getBoundary([(2, disk)], oriented=False)]
        gmsh.model.addPhysicalGroup(1, curves, CIRCLE)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
        gmsh.model.mesh.generate(2)
    mesh, ctags, ftags = model_to_mesh(gmsh.model, MPI.COMM_WORLD, 0)
    mesh.topology.create_entities(1)
    edges = np.arange(mesh.topology.index_map(1).size_local, dtype=np.int32)
    fine, (_, ftags) = refine_marked(mesh, edges, (ctags, ftags))
    return fine, ftags


def _boundary_radii(mesh, ftags):
    mesh.topology.create_connectivity(1, 2)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    dofs = dolfinx.fem.locate_dofs_topological(V, 1, ftags.find(CIRCLE))
    owned = dofs[dofs < V.dofmap.index_map.size_local]
    x = V.tabulate_dof_coordinates()[owned, :2]
    points = np.concatenate(mesh.comm.allgather(x))
    return np.linalg.norm(points, axis=1), points


def _area_matches_polygon(mesh, points):
    area = mesh.comm.allreduce(
        dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * ufl.dx(domain=mesh)))
    )
    p = points[np.argsort(np.arctan2(points[:, 1], points[:, 0]))]
    polygon = 0.5 * abs(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))
    assert area == pytest.approx(polygon, rel=1e-12)
    assert area == pytest.approx(math.pi, rel=0.01)


def _circle(tag, points):
    if tag != CIRCLE:
        return None
    return points / np.linalg.norm(points, axis=1)[:, None]


@pytest.mark.parametrize("projection", ["analytic", "gmsh"])
def test_refined_nodes_on_the_circle(projection):
    with gmsh_session() as gmsh:
        mesh, ftags = _refined_disk(gmsh)
        radii, _ = _boundary_radii(mesh, ftags)
        assert radii.min() < 1 - 1e-3  # the refinement's nodes lie on chords
        project = _circle if projection == "analytic" else gmsh_projection(mesh.comm)
        moved = snap_boundary(mesh, ftags, project)
    radii, points = _boundary_radii(mesh, ftags)
    assert moved > 0
    tol = 1e-12 if projection == "analytic" else 1e-7  # Gmsh's closest point: its own tolerance
    assert np.max(np.abs(radii - 1.0)) < tol
    _area_matches_polygon(mesh, points)


def test_bad_projection():
    mesh = dolfinx.mesh.create_unit_square(MPI.COMM_WORLD, 2, 2)
    facets = dolfinx.mesh.locate_entities_boundary(mesh, 1, lambda x: np.isclose(x[0], 0))
    tags = dolfinx.mesh.meshtags(mesh, 1, np.sort(facets), np.full(facets.size, 3, np.int32))
    with pytest.raises(ValueError, match="shape"):
        snap_boundary(mesh, tags, lambda tag, x: x[:, :2])

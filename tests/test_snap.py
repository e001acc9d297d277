# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Refined boundary nodes moved onto the true geometry: an analytic projection and Gmsh's.

A disk of radius 1 meshed by Gmsh and refined everywhere: the new boundary nodes lie on
chords (inside the circle) until snap_boundary moves them onto it. The geometry must be
the same on every process: the area DOLFINx integrates over the cells of each process
equals the area of the polygon of the gathered boundary nodes. Lifted to a quadratic
geometry (curved_mesh), each boundary edge is the parabola through its ends and the
arc's midpoint: the area adds a parabolic segment, 2/3 chord x sagitta, per edge.
"""

import math

from mpi4py import MPI

import basix
import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import (
    curved_mesh,
    gmsh_projection,
    gmsh_session,
    model_to_mesh,
    snap_boundary,
)
from dolfinx_contact_s2s.compat import geometry_dofmap, refine_marked

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
    fine, (ctags, ftags) = refine_marked(mesh, edges, (ctags, ftags))
    return fine, ctags, ftags


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
        mesh, _, ftags = _refined_disk(gmsh)
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


def _integral(mesh, measure):
    one = dolfinx.fem.Constant(mesh, 1.0)
    return mesh.comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(one * measure)))


def test_curved_mesh_puts_its_edges_on_the_circle():
    """The area of the lifted disk: the polygon plus a parabolic segment on every edge."""
    with gmsh_session() as gmsh:
        mesh, ctags, ftags = _refined_disk(gmsh)
    snap_boundary(mesh, ftags, _circle)
    curved, new_ctags, new_ftags = curved_mesh(mesh, ctags, ftags, _circle)
    _, points = _boundary_radii(mesh, ftags)
    theta = np.sort(np.arctan2(points[:, 1], points[:, 0]))
    half = 0.5 * np.diff(np.append(theta, theta[0] + 2 * math.pi))
    polygon = 0.5 * np.sum(np.sin(2 * half))
    parabolas = np.sum(2 / 3 * (2 * np.sin(half)) * (1 - np.cos(half)))
    dx = ufl.Measure("dx", domain=curved, subdomain_data=new_ctags)
    ds = ufl.Measure("ds", domain=curved, subdomain_data=new_ftags)
    assert _integral(curved, dx(1)) == pytest.approx(polygon + parabolas, rel=1e-12)
    assert _integral(curved, dx) == pytest.approx(polygon + parabolas, rel=1e-12)
    # The tags carried over: the whole boundary, closer to 2 pi than the chords' length.
    chords = _integral(mesh, ufl.Measure("ds", domain=mesh, subdomain_data=ftags)(CIRCLE))
    arcs = _integral(curved, ds(CIRCLE))
    assert chords == pytest.approx(np.sum(2 * np.sin(half)), rel=1e-12)
    assert abs(arcs - 2 * math.pi) < 1e-3 * abs(chords - 2 * math.pi)
    for old, new in ((ctags, new_ctags), (ftags, new_ftags)):
        count = [mesh.comm.allreduce(t.indices.size) for t in (old, new)]
        assert count[0] == count[1] > 0


def test_curved_mesh_of_a_mesh_with_ghosts_and_bad_input():
    """A unit square with ghost cells (DOLFINx's default) lifts to the same square and tags."""
    quads = dolfinx.mesh.create_unit_square(
        MPI.COMM_WORLD, 2, 2, dolfinx.mesh.CellType.quadrilateral
    )
    mesh = dolfinx.mesh.create_unit_square(MPI.COMM_WORLD, 2, 2)
    tags = []
    for m in (quads, mesh):
        facets = dolfinx.mesh.locate_entities_boundary(m, 1, lambda x: np.isclose(x[0], 0))
        cells = np.arange(m.topology.index_map(2).size_local, dtype=np.int32)
        tags.append(
            (
                dolfinx.mesh.meshtags(m, 2, cells, np.ones(cells.size, np.int32)),
                dolfinx.mesh.meshtags(m, 1, np.sort(facets), np.full(facets.size, 3, np.int32)),
            )
        )
    square, cell_tags, facet_tags = curved_mesh(mesh, *tags[1])
    ds = ufl.Measure("ds", domain=square, subdomain_data=facet_tags)
    dx = ufl.Measure("dx", domain=square, subdomain_data=cell_tags)
    assert _integral(square, ds(3)) == pytest.approx(1.0, rel=1e-14)
    assert _integral(square, dx(1)) == pytest.approx(1.0, rel=1e-14)
    with pytest.raises(NotImplementedError, match="triangle or tetrahedron"):
        curved_mesh(quads, *tags[0])
    with pytest.raises(ValueError, match="shape"):
        curved_mesh(mesh, *tags[1], lambda tag, x: x[:, :2])


def _sphere(tag, x):
    return x / np.linalg.norm(x, axis=1)[:, None] if tag == CIRCLE else None


def test_curved_mesh_of_tetrahedra_puts_its_faces_on_the_sphere():
    """A refined, snapped ball lifted to 10-node tetrahedra: node order and volume.

    Every edge node of a cell sits at the midpoint of the edge that Basix's reference
    tetrahedron names for it (DOLFINx's node order), or on the sphere above it for an
    edge of the boundary; the volume is much closer to 4 pi / 3 than the chords'.
    """
    with gmsh_session() as gmsh:
        gmsh.model.add("ball")
        if MPI.COMM_WORLD.rank == 0:
            ball = gmsh.model.occ.addSphere(0, 0, 0, 1)
            gmsh.model.occ.synchronize()
            gmsh.model.addPhysicalGroup(3, [ball], 1)
            faces = [f for _, f in gmsh.model.getBoundary([(3, ball)], oriented=False)]
            gmsh.model.addPhysicalGroup(2, faces, CIRCLE)
            gmsh.option.setNumber("Mesh.MeshSizeMax", 0.6)
            gmsh.model.mesh.generate(3)
        mesh, ctags, ftags = model_to_mesh(gmsh.model, MPI.COMM_WORLD, 0, gdim=3)
    mesh.topology.create_entities(1)
    edges = np.arange(mesh.topology.index_map(1).size_local, dtype=np.int32)
    mesh, (ctags, ftags) = refine_marked(mesh, edges, (ctags, ftags))
    snap_boundary(mesh, ftags, _sphere)
    curved, new_ctags, new_ftags = curved_mesh(mesh, ctags, ftags, _sphere)
    assert curved.topology.cell_name() == "tetrahedron"
    nodes = curved.geometry.x[geometry_dofmap(curved)]
    assert nodes.shape[1] == 10
    ends = np.array(basix.topology(basix.CellType.tetrahedron)[1])
    mid = 0.5 * (nodes[:, ends[:, 0]] + nodes[:, ends[:, 1]])
    edge_nodes = nodes[:, 4:]
    on_sphere = np.isclose(np.linalg.norm(edge_nodes, axis=2), 1.0, atol=1e-12)
    straight = np.linalg.norm(edge_nodes - mid, axis=2) < 1e-13
    assert np.all(straight | on_sphere)
    lifted = on_sphere & ~straight
    assert MPI.COMM_WORLD.allreduce(int(lifted.sum())) > 0
    # A lifted node lies right above its chord's midpoint (the radial projection).
    above = mid[lifted] / np.linalg.norm(mid[lifted], axis=1)[:, None]
    assert np.allclose(edge_nodes[lifted], above, atol=1e-12)
    volume = {m: _integral(m, ufl.dx(domain=m)) for m in (mesh, curved)}
    exact = 4 * math.pi / 3
    assert abs(volume[curved] - exact) < 0.05 * abs(volume[mesh] - exact)
    ds = ufl.Measure("ds", domain=curved, subdomain_data=new_ftags)
    assert abs(_integral(curved, ds(CIRCLE)) - 4 * math.pi) < 0.05 * abs(
        _integral(mesh, ufl.Measure("ds", domain=mesh, subdomain_data=ftags)(CIRCLE)) - 4 * math.pi
    )
    for old, new in ((ctags, new_ctags), (ftags, new_ftags)):
        count = [mesh.comm.allreduce(t.indices.size) for t in (old, new)]
        assert count[0] == count[1] > 0

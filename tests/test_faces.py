# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Contact surfaces of 3D DOLFINx meshes: face nodes, boxes and polygonal pieces (issue 21).

Expected numbers come from outside the module: DOLFINx's own cell geometry map
(``cmap.push_forward``), the known outward normals of a box's sides, and closed-form
areas and integrals of P1/Q1 basis functions on flat faces.
"""

from mpi4py import MPI

import basix
import dolfinx
import numpy as np
import pytest

from dolfinx_contact_s2s import contact_surface
from dolfinx_contact_s2s.compat import geometry_dofmap, gmsh_model_to_mesh
from dolfinx_contact_s2s.kernels import polygon
from dolfinx_contact_s2s.search import box_pairs
from dolfinx_contact_s2s.segmentation import PolygonSegmentation
from dolfinx_contact_s2s.surface import ContactSurface, SurfaceData

COMM = MPI.COMM_WORLD
EPS = np.finfo(np.float64).eps
CELLS = {
    "tetrahedron": dolfinx.mesh.CellType.tetrahedron,
    "hexahedron": dolfinx.mesh.CellType.hexahedron,
}


class Faces:
    """The faces of a contact surface (its own rows or all gathered), by this test's names."""

    def __init__(self, surface: ContactSurface, data: SurfaceData):
        self.surface, self.data = surface, data
        self.nodes = data.coefficients
        self.local_facet, self.dofs, self.orientation = (
            data.local_facet,
            data.dofs,
            data.orientation,
        )
        self.cells = surface.cells

    def __len__(self):
        return len(self.data)

    def boxes(self):
        return self.surface.bounding_boxes(self.data)

    def gathered(self):
        return Faces(self.surface, self.surface.gather())


def face_data(V, tags, tag):
    surface = contact_surface(V, tags, tag)
    return Faces(surface, surface.data)


def gmsh_box(cell: str, order: int, n: int = 2):
    """The unit cube meshed by Gmsh with geometry of degree ``order``; boundary tag 1."""
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        if COMM.rank == 0:
            gmsh.model.add("box")
            gmsh.model.occ.addBox(0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
            gmsh.model.occ.synchronize()
            volumes = [v[1] for v in gmsh.model.getEntities(3)]
            surfaces = [s[1] for s in gmsh.model.getEntities(2)]
            gmsh.model.addPhysicalGroup(3, volumes, 1)
            gmsh.model.addPhysicalGroup(2, surfaces, 1)
            if cell == "hexahedron":
                for _, c in gmsh.model.getEntities(1):
                    gmsh.model.mesh.setTransfiniteCurve(c, n + 1)
                for s in surfaces:
                    gmsh.model.mesh.setTransfiniteSurface(s)
                    gmsh.model.mesh.setRecombine(2, s)
                for v in volumes:
                    gmsh.model.mesh.setTransfiniteVolume(v)
            else:
                gmsh.option.setNumber("Mesh.MeshSizeMax", 1.0 / n)
            gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
            gmsh.model.mesh.generate(3)
            gmsh.model.mesh.setOrder(order)
        mesh, _, facet_tags = gmsh_model_to_mesh(gmsh.model, COMM, 0, gdim=3)
    finally:
        gmsh.finalize()
    return mesh, facet_tags


def boundary_tags(mesh, marker=lambda x: np.full(x.shape[1], True), tag=1):
    mesh.topology.create_entities(2)
    facets = dolfinx.mesh.locate_entities_boundary(mesh, 2, marker)
    return dolfinx.mesh.meshtags(mesh, 2, facets, np.full(facets.size, tag, dtype=np.int32))


def perturb(mesh):
    """Move every geometry node by a smooth nonlinear map (curves the faces of P2 meshes)."""
    x = mesh.geometry.x
    X, Y, Z = x[:, 0].copy(), x[:, 1].copy(), x[:, 2].copy()
    x[:, 0] += 0.05 * np.sin(2.0 * Y + Z)
    x[:, 1] += 0.05 * np.sin(1.5 * Z + X * X)
    x[:, 2] += 0.05 * np.cos(X + 2.0 * Y)


def unit_box(cell, geometry_degree):
    if geometry_degree == 1:
        mesh = dolfinx.mesh.create_unit_cube(COMM, 2, 2, 2, CELLS[cell])
        return mesh, boundary_tags(mesh)
    return gmsh_box(cell, 2)


def reference_face_points(num_nodes, rng, count):
    face, _ = polygon.FACE_ELEMENTS[num_nodes]
    s = rng.uniform(0.0, 1.0, (count, 2))
    if face == "triangle":
        s[s.sum(axis=1) > 1.0] = 1.0 - s[s.sum(axis=1) > 1.0][:, ::-1]
    return s


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("geometry_degree", [1, 2])
@pytest.mark.parametrize("cell", ["tetrahedron", "hexahedron"])
def test_node_order_matches_cell_geometry_map(cell, geometry_degree, degree):
    """The face map of ``nodes`` is DOLFINx's cell map on the facet, at random points."""
    mesh, tags = unit_box(cell, geometry_degree)
    perturb(mesh)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
    data = face_data(V, tags, 1)
    K = {("tetrahedron", 1): 3, ("hexahedron", 1): 4, ("tetrahedron", 2): 6}
    assert data.nodes.shape[1:] == (K.get((cell, geometry_degree), 9), 3)
    assert data.dofs.dtype == np.int64 and data.dofs.shape[1] == V.dofmap.list.shape[1] * 3
    rng = np.random.default_rng(3)
    topology = basix.topology(basix.CellType[cell])[2]
    ref = basix.geometry(basix.CellType[cell])
    dofmap = geometry_dofmap(mesh)
    # DOLFINx's coordinate map (``cmaps[0]`` from 0.10, ``cmap`` before).
    cmap = mesh.geometry.cmaps[0] if hasattr(mesh.geometry, "cmaps") else mesh.geometry.cmap
    worst = 0.0
    for row in range(len(data)):
        s = reference_face_points(data.nodes.shape[1], rng, 5)
        v = ref[topology[data.local_facet[row]]]
        X = v[0] + s[:, :1] * (v[1] - v[0]) + s[:, 1:] * (v[2] - v[0])
        cell_x = mesh.geometry.x[dofmap[data.cells[row]]]
        expected = cmap.push_forward(X, cell_x)
        x, _ = polygon.evaluate(data.nodes, np.full(5, row, dtype=np.int32), s)
        worst = max(worst, float(np.max(np.abs(x - expected))))
    assert COMM.allreduce(worst, op=MPI.MAX) <= 1e-13
    # The faces are curved (or warped) for real: the check is not of a flat map.
    if geometry_degree == 2:
        mid = data.nodes[:, 3:6] if cell == "tetrahedron" else data.nodes[:, 4:8]
        assert np.max(np.abs(mid), initial=1.0) > 0.0


@pytest.mark.parametrize("cell", ["tetrahedron", "hexahedron"])
def test_orientation_is_outward_on_every_side(cell):
    mesh = dolfinx.mesh.create_unit_cube(COMM, 2, 3, 2, CELLS[cell])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    sides = {
        1: (0, 0.0, [-1, 0, 0]),
        2: (0, 1.0, [1, 0, 0]),
        3: (1, 0.0, [0, -1, 0]),
        4: (1, 1.0, [0, 1, 0]),
        5: (2, 0.0, [0, 0, -1]),
        6: (2, 1.0, [0, 0, 1]),
    }
    for tag, (axis, value, normal) in sides.items():
        tags = boundary_tags(mesh, lambda x, a=axis, v=value: np.isclose(x[a], v), tag)
        data = face_data(V, tags, tag)
        centre = np.full((len(data), 2), 1.0 / 3.0 if data.nodes.shape[1] == 3 else 0.5)
        _, dx = polygon.evaluate(data.nodes, np.arange(len(data), dtype=np.int32), centre)
        n = np.cross(dx[:, :, 0], dx[:, :, 1]) * data.orientation[:, None]
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        assert np.max(np.abs(n - normal), initial=0.0) <= 4 * EPS


def blocks(lower: str, upper: str, n1: int, n2: int, degree: int):
    """Lower block [0,1]^2 x [0,1] (top tag 2), upper [0,1]^2 x [1,2] (bottom tag 1)."""
    lo = dolfinx.mesh.create_box(COMM, [[0, 0, 0], [1, 1, 1]], [n1, n1, 2], CELLS[lower])
    up = dolfinx.mesh.create_box(COMM, [[0, 0, 1], [1, 1, 2]], [n2, n2, 2], CELLS[upper])
    V_lo = dolfinx.fem.functionspace(lo, ("Lagrange", degree, (3,)))
    V_up = dolfinx.fem.functionspace(up, ("Lagrange", degree, (3,)))
    top = boundary_tags(lo, lambda x: np.isclose(x[2], 1.0), 2)
    bottom = boundary_tags(up, lambda x: np.isclose(x[2], 1.0), 1)
    return face_data(V_up, bottom, 1), face_data(V_lo, top, 2)


def p1_basis(num_nodes, s):
    """P1/Q1 basis of a face at reference points (the corner nodes' functions)."""
    face, _ = polygon.FACE_ELEMENTS[num_nodes]
    element = basix.create_element(basix.ElementFamily.P, basix.CellType[face], 1)
    return element.tabulate(0, s)[0, :, :, 0]


def flat_area(nodes):
    """Area of flat faces from their corners (triangle: half the cross product)."""
    if nodes.shape[1] == 3:
        return 0.5 * np.linalg.norm(
            np.cross(nodes[:, 1] - nodes[:, 0], nodes[:, 2] - nodes[:, 0]), axis=1
        )
    return np.linalg.norm(np.cross(nodes[:, 1] - nodes[:, 0], nodes[:, 2] - nodes[:, 0]), axis=1)


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize(
    "lower, upper", [("tetrahedron", "hexahedron"), ("hexahedron", "tetrahedron")]
)
def test_two_blocks_patch_identity(lower, upper, degree):
    """Area and the 3D patch-test identity of Eq. (36) on non-matching flat faces."""
    C, local_target = blocks(lower, upper, 3, 4, degree)
    T = local_target.gathered()
    assert len(T) == COMM.allreduce(len(local_target))
    seg = PolygonSegmentation()
    radius = 0.1
    ic, it = box_pairs(seg.sweep(C.data, C.boxes(), radius), T.boxes())
    pieces = seg.cut(C.data, T.data, ic, it, radius)
    X, W = basix.make_quadrature(basix.CellType.triangle, 4)
    xi, w = seg.points(C.data, pieces, (X, W))
    area = COMM.allreduce(float(w.sum()))
    assert abs(area - 1.0) <= 1e-13

    S, Q = w.shape
    rows_c = np.repeat(pieces.contactor, Q)
    x_c, dx = polygon.evaluate(C.nodes, rows_c, xi.reshape(-1, 2))
    normals = np.cross(dx[:, :, 0], dx[:, :, 1]) * C.orientation[rows_c, None]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    eta, gap = polygon.intersect(T.nodes, np.repeat(pieces.target, Q), x_c, normals)
    assert np.max(np.abs(gap), initial=0.0) <= 1e-14
    phi = p1_basis(C.nodes.shape[1], xi.reshape(-1, 2)).reshape(S, Q, -1)
    psi = p1_basis(T.nodes.shape[1], eta).reshape(S, Q, -1)
    M = np.einsum("sq,sqi,sqj->sij", w, phi, psi)
    rows = np.zeros((len(C), phi.shape[2]))
    np.add.at(rows, pieces.contactor, M.sum(axis=2))
    cols = np.zeros((len(T), psi.shape[2]))
    np.add.at(cols, pieces.target, M.sum(axis=1))
    cols = COMM.allreduce(cols)
    # Closed forms: a P1/Q1 basis function of a flat triangle/parallelogram integrates
    # to a third/quarter of its area; every face is covered by the other surface.
    share = {3: 3.0, 4: 4.0}
    rows_expected = flat_area(C.nodes)[:, None] / share[C.nodes.shape[1]]
    cols_expected = flat_area(T.nodes)[:, None] / share[T.nodes.shape[1]]
    assert np.max(np.abs(rows - rows_expected), initial=0.0) <= 1e-13
    assert np.max(np.abs(cols - cols_expected), initial=0.0) <= 1e-13


@pytest.mark.parametrize("cell", ["tetrahedron", "hexahedron"])
def test_boxes_contain_curved_faces(cell):
    mesh, tags = gmsh_box(cell, 2)
    perturb(mesh)
    data = face_data(dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,))), tags, 1)
    boxes = data.boxes()
    radius = 0.07
    swept = PolygonSegmentation().sweep(data.data, boxes, radius)
    rng = np.random.default_rng(5)
    count = 50
    rows = np.repeat(np.arange(len(data), dtype=np.int32), count)
    s = reference_face_points(data.nodes.shape[1], rng, rows.size)
    x, dx = polygon.evaluate(data.nodes, rows, s)
    n = np.cross(dx[:, :, 0], dx[:, :, 1])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    tol = 1e-14
    assert np.all((boxes[rows, 0] - tol <= x) & (x <= boxes[rows, 1] + tol))
    for t in (-radius, radius):
        y = x + t * n
        assert np.all((swept[rows, 0] - tol <= y) & (y <= swept[rows, 1] + tol))


def test_missing_tag_raises():
    mesh = dolfinx.mesh.create_unit_cube(COMM, 2, 2, 2, CELLS["tetrahedron"])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    with pytest.raises(ValueError, match="no facet of the mesh carries contact tag 7"):
        face_data(V, boundary_tags(mesh), 7)


def test_wrong_space_raises():
    mesh = dolfinx.mesh.create_unit_cube(COMM, 2, 2, 2, CELLS["tetrahedron"])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    with pytest.raises(ValueError, match="one component per dimension"):
        face_data(V, boundary_tags(mesh), 1)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 3, (3,)))
    with pytest.raises(ValueError, match="degree 1 or 2"):
        face_data(V, boundary_tags(mesh), 1)


def test_interior_facet_and_nan_node_raise():
    mesh = dolfinx.mesh.create_unit_cube(COMM, 2, 2, 2, CELLS["hexahedron"])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    mesh.topology.create_entities(2)
    middle = dolfinx.mesh.locate_entities(mesh, 2, lambda x: np.isclose(x[2], 0.5))
    tags = dolfinx.mesh.meshtags(mesh, 2, middle, np.full(middle.size, 4, dtype=np.int32))
    with pytest.raises(ValueError, match="must be on the boundary"):
        face_data(V, tags, 4)
    tags = boundary_tags(mesh)
    mesh.geometry.x[0, 0] = np.nan
    with pytest.raises(ValueError, match="NaN or infinite"):
        face_data(V, tags, 1)


def test_zero_area_face_raises_on_every_rank():
    # One hexahedron (on one rank only when run on two): its top corners moved onto the
    # line y = 0, z = 1, so the top face has no area.
    mesh = dolfinx.mesh.create_unit_cube(COMM, 1, 1, 1, CELLS["hexahedron"])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    tags = boundary_tags(mesh, lambda x: np.isclose(x[2], 1.0), 6)
    x = mesh.geometry.x
    top = np.isclose(x[:, 2], 1.0) & np.isclose(x[:, 1], 1.0)
    x[top, 1] = 0.0
    x[top, 0] = 0.5 * x[top, 0] + 0.25
    with pytest.raises(ValueError, match="zero area"):
        face_data(V, tags, 6)


def gmsh_two_blocks(order: int):
    """One Gmsh model of two touching, independently meshed tetrahedral blocks.

    Lower [0,1]^2 x [0,1] (size 1/3, top tag 2), upper [0,1]^2 x [1,2] (size 1/4,
    bottom tag 1); the boxes are not fragmented, so the meshes do not match at z = 1.
    """
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        if COMM.rank == 0:
            gmsh.model.add("blocks")
            lower = gmsh.model.occ.addBox(0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
            upper = gmsh.model.occ.addBox(0.0, 0.0, 1.0, 1.0, 1.0, 1.0)
            gmsh.model.occ.synchronize()
            gmsh.model.addPhysicalGroup(3, [lower], 1)
            gmsh.model.addPhysicalGroup(3, [upper], 2)
            for volume, z, tag, size in ((lower, 1.0, 2, 1.0 / 3.0), (upper, 1.0, 1, 0.25)):
                _, surfaces = gmsh.model.getAdjacencies(3, volume)
                face = [
                    s for s in surfaces if np.isclose(gmsh.model.occ.getCenterOfMass(2, s)[2], z)
                ]
                gmsh.model.addPhysicalGroup(2, face, tag)
                points = gmsh.model.getBoundary([(3, volume)], recursive=True)
                gmsh.model.mesh.setSize(points, size)
            gmsh.model.mesh.generate(3)
            gmsh.model.mesh.setOrder(order)
        mesh, _, facet_tags = gmsh_model_to_mesh(gmsh.model, COMM, 0, gdim=3)
    finally:
        gmsh.finalize()
    return mesh, facet_tags


@pytest.mark.parametrize("order", [1, 2])
def test_gmsh_two_bodies_patch_identity(order):
    """Area and Eq. (36)'s row and column sums on a Gmsh two-body model (P1, P2 geometry)."""
    mesh, tags = gmsh_two_blocks(order)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", order, (3,)))
    C = face_data(V, tags, 1)
    T = face_data(V, tags, 2).gathered()
    assert C.nodes.shape[1] == T.nodes.shape[1] == (3 if order == 1 else 6)
    seg = PolygonSegmentation()
    radius = 0.1
    ic, it = box_pairs(seg.sweep(C.data, C.boxes(), radius), T.boxes())
    pieces = seg.cut(C.data, T.data, ic, it, radius)
    X, W = basix.make_quadrature(basix.CellType.triangle, 2)
    xi, w = seg.points(C.data, pieces, (X, W))
    assert abs(COMM.allreduce(float(w.sum())) - 1.0) <= 1e-13
    S, Q = w.shape
    rows_c = np.repeat(pieces.contactor, Q)
    x_c, dx = polygon.evaluate(C.nodes, rows_c, xi.reshape(-1, 2))
    normals = np.cross(dx[:, :, 0], dx[:, :, 1]) * C.orientation[rows_c, None]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    eta, _ = polygon.intersect(T.nodes, np.repeat(pieces.target, Q), x_c, normals)
    # The corner (vertex) functions of the flat faces: P1 on the corner nodes.
    phi = p1_basis(3, xi.reshape(-1, 2)).reshape(S, Q, 3)
    psi = p1_basis(3, eta).reshape(S, Q, 3)
    M = np.einsum("sq,sqi,sqj->sij", w, phi, psi)
    rows = np.zeros((len(C), 3))
    np.add.at(rows, pieces.contactor, M.sum(axis=2))
    cols = np.zeros((len(T), 3))
    np.add.at(cols, pieces.target, M.sum(axis=1))
    cols = COMM.allreduce(cols)
    assert np.max(np.abs(rows - flat_area(C.nodes[:, :3])[:, None] / 3.0), initial=0.0) <= 1e-13
    assert np.max(np.abs(cols - flat_area(T.nodes[:, :3])[:, None] / 3.0), initial=0.0) <= 1e-13


@pytest.mark.parametrize("lower, upper", [("hexahedron", "tetrahedron")])
def test_points_agree_with_overlap_rule(lower, upper):
    """PolygonSegmentation.points and kernels.polygon.overlap_rule give one rule."""
    C, local_target = blocks(lower, upper, 3, 4, 1)
    T = local_target.gathered()
    seg = PolygonSegmentation()
    ic, it = box_pairs(seg.sweep(C.data, C.boxes(), 0.1), T.boxes())
    pieces = seg.cut(C.data, T.data, ic, it, 0.1)
    xi, w = seg.points(C.data, pieces, basix.make_quadrature(basix.CellType.triangle, 3))
    rule = polygon.overlap_rule(C.nodes, C.orientation, T.nodes, T.orientation, ic, it, 3)
    assert np.array_equal(pieces.contactor, rule.contactor)
    assert np.array_equal(pieces.target, rule.target)
    assert np.max(np.abs(xi - rule.xi), initial=0.0) <= 1e-14
    assert np.max(np.abs(w - rule.surface_weights), initial=0.0) <= 1e-15


def test_no_faces_and_no_facing_pairs_give_no_pieces():
    """A process without contactor faces, and a pair facing the same way, cut to nothing."""
    seg = PolygonSegmentation()
    rule = basix.make_quadrature(basix.CellType.triangle, 2)
    none = np.zeros(0, dtype=np.int32)
    empty = SurfaceData(
        np.zeros((0, 4, 3)), none, np.zeros((0, 12), np.int64), none, np.zeros((0, 3, 3)), none
    )
    ic, it = none, none
    pieces = seg.cut(empty, empty, ic, it, 0.1)
    assert len(pieces) == 0 and seg.points(empty, pieces, rule)[0].shape == (0, 3, 2)
    one = np.zeros(1, dtype=np.int32)
    nodes = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    face = SurfaceData(nodes, one, np.zeros((1, 12), np.int64), one, nodes, np.ones(1))
    assert len(seg.cut(face, face, one, one, 0.1)) == 0

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Faces of 3D meshes as arrays, their candidate search and their polygonal pieces.

The composite quadrature of section 5 integrates the contact term of Eq. (40) on pieces
of the contactor facets bounded by the nodes of both surfaces (Fig. 15(b)); the target
side of each point is the point met along the contactor normal (Eq. 38). On the faces
of tetrahedra and hexahedra the pieces are polygons, computed on arrays by
:mod:`dolfinx_contact_s2s.kernels.polygon`. This module gives it its input from a
DOLFINx mesh, and the candidate search in 3D:

- :func:`face_data`: the owned tagged exterior facets of a 3D mesh as
  :class:`FaceData`: each face's geometry nodes in the order of Basix's Lagrange element
  on the face (:data:`~dolfinx_contact_s2s.kernels.polygon.FACE_ELEMENTS`), the sign
  turning :math:`\partial_1 x \times \partial_2 x` outward, and the displacement dofs of
  its cell; :func:`gather_faces` collects them from every process.
- :func:`face_boxes` and :func:`swept_face_boxes`: boxes containing the (curved) faces,
  and the region a face moved along its normal by the search radius covers.
- :class:`PolygonSegmentation`: the :class:`~dolfinx_contact_s2s.segmentation.Segmentation`
  of facets of dimension 2: pieces are the triangles of the clipped overlaps, and
  :meth:`PolygonSegmentation.points` places a triangle rule on them with the weights
  :math:`w^i` of Eq. (40). It is not registered in
  :data:`~dolfinx_contact_s2s.segmentation.SEGMENTATIONS` yet: the pair and its kernels
  are 2D.
"""

from __future__ import annotations

import math
import typing
from dataclasses import dataclass

from mpi4py import MPI

import basix
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import blocked_sub_element, geometry_dofmap
from dolfinx_contact_s2s.kernels import polygon
from dolfinx_contact_s2s.surface import DEGENERATE_TOLERANCE, tabulate

__all__ = [
    "FaceData",
    "PolygonPieces",
    "PolygonSegmentation",
    "face_boxes",
    "face_data",
    "face_node_order",
    "gather_faces",
    "swept_face_boxes",
]

_Array = npt.NDArray[np.float64]
_Rows = npt.NDArray[np.int32]

# Reference points of the face centres: the triangle's centroid, the square's centre.
_CENTRE = {"triangle": (1.0 / 3.0, 1.0 / 3.0), "quadrilateral": (0.5, 0.5)}


@dataclass(frozen=True)
class FaceData:
    r"""Per-face arrays of the tagged faces of a 3D body (one row per face).

    Attributes:
        nodes: Geometry nodes of each face in the order of Basix's Lagrange element on
            the face (3: P1 triangle, 4: Q1 quadrilateral, 6: P2, 9: Q2), ``(F, K, 3)``.
        local_facet: Local index of the face in its cell, ``(F,)``.
        cells: Process-local cell of each face (``-1`` for gathered rows), ``(F,)``.
        facets: Process-local facet index (``-1`` for gathered rows), ``(F,)``.
        dofs: Global (unrolled) displacement dofs of the face's cell,
            ``(F, num_cell_dofs * 3)``.
        orientation: ``+1`` where :math:`\partial_1 x \times \partial_2 x` of the face
            map points out of the cell, else ``-1``, ``(F,)``.
    """

    nodes: _Array
    local_facet: _Rows
    cells: _Rows
    facets: _Rows
    dofs: npt.NDArray[np.int64]
    orientation: _Array

    def __len__(self) -> int:
        """Number of faces."""
        return self.local_facet.shape[0]


def _face_element(face: str, degree: int) -> basix.finite_element.FiniteElement:
    """Basix's Lagrange element on a face (the one kernels.polygon evaluates)."""
    return basix.create_element(
        basix.ElementFamily.P, basix.CellType[face], degree, basix.LagrangeVariant.gll_warped
    )


def _facet_map(cell: basix.CellType, facet: int) -> tuple[_Array, _Array]:
    """``(X0, A)``: the affine map :math:`X = X_0 + A s` of the reference face on a facet."""
    v = basix.geometry(cell)[basix.topology(cell)[2][facet]]
    return v[0], np.stack([v[1] - v[0], v[2] - v[0]], axis=1)


def face_node_order(element: typing.Any) -> npt.NDArray[np.int32]:
    r"""Which cell nodes are each facet's face-element nodes, in the face element's order.

    Face-element node :math:`k` of local facet :math:`i` is cell node ``order[i, k]``:
    the face's vertices in the order of the facet's reference vertices
    (:func:`basix.topology`), then (degree 2) one midside node per edge of the face in
    the face cell's edge order, then (Q2) the face's interior node. The order is then
    verified: at points :math:`s` of the reference face, the cell basis at
    :math:`X_i(s)` must be the face basis on the picked nodes and zero on all others,
    i.e. the cell's geometry map restricted to the facet is the face element's map.

    Args:
        element: Scalar Basix-UFL Lagrange element of a tetrahedron or hexahedron, of
            degree 1 or 2 (the coordinate element).

    Returns:
        ``order``, ``(num_facets, K)``.

    Raises:
        RuntimeError: If the derived order fails the check (a Basix layout change).
    """
    cell = element.cell_type
    degree = element.degree
    topology = basix.topology(cell)
    edges = {frozenset(e): j for j, e in enumerate(topology[1])}
    entity_dofs = element.entity_dofs
    rows = []
    for i, vertices in enumerate(topology[2]):
        face = "triangle" if len(vertices) == 3 else "quadrilateral"
        order = [entity_dofs[0][v][0] for v in vertices]
        if degree == 2:
            for a, b in basix.topology(basix.CellType[face])[1]:
                order.append(entity_dofs[1][edges[frozenset((vertices[a], vertices[b]))]][0])
            order.extend(entity_dofs[2][i])
        rows.append(order)
    order_array = np.asarray(rows, dtype=np.int32)
    # The check: at random reference points s of the face, phi_cell(X(s)) = phi_face(s)
    # on the picked nodes and 0 elsewhere.
    rng = np.random.default_rng(7)
    s = rng.uniform(0.0, 0.5, (7, 2))
    for i, vertices in enumerate(topology[2]):
        face = "triangle" if len(vertices) == 3 else "quadrilateral"
        phi_face = _face_element(face, degree).tabulate(0, s)[0, :, :, 0]
        X0, A = _facet_map(cell, i)
        phi_cell = tabulate(element, 0, X0 + s @ A.T)[0]
        expected = np.zeros_like(phi_cell)
        expected[:, order_array[i]] = phi_face
        if not np.allclose(phi_cell, expected, rtol=0.0, atol=1e-13):
            raise RuntimeError(
                f"the face-node order of facet {i} of the {cell.name} element of degree "
                f"{degree} does not reproduce its geometry map: Basix's layout changed"
            )
    return order_array


def face_data(
    V: dolfinx.fem.FunctionSpace, facet_tags: dolfinx.mesh.MeshTags, tag: int
) -> FaceData:
    r"""The owned facets marked ``tag`` of a 3D mesh as :class:`FaceData` (collective).

    The nodes of facet :math:`i` of a cell are its geometry nodes on that facet
    (:func:`face_node_order`). The orientation compares the cell's outward normal
    :math:`J^{-T} \hat n_i` (Eq. 38's :math:`n_C` up to length) with
    :math:`\partial_1 x \times \partial_2 x` of the face map at the face centre.

    Args:
        V: Vector Lagrange space of degree 1 or 2, ``("Lagrange", k, (3,))``, on a mesh
            of tetrahedra or hexahedra with a coordinate element of degree 1 or 2.
        facet_tags: Facet markers (dimension 2) of the mesh of ``V``.
        tag: Marker of the faces; they must lie on the boundary.

    Returns:
        This process's owned tagged faces.

    Raises:
        ValueError: On every rank, with the same message: the mesh is not a 3D mesh of
            tetrahedra or hexahedra, ``V`` is not such a space, ``facet_tags`` are not
            facet tags of the mesh of ``V``, no process holds a facet marked ``tag``, a
            tagged facet is not on the boundary, or a face has a NaN or infinite node or
            zero area.
    """
    mesh = V.mesh
    comm = mesh.comm
    tdim = mesh.topology.dim
    cell_name = mesh.topology.cell_name()
    if tdim != 3 or mesh.geometry.dim != 3 or cell_name not in ("tetrahedron", "hexahedron"):
        raise ValueError(
            f"face_data needs a 3D mesh of tetrahedra or hexahedra, not {cell_name} (tdim "
            f"{tdim}, gdim {mesh.geometry.dim}); for 2D meshes use contact_surface"
        )
    if facet_tags.dim != 2:
        raise ValueError(f"facet_tags must mark facets (dimension 2), not {facet_tags.dim}")
    same = getattr(facet_tags.topology, "_cpp_object", facet_tags.topology) is getattr(
        mesh.topology, "_cpp_object", mesh.topology
    )
    if not comm.allreduce(same, op=MPI.LAND):
        raise ValueError("facet_tags belong to another mesh than V's")
    element = V.ufl_element()
    scalar = blocked_sub_element(element)
    if element.block_size != 3 or scalar.degree not in (1, 2) or scalar.discontinuous:
        raise ValueError(
            "V must be a continuous vector Lagrange space of degree 1 or 2, shape (3,)"
        )
    cmap = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element())
    if cmap.degree not in (1, 2):
        raise ValueError(f"the mesh's geometry must be of degree 1 or 2, not {cmap.degree}")

    num_owned = mesh.topology.index_map(2).size_local
    marked = facet_tags.indices[facet_tags.values == tag]
    facets = np.sort(marked[marked < num_owned]).astype(np.int32)
    if comm.allreduce(facets.size, op=MPI.SUM) == 0:
        raise ValueError(f"no facet of the mesh carries tag {tag}")
    mesh.topology.create_connectivity(2, 3)
    mesh.topology.create_connectivity(3, 2)
    exterior = dolfinx.mesh.exterior_facet_indices(mesh.topology)
    inside = np.count_nonzero(~np.isin(facets, exterior, assume_unique=True))
    if comm.allreduce(int(inside), op=MPI.SUM):
        raise ValueError(f"faces must be on the boundary: facets marked {tag} are not")
    f_to_c = mesh.topology.connectivity(2, 3)
    c_to_f = mesh.topology.connectivity(3, 2)
    cells = f_to_c.array[f_to_c.offsets[facets]].astype(np.int32)
    cell_type = basix.CellType[cell_name]
    per_cell = len(basix.topology(cell_type)[2])
    cell_facets = c_to_f.array.reshape(-1, per_cell)[cells]
    local_facet = np.argmax(cell_facets == facets[:, None], axis=1).astype(np.int32)

    x_dofs = geometry_dofmap(mesh)[cells]
    order = face_node_order(cmap)
    coords = mesh.geometry.x[x_dofs]
    nodes = np.take_along_axis(x_dofs, order[local_facet], axis=1)
    nodes = mesh.geometry.x[nodes][:, :, :3].copy()

    bs = V.dofmap.index_map_bs
    blocks = V.dofmap.list[cells]
    global_blocks = V.dofmap.index_map.local_to_global(blocks.reshape(-1)).reshape(blocks.shape)
    dofs = (global_blocks[:, :, None] * bs + np.arange(bs)[None, None, :]).reshape(
        cells.size, blocks.shape[1] * bs
    )

    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        orientation, ok = _orientation(cmap, coords, local_facet, nodes)
        finite = np.all(np.isfinite(nodes), axis=(1, 2)) & np.all(np.isfinite(coords), axis=(1, 2))
        flat = finite & ~(ok & _corner_area_ok(nodes))
    bad = comm.allreduce(np.array([np.count_nonzero(~finite), np.count_nonzero(flat)]))
    if bad[0]:
        raise ValueError(
            f"faces marked {tag}: the cells of {bad[0]} face(s) have a node with NaN or "
            "infinite coordinates; check mesh.geometry.x"
        )
    if bad[1]:
        where = nodes[flat, 0][:1]
        first = next(w for w in comm.allgather(where) if w.size)[0]
        raise ValueError(
            f"faces marked {tag}: {bad[1]} face(s) have zero area (corner nodes coincide or "
            f"lie on one line), the first at ({first[0]:.6g}, {first[1]:.6g}, "
            f"{first[2]:.6g}): they have no normal"
        )
    return FaceData(nodes, local_facet, cells, facets, dofs.astype(np.int64), orientation)


def _orientation(
    cmap: typing.Any, coords: _Array, local_facet: _Rows, nodes: _Array
) -> tuple[_Array, npt.NDArray[np.bool_]]:
    r"""Signs of :math:`J^{-T}\hat n \cdot (\partial_1 x \times \partial_2 x)` at face centres.

    Returns:
        ``(orientation, ok)``: the signs, and whether both normals are finite and nonzero.
    """
    cell = cmap.cell_type
    num_facets = len(basix.topology(cell)[2])
    face = "triangle" if nodes.shape[1] in (3, 6) else "quadrilateral"
    centre = np.array([_CENTRE[face]])
    maps = [_facet_map(cell, i) for i in range(num_facets)]
    X = np.concatenate([X0 + centre @ A.T for X0, A in maps])
    dphi = tabulate(cmap, 1, X)[1:4]  # (3, num_facets, num_cell_nodes)
    J = np.einsum("dfk,fkg->fgd", dphi[:, local_facet], coords[:, :, :3])
    n_ref = np.asarray(basix.cell.facet_outward_normals(cell))[local_facet]
    # J^{-T} = [j1 x j2, j2 x j0, j0 x j1] / det J (columns j_d = dx/dX_d): only the
    # direction counts, so no solve (and no LinAlgError on a collapsed cell).
    j0, j1, j2 = J[:, :, 0], J[:, :, 1], J[:, :, 2]
    cof = np.stack([np.cross(j1, j2), np.cross(j2, j0), np.cross(j0, j1)], axis=2)
    det = np.einsum("fg,fg->f", j0, cof[:, :, 0])
    n = np.sign(det)[:, None] * np.einsum("fgd,fd->fg", cof, n_ref)
    rows = np.arange(nodes.shape[0], dtype=np.int32)
    _, dx = polygon.evaluate(nodes, rows, np.repeat(centre, rows.size, axis=0))
    area = np.cross(dx[:, :, 0], dx[:, :, 1])
    dot = np.einsum("fg,fg->f", n, area)
    ok = np.isfinite(dot) & (np.abs(dot) > 0.0) & (np.abs(det) > 0.0)
    return np.where(dot < 0.0, -1.0, 1.0), ok


def _corner_area_ok(nodes: _Array) -> npt.NDArray[np.bool_]:
    """Whether the corner polygon of each face spans an area (relative to its size)."""
    corners = nodes[:, [0, 1, 2] if nodes.shape[1] in (3, 6) else [0, 1, 3, 2]]
    rel = corners - corners.mean(axis=1, keepdims=True)
    area = 0.5 * np.linalg.norm(np.cross(rel, np.roll(rel, -1, axis=1)).sum(axis=1), axis=1)
    size = np.max(np.linalg.norm(rel, axis=2), axis=1)
    return area > DEGENERATE_TOLERANCE * size**2


def gather_faces(data: FaceData, comm: MPI.Comm) -> FaceData:
    """All rows of ``data`` from every process, rank by rank, on every process (collective).

    ``cells`` and ``facets`` are process-local, so they are ``-1`` in the result.
    """
    parts = comm.allgather(data)
    count = sum(len(p) for p in parts)
    return FaceData(
        np.concatenate([p.nodes for p in parts]),
        np.concatenate([p.local_facet for p in parts]),
        np.full(count, -1, dtype=np.int32),
        np.full(count, -1, dtype=np.int32),
        np.concatenate([p.dofs for p in parts]),
        np.concatenate([p.orientation for p in parts]),
    )


def _bernstein(face: str, degree: int, s: _Array) -> _Array:
    """Bernstein polynomials of a face at points ``s``, ``(P, (degree+1)...)`` in any order."""
    if face == "triangle":
        lam = np.stack([1.0 - s[:, 0] - s[:, 1], s[:, 0], s[:, 1]], axis=1)
        powers = [(i, j, degree - i - j) for i in range(degree + 1) for j in range(degree + 1 - i)]
        return np.stack(
            [
                math.factorial(degree)
                / (math.factorial(a) * math.factorial(b) * math.factorial(c))
                * lam[:, 0] ** a
                * lam[:, 1] ** b
                * lam[:, 2] ** c
                for a, b, c in powers
            ],
            axis=1,
        )
    one = [math.comb(degree, i) * s**i * (1.0 - s) ** (degree - i) for i in range(degree + 1)]
    return np.stack([u[:, 0] * v[:, 1] for u in one for v in one], axis=1)


def face_boxes(data: FaceData, pad: float = 0.0) -> _Array:
    r"""Axis-aligned boxes ``(F, 2, 3)`` that contain the faces, grown by ``pad``.

    A P1 or Q1 face lies in the convex hull of its corner nodes (a bilinear quadrilateral
    is a convex combination of its corners). A P2 or Q2 face does not lie in the hull of
    its nodes: it bulges beyond a midside node. It lies in the hull of its *Bernstein
    control points* (the Bernstein polynomials are nonnegative and sum to one), which
    this box contains. On an edge with ends :math:`a, b` and midside node :math:`m` the
    control point is :math:`m + d`, :math:`d = m - (a + b)/2` the deviation of the
    midside node from the chord: the box of the nodes padded by the deviation of the
    midside nodes from the corners' chords (for Q2, its interior control point adds
    the deviation of the centre node from the bilinear face of the edge nodes). The
    box is therefore safe without sampling, and exact for flat faces.

    Args:
        data: The faces.
        pad: Absolute amount added on every side (round-off, or a search radius).

    Returns:
        Lower and upper corners of each face's box.
    """
    F, K, _ = data.nodes.shape
    face, degree = polygon.FACE_ELEMENTS[K]
    if F == 0:
        return np.zeros((0, 2, 3))
    control = data.nodes
    if degree == 2:
        points = _face_element(face, degree).points
        control = np.einsum("jk,fkg->fjg", np.linalg.inv(_bernstein(face, degree, points)), control)
    return np.stack([control.min(axis=1) - pad, control.max(axis=1) + pad], axis=1)


def swept_face_boxes(data: FaceData, boxes: _Array, radius: float) -> _Array:
    r"""Boxes of the faces moved by up to ``radius`` along their normals (either way).

    A point :math:`x` of a face moved to :math:`x \pm t n`, :math:`0 \le t \le r`,
    :math:`|n| = 1`, stays within :math:`r` of :math:`x` in every coordinate: growing
    every side of a box that contains the face by ``radius`` contains the swept region,
    for curved and warped faces alike. It is the simplest safe choice; a flat face's
    prism would need only :math:`r |n_g|` along axis :math:`g`.

    Args:
        data: The faces (only their number is used).
        boxes: Boxes ``(F, 2, 3)`` containing the faces (:func:`face_boxes`).
        radius: The search radius.

    Returns:
        New boxes ``(F, 2, 3)``.
    """
    if boxes.shape[0] != len(data):
        raise ValueError(f"{boxes.shape[0]} boxes for {len(data)} faces")
    out = boxes.copy()
    out[:, 0] -= radius
    out[:, 1] += radius
    return out


@dataclass(frozen=True)
class PolygonPieces:
    r"""Triangles of the overlaps of contactor and target faces (Fig. 15(b) in 3D).

    The :class:`~dolfinx_contact_s2s.segmentation.Pieces` of :class:`PolygonSegmentation`.
    Piece ``s`` is a triangle of the contactor face's plane (origin and frame of
    :func:`~dolfinx_contact_s2s.kernels.polygon.project_faces`) inside the overlap of the
    contactor face ``contactor[s]`` with the target face ``target[s]``.

    Attributes:
        contactor: Row of each piece's contactor face, ``(S,)``.
        target: Row of each piece's target face in the target data, ``(S,)``.
        triangles: Vertices in plane coordinates, counter-clockwise, ``(S, 3, 2)``.
        origin: Origin of each piece's plane, ``(S, 3)``.
        frame: Rows :math:`e_1, e_2, n` of each piece's plane, ``(S, 3, 3)``.
        gap: :math:`(x_T - x_C) \cdot n_C` at the triangle's centroid (Eq. 38), ``(S,)``.
    """

    contactor: _Rows
    target: _Rows
    triangles: _Array
    origin: _Array
    frame: _Array
    gap: _Array

    def __len__(self) -> int:
        """Number of pieces."""
        return self.contactor.size


def _pull_back(
    contactor: FaceData, rows: _Rows, x: _Array, frame: _Array
) -> tuple[_Array, _Array, _Array]:
    """Contactor reference coordinates, normals and area ratios of plane points ``x``."""
    xi, _ = polygon.intersect(contactor.nodes, rows, x, frame[:, 2], name="contactor face")
    _, dx = polygon.evaluate(contactor.nodes, rows, xi)
    area = np.cross(dx[:, :, 0], dx[:, :, 1])
    jac = np.linalg.norm(area, axis=1)
    normals = contactor.orientation[rows, None] * area / jac[:, None]
    ratio = jac / np.abs(np.einsum("pg,pg->p", area, frame[:, 2]))
    return xi, normals, ratio


class PolygonSegmentation:
    """Polygonal pieces of faces, the facets of 3D cells (section 5, Fig. 15(b)).

    Satisfies :class:`~dolfinx_contact_s2s.segmentation.Segmentation` with
    :class:`FaceData` in place of ``SurfaceData``; the ``backend`` arguments are unused
    (the NumPy geometry of :mod:`~dolfinx_contact_s2s.kernels.polygon` runs).
    """

    facet_dim = 2

    def sweep(self, contactor: FaceData, boxes: _Array, radius: float) -> _Array:
        """The faces' boxes swept along their normals (:func:`swept_face_boxes`)."""
        return swept_face_boxes(contactor, boxes, radius)

    def cut(
        self,
        contactor: FaceData,
        target: FaceData,
        ic: _Rows,
        it: _Rows,
        radius: float,
        backend: typing.Any = None,
    ) -> PolygonPieces:
        r"""Clip the candidate pairs' corner polygons and triangulate the overlaps.

        Pairs whose outward normals do not oppose are dropped
        (:func:`~dolfinx_contact_s2s.kernels.polygon.project_faces`), and so are
        triangles whose centroid is farther than ``radius`` from the target face along
        the contactor normal (Eq. 38).
        """
        C, T = contactor, target
        ic = np.asarray(ic, dtype=np.int32)
        it = np.asarray(it, dtype=np.int32)
        if ic.size == 0:  # A process without candidates (or without contactor faces).
            none = np.zeros(0, dtype=np.int32)
            return PolygonPieces(
                none, none, np.zeros((0, 3, 2)), np.zeros((0, 3)), np.zeros((0, 3, 3)), np.zeros(0)
            )
        origin, frame, c_poly, t_poly, facing = polygon.project_faces(
            C.nodes, C.orientation, T.nodes, T.orientation, ic, it
        )
        tris, pairs = [np.zeros((0, 3, 2))], [np.zeros(0, dtype=np.int32)]
        for p in np.flatnonzero(facing):
            triangles = polygon.triangulate(polygon.clip_convex(t_poly[p], c_poly[p]))
            tris.append(triangles)
            pairs.append(np.full(triangles.shape[0], p, dtype=np.int32))
        triangles, pair = np.concatenate(tris), np.concatenate(pairs)
        f, o = frame[pair], origin[pair]
        centroid = o + np.einsum("sd,sdg->sg", triangles.mean(axis=1), f[:, :2])
        xi, normals, _ = _pull_back(C, ic[pair], centroid, f)
        x_c, _ = polygon.evaluate(C.nodes, ic[pair], xi)
        _, gap = polygon.intersect(T.nodes, it[pair], x_c, normals, name="target face")
        keep = np.abs(gap) <= radius
        return PolygonPieces(
            ic[pair][keep], it[pair][keep], triangles[keep], o[keep], f[keep], gap[keep]
        )

    def points(
        self,
        contactor: FaceData,
        pieces: PolygonPieces,
        rule: tuple[_Array, _Array],
        backend: typing.Any = None,
    ) -> tuple[_Array, _Array]:
        r"""A triangle rule on each piece, pulled back to the contactor face (Eq. 40).

        Args:
            contactor: The contactor faces.
            pieces: The pieces of :meth:`cut`.
            rule: Points ``(Q, 2)`` and weights ``(Q,)`` on the reference triangle
                (``basix.make_quadrature(basix.CellType.triangle, degree)``).
            backend: Unused.

        Returns:
            ``(xi, weights)``: contactor reference coordinates ``(S, Q, 2)``, found along
            the plane's normal, and the weights :math:`w^i` of Eq. (40) ``(S, Q)``: the
            rule's weight times twice the triangle's area times the ratio of the face's
            area element to the plane's.
        """
        X, W = (np.asarray(r, dtype=np.float64) for r in rule)
        t = pieces.triangles
        a, ab, ac = t[:, 0], t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        plane = a[:, None] + X[None, :, :1] * ab[:, None] + X[None, :, 1:] * ac[:, None]
        det = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
        S, Q = len(pieces), W.size
        if S == 0:
            return np.zeros((0, Q, 2)), np.zeros((0, Q))
        x = pieces.origin[:, None] + np.einsum("sqd,sdg->sqg", plane, pieces.frame[:, :2])
        rows = np.repeat(pieces.contactor, Q)
        xi, _, ratio = _pull_back(
            contactor, rows, x.reshape(-1, 3), np.repeat(pieces.frame, Q, axis=0)
        )
        return xi.reshape(S, Q, 2), det[:, None] * W[None, :] * ratio.reshape(S, Q)

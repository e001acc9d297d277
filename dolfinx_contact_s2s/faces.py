# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Faces of 3D cells as contact facets: their nodes, orientation and checks.

The composite quadrature of section 5 integrates the contact term of Eq. (40) on pieces
of the contactor facets bounded by the nodes of both surfaces (Fig. 15(b)); on the faces
of tetrahedra and hexahedra the pieces are polygons
(:class:`~dolfinx_contact_s2s.segmentation.PolygonSegmentation`), computed on arrays by
:mod:`dolfinx_contact_s2s.kernels.polygon` and
:mod:`dolfinx_contact_s2s.kernels.face_backend`. Their input is each face's geometry
nodes in the order of Basix's Lagrange element on the face
(:data:`~dolfinx_contact_s2s.kernels.polygon.FACE_ELEMENTS`) and the sign turning
:math:`\partial_1 x \times \partial_2 x` outward; a
:class:`~dolfinx_contact_s2s.surface.ContactSurface` on a 3D mesh takes them from here:

- :func:`face_node_order`: which cell geometry nodes are each facet's face nodes, checked
  against the cell's geometry map;
- :func:`face_orientation`: the sign, from the cell's outward normal :math:`J^{-T} \hat n`;
- :func:`check_faces`: NaN nodes or faces of zero area, raised on every rank.
"""

from __future__ import annotations

import typing

from mpi4py import MPI

import basix
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import tabulate
from dolfinx_contact_s2s.kernels import polygon
from dolfinx_contact_s2s.kernels.numpy_backend import DEGENERATE_TOLERANCE

__all__ = [
    "check_faces",
    "face_node_order",
    "face_orientation",
    "raise_degenerate",
    "reference_vertices",
]

_Array = npt.NDArray[np.float64]
_Rows = npt.NDArray[np.int32]

# Reference points of the face centres: the triangle's centroid, the square's centre.
_CENTRE = {"triangle": (1.0 / 3.0, 1.0 / 3.0), "quadrilateral": (0.5, 0.5)}


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
    phi_face = polygon.face_element(order_array.shape[1]).tabulate(0, s)[0, :, :, 0]
    for i in range(len(topology[2])):
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


def face_orientation(
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


def check_faces(
    comm: MPI.Comm, tag: int, coords: _Array, nodes: _Array, oriented: npt.NDArray[np.bool_]
) -> None:
    """Raise on every rank for NaN or infinite nodes, or faces of zero area (collective).

    Args:
        comm: The mesh's communicator.
        tag: The surface's tag, for the message.
        coords: Geometry nodes of the faces' cells, ``(F, num_cell_nodes, 3)``.
        nodes: The faces' nodes, ``(F, K, 3)``.
        oriented: Whether :func:`face_orientation` found both normals, ``(F,)``.
    """
    finite = np.all(np.isfinite(nodes), axis=(1, 2)) & np.all(np.isfinite(coords), axis=(1, 2))
    with np.errstate(invalid="ignore", over="ignore"):
        flat = finite & ~(oriented & _corner_area_ok(nodes))
    raise_degenerate(
        comm,
        tag,
        finite,
        flat,
        nodes[:, 0],
        "face",
        "zero area (corner nodes coincide or lie on one line)",
        "remove the degenerate cells",
    )


def raise_degenerate(
    comm: MPI.Comm,
    tag: int,
    finite: npt.NDArray[np.bool_],
    flat: npt.NDArray[np.bool_],
    points: _Array,
    entity: str,
    what: str,
    remedy: str,
) -> None:
    """Raise one message on every rank for facets with NaN nodes or without a normal.

    Collective: one reduction of two counts; the point of the first facet without a
    normal is gathered only when there is one.

    Args:
        comm: The mesh's communicator.
        tag: The surface's tag.
        finite: Whether each facet's cell has finite nodes.
        flat: Whether each facet (with finite nodes) has no normal.
        points: A point of each facet, named in the message.
        entity: ``"facet"`` or ``"face"``.
        what: What makes a facet degenerate, e.g. ``"zero length (two nodes coincide)"``.
        remedy: What to do about it.
    """
    bad = comm.allreduce(np.array([np.count_nonzero(~finite), np.count_nonzero(flat)]))
    if bad[0]:
        raise ValueError(
            f"contact surface {tag}: the cells of {bad[0]} {entity}(s) have a node with NaN "
            "or infinite coordinates; check the mesh (mesh.geometry.x) and how it was built "
            "or moved"
        )
    if bad[1]:
        first = next(w for w in comm.allgather(points[flat][:1]) if w.size)[0]
        where = ", ".join(f"{c:.6g}" for c in first)
        raise ValueError(
            f"contact surface {tag}: {bad[1]} {entity}(s) have {what}, the first at "
            f"({where}): they have no normal; {remedy}"
        )


def reference_vertices(cell: basix.CellType) -> _Array:
    r"""Reference-cell coordinates of each facet's vertices 0, 1, 2, ``(num_facets, 3, 3)``.

    A face's reference coordinates :math:`\xi` are the point
    :math:`X_0 + \xi_1 (X_1 - X_0) + \xi_2 (X_2 - X_0)` of the reference cell (for a
    quadrilateral face, vertex 3 is :math:`X_1 + X_2 - X_0`).
    """
    x = basix.geometry(cell)
    return np.ascontiguousarray(np.stack([x[v[:3]] for v in basix.topology(cell)[2]]))

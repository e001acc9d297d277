# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Polygonal pieces of faces: the geometry of the composite quadrature in 3D (Fig. 15(b)).

The new algorithm (section 5) integrates the contact term of Eq. (40) with a
*composite* rule: on pieces of the contactor facets bounded by the nodes of both
surfaces, so that the contactor displacement (Eq. 41), the multiplier (Eq. 42) and the
target displacement at the point met along the normal (Eq. 38) are all smooth on each
piece. On the edges of 2D cells a piece is an interval
(:func:`~dolfinx_contact_s2s.kernels.numpy_backend.clip_segments`); on the faces of 3D
cells it is a polygon, and this module computes it, on arrays only:

1. :func:`project_faces`: each candidate pair (contactor face, target face) is drawn in
   the contactor face's plane (origin at the centroid of its corners, orthonormal
   tangents, outward normal), the target's corners projected along the contactor
   normal; pairs whose outward normals do not oppose are dropped.
2. :func:`clip_convex`: the overlap of the two corner polygons (Sutherland-Hodgman).
3. :func:`triangulate`: the overlap cut into triangles, a fan from its vertex centroid.
4. :func:`overlap_rule`: a Gauss rule of the triangle (Basix) placed on every
   sub-triangle, and its points pulled back to the contactor face's reference
   coordinates and to the target face's (Eq. 38) by :func:`intersect`.

As the paper says for quadratic elements, only the corner (vertex) nodes bound the
pieces. A face is given by its geometry nodes, ``nodes[f, k, :]``, in the order of
Basix's Lagrange element on the face (the number of nodes picks the element:
:data:`FACE_ELEMENTS`); ``orientation[f]`` is ``+1`` when
:math:`\partial_1 x \times \partial_2 x` points out of the face's cell, else ``-1``.
Reference coordinates are Basix's: the triangle :math:`\{\xi_1, \xi_2 \ge 0,
\xi_1 + \xi_2 \le 1\}`, the square :math:`[0, 1]^2`.

This is the NumPy reference: the geometry and the Newton solves are vectorized over
points and pairs; the clipping and triangulation, on the plane polygons, are those of
:mod:`~dolfinx_contact_s2s.kernels.clipping` (a Python loop over the facing pairs, about
0.1 ms a pair), or the compiled ones of :mod:`~dolfinx_contact_s2s.kernels.c_backend`
(the same results) when :func:`overlap_rule` is given that module as ``backend``.
Sutherland-Hodgman needs convex polygons: a quadrilateral whose projected corners are
not convex (a badly warped or folded face) is not detected here.
"""

from __future__ import annotations

import functools
import types
from dataclasses import dataclass

import basix
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels import clipping as _clipping
from dolfinx_contact_s2s.kernels.clipping import (
    clip_convex,
    clip_polygons,
    signed_area,
    triangulate,
    triangulate_polygons,
)
from dolfinx_contact_s2s.kernels.numpy_backend import NEWTON_TOL, ROUND_OFF

__all__ = [
    "FACE_ELEMENTS",
    "OverlapRule",
    "check_lines",
    "clip_convex",
    "clip_polygons",
    "corner_nodes",
    "evaluate",
    "face_element",
    "flat_normals",
    "intersect",
    "overlap_rule",
    "project_faces",
    "triangulate",
    "triangulate_polygons",
]

_Array = npt.NDArray[np.float64]
_Rows = npt.NDArray[np.int32]

#: The face element of each number of geometry nodes: ``(cell, degree)`` of a Basix
#: Lagrange element (3: P1 triangle, 4: Q1 quadrilateral, 6: P2 triangle, 9: Q2).
FACE_ELEMENTS: dict[int, tuple[str, int]] = {
    3: ("triangle", 1),
    4: ("quadrilateral", 1),
    6: ("triangle", 2),
    9: ("quadrilateral", 2),
}

# The corner nodes counter-clockwise around the reference cell: Basix numbers the
# square's vertices (0, 0), (1, 0), (0, 1), (1, 1), not cyclically.
_CORNERS = {"triangle": (0, 1, 2), "quadrilateral": (0, 1, 3, 2)}


def _face_element(num_nodes: int) -> tuple[str, int]:
    """The ``(cell, degree)`` of faces with ``num_nodes`` geometry nodes."""
    if num_nodes not in FACE_ELEMENTS:
        raise ValueError(
            f"faces with {num_nodes} nodes are not supported; the number of nodes picks "
            f"the element: {FACE_ELEMENTS}"
        )
    return FACE_ELEMENTS[num_nodes]


@functools.lru_cache
def face_element(num_nodes: int) -> basix.finite_element.FiniteElement:
    """The Basix Lagrange element of faces with ``num_nodes`` geometry nodes."""
    cell, degree = _face_element(num_nodes)
    return basix.create_element(
        basix.ElementFamily.P, basix.CellType[cell], degree, basix.LagrangeVariant.gll_warped
    )


def corner_nodes(nodes: _Array) -> _Array:
    """The corner nodes of faces, counter-clockwise in the reference cell, ``(F, m, 3)``."""
    cell, _ = _face_element(nodes.shape[1])
    return nodes[:, _CORNERS[cell]]


def _unit(v: _Array) -> _Array:
    """Vectors along the last axis divided by their length."""
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def flat_normals(nodes: _Array, tol: float = 1e-10) -> tuple[_Array, npt.NDArray[np.bool_]]:
    r"""Unit normals of faces' corner polygons (their vector areas) and whether faces are flat.

    A face is flat when every node lies within ``tol`` times its size (largest corner
    distance from the corners' centroid) of the plane through that centroid normal to
    the polygon's vector area; its normal is then constant up to a relative ``tol``.

    Returns:
        ``(normals, flat)``: ``(F, 3)`` (the sign of the corner order) and ``(F,)``.
    """
    corners = corner_nodes(nodes)
    centre = corners.mean(axis=1, keepdims=True)
    rel = corners - centre
    n = _unit(np.cross(rel, np.roll(rel, -1, axis=1)).sum(axis=1))
    size = np.max(np.linalg.norm(rel, axis=2), axis=1)
    off = np.max(np.abs(np.einsum("fkg,fg->fk", nodes - centre, n)), axis=1)
    return n, off <= tol * size


def evaluate(nodes: _Array, rows: _Rows, xi: _Array) -> tuple[_Array, _Array]:
    r"""Points and tangents of faces at reference coordinates.

    Args:
        nodes: Geometry nodes of the faces, ``(F, K, 3)``.
        rows: Face of each point, ``(P,)``.
        xi: Reference coordinates of each point, ``(P, 2)``.

    Returns:
        ``(x, dx)``: the points :math:`x(\xi)`, ``(P, 3)``, and the tangents
        :math:`\partial x / \partial \xi_d` as the columns of ``dx``, ``(P, 3, 2)``.
    """
    element = face_element(nodes.shape[1])
    if rows.size == 0:
        return np.zeros((0, 3)), np.zeros((0, 3, 2))
    table = element.tabulate(1, np.ascontiguousarray(xi, dtype=np.float64))[:, :, :, 0]
    c = nodes[rows]
    return np.einsum("pk,pkg->pg", table[0], c), np.einsum("dpk,pkg->pgd", table[1:], c)


def _solve(A: _Array, b: _Array) -> tuple[_Array, npt.NDArray[np.bool_]]:
    """Batched 3x3 solves; singular ones (relative to Hadamard's bound) give NaN."""
    finite = np.all(np.isfinite(A), axis=(1, 2)) & np.all(np.isfinite(b), axis=1)
    A = np.where(finite[:, None, None], A, np.eye(3))
    bound = np.prod(np.linalg.norm(A, axis=1), axis=1)
    regular = finite & (np.abs(np.linalg.det(A)) > ROUND_OFF * bound)
    safe = np.where(regular[:, None, None], A, np.eye(3))
    x = np.linalg.solve(safe, b[:, :, None])[:, :, 0]
    x[~regular] = np.nan
    return x, regular


def intersect(
    nodes: _Array,
    rows: _Rows,
    origins: _Array,
    directions: _Array,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
    name: str = "face",
) -> tuple[_Array, _Array]:
    r"""Where the lines :math:`o + t d` cross the (extended) faces (Eq. 38, Fig. 7(b)).

    Solves :math:`x(\xi) - (o + t d) = 0` for :math:`(\xi_1, \xi_2, t)`. The start is
    the exact solution for the flat face through corners 0, 1, 2 (the reference points
    :math:`(0, 0), (1, 0), (0, 1)`): exact, and final, for P1 triangles. On other faces
    (bilinear, warped, P2, Q2) Newton's method follows, stopping once every step
    satisfies :math:`|\delta\xi| \le` ``tol`` :math:`(1 + |\xi|)` and
    :math:`|\delta t| \le` ``tol`` :math:`(h + |t|)`, :math:`h` the face's largest
    corner distance. With :math:`o` on the face and :math:`d` not tangent to it, this
    inverts the face's geometry map. Works relative to the face's first node.

    Args:
        nodes: Geometry nodes of the faces, ``(F, K, 3)``.
        rows: Face of each line, ``(P,)``.
        origins: Points :math:`o` of the lines, ``(P, 3)``.
        directions: Directions :math:`d` of the lines, ``(P, 3)``, of unit length
            (else :math:`t` is in their units).
        iterations: Newton iterations at most.
        tol: Relative Newton stopping test.
        name: What a face is called in the error message (``"target face"``).

    Returns:
        ``(xi, t)``: reference coordinates ``(P, 2)`` and line parameters ``(P,)``.

    Raises:
        RuntimeError: Naming the faces (by row) whose line runs along them, or where
            Newton's method does not converge (a line missing a folded face).
    """
    c = nodes[rows] - nodes[rows, :1]
    o = origins - nodes[rows, 0]
    A = np.stack([c[:, 1], c[:, 2], -directions], axis=2)
    start, ok = _solve(A, o)
    xi, t = start[:, :2], start[:, 2]
    if nodes.shape[1] > 3:
        h = np.max(np.linalg.norm(c, axis=2), axis=1)
        local = np.arange(rows.size, dtype=np.int32)
        small = np.zeros(rows.size, dtype=bool)
        for _ in range(iterations):
            x, dx = evaluate(c, local, xi)
            J = np.concatenate([dx, -directions[:, :, None]], axis=2)
            step, regular = _solve(J, x - o - t[:, None] * directions)
            ok &= regular
            xi = xi - step[:, :2]
            t = t - step[:, 2]
            small = np.all(np.abs(step[:, :2]) <= tol * (1.0 + np.abs(xi)), axis=1)
            small &= np.abs(step[:, 2]) <= tol * (h + np.abs(t))
            if np.all(small | ~ok):
                break
        ok &= small
    ok &= np.all(np.isfinite(xi), axis=1) & np.isfinite(t)
    check_lines(rows, ok, name, iterations)
    return xi, t


def check_lines(rows: _Rows, ok: npt.NDArray[np.bool_], name: str, iterations: int) -> None:
    """Raise the RuntimeError of :func:`intersect` naming the faces of the lines not ``ok``."""
    if not np.all(ok):
        bad = np.unique(rows[~ok])
        raise RuntimeError(
            f"{name} {', '.join(map(str, bad[:5]))}{' ...' if bad.size > 5 else ''}: no "
            f"point met along the line ({np.count_nonzero(~ok)} of {rows.size} lines): the "
            f"line runs along the face, or Newton's method did not converge in "
            f"{iterations} iterations"
        )


def _check_areas(nodes: _Array, rows: _Rows, round_off: float, name: str) -> None:
    """Raise a ValueError naming the first face of ``rows`` whose corners span no area."""
    faces = np.unique(rows)
    corners = corner_nodes(nodes[faces])
    rel = corners - corners.mean(axis=1, keepdims=True)
    area = 0.5 * np.linalg.norm(np.cross(rel, np.roll(rel, -1, axis=1)).sum(axis=1), axis=1)
    size = np.max(np.linalg.norm(rel, axis=2), axis=1)
    bad = faces[~(area > round_off * size**2)]
    if bad.size:
        raise ValueError(
            f"{name} {bad[0]} has zero area (its corner nodes coincide or lie on one "
            f"line){f'; {bad.size - 1} more' if bad.size > 1 else ''}"
        )


def project_faces(
    c_nodes: _Array,
    c_orientation: _Array,
    t_nodes: _Array,
    t_orientation: _Array,
    ic: _Rows,
    it: _Rows,
    round_off: float = ROUND_OFF,
) -> tuple[_Array, _Array, _Array, _Array, npt.NDArray[np.bool_]]:
    r"""Corner polygons of candidate pairs in the contactor face's plane (Fig. 15(b)).

    The plane of contactor face ``ic[p]`` has its origin at the centroid of the face's
    corners and the frame :math:`(e_1, e_2, n)`: :math:`n` the outward unit normal of the
    corner polygon (its vector area, :math:`\frac12 (x_3 - x_0) \times (x_2 - x_1)` for a
    quadrilateral), :math:`e_1` the first corner edge made orthogonal to :math:`n`,
    :math:`e_2 = n \times e_1`. The corners of both faces are projected on it along
    :math:`n`. A slightly warped quadrilateral's corners are projected too: its polygon
    is the plane's best view of it, and the pull-back in :func:`overlap_rule` follows the
    curved face. Only corner nodes count (midside nodes of P2/Q2 faces do not bound
    pieces).

    Args:
        c_nodes: Contactor face nodes, ``(Fc, Kc, 3)``.
        c_orientation: Contactor orientation signs, ``(Fc,)``.
        t_nodes: Target face nodes, ``(Ft, Kt, 3)``.
        t_orientation: Target orientation signs, ``(Ft,)``.
        ic: Contactor face of each candidate pair, ``(N,)``.
        it: Target face of each candidate pair, ``(N,)``.
        round_off: Relative round-off: faces with area below ``round_off`` times their
            size squared are refused.

    Returns:
        ``(origin, frame, c_poly, t_poly, facing)``: plane origins ``(N, 3)``, frames
        ``(N, 3, 3)`` with rows :math:`e_1, e_2, n`, both polygons counter-clockwise in
        plane coordinates, ``(N, mc, 2)`` and ``(N, mt, 2)``, and whether the faces'
        outward normals oppose, ``(N,)``.

    Raises:
        ValueError: Naming a contactor or target face of zero area.
    """

    def outward(corners: _Array, sign: _Array) -> _Array:
        rel = corners - corners.mean(axis=1, keepdims=True)
        return sign[:, None] * _unit(np.cross(rel, np.roll(rel, -1, axis=1)).sum(axis=1))

    def counter_clockwise(poly: _Array) -> _Array:
        clockwise = signed_area(poly) < 0.0
        poly[clockwise] = poly[clockwise, ::-1]
        return poly

    # Each face's plane, normal and polygon once (a face meets several), then per pair.
    faces, ic = np.unique(ic, return_inverse=True)
    t_faces, it = np.unique(it, return_inverse=True)
    _check_areas(c_nodes, faces, round_off, "contactor face")
    _check_areas(t_nodes, t_faces, round_off, "target face")
    cc = corner_nodes(c_nodes[faces])
    origin = cc.mean(axis=1)
    cc = cc - origin[:, None]
    n = outward(cc, c_orientation[faces])
    edge = cc[:, 1] - cc[:, 0]
    e1 = _unit(edge - np.einsum("pg,pg->p", edge, n)[:, None] * n)
    frame = np.stack([e1, np.cross(n, e1), n], axis=1)
    c_poly = counter_clockwise(np.einsum("pmg,pdg->pmd", cc, frame[:, :2]))[ic]
    t_corners = corner_nodes(t_nodes[t_faces])
    facing = np.einsum("pg,pg->p", n[ic], outward(t_corners, t_orientation[t_faces])[it]) < 0.0
    origin, frame = origin[ic], frame[ic]
    tc = t_corners[it] - origin[:, None]
    t_poly = counter_clockwise(np.einsum("pmg,pdg->pmd", tc, frame[:, :2]))
    return origin, frame, c_poly, t_poly, facing


@dataclass(frozen=True)
class OverlapRule:
    r"""A Gauss rule on the sub-triangles of the overlaps of candidate face pairs (Eq. 40).

    Sub-triangle ``s`` is a piece of the overlap of the candidate pair ``pair[s]``;
    ``Q`` points each.

    Attributes:
        pair: Candidate pair of each sub-triangle (an index into ``ic``, ``it``), ``(S,)``.
        contactor: Contactor face of each sub-triangle, ``(S,)``.
        target: Target face of each sub-triangle, ``(S,)``.
        points: Points in the contactor plane's coordinates, ``(S, Q, 2)``.
        weights: Weights in that plane (summing to the sub-triangle's area), ``(S, Q)``.
        xi: Contactor reference coordinates of the points, ``(S, Q, 2)``.
        surface_weights: Weights :math:`w^i` of Eq. (40) on the contactor face:
            ``weights`` times the ratio of its area element to the plane's, ``(S, Q)``.
        normals: Outward unit normals :math:`n_C` of the contactor at the points,
            ``(S, Q, 3)``.
        eta: Target reference coordinates of the points met along :math:`n_C` (Eq. 38),
            ``(S, Q, 2)``.
        gap: :math:`(x_T^{i*} - x_C^i) \cdot n_C`, the initial gap :math:`g_0^i` of
            Eq. (40) (positive apart; ``pair.py``'s :math:`(x_C - x_T) \cdot N` with the
            contact normal :math:`N = -n_C`), ``(S, Q)``.
    """

    pair: _Rows
    contactor: _Rows
    target: _Rows
    points: _Array
    weights: _Array
    xi: _Array
    surface_weights: _Array
    normals: _Array
    eta: _Array
    gap: _Array

    def __len__(self) -> int:
        """Number of sub-triangles."""
        return self.pair.size


def overlap_rule(
    c_nodes: _Array,
    c_orientation: _Array,
    t_nodes: _Array,
    t_orientation: _Array,
    ic: _Rows,
    it: _Rows,
    degree: int,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
    round_off: float = ROUND_OFF,
    backend: types.ModuleType | None = None,
) -> OverlapRule:
    r"""The composite Gauss rule on the overlaps of candidate face pairs (Eqs. 38-42).

    Each pair is drawn in the contactor's plane (:func:`project_faces`); pairs whose
    normals do not oppose are dropped; the overlap of the two corner polygons
    (:func:`clip_polygons`) is cut into triangles (:func:`triangulate_polygons`) and Basix's Gauss
    rule of the triangle is mapped on each. The points are then pulled back to the
    contactor face along the plane's normal (:func:`intersect`: exact on flat triangles,
    Newton's method on bilinear, warped or curved faces), and the target point of each
    is the one met along the contactor's outward normal there (Eq. 38).

    On flat faces the pieces tile the overlap exactly and the rule integrates every
    polynomial of the contactor's and target's coordinates up to ``degree`` exactly (the
    patch test). On curved faces the pieces are bounded by the chords between corners in
    the contactor's plane, so their pull-backs may leave the reference cell by the bulge
    of a curved edge; ``eta`` may leave the target's cell by round-off near its edges.

    Args:
        c_nodes: Contactor face nodes, ``(Fc, Kc, 3)``.
        c_orientation: Contactor orientation signs, ``(Fc,)``.
        t_nodes: Target face nodes, ``(Ft, Kt, 3)``.
        t_orientation: Target orientation signs, ``(Ft,)``.
        ic: Contactor face of each candidate pair, ``(N,)``.
        it: Target face of each candidate pair, ``(N,)``.
        degree: Maximum polynomial degree that will be integrated exactly on each
            sub-triangle.
        iterations: Newton iterations at most.
        tol: Relative Newton stopping test.
        round_off: Relative round-off of the coordinates.
        backend: The module whose ``clip_polygons`` and ``triangulate_polygons`` cut the
            overlaps: None for this module's (NumPy), or
            :mod:`~dolfinx_contact_s2s.kernels.c_backend` once loaded (the same rule).

    Returns:
        The rule on the sub-triangles of all overlaps.

    Raises:
        ValueError: Naming a contactor or target face of zero area.
        RuntimeError: Naming a face on which Newton's method fails.
    """
    ic = np.asarray(ic, dtype=np.int32)
    it = np.asarray(it, dtype=np.int32)
    origin, frame, c_poly, t_poly, facing = project_faces(
        c_nodes, c_orientation, t_nodes, t_orientation, ic, it, round_off
    )
    kernels = backend if backend is not None else _clipping
    facing_pairs = np.flatnonzero(facing).astype(np.int32)
    pieces, counts = kernels.clip_polygons(
        t_poly[facing_pairs], c_poly[facing_pairs], round_off=round_off
    )
    triangles, owner = kernels.triangulate_polygons(pieces, counts, round_off)
    pair = facing_pairs[owner]
    X, W = basix.make_quadrature(basix.CellType.triangle, degree)
    # The affine map of the reference triangle onto each sub-triangle; |det| = 2 area.
    a = triangles[:, 0]
    ab, ac = triangles[:, 1] - a, triangles[:, 2] - a
    points = a[:, None] + X[None, :, :1] * ab[:, None] + X[None, :, 1:] * ac[:, None]
    det = ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]
    weights = np.abs(det)[:, None] * W[None, :]
    S, Q = weights.shape

    f = frame[pair]
    x_plane = origin[pair][:, None] + np.einsum("sqd,sdg->sqg", points, f[:, :2])
    rows_c = np.repeat(ic[pair], Q)
    rows_t = np.repeat(it[pair], Q)
    n_plane = np.repeat(f[:, 2], Q, axis=0)
    xi, _ = intersect(
        c_nodes, rows_c, x_plane.reshape(-1, 3), n_plane, iterations, tol, "contactor face"
    )
    x_c, dx_c = evaluate(c_nodes, rows_c, xi)
    area = np.cross(dx_c[:, :, 0], dx_c[:, :, 1])
    jac = np.linalg.norm(area, axis=1)
    normals = c_orientation[rows_c, None] * area / jac[:, None]
    ratio = jac / np.abs(np.einsum("pg,pg->p", area, n_plane))
    eta, t = intersect(t_nodes, rows_t, x_c, normals, iterations, tol, "target face")
    return OverlapRule(
        pair=pair,
        contactor=ic[pair],
        target=it[pair],
        points=points,
        weights=weights,
        xi=xi.reshape(S, Q, 2),
        surface_weights=weights * ratio.reshape(S, Q),
        normals=normals.reshape(S, Q, 3),
        eta=eta.reshape(S, Q, 2),
        gap=t.reshape(S, Q),
    )

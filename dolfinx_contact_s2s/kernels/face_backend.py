# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Array kernels of the contact assembly on faces, the facets of 3D cells (NumPy).

The kernels of :mod:`~dolfinx_contact_s2s.kernels.numpy_backend` with the same names and
meanings, for facets of topological dimension 2 (:data:`FACET_DIM`). A face's geometry
("coefficients" in the interface of :class:`~dolfinx_contact_s2s.kernels.KernelBackend`)
is its geometry nodes ``(F, K, 3)`` in the order of Basix's Lagrange element on the face
(:data:`~dolfinx_contact_s2s.kernels.polygon.FACE_ELEMENTS`), and a facet parameter is a
pair of reference coordinates :math:`\xi = (\xi_1, \xi_2)` of that element, so every
``xi`` below has a trailing axis of length 2. The pieces of the composite rule
(Fig. 15(b)) are cut by :mod:`~dolfinx_contact_s2s.kernels.polygon` and the clipping of
:mod:`~dolfinx_contact_s2s.kernels.clipping`; the coupling kernel of Eqs. (40)-(42) does
not depend on the facet dimension and is shared. This is the reference of the compiled
:mod:`~dolfinx_contact_s2s.kernels.face_c_backend`.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels import polygon
from dolfinx_contact_s2s.kernels.clipping import clip_polygons, triangulate_polygons
from dolfinx_contact_s2s.kernels.numpy_backend import (
    NEWTON_TOL,
    box_overlaps,
    coo_to_csr,
    csr_slots,
    segment_to_segment,
)

__all__ = [
    "FACET_DIM",
    "NAME",
    "bounding_boxes",
    "box_overlaps",
    "clip_polygons",
    "coo_to_csr",
    "csr_slots",
    "evaluate",
    "face_coupling",
    "facet_coefficients",
    "intersect",
    "intersect_lines",
    "monomial_values",
    "monomials",
    "outward_normals",
    "piece_gaps",
    "piece_points",
    "project_faces",
    "runs",
    "segment_to_segment",
    "shift",
    "tangents",
    "triangulate_polygons",
]

#: Topological dimension of the facets these kernels handle (faces of 3D cells).
FACET_DIM = 2

#: The backend's name (:data:`~dolfinx_contact_s2s.kernels.BACKENDS`).
NAME = "numpy"

#: Candidate face pairs drawn in the contactor faces' planes (Fig. 15(b)).
project_faces = polygon.project_faces

#: Reference coordinates and line parameters where lines cross faces, raising a
#: RuntimeError naming the faces missed (:func:`~.polygon.intersect`).
intersect_lines = polygon.intersect

_Array = npt.NDArray[np.float64]
_Rows = npt.NDArray[np.int32]


def facet_coefficients(nodes: npt.NDArray[np.int32], local_facet: _Rows, coords: _Array) -> _Array:
    """The geometry nodes of each face, in the face element's order.

    Args:
        nodes: Cell geometry node of each face node, per local facet of the cell,
            ``(num_cell_facets, K)``.
        local_facet: Local index of each face in its cell, ``(F,)``.
        coords: Geometry nodes of the faces' cells, ``(F, num_cell_nodes, 3)``.

    Returns:
        The face nodes, ``(F, K, 3)``.
    """
    index = nodes[local_facet]
    return np.ascontiguousarray(np.take_along_axis(coords, index[:, :, None], axis=1))


def shift(coefficients: _Array, offset: _Array) -> _Array:
    """The faces moved by ``offset`` ``(F, 3)``: every node moves (a new array)."""
    return coefficients + offset[:, None, :]


def evaluate(
    coefficients: _Array, rows: _Rows, xi: _Array, derivatives: int = 1
) -> tuple[_Array, ...]:
    r"""Points :math:`x(\xi)` ``(P, 3)`` and tangents :math:`\partial x/\partial \xi` ``(P, 3, 2)``.

    Raises:
        NotImplementedError: For second derivatives (no kernel of the faces uses them).
    """
    if derivatives != 1:
        raise NotImplementedError("face kernels evaluate first derivatives only")
    return polygon.evaluate(coefficients, rows, np.reshape(xi, (-1, 2)))


def outward_normals(coefficients: _Array, orientation: _Array, rows: _Rows, xi: _Array) -> _Array:
    r"""Unit outward normals: the orientation times :math:`\partial_1 x \times \partial_2 x`."""
    _, dx = evaluate(coefficients, rows, xi)
    n = np.cross(dx[:, :, 0], dx[:, :, 1])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return orientation[rows, None] * n


def tangents(normals: _Array, axis: _Array, which: int) -> _Array:
    r"""The tangent basis of friction at unit normals :math:`N` ``(P, 3)``, from an axis :math:`a`.

    :math:`T_1 = a \times N / |a \times N|` (``which = 1``) and :math:`T_2 = N \times T_1`
    (``which = 2``): with :math:`N`, a right-handed orthonormal frame at every point,
    smooth where :math:`N` is, and the same on every face of a flat surface.
    """
    t = np.cross(np.asarray(axis, dtype=np.float64), normals)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    return t if which == 1 else np.cross(normals, t)


def intersect(
    coefficients: _Array,
    rows: _Rows,
    origins: _Array,
    directions: _Array,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
) -> _Array:
    r"""Reference coordinates where the lines ``origins + t directions`` cross the faces (Eq. 38).

    Newton's method on :math:`x(\eta) - (o + t\, d) = 0`
    (:func:`~dolfinx_contact_s2s.kernels.polygon.intersect`), ``(P, 2)``.
    """
    eta, _ = polygon.intersect(coefficients, rows, origins, directions, iterations, tol)
    return eta


def _pull_back(
    nodes: _Array,
    orientation: _Array,
    rows: _Rows,
    x: _Array,
    frames: _Array,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
) -> tuple[_Array, _Array, _Array]:
    r"""Plane points ``x`` ``(P, 3)`` pulled back to faces along their planes' normals.

    Args:
        nodes: Face nodes ``(F, K, 3)``.
        orientation: The faces' orientation signs ``(F,)``.
        rows: Face of each point ``(P,)``.
        x: The points.
        frames: Rows :math:`e_1, e_2, n` of each point's plane ``(P, 3, 3)``.
        iterations: Newton iterations at most.
        tol: Relative Newton stopping test.

    Returns:
        ``(xi, normals, ratio)``: reference coordinates ``(P, 2)``, outward unit normals
        ``(P, 3)`` and the ratios of the faces' area elements to the planes' ``(P,)``.

    Raises:
        RuntimeError: Naming the faces that a line misses.
    """
    xi, _ = polygon.intersect(nodes, rows, x, frames[:, 2], iterations, tol, "contactor face")
    _, dx = evaluate(nodes, rows, xi)
    area = np.cross(dx[:, :, 0], dx[:, :, 1])
    jac = np.linalg.norm(area, axis=1)
    normals = orientation[rows, None] * area / jac[:, None]
    ratio = jac / np.abs(np.einsum("pg,pg->p", area, frames[:, 2]))
    return xi, normals, ratio


def piece_gaps(
    c_nodes: _Array,
    c_orientation: _Array,
    t_nodes: _Array,
    rows: tuple[_Rows, _Rows],
    triangles: _Array,
    origin: _Array,
    frame: _Array,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
) -> _Array:
    r"""The gap :math:`(x_T - x_C) \cdot n_C` at the centroid of each plane triangle (Eq. 38).

    The centroid is pulled back to the contactor face along its plane's normal, and the
    line along the contactor's outward normal there is met with the target face.

    Args:
        c_nodes: Contactor face nodes ``(Fc, Kc, 3)``.
        c_orientation: Their orientation signs ``(Fc,)``.
        t_nodes: Target face nodes ``(Ft, Kt, 3)``.
        rows: Contactor and target face of each triangle, ``(S,)`` each.
        triangles: Vertices in plane coordinates ``(S, 3, 2)``.
        origin: Origin of each triangle's plane ``(S, 3)``.
        frame: Rows :math:`e_1, e_2, n` of each triangle's plane ``(S, 3, 3)``.
        iterations: Newton iterations at most.
        tol: Relative Newton stopping test.

    Returns:
        The gaps ``(S,)``.

    Raises:
        RuntimeError: Naming the faces that a line misses.
    """
    centroid = origin + np.einsum("sd,sdg->sg", triangles.mean(axis=1), frame[:, :2])
    xi, normals, _ = _pull_back(c_nodes, c_orientation, rows[0], centroid, frame, iterations, tol)
    x_c, _ = evaluate(c_nodes, rows[0], xi)
    _, gap = polygon.intersect(t_nodes, rows[1], x_c, normals, iterations, tol, "target face")
    return gap


def piece_points(
    nodes: _Array,
    rows: _Rows,
    triangles: _Array,
    origin: _Array,
    frame: _Array,
    rule: tuple[_Array, _Array],
    iterations: int = 16,
    tol: float = NEWTON_TOL,
) -> tuple[_Array, _Array]:
    r"""A triangle rule on plane triangles, pulled back to faces (Eq. 40).

    Args:
        nodes: Face nodes ``(F, K, 3)``.
        rows: Face of each triangle ``(S,)``.
        triangles: Vertices in plane coordinates ``(S, 3, 2)``.
        origin: Origin of each triangle's plane ``(S, 3)``.
        frame: Rows :math:`e_1, e_2, n` of each triangle's plane ``(S, 3, 3)``.
        rule: Points ``(Q, 2)`` and weights ``(Q,)`` on the reference triangle.
        iterations: Newton iterations at most.
        tol: Relative Newton stopping test.

    Returns:
        ``(xi, weights)``: reference coordinates ``(S, Q, 2)`` found along the planes'
        normals, and the rule's weights times twice the triangles' areas times the ratio
        of the face's area element to the plane's ``(S, Q)``.
    """
    X, W = rule
    a, ab, ac = (
        triangles[:, 0],
        triangles[:, 1] - triangles[:, 0],
        triangles[:, 2] - triangles[:, 0],
    )
    plane = a[:, None] + X[None, :, :1] * ab[:, None] + X[None, :, 1:] * ac[:, None]
    det = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    S, Q = triangles.shape[0], W.size
    x = origin[:, None] + np.einsum("sqd,sdg->sqg", plane, frame[:, :2])
    r = np.repeat(rows, Q)
    xi, _, ratio = _pull_back(
        nodes, np.ones(nodes.shape[0]), r, x.reshape(-1, 3), np.repeat(frame, Q, axis=0),
        iterations, tol,
    )  # fmt: skip
    return xi.reshape(S, Q, 2), det[:, None] * W[None, :] * ratio.reshape(S, Q)


def monomials(xi: _Array, degree: int) -> _Array:
    r""":math:`\xi_1^i \xi_2^j` at points ``xi`` ``(P, 2)``, column :math:`j (d + 1) + i`."""
    p = np.arange(degree + 1)
    return (xi[:, None, 1:] ** p[:, None] * xi[:, None, :1] ** p).reshape(xi.shape[0], -1)


def monomial_values(coef: _Array, index: _Rows, xi: _Array, zero_below: float = 0.0) -> _Array:
    r"""Functions given by monomial tables at face coordinates, ``(P, N)``.

    Point ``p`` takes the table ``coef[index[p]]`` of shape ``((d + 1)^2, N)``, the
    coefficients of :math:`\xi_1^i \xi_2^j` in row :math:`j (d + 1) + i`
    (:class:`~dolfinx_contact_s2s.face_basis.FaceBasis`); values below ``zero_below`` in
    magnitude are set to zero.
    """
    mono = monomials(np.reshape(xi, (-1, 2)), math.isqrt(coef.shape[1]) - 1)
    out = np.einsum("pm,pmn->pn", mono, coef[index])
    out[np.abs(out) < zero_below] = 0.0
    return out


def runs(rows_c: _Rows, rows_t: _Rows) -> _Rows:
    """The first group of each run of consecutive groups on the same pair of faces."""
    same = (rows_c[1:] == rows_c[:-1]) & (rows_t[1:] == rows_t[:-1])
    return np.flatnonzero(np.concatenate([[True], ~same])).astype(np.int32)


def face_coupling(
    c_nodes: _Array,
    c_orientation: _Array,
    t_nodes: _Array,
    rows: tuple[_Rows, _Rows],
    xi: _Array,
    weights: _Array,
    bases: tuple[tuple[_Array, _Rows], ...],
    square: bool = True,
    zero_below: float = 0.0,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
    tangent: tuple[_Array, int] | None = None,
) -> tuple[_Array, ...]:
    r"""The local blocks of Eqs. (40)-(42) on faces, from the points of each group.

    At each point: the contact normal :math:`N = -n_C`, the target point met along it
    (Eq. 38, reference coordinates clipped to :math:`[0, 1]`), the gap
    :math:`(x_C - x_T) \cdot N`, all relative to the contactor face's node 0; the bases
    from monomial tables (:func:`monomial_values`), and :func:`segment_to_segment`.

    Args:
        c_nodes: Contactor face nodes ``(Fc, Kc, 3)``.
        c_orientation: Their orientation signs ``(Fc,)``.
        t_nodes: Target face nodes ``(Ft, Kt, 3)``.
        rows: Contactor and target face of each group, ``(S,)`` each.
        xi: Contactor reference coordinates of the points, ``(S, Q, 2)``.
        weights: The weights :math:`w^i` of Eq. (40), ``(S, Q)``.
        bases: ``(coef, index)`` per group (``(S,)``) of the multiplier, the contactor
            basis (at ``xi``) and the target basis (at the target points).
        square: Whether the coverage sums :math:`w \mu^2` (else :math:`w \mu`).
        zero_below: The displacement bases' values set to zero below it.
        iterations: Newton iterations at most.
        tol: Relative Newton stopping test.
        tangent: ``(axis, which)``: the tangent :func:`tangents` in place of :math:`N` in
            the blocks, and a zero gap (friction's tangential coupling).

    Returns:
        ``(B_C, B_T, G, coverage, first)``: the blocks of :func:`segment_to_segment` and
        the coverage of :class:`~dolfinx_contact_s2s.pair.CouplingBlocks`, with the
        consecutive groups on the same pair of faces summed into one block (the pieces
        of one overlap: several times fewer entries to assemble); ``first`` is the first
        group of each block.

    Raises:
        RuntimeError: Naming the points whose target line Newton's method misses.
    """
    S, Q = weights.shape
    rc, rt = np.repeat(rows[0], Q), np.repeat(rows[1], Q)
    x = np.reshape(xi, (-1, 2))
    normals = -outward_normals(c_nodes, c_orientation, rc, x)
    origin = c_nodes[rc, 0]
    local = np.arange(rc.size, dtype=np.int32)
    c_local = shift(c_nodes[rc], -origin)
    t_local = shift(t_nodes[rt], -origin)
    x_c, _ = evaluate(c_local, local, x)
    eta, _ = polygon.intersect(t_local, local, x_c, normals, iterations, tol, "target point")
    np.clip(eta, 0.0, 1.0, out=eta)
    x_t, _ = evaluate(t_local, local, eta)
    gaps = np.einsum("pg,pg->p", x_c - x_t, normals)
    if tangent is not None:
        normals, gaps = tangents(normals, *tangent), np.zeros_like(gaps)
    (m_coef, m_index), (c_coef, c_index), (t_coef, t_index) = bases
    mu = monomial_values(m_coef, np.repeat(m_index, Q), x).reshape(S, Q, -1)
    phi_c = monomial_values(c_coef, np.repeat(c_index, Q), x, zero_below)
    phi_t = monomial_values(t_coef, np.repeat(t_index, Q), eta, zero_below)
    b_c, b_t, gap = segment_to_segment(
        mu,
        phi_c.reshape(S, Q, -1),
        phi_t.reshape(S, Q, -1),
        normals.reshape(S, Q, 3),
        weights,
        gaps.reshape(S, Q),
    )
    coverage = np.einsum("sqk,sq->sk", mu**2 if square else mu, weights)
    first = runs(*rows)
    blocks = (np.add.reduceat(a, first, axis=0) for a in (b_c, b_t, gap, coverage))
    return (*blocks, first)


def bounding_boxes(coefficients: _Array, samples: int, pad: float) -> _Array:
    r"""Axis-aligned boxes ``(F, 2, 3)`` that contain the faces.

    A P1 or Q1 face lies in the convex hull of its corners (a bilinear quadrilateral is a
    convex combination of them). A P2 or Q2 face bulges beyond its midside nodes, but
    lies in the hull of its *Bernstein control points* (the Bernstein polynomials are
    nonnegative and sum to one): on an edge with ends :math:`a, b` and midside node
    :math:`m` the control point is :math:`m + (m - (a + b)/2)`. The box of the control
    points is therefore safe without sampling, and exact for flat faces. ``samples`` and
    ``pad`` (the sampled boxes of curved edges in 2D) are not used.
    """
    F, K, _ = coefficients.shape
    if F == 0:
        return np.zeros((0, 2, 3))
    control = coefficients
    if K > 4:
        face, degree = polygon.FACE_ELEMENTS[K]
        inverse = np.linalg.inv(_bernstein(face, degree, polygon.face_element(K).points))
        control = np.einsum("jk,fkg->fjg", inverse, coefficients)
    return np.stack([control.min(axis=1), control.max(axis=1)], axis=1)


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

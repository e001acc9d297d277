# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The quadrature rule of a contact pair, and on faces a rule measured to be exact enough.

:func:`contact_rule` picks the rule of Eq. (17) for a pair: on edges the interval rule
of the fewest points that integrates it exactly (Fig. 15), on faces :func:`face_rule`.

The pieces of Fig. 15(b) in 3D are triangles with straight sides in the contactor face's
plane, and the rule placed on them is pulled back to both faces (Eqs. 38, 40). On an
*affine* face (a triangle, a parallelogram) the pull-back is affine, so the integrand of
Eq. (40) is a polynomial and a Gauss rule of its degree integrates it exactly: the
patch test holds to round-off. A flat quadrilateral that is not a parallelogram (or a
flat P2/Q2 face whose midside nodes are not at the midpoints) has a *rational* inverse
map: no rule is exact, but the error of a Gauss rule falls exponentially with its
degree (measured on the perturbed hexahedra of ``paper/blocks3d.py``: 5e-7 at degree
4, 2e-9 at 6, 9e-12 at 8, round-off from 10).

:func:`face_rule` therefore measures the rule on the surfaces themselves before it is
used: on every flat, non-affine face it integrates the face's own shape functions over
the two (or one) triangles of its corner polygon, exactly as the pieces are integrated,
and compares with the exact integrals in reference coordinates; the degree rises until
the worst relative error on any rank is below :data:`RULE_TOLERANCE`. Scenes of affine
faces keep the polynomial degree and pay nothing. On curved faces the pieces' straight
sides do not follow the curved edges, a geometric error of the discretization that no
rule removes; those faces are not measured.
"""

from __future__ import annotations

import logging
import typing
from collections.abc import Sequence

from mpi4py import MPI

import basix
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels import polygon
from dolfinx_contact_s2s.quadrature import interval_rule, triangle_rule

__all__ = [
    "MAX_RULE_DEGREE",
    "RULE_TOLERANCE",
    "contact_rule",
    "face_rule",
    "non_affine",
    "piece_integrals",
    "rule_error",
]

logger = logging.getLogger("dolfinx_contact_s2s")

_Array = npt.NDArray[np.float64]

#: Largest relative error of a face's shape-function integrals that :func:`face_rule`
#: accepts: a few hundred units of round-off of the sums over the pieces.
RULE_TOLERANCE = 1e-13
#: Highest degree :func:`face_rule` tries (Basix's Gauss-Jacobi rules have any degree).
MAX_RULE_DEGREE = 40


def _affine_image(nodes: _Array) -> _Array:
    """The face nodes as the affine map through the first corners would place them."""
    X = polygon.face_element(nodes.shape[1]).points
    # Basix's vertices: (0, 0), (1, 0), (0, 1) on both cells; the affine map through them.
    x0, x1, x2 = nodes[:, 0], nodes[:, 1], nodes[:, 2]
    return x0[:, None] + X[None, :, :1] * (x1 - x0)[:, None] + X[None, :, 1:] * (x2 - x0)[:, None]


def non_affine(nodes: _Array) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]]:
    """Which faces are flat but not affine, and which are curved.

    Args:
        nodes: Geometry nodes of the faces, ``(F, K, 3)``.

    Returns:
        ``(flat_non_affine, curved)``: masks ``(F,)``. A face is affine when every node
        is where the affine map through its first three vertices puts it, flat when
        every node lies in the plane of those vertices (both to round-off of its size).
    """
    if nodes.shape[0] == 0:
        none = np.zeros(0, dtype=bool)
        return none, none
    size = np.ptp(nodes, axis=1).max(axis=1)
    tol = 64 * np.finfo(np.float64).eps * size
    off = np.linalg.norm(nodes - _affine_image(nodes), axis=2).max(axis=1)
    x0, x1, x2 = nodes[:, 0], nodes[:, 1], nodes[:, 2]
    n = np.cross(x1 - x0, x2 - x0)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    height = np.abs(np.einsum("fkg,fg->fk", nodes - x0[:, None], n)).max(axis=1)
    curved = height > tol
    if nodes.shape[1] > 4:
        # A midside node off its edge's chord bends the edge within the plane: the
        # pieces' straight sides then miss the face's boundary as on a curved face.
        cell, _ = polygon.FACE_ELEMENTS[nodes.shape[1]]
        curved |= _bent_edges(nodes, cell) > tol
    return (off > tol) & ~curved, curved


def _bent_edges(nodes: _Array, cell: str) -> _Array:
    """Largest distance of a midside node from the chord of its edge, ``(F,)``."""
    # Basix's P2/Q2 edge nodes follow the vertices, one per edge in its edge order.
    edges = basix.topology(basix.CellType[cell])[1]
    worst = np.zeros(nodes.shape[0])
    vertices = 3 if cell == "triangle" else 4
    for e, (a, b) in enumerate(edges):
        xa, xb, xm = nodes[:, a], nodes[:, b], nodes[:, vertices + e]
        t = xb - xa
        t /= np.linalg.norm(t, axis=1, keepdims=True)
        d = xm - xa
        worst = np.maximum(worst, np.linalg.norm(d - np.sum(d * t, axis=1)[:, None] * t, axis=1))
    return worst


def piece_integrals(nodes: _Array, rule: tuple[_Array, _Array]) -> _Array:
    r""":math:`\int N_j\, dA` of each face by the pieces' rule, ``(F, K)``.

    The face's corner polygon is drawn in its plane and cut into triangles from its
    first corner; ``rule`` on each is pulled back to the face along the normal, as
    :meth:`~dolfinx_contact_s2s.segmentation.PolygonSegmentation.points` pulls back the
    points of the pieces (flat faces: the ratio of area elements is 1).
    """
    F, K, _ = nodes.shape
    element = polygon.face_element(K)
    corners = polygon.corner_nodes(nodes)
    x0 = corners[:, 0]
    e1 = corners[:, 1] - x0
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    n = np.cross(corners[:, 1] - x0, corners[:, -1] - x0)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    frame = np.stack([e1, np.cross(n, e1), n], axis=1)
    plane = np.einsum("fmg,fdg->fmd", corners - x0[:, None], frame[:, :2])
    X, W = rule
    rows = np.repeat(np.arange(F, dtype=np.int32), W.size)
    integrals = np.zeros((F, element.dim))
    for k in range(1, corners.shape[1] - 1):  # The fan from the first corner.
        a, ab, ac = plane[:, 0], plane[:, k] - plane[:, 0], plane[:, k + 1] - plane[:, 0]
        det = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
        p = a[:, None] + X[None, :, :1] * ab[:, None] + X[None, :, 1:] * ac[:, None]
        x = x0[:, None] + np.einsum("fqd,fdg->fqg", p, frame[:, :2])
        xi, _ = polygon.intersect(
            nodes, rows, x.reshape(-1, 3), np.repeat(n, W.size, axis=0), name="face"
        )
        phi = element.tabulate(0, xi)[0, :, :, 0].reshape(F, W.size, -1)
        integrals += np.einsum("fqj,q,f->fj", phi, W, det)
    return integrals


def rule_error(nodes: _Array, rule: tuple[_Array, _Array]) -> _Array:
    r"""Relative error of :func:`piece_integrals` on each face, ``(F,)``.

    The exact :math:`\int N_j\, dA` is a Gauss rule in reference coordinates (exact on
    flat faces, where the area element is a polynomial); the largest difference over
    :math:`j`, divided by the face's area.
    """
    F, K, _ = nodes.shape
    if F == 0:
        return np.zeros(0)
    cell, degree = polygon.FACE_ELEMENTS[K]
    X, W = basix.make_quadrature(basix.CellType[cell], 4 * degree + 2)
    rows = np.repeat(np.arange(F, dtype=np.int32), W.size)
    _, dx = polygon.evaluate(nodes, rows, np.tile(X, (F, 1)))
    jac = np.linalg.norm(np.cross(dx[:, :, 0], dx[:, :, 1]), axis=1).reshape(F, W.size)
    phi = polygon.face_element(K).tabulate(0, X)[0, :, :, 0]
    exact = np.einsum("qj,q,fq->fj", phi, W, jac)
    return np.abs(piece_integrals(nodes, rule) - exact).max(axis=1) / exact.sum(axis=1)


def face_rule(
    surfaces: Sequence, degree: int, comm: MPI.Comm
) -> tuple[tuple[_Array, _Array], int, float]:
    r"""The triangle rule for the pieces of a pair's faces (collective).

    Args:
        surfaces: The pair's contact surfaces (their ``data.coefficients`` are the face
            nodes).
        degree: The degree that integrates Eq. (40) exactly on affine faces.
        comm: The surfaces' communicator: every rank ends with the same rule.

    Returns:
        ``(rule, degree, error)``: the rule, its degree, and the largest measured
        relative error of :func:`rule_error` (0 when every flat face is affine).
    """
    faces = [s.data.coefficients for s in surfaces if len(s.data)]
    flat = [f[non_affine(f)[0]] for f in faces]
    flat = [f for f in flat if f.shape[0]]
    measured = comm.allreduce(bool(flat), op=MPI.LOR)
    q = int(degree)
    if not measured:
        return triangle_rule(q), q, 0.0
    while True:
        rule = triangle_rule(q)
        local = max((float(rule_error(f, rule).max()) for f in flat), default=0.0)
        error = comm.allreduce(local, op=MPI.MAX)
        if error <= RULE_TOLERANCE or q >= MAX_RULE_DEGREE:
            break
        q += 2
    if error > RULE_TOLERANCE:
        logger.warning(
            "the composite rule on non-affine faces reached degree %d with a relative "
            "error of %.1e on the faces' own integrals (the patch test holds to about "
            "that): the faces are close to degenerate",
            q,
            error,
        )
    return rule, q, error


def contact_rule(
    contactor: typing.Any,
    targets: Sequence,
    quadrature: str,
    points: int | None,
    degree: int,
    axisymmetric: bool,
) -> tuple[tuple[_Array, _Array], int, int, float]:
    r"""The rule of Eq. (17) for a pair, on edges or on the pieces of faces (collective).

    Args:
        contactor: The contactor surface.
        targets: The meshed target surfaces.
        quadrature: One of :data:`~dolfinx_contact_s2s.quadrature.RULES`.
        points: Points per (sub-)segment on edges, or ``None``: the fewest Gauss points
            that integrate the multiplier (degree :math:`s`) times a displacement
            function (:math:`k`) exactly, plus one per curved geometry degree
            :math:`c`, :math:`\lfloor (s + k + 2c)/2 \rfloor + 1`, or :math:`s + k + 1`
            Newton-Cotes points; in axisymmetry :math:`k` counts :math:`r`'s degree too.
        degree: The multiplier degree :math:`s`.
        axisymmetric: Whether Eq. (17) carries the weight :math:`2\pi r`.

    Returns:
        ``(rule, points, rule_degree, rule_error)``: points and weights on :math:`[0, 1]`
        or on the reference triangle; on faces, the triangle rule's degree (:math:`Q_k`
        counted as total degree :math:`2k`) and its measured error (:func:`face_rule`),
        on edges ``points`` and ``2 points - 1`` (Gauss) and 0.
    """
    curved = contactor.cmap.degree - 1 + max((t.cmap.degree - 1 for t in targets), default=0)
    k_u = max([contactor.element.degree, *(t.element.degree for t in targets)])
    # In axisymmetry the weight 2 pi r raises the integrand's degree by r's.
    k_u += contactor.cmap.degree if axisymmetric else 0
    if points is None:
        if quadrature.endswith("newton-cotes"):
            points = max(degree + k_u, 1) + 1
        else:
            points = (degree + k_u + 2 * curved) // 2 + 1
    points = int(points)
    if contactor.facet_dim != 2:
        return interval_rule(quadrature, points), points, 2 * points - 1, 0.0
    surfaces = (contactor, *targets)
    quad = [2 if s.cell_type.name == "hexahedron" else 1 for s in surfaces]
    k_t = max(q * s.element.degree for q, s in zip(quad, surfaces, strict=True))
    rule, rule_degree, error = face_rule(
        surfaces, quad[0] * degree + k_t + 2 * curved, contactor.comm
    )
    return rule, points, rule_degree, error

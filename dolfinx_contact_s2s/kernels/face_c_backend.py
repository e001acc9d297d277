# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Compiled (C, through CFFI) kernels of the contact assembly on faces of 3D cells.

The functions of :mod:`~dolfinx_contact_s2s.kernels.face_backend` (the NumPy reference)
with the same names, signatures and meanings. Compiled: the face geometry
(:func:`evaluate`, :func:`outward_normals`), the Newton pull-back of points along lines
onto faces (:func:`intersect`, :func:`intersect_lines`, Eq. 38; ``_faces.c``), and from
:mod:`~dolfinx_contact_s2s.kernels.c_backend` the clipping and triangulation of the
overlap polygons (Fig. 15(b)) and the local blocks of Eqs. (40)-(42). The set-up work
done once per surface (:func:`facet_coefficients`, :func:`bounding_boxes`,
:func:`shift`) stays NumPy. Results agree with the reference to round-off (Basix
tabulates and LAPACK solves in another order; ``tests/test_face_kernels.py``); the
clipping and the local blocks agree to the last bit.

Load it through :func:`~dolfinx_contact_s2s.kernels.get_backend` (``"c"`` or
``"auto"`` with ``facet_dim=2``), which compiles the C sources on rank 0 first.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels import c_backend, polygon
from dolfinx_contact_s2s.kernels.c_backend import (
    box_overlaps,
    clip_polygons,
    coo_to_csr,
    csr_slots,
    segment_to_segment,
    triangulate_polygons,
)
from dolfinx_contact_s2s.kernels.face_backend import (
    FACET_DIM,
    bounding_boxes,
    facet_coefficients,
    monomial_values,
    monomials,
    runs,
    shift,
    tangents,
)
from dolfinx_contact_s2s.kernels.numpy_backend import NEWTON_TOL, ROUND_OFF

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

#: The backend's name (:data:`~dolfinx_contact_s2s.kernels.BACKENDS`).
NAME = "c"

_Array = npt.NDArray[np.float64]
_Rows = npt.NDArray[np.int32]


def _ptr(ffi, a: np.ndarray, ctype: str = "double *"):
    return ffi.cast(ctype, ffi.from_buffer(a)) if a.size else ffi.NULL


def _nodes(nodes: _Array) -> tuple[_Array, int]:
    """C-contiguous face nodes ``(F, K, 3)`` of a supported face element, and ``K``."""
    c = np.ascontiguousarray(nodes, dtype=np.float64)
    if c.ndim != 3 or c.shape[2] != 3:
        raise ValueError(f"face nodes must be (F, K, 3), not {c.shape}")
    polygon.face_element(c.shape[1])  # A ValueError naming the supported elements.
    return c, c.shape[1]


def evaluate(
    coefficients: _Array, rows: _Rows, xi: _Array, derivatives: int = 1
) -> tuple[_Array, ...]:
    r"""Points :math:`x(\xi)` ``(P, 3)`` and tangents :math:`\partial x/\partial \xi` ``(P, 3, 2)``.

    Raises:
        NotImplementedError: For second derivatives (no kernel of the faces uses them).
    """
    if derivatives != 1:
        raise NotImplementedError("face kernels evaluate first derivatives only")
    ffi, lib = c_backend.compiled()
    c, K = _nodes(coefficients)
    rows = np.ascontiguousarray(rows, dtype=np.int32)
    xi = np.ascontiguousarray(np.reshape(xi, (-1, 2)), dtype=np.float64)
    P = rows.size
    x, dx = np.empty((P, 3)), np.empty((P, 3, 2))
    lib.s2s_face_evaluate(
        _ptr(ffi, c), K, _ptr(ffi, rows, "int32_t *"), _ptr(ffi, xi), P,
        _ptr(ffi, x), _ptr(ffi, dx),
    )  # fmt: skip
    return x, dx


def outward_normals(coefficients: _Array, orientation: _Array, rows: _Rows, xi: _Array) -> _Array:
    r"""Unit outward normals: the orientation times :math:`\partial_1 x \times \partial_2 x`."""
    _, dx = evaluate(coefficients, rows, xi)
    n = np.cross(dx[:, :, 0], dx[:, :, 1])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return orientation[rows, None] * n


def intersect_lines(
    nodes: _Array,
    rows: _Rows,
    origins: _Array,
    directions: _Array,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
    name: str = "face",
) -> tuple[_Array, _Array]:
    r"""Where the lines :math:`o + t d` cross the faces: :func:`~.polygon.intersect` in C.

    The same start (the flat face through nodes 0, 1, 2), Newton iteration and stopping
    test, per line (a line stops when its own step is small).

    Returns:
        ``(xi, t)``: reference coordinates ``(P, 2)`` and line parameters ``(P,)``.

    Raises:
        RuntimeError: Naming the faces (by row) whose line runs along them, or where
            Newton's method does not converge (as the reference does).
    """
    ffi, lib = c_backend.compiled()
    c, K = _nodes(nodes)
    rows = np.ascontiguousarray(rows, dtype=np.int32)
    o = np.ascontiguousarray(origins, dtype=np.float64)
    d = np.ascontiguousarray(directions, dtype=np.float64)
    P = rows.size
    xi, t, ok = np.empty((P, 2)), np.empty(P), np.empty(P, dtype=np.int8)
    lib.s2s_face_intersect(
        _ptr(ffi, c), K, _ptr(ffi, rows, "int32_t *"), _ptr(ffi, o), _ptr(ffi, d), P,
        int(iterations), float(tol), float(ROUND_OFF), _ptr(ffi, xi), _ptr(ffi, t),
        _ptr(ffi, ok, "int8_t *"),
    )  # fmt: skip
    polygon.check_lines(rows, ok.astype(bool), name, iterations)
    return xi, t


def intersect(
    coefficients: _Array,
    rows: _Rows,
    origins: _Array,
    directions: _Array,
    iterations: int = 16,
    tol: float = NEWTON_TOL,
) -> _Array:
    r"""Reference coordinates where the lines ``origins + t directions`` cross the faces (Eq. 38).

    :func:`intersect_lines` without the line parameters, ``(P, 2)``.
    """
    eta, _ = intersect_lines(coefficients, rows, origins, directions, iterations, tol)
    return eta


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
    """:func:`~.face_backend.face_coupling` in one pass over the points (``_faces.c``).

    Raises:
        ValueError: For monomial tables of degree above 3 or more than 16 functions.
        RuntimeError: Naming the points whose target line Newton's method misses.
    """
    ffi, lib = c_backend.compiled()
    c, Kc = _nodes(c_nodes)
    t, Kt = _nodes(t_nodes)
    orientation = np.ascontiguousarray(c_orientation, dtype=np.float64)
    rc, rt = (np.ascontiguousarray(r, dtype=np.int32) for r in rows)
    weights = np.ascontiguousarray(weights, dtype=np.float64)
    S, Q = weights.shape
    xi = np.ascontiguousarray(np.reshape(xi, (S * Q, 2)), dtype=np.float64)
    arrays, args = [], []  # the tables, kept alive through the call, and their pointers
    for coef, index in bases:
        coef = np.ascontiguousarray(coef, dtype=np.float64)
        if coef.shape[1] not in (1, 4, 9, 16) or coef.shape[2] > 16:
            raise ValueError(f"monomial tables up to degree 3, 16 functions, not {coef.shape}")
        index = np.ascontiguousarray(index, dtype=np.int32)
        arrays += [coef, index]
        args += [_ptr(ffi, coef), coef.shape[1], coef.shape[2], _ptr(ffi, index, "int32_t *")]
    nk, nc, nt = (a.shape[2] for a in arrays[::2])
    axis, which = (np.zeros(3), 0) if tangent is None else tangent
    axis = np.ascontiguousarray(axis, dtype=np.float64)
    first = runs(rc, rt)
    B = first.size  # the blocks, allocated as they are written (no untouched pages)
    b_c, b_t = np.empty((B, nk, nc * 3)), np.empty((B, nk, nt * 3))
    g, coverage, ok = np.empty((B, nk)), np.empty((B, nk)), np.empty(S * Q, dtype=np.int8)
    lib.s2s_face_coupling(
        _ptr(ffi, c), Kc, _ptr(ffi, orientation), _ptr(ffi, t), Kt,
        _ptr(ffi, rc, "int32_t *"), _ptr(ffi, rt, "int32_t *"), _ptr(ffi, xi),
        _ptr(ffi, weights), S, Q, *args, int(bool(square)), int(iterations), float(tol),
        float(ROUND_OFF), float(zero_below), _ptr(ffi, axis), int(which), _ptr(ffi, b_c),
        _ptr(ffi, b_t), _ptr(ffi, g),
        _ptr(ffi, coverage), _ptr(ffi, ok, "int8_t *"),
    )  # fmt: skip
    polygon.check_lines(np.arange(S * Q), ok.astype(bool), "target point", iterations)
    return b_c, b_t, g, coverage, first


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
    """:func:`~.face_backend.piece_gaps` in one pass over the pieces (``_faces.c``)."""
    ffi, lib = c_backend.compiled()
    c, Kc = _nodes(c_nodes)
    t, Kt = _nodes(t_nodes)
    co = np.ascontiguousarray(c_orientation, dtype=np.float64)
    rc, rt = (np.ascontiguousarray(r, dtype=np.int32) for r in rows)
    triangles, origin, frame = (
        np.ascontiguousarray(a, dtype=np.float64) for a in (triangles, origin, frame)
    )
    S = rc.size
    gap, ok_c, ok_t = np.empty(S), np.empty(S, dtype=np.int8), np.empty(S, dtype=np.int8)
    lib.s2s_face_piece_gaps(
        _ptr(ffi, c), Kc, _ptr(ffi, co), _ptr(ffi, t), Kt, _ptr(ffi, rc, "int32_t *"),
        _ptr(ffi, rt, "int32_t *"), _ptr(ffi, triangles), _ptr(ffi, origin), _ptr(ffi, frame),
        S, int(iterations), float(tol), float(ROUND_OFF), _ptr(ffi, gap),
        _ptr(ffi, ok_c, "int8_t *"), _ptr(ffi, ok_t, "int8_t *"),
    )  # fmt: skip
    polygon.check_lines(rc, ok_c.astype(bool), "contactor face", iterations)
    polygon.check_lines(rt, ok_t.astype(bool), "target face", iterations)
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
    """:func:`~.face_backend.piece_points` in one pass over the pieces (``_faces.c``)."""
    ffi, lib = c_backend.compiled()
    c, K = _nodes(nodes)
    rows = np.ascontiguousarray(rows, dtype=np.int32)
    triangles, origin, frame = (
        np.ascontiguousarray(a, dtype=np.float64) for a in (triangles, origin, frame)
    )
    X, W = (np.ascontiguousarray(r, dtype=np.float64) for r in rule)
    S, Q = rows.size, W.size
    xi, weights, ok = np.empty((S, Q, 2)), np.empty((S, Q)), np.empty(S * Q, dtype=np.int8)
    lib.s2s_face_piece_points(
        _ptr(ffi, c), K, _ptr(ffi, rows, "int32_t *"), _ptr(ffi, triangles), _ptr(ffi, origin),
        _ptr(ffi, frame), S, _ptr(ffi, X), _ptr(ffi, W), Q, int(iterations), float(tol),
        float(ROUND_OFF), _ptr(ffi, xi), _ptr(ffi, weights), _ptr(ffi, ok, "int8_t *"),
    )  # fmt: skip
    polygon.check_lines(np.repeat(rows, Q), ok.astype(bool), "contactor face", iterations)
    return xi, weights


def project_faces(
    c_nodes: _Array,
    c_orientation: _Array,
    t_nodes: _Array,
    t_orientation: _Array,
    ic: _Rows,
    it: _Rows,
    round_off: float = ROUND_OFF,
) -> tuple[_Array, _Array, _Array, _Array, npt.NDArray[np.bool_]]:
    """:func:`~.polygon.project_faces` in one pass over the candidate pairs (``_faces.c``).

    Raises:
        ValueError: Naming a contactor or target face of zero area (as the reference).
    """
    ffi, lib = c_backend.compiled()
    c, Kc = _nodes(c_nodes)
    t, Kt = _nodes(t_nodes)
    co, to = (np.ascontiguousarray(o, dtype=np.float64) for o in (c_orientation, t_orientation))
    ic, it = (np.ascontiguousarray(r, dtype=np.int32) for r in (ic, it))
    N = ic.size
    mc, mt = (3 if K in (3, 6) else 4 for K in (Kc, Kt))
    origin, frame = np.empty((N, 3)), np.empty((N, 3, 3))
    c_poly, t_poly = np.empty((N, mc, 2)), np.empty((N, mt, 2))
    facing, ok_c, ok_t = (np.empty(N, dtype=np.int8) for _ in range(3))
    lib.s2s_face_project(
        _ptr(ffi, c), Kc, _ptr(ffi, co), _ptr(ffi, t), Kt, _ptr(ffi, to),
        _ptr(ffi, ic, "int32_t *"), _ptr(ffi, it, "int32_t *"), N, float(round_off),
        _ptr(ffi, origin), _ptr(ffi, frame), _ptr(ffi, c_poly), _ptr(ffi, t_poly),
        _ptr(ffi, facing, "int8_t *"), _ptr(ffi, ok_c, "int8_t *"), _ptr(ffi, ok_t, "int8_t *"),
    )  # fmt: skip
    if not (np.all(ok_c) and np.all(ok_t)):  # The reference names the faces.
        polygon.project_faces(c_nodes, c_orientation, t_nodes, t_orientation, ic, it, round_off)
    return origin, frame, c_poly, t_poly, facing.astype(bool)

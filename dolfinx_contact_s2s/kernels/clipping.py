# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Convex polygons in the plane: their overlap and its triangles (Fig. 15(b) on faces).

The plane geometry of :mod:`~dolfinx_contact_s2s.kernels.polygon`, on polygons given by
their vertices in plane coordinates: :func:`clip_convex` (Sutherland-Hodgman, with a
round-off snapping rule so that shared edges and vertices leave no slivers) and
:func:`triangulate` (a fan from the vertex centroid), one polygon at a time, and their
batched forms over padded arrays, :func:`clip_polygons` and :func:`triangulate_polygons`.

This is the NumPy reference, a Python loop over the pairs (about 0.1 ms a pair).
:mod:`~dolfinx_contact_s2s.kernels.c_backend` has :func:`clip_polygons` and
:func:`triangulate_polygons` with the same signatures and the same results to the last
bit (``tests/test_polygon_kernels.py``).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels.numpy_backend import ROUND_OFF

__all__ = ["clip_convex", "clip_polygons", "signed_area", "triangulate", "triangulate_polygons"]

_Array = npt.NDArray[np.float64]
_Rows = npt.NDArray[np.int32]


def signed_area(poly: _Array) -> _Array:
    """Signed areas of polygons ``(..., m, 2)`` (positive counter-clockwise)."""
    x, y = poly[..., 0], poly[..., 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=-1) - np.roll(x, -1, axis=-1) * y, axis=-1)


def clip_convex(subject: _Array, clip: _Array, round_off: float = ROUND_OFF) -> _Array:
    r"""The overlap of two convex polygons in the plane (Sutherland-Hodgman).

    ``subject`` is cut by the half-plane to the left of each edge of ``clip``. A vertex
    closer to an edge's line than ``round_off`` times the polygons' size is taken to lie
    on it, so shared edges and vertices give no slivers; consecutive vertices closer
    than that are merged. Either orientation is accepted.

    Args:
        subject: Vertices of a convex polygon, ``(m, 2)``.
        clip: Vertices of a convex polygon, ``(k, 2)``.
        round_off: Relative round-off of the coordinates.

    Returns:
        The vertices of the overlap, counter-clockwise, ``(r, 2)``; ``(0, 2)`` when the
        polygons are disjoint or overlap in no area (a shared edge or vertex, or a
        polygon of zero area).
    """
    subject = np.asarray(subject, dtype=np.float64).reshape(-1, 2)
    clip = np.asarray(clip, dtype=np.float64).reshape(-1, 2)
    empty = np.zeros((0, 2))
    if subject.shape[0] < 3 or clip.shape[0] < 3:
        return empty
    centre = clip.mean(axis=0)
    subject, clip = subject - centre, clip - centre
    size = max(np.max(np.abs(subject)), np.max(np.abs(clip)))
    tol = round_off * size
    if signed_area(subject) < 0.0:
        subject = subject[::-1]
    if signed_area(clip) < 0.0:
        clip = clip[::-1]
    if not signed_area(clip) > tol * size:
        return empty
    poly = subject
    for a, b in zip(clip, np.roll(clip, -1, axis=0), strict=True):
        e = b - a
        length = np.hypot(e[0], e[1])
        if length <= tol:
            continue
        d = (e[0] * (poly[:, 1] - a[1]) - e[1] * (poly[:, 0] - a[0])) / length
        d[np.abs(d) <= tol] = 0.0
        if np.all(d <= 0.0):
            return empty
        if np.all(d >= 0.0):
            continue
        nxt, dn = np.roll(poly, -1, axis=0), np.roll(d, -1)
        crossing = ((d > 0.0) & (dn < 0.0)) | ((d < 0.0) & (dn > 0.0))
        s = np.where(crossing, d / np.where(crossing, d - dn, 1.0), 0.0)
        candidates = np.stack([poly, poly + s[:, None] * (nxt - poly)], axis=1)
        poly = candidates[np.stack([d >= 0.0, crossing], axis=1)]
    # Merge coinciding consecutive vertices.
    keep = np.linalg.norm(poly - np.roll(poly, 1, axis=0), axis=1) > tol
    poly = poly[keep] if keep.any() else poly[:1]
    if poly.shape[0] < 3 or not signed_area(poly) > tol * size:
        return empty
    return poly + centre


def triangulate(polygon: _Array, round_off: float = ROUND_OFF) -> _Array:
    r"""Triangles of a convex polygon: a fan from the mean of its vertices.

    The fan from the vertex centroid (inside a convex polygon) gives one triangle per
    edge, better shaped than the fan from the first vertex, whose triangles are slivers
    when clipping leaves nearly collinear vertices. The centroid is strictly inside a
    convex polygon of positive area, so only the triangles on edges of round-off length
    (repeated vertices) are flat: those of area below ``round_off`` times the polygon's
    size squared are dropped.

    Args:
        polygon: Vertices of a convex polygon, counter-clockwise, ``(m, 2)``.
        round_off: Relative round-off of the coordinates.

    Returns:
        Vertices of the triangles, counter-clockwise, ``(T, 3, 2)``.
    """
    polygon = np.asarray(polygon, dtype=np.float64).reshape(-1, 2)
    if polygon.shape[0] < 3:
        return np.zeros((0, 3, 2))
    centre = polygon.mean(axis=0)
    rel = polygon - centre
    nxt = np.roll(rel, -1, axis=0)
    area = 0.5 * (rel[:, 0] * nxt[:, 1] - rel[:, 1] * nxt[:, 0])
    size = np.max(np.abs(rel))
    keep = area > round_off * size**2
    tris = np.stack([np.zeros_like(rel), rel, nxt], axis=1)[keep]
    return tris + centre


def _padded(polygons: _Array, counts: _Rows | None, name: str) -> tuple[_Array, _Rows]:
    """Padded polygons ``(P, m, 2)`` and their vertex counts (all ``m`` if None), checked."""
    v = np.asarray(polygons, dtype=np.float64)
    if v.ndim != 3 or v.shape[2] != 2:
        raise ValueError(f"{name} must be padded polygons (P, m, 2), not {v.shape}")
    n = np.full(v.shape[0], v.shape[1], np.int32) if counts is None else np.asarray(counts)
    if n.shape != v.shape[:1] or (n.size and (n.min() < 0 or n.max() > v.shape[1])):
        raise ValueError(f"{name} counts must be ({v.shape[0]},) in [0, {v.shape[1]}]")
    return v, n.astype(np.int32)


def clip_polygons(
    subject: _Array,
    clip: _Array,
    subject_counts: _Rows | None = None,
    clip_counts: _Rows | None = None,
    round_off: float = ROUND_OFF,
) -> tuple[_Array, _Rows]:
    r"""The overlaps of ``P`` pairs of convex polygons: :func:`clip_convex` on each pair.

    Polygons are padded: pair ``p`` clips ``subject[p, :subject_counts[p]]`` by
    ``clip[p, :clip_counts[p]]``. The overlap of convex polygons with :math:`m_s` and
    :math:`m_c` vertices has at most :math:`m_s + m_c` (each cut by an edge's line adds
    at most one).

    Args:
        subject: Vertices of the subject polygons, ``(P, ms, 2)``.
        clip: Vertices of the clip polygons, ``(P, mc, 2)``.
        subject_counts: Vertices of each subject polygon, ``(P,)``; None: ``ms`` each.
        clip_counts: Vertices of each clip polygon, ``(P,)``; None: ``mc`` each.
        round_off: Relative round-off of the coordinates.

    Returns:
        ``(overlap, counts)``: the overlaps, counter-clockwise, padded with zeros,
        ``(P, ms + mc, 2)``, and their numbers of vertices, ``(P,)`` (0 if empty).

    Raises:
        ValueError: For inconsistent shapes or counts, or an overlap with more than
            ``ms + mc`` vertices (polygons that are not convex).
    """
    subject, ns = _padded(subject, subject_counts, "subject")
    clip, nc = _padded(clip, clip_counts, "clip")
    if clip.shape[0] != subject.shape[0]:
        raise ValueError(f"{subject.shape[0]} subject polygons but {clip.shape[0]} clip polygons")
    width = subject.shape[1] + clip.shape[1]
    out = np.zeros((subject.shape[0], width, 2))
    counts = np.zeros(subject.shape[0], dtype=np.int32)
    for p in range(subject.shape[0]):
        piece = clip_convex(subject[p, : ns[p]], clip[p, : nc[p]], round_off)
        if piece.shape[0] > width:
            raise ValueError(
                f"pair {p}: the overlap has more than {width} vertices: the polygons are not convex"
            )
        out[p, : piece.shape[0]] = piece
        counts[p] = piece.shape[0]
    return out, counts


def triangulate_polygons(
    polygons: _Array, counts: _Rows | None = None, round_off: float = ROUND_OFF
) -> tuple[_Array, _Rows]:
    """The triangles of padded convex polygons: :func:`triangulate` on each.

    Args:
        polygons: Vertices, counter-clockwise, ``(P, m, 2)``.
        counts: Vertices of each polygon, ``(P,)``; None: ``m`` each.
        round_off: Relative round-off of the coordinates.

    Returns:
        ``(triangles, polygon)``: the triangles of all polygons, counter-clockwise, in
        the order of the polygons, ``(T, 3, 2)``, and the polygon of each, ``(T,)``.
    """
    polygons, n = _padded(polygons, counts, "polygon")
    tris = [np.zeros((0, 3, 2))] + [
        triangulate(v[:k], round_off) for v, k in zip(polygons, n, strict=True)
    ]
    owner = np.repeat(np.arange(n.size, dtype=np.int32), [t.shape[0] for t in tris[1:]])
    return np.concatenate(tris), owner

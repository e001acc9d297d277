# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Contact search: which contactor facets face which target facets, and where.

Stages shared by every discretization of :mod:`dolfinx_contact_s2s.pair`, as functions
that return new arrays and set nothing on their arguments:

- candidate pairs of facets from bounding boxes padded by the search radius, or swept
  along the normals (:func:`box_pairs`, :func:`candidates`, :func:`swept_boxes`; the
  sub-segments of Fig. 15(b) are cut from such candidates by
  :mod:`dolfinx_contact_s2s.segmentation`);
- the target point :math:`x_T^{i*}` met along the normal :math:`N = -n_C` from a
  contactor point (Eq. 38, Fig. 7(b)), the nearest over several target surfaces
  (:func:`find_targets`), and its distance to the nearest target node
  (:func:`node_offsets`, for node-to-node and the two-pass method).

Target facets are passed as arrays, gathered on every process
(:meth:`~dolfinx_contact_s2s.surface.ContactSurface.gather`), with the kernels
(:mod:`dolfinx_contact_s2s.kernels`) that evaluate them.
"""

from __future__ import annotations

import typing
from collections.abc import Sequence
from dataclasses import dataclass

from mpi4py import MPI

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels import KernelBackend, numpy_backend
from dolfinx_contact_s2s.surface import ContactSurface, SurfaceData

__all__ = [
    "Hits",
    "box_pairs",
    "candidates",
    "default_search_radius",
    "find_targets",
    "node_offsets",
    "swept_boxes",
]


@dataclass(frozen=True)
class Hits:
    """Contactor points that meet a target along their normal (Eq. 38).

    Attributes:
        points: Index of the point in the arrays passed to :func:`find_targets`.
        target: Index of the target surface met.
        rows: Row of the target facet met, in that target's gathered data.
    """

    points: npt.NDArray[np.int64]
    target: npt.NDArray[np.int32]
    rows: npt.NDArray[np.int32]


def box_pairs(
    a: npt.NDArray[np.floating],
    b: npt.NDArray[np.floating],
    backend: KernelBackend | None = None,
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
    """All pairs of overlapping boxes, by sweep and prune along the longest axis.

    Args:
        a: Boxes ``(na, 2, gdim)`` (lower and upper corners).
        b: Boxes ``(nb, 2, gdim)``.
        backend: The kernels that test the candidates (``box_overlaps``); None: NumPy.

    Returns:
        Indices ``(ia, ib)`` of the overlapping pairs.
    """
    empty = np.empty(0, dtype=np.int32)
    if a.shape[0] == 0 or b.shape[0] == 0:
        return empty, empty
    # The spread of the centres (twice: halving is exact) one axis at a time: NumPy
    # reduces a narrow array along its first axis twenty times slower.
    spread = []
    for g in range(a.shape[2]):
        centres = np.concatenate([a[:, 0, g] + a[:, 1, g], b[:, 0, g] + b[:, 1, g]])
        spread.append(centres.max() - centres.min())
    axis = int(np.argmax(spread))
    order = np.argsort(b[:, 0, axis], kind="stable")
    b_lo = b[order, 0, axis]
    width = float(np.max(b[:, 1, axis] - b[:, 0, axis]))
    start = np.searchsorted(b_lo, a[:, 0, axis] - width, side="left")
    stop = np.searchsorted(b_lo, a[:, 1, axis], side="right")
    kernels = numpy_backend if backend is None else backend
    return kernels.box_overlaps(a, b, order, start, stop)


def default_search_radius(contactor: ContactSurface, targets: Sequence[ContactSurface]) -> float:
    """The largest facet of the contactor and all targets, over all processes (collective)."""
    local = max(float(np.max(s.sizes(s.data), initial=0.0)) for s in (contactor, *targets))
    return contactor.comm.allreduce(local, op=MPI.MAX)


def candidates(
    boxes: npt.NDArray[np.floating], target_boxes: npt.NDArray[np.floating], radius: float
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
    """Pairs (box, target box) that overlap once ``boxes`` are padded by ``radius``."""
    padded = boxes.copy()
    padded[:, 0] -= radius
    padded[:, 1] += radius
    return box_pairs(padded, target_boxes)


def swept_boxes(
    boxes: npt.NDArray[np.floating], coefficients: npt.NDArray[np.floating], radius: float
) -> npt.NDArray[np.floating]:
    r"""Boxes of edges (facets of 2D cells) moved by up to ``radius`` along their normals.

    A straight edge swept along :math:`\pm r \mathbf n` covers a parallelogram whose
    box is the edge's box grown by :math:`r |n_x|` and :math:`r |n_y|`; a curved edge's
    box grows by :math:`r` in every direction.

    Args:
        boxes: The edges' boxes ``(F, 2, 2)``
            (:meth:`~dolfinx_contact_s2s.surface.ContactSurface.bounding_boxes`).
        coefficients: The edges' monomial coefficients ``(F, p + 1, 2)``.
        radius: The search radius.

    Returns:
        New boxes ``(F, 2, 2)``.
    """
    boxes = boxes.copy()
    c = coefficients
    pad = np.full((c.shape[0], boxes.shape[2]), radius)
    straight = np.all(c[:, 2:] == 0.0, axis=(1, 2))
    tangent = c[straight, 1]
    length = np.sqrt(np.einsum("fg,fg->f", tangent, tangent))[:, None]
    pad[straight] = radius * np.abs(tangent[:, ::-1]) / length
    boxes[:, 0] -= pad
    boxes[:, 1] += pad
    return boxes


def _inside(
    eta: npt.NDArray[np.floating], num_nodes: int, tol: float
) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.floating]]:
    r"""Whether facet parameters lie on the facet (within ``tol``), and them moved onto it.

    Edges: :math:`\eta \in [0, 1]`; faces (``eta`` of shape ``(P, 2)``): the square
    :math:`[0, 1]^2`, or the triangle :math:`\eta_1, \eta_2 \ge 0`,
    :math:`\eta_1 + \eta_2 \le 1` of faces with 3 or 6 nodes.
    """
    if eta.ndim == 1:
        return (eta >= -tol) & (eta <= 1 + tol), np.clip(eta, 0.0, 1.0)
    inside = np.all(eta >= -tol, axis=1)
    clipped = np.clip(eta, 0.0, 1.0)
    if num_nodes in (3, 6):
        total = eta.sum(axis=1)
        inside &= total <= 1 + tol
        clipped /= np.maximum(clipped.sum(axis=1), 1.0)[:, None]
    else:
        inside &= np.all(eta <= 1 + tol, axis=1)
    return inside, clipped


def _hits_on(
    T: SurfaceData,
    boxes: npt.NDArray[np.floating],
    backend: KernelBackend,
    x: npt.NDArray[np.floating],
    normals: npt.NDArray[np.floating],
    radius: float,
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32], npt.NDArray[np.floating]]:
    """Every (point, facet) of one target met along the normal, with the signed gap."""
    ip, it = candidates(np.stack([x, x], axis=1), boxes, radius)
    c = T.coefficients
    eta = backend.intersect(c, it, x[ip], normals[ip])
    inside, eta = _inside(eta, c.shape[1], 1e-10)
    x_t, _ = backend.evaluate(c, it, eta)
    gap = np.einsum("pg,pg->p", x[ip] - x_t, normals[ip])
    n_t = backend.outward_normals(c, T.orientation, it, eta)
    facing = np.einsum("pg,pg->p", n_t, normals[ip]) > 0
    ok = inside & facing & (np.abs(gap) <= radius)
    return ip[ok], it[ok], gap[ok]


def find_targets(
    x: npt.NDArray[np.floating],
    normals: npt.NDArray[np.floating],
    gathered: Sequence[SurfaceData],
    boxes: Sequence[npt.NDArray[np.floating]],
    backends: Sequence[KernelBackend],
    radius: float,
) -> Hits:
    r"""The target facet hit along the normal from each contactor point (Eq. 38, Fig. 7(b)).

    Args:
        x: Contactor points, ``(P, gdim)``.
        normals: The direction :math:`\mathbf N = -\mathbf n_C` at each point.
        gathered: The facets of each target surface.
        boxes: Their boxes
            (:meth:`~dolfinx_contact_s2s.surface.ContactSurface.bounding_boxes`).
        backends: The kernels of each target.
        radius: Largest normal distance of a hit.

    Returns:
        The points that hit a facing target facet within the search radius, with the
        target and facet each of them hits: the nearest over all targets (any one of
        them where several are equally near).
    """
    found = [
        _hits_on(T, b, k, x, normals, radius)
        for T, b, k in zip(gathered, boxes, backends, strict=True)
    ]
    ip = np.concatenate([f[0] for f in found]).astype(np.int64)
    it = np.concatenate([f[1] for f in found]).astype(np.int32)
    gap = np.concatenate([f[2] for f in found])
    which = np.repeat(np.arange(len(found), dtype=np.int32), [f[0].size for f in found])
    order = np.lexsort((np.abs(gap), ip))
    first = np.ones(order.size, dtype=bool)
    first[1:] = ip[order][1:] != ip[order][:-1]
    best = order[first]
    return Hits(ip[best], which[best], it[best])


def node_offsets(
    x: npt.NDArray[np.floating],
    normals: npt.NDArray[np.floating],
    T: SurfaceData,
    t_rows: npt.NDArray[np.int32],
    degree: int,
    backend: KernelBackend,
) -> npt.NDArray[np.floating]:
    r"""Distance from each contactor point's target point to the nearest target node.

    Args:
        x: Contactor points, ``(P, gdim)``.
        normals: The direction :math:`\mathbf N = -\mathbf n_C` at each point.
        T: The target's facets.
        t_rows: The target facet row each point meets.
        degree: The target's displacement degree (its nodes on a facet).
        backend: The target's kernels.
    """
    c = T.coefficients
    eta = backend.intersect(c, t_rows, x, normals)
    # Facet parameters of the target's Lagrange nodes (P1: ends; P2: ends and middle).
    nodes = np.linspace(0.0, 1.0, degree + 1)
    off = np.min(np.abs(eta[:, None] - nodes[None, :]), axis=1, initial=np.inf)
    x0, _ = backend.evaluate(c, t_rows, np.zeros(t_rows.size))
    x1, _ = backend.evaluate(c, t_rows, np.ones(t_rows.size))
    return off * np.linalg.norm(x1 - x0, axis=1)


_MOVED = {
    "SubSegments": "import it from dolfinx_contact_s2s (or dolfinx_contact_s2s.segmentation)",
    "sub_segments": "use ContactPair.sub_segments, or the cut of "
    "dolfinx_contact_s2s.segmentation.get_segmentation(facet_dim)",
}


def __getattr__(name: str) -> typing.Any:
    """Names that moved to :mod:`dolfinx_contact_s2s.segmentation` in 0.3.

    An ImportError, not an AttributeError: ``from ... import`` shows its message.
    """
    if name in _MOVED:
        raise ImportError(f"dolfinx_contact_s2s.search.{name} moved in 0.3: {_MOVED[name]}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

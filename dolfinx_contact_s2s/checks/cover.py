# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Contactor parts that face a contact surface other than their own pair's targets.

A pair integrates Eq. (17) only where its contactor faces one of *its* targets; a
multiplier whose support faces none carries no constraint (the contactor hangs over
the end of its target). When that part faces another contact surface instead (another
pair's target or contactor) within the search radius, the bodies overlap there without
any constraint: the answer is wrong, silently. The usual cause is a contactor side
split into two tags at the facet midpoints, each paired with the body under it, while
one facet lies over both bodies (Fig. 3 of the paper with the joint inside a facet).

:func:`unconstrained_parts` finds those parts with the sub-segments of the search
(the pair's :attr:`~dolfinx_contact_s2s.pair.ContactPair.segmentation`, Fig. 15(b)), whatever the
discretization; :func:`check_cover` raises on them. Both are collective and return or
raise the same on every process.
"""

from __future__ import annotations

import typing
from collections.abc import Sequence
from dataclasses import dataclass

from mpi4py import MPI

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels.numpy_backend import ROUND_OFF
from dolfinx_contact_s2s.search import box_pairs

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.pair import ContactPair
    from dolfinx_contact_s2s.surface import ContactSurface

__all__ = ["COVER_TOL", "Unconstrained", "check_cover", "unconstrained_parts"]

#: A part of a contactor facet shorter than this fraction of the facet (or than the
#: round-off of its node coordinates, see
#: :data:`~dolfinx_contact_s2s.kernels.numpy_backend.ROUND_OFF`) is not reported.
COVER_TOL: float = 1e-10


@dataclass(frozen=True)
class Unconstrained:
    """Parts of one pair's contactor that face other contact surfaces but not its targets.

    Attributes:
        pair: Position of the pair in the sequence checked.
        contactor: Tag of the pair's contactor surface.
        targets: Tags of the pair's own targets.
        faces: Tags of the other contact surfaces these parts face.
        facets: Number of contactor facets with such a part.
        length: Total length of the parts (parameter length times facet chord).
        facet_ends: End points of those facets, ``(facets, 2, gdim)``, sorted.
        parts: End points of the parts, ``(n, 2, gdim)``, sorted.
    """

    pair: int
    contactor: int
    targets: tuple[int, ...]
    faces: tuple[int, ...]
    facets: int
    length: float
    facet_ends: npt.NDArray[np.floating]
    parts: npt.NDArray[np.floating]


def _key(surface: ContactSurface) -> tuple[int, int]:
    return id(surface.V.mesh), int(surface.tag)


def _merge(
    rows: npt.NDArray[np.int32], lo: npt.NDArray[np.floating], hi: npt.NDArray[np.floating]
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    """Union of the intervals ``[lo, hi]`` on each facet ``rows``, sorted by facet."""
    if rows.size == 0:
        return rows, lo, hi
    order = np.lexsort((lo, rows))
    rows, lo, hi = rows[order], lo[order], hi[order]
    # Parameters lie in [0, 1]: shifted by twice the facet row, the facets never mix in
    # the running end (the shift serves the comparison only, the values stay exact).
    reach = np.maximum.accumulate(2.0 * rows + hi)
    start = np.ones(rows.size, dtype=bool)
    start[1:] = 2.0 * rows[1:] + lo[1:] > reach[:-1]
    first = np.flatnonzero(start)
    return rows[first], lo[first], np.maximum.reduceat(hi, first)


def _subtract(
    rows: npt.NDArray[np.int32],
    lo: npt.NDArray[np.floating],
    hi: npt.NDArray[np.floating],
    cover: tuple[npt.NDArray[np.int32], npt.NDArray[np.floating], npt.NDArray[np.floating]],
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    """The pieces of ``[lo, hi]`` on facets ``rows`` that the merged ``cover`` leaves out."""
    out_rows, out_lo, out_hi = [], [], []
    c_rows, c_lo, c_hi = cover
    starts = np.searchsorted(c_rows, rows, side="left")
    stops = np.searchsorted(c_rows, rows, side="right")
    for f, a, b, i, j in zip(rows, lo, hi, starts, stops, strict=True):
        # The cover of one facet is a few sorted, disjoint intervals.
        for s, e in zip(c_lo[i:j], c_hi[i:j], strict=True):
            if e <= a:
                continue
            if s >= b:
                break
            if s > a:
                out_rows.append(f)
                out_lo.append(a)
                out_hi.append(s)
            a = max(a, e)
            if a >= b:
                break
        if a < b:
            out_rows.append(f)
            out_lo.append(a)
            out_hi.append(b)
    return (
        np.asarray(out_rows, dtype=np.int32),
        np.asarray(out_lo, dtype=np.float64),
        np.asarray(out_hi, dtype=np.float64),
    )


def _sorted_points(points: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    """Rows of ``points`` ``(n, 2, gdim)`` in lexicographic order of their coordinates."""
    if points.shape[0] == 0:
        return points
    flat = points.reshape(points.shape[0], -1)
    return points[np.lexsort(flat.T[::-1])]


def _pieces(pair: ContactPair, surface: ContactSurface) -> typing.Any:
    """The pieces of ``pair``'s contactor against ``surface``, as against one of its targets."""
    T = surface.gather()
    ic, it = box_pairs(pair.swept_boxes(), surface.bounding_boxes(T))
    C = pair.contactor.data
    return pair.segmentation.cut(C, T, ic, it, pair.search_radius, pair.contactor.backend)


def unconstrained_parts(pairs: Sequence[ContactPair]) -> list[Unconstrained]:
    """Contactor parts that face other contact surfaces of ``pairs`` but not their targets.

    A part of a contactor facet of pair :math:`j` counts when it faces (normals opposed,
    within pair :math:`j`'s search radius, as the search pairs facets) a contactor or
    target surface of another pair, other than pair :math:`j`'s own contactor and
    targets, and none of pair :math:`j`'s targets. Parts that face nothing are legal:
    their multipliers carry no constraint.

    Args:
        pairs: The contact pairs of one problem.

    Returns:
        One :class:`Unconstrained` per pair with such parts, in the order of ``pairs``;
        the same on every process (collective).
    """
    surfaces: dict[tuple[int, int], ContactSurface] = {}
    for pair in pairs:
        for surface in (pair.contactor, *pair.targets):
            surfaces.setdefault(_key(surface), surface)
    found = []
    for j, pair in enumerate(pairs):
        cs = pair.contactor
        own = {_key(cs), *(_key(t) for t in pair.targets)}
        others = [s for k, s in surfaces.items() if k not in own]
        if not others or not pair.targets:  # analytic obstacles only: no pieces to cut
            continue
        C = cs.data
        pieces = [pair.sub_segments(k) for k in range(len(pair.targets))]
        cover = _merge(
            np.concatenate([p.contactor for p in pieces]).astype(np.int32),
            np.concatenate([p.lo for p in pieces]),
            np.concatenate([p.hi for p in pieces]),
        )
        sizes = cs.sizes(C)
        # Shorter than the round-off of the facet's nodes, or than COVER_TOL of it: no part.
        n = len(C)
        rows_all = np.arange(n, dtype=np.int32)
        _, x0, _ = cs.evaluate(C, rows_all, np.zeros(n))
        _, x1, _ = cs.evaluate(C, rows_all, np.ones(n))
        scale = np.maximum(np.max(np.abs(x0), axis=1, initial=0.0), np.max(np.abs(x1), axis=1))
        with np.errstate(divide="ignore", invalid="ignore"):
            shortest = np.maximum(COVER_TOL, ROUND_OFF * (scale + sizes) / sizes)
        # Facets their own targets cover whole (the usual case) need no interval arithmetic.
        whole = np.zeros(n, dtype=bool)
        ends = (cover[1] <= shortest[cover[0]]) & (cover[2] >= 1.0 - shortest[cover[0]])
        whole[cover[0][ends]] = True
        rows, lo, hi, faces = [], [], [], []
        for other in others:
            s = _pieces(pair, other)
            open_ = ~whole[s.contactor]
            r, a, b = _subtract(s.contactor[open_], s.lo[open_], s.hi[open_], cover)
            keep = b - a > shortest[r]
            rows.append(r[keep])
            lo.append(a[keep])
            hi.append(b[keep])
            faces.append(cs.comm.allreduce(bool(keep.any()), op=MPI.LOR))
        r, a, b = _merge(np.concatenate(rows), np.concatenate(lo), np.concatenate(hi))
        comm = cs.comm
        if comm.allreduce(r.size) == 0:
            continue
        _, xa, _ = cs.evaluate(C, r, a)
        _, xb, _ = cs.evaluate(C, r, b)
        facets = np.unique(r)
        ends = np.stack([x0[facets], x1[facets]], axis=1)
        length = float(np.sum((b - a) * sizes[r]))
        found.append(
            Unconstrained(
                pair=j,
                contactor=int(cs.tag),
                targets=tuple(int(t.tag) for t in pair.targets),
                faces=tuple(int(o.tag) for o, f in zip(others, faces, strict=True) if f),
                facets=comm.allreduce(int(facets.size)),
                length=comm.allreduce(length),
                facet_ends=_sorted_points(np.concatenate(comm.allgather(ends))),
                parts=_sorted_points(np.concatenate(comm.allgather(np.stack([xa, xb], axis=1)))),
            )
        )
    return found


def _point(x: npt.NDArray[np.floating]) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in x) + ")"


def check_cover(pairs: Sequence[ContactPair], shown: int = 3) -> None:
    """Raise if a contactor part faces other contact surfaces but none of its targets.

    Args:
        pairs: The contact pairs of one problem.
        shown: Facets named in the message, at most.

    Raises:
        ValueError: On every rank (collective), naming the contactor, its facets and the
            remedy: give the pair every target the contactor faces, or split the
            contactor's tags at a node where the target changes.
    """
    found = unconstrained_parts(pairs)
    if not found:
        return
    u = found[0]
    facets = "; ".join(f"{_point(e[0])} to {_point(e[1])}" for e in u.facet_ends[:shown]) + (
        "; ..." if u.facets > shown else ""
    )
    parts = "; ".join(f"{_point(p[0])} to {_point(p[1])}" for p in u.parts[:shown])
    tags = ", ".join(str(t) for t in u.targets)
    faces = ", ".join(str(t) for t in u.faces)
    more = f" (and {len(found) - 1} more pair(s) alike)" if len(found) > 1 else ""
    raise ValueError(
        f"pair {u.pair}: {u.facets} facet(s) of contactor surface {u.contactor} face contact "
        f"surface(s) {faces} but not the pair's own target(s) {tags}, over a length of "
        f"{u.length:.6g}: there the bodies are not constrained and the answer would be "
        f"wrong{more}. Facets: {facets}; the parts facing no own target: {parts}. Give one "
        "pair every surface the contactor faces, with one tag for the whole contactor side: "
        f"contact_pair(contactor, [target_a, target_b]) with the surfaces of tags "
        f"{', '.join(str(t) for t in (*u.targets, *u.faces))}; or, where the targets meet at "
        "a node of the contactor, split the contactor's tags at that node, so that each tag "
        "faces its own targets only"
    )

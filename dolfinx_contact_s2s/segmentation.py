# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Segmentation: contactor facets cut into pieces, each facing one target facet.

The new algorithm (section 5, Eqs. 40-42) integrates Eq. (17) on pieces of the contactor
facets bounded by the nodes of both surfaces (Fig. 15(b)-(c)), so that both
displacements are smooth on each piece. How the pieces are cut depends on the
topological dimension of the facets: on the edges of 2D cells (dimension 1) a piece
is an interval of the edge's parameter :math:`\xi`, between the projections of the
target's corner nodes (:class:`IntervalSegmentation`); on the faces of 3D cells
(dimension 2) it would be a polygon, the clipped overlap of two faces.

A :class:`Segmentation` is that rule for one dimension; :data:`SEGMENTATIONS` holds
one per facet dimension and :func:`get_segmentation` looks one up. A pair
(:class:`~dolfinx_contact_s2s.pair.ContactPair`) takes its segmentation from its
contactor's :attr:`~dolfinx_contact_s2s.surface.ContactSurface.facet_dim` when it is
built, so an implementation for another dimension is added here (and in the kernels,
:func:`~dolfinx_contact_s2s.kernels.get_backend`) without touching the pair, the
discretizations or the problems.
"""

from __future__ import annotations

import typing
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels import KernelBackend
from dolfinx_contact_s2s.search import swept_boxes
from dolfinx_contact_s2s.surface import SurfaceData

__all__ = [
    "SEGMENTATIONS",
    "IntervalSegmentation",
    "Pieces",
    "Segmentation",
    "SubSegments",
    "get_segmentation",
]


@typing.runtime_checkable
class Pieces(typing.Protocol):
    """The pieces of a segmentation: each a part of one contactor facet facing one target facet.

    Attributes:
        contactor: Row of each piece's contactor facet in its surface's data.
        target: Row of each piece's target facet in the target data segmented against.
    """

    @property
    def contactor(self) -> npt.NDArray[np.int32]:
        """Contactor facet row of each piece."""
        ...

    @property
    def target(self) -> npt.NDArray[np.int32]:
        """Target facet row of each piece."""
        ...

    def __len__(self) -> int:
        """Number of pieces."""
        ...


@dataclass(frozen=True)
class SubSegments:
    """Sub-segments of the contactor facets of one process against one target (Fig. 15(b)).

    The :class:`Pieces` of :class:`IntervalSegmentation`.

    Attributes:
        contactor: Row of the contactor facet in :attr:`ContactSurface.data`.
        target: Row of the target facet in the gathered target data.
        lo: Start of the sub-segment, as a contactor facet parameter in [0, 1].
        hi: End of the sub-segment.
    """

    contactor: npt.NDArray[np.int32]
    target: npt.NDArray[np.int32]
    lo: npt.NDArray[np.floating]
    hi: npt.NDArray[np.floating]

    def __len__(self) -> int:
        """Number of sub-segments."""
        return self.contactor.size


@typing.runtime_checkable
class Segmentation(typing.Protocol):
    r"""How facets of one topological dimension are searched and cut (Fig. 15(b)).

    Three stages, on arrays only: :meth:`sweep` grows the contactor facets' boxes into
    the region a facet moved along its normal by the search radius covers (candidate
    pairs are the overlaps of those boxes with the target facets' boxes,
    :func:`~dolfinx_contact_s2s.search.box_pairs`); :meth:`cut` cuts the candidate pairs
    into pieces; :meth:`points` places a reference rule on the pieces, in contactor
    facet parameters with the weights of Eq. (40). The target side of each point is
    the target point met along the contactor normal (Eq. 38), found by the pair.

    Attributes:
        facet_dim: Topological dimension of the facets handled.
    """

    facet_dim: int

    def sweep(
        self, contactor: SurfaceData, boxes: npt.NDArray[np.floating], radius: float
    ) -> npt.NDArray[np.floating]:
        """New boxes ``(F, 2, gdim)`` of the contactor facets swept by ``radius``."""
        ...

    def cut(
        self,
        contactor: SurfaceData,
        target: SurfaceData,
        ic: npt.NDArray[np.int32],
        it: npt.NDArray[np.int32],
        radius: float,
        backend: KernelBackend,
    ) -> Pieces:
        """The pieces of the candidate pairs ``(ic[i], it[i])`` that face each other."""
        ...

    def points(
        self,
        contactor: SurfaceData,
        pieces: Pieces,
        rule: tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]],
        backend: KernelBackend,
    ) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
        """Contactor facet parameters and weights (with the measure) of ``rule`` on the pieces.

        Returns:
            ``(xi, weights)``: ``xi`` of shape ``(S, Q)`` (one parameter per point on an
            edge; a trailing axis of ``facet_dim`` parameters otherwise), ``weights``
            of shape ``(S, Q)``.
        """
        ...


class IntervalSegmentation:
    """Sub-segments of edges, the facets of 2D cells (section 5, Fig. 15(b)).

    Each candidate pair of edges is clipped to the interval of the contactor edge
    between the projections of the target edge's ends, by the kernels' ``clip_segments``.
    """

    facet_dim = 1

    def sweep(
        self, contactor: SurfaceData, boxes: npt.NDArray[np.floating], radius: float
    ) -> npt.NDArray[np.floating]:
        """The edges' boxes swept along their normals (:func:`.search.swept_boxes`)."""
        return swept_boxes(boxes, contactor.coefficients, radius)

    def cut(
        self,
        contactor: SurfaceData,
        target: SurfaceData,
        ic: npt.NDArray[np.int32],
        it: npt.NDArray[np.int32],
        radius: float,
        backend: KernelBackend,
    ) -> SubSegments:
        """Cut the contactor edges at the projected target corner nodes (Fig. 15(b)).

        Pairs whose outward normals do not oppose are dropped, and so are pieces whose
        middle is farther than ``radius`` from the target edge along the normal.
        """
        C, T = contactor, target
        # No shortest length besides round-off: dropping a real piece between nodes of the
        # two surfaces delta apart costs a consistency error of order delta in the pressure.
        lo, hi, keep = backend.clip_segments(
            C.coefficients, C.orientation, T.coefficients, T.orientation, ic, it, radius, 0.0
        )
        return SubSegments(ic[keep], it[keep], lo[keep], hi[keep])

    def points(
        self,
        contactor: SurfaceData,
        pieces: Pieces,
        rule: tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]],
        backend: KernelBackend,
    ) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
        """The rule on each sub-segment, weighted by its length and the length element."""
        seg = typing.cast(SubSegments, pieces)
        s_ref, w_ref = rule
        length = seg.hi - seg.lo
        xi = seg.lo[:, None] + length[:, None] * s_ref[None, :]
        rows = np.repeat(seg.contactor, s_ref.size)
        _, dx = backend.evaluate(contactor.coefficients, rows, xi.reshape(-1))
        jac = np.sqrt(np.einsum("pg,pg->p", dx, dx)).reshape(xi.shape)
        return xi, length[:, None] * w_ref[None, :] * jac


#: The segmentation of each facet dimension (1: edges of 2D cells).
SEGMENTATIONS: dict[int, Segmentation] = {1: IntervalSegmentation()}


def get_segmentation(facet_dim: int) -> Segmentation:
    """The segmentation registered in :data:`SEGMENTATIONS` for ``facet_dim``.

    Raises:
        NotImplementedError: For a facet dimension without a segmentation.
    """
    try:
        return SEGMENTATIONS[facet_dim]
    except KeyError:
        raise NotImplementedError(
            f"no contact segmentation for facets of dimension {facet_dim}; implemented: "
            f"{sorted(SEGMENTATIONS)} (1: the edges of 2D cells)"
        ) from None

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Segment-to-segment coupling with composite quadrature (El-Abbasi & Bathe 2001, section 5).

The contact integral of Eq. (17),

.. math:: b(\mathbf v_h, \mu_h) = \int_{\Gamma_C} \mu_h\,
    [(\mathbf v_C - \mathbf v_T^*) \cdot \mathbf N + g_0]\, d\Gamma_C,

is evaluated as in Eqs. (40)-(42): the contactor and target are both surfaces; the
contactor facets are cut into *sub-segments* at the projections of the target's
corner nodes (Fig. 15(b)), and every sub-segment is integrated with its own Gauss
rule. On each sub-segment both the contactor and the target displacements are
smooth, so the rule integrates Eq. (17) exactly for straight facets and polynomial
fields: this is what passes the contact patch test (section 3.2). The multiplier
lives in a DOLFINx function space on the contactor facets (Eq. 16, by default
:math:`\mathcal M^1_{h,k}`, continuous and of the displacement degree :math:`k`),
so its number of unknowns does not depend on the number of integration points.

The work is split into array stages (candidate search, sub-segments, points,
kernel), each a batch over all sub-segments of the process.
"""

from __future__ import annotations

from dataclasses import dataclass

from mpi4py import MPI

import basix
import basix.ufl
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s import kernels
from dolfinx_contact_s2s._compat import geometry_dofmap, submesh_parent_entities
from dolfinx_contact_s2s.surface import ContactSurface, SurfaceData, tabulate

__all__ = ["ContactPair", "CouplingBlocks", "SubSegments", "box_pairs", "contact_pair"]


@dataclass(frozen=True)
class SubSegments:
    """Sub-segments of the contactor facets of one process (Fig. 15(b)).

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


@dataclass(frozen=True)
class CouplingBlocks:
    r"""Local blocks of :math:`B` and :math:`G` with global indices, one row per sub-segment.

    Attributes:
        rows: Global multiplier dofs, shape ``(S, nk)``.
        cols_contactor: Global contactor displacement dofs, shape ``(S, nc)``.
        cols_target: Global target displacement dofs, shape ``(S, nt)``.
        contactor: Blocks :math:`\int \mu \, \mathbf v_C \cdot \mathbf N`, ``(S, nk, nc)``.
        target: Blocks :math:`-\int \mu \, \mathbf v_T^* \cdot \mathbf N`, ``(S, nk, nt)``.
        gap: Blocks :math:`\int \mu \, g_0`, ``(S, nk)``.
    """

    rows: npt.NDArray[np.int64]
    cols_contactor: npt.NDArray[np.int64]
    cols_target: npt.NDArray[np.int64]
    contactor: npt.NDArray[np.floating]
    target: npt.NDArray[np.floating]
    gap: npt.NDArray[np.floating]


def box_pairs(
    a: npt.NDArray[np.floating], b: npt.NDArray[np.floating]
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
    """All pairs of overlapping boxes, by sweep and prune along the longest axis.

    Args:
        a: Boxes ``(na, 2, gdim)`` (lower and upper corners).
        b: Boxes ``(nb, 2, gdim)``.

    Returns:
        Indices ``(ia, ib)`` of the overlapping pairs.
    """
    empty = np.empty(0, dtype=np.int32)
    if a.shape[0] == 0 or b.shape[0] == 0:
        return empty, empty
    centres = np.concatenate([a.mean(axis=1), b.mean(axis=1)])
    axis = int(np.argmax(np.ptp(centres, axis=0)))
    order = np.argsort(b[:, 0, axis], kind="stable")
    b_lo = b[order, 0, axis]
    width = float(np.max(b[:, 1, axis] - b[:, 0, axis]))
    start = np.searchsorted(b_lo, a[:, 0, axis] - width, side="left")
    stop = np.searchsorted(b_lo, a[:, 1, axis], side="right")
    counts = np.maximum(stop - start, 0)
    ia = np.repeat(np.arange(a.shape[0], dtype=np.int32), counts)
    offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    ib = order[np.repeat(start, counts) + offsets].astype(np.int32)
    overlap = np.all((a[ia, 0] <= b[ib, 1]) & (b[ib, 0] <= a[ia, 1]), axis=1)
    return ia[overlap], ib[overlap]


class ContactPair:
    """A contactor surface, a target surface and the multiplier space between them.

    The multiplier space is a Lagrange space of degree ``multiplier_degree`` on a
    submesh made of the contactor facets only (no multiplier exists elsewhere).
    """

    def __init__(
        self,
        contactor: ContactSurface,
        target: ContactSurface,
        *,
        multiplier_degree: int | None = None,
        quadrature_degree: int | None = None,
        search_radius: float | None = None,
    ):
        r"""Define the pair and its multiplier space.

        Args:
            contactor: Surface :math:`\Gamma_C` carrying the multiplier.
            target: Surface :math:`\Gamma_T`.
            multiplier_degree: Degree :math:`s` of :math:`\mathcal M^1_{h,s}` (Eq. 16);
                defaults to the contactor's displacement degree.
            quadrature_degree: Degree that the Gauss rule on each sub-segment integrates
                exactly; defaults to the multiplier degree plus the larger displacement
                degree, plus two per curved geometry degree.
            search_radius: Largest normal distance at which facets are paired; defaults
                to the largest facet size of either surface.

        Raises:
            ValueError: On every rank, if the contactor is its own target.
        """
        if contactor is target or (
            contactor.V.mesh is target.V.mesh and contactor.tag == target.tag
        ):
            raise ValueError("the contactor surface must differ from its target surface")
        if contactor.V.mesh.comm.Compare(target.V.mesh.comm) == MPI.UNEQUAL:
            raise ValueError("contactor and target must live on the same communicator")
        self.contactor = contactor
        self.target = target

        degree_u = max(contactor.element.degree, target.element.degree)
        self.multiplier_degree = (
            contactor.element.degree if multiplier_degree is None else int(multiplier_degree)
        )
        if self.multiplier_degree < 1:
            raise ValueError("the continuous multiplier needs degree 1 or more")
        curved = contactor.cmap.degree - 1 + target.cmap.degree - 1
        self.quadrature_degree = (
            self.multiplier_degree + degree_u + 2 * curved
            if quadrature_degree is None
            else int(quadrature_degree)
        )
        self._search_radius = search_radius
        self._build_multiplier_space()

    def _build_multiplier_space(self) -> None:
        mesh = self.contactor.V.mesh
        fdim = mesh.topology.dim - 1
        owned = self.contactor.data.facets
        imap = mesh.topology.index_map(fdim)
        num_facets = imap.size_local + imap.num_ghosts
        submesh, entity_map, _, _ = dolfinx.mesh.create_submesh(
            mesh, fdim, self.contactor.tagged_facets
        )
        num_sub = (
            submesh.topology.index_map(fdim).size_local
            + submesh.topology.index_map(fdim).num_ghosts
        )
        parent = submesh_parent_entities(entity_map, num_sub)
        parent_to_sub = np.full(num_facets, -1, dtype=np.int32)
        parent_to_sub[parent] = np.arange(num_sub, dtype=np.int32)
        self.multiplier_element = basix.ufl.element(
            "Lagrange", submesh.basix_cell(), self.multiplier_degree
        )
        self.Q = dolfinx.fem.functionspace(submesh, self.multiplier_element)
        self.submesh = submesh
        self._sub_cells = parent_to_sub[owned]

        # The submesh cell may run against the facet parametrisation: s = xi or 1 - xi.
        data = self.contactor.data
        rows = np.arange(len(data), dtype=np.int32)
        _, x0, _ = self.contactor.evaluate(data, rows, np.zeros(rows.size))
        sub_x = submesh.geometry.x[geometry_dofmap(submesh)[self._sub_cells, 0], : x0.shape[1]]
        self._flip = np.linalg.norm(sub_x - x0, axis=1) > 1e-8 * (1.0 + np.linalg.norm(x0, axis=1))

    @property
    def search_radius(self) -> float:
        """Largest normal distance at which facets are paired."""
        if self._search_radius is None:
            local = max(
                float(np.max(self.contactor.sizes(self.contactor.data), initial=0.0)),
                float(np.max(self.target.sizes(self.target.data), initial=0.0)),
            )
            self._search_radius = self.contactor.comm.allreduce(local, op=MPI.MAX)
        return self._search_radius

    def sub_segments(self, target_data: SurfaceData | None = None) -> SubSegments:
        """Cut the contactor facets at the projected target corner nodes (Fig. 15(b)).

        Candidate pairs come from overlapping bounding boxes padded by the search
        radius; pairs whose outward normals do not oppose are dropped.

        Args:
            target_data: The gathered target facets; gathered here if not given.
        """
        C, cs = self.contactor.data, self.contactor
        T = self.target.gather() if target_data is None else target_data
        ts = self.target
        r = self.search_radius
        boxes_c = cs.bounding_boxes(C)
        boxes_c[:, 0] -= r
        boxes_c[:, 1] += r
        ic, it = box_pairs(boxes_c, ts.bounding_boxes(T))

        half = np.full(ic.size, 0.5)
        n_c = cs.outward_normals(C, ic, cs.reference_points(C, ic, half))
        n_t = ts.outward_normals(T, it, ts.reference_points(T, it, half))
        facing = np.einsum("pg,pg->p", n_c, n_t) < 0.0
        ic, it = ic[facing], it[facing]

        # Only the corner (edge) nodes bound sub-segments, also for quadratic facets.
        _, xa, _ = ts.evaluate(T, it, np.zeros(it.size))
        _, xb, _ = ts.evaluate(T, it, np.ones(it.size))
        xi_a = cs.project(C, ic, xa)
        xi_b = cs.project(C, ic, xb)
        lo = np.clip(np.minimum(xi_a, xi_b), 0.0, 1.0)
        hi = np.clip(np.maximum(xi_a, xi_b), 0.0, 1.0)
        # Distance along the contactor normal from the facet mid-point to the target.
        _, xm, _ = cs.evaluate(C, ic, 0.5 * (lo + hi))
        _, xt_a, _ = ts.evaluate(T, it, np.full(it.size, 0.5))
        near = np.abs(np.einsum("pg,pg->p", xt_a - xm, n_c[facing])) <= r
        keep = (hi - lo > 1e-12) & near
        return SubSegments(ic[keep], it[keep], lo[keep], hi[keep])

    def quadrature(self) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
        """Gauss points and weights on the unit interval, used on every sub-segment."""
        points, weights = basix.make_quadrature(
            basix.CellType.interval, self.quadrature_degree, rule=basix.QuadratureType.gauss_jacobi
        )
        return points[:, 0], weights

    def coupling_blocks(self) -> CouplingBlocks:
        """Integrate Eq. (40) over every sub-segment of the process's contactor facets.

        Returns:
            The local blocks with their global row and column indices.
        """
        C, cs, ts = self.contactor.data, self.contactor, self.target
        T = ts.gather()
        seg = self.sub_segments(T)
        s_ref, w_ref = self.quadrature()
        S, nq = len(seg), s_ref.size
        length = seg.hi - seg.lo
        xi = (seg.lo[:, None] + length[:, None] * s_ref[None, :]).reshape(-1)
        rows_c = np.repeat(seg.contactor, nq)
        rows_t = np.repeat(seg.target, nq)

        X_c, x_c, dx_c = cs.evaluate(C, rows_c, xi)
        weights = (length[:, None] * w_ref[None, :]).reshape(-1) * np.linalg.norm(dx_c, axis=1)
        normals = -cs.outward_normals(C, rows_c, X_c)
        eta = ts.intersect(T, rows_t, x_c, normals)
        X_t, x_t, _ = ts.evaluate(T, rows_t, eta)
        gaps = np.einsum("pg,pg->p", x_c - x_t, normals)

        s_sub = np.where(self._flip[rows_c], 1.0 - xi, xi)
        mu = tabulate(self.multiplier_element, 0, s_sub[:, None])[0]
        gdim = normals.shape[1]
        phi_c, phi_t = cs.basis(X_c), ts.basis(X_t)
        b_c, b_t, g = kernels.segment_to_segment(
            mu.reshape(S, nq, mu.shape[1]),
            phi_c.reshape(S, nq, phi_c.shape[1]),
            phi_t.reshape(S, nq, phi_t.shape[1]),
            normals.reshape(S, nq, gdim),
            weights.reshape(S, nq),
            gaps.reshape(S, nq),
        )

        qmap = self.Q.dofmap
        local_rows = qmap.list[self._sub_cells[seg.contactor]]
        rows = qmap.index_map.local_to_global(local_rows.reshape(-1)).reshape(local_rows.shape)
        return CouplingBlocks(
            rows.astype(np.int64),
            C.dofs[seg.contactor],
            T.dofs[seg.target],
            b_c,
            b_t,
            g,
        )

    def check_facing(self, segments: SubSegments) -> None:
        """Raise on every rank if the surfaces share no sub-segment."""
        if self.contactor.comm.allreduce(len(segments), op=MPI.SUM) == 0:
            raise ValueError(
                "the contactor and target surfaces never face each other within the search "
                f"radius {self.search_radius:g}: no sub-segment to integrate"
            )


def contact_pair(
    contactor: ContactSurface,
    target: ContactSurface,
    *,
    multiplier_degree: int | None = None,
    quadrature_degree: int | None = None,
    search_radius: float | None = None,
) -> ContactPair:
    """Create a :class:`ContactPair` (see its constructor for the arguments)."""
    return ContactPair(
        contactor,
        target,
        multiplier_degree=multiplier_degree,
        quadrature_degree=quadrature_degree,
        search_radius=search_radius,
    )

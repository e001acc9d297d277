# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Contact coupling blocks of every discretization of El-Abbasi & Bathe (2001).

The contact integral of Eq. (17),

.. math:: b(\mathbf v_h, \mu_h) = \int_{\Gamma_C} \mu_h\,
    [(\mathbf v_C - \mathbf v_T^*) \cdot \mathbf N + g_0]\, d\Gamma_C,

is evaluated as a weighted sum over contactor points, each paired with the target
point met along the normal :math:`\mathbf N = -\mathbf n_C` (Eq. 38). The
discretizations differ in the points, the weights and the multiplier space
(:class:`ContactPair`): nodes with unit or tributary weights (node-to-node, Eq. 37;
node-to-segment, Eq. 39), Gauss points of the contactor segments, or (the new
algorithm, section 5, Eqs. 40-42) Gauss or Newton-Cotes points of *sub-segments*
bounded by the nodes of both surfaces (Fig. 15(b)-(c)). On a sub-segment both
displacements are smooth, so the composite rule integrates Eq. (17) exactly for
straight facets and polynomial fields, which is what passes the contact patch test
(section 3.2). The multiplier lives in a DOLFINx function space on the contactor
facets (Eq. 16), so its number of unknowns does not depend on the number of
integration points; the intermediate surface (section 4.4) has its own segment mesh.

The work is split into array stages (candidate search, sub-segments or target search,
points, kernel), each a batch over all points of the process.
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
from dolfinx_contact_s2s.quadrature import RULES, interval_rule
from dolfinx_contact_s2s.surface import ContactSurface, SurfaceData, tabulate

__all__ = [
    "METHODS",
    "ContactPair",
    "CouplingBlocks",
    "SubSegments",
    "box_pairs",
    "contact_pair",
    "contact_pairs",
]

#: Contact discretizations of a single pair (sections 4 and 5); see also
#: :func:`contact_pairs` for the two-pass method.
METHODS = (
    "segment-to-segment",
    "node-to-segment",
    "node-to-segment-gauss",
    "node-to-node",
    "intermediate-surface",
)


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
    r"""A contactor surface, a target surface, a discretization and its multiplier space.

    The multiplier lives in a space of Eq. (16) on a submesh made of the contactor's
    tagged facets only. The discretizations (``method``):

    - ``"segment-to-segment"`` (section 5, Eqs. 40-42): the multiplier is interpolated
      from its own unknowns (Eq. 42) and Eq. (17) is integrated with ``quadrature``:
      ``"composite-gauss"`` or ``"composite-newton-cotes"`` on the sub-segments bounded
      by the nodes of both surfaces (Fig. 15(b)-(c), the new algorithm), or
      ``"gauss"``/``"newton-cotes"`` on the contactor segments only (Fig. 15(a)).
    - ``"node-to-segment"`` (Eqs. 38-39): one constraint per contactor node, projected
      along the contactor normal onto the target, with weight :math:`w^i = 1`
      (``weight="unit"``: the multiplier is a nodal force) or the node's tributary
      length (``weight="tributary"``: the multiplier is a pressure).
    - ``"node-to-segment-gauss"``: the same constraint at the Gauss points of the
      contactor segments, with one multiplier per point [21, 22].
    - ``"node-to-node"`` (Eq. 37): node-to-segment with unit weights on meshes whose
      nodes coincide; other meshes raise :class:`ValueError`.
    - ``"intermediate-surface"`` (section 4.4, Fig. 13, for linear 2D surfaces [24]): the
      nodes of both surfaces are projected onto a surface midway between them; one
      constant pressure per segment between projected nodes, integrated exactly there.
      The multiplier lives on a mesh of those segments.
    """

    def __init__(
        self,
        contactor: ContactSurface,
        target: ContactSurface,
        *,
        method: str = "segment-to-segment",
        multiplier: tuple[str, int] | None = None,
        quadrature: str | None = None,
        quadrature_points: int | None = None,
        weight: str = "unit",
        search_radius: float | None = None,
        drop_coincident: bool = False,
    ):
        r"""Define the pair and its multiplier space.

        Args:
            contactor: Surface :math:`\Gamma_C` carrying the multiplier.
            target: Surface :math:`\Gamma_T`.
            method: One of :data:`METHODS`.
            multiplier: ``("Lagrange", s)`` for :math:`\mathcal M^1_{h,s}` (continuous) or
                ``("DG", s)`` for :math:`\mathcal M^0_{h,s}` (discontinuous), Eq. (16);
                defaults to continuous of the contactor's displacement degree. Node-based
                methods need the default.
            quadrature: One of :data:`~dolfinx_contact_s2s.quadrature.RULES`; defaults
                to ``"composite-gauss"`` (``"gauss"`` for ``node-to-segment-gauss``).
            quadrature_points: Points per (sub-)segment; defaults to the fewest Gauss
                points that integrate Eq. (17) exactly on straight segments (plus one per
                curved geometry degree), or the multiplier degree plus the displacement
                degree plus one for Newton-Cotes.
            weight: ``"unit"`` or ``"tributary"``, for ``node-to-segment``.
            search_radius: Largest normal distance at which facets are paired; defaults
                to the largest facet size of either surface.
            drop_coincident: For ``node-to-segment``: leave out the constraints of nodes
                that meet a target node (the duplicates of the second pass of the
                two-pass algorithm, section 4.3); see :func:`contact_pairs`.

        Raises:
            ValueError: On every rank, for an unknown or inconsistent choice, or a
                contactor that is its own target.
        """
        if contactor is target or (
            contactor.V.mesh is target.V.mesh and contactor.tag == target.tag
        ):
            raise ValueError("the contactor surface must differ from its target surface")
        if contactor.V.mesh.comm.Compare(target.V.mesh.comm) == MPI.UNEQUAL:
            raise ValueError("contactor and target must live on the same communicator")
        if method not in METHODS:
            raise ValueError(f"unknown contact method {method!r}; choose from {METHODS}")
        if weight not in ("unit", "tributary"):
            raise ValueError("weight must be 'unit' or 'tributary'")
        self.contactor = contactor
        self.target = target
        self.method = method
        self.weight = "unit" if method == "node-to-node" else weight
        if drop_coincident and method != "node-to-segment":
            raise ValueError("drop_coincident applies to node-to-segment only")
        self.drop_coincident = drop_coincident
        k_c = contactor.element.degree
        nodal = method in ("node-to-segment", "node-to-node")

        if quadrature is None:
            quadrature = "gauss" if method == "node-to-segment-gauss" else "composite-gauss"
        if quadrature not in RULES:
            raise ValueError(f"unknown quadrature {quadrature!r}; choose from {RULES}")
        if method == "node-to-segment-gauss" and quadrature != "gauss":
            raise ValueError("node-to-segment-gauss constrains the contactor's Gauss points")
        self.quadrature = quadrature

        family, degree = ("Lagrange", k_c) if multiplier is None else multiplier
        continuous = family in ("Lagrange", "P", "CG")
        if not continuous and family not in ("DG", "Discontinuous Lagrange"):
            raise ValueError(f"multiplier family must be 'Lagrange' or 'DG', not {family!r}")
        if continuous and degree < 1:
            raise ValueError("a continuous multiplier needs degree 1 or more")
        if nodal and (not continuous or degree != k_c):
            raise ValueError(f"{method} puts one multiplier on every contactor node")
        if method in ("node-to-segment-gauss", "intermediate-surface") and multiplier is not None:
            raise ValueError(f"{method} defines its own multiplier space")
        if method == "intermediate-surface":
            linear = (contactor.element.degree, target.element.degree) == (1, 1)
            if not linear or contactor.cmap.degree != 1 or target.cmap.degree != 1:
                raise ValueError("the intermediate contact surface is for linear 2D surfaces")
            if quadrature != "composite-gauss":
                raise ValueError("the intermediate surface integrates its own segments exactly")
            family, degree = "DG", 0

        curved = contactor.cmap.degree - 1 + target.cmap.degree - 1
        k_u = max(k_c, target.element.degree)
        if quadrature_points is None:
            if quadrature.endswith("newton-cotes"):
                quadrature_points = max(degree + k_u, 1) + 1
            else:
                quadrature_points = (degree + k_u + 2 * curved) // 2 + 1
        self.quadrature_points = int(quadrature_points)
        self._rule = interval_rule(quadrature, self.quadrature_points)

        variant = basix.LagrangeVariant.unset
        if method == "node-to-segment-gauss":
            # One discontinuous multiplier per Gauss point: Lagrange at the Gauss points.
            continuous, degree = False, self.quadrature_points - 1
            variant = basix.LagrangeVariant.gl_warped
        elif degree > 2 or (not continuous and degree > 0):
            variant = basix.LagrangeVariant.gll_warped
        self.multiplier_degree = degree
        self.multiplier_continuous = continuous
        #: Global multiplier dofs whose constraint is left out (the multiplier is zero).
        self.inactive = np.empty(0, dtype=np.int64)
        self._search_radius = search_radius
        if method == "intermediate-surface":
            self._build_intermediate_space()
        else:
            self._build_multiplier_space(degree, not continuous, variant)

    @property
    def multiplier_label(self) -> str:
        r"""The multiplier space in the notation of Eq. (16), e.g. ``M^1_{h,1}``."""
        if self.method == "node-to-segment-gauss":
            return "point values"
        if self.method == "intermediate-surface":
            return "M^0_{h,0} (intermediate)"
        return f"M^{int(self.multiplier_continuous)}_{{h,{self.multiplier_degree}}}"

    def _build_multiplier_space(
        self, degree: int, discontinuous: bool, variant: basix.LagrangeVariant
    ) -> None:
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
            "Lagrange",
            submesh.basix_cell(),
            degree,
            lagrange_variant=variant,
            discontinuous=discontinuous,
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

    def _intermediate_points(
        self, seg: SubSegments, T: SurfaceData, xi: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        """Points midway between contactor points and their target points (Fig. 13)."""
        cs, C = self.contactor, self.contactor.data
        rows = np.repeat(seg.contactor, xi.size // max(len(seg), 1))
        X, x, _ = cs.evaluate(C, rows, xi)
        t_rows = np.repeat(seg.target, xi.size // max(len(seg), 1))
        eta = np.clip(self.target.intersect(T, t_rows, x, -cs.outward_normals(C, rows, X)), 0, 1)
        _, x_t, _ = self.target.evaluate(T, t_rows, eta)
        return 0.5 * (x + x_t)

    def _build_intermediate_space(self) -> None:
        """A mesh of the intermediate segments and a piecewise-constant multiplier on it."""
        comm = self.contactor.comm
        T = self.target.gather()
        seg = self.sub_segments(T)
        n = len(seg)
        ends = np.stack([seg.lo, seg.hi], axis=1).reshape(-1)
        x = self._intermediate_points(seg, T, ends)
        offset = comm.exscan(n) or 0
        cells = (2 * offset + np.arange(2 * n, dtype=np.int64)).reshape(n, 2)
        gdim = x.shape[1]
        coordinate = basix.ufl.element("Lagrange", "interval", 1, shape=(gdim,))
        mesh = dolfinx.mesh.create_mesh(comm, cells=cells, x=x, e=coordinate)
        self.multiplier_element = basix.ufl.element("DG", "interval", 0)
        self.Q = dolfinx.fem.functionspace(mesh, self.multiplier_element)
        self.submesh = mesh
        # DOLFINx redistributes the cells: find each segment's multiplier dof again.
        original = np.asarray(mesh.topology.original_cell_index, dtype=np.int64)
        imap = self.Q.dofmap.index_map
        dofs = imap.local_to_global(self.Q.dofmap.list[: original.size, 0].astype(np.int32))
        lookup = np.empty(comm.allreduce(n), dtype=np.int64)
        for orig, gdofs in comm.allgather((original, dofs)):
            lookup[orig] = gdofs
        self._segments = seg
        self._segment_rows = lookup[offset + np.arange(n)]
        self._segment_lengths = np.linalg.norm(x[1::2] - x[0::2], axis=1)
        self._flip = np.zeros(len(self.contactor.data), dtype=bool)

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

    def _candidates(
        self, boxes: npt.NDArray[np.floating], T: SurfaceData
    ) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
        """Pairs (box, target facet) whose boxes overlap once padded by the search radius."""
        r = self.search_radius
        padded = boxes.copy()
        padded[:, 0] -= r
        padded[:, 1] += r
        return box_pairs(padded, self.target.bounding_boxes(T))

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
        ic, it = self._candidates(cs.bounding_boxes(C), T)

        half = np.full(ic.size, 0.5)
        n_c = cs.outward_normals(C, ic, cs.reference_points(C, ic, half))
        n_t = ts.outward_normals(T, it, ts.reference_points(T, it, half))
        facing = np.einsum("pg,pg->p", n_c, n_t) < 0.0
        ic, it, n_c = ic[facing], it[facing], n_c[facing]

        # Only the corner (edge) nodes bound sub-segments, also for quadratic facets.
        _, xa, _ = ts.evaluate(T, it, np.zeros(it.size))
        _, xb, _ = ts.evaluate(T, it, np.ones(it.size))
        xi_a = cs.project(C, ic, xa)
        xi_b = cs.project(C, ic, xb)
        lo = np.clip(np.minimum(xi_a, xi_b), 0.0, 1.0)
        hi = np.clip(np.maximum(xi_a, xi_b), 0.0, 1.0)
        # Normal distance from the sub-segment's middle to the target facet.
        _, xm, _ = cs.evaluate(C, ic, 0.5 * (lo + hi))
        _, xt, _ = ts.evaluate(T, it, np.full(it.size, 0.5))
        near = np.abs(np.einsum("pg,pg->p", xt - xm, n_c)) <= self.search_radius
        keep = (hi - lo > 1e-12) & near
        return SubSegments(ic[keep], it[keep], lo[keep], hi[keep])

    def _find_targets(
        self, rows: npt.NDArray[np.int32], xi: npt.NDArray[np.floating], T: SurfaceData
    ) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int32]]:
        """The target facet hit along the normal from each contactor point (Fig. 7(b)).

        Returns:
            The points that hit a facing target facet within the search radius, and
            the facet each of them hits (the nearest; any one where several meet).
        """
        cs, ts, C = self.contactor, self.target, self.contactor.data
        X, x, _ = cs.evaluate(C, rows, xi)
        normals = -cs.outward_normals(C, rows, X)
        ip, it = self._candidates(np.stack([x, x], axis=1), T)
        eta = ts.intersect(T, it, x[ip], normals[ip])
        tol = 1e-10
        inside = (eta >= -tol) & (eta <= 1 + tol)
        eta = np.clip(eta, 0.0, 1.0)
        X_t, x_t, _ = ts.evaluate(T, it, eta)
        gap = np.einsum("pg,pg->p", x[ip] - x_t, normals[ip])
        facing = np.einsum("pg,pg->p", ts.outward_normals(T, it, X_t), normals[ip]) > 0
        ok = inside & facing & (np.abs(gap) <= self.search_radius)
        ip, it, gap = ip[ok], it[ok], gap[ok]
        order = np.lexsort((np.abs(gap), ip))
        first = np.ones(order.size, dtype=bool)
        first[1:] = ip[order][1:] != ip[order][:-1]
        best = order[first]
        return ip[best].astype(np.int64), it[best]

    def _multiplicity(self) -> npt.NDArray[np.floating]:
        """Number of contactor facets (over all processes) that share each multiplier dof."""
        count = dolfinx.fem.Function(self.Q)
        np.add.at(count.x.array, self.Q.dofmap.list[self._sub_cells].reshape(-1), 1.0)
        count.x.scatter_reverse(dolfinx.la.InsertMode.add)
        count.x.scatter_forward()
        return count.x.array

    def _point_rule(self) -> tuple[npt.NDArray[np.int32], ...]:
        """Constraint points on the contactor facets for the point-based methods.

        Returns:
            ``(rows, xi, weights, dofs)``: facet row, facet parameter, weight and (for
            the nodal methods, else -1) local multiplier dof of every point.
        """
        cs, C = self.contactor, self.contactor.data
        n = len(C)
        if self.method in ("node-to-segment", "node-to-node"):
            # Every multiplier dof sits on a contactor node; s is the submesh parameter.
            s_nodes = self.multiplier_element.basix_element.points[:, 0]
            k = s_nodes.size
            rows = np.repeat(np.arange(n, dtype=np.int32), k)
            s = np.tile(s_nodes, n)
            xi = np.where(self._flip[rows], 1.0 - s, s)
            dofs = self.Q.dofmap.list[self._sub_cells].reshape(-1)
            if self.weight == "unit":
                weights = 1.0 / self._multiplicity()[dofs]
            else:
                weights = self._facet_integrals().reshape(-1)
            return rows, xi, weights, dofs
        s_ref, w_ref = self._rule
        rows = np.repeat(np.arange(n, dtype=np.int32), s_ref.size)
        xi = np.tile(s_ref, n)
        _, _, dx = cs.evaluate(C, rows, xi)
        weights = np.tile(w_ref, n) * np.linalg.norm(dx, axis=1)
        return rows, xi, weights, np.full(rows.size, -1, dtype=np.int32)

    def _facet_integrals(self) -> npt.NDArray[np.floating]:
        r"""Integrals :math:`\int_f \mu_k` of the multiplier basis over each contactor facet."""
        cs, C = self.contactor, self.contactor.data
        n = len(C)
        s_ref, w_ref = interval_rule("gauss", self.multiplier_degree + 3)
        rows = np.repeat(np.arange(n, dtype=np.int32), s_ref.size)
        xi = np.tile(s_ref, n)
        _, _, dx = cs.evaluate(C, rows, xi)
        s_sub = np.where(self._flip[rows], 1.0 - xi, xi)
        mu = tabulate(self.multiplier_element, 0, s_sub[:, None])[0]
        w = (np.tile(w_ref, n) * np.linalg.norm(dx, axis=1))[:, None] * mu
        return w.reshape(n, s_ref.size, mu.shape[1]).sum(axis=1)

    def integration_points(
        self, target_data: SurfaceData | None = None
    ) -> tuple[npt.NDArray, npt.NDArray, npt.NDArray, npt.NDArray]:
        """Contactor integration points of Eq. (40), grouped by (sub-)segment.

        Returns:
            ``(contactor_rows, target_rows, xi, weights)``: per group the contactor and
            target facet rows, and per group and point the contactor facet parameter
            and the weight (including the facet's length element), shapes ``(S,)``,
            ``(S,)``, ``(S, Q)``, ``(S, Q)``.
        """
        cs, C = self.contactor, self.contactor.data
        T = self.target.gather() if target_data is None else target_data
        if self.method == "intermediate-surface":
            # Integrated on the intermediate segments, which map linearly onto the
            # contactor's sub-segments.
            seg = self._segments
            s_ref, w_ref = self._rule
            xi = seg.lo[:, None] + (seg.hi - seg.lo)[:, None] * s_ref[None, :]
            weights = self._segment_lengths[:, None] * w_ref[None, :]
            return seg.contactor, seg.target, xi, weights
        if self.method == "segment-to-segment" and self.quadrature.startswith("composite-"):
            seg = self.sub_segments(T)
            s_ref, w_ref = self._rule
            length = seg.hi - seg.lo
            xi = seg.lo[:, None] + length[:, None] * s_ref[None, :]
            _, _, dx = cs.evaluate(C, np.repeat(seg.contactor, s_ref.size), xi.reshape(-1))
            jac = np.linalg.norm(dx, axis=1).reshape(xi.shape)
            return seg.contactor, seg.target, xi, length[:, None] * w_ref[None, :] * jac
        rows, xi, weights, dofs = self._point_rule()
        hit, t_rows = self._find_targets(rows, xi, T)
        rows, xi, weights, dofs = rows[hit], xi[hit], weights[hit], dofs[hit]
        if self.method == "node-to-node" or self.drop_coincident:
            h = self.contactor.comm.allreduce(
                float(np.min(self.target.sizes(T), initial=np.inf)), op=MPI.MIN
            )
            coincident = self._node_offsets(rows, xi, t_rows, T) <= 1e-8 * h
            if self.method == "node-to-node":
                # Every contactor node meets a target node, and there are as many of each.
                fdim = 1
                closure = self.target.element.basix_element.entity_closure_dofs[fdim]
                bs = self.target.V.dofmap.index_map_bs
                facet_nodes = np.array([closure[lf] for lf in T.local_facet], dtype=np.int64)
                if facet_nodes.size:
                    nodes = np.take_along_axis(T.dofs[:, ::bs], facet_nodes, axis=1)
                else:
                    nodes = np.empty(0, dtype=np.int64)
                same_count = np.unique(nodes).size == self.Q.dofmap.index_map.size_global
                if not same_count or self.contactor.comm.allreduce(
                    int(np.count_nonzero(~coincident))
                ):
                    raise ValueError(
                        "node-to-node contact needs coincident nodes on the two surfaces; "
                        "use node-to-segment or segment-to-segment on non-matching meshes"
                    )
            else:
                imap = self.Q.dofmap.index_map
                local = np.unique(dofs[coincident])
                mine = imap.local_to_global(local.astype(np.int32)).astype(np.int64)
                self.inactive = np.unique(np.concatenate(self.contactor.comm.allgather(mine)))
        return rows, t_rows, xi[:, None], weights[:, None]

    def _node_offsets(
        self,
        rows: npt.NDArray[np.int32],
        xi: npt.NDArray[np.floating],
        t_rows: npt.NDArray[np.int32],
        T: SurfaceData,
    ) -> npt.NDArray[np.floating]:
        """Distance from each contactor point's target point to the nearest target node."""
        cs, ts = self.contactor, self.target
        X, x, _ = cs.evaluate(cs.data, rows, xi)
        eta = ts.intersect(T, t_rows, x, -cs.outward_normals(cs.data, rows, X))
        # Facet parameters of the target's Lagrange nodes (P1: ends; P2: ends and middle).
        nodes = np.linspace(0.0, 1.0, ts.element.degree + 1)
        off = np.min(np.abs(eta[:, None] - nodes[None, :]), axis=1, initial=np.inf)
        return off * ts.sizes(T)[t_rows]

    def coupling_blocks(self) -> CouplingBlocks:
        """Integrate Eq. (17) as the method prescribes (Eqs. 37, 39 or 40).

        Returns:
            The local blocks with their global row and column indices.
        """
        C, cs, ts = self.contactor.data, self.contactor, self.target
        T = ts.gather()
        c_rows, t_rows, xi, w = self.integration_points(T)
        S, nq = xi.shape
        rows_c = np.repeat(c_rows, nq)
        rows_t = np.repeat(t_rows, nq)
        xi = xi.reshape(-1)

        X_c, x_c, _ = cs.evaluate(C, rows_c, xi)
        normals = -cs.outward_normals(C, rows_c, X_c)
        eta = np.clip(ts.intersect(T, rows_t, x_c, normals), 0.0, 1.0)
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
            w.reshape(S, nq),
            gaps.reshape(S, nq),
        )

        if self.method == "intermediate-surface":
            rows = self._segment_rows[:, None]
        else:
            qmap = self.Q.dofmap
            local_rows = qmap.list[self._sub_cells[c_rows]]
            rows = qmap.index_map.local_to_global(local_rows.reshape(-1)).reshape(local_rows.shape)
        return CouplingBlocks(rows.astype(np.int64), C.dofs[c_rows], T.dofs[t_rows], b_c, b_t, g)


def contact_pairs(
    contactor: ContactSurface,
    target: ContactSurface,
    *,
    method: str = "segment-to-segment",
    **options,
) -> list[ContactPair]:
    """The contact pairs of a discretization: one, or two for a two-pass method.

    Args:
        contactor: First surface (the contactor of the first pass).
        target: Second surface.
        method: One of :data:`METHODS`, or ``"two-pass node-to-segment"`` (section 4.3):
            node-to-segment with each surface as contactor in turn, the second pass
            without the constraints of nodes that coincide with nodes of the first
            (within :math:`10^{-8}` of the element size).
        options: Further arguments of :class:`ContactPair`.
    """
    if method == "two-pass node-to-segment":
        return [
            ContactPair(contactor, target, method="node-to-segment", **options),
            ContactPair(
                target, contactor, method="node-to-segment", drop_coincident=True, **options
            ),
        ]
    return [ContactPair(contactor, target, method=method, **options)]


def contact_pair(
    contactor: ContactSurface,
    target: ContactSurface,
    *,
    method: str = "segment-to-segment",
    multiplier: tuple[str, int] | None = None,
    quadrature: str | None = None,
    quadrature_points: int | None = None,
    weight: str = "unit",
    search_radius: float | None = None,
) -> ContactPair:
    """Create a :class:`ContactPair` (see its constructor for the arguments)."""
    return ContactPair(
        contactor,
        target,
        method=method,
        multiplier=multiplier,
        quadrature=quadrature,
        quadrature_points=quadrature_points,
        weight=weight,
        search_radius=search_radius,
    )

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Contact pairs and the local coupling blocks of El-Abbasi & Bathe (2001).

The contact integral of Eq. (17),

.. math:: b(\mathbf v_h, \mu_h) = \int_{\Gamma_C} \mu_h\,
    [(\mathbf v_C - \mathbf v_T^*) \cdot \mathbf N + g_0]\, d\Gamma_C,

is evaluated as a weighted sum over contactor points, each paired with the target
point met along the normal :math:`\mathbf N = -\mathbf n_C` (Eq. 38). The
discretizations (:mod:`dolfinx_contact_s2s.discretizations`) differ in the points, the
weights and the multiplier space: nodes with unit or tributary weights (node-to-node,
Eq. 37; node-to-segment, Eq. 39), Gauss points of the contactor segments, or (the new
algorithm, section 5, Eqs. 40-42) Gauss or Newton-Cotes points of *sub-segments*
bounded by the nodes of both surfaces (Fig. 15(b)-(c)). On a sub-segment both
displacements are smooth, so the composite rule integrates Eq. (17) exactly for
straight facets and polynomial fields, which is what passes the contact patch test
(section 3.2). The multiplier lives in a DOLFINx function space on the contactor
facets (Eq. 16), so its number of unknowns does not depend on the number of
integration points; the intermediate surface (section 4.4) has its own segment mesh.

A contactor may face several target surfaces (other bodies, or other parts of its own
mesh): it carries one multiplier field for all of them, and the coupling is integrated
against each target separately (:meth:`ContactPair.coupling_blocks`). The search
(:mod:`dolfinx_contact_s2s.search`), the segmentation
(:mod:`dolfinx_contact_s2s.segmentation`, chosen by the contactor's facet dimension) and
the kernels (:mod:`dolfinx_contact_s2s.kernels`) are batches over all points of the
process.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from mpi4py import MPI

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.axisymmetry import (
    check_axis_surface,
    check_axisymmetric_mesh,
    ring_weights,
)
from dolfinx_contact_s2s.contact_rule import contact_rule
from dolfinx_contact_s2s.discretizations import DISCRETIZATIONS, PointGroups
from dolfinx_contact_s2s.face_basis import edge_blocks, face_basis, face_blocks
from dolfinx_contact_s2s.quadrature import RULES
from dolfinx_contact_s2s.search import box_pairs, default_search_radius
from dolfinx_contact_s2s.segmentation import Pieces, SubSegments, get_segmentation
from dolfinx_contact_s2s.surface import ContactSurface, SurfaceData

__all__ = [
    "METHODS",
    "ContactPair",
    "CouplingBlocks",
    "SubSegments",
    "box_pairs",
    "contact_pair",
    "contact_pairs",
]

#: Contact discretizations of a single pair (sections 4, 5; two-pass: :func:`contact_pairs`).
METHODS = tuple(DISCRETIZATIONS)


@dataclass(frozen=True)
class CouplingBlocks:
    r"""Local blocks of :math:`B` and :math:`G` against one target, one row per group.

    A group is a sub-segment or a contactor point (``S`` groups, ``nk`` multiplier dofs);
    on faces, the pieces of one overlap of two faces, summed.

    Attributes:
        target: The target surface.
        rows: Global multiplier dofs, shape ``(S, nk)``.
        cols_contactor: Global contactor displacement dofs, shape ``(S, nc)``.
        values_contactor: :math:`\int \mu \, \mathbf v_C \cdot \mathbf N`, ``(S, nk, nc)``.
        cols_target: Global target displacement dofs, shape ``(S, nt)``.
        values_target: :math:`-\int \mu \, \mathbf v_T^* \cdot \mathbf N`, ``(S, nk, nt)``.
        gap: :math:`\int \mu \, g_0`, ``(S, nk)``.
        coverage: The integral of :math:`\mu_k` (:math:`\mu_k^2` if
            :attr:`ContactPair.squared_coverage`) over the part facing the target, ``(S, nk)``.
        signed: That of :math:`\mu_k` on edges; ``None`` on faces.
    """

    target: ContactSurface
    rows: npt.NDArray[np.int64]
    cols_contactor: npt.NDArray[np.int64]
    values_contactor: npt.NDArray[np.floating]
    cols_target: npt.NDArray[np.int64]
    values_target: npt.NDArray[np.floating]
    gap: npt.NDArray[np.floating]
    coverage: npt.NDArray[np.floating]
    signed: npt.NDArray[np.floating] | None = None


class ContactPair:
    r"""A contactor surface, its target surfaces, a discretization and its multiplier space.

    The multiplier lives in a space of Eq. (16) on a submesh made of the contactor's
    tagged facets only. The discretizations (``method``):

    - ``"segment-to-segment"`` (section 5, Eqs. 40-42): the multiplier is interpolated
      from its own unknowns (Eq. 42) and Eq. (17) is integrated with ``quadrature``:
      ``"composite-gauss"`` or ``"composite-newton-cotes"`` on the sub-segments bounded
      by the nodes of both surfaces (Fig. 15(b)-(c), the new algorithm), or
      ``"gauss"``/``"newton-cotes"`` on the contactor segments only (Fig. 15(a)).
    - ``"node-to-segment"`` (Eqs. 38-39): one constraint per contactor node, projected
      along the contactor normal onto the nearest target, with weight :math:`w^i = 1`
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

    Attributes:
        contactor: The contactor surface :math:`\Gamma_C`.
        targets: The target surfaces (meshed, deformable or rigid).
        obstacles: The analytic obstacles among the targets given.
        method: The method name; :attr:`discretization` holds its rules.
        Q: The multiplier space.
        duplicates: Global multiplier dofs left out at construction (the second pass of
            the two-pass method: nodes meeting a target node); empty otherwise.
        search_radius: Largest normal distance at which facets are paired.
        segmentation: The :class:`~dolfinx_contact_s2s.segmentation.Segmentation` of the
            contactor's facet dimension (Fig. 15(b)).
        axisymmetric: Whether Eq. (17) carries the ring weight :math:`2\pi r` (see
            :func:`contact_pair`).
    """

    def __init__(
        self,
        contactor: ContactSurface,
        targets: ContactSurface | Sequence[ContactSurface],
        *,
        method: str = "segment-to-segment",
        multiplier: tuple[str, int] | None = None,
        quadrature: str | None = None,
        quadrature_points: int | None = None,
        weight: str = "unit",
        search_radius: float | None = None,
        drop_coincident: bool = False,
        axisymmetric: bool = False,
    ):
        r"""Define the pair and its multiplier space (collective).

        Args:
            contactor: Surface :math:`\Gamma_C` carrying the multiplier.
            targets: Surface :math:`\Gamma_T`, or several: on other meshes, or other
                surfaces of the contactor's own mesh and space.
            method: One of :data:`METHODS`.
            multiplier: ``("Lagrange", s)`` for :math:`\mathcal M^1_{h,s}` (continuous) or
                ``("DG", s)`` for :math:`\mathcal M^0_{h,s}` (discontinuous), Eq. (16);
                defaults to continuous of the contactor's displacement degree; ``("Dual",
                k)``: the dual basis of Pk, k the contactor's degree (:func:`contact_pair`).
            quadrature: One of :data:`~dolfinx_contact_s2s.quadrature.RULES`; defaults
                to ``"composite-gauss"`` (``"gauss"`` for ``node-to-segment-gauss``).
            quadrature_points: Points per (sub-)segment; defaults to the fewest Gauss
                points that integrate Eq. (17) exactly on straight segments (plus one per
                curved geometry degree), or the multiplier degree plus the displacement
                degree plus one for Newton-Cotes (highest degrees over all surfaces).
            weight: ``"unit"`` or ``"tributary"``, for ``node-to-segment``.
            search_radius: Largest normal distance at which facets are paired; defaults
                to the largest facet size of all surfaces.
            drop_coincident: For ``node-to-segment``: leave out the constraints of nodes
                that meet a target node (the duplicates of the second pass of the
                two-pass algorithm, section 4.3); see :func:`contact_pairs`.
            axisymmetric: Weight Eq. (17) by :math:`2\pi r` (see :func:`contact_pair`).

        Raises:
            ValueError: On every rank, for an unknown or inconsistent choice, a
                contactor that is its own target, or (``axisymmetric``) a mesh with
                :math:`r < 0` or a surface crossing or lying on the axis.
            NotImplementedError: On every rank, for a contactor whose facet dimension has
                no segmentation (:func:`~dolfinx_contact_s2s.segmentation.get_segmentation`).
        """
        single = isinstance(targets, ContactSurface) or hasattr(targets, "coupling_blocks")
        targets = [targets] if single else list(targets)
        if not targets:
            raise ValueError("a contact pair needs at least one target surface")
        if getattr(contactor, "rigid", False):
            raise ValueError(
                f"the rigid surface {contactor.tag} cannot be a contactor: the contactor "
                "carries the multiplier and must be deformable; make the rigid surface the "
                "target, contact_pair(deformable_surface, rigid_surface)"
            )
        #: Analytic obstacles among the targets (:mod:`dolfinx_contact_s2s.obstacles`).
        self.obstacles = [t for t in targets if getattr(t, "analytic", False)]
        targets = [t for t in targets if not getattr(t, "analytic", False)]
        if self.obstacles and method in ("node-to-node", "intermediate-surface"):
            raise ValueError(f"{method} needs target nodes: analytic obstacles have none")
        if self.obstacles and contactor.facet_dim == 2:
            raise NotImplementedError("analytic obstacles are implemented for 2D meshes only")
        for target in targets:
            if contactor is target or (
                contactor.V.mesh is target.V.mesh and contactor.tag == target.tag
            ):
                raise ValueError("the contactor surface must differ from its target surface")
            if contactor.V.mesh.comm.Compare(target.V.mesh.comm) == MPI.UNEQUAL:
                raise ValueError("contactor and target must live on the same communicator")
        self.axisymmetric = bool(axisymmetric)
        if self.axisymmetric:
            # The surfaces first: a surface crossing the axis is the more precise message.
            for surface in (contactor, *targets):
                check_axis_surface(surface)
            for mesh in {id(s.V.mesh): s.V.mesh for s in (contactor, *targets)}.values():
                check_axisymmetric_mesh(mesh)
        if method not in DISCRETIZATIONS:
            raise ValueError(f"unknown contact method {method!r}; choose from {METHODS}")
        if weight not in ("unit", "tributary"):
            raise ValueError("weight must be 'unit' or 'tributary'")
        discretization = DISCRETIZATIONS[method](method)
        self.segmentation = get_segmentation(contactor.facet_dim)
        # Cache of :meth:`swept_boxes`.
        self._swept: tuple[SurfaceData, npt.NDArray[np.floating]] | None = None
        if drop_coincident and not discretization.drops_coincident:
            raise ValueError("drop_coincident applies to node-to-segment only")
        self.contactor = contactor
        self.targets = targets
        self.method = method
        self.discretization = discretization
        self.weight = discretization.weight(weight)
        self.drop_coincident = drop_coincident

        quadrature = discretization.default_quadrature if quadrature is None else quadrature
        if quadrature not in RULES:
            raise ValueError(f"unknown quadrature {quadrature!r}; choose from {RULES}")
        self.quadrature = quadrature

        k_c = contactor.element.degree
        family, degree = ("Lagrange", k_c) if multiplier is None else multiplier
        continuous, self.dual = family in ("Lagrange", "P", "CG", "Dual"), family == "Dual"
        if not continuous and family not in ("DG", "Discontinuous Lagrange"):
            raise ValueError(f"multiplier family must be 'Lagrange' or 'DG', not {family!r}")
        if not isinstance(degree, (int, np.integer)) or degree < 0:
            raise ValueError(f"the multiplier degree must be an integer >= 0, not {degree!r}")
        if continuous and degree < 1:
            raise ValueError("a continuous multiplier needs degree 1 or more")
        discretization.check(contactor, targets, quadrature, multiplier)
        if discretization.fixed_multiplier is not None:
            family, degree = discretization.fixed_multiplier
            continuous = False

        #: The rule on [0, 1] (edges) or on each sub-triangle (faces), :func:`contact_rule`.
        self.rule, self.quadrature_points, self.rule_degree, self.rule_error = contact_rule(
            contactor, targets, quadrature, quadrature_points, degree, self.axisymmetric
        )

        continuous, degree, variant = discretization.multiplier(
            continuous, degree, self.quadrature_points
        )
        self.multiplier_degree = degree
        self.multiplier_continuous = continuous
        self.multiplier_variant = variant
        if search_radius is not None and not 0 < search_radius < np.inf:
            raise ValueError(
                f"search_radius must be positive and finite, not {search_radius!r}: the "
                "largest normal distance at which facets are paired (default: the largest "
                "facet size)"
            )
        if search_radius is None:
            search_radius = default_search_radius(contactor, targets)
        self.search_radius = float(search_radius)
        #: The multiplier space and its place on the contactor facets.
        self.multiplier = discretization.space(self)
        self.Q = self.multiplier.Q
        self.multiplier_element = self.multiplier.element
        self.submesh = self.Q.mesh
        gathered = [t.gather() for t in targets] if discretization.nodal else []
        self.duplicates = discretization.duplicates(self, gathered)

    @property
    def nodal(self) -> bool:
        """Whether the multipliers are nodal values (node-to-segment, node-to-node)."""
        return self.discretization.nodal

    @property
    def multiplier_label(self) -> str:
        r"""The multiplier space in the notation of Eq. (16), e.g. ``M^1_{h,1}``."""
        return self.discretization.label(self.multiplier_continuous, self.multiplier_degree)

    def swept_boxes(self) -> npt.NDArray[np.floating]:
        """Boxes of this process's contactor facets swept by the search radius (read-only).

        The candidate search of :meth:`sub_segments`, by :attr:`segmentation`; kept until
        the contactor's :attr:`~ContactSurface.data` is replaced.
        """
        C = self.contactor.data
        if self._swept is None or self._swept[0] is not C:
            boxes = self.segmentation.sweep(C, self.contactor.bounding_boxes(C), self.search_radius)
            boxes.setflags(write=False)
            self._swept = (C, boxes)
        return self._swept[1]

    def sub_segments(self, target: int = 0, data: SurfaceData | None = None) -> Pieces:
        """The pieces of the contactor facets against ``targets[target]`` (Fig. 15(b)).

        Contactor facets whose swept boxes (:meth:`swept_boxes`) overlap target facet
        boxes are cut by :attr:`segmentation`: :class:`SubSegments` for edges.

        Args:
            target: Index of the target in :attr:`targets`.
            data: The target facets to cut against; defaults to
                ``targets[target].gather()``. The target rows of the pieces index it.
        """
        t = self.targets[target]
        T = t.gather() if data is None else data
        ic, it = box_pairs(self.swept_boxes(), t.bounding_boxes(T), self.contactor.backend)
        C = self.contactor.data
        return self.segmentation.cut(C, T, ic, it, self.search_radius, self.contactor.backend)

    def multiplier_integrals(self) -> npt.NDArray[np.floating]:
        r"""The integrals :math:`|\int \mu_k|` of the owned multiplier basis functions.

        Collective the first time (:attr:`MultiplierSpace.integrals`). Without the ring
        weight also in axisymmetry: they measure the support of :math:`\mu_k` (is it
        covered by a target?), and a P2 vertex function on the axis has
        :math:`\int \mu_k\, 2\pi r\, ds = 0`.
        """
        return self.multiplier.integrals

    def multiplier_supports(self) -> npt.NDArray[np.floating]:
        r"""What a multiplier's coverage is compared with to call it uncovered (collective).

        :math:`\int \mu_k^2` (:attr:`MultiplierSpace.squares`) where
        :attr:`squared_coverage`, else :meth:`multiplier_integrals`.
        """
        return self.multiplier.squares if self.squared_coverage else self.multiplier.integrals

    @property
    def squared_coverage(self) -> bool:
        """Whether coverage is of mu_k^2 (faces, quadratic edges: vertex integrals may vanish)."""
        return self.contactor.facet_dim == 2 or self.multiplier.element.degree > 1 or self.dual

    def reach(self) -> npt.NDArray[np.floating] | None:
        """This process's contactor facets' box ``(2, gdim)``, grown by the search radius.

        ``None`` without facets. Every target facet that a contactor point or swept facet
        can meet lies in it (see :meth:`ContactSurface.gather_near`).
        """
        C = self.contactor.data
        if len(C) == 0:
            return None
        boxes = self.contactor.bounding_boxes(C)
        # One axis at a time: NumPy reduces a narrow array along its first axis slowly.
        lo = [boxes[:, 0, g].min() - self.search_radius for g in range(boxes.shape[2])]
        return np.array([lo, [boxes[:, 1, g].max() + self.search_radius for g in range(len(lo))]])

    def coupling_blocks(self, tangent: tuple | None = None) -> list[CouplingBlocks]:
        r"""Integrate Eq. (17) as the method prescribes (Eqs. 37, 39 or 40), per target.

        With ``tangent`` ``(axis, which)`` (meshed targets), a tangent in place of
        :math:`\mathbf N` and no gap: friction's weighted tangential displacements. In 2D
        the contactor's :math:`\mathbf T = (-n_{C,y}, n_{C,x})`; on faces :math:`\mathbf
        T_1` or :math:`\mathbf T_2` (1, 2) of :func:`~.kernels.face_backend.tangents`.

        Returns:
            One :class:`CouplingBlocks` per target, in the order of :attr:`targets`, then
            one per analytic obstacle of :attr:`obstacles` (no target columns), with
            global row and column indices (possibly empty on some processes).

        Raises:
            ValueError: On every rank, if a mesh of the pair moved after its surfaces were
                created.
        """
        for surface in (self.contactor, *self.targets):
            if surface.moved():
                raise ValueError(
                    f"the mesh of contact surface {surface.tag} moved after the surface was "
                    "created: create the contact surfaces and pairs again after moving a mesh"
                )
        blocks = [o.coupling_blocks(self) for o in self.obstacles]
        if not self.targets:
            return blocks
        gathered = self.discretization.gathered(self)
        groups = self.discretization.points(self, gathered)
        return [
            self._integrate(t, T, g, tangent)
            for t, T, g in zip(self.targets, gathered, groups, strict=True)
        ] + blocks

    def _integrate(
        self, ts: ContactSurface, T: SurfaceData, g: PointGroups, tangent: tuple | None = None
    ) -> CouplingBlocks:
        """The blocks of Eqs. (40)-(42) at the points ``g`` against target ``ts``."""
        cs, C = self.contactor, self.contactor.data
        if self.multiplier.corners is not None and not self.axisymmetric:
            return CouplingBlocks(ts, *face_blocks(self.multiplier, cs, C, ts, T, g, tangent))
        if hasattr(cs.backend, "edge_coupling") and not self.axisymmetric:
            args = (self.multiplier, cs, C, ts, T, g, self.squared_coverage, tangent)
            return CouplingBlocks(ts, *edge_blocks(*args))
        S, nq = g.weights.shape
        rows_c = np.repeat(g.contactor, nq)
        # One parameter per point on an edge, two reference coordinates on a face.
        xi = np.ascontiguousarray(g.xi.reshape(S * nq, *g.xi.shape[2:]))

        kernels = cs.backend
        normals = -kernels.outward_normals(C.coefficients, C.orientation, rows_c, xi)
        # Points, target points and gaps relative to the contactor facet's first point (one
        # copy of each group's facets; point p is in group local[p]): differences of numbers
        # of the size of the facets, so that a scene far from the origin loses nothing but
        # the round-off of its own node coordinates.
        local = np.repeat(np.arange(S, dtype=np.int32), nq)
        origin = C.coefficients[g.contactor, 0]
        c_local = kernels.shift(C.coefficients[g.contactor], -origin)
        t_local = ts.backend.shift(T.coefficients[g.target], -origin)
        x_c, _ = kernels.evaluate(c_local, local, xi)
        eta = kernels.intersect(t_local, local, x_c, normals)
        np.clip(eta, 0.0, 1.0, out=eta)
        x_t, _ = kernels.evaluate(t_local, local, eta)
        gaps = np.einsum("pg,pg->p", x_c - x_t, normals)

        mu = self.multiplier.basis(rows_c, xi, kernels)
        mu = mu.reshape(S, nq, mu.shape[1])
        gdim = normals.shape[1]
        if tangent is not None:  # T = (N_y, -N_x), the contactor's counterclockwise tangent
            normals, gaps = np.stack([normals[:, 1], -normals[:, 0]], axis=1), 0.0 * gaps
        phi_c, dofs_c = face_basis(cs, C, g.contactor, nq, xi)
        phi_t, dofs_t = face_basis(ts, T, g.target, nq, eta)
        b_c, b_t, gap = kernels.segment_to_segment(
            mu,
            phi_c.reshape(S, nq, phi_c.shape[1]),
            phi_t.reshape(S, nq, phi_t.shape[1]),
            normals.reshape(S, nq, gdim),
            self.point_weights(g, x_c + origin[local] if self.axisymmetric else x_c),
            gaps.reshape(S, nq),
        )
        # Plain weights: a P2 vertex function on the axis has a zero r-weighted integral.
        signed = np.einsum("sqk,sq->sk", mu, g.weights)
        coverage = np.einsum("sqk,sq->sk", mu**2, g.weights) if self.squared_coverage else signed
        return CouplingBlocks(ts, g.rows, dofs_c, b_c, dofs_t, b_t, gap, coverage, signed)

    def point_weights(
        self, g: PointGroups, x: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        r"""The weights of Eq. (40) at contactor points ``x``: times :math:`2\pi r` in axisymmetry.

        Node-based methods keep theirs: a tributary weight already is
        :math:`\int 2\pi r N_i\, ds`, and a unit weight makes the multiplier the node's ring
        force (:class:`~dolfinx_contact_s2s.discretizations.NodeToSegment`).
        """
        if not self.axisymmetric or self.nodal:
            return g.weights
        return ring_weights(g.weights, x[:, 0].reshape(g.weights.shape))


def contact_pairs(
    contactor: ContactSurface,
    targets: ContactSurface | Sequence[ContactSurface],
    *,
    method: str = "segment-to-segment",
    **options,
) -> list[ContactPair]:
    """The contact pairs of a discretization: one, or more for a two-pass method.

    Give every pair returned to the problem, e.g.
    ``LinearContactProblem(a, L, contact_pairs(c, t, method=...), bcs, ...)``.

    Args:
        contactor: First surface (the contactor of the first pass), from
            :func:`~dolfinx_contact_s2s.surface.contact_surface`.
        targets: Second surface, or a list of several.
        method: One of :data:`METHODS` (see :func:`contact_pair`), giving one pair, or
            ``"two-pass node-to-segment"`` (section 4.3), giving ``1 + len(targets)``
            pairs: node-to-segment with the contactor against the targets, then each
            target against the contactor without the constraints of nodes that coincide
            with nodes of the first (within :math:`10^{-8}` of the element size).
        **options: Keyword arguments of :func:`contact_pair`: ``multiplier``,
            ``quadrature``, ``quadrature_points``, ``weight``, ``search_radius`` and
            ``axisymmetric``, given to every pair.

    Returns:
        The list of :class:`ContactPair`.

    Raises:
        ValueError: On every rank, as :func:`contact_pair`.
    """
    if method == "two-pass node-to-segment":
        targets = [targets] if isinstance(targets, ContactSurface) else list(targets)
        first = ContactPair(contactor, targets, method="node-to-segment", **options)
        return [first] + [
            ContactPair(t, contactor, method="node-to-segment", drop_coincident=True, **options)
            for t in targets
        ]
    return [ContactPair(contactor, targets, method=method, **options)]


def contact_pair(
    contactor: ContactSurface,
    targets: ContactSurface | Sequence[ContactSurface],
    *,
    method: str = "segment-to-segment",
    multiplier: tuple[str, int] | None = None,
    quadrature: str | None = None,
    quadrature_points: int | None = None,
    weight: str = "unit",
    search_radius: float | None = None,
    axisymmetric: bool = False,
) -> ContactPair:
    r"""A contactor surface, its target surface(s) and a contact discretization (collective).

    The contactor :math:`\Gamma_C` carries the multiplier :math:`\lambda` (the contact
    pressure, positive in compression); the coupling of Eq. (17) is integrated wherever
    the contactor faces a target along its normal. A contactor that faces several
    surfaces takes them all in one pair, ``contact_pair(contactor, [target_a,
    target_b])``: one multiplier field for all of them. A contactor part facing no
    target carries no constraint; a part facing another pair's surface but none of its
    own targets is an error of the problem (:func:`~dolfinx_contact_s2s.checks.check_cover`).

    Args:
        contactor: Surface :math:`\Gamma_C` carrying the multiplier, from
            :func:`~dolfinx_contact_s2s.surface.contact_surface`.
        targets: Target surface :math:`\Gamma_T`, or a list of several: on other meshes,
            or other surfaces of the contactor's own mesh and space; rigid ones from
            :func:`~dolfinx_contact_s2s.obstacles.rigid_surface`, or analytic obstacles
            (:func:`~dolfinx_contact_s2s.obstacles.plane_obstacle`, ...: not with
            ``"node-to-node"`` or ``"intermediate-surface"``).
        method: The discretization, one of :data:`METHODS`:
            ``"segment-to-segment"`` (the default, section 5, Eqs. 40-42: the new
            algorithm with composite quadrature; passes the patch and inf-sup tests),
            ``"node-to-segment"`` (Eqs. 38-39: one constraint per contactor node),
            ``"node-to-segment-gauss"`` (the constraint at the Gauss points of the
            contactor segments, one multiplier per point), ``"node-to-node"`` (Eq. 37,
            coincident nodes only) or ``"intermediate-surface"`` (section 4.4, linear
            surfaces). For the two-pass method use :func:`contact_pairs`.
        multiplier: The multiplier space of Eq. (16): ``("Lagrange", s)`` for
            :math:`\mathcal M^1_{h,s}` (continuous, :math:`s \ge 1`) or ``("DG", s)`` for
            :math:`\mathcal M^0_{h,s}` (discontinuous, :math:`s \ge 0`), on the contactor
            facets. Default ``None``: continuous, of the contactor's displacement degree.
            ``("Dual", k)``: the dual basis of Pk, k the contactor's displacement degree
            (segment-to-segment; straight edges, triangles, parallelograms; not P2 triangles).
            Node-based methods and the intermediate surface need the default.
        quadrature: The rule integrating Eq. (17), one of
            :data:`~dolfinx_contact_s2s.quadrature.RULES`: ``"composite-gauss"`` or
            ``"composite-newton-cotes"`` on the sub-segments bounded by the nodes of both
            surfaces (Fig. 15(b)-(c)), ``"gauss"`` or ``"newton-cotes"`` on the contactor
            segments (Fig. 15(a), fails the patch test on non-matching meshes). Default
            ``None``: ``"composite-gauss"`` (``"gauss"`` for
            ``"node-to-segment-gauss"``).
        quadrature_points: Points per (sub-)segment. Default ``None``: the fewest that
            integrate Eq. (17) exactly on straight segments, plus one per curved
            geometry degree (Gauss: :math:`\lfloor (s + k + 2c)/2 \rfloor + 1` for
            multiplier degree :math:`s`, displacement degree :math:`k` and
            :math:`c` curved geometry degrees; Newton-Cotes: :math:`s + k + 1`); in
            axisymmetry :math:`k` counts the degree of :math:`r` too (the contactor's
            geometry degree).
        weight: For ``"node-to-segment"``: ``"unit"`` (the default, :math:`w^i = 1`: the
            multiplier is a nodal force) or ``"tributary"`` (the node's tributary
            length: the multiplier is a pressure), Eq. (39).
        search_radius: The largest normal distance (gap or overlap) at which a
            contactor facet and a target facet are paired, in the mesh's length unit: a
            contactor point meets a target only within this distance along its normal.
            Default ``None``: the largest facet length (chord) of the contactor and all
            targets, over all processes. Pass a larger value for surfaces that start
            farther apart, a smaller one where a surface must not reach a far one.
        axisymmetric: For bodies of
            :class:`~dolfinx_contact_s2s.elasticity.Material` ``(plane="axisymmetric")``:
            weight Eq. (17) by :math:`2\pi r`, with :math:`r = x_0` of the contactor point,
            so that :math:`\mathbf B` (Eq. 40), :math:`\mathbf G` and the multiplier mass
            (Eq. 29) are integrals over the 3D surface, the multiplier is the contact
            pressure and ``contact_forces()`` are total forces, as the forms' loads are.
            Node-to-segment and node-to-node: a tributary weight is
            :math:`\int 2\pi r N_i\, ds` (the multiplier a pressure), a unit weight makes
            the multiplier the node's total ring force. The surfaces must lie in
            :math:`r \ge 0`; one may touch the axis at an end node.

    Returns:
        The :class:`ContactPair`, with its multiplier space ``Q`` (a DOLFINx function
        space on a submesh of the contactor facets).

    Raises:
        ValueError: On every rank: an unknown ``method``, ``quadrature`` or ``weight``;
            a multiplier family other than Lagrange or DG or a bad degree; a multiplier
            or quadrature the method cannot use; non-matching meshes for
            ``"node-to-node"``; a ``search_radius`` that is not positive and finite; no
            target, a contactor that is its own target or rigid, or surfaces on
            different communicators; with ``axisymmetric``, a mesh with a node at
            :math:`r < 0`, or a surface crossing the axis or lying on it
            (:mod:`~dolfinx_contact_s2s.axisymmetry`).
    """
    return ContactPair(
        contactor,
        targets,
        method=method,
        multiplier=multiplier,
        quadrature=quadrature,
        quadrature_points=quadrature_points,
        weight=weight,
        search_radius=search_radius,
        axisymmetric=axisymmetric,
    )

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The rules of each contact discretization of El-Abbasi & Bathe (2001).

A discretization fixes three things (sections 4 and 5): the multiplier space (Eq. 16
on the contactor facets, point values, or the intermediate segments of section 4.4),
the contactor points with their weights :math:`w^i` (nodes, Eqs. 37 and 39; Gauss or
Newton-Cotes points of the contactor segments, Fig. 15(a); or of the sub-segments of
the new algorithm, Eqs. 40-42 and Fig. 15(b)-(c)), and which target each point meets.
Each is a small class; :data:`DISCRETIZATIONS` maps the method names of
:class:`~dolfinx_contact_s2s.pair.ContactPair` to them, so the method string is
read once, when the pair is built. What they need from a pair is :class:`PairLike`.
"""

from __future__ import annotations

import typing
from collections.abc import Sequence
from dataclasses import dataclass

from mpi4py import MPI

import basix
import basix.ufl
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.axisymmetry import ring_weights
from dolfinx_contact_s2s.multiplier import MultiplierSpace, cell_rows, facet_space
from dolfinx_contact_s2s.quadrature import interval_rule
from dolfinx_contact_s2s.search import find_targets, node_offsets
from dolfinx_contact_s2s.segmentation import Pieces, Segmentation, SubSegments
from dolfinx_contact_s2s.surface import ContactSurface, SurfaceData, tabulate

__all__ = [
    "DISCRETIZATIONS",
    "Discretization",
    "IntermediateSurface",
    "MultiplierSpace",
    "NodeToNode",
    "NodeToSegment",
    "NodeToSegmentGauss",
    "PairLike",
    "PointGroups",
    "SegmentToSegment",
]


@dataclass(frozen=True)
class PointGroups:
    """Integration points of Eq. (40) against one target, grouped by (sub-)segment.

    Attributes:
        contactor: Contactor facet row of each group, ``(S,)``.
        target: Target facet row (gathered data) of each group, ``(S,)``.
        xi: Contactor facet parameter of each point, ``(S, Q)``.
        weights: Weight of each point including the length element, ``(S, Q)``.
        rows: Global multiplier dofs of each group, ``(S, nk)``.
    """

    contactor: npt.NDArray[np.int32]
    target: npt.NDArray[np.int32]
    xi: npt.NDArray[np.floating]
    weights: npt.NDArray[np.floating]
    rows: npt.NDArray[np.int64]


class PairLike(typing.Protocol):
    """What a discretization reads from a pair (:class:`~dolfinx_contact_s2s.pair.ContactPair`).

    The multiplier attributes are those of the pair being built: :meth:`Discretization.space`
    runs before :attr:`multiplier` and :attr:`Q` exist.
    """

    contactor: ContactSurface
    targets: list[ContactSurface]
    search_radius: float
    segmentation: Segmentation
    quadrature: str
    rule: tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]
    weight: str
    axisymmetric: bool
    drop_coincident: bool
    multiplier_degree: int
    multiplier_continuous: bool
    multiplier_variant: basix.LagrangeVariant
    multiplier: MultiplierSpace
    Q: dolfinx.fem.FunctionSpace

    def reach(self) -> npt.NDArray[np.floating] | None:
        """This process's contactor box grown by the search radius."""
        ...

    def sub_segments(self, target: int = 0, data: SurfaceData | None = None) -> Pieces:
        """The pieces of the contactor facets against a target (Fig. 15(b))."""
        ...


def _multiplicity(space: MultiplierSpace) -> npt.NDArray[np.floating]:
    """Number of contactor facets (over all processes) that share each multiplier dof."""
    count = dolfinx.fem.Function(space.Q)
    np.add.at(count.x.array, space.Q.dofmap.list[space.cells].reshape(-1), 1.0)
    count.x.scatter_reverse(dolfinx.la.InsertMode.add)
    count.x.scatter_forward()
    return count.x.array


def _facet_integrals(pair: PairLike) -> npt.NDArray[np.floating]:
    r"""Integrals :math:`\int_f \mu_k` of the multiplier basis over each contactor facet.

    In axisymmetry (``pair.axisymmetric``) :math:`\int_f \mu_k\, 2\pi r`: the
    tributary area of the node's ring.
    """
    cs, C, space = pair.contactor, pair.contactor.data, pair.multiplier
    n = len(C)
    if cs.facet_dim == 2:
        # Faces: a rule of the multiplier's cell, exact for mu_k on parallelograms.
        X, w_face = basix.make_quadrature(space.element.cell_type, 2 * pair.multiplier_degree + 2)
        rows = np.repeat(np.arange(n, dtype=np.int32), w_face.size)
        xi = np.tile(X, (n, 1))
        _, _, dx = cs.evaluate(C, rows, xi)
        area = np.tile(w_face, n) * np.linalg.norm(np.cross(dx[:, :, 0], dx[:, :, 1]), axis=1)
        w = area[:, None] * space.basis(rows, xi, cs.backend)
        return w.reshape(n, w_face.size, w.shape[1]).sum(axis=1)  # n may be 0
    s_ref, w_ref = interval_rule("gauss", pair.multiplier_degree + 3)
    rows = np.repeat(np.arange(n, dtype=np.int32), s_ref.size)
    xi = np.tile(s_ref, n)
    _, x, dx = cs.evaluate(C, rows, xi)
    s_sub = np.where(space.flip[rows], 1.0 - xi, xi)
    mu = tabulate(space.element, 0, s_sub[:, None])[0]
    length = np.tile(w_ref, n) * np.linalg.norm(dx, axis=1)
    if pair.axisymmetric:
        length = ring_weights(length, x[:, 0])
    w = length[:, None] * mu
    return w.reshape(n, s_ref.size, mu.shape[1]).sum(axis=1)


def _rays(
    contactor: ContactSurface, rows: npt.NDArray[np.int32], xi: npt.NDArray[np.floating]
) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    r"""Contactor points and the direction :math:`\mathbf N = -\mathbf n_C` there (Eq. 38)."""
    C = contactor.data
    _, x, _ = contactor.evaluate(C, rows, xi)
    return x, -contactor.outward_normals(C, rows, xi)


class Discretization:
    """Rules shared by the discretizations; subclasses override what differs.

    Attributes:
        nodal: The multipliers are nodal values (collocation, Eqs. 37-39).
        drops_coincident: The method can leave out nodes meeting a target node (two-pass).
        default_quadrature: Rule used when the pair names none.
        own_multiplier: The method defines its own multiplier space.
        fixed_multiplier: ``(family, degree)`` that method's space starts from.
    """

    nodal: bool = False
    drops_coincident: bool = False
    default_quadrature: str = "composite-gauss"
    own_multiplier: bool = False
    fixed_multiplier: tuple[str, int] | None = None

    def __init__(self, method: str):
        """Rules of ``method`` (one of :data:`DISCRETIZATIONS`)."""
        self.method = method

    def check(
        self,
        contactor: ContactSurface,
        targets: Sequence[ContactSurface],
        quadrature: str,
        multiplier: tuple[str, int] | None,
    ) -> None:
        """Raise ValueError (on every rank: the inputs are the same) for a bad choice.

        Raises:
            NotImplementedError: On faces (3D), for all but segment-to-segment with the
                composite Gauss rule and a continuous Lagrange multiplier, and
                node-to-segment.
        """
        if self.own_multiplier and multiplier is not None:
            raise ValueError(f"{self.method} defines its own multiplier space")
        if (
            multiplier is not None
            and multiplier[0] == "Dual"
            and not (
                self.method == "segment-to-segment"
                and quadrature.startswith("composite")
                and multiplier[1] == contactor.element.degree
            )
        ):
            raise ValueError(
                "dual multipliers are implemented as ('Dual', k), k the contactor's "
                f"displacement degree ({contactor.element.degree}: the basis is "
                "biorthogonal to its trace), with segment-to-segment and a composite rule"
            )
        continuous = multiplier is None or multiplier[0] in ("Lagrange", "P", "CG", "Dual")
        s2s = self.method == "segment-to-segment" and quadrature == "composite-gauss"
        if contactor.facet_dim == 2 and not (
            (s2s and continuous) or self.method == "node-to-segment"
        ):
            raise NotImplementedError(
                "on the faces of 3D meshes: method='segment-to-segment' with the "
                "composite-gauss rule and a continuous Lagrange multiplier, or "
                "method='node-to-segment', only (got "
                f"method={self.method!r}, quadrature={quadrature!r}, multiplier={multiplier!r})"
            )

    def weight(self, weight: str) -> str:
        """The weight actually used (``"unit"`` or ``"tributary"``)."""
        return weight

    def multiplier(
        self, continuous: bool, degree: int, quadrature_points: int
    ) -> tuple[bool, int, basix.LagrangeVariant]:
        """Continuity, degree and Lagrange variant of the multiplier space."""
        variant = basix.LagrangeVariant.unset
        if degree > 2 or (not continuous and degree > 0):
            variant = basix.LagrangeVariant.gll_warped
        return continuous, degree, variant

    def label(self, continuous: bool, degree: int) -> str:
        r"""The multiplier space in the notation of Eq. (16), e.g. ``M^1_{h,1}``."""
        return f"M^{int(continuous)}_{{h,{degree}}}"

    def gathered(self, pair: PairLike) -> list[SurfaceData]:
        """The target facets this process can meet (collective).

        Row indices of the point groups of :meth:`points` refer to these arrays.
        """
        region = pair.reach()
        return [t.gather_near(region) for t in pair.targets]

    def space(self, pair: PairLike) -> MultiplierSpace:
        """The multiplier space of ``pair`` (Eq. 16 on the contactor facets)."""
        variant = pair.multiplier_variant
        dual = getattr(pair, "dual", False)
        if dual and (pair.axisymmetric or pair.contactor.cmap.degree != 1):
            raise ValueError(
                "dual multipliers need straight contactor facets (geometry of degree 1) in "
                "the plane: their biorthogonal basis (2 mu_i - mu_j on P1) holds for a "
                "constant Jacobian and no ring weight"
            )
        space = facet_space(
            pair.contactor, pair.multiplier_degree, not pair.multiplier_continuous, variant, dual
        )
        if dual:
            space.check_dual()
        return space

    def duplicates(self, pair: PairLike, gathered: Sequence[SurfaceData]) -> npt.NDArray[np.int64]:
        """Global multiplier dofs left out at construction (none by default)."""
        return np.empty(0, dtype=np.int64)

    def point_rule(self, pair: PairLike) -> tuple[npt.NDArray, ...]:
        """Contactor points of a point-based method: ``(rows, xi, weights, dofs)``.

        The points of ``pair.rule`` on every contactor segment (Fig. 15(a)), weighted by
        the rule's weight times the length element; ``dofs`` is -1 (no nodal dof).
        """
        cs, C = pair.contactor, pair.contactor.data
        n = len(C)
        s_ref, w_ref = pair.rule
        rows = np.repeat(np.arange(n, dtype=np.int32), s_ref.size)
        xi = np.tile(s_ref, n)
        _, _, dx = cs.evaluate(C, rows, xi)
        weights = np.tile(w_ref, n) * np.linalg.norm(dx, axis=1)
        return rows, xi, weights, np.full(rows.size, -1, dtype=np.int32)

    def hits(
        self, pair: PairLike, gathered: Sequence[SurfaceData]
    ) -> tuple[tuple[npt.NDArray, ...], npt.NDArray[np.int32], npt.NDArray[np.int32]]:
        """The points of :meth:`point_rule` that meet a target, the target and its facet."""
        rows, xi, weights, dofs = self.point_rule(pair)
        x, normals = _rays(pair.contactor, rows, xi)
        boxes = [t.bounding_boxes(T) for t, T in zip(pair.targets, gathered, strict=True)]
        backends = [t.backend for t in pair.targets]
        hit = find_targets(x, normals, gathered, boxes, backends, pair.search_radius)
        p = hit.points
        return (rows[p], xi[p], weights[p], dofs[p]), hit.target, hit.rows

    def points(self, pair: PairLike, gathered: Sequence[SurfaceData]) -> list[PointGroups]:
        """Integration points against each target (one group per point, Eqs. 37-39)."""
        (rows, xi, weights, _), which, t_rows = self.hits(pair, gathered)
        out = []
        for j in range(len(pair.targets)):
            sel = which == j
            r = rows[sel]
            out.append(
                PointGroups(
                    r, t_rows[sel], xi[sel, None], weights[sel, None], cell_rows(pair.multiplier, r)
                )
            )
        return out


class SegmentToSegment(Discretization):
    """Segment-to-segment (section 5, Eqs. 40-42): Eq. (17) integrated by a rule.

    ``composite-`` rules integrate on the sub-segments bounded by the nodes of the
    contactor and of every target (Fig. 15(b)-(c), the new algorithm; a contactor facet
    facing two targets is integrated on both pieces); the others on the contactor
    segments only (Fig. 15(a)).
    """

    def points(self, pair: PairLike, gathered: Sequence[SurfaceData]) -> list[PointGroups]:
        """Sub-segment points (composite rules) or contactor segment points."""
        if not pair.quadrature.startswith("composite-"):
            return super().points(pair, gathered)
        cs = pair.contactor
        out = []
        for j, (_, T) in enumerate(zip(pair.targets, gathered, strict=True)):
            seg = pair.sub_segments(j, T)
            xi, weights = pair.segmentation.points(cs.data, seg, pair.rule, cs.backend)
            rows = cell_rows(pair.multiplier, seg.contactor)
            out.append(PointGroups(seg.contactor, seg.target, xi, weights, rows))
        return out


class NodeToSegment(Discretization):
    r"""Node-to-segment (Eqs. 38-39): one constraint per contactor node.

    The weight is :math:`w^i = 1` (``"unit"``, the multiplier is a nodal force) or the
    node's tributary length (``"tributary"``, a pressure). In axisymmetry the tributary
    weight is :math:`\int 2\pi r N_i\, ds` and a unit weight makes the multiplier the
    node's total ring force; with P2 the tributary weight of a vertex on the axis is 0
    (:math:`\int_0^h 2\pi r N_0\, dr = 0`), a zero constraint that the rank check
    (Eq. 35) refuses: use segment-to-segment there. Each node meets the nearest
    target along its normal. With ``drop_coincident`` (the second pass of section 4.3)
    nodes meeting a target node are left out: :meth:`duplicates`. On faces (3D) the
    nodes are those of the contactor's displacement degree, the tributary weight is the
    node's area :math:`\int N_i\, dA` (zero at the vertices of P2 triangles: refused),
    and the two-pass method is not implemented.
    """

    nodal = True
    drops_coincident = True

    def check(self, contactor, targets, quadrature, multiplier) -> None:
        """Nodal multipliers: continuous, of the contactor's degree."""
        super().check(contactor, targets, quadrature, multiplier)
        family, degree = (
            ("Lagrange", contactor.element.degree) if multiplier is None else multiplier
        )
        if family not in ("Lagrange", "P", "CG") or degree != contactor.element.degree:
            raise ValueError(f"{self.method} puts one multiplier on every contactor node")

    def space(self, pair: PairLike) -> MultiplierSpace:
        """The nodal multiplier space; ValueError (every rank) for zero tributary areas."""
        cs = pair.contactor
        if pair.weight == "tributary" and cs.facet_dim == 2 and cs.element.degree == 2:
            if cs.cell_type == basix.CellType.tetrahedron:
                raise ValueError(
                    "node-to-segment with weight='tributary' on P2 triangles: a vertex "
                    "node's tributary area (the integral of its basis function) is zero, "
                    "a constraint of weight 0; use weight='unit' or segment-to-segment"
                )
        return super().space(pair)

    def point_rule(self, pair: PairLike) -> tuple[npt.NDArray, ...]:
        """Every multiplier node on every contactor facet, with its weight (Eq. 39)."""
        space, n = pair.multiplier, len(pair.contactor.data)
        # Every multiplier dof sits on a contactor node, at these points of Q's cell.
        points = space.element.basix_element.points
        k = points.shape[0]
        rows = np.repeat(np.arange(n, dtype=np.int32), k)
        if space.corners is None:
            s = np.tile(points[:, 0], n)
            xi = np.where(space.flip[rows], 1.0 - s, s)
        else:
            # Faces: invert X = X0 + xi_1 (X1 - X0) + xi_2 (X2 - X0) (MultiplierSpace.basis).
            X0, X1, X2 = (space.corners[rows, i] for i in range(3))
            A = np.stack([X1 - X0, X2 - X0], axis=2)
            xi = np.linalg.solve(A, (np.tile(points, (n, 1)) - X0)[:, :, None])[:, :, 0]
        dofs = space.Q.dofmap.list[space.cells].reshape(-1)
        if pair.weight == "unit":
            weights = 1.0 / _multiplicity(space)[dofs]
        else:
            weights = _facet_integrals(pair).reshape(-1)
        return rows, xi, weights, dofs

    def coincident(
        self, pair: PairLike, gathered: Sequence[SurfaceData]
    ) -> tuple[npt.NDArray[np.bool_], npt.NDArray]:
        """Whether each hitting node meets a target node (within 1e-8 of the element size)."""
        (rows, xi, _, dofs), which, t_rows = self.hits(pair, gathered)
        local_h = min(
            (
                float(np.min(t.sizes(T), initial=np.inf))
                for t, T in zip(pair.targets, gathered, strict=True)
            ),
            default=np.inf,
        )
        h = pair.contactor.comm.allreduce(local_h, op=MPI.MIN)
        offsets = np.empty(rows.size)
        for j, (t, T) in enumerate(zip(pair.targets, gathered, strict=True)):
            sel = which == j
            x, normals = _rays(pair.contactor, rows[sel], xi[sel])
            degree = t.element.degree
            offsets[sel] = node_offsets(x, normals, T, t_rows[sel], degree, t.backend)
        return offsets <= 1e-8 * h, dofs

    def duplicates(self, pair: PairLike, gathered: Sequence[SurfaceData]) -> npt.NDArray[np.int64]:
        """With ``drop_coincident``: the multipliers of nodes that meet a target node."""
        if not pair.drop_coincident:
            return np.empty(0, dtype=np.int64)
        if pair.contactor.facet_dim == 2:
            raise NotImplementedError(
                "on the faces of 3D meshes: single-pass node-to-segment only, not the "
                "two-pass method (drop_coincident)"
            )
        coincident, dofs = self.coincident(pair, gathered)
        imap = pair.Q.dofmap.index_map
        local = np.unique(dofs[coincident])
        mine = imap.local_to_global(local.astype(np.int32)).astype(np.int64)
        return np.unique(np.concatenate(pair.contactor.comm.allgather(mine)))


class NodeToNode(NodeToSegment):
    """Node-to-node (Eq. 37): node-to-segment with unit weights on coincident nodes."""

    drops_coincident = False

    def weight(self, weight: str) -> str:
        """Always ``"unit"``."""
        return "unit"

    def duplicates(self, pair: PairLike, gathered: Sequence[SurfaceData]) -> npt.NDArray[np.int64]:
        """None; raise ValueError on every rank unless the nodes of both sides coincide."""
        coincident, _ = self.coincident(pair, gathered)
        # Every contactor node meets a target node, and there are as many of each
        # (targets sharing a space share their nodes: count each space's nodes once).
        nodes: dict[int, list[npt.NDArray[np.int64]]] = {}
        for t, T in zip(pair.targets, gathered, strict=True):
            closure = t.element.basix_element.entity_closure_dofs[1]
            local = np.array([closure[lf] for lf in T.local_facet], dtype=np.int64)
            local = local.reshape(len(T), -1)
            block_dofs = T.dofs[:, :: t.V.dofmap.index_map_bs]
            nodes.setdefault(id(t.V), []).append(np.take_along_axis(block_dofs, local, axis=1))
        num_nodes = sum(np.unique(np.concatenate(n, axis=None)).size for n in nodes.values())
        same_count = num_nodes == pair.Q.dofmap.index_map.size_global
        if not same_count or pair.contactor.comm.allreduce(int(np.count_nonzero(~coincident))):
            raise ValueError(
                "node-to-node contact needs coincident nodes on the two surfaces; "
                "use node-to-segment or segment-to-segment on non-matching meshes"
            )
        return np.empty(0, dtype=np.int64)


class NodeToSegmentGauss(Discretization):
    """The node-to-segment constraint at the contactor's Gauss points [21, 22].

    One discontinuous multiplier per Gauss point: Lagrange at the Gauss points.
    """

    default_quadrature = "gauss"
    own_multiplier = True

    def check(self, contactor, targets, quadrature, multiplier) -> None:
        """Only the plain Gauss rule."""
        super().check(contactor, targets, quadrature, multiplier)
        if quadrature != "gauss":
            raise ValueError("node-to-segment-gauss constrains the contactor's Gauss points")

    def multiplier(self, continuous, degree, quadrature_points):
        """Discontinuous Lagrange of degree ``points - 1`` at the Gauss points."""
        return False, quadrature_points - 1, basix.LagrangeVariant.gl_warped

    def label(self, continuous: bool, degree: int) -> str:
        """``"point values"``."""
        return "point values"


class IntermediateSurface(Discretization):
    """The intermediate contact surface (section 4.4, Fig. 13, linear 2D surfaces [24]).

    The nodes of both surfaces are projected onto a surface midway between them; one
    constant pressure per segment between projected nodes, integrated exactly there.
    The multiplier lives on a mesh of those segments (against every target).
    """

    own_multiplier = True
    fixed_multiplier = ("DG", 0)

    def __init__(self, method: str):
        """Rules of ``method``; :meth:`space` fills the segments of :meth:`points`."""
        super().__init__(method)
        self._segments: list[SubSegments] = []
        self._rows = np.empty(0, dtype=np.int64)
        self._lengths = np.empty(0)

    def check(self, contactor, targets, quadrature, multiplier) -> None:
        """Linear surfaces and the composite Gauss rule only."""
        super().check(contactor, targets, quadrature, multiplier)
        linear = all(s.element.degree == 1 and s.cmap.degree == 1 for s in (contactor, *targets))
        if not linear:
            raise ValueError("the intermediate contact surface is for linear 2D surfaces")
        if quadrature != "composite-gauss":
            raise ValueError("the intermediate surface integrates its own segments exactly")

    def label(self, continuous: bool, degree: int) -> str:
        """``"M^0_{h,0} (intermediate)"``."""
        return "M^0_{h,0} (intermediate)"

    def gathered(self, pair: PairLike) -> list[SurfaceData]:
        """The whole targets: :meth:`space` cut its segments against them."""
        return [t.gather() for t in pair.targets]

    def space(self, pair: PairLike) -> MultiplierSpace:
        """A mesh of the intermediate segments and a piecewise-constant multiplier on it."""
        cs, C, comm = pair.contactor, pair.contactor.data, pair.contactor.comm
        self._segments = []
        mids = []
        for j, target in enumerate(pair.targets):
            T = target.gather()
            seg = typing.cast(SubSegments, pair.sub_segments(j, T))
            # Points midway between the contactor's sub-segment ends and their target points.
            rows = np.repeat(seg.contactor, 2)
            xi = np.stack([seg.lo, seg.hi], axis=1).reshape(-1)
            _, x, _ = cs.evaluate(C, rows, xi)
            t_rows = np.repeat(seg.target, 2)
            eta = np.clip(target.intersect(T, t_rows, x, -cs.outward_normals(C, rows, xi)), 0, 1)
            _, x_t, _ = target.evaluate(T, t_rows, eta)
            self._segments.append(seg)
            mids.append(0.5 * (x + x_t))
        x = np.concatenate(mids)
        n = x.shape[0] // 2
        offset = comm.exscan(n) or 0
        cells = (2 * offset + np.arange(2 * n, dtype=np.int64)).reshape(n, 2)
        coordinate = basix.ufl.element("Lagrange", "interval", 1, shape=(x.shape[1],))
        mesh = dolfinx.mesh.create_mesh(comm, cells=cells, x=x, e=coordinate)
        element = basix.ufl.element("DG", "interval", 0)
        Q = dolfinx.fem.functionspace(mesh, element)
        # DOLFINx redistributes the cells: find each segment's multiplier dof again.
        original = np.asarray(mesh.topology.original_cell_index, dtype=np.int64)
        imap = Q.dofmap.index_map
        dofs = imap.local_to_global(Q.dofmap.list[: original.size, 0].astype(np.int32))
        lookup = np.empty(comm.allreduce(n), dtype=np.int64)
        for orig, gdofs in comm.allgather((original, dofs)):
            lookup[orig] = gdofs
        self._rows = lookup[offset + np.arange(n)]
        self._lengths = np.linalg.norm(x[1::2] - x[0::2], axis=1)
        return MultiplierSpace(
            Q, element, np.empty(0, dtype=np.int32), np.zeros(len(C), dtype=bool)
        )

    def points(self, pair: PairLike, gathered: Sequence[SurfaceData]) -> list[PointGroups]:
        """The rule on the intermediate segments, mapped linearly onto the sub-segments."""
        s_ref, w_ref = pair.rule
        out, start = [], 0
        for seg in self._segments:
            stop = start + len(seg)
            xi = seg.lo[:, None] + (seg.hi - seg.lo)[:, None] * s_ref[None, :]
            weights = self._lengths[start:stop, None] * w_ref[None, :]
            rows = self._rows[start:stop, None]
            out.append(PointGroups(seg.contactor, seg.target, xi, weights, rows))
            start = stop
        return out


#: The discretization of each method name (sections 4 and 5).
DISCRETIZATIONS: dict[str, type[Discretization]] = {
    "segment-to-segment": SegmentToSegment,
    "node-to-segment": NodeToSegment,
    "node-to-segment-gauss": NodeToSegmentGauss,
    "node-to-node": NodeToNode,
    "intermediate-surface": IntermediateSurface,
}

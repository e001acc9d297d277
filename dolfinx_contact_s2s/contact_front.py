# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Where a 3D contact zone ends: the zero level set of the multiplier on the contactor's faces.

The discrete contact conditions (Eq. 1 on the nodal weighted gaps of Eq. 17) end the
contact zone of a 3D model between multiplier nodes: on every edge of a multiplier face
with an active end and an inactive end. :func:`contact_front` finds, on each such edge,
where the linear interpolant of :math:`\lambda` between its two ends crosses zero (on
the chord between the nodes: the zero level set of the P1 multiplier), and measures
those crossings from an axis the user gives (the normal through the first touching
point of an axisymmetric contact). It needs no law of the pressure (no Hertz): the
estimate of the contact radius is the mean radius of the crossings, its bracket the
mean radii of the edges' active and inactive ends (each crossing lies between them;
the 3D form of :class:`~dolfinx_contact_s2s.postprocess.ContactEdge`'s bracket), and
the faces that carry the crossings give the band where the front lies (their radial
spread, and their nodes: where to refine,
:func:`~dolfinx_contact_s2s.unilateral.refine_contact_zone`).

Inside the bracket, the weighted gaps of the inactive nodes near the front place it
(``gaps=``, the 3D form of the ``"gap"`` estimate of
:func:`~dolfinx_contact_s2s.contact_zones`): beyond a smooth contact edge at radius
:math:`e` the gap opens like :math:`C (r - e)_+^{3/2}` (the local law of an elastic
contact edge between smooth bodies, not Hertz's whole profile); weighted by the
multiplier's basis as in Eq. (17) it predicts every nodal weighted gap
:math:`\tilde g_k = C \int \mu_k (r - e)_+^{3/2}`, and :math:`e` is the radius that fits
the measured ones best (:math:`C` by least squares for each :math:`e`, the relative
misfits of the nodes within three edges of the front).

Collective; the same numbers on every process, whatever the partition.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from dataclasses import dataclass, field

import basix
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.quadrature import split_face_rule

__all__ = ["ContactFront", "contact_front", "curvature_indicator"]

#: The inactive nodes within this many edges of the front fit the gap estimate.
GAP_RINGS = 3


@dataclass(frozen=True)
class ContactFront:
    r"""The edge of the contact zone of a 3D pair, measured from an axis.

    Attributes:
        points: The zero crossings of :math:`\lambda` ``(n, 3)``, one per edge of a
            multiplier face from an active to an inactive node (a crossing at a node
            shared by several such edges counted once).
        radii: Their distances from the axis ``(n,)``.
        inside: Distance from the axis of each crossing's active node ``(n,)`` (of a
            crossing at an inactive node: the mean over its edges to active nodes).
        outside: Distance from the axis of each crossing's inactive node ``(n,)``.
        edge_lengths: Length of each crossing's edge ``(n,)`` (the mean, likewise).
        face_radii: Smallest and largest distance from the axis of the nodes of the faces
            that carry the crossings (``nan`` without crossings).
        peak: The largest :math:`\lambda` of the multiplier's nodes (the peak pressure).
        peak_point: Where it is ``(3,)``.
        peak_length: The longest edge of the multiplier faces at that node (where to
            refine to measure the peak's discretization error).
        gap_radius: The radius of the contact edge fitted to the weighted gaps of the
            inactive nodes near the front (``gaps=``; ``nan`` without them, or with too
            few such nodes), clipped to :attr:`bounds`.
        gap_nodes: How many nodes that fit used.
    """

    points: npt.NDArray[np.floating]
    radii: npt.NDArray[np.floating]
    inside: npt.NDArray[np.floating]
    outside: npt.NDArray[np.floating]
    edge_lengths: npt.NDArray[np.floating]
    face_radii: tuple[float, float]
    peak: float = math.nan
    peak_point: npt.NDArray[np.floating] = field(default_factory=lambda: np.full(3, np.nan))
    peak_length: float = math.nan
    gap_radius: float = math.nan
    gap_nodes: int = 0

    @property
    def radius(self) -> float:
        """The estimated contact radius: the mean radius of the crossings."""
        return float(np.mean(self.radii)) if self.radii.size else math.nan

    @property
    def bounds(self) -> tuple[float, float]:
        """The bracket of :attr:`radius`: the mean radii of the inactive and active ends.

        Each crossing lies on its edge, between its active and its inactive node; the
        mean radius of the discrete front lies between their means.
        """
        if not self.radii.size:
            return (math.nan, math.nan)
        lo, hi = float(np.mean(self.inside)), float(np.mean(self.outside))
        return (min(lo, hi), max(lo, hi))

    @property
    def middle(self) -> float:
        r"""The middle of :attr:`bounds`: an estimate off by at most half the bracket.

        Where :math:`\lambda = 0` at the inactive nodes (the active-set solution), every
        crossing is an inactive node and :attr:`radius` is the bracket's upper end.
        """
        lo, hi = self.bounds
        return 0.5 * (lo + hi)

    @property
    def estimate(self) -> float:
        """:attr:`gap_radius` where it was made, else :attr:`middle` (:attr:`method`)."""
        return self.gap_radius if math.isfinite(self.gap_radius) else self.middle

    @property
    def method(self) -> str:
        """How :attr:`estimate` was found: ``"gap"`` or ``"middle"``."""
        return "gap" if math.isfinite(self.gap_radius) else "middle"

    @property
    def bracket(self) -> float:
        """Width of :attr:`bounds` (the error bar of :attr:`radius`)."""
        lo, hi = self.bounds
        return hi - lo

    @property
    def spread(self) -> float:
        """Radial spread of the faces that carry the crossings (the band of the front)."""
        return self.face_radii[1] - self.face_radii[0]


def _gather(
    multiplier: dolfinx.fem.Function,
    active: dolfinx.fem.Function | None,
    gaps: dolfinx.fem.Function | None = None,
) -> tuple[npt.NDArray, npt.NDArray, npt.NDArray, npt.NDArray, npt.NDArray]:
    """Coordinates, values, active flags, gaps (global dof order), vertex dofs of every face."""
    Q = multiplier.function_space
    mesh = Q.mesh
    imap = Q.dofmap.index_map
    n = imap.size_local
    x = Q.tabulate_dof_coordinates()[:n]
    lam = multiplier.x.array[:n].real
    on = (lam > 0.0) if active is None else (active.x.array[:n].real > 0.5)
    g = np.zeros(n) if gaps is None else gaps.x.array[:n].real
    num = mesh.topology.index_map(mesh.topology.dim).size_local
    cell = mesh.topology.cell_name()
    vertices = len(basix.topology(basix.CellType[cell])[0])
    local = Q.dofmap.list[:num, :vertices]
    cells = imap.local_to_global(local.reshape(-1)).reshape(-1, vertices)
    parts = mesh.comm.allgather((imap.local_range[0], x, lam, on, g, cells))
    size = imap.size_global
    X, L, A, G = np.zeros((size, 3)), np.zeros(size), np.zeros(size, dtype=bool), np.zeros(size)
    for start, xx, ll, aa, gg, _ in parts:
        X[start : start + ll.size], L[start : start + ll.size] = xx, ll
        A[start : start + ll.size], G[start : start + ll.size] = aa, gg
    faces = np.concatenate([p[5] for p in parts]).astype(np.int64)
    return X, L, A, G, faces


def _unique_edges(faces: npt.NDArray, cell: str) -> npt.NDArray:
    """The edges of the faces, each once, as sorted pairs of node indices."""
    ref = basix.topology(basix.CellType[cell])[1]
    return np.unique(np.sort(np.concatenate([faces[:, list(e)] for e in ref]), axis=1), axis=0)


def _gap_radius(
    X: npt.NDArray,
    on: npt.NDArray,
    g: npt.NDArray,
    faces: npt.NDArray,
    cell: str,
    radius: typing.Callable[[npt.NDArray], npt.NDArray],
    bounds: tuple[float, float],
    dual: bool,
) -> tuple[float, int]:
    r"""The edge radius :math:`e` whose law :math:`C (r - e)_+^{3/2}` fits the weighted gaps.

    The inactive nodes with a positive weighted gap within :data:`GAP_RINGS` edges of the
    front; on each of their faces (on its chords: flat faces through the vertices) the
    model :math:`\int \mu_k (r - e)_+^{3/2}` by a degree-8 rule on each of 16 pieces of
    the face (the kink then costs accuracy on a few pieces); for each :math:`e`,
    :math:`C` minimizes :math:`\sum_k (1 - C m_k(e) / \tilde g_k)^2`; :math:`e` minimizes
    the rest (a scan of the search interval, then golden sections).
    """
    edges = _unique_edges(faces, cell)
    mixed = edges[on[edges[:, 0]] != on[edges[:, 1]]]
    near = np.zeros(X.shape[0], dtype=bool)
    near[mixed[~on[mixed]]] = True
    for _ in range(GAP_RINGS - 1):
        touched = near[edges[:, 0]] | near[edges[:, 1]]
        near[edges[touched].reshape(-1)] = True
        near &= ~on
    nodes = np.flatnonzero(near & (g > 0.0))
    if nodes.size < 2:
        return math.nan, int(nodes.size)
    index = np.full(X.shape[0], -1)
    index[nodes] = np.arange(nodes.size)
    around = faces[np.isin(faces, nodes).any(axis=1)]
    local, corners = index[around], X[around]
    points, weights = split_face_rule(cell, 8, 4)
    element = basix.create_element(basix.ElementFamily.P, basix.CellType[cell], 1)
    phi = element.tabulate(1, points)[:, :, :, 0]
    mu = phi[0]
    if dual:
        # psi = A mu, A = D M^-1 on the reference face (the dual basis on affine faces).
        mass = mu.T @ (weights[:, None] * mu)
        mu = mu @ np.linalg.solve(mass, np.diag(mass.sum(axis=1)))
    x = np.einsum("qv,fvd->fqd", phi[0], corners)
    tangents = [np.einsum("qv,fvd->fqd", phi[i], corners) for i in (1, 2)]
    area = np.linalg.norm(np.cross(*tangents), axis=2) * weights
    r = radius(x.reshape(-1, 3)).reshape(area.shape)
    keep = local >= 0

    def misfit(e: float) -> float:
        moments = (np.maximum(r - e, 0.0) ** 1.5 * area) @ mu
        m = np.bincount(local[keep], weights=moments[keep], minlength=nodes.size)
        y = m / g[nodes]
        return float(y.size - y.sum() ** 2 / (y @ y)) if y @ y > 0.0 else math.inf

    lo, hi = float(radius(X[mixed[on[mixed]]]).min()), float(radius(X[nodes]).max())
    grid = np.linspace(lo, hi, 101)
    k = int(np.argmin([misfit(e) for e in grid]))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    golden = 0.5 * (math.sqrt(5.0) - 1.0)
    for _ in range(40):
        c, d = b - golden * (b - a), a + golden * (b - a)
        a, b = (a, d) if misfit(c) < misfit(d) else (c, b)
    return float(np.clip(0.5 * (a + b), *bounds)), int(nodes.size)


def contact_front(
    multiplier: dolfinx.fem.Function,
    active: dolfinx.fem.Function | None = None,
    *,
    centre: npt.ArrayLike,
    axis: npt.ArrayLike,
    gaps: dolfinx.fem.Function | None = None,
    dual: bool = False,
) -> ContactFront:
    r"""The zero level set of the multiplier on the contactor's faces (collective).

    On every edge of a multiplier face (its vertices: the P1 interpolant, or the vertex
    values of a higher degree) whose ends are an active node :math:`i` and an inactive
    node :math:`o`, the crossing is at :math:`t = \lambda_i / (\lambda_i - \lambda_o)`
    along the chord from :math:`i` to :math:`o` (at :math:`o` where
    :math:`\lambda_o = 0`, the active-set solution's value; clipped to the edge). The
    distances are measured from the line through ``centre`` along ``axis``.

    Args:
        multiplier: The multiplier of a pair of a 3D model, ``problem.multipliers[j]``.
        active: Its active set, ``problem.active[j]`` (``None``: :math:`\lambda > 0`).
        centre: A point of the axis (e.g. the first touching point).
        axis: Direction of the axis (e.g. the contact normal there); need not be unit.
        gaps: The pair's weighted gaps, ``problem.gaps[j]``: with them the front also
            has :attr:`ContactFront.gap_radius` (the module's gap estimate), for
            multipliers of degree 1 (P1 triangles, Q1 quadrilaterals).
        dual: Whether the pair's multipliers are dual (``multiplier=("Dual", 1)``): its
            weighted gaps are integrals against the dual basis.

    Returns:
        The front; the same on every process.

    Raises:
        ValueError: On every process, for a multiplier not on faces in 3D, a non-finite
            centre, an axis of zero length, or gaps with a multiplier of higher degree
            or on another space.
    """
    Q = multiplier.function_space
    mesh = Q.mesh
    if mesh.geometry.dim != 3 or mesh.topology.dim != 2:
        raise ValueError(
            f"contact_front reads a multiplier on the faces of a 3D model, not on a "
            f"{mesh.topology.dim}D mesh in {mesh.geometry.dim}D (2D: contact_zones)"
        )
    c = np.asarray(centre, dtype=np.float64).reshape(-1)
    n = np.asarray(axis, dtype=np.float64).reshape(-1)
    if c.size != 3 or n.size != 3 or not (np.all(np.isfinite(c)) and np.all(np.isfinite(n))):
        raise ValueError(f"centre and axis must be 3 finite numbers each, not {centre}, {axis}")
    if not np.linalg.norm(n) > 0.0:
        raise ValueError("the axis has zero length")
    n = n / np.linalg.norm(n)
    if gaps is not None:
        degree = Q.ufl_element().basix_element.degree
        if degree != 1 or gaps.function_space.dofmap.index_map.size_global != (
            Q.dofmap.index_map.size_global
        ):
            raise ValueError(
                f"the gap estimate reads the weighted gaps of a multiplier of degree 1 on "
                f"the multiplier's own space (degree {degree} here)"
            )

    X, lam, on, g, faces = _gather(multiplier, active, gaps)

    def radius(p: npt.NDArray) -> npt.NDArray:
        d = p - c
        return np.linalg.norm(d - np.outer(d @ n, n), axis=1)

    ref = basix.topology(basix.CellType[mesh.topology.cell_name()])[1]
    edges = np.concatenate([faces[:, list(e)] for e in ref])
    owner = np.tile(np.arange(faces.shape[0]), len(ref))
    mixed = on[edges[:, 0]] != on[edges[:, 1]]
    edges, owner = edges[mixed], owner[mixed]
    # Each edge from its active node i to its inactive node o, once.
    flip = ~on[edges[:, 0]]
    edges[flip] = edges[flip][:, ::-1]
    edges = np.unique(edges, axis=0)
    carriers = np.unique(owner)
    i, o = edges[:, 0], edges[:, 1]
    li, lo = np.maximum(lam[i], 0.0), np.minimum(lam[o], 0.0)
    t = np.clip(np.where(li - lo > 0.0, li / np.maximum(li - lo, 1e-300), 0.5), 0.0, 1.0)
    # A crossing at an inactive node (t = 1) is that node, whatever the edge: once, with
    # the mean radius and length of its edges (not one edge's: the choice would follow
    # the dof numbering, which changes with the partition).
    key = np.where(t >= 1.0, o, X.shape[0] + np.arange(edges.shape[0]))
    _, once, group = np.unique(key, return_index=True, return_inverse=True)
    group = group.reshape(-1)
    count = np.bincount(group)

    def mean(values: npt.NDArray) -> npt.NDArray:
        return np.bincount(group, weights=values) / count

    inside = mean(radius(X[i]))
    lengths_io = mean(np.linalg.norm(X[o] - X[i], axis=1))
    i, o, t = i[once], o[once], t[once]
    points = X[i] + t[:, None] * (X[o] - X[i])
    if carriers.size:
        r = radius(X[faces[carriers].reshape(-1)])
        face_radii = (float(r.min()), float(r.max()))
    else:
        face_radii = (math.nan, math.nan)
    corners = np.unique(faces)
    top = int(corners[np.argmax(lam[corners])]) if corners.size else -1
    around = faces[np.any(faces == top, axis=1)]
    lengths = np.concatenate(
        [np.linalg.norm(X[around[:, e[0]]] - X[around[:, e[1]]], axis=1) for e in ref]
    )
    front = ContactFront(
        points,
        radius(points),
        inside,
        radius(X[o]),
        lengths_io,
        face_radii,
        float(lam[top]) if corners.size else math.nan,
        X[top].copy() if corners.size else np.full(3, np.nan),
        float(lengths.max()) if lengths.size else math.nan,
    )
    if gaps is None or not i.size:
        return front
    cell = mesh.topology.cell_name()
    fitted, used = _gap_radius(X, on, g, faces, cell, radius, front.bounds, dual)
    return dataclasses.replace(front, gap_radius=fitted, gap_nodes=used)


def curvature_indicator(
    fields: typing.Sequence[dolfinx.fem.Function], active: dolfinx.fem.Function | None = None
) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    r"""How well the multiplier faces resolve a field inside a 3D contact zone (collective).

    At every active node whose neighbours (the other vertices of its faces) are all
    active: the distance of the field from the plane fitted by least squares, in the
    node's tangent plane, to its neighbours' values, relative to the largest value over
    the active nodes. The 3D form of the 2D pressure indicator (the distance from the line
    through the two neighbours): zero for a linear field, about :math:`h^2 |\nabla^2
    \lambda|` for a smooth one (on a centrally symmetric ring, the mean of
    :math:`\frac12 \mathbf d^T \nabla^2 \lambda\, \mathbf d` over the offsets
    :math:`\mathbf d` of the neighbours). A vector field (the components of
    :math:`\lambda_t`) is measured by the Euclidean norms of its values and residuals.

    Args:
        fields: The components of one multiplier on the faces of a 3D model's pair.
        active: The active set (``None``: where the first component is positive).

    Returns:
        The nodes ``(n, 3)``, their indicators ``(n,)`` and the longest edge at each
        ``(n,)``; the same on every process.
    """
    X, first, on, _, faces = _gather(fields[0], active)
    # The other components on the same space: their values only, in global dof order.
    owned = fields[0].function_space.dofmap.index_map.size_local
    comm = fields[0].function_space.mesh.comm
    rest = [np.concatenate(comm.allgather(f.x.array[:owned].real)) for f in fields[1:]]
    values = np.stack([first, *rest], axis=1)
    edges = _unique_edges(faces, fields[0].function_space.mesh.topology.cell_name())
    edges = np.concatenate([edges, edges[:, ::-1]])  # directed: from node k to neighbour j
    k, j = edges[:, 0], edges[:, 1]
    size = X.shape[0]
    outside = np.zeros(size, dtype=int)
    np.add.at(outside, k, ~on[j])
    # The tangent plane: the main direction of the nodes' face normals (any orientation).
    corners = X[faces[:, :3]]
    n = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    scatter = np.zeros((size, 3, 3))
    for c in range(faces.shape[1]):
        np.add.at(scatter, faces[:, c], np.einsum("fi,fj->fij", n, n))
    normal = np.linalg.eigh(scatter)[1][:, :, -1]
    least = np.eye(3)[np.argmin(np.abs(normal), axis=1)]
    t1 = least - np.einsum("ni,ni->n", least, normal)[:, None] * normal
    t1 /= np.maximum(np.linalg.norm(t1, axis=1), 1e-300)[:, None]
    t2 = np.cross(normal, t1)
    d = X[j] - X[k]
    rows = np.stack(
        [np.ones(len(k)), np.einsum("ei,ei->e", d, t1[k]), np.einsum("ei,ei->e", d, t2[k])], 1
    )
    gram, rhs = np.zeros((size, 3, 3)), np.zeros((size, 3, values.shape[1]))
    np.add.at(gram, k, np.einsum("ei,ej->eij", rows, rows))
    np.add.at(rhs, k, np.einsum("ei,ec->eic", rows, values[j]))
    longest = np.zeros(size)
    np.maximum.at(longest, k, np.linalg.norm(d, axis=1))
    count = np.bincount(k, minlength=size)
    inside = on & (outside == 0) & (count >= 3)
    # A ring whose neighbours lie on a line has no plane (a singular Gram matrix).
    inside &= np.abs(np.linalg.det(gram)) > 1e-12 * np.maximum(longest, 1e-300) ** 4 * count**3
    fit = np.linalg.solve(gram[inside], rhs[inside])[:, 0, :]
    top = float(np.max(np.linalg.norm(values[on], axis=1), initial=0.0))
    eta = np.linalg.norm(values[inside] - fit, axis=1) / max(top, 1e-300)
    return X[inside], eta, longest[inside]

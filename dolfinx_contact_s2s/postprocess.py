# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""What a user reads after a solve: contact forces, contact zones and pressure profiles.

Everything here is collective and returns the same numbers on every process, whatever
the partition: the multiplier of a pair (:attr:`~dolfinx_contact_s2s.pair.ContactPair.Q`,
``problem.multipliers[j]``) is gathered, its nodes ordered along the contactor and
coincident nodes merged.

- :func:`contact_force`: the resultant of the contact pressure of Eq. (15),
  :math:`\mathbf F_C = \int_{\Gamma_C} \lambda \mathbf N \, d\Gamma` on the contactor
  (:math:`\mathbf N = -\mathbf n_C`, Eq. 38, so the force pushes the contactor away from
  the target) and :math:`-\int \lambda \mathbf N` on each target, integrated by the pair's
  own rule (the coupling of Eqs. 17 and 40): the nodal forces
  :math:`\mathbf B^T \Lambda` summed per component, so they balance the reactions of
  the supports to round-off. Only the contactor's unknowns are used: a target may be
  rigid.
- :func:`pressure_profile`: the nodes of the multiplier sorted by arclength along the
  contactor, with :math:`\lambda`, the active set and the weighted gaps, ready to plot.
- :func:`contact_zones`: the runs of active multipliers along the contactor; each end is
  a :class:`ContactEdge` with its bracket (last active node, first inactive node) and an
  estimate inside it.

The multiplier is a pressure for every discretization except node-to-segment with unit
weights (Eq. 39), where it is a nodal force. :func:`contact_force` takes curves and
faces (3D); profiles and zones need curves (2D models), the arclength running along the
chords of the facets.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from mpi4py import MPI

import basix
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import blocked_sub_element, geometry_dofmap
from dolfinx_contact_s2s.pair import ContactPair

__all__ = [
    "ESTIMATES",
    "ContactEdge",
    "ContactForce",
    "ContactZone",
    "PressureProfile",
    "contact_force",
    "contact_zones",
    "point_weight",
    "pressure_profile",
]

#: Estimates of a contact edge inside its bracket (see :class:`ContactEdge`).
ESTIMATES = ("gap", "pressure", "middle")

#: Relative distance (to the surface's size) below which two multiplier nodes coincide.
_COINCIDENT = 1e-10


def point_weight(pair: ContactPair, points: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    r"""Weight of the surface measure at ``points`` ``(n, gdim)``.

    1 in plane strain or stress; :math:`2 \pi r` for an axisymmetric pair
    (``pair.axisymmetric``), as in its coupling: the pressure integral is then the total
    force of the ring.
    """
    if pair.axisymmetric:
        return 2.0 * np.pi * points[:, 0]
    return np.ones(points.shape[0])


@dataclass(frozen=True)
class ContactForce:
    r"""The resultant of the contact pressure of one pair.

    Attributes:
        contactor: :math:`\int \lambda \mathbf N \, d\Gamma` over the contactor, the force
            the targets exert on the contactor's body, shape ``(gdim,)``.
        targets: Per target, the force the contactor exerts on it (minus the part of
            :attr:`contactor` that faces it).
        pressure_integral: :math:`\int_{\Gamma_C} \lambda \, d\Gamma` over the whole
            multiplier mesh, weighted by :func:`point_weight`: the normal resultant of
            a flat contact, an independent check of :attr:`contactor` on any.
    """

    contactor: npt.NDArray[np.floating]
    targets: tuple[npt.NDArray[np.floating], ...]
    pressure_integral: float

    @property
    def normal(self) -> float:
        r"""Magnitude :math:`|\mathbf F_C|` of the resultant."""
        return float(np.linalg.norm(self.contactor))


def _global_values(f: dolfinx.fem.Function) -> npt.NDArray[np.floating]:
    """The owned values of a scalar function, gathered in global dof order on every rank."""
    imap = f.function_space.dofmap.index_map
    n = imap.size_local
    start = imap.local_range[0]
    parts = f.function_space.mesh.comm.allgather((start, f.x.array[:n].real.copy()))
    out = np.zeros(imap.size_global)
    for s, v in parts:
        out[s : s + v.size] = v
    return out


def _facet_rule(mesh: dolfinx.mesh.Mesh, degree: int) -> tuple:
    """Gauss points and weights on the reference cell exact to ``degree``, and the cmap."""
    cell = getattr(basix.CellType, mesh.topology.cell_name())
    s, w = basix.make_quadrature(cell, degree)
    cmap = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element()).basix_element
    return s, w, cmap


def _pressure_integral(
    pair: ContactPair,
    lam: dolfinx.fem.Function,
    weight: Callable[[npt.NDArray[np.floating]], npt.NDArray[np.floating]],
) -> float:
    r""":math:`\int \lambda \, w \, d\Gamma` over the owned cells of the multiplier mesh.

    Curves (2D models) and faces (3D): the measure is :math:`|dx/ds|` or
    :math:`|\partial_1 x \times \partial_2 x|` of the cells' own geometry.
    """
    Q = lam.function_space
    mesh = Q.mesh
    tdim = mesh.topology.dim
    num = mesh.topology.index_map(tdim).size_local
    element = Q.ufl_element().basix_element
    s, w, cmap = _facet_rule(mesh, 2 * (element.degree + _cmap_degree(mesh)) + 2)
    psi = cmap.tabulate(1, s)[:, :, :, 0]  # (1 + tdim, points, nodes)
    phi = element.tabulate(0, s)[0, :, :, 0]
    nodes = mesh.geometry.x[geometry_dofmap(mesh)[:num]]  # (cells, nodes, 3)
    xq = np.einsum("qn,cnd->cqd", psi[0], nodes)
    tangents = [np.einsum("qn,cnd->cqd", psi[1 + k], nodes) for k in range(tdim)]
    jac = np.linalg.norm(tangents[0] if tdim == 1 else np.cross(*tangents), axis=2)
    values = lam.x.array[Q.dofmap.list[:num]].real
    lq = values @ phi.T
    wq = weight(xq.reshape(-1, 3)[:, : mesh.geometry.dim]).reshape(lq.shape)
    local = float(np.sum(lq * wq * jac * w[None, :]))
    return mesh.comm.allreduce(local, op=MPI.SUM)


def _cmap_degree(mesh: dolfinx.mesh.Mesh) -> int:
    """Degree of the mesh's coordinate element."""
    return blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element()).degree


def contact_force(
    pair: ContactPair,
    multiplier: dolfinx.fem.Function,
    *,
    weight: Callable[[npt.NDArray[np.floating]], npt.NDArray[np.floating]] | None = None,
) -> ContactForce:
    r"""The contact force of a pair from its multiplier (collective).

    The force on the contactor is :math:`\mathbf F_C = \sum_k \Lambda_k
    \int_{\Gamma_C} \mu_k \mathbf N \, d\Gamma` (Eqs. 15, 17), summed from the pair's own
    coupling (:meth:`~dolfinx_contact_s2s.pair.ContactPair.coupling_blocks`, the
    contactor part of :math:`\mathbf B^T \Lambda` per displacement component): exactly
    the contact force in the discrete equilibrium, so it equals the reactions of the
    supports of a body held by contact (to round-off). Each target takes minus the part
    facing it.

    Args:
        pair: The contact pair (after the solve that set ``multiplier``).
        multiplier: The pair's multiplier, e.g. ``problem.multipliers[j]``.
        weight: Weight of the surface measure of the pressure integral at points
            ``(n, gdim)``; defaults to :func:`point_weight`.

    Returns:
        The :class:`ContactForce`, the same on every process.

    Raises:
        ValueError: On every rank, if ``multiplier`` is not on ``pair.Q``.
    """
    if multiplier.function_space is not pair.Q and multiplier.function_space != pair.Q:
        raise ValueError("the multiplier must live on the pair's multiplier space pair.Q")
    lam = _global_values(multiplier)
    bs = pair.contactor.V.dofmap.index_map_bs
    forces = []
    for blocks in pair.coupling_blocks():
        f = np.zeros(bs)
        if blocks.rows.size:
            # sum_i (values[s, k, i] of component c) Lambda[rows[s, k]]
            weighted = np.einsum("skc,sk->sc", blocks.values_contactor, lam[blocks.rows])
            np.add.at(f, (blocks.cols_contactor % bs).reshape(-1), weighted.reshape(-1))
        forces.append(pair.contactor.comm.allreduce(f, op=MPI.SUM))
    point = weight if weight is not None else (lambda x: point_weight(pair, x))
    return ContactForce(
        contactor=np.sum(forces, axis=0),
        targets=tuple(-f for f in forces),
        pressure_integral=_pressure_integral(pair, multiplier, point),
    )


# --- the profile along the contactor ----------------------------------------------------


@dataclass(frozen=True)
class PressureProfile:
    r"""The multiplier nodes of a pair, sorted along the contactor (the same on every rank).

    Coincident nodes (a discontinuous multiplier) are merged: their :math:`\lambda` and
    gaps averaged, active if any is. Arrays of length ``n``, sorted by
    ``(chain, s)``.

    Attributes:
        chain: Which connected curve of the contactor (0, 1, ...; ordered by their
            first point), each traversed from its end of smallest ``(x, y)``.
        s: Arclength along the chain (along the facets' chords).
        x: Coordinates of the nodes, shape ``(n, gdim)``.
        pressure: :math:`\lambda` at the nodes.
        active: Active multipliers (all True for a tied problem).
        gap: Weighted gaps :math:`\tilde g_j` (Eq. 17; NaN if not given).
        closed: Per chain, whether it is a closed curve.
    """

    chain: npt.NDArray[np.int32]
    s: npt.NDArray[np.floating]
    x: npt.NDArray[np.floating]
    pressure: npt.NDArray[np.floating]
    active: npt.NDArray[np.bool_]
    gap: npt.NDArray[np.floating]
    closed: tuple[bool, ...]


def _gather_cells(Q: dolfinx.fem.FunctionSpace) -> tuple[npt.NDArray, npt.NDArray, npt.NDArray]:
    """Vertices ``(cells, 2, gdim)``, global dofs and dof coordinates of all cells."""
    mesh = Q.mesh
    gdim = mesh.geometry.dim
    num = mesh.topology.index_map(1).size_local
    ends = mesh.geometry.x[geometry_dofmap(mesh)[:num, :2]][:, :, :gdim]
    local = Q.dofmap.list[:num]
    dofs = Q.dofmap.index_map.local_to_global(local.reshape(-1)).reshape(local.shape)
    xyz = Q.tabulate_dof_coordinates()[:, :gdim][local]
    parts = mesh.comm.allgather((ends, dofs, xyz))
    return tuple(np.concatenate([p[i] for p in parts]) for i in range(3))  # type: ignore[return-value]


def _walk(ends: npt.NDArray) -> tuple[npt.NDArray, npt.NDArray, npt.NDArray, list[bool]]:
    """Chain, arclength at both vertices, for every cell; and whether each chain closes."""
    gdim = ends.shape[2]
    points = ends.reshape(-1, gdim)
    scale = max(float(np.ptp(points, axis=0).max()), 1e-300)
    key = np.round(points / (scale * _COINCIDENT)).astype(np.int64)
    unique, vertex = np.unique(key, axis=0, return_inverse=True)
    vertex = vertex.reshape(-1, 2)
    nv = unique.shape[0]
    touching: list[list[int]] = [[] for _ in range(nv)]
    for c, (v0, v1) in enumerate(vertex):
        touching[v0].append(c)
        touching[v1].append(c)
    if any(len(t) > 2 for t in touching):
        raise ValueError("the contactor branches: a profile needs curves (each node on two facets)")
    coords = np.zeros((nv, gdim))
    coords[vertex.reshape(-1)] = points
    # Starts: the free ends, then closed loops, each by smallest (x, y).
    order = np.lexsort(coords.T[::-1])
    free = [v for v in order if len(touching[v]) == 1]
    chain = np.full(len(vertex), -1, dtype=np.int32)
    s_ends = np.zeros((len(vertex), 2))
    closed: list[bool] = []
    for start in [*free, *order]:
        if not touching[start] or all(chain[c] >= 0 for c in touching[start]):
            continue
        k, v, s = len(closed), start, 0.0
        closed.append(len(touching[start]) == 2)
        while True:
            nxt = [c for c in touching[v] if chain[c] < 0]
            if not nxt:
                break
            c = nxt[0]
            side = 0 if vertex[c, 0] == v else 1
            other = vertex[c, 1 - side]
            length = float(np.linalg.norm(coords[other] - coords[v]))
            chain[c] = k
            s_ends[c, side], s_ends[c, 1 - side] = s, s + length
            v, s = other, s + length
    return chain, s_ends, coords, closed


def pressure_profile(
    pair: ContactPair,
    multiplier: dolfinx.fem.Function,
    active: dolfinx.fem.Function | None = None,
    gaps: dolfinx.fem.Function | None = None,
) -> PressureProfile:
    """The multiplier along the contactor, sorted, gathered and merged (collective).

    Args:
        pair: The contact pair.
        multiplier: Its multiplier (``problem.multipliers[j]``).
        active: The active set (``problem.active[j]``); default: every node active.
        gaps: The weighted gaps (``problem.gaps[j]``); default: NaN.

    Returns:
        The :class:`PressureProfile`, the same on every process.

    Raises:
        NotImplementedError: On every rank, for a contactor that is not a curve.
        ValueError: On every rank, for a branching contactor.
    """
    Q = pair.Q
    if Q.mesh.topology.dim != 1:
        raise NotImplementedError("pressure profiles need a contactor curve (a 2D model)")
    ends, dofs, xyz = _gather_cells(Q)
    lam = _global_values(multiplier)
    flags = _global_values(active) > 0.5 if active is not None else np.ones(lam.size, bool)
    gap = _global_values(gaps) if gaps is not None else np.full(lam.size, np.nan)
    chain, s_ends, _, closed = _walk(ends)
    # Every dof: its position along its cell's chord.
    chord = ends[:, 1] - ends[:, 0]
    t = (
        np.einsum("cnd,cd->cn", xyz - ends[:, None, 0], chord)
        / np.einsum("cd,cd->c", chord, chord)[:, None]
    )
    s = s_ends[:, :1] + np.clip(t, 0.0, 1.0) * (s_ends[:, 1:] - s_ends[:, :1])
    flat = dofs.reshape(-1)
    order = np.argsort(flat, kind="stable")
    g, first = np.unique(flat[order], return_index=True)
    first_of = order[first]
    ch = np.repeat(chain, dofs.shape[1])[first_of]
    # A node on two cells: its smaller arclength (the start of a closed chain is at 0).
    s_dof = np.minimum.reduceat(s.reshape(-1)[order], first)
    x_dof = xyz.reshape(-1, xyz.shape[2])[first_of]
    # Coincident dofs: the same chain and arclength.
    length = max(float(s_ends.max()), 1e-300) if s_ends.size else 1.0
    key = np.round(s_dof / (length * _COINCIDENT)).astype(np.int64)
    groups, index = np.unique(np.stack([ch, key], axis=1), axis=0, return_inverse=True)
    index = index.reshape(-1)
    count = np.bincount(index, minlength=len(groups))

    def mean(v: npt.NDArray) -> npt.NDArray:
        return np.bincount(index, weights=v, minlength=len(groups)) / count

    x = np.stack([mean(x_dof[:, d]) for d in range(x_dof.shape[1])], axis=1)
    profile = PressureProfile(
        chain=groups[:, 0].astype(np.int32),
        s=mean(s_dof),
        x=x,
        pressure=mean(lam[g]),
        active=np.bincount(index, weights=flags[g], minlength=len(groups)) > 0,
        gap=mean(gap[g]),
        closed=tuple(closed),
    )
    return profile


# --- contact zones ----------------------------------------------------------------------


@dataclass(frozen=True)
class ContactEdge:
    r"""One end of a contact zone, with its error bar.

    The discrete conditions (Eq. 1 on nodal weighted gaps) put the edge between the last
    active node and the first inactive one: that bracket is certain; the estimate inside
    it is not.

    Attributes:
        inside: Arclength of the last active node.
        outside: Arclength of the first inactive node (:attr:`inside` where the zone
            reaches the end of the contactor: no bracket).
        estimate: Arclength of the estimated edge, in ``[inside, outside]``.
        point: Coordinates of the estimated edge (on the chord between the two nodes).
        bracket_points: Coordinates of the last active and the first inactive node.
        method: How :attr:`estimate` was found: ``"gap"``, ``"pressure"`` or
            ``"middle"`` (:data:`ESTIMATES`; the middle also where the others cannot
            be applied, or ``"end"`` at the end of the contactor).
    """

    inside: float
    outside: float
    estimate: float
    point: npt.NDArray[np.floating]
    bracket_points: npt.NDArray[np.floating]
    method: str

    @property
    def bracket(self) -> float:
        """Width of the bracket (the error bar of the edge)."""
        return abs(self.outside - self.inside)

    @property
    def middle(self) -> float:
        """Middle of the bracket."""
        return 0.5 * (self.inside + self.outside)


@dataclass(frozen=True)
class ContactZone:
    """A run of active multipliers along one chain of the contactor.

    Attributes:
        chain: The chain of the :class:`PressureProfile`.
        start: The edge at the smaller arclength.
        end: The edge at the larger arclength.
    """

    chain: int
    start: ContactEdge
    end: ContactEdge

    @property
    def length(self) -> float:
        """Estimated length of the zone (arclength)."""
        return self.end.estimate - self.start.estimate

    @property
    def length_bounds(self) -> tuple[float, float]:
        """Shortest and longest length the brackets allow."""
        return (self.end.inside - self.start.inside, self.end.outside - self.start.outside)

    @property
    def bracket(self) -> float:
        """The larger bracket of the two edges."""
        return max(self.start.bracket, self.end.bracket)


def _cross(s0: float, v0: float, s1: float, v1: float) -> float | None:
    """Where the line through ``(s0, v0)`` and ``(s1, v1)`` crosses zero (None if flat)."""
    if v1 == v0:
        return None
    return s0 - v0 * (s1 - s0) / (v1 - v0)


def _hat_moment(t: npt.NDArray, j: int, e: float) -> float:
    r""":math:`\int \mu_j(t) (t - e)_+^{3/2} dt` for the hat :math:`\mu_j` on the nodes ``t``."""
    total = 0.0
    for lo, hi, rising in ((j - 1, j, True), (j, j + 1, False)):
        if lo < 0 or hi >= t.size or t[hi] <= e:
            continue
        h = t[hi] - t[lo]
        # The hat as c0 + c1 (t - e) on the piece; integrate (t - e)^{3/2} times it.
        c0, c1 = ((e - t[lo]) / h, 1.0 / h) if rising else ((t[hi] - e) / h, -1.0 / h)
        a, b = max(t[lo], e) - e, t[hi] - e
        total += c0 * 0.4 * (b**2.5 - a**2.5) + c1 * (2.0 / 7.0) * (b**3.5 - a**3.5)
    return total


def _gap_edge(t: npt.NDArray, ratio: float) -> float | None:
    r"""The edge :math:`e \in [t_0, t_1]` whose gap model matches ``ratio`` (bisection).

    ``t``: outward coordinates of the last active node (0), the first two inactive
    nodes and the next one. The gap :math:`C (t - e)_+^{3/2}` weighted by the hats of
    the nodes (Eq. 17 with P1 multipliers) gives :math:`\tilde g_2 / \tilde g_1`,
    which grows with :math:`e`.
    """

    def r(e: float) -> float:
        return _hat_moment(t, 2, e) / _hat_moment(t, 1, e)

    lo, hi = float(t[0]), float(t[1]) * (1.0 - 1e-9)
    if not r(lo) <= ratio:
        return lo
    if not ratio <= r(hi):
        return float(t[1])
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if r(mid) < ratio else (lo, mid)
    return 0.5 * (lo + hi)


def _edge(
    s: npt.NDArray,
    x: npt.NDArray,
    p: npt.NDArray,
    g: npt.NDArray,
    i: int,
    o: int | None,
    d: int,
    estimate: str,
) -> ContactEdge:
    """The edge between active node ``i`` and inactive node ``o``, outward in direction ``d``."""
    n = s.size
    if o is None:
        return ContactEdge(s[i], s[i], s[i], x[i].copy(), np.stack([x[i], x[i]]), "end")
    found, method = None, estimate
    if estimate == "pressure":
        j = i - d
        if 0 <= j < n and p[j] > p[i] >= 0.0:
            # p ~ sqrt(distance): p^2 linear in s through the last two active nodes.
            found = _cross(s[i], p[i] ** 2, s[j], p[j] ** 2)
    elif estimate == "gap":
        j = o + d
        if 0 <= j < n and g[j] > g[o] > 0.0:
            # Outward coordinates of the nodes i, o, j and the one after j (if any).
            k = [m for m in (i, o, j, j + d) if 0 <= m < n]
            found = _gap_edge(d * (s[k] - s[i]), g[j] / g[o])
            found = None if found is None else s[i] + d * found
    lo, hi = sorted((s[i], s[o]))
    if found is None or not math.isfinite(found):
        found, method = 0.5 * (s[i] + s[o]), "middle"
    found = float(np.clip(found, lo, hi))
    theta = 0.0 if s[o] == s[i] else (found - s[i]) / (s[o] - s[i])
    point = x[i] + theta * (x[o] - x[i])
    return ContactEdge(float(s[i]), float(s[o]), found, point, np.stack([x[i], x[o]]), method)


def contact_zones(
    pair: ContactPair,
    multiplier: dolfinx.fem.Function,
    active: dolfinx.fem.Function,
    gaps: dolfinx.fem.Function | None = None,
    *,
    estimate: str = "gap",
    profile: PressureProfile | None = None,
) -> list[ContactZone]:
    r"""The contact zones of a pair after a unilateral solve (collective).

    A zone is a run of active multiplier nodes along a chain of the contactor. Each end
    is bracketed by its last active and first inactive node; inside the bracket
    (``estimate``):

    - ``"gap"`` (the default): beyond a smooth (Hertz-like) edge :math:`e` the gap opens
      like :math:`C (s - e)^{3/2}`; weighted by the multiplier hats as in Eq. (17), it
      gives the weighted gaps of the first two inactive nodes, whose ratio fixes
      :math:`e` (bisection; needs ``gaps``; the hats are P1 on the node sequence);
    - ``"pressure"``: inside it the pressure falls like :math:`\sqrt d`, so
      :math:`\lambda^2` at the last two active nodes is extrapolated linearly to zero;
    - ``"middle"``: the middle of the bracket.

    The estimate is clipped to the bracket; where it cannot be made (too few nodes, a
    profile of the wrong shape) the middle is taken and the edge says so
    (:attr:`ContactEdge.method`). Measured on Hertz (``tests/test_postprocess.py``),
    ``"gap"`` is closer to the exact edge than the middle, ``"pressure"`` is not.

    Args:
        pair: The contact pair.
        multiplier: Its multiplier, ``problem.multipliers[j]``.
        active: Its active set, ``problem.active[j]``.
        gaps: Its weighted gaps, ``problem.gaps[j]`` (needed by ``"gap"``).
        estimate: One of :data:`ESTIMATES`.
        profile: The :func:`pressure_profile` of these functions, if already made.

    Returns:
        The zones, by chain and arclength; the same on every process.

    Raises:
        ValueError: On every rank, for an unknown estimate or ``"gap"`` without gaps.
    """
    if estimate not in ESTIMATES:
        raise ValueError(f"estimate must be one of {ESTIMATES}, not {estimate!r}")
    if estimate == "gap" and gaps is None:
        raise ValueError("the 'gap' estimate needs the weighted gaps (problem.gaps[j])")
    if profile is None:
        profile = pressure_profile(pair, multiplier, active, gaps)
    zones = []
    for k, closed in enumerate(profile.closed):
        sel = profile.chain == k
        s, x, p = profile.s[sel], profile.x[sel], profile.pressure[sel]
        g, on = profile.gap[sel], profile.active[sel]
        if on.all() or not on.any():
            continue  # all in contact (or a closed ring) or none: no edge on this chain
        if closed:
            # Start the loop at an inactive node; arclength grows through the closure.
            shift = int(np.flatnonzero(~on)[0])
            total = float(s.max() + np.linalg.norm(x[-1] - x[0]))
            s = np.concatenate([s[shift:], s[:shift] + total])
            x, p, g, on = (np.roll(v, -shift, axis=0) for v in (x, p, g, on))
        n = s.size
        i = 0
        while i < n:
            if not on[i]:
                i += 1
                continue
            i0 = i
            while i + 1 < n and on[i + 1]:
                i += 1
            before = i0 - 1 if i0 > 0 else None
            after = i + 1 if i + 1 < n else None
            zones.append(
                ContactZone(
                    k,
                    _edge(s, x, p, g, i0, before, -1, estimate),
                    _edge(s, x, p, g, i, after, +1, estimate),
                )
            )
            i += 1
    return zones

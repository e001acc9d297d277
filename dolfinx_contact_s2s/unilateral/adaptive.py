# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Accuracy on demand at the contact edge: refine the mesh around it until it is resolved.

The discrete contact conditions (Eq. 1 on the nodal weighted gaps of Eq. 17) end the
contact zone between two multiplier nodes: the last active one and the first inactive
one (:class:`~dolfinx_contact_s2s.postprocess.ContactEdge`). Its bracket is the
contactor's facet size there, whatever the rest of the mesh. :func:`refine_contact_zone`
solves, splits the edges of the cells within a few facet sizes of every edge whose
bracket is too wide (:func:`dolfinx.mesh.refine`, tags carried over by
:func:`dolfinx.mesh.transfer_meshtag`), moves the new boundary nodes onto the true
geometry (:func:`~dolfinx_contact_s2s.meshing.snap_boundary`, with the user's
projection), rebuilds the user's problem on the new mesh through their own ``build``
callable, and solves again from the previous contact zones (a new multiplier node starts
active if it lies between the previous estimates of a zone's edges), until every bracket
is below the tolerance.

In 3D the edge is a closed curve on the contactor's faces: its bracket is that of the
mean radius of the zero crossings of :math:`\lambda` around an axis the user gives
(:func:`~dolfinx_contact_s2s.contact_front.contact_front`); the cells near every
crossing are refined, and a new multiplier node starts active if it lies within the
previous estimate of the radius. Inside the zones
(``pressure_tolerance``, :mod:`.indicators`) the mesh is refined where the multiplier
is far from the line (2D) or the plane (3D) through its neighbours' values.

With friction (a :class:`~dolfinx_contact_s2s.friction.FrictionalContactProblem`,
solved along the user's load path) the edges of the stick zones are refined the same
way: there the shear changes from the stick solution to :math:`\mu \lambda_n` with an
infinite slope (Cattaneo-Mindlin), and the stick zone ends between two nodes as the
contact zone does.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import logging
import math
import time
import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import blocked_sub_element, refine_marked
from dolfinx_contact_s2s.contact_front import ContactFront, contact_front
from dolfinx_contact_s2s.meshing import Projection, curved_mesh, snap_boundary
from dolfinx_contact_s2s.postprocess import (
    ContactZone,
    PressureProfile,
    contact_zones,
    pressure_profile,
)
from dolfinx_contact_s2s.problem import ContactProblemBase
from dolfinx_contact_s2s.unilateral.indicators import (
    curvature_balls,
    marked_edges,
    peak_ball,
    pressure_balls,
)
from dolfinx_contact_s2s.unilateral.problem import UnilateralContactProblem

__all__ = [
    "AdaptiveResult",
    "AdaptiveStep",
    "RefinementError",
    "inside_zones",
    "refine_contact_zone",
]

logger = logging.getLogger("dolfinx_contact_s2s.unilateral")


@dataclass(frozen=True)
class AdaptiveStep:
    r"""One solve of :func:`refine_contact_zone`.

    Attributes:
        unknowns: Displacement and multiplier unknowns of the solve (global).
        bracket: Widest bracket of all edges (length).
        relative: Widest bracket relative to its reference length (the zone's length,
            or the ``length`` given).
        zones: The contact zones of every pair (2D models; empty in 3D).
        seconds: Wall time of the step (build, solve and post-processing; rank 0's).
        solves: Linear solves of the active-set iteration of the step (of the last
            ``problem.solve`` call of a load path given as ``solve``).
        restarted: Whether the step started from the previous step's contact zones.
        fronts: The contact front of every pair (3D models; empty in 2D), with its gap
            estimate where the multiplier is of degree 1 (:attr:`ContactFront.estimate`).
        peak_change: Largest relative change of a pair's peak :math:`\lambda` since
            the previous step (``nan`` at the first step or without ``peak_tolerance``).
        stick_zones: With friction, the stick zones of every pair (2D): the runs of
            sticking multiplier nodes, their ends bracketed by the last sticking and the
            first slipping (or inactive) node.
        stick_fronts: With friction, the stick front of every pair (3D).
    """

    unknowns: int
    bracket: float
    relative: float
    zones: list[list[ContactZone]]
    seconds: float
    solves: int = 0
    restarted: bool = False
    fronts: list[ContactFront] = field(default_factory=list)
    peak_change: float = math.nan
    stick_zones: list[list[ContactZone]] = field(default_factory=list)
    stick_fronts: list[ContactFront] = field(default_factory=list)

    @property
    def lengths(self) -> list[list[float]]:
        """Estimated length of every zone of every pair."""
        return [[z.length for z in zones] for zones in self.zones]


@dataclass
class AdaptiveResult:
    """What :func:`refine_contact_zone` returns.

    Attributes:
        problem: The last problem, solved (the caller destroys it).
        meshes: Its mesh(es), cell tags and facet tags, as given to ``build``.
        history: One :class:`AdaptiveStep` per solve.
    """

    problem: ContactProblemBase
    meshes: tuple
    history: list[AdaptiveStep] = field(default_factory=list)


class RefinementError(RuntimeError):
    """The tolerance was not reached in the allowed steps (raised on every rank).

    Attributes:
        history: The steps made.
        problem: The last problem, solved (the caller destroys it).
    """

    def __init__(self, message: str, history: list[AdaptiveStep], problem: typing.Any):
        """Keep the history and the last problem."""
        super().__init__(message)
        self.history = history
        self.problem = problem


def _unknowns(problem: ContactProblemBase) -> int:
    count = sum(V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces)
    fields = [*problem.multipliers, *getattr(problem, "tangential", [])]
    return count + sum(lam.function_space.dofmap.index_map.size_global for lam in fields)


def _zones(
    problem: ContactProblemBase, estimate: str
) -> tuple[list[PressureProfile], list[list[ContactZone]]]:
    profiles = [
        pressure_profile(pair, lam, act, gap)
        for pair, lam, act, gap in zip(
            problem.pairs, problem.multipliers, problem.active, problem.gaps, strict=True
        )
    ]
    zones = [
        contact_zones(pair, lam, act, gap, estimate=estimate, profile=profile)
        for pair, lam, act, gap, profile in zip(
            problem.pairs, problem.multipliers, problem.active, problem.gaps, profiles, strict=True
        )
    ]
    return profiles, zones


def inside_zones(
    profile: PressureProfile, zones: Sequence[ContactZone]
) -> Callable[[npt.NDArray[np.floating]], npt.NDArray[np.bool_]]:
    """A marker ``f(x) -> bool`` of the points inside the ``zones`` of a previous solve.

    A point ``x`` ``(3, n)`` is projected onto the nearest chord of the previous
    contactor (the ``profile``'s nodes, chain by chain) and marked if its arclength lies
    between the estimated edges of a zone of that chain: the first active set of
    :meth:`UnilateralContactProblem.solve` (``active=``) on a refined mesh.
    """
    gdim = profile.x.shape[1]
    starts, ends, s0, chains = [], [], [], []
    for k in range(len(profile.closed)):
        sel = np.flatnonzero(profile.chain == k)
        starts.append(profile.x[sel[:-1]])
        ends.append(profile.x[sel[1:]])
        s0.append(profile.s[sel[:-1]])
        chains.append(np.full(sel.size - 1, k))
    A, B, S, C = (np.concatenate(v) for v in (starts, ends, s0, chains))
    totals = [
        float(profile.s[profile.chain == k].max()) if closed else 0.0
        for k, closed in enumerate(profile.closed)
    ]

    def marker(x: npt.NDArray[np.floating]) -> npt.NDArray[np.bool_]:
        points = np.asarray(x)[:gdim].T
        out = np.zeros(points.shape[0], dtype=bool)
        if A.shape[0] == 0 or points.shape[0] == 0:
            return out
        d = B - A
        length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        t = np.clip(np.einsum("pij,ij->pi", points[:, None, :] - A[None], d) / length2, 0, 1)
        foot = A[None] + t[..., None] * d[None]
        nearest = np.argmin(np.linalg.norm(points[:, None, :] - foot, axis=2), axis=1)
        rows = np.arange(points.shape[0])
        s = S[nearest] + t[rows, nearest] * np.sqrt(length2[nearest])
        chain = C[nearest]
        for z in zones:
            on = chain == z.chain
            for shift in (0.0, totals[z.chain]) if totals[z.chain] else (0.0,):
                out |= on & (s + shift >= z.start.estimate) & (s + shift <= z.end.estimate)
        return out

    return marker


def _fronts(
    problem: ContactProblemBase, axis: tuple[npt.ArrayLike, npt.ArrayLike], stick: bool = False
) -> list[ContactFront]:
    sets = problem.stick if stick else problem.active  # type: ignore[attr-defined]
    fields = sets if stick else problem.multipliers
    gaps = getattr(problem, "gaps", None)
    fronts = []
    for j, (lam, act) in enumerate(zip(fields, sets, strict=True)):
        # The contact front's gap estimate where its weighted gaps are those of hats.
        fit = not stick and gaps is not None and _degree(lam) == 1
        fronts.append(
            contact_front(
                lam,
                act,
                centre=axis[0],
                axis=axis[1],
                gaps=gaps[j] if fit else None,
                dual=fit and problem.pairs[j].dual,
            )
        )
    return fronts


def _degree(f: dolfinx.fem.Function) -> int:
    return f.function_space.ufl_element().basix_element.degree


def _inside_front(
    front: ContactFront, axis: tuple[npt.ArrayLike, npt.ArrayLike]
) -> Callable[[npt.NDArray[np.floating]], npt.NDArray[np.bool_]]:
    """Marker of the points within the front's estimated radius of the axis (3D restart)."""
    c = np.asarray(axis[0], dtype=np.float64).reshape(3)
    n = np.asarray(axis[1], dtype=np.float64).reshape(3)
    n = n / np.linalg.norm(n)

    def marker(x: npt.NDArray[np.floating]) -> npt.NDArray[np.bool_]:
        d = np.asarray(x).T - c
        return np.linalg.norm(d - np.outer(d @ n, n), axis=1) <= front.radius

    return marker


def refine_contact_zone(
    build: Callable[..., ContactProblemBase],
    mesh: dolfinx.mesh.Mesh | Sequence[dolfinx.mesh.Mesh],
    cell_tags: dolfinx.mesh.MeshTags | Sequence[dolfinx.mesh.MeshTags],
    facet_tags: dolfinx.mesh.MeshTags | Sequence[dolfinx.mesh.MeshTags],
    *,
    tolerance: float = 0.01,
    max_steps: int = 5,
    length: float | None = None,
    layers: float = 2.0,
    estimate: str = "gap",
    load_factors: Sequence[float] = (1.0,),
    snap: Projection | Sequence[Projection | None] | None = None,
    restart: bool = True,
    pressure_tolerance: float | None = None,
    peak_tolerance: float | None = None,
    geometry_degree: int = 1,
    axis: tuple[npt.ArrayLike, npt.ArrayLike] | None = None,
    solve: Callable[[typing.Any, list | None], object] | None = None,
    on_step: Callable[[int, typing.Any], None] | None = None,
) -> AdaptiveResult:
    r"""Solve, refine around the contact edges and solve again, until they are resolved.

    Every step calls ``build(mesh, cell_tags, facet_tags)`` (with the arguments in the
    shape given here: one mesh or a list) for a new
    :class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem` or
    :class:`~dolfinx_contact_s2s.friction.FrictionalContactProblem`, solves it at
    ``load_factors`` (or along the user's load path, ``solve``) and reads its contact zones
    (:func:`~dolfinx_contact_s2s.postprocess.contact_zones`). An edge is resolved when
    its bracket (the distance from the last active to the first inactive multiplier
    node) is at most ``tolerance`` times the zone's length (or ``length``). Around every
    other edge, the cells of every mesh whose midpoint lies within ``layers`` brackets
    of its two nodes have all their edges split, and the tags are carried to the new
    mesh. Nodes added on a curved boundary lie on the chords of the old facets: ``snap``
    moves them onto the true geometry (:func:`~dolfinx_contact_s2s.meshing.snap_boundary`;
    :func:`~dolfinx_contact_s2s.meshing.gmsh_projection` for a live Gmsh model) before
    ``build`` sees the mesh; without it the refinement converges to the polygon's
    answer. Every solve after the first starts from the previous contact zones
    (:func:`inside_zones`), unless ``restart`` is False.

    With friction, the ends of every stick zone (2D: ``contact_zones`` of the stick set,
    their estimate the bracket's middle; 3D: the front of the stick set) are edges too,
    resolved when their bracket is at most ``tolerance`` times the stick zone's length
    (its radius in 3D, or ``length``).

    In 3D (tetrahedra), the edge of every pair is its
    :func:`~dolfinx_contact_s2s.contact_front.contact_front` around ``axis``: it is
    resolved when its bracket (the mean radii of the active and inactive ends of the
    edges that cross it) is at most ``tolerance`` times its radius (or ``length``);
    else the cells within ``layers`` edge lengths of every crossing are refined, and
    the next solve starts with the multiplier nodes inside the estimated radius active.

    Args:
        build: Makes the problem of a mesh: forms, Dirichlet conditions, contact
            surfaces and pairs, e.g. from the tags of the user's Gmsh model.
        mesh: The mesh, or a list of meshes (triangles or tetrahedra, linear geometry).
        cell_tags: Their cell tags (as many).
        facet_tags: Their facet tags (as many).
        tolerance: Largest relative bracket of a resolved edge.
        max_steps: Largest number of refinements (``max_steps + 1`` solves).
        length: Reference length of the brackets (default: each zone's length).
        layers: Radius of the refined region, in brackets.
        estimate: The edge estimate of the zones, one of
            :data:`~dolfinx_contact_s2s.postprocess.ESTIMATES`.
        load_factors: Given to every ``solve``.
        snap: The :data:`~dolfinx_contact_s2s.meshing.Projection` of the facet tags of
            the mesh (or one per mesh, ``None`` for a mesh to leave alone), applied to
            every refined mesh.
        restart: Start every solve after the first from the previous step's contact
            zones (else from the problem's ``start``).
        pressure_tolerance: Also refine inside the zones, around every active node
            whose :math:`\lambda` lies farther than this (relative to the zone's largest
            :math:`\lambda`) from the line through its two neighbours' (3D: the plane
            fitted to its neighbours', also of :math:`\lambda_t` with friction), until
            none does (``None``: the edges only).
        peak_tolerance: Also refine around the node of every pair's largest
            :math:`\lambda` (the peak pressure; ``layers`` of its longest edge), until
            the peak changes by at most this (relative) over a step: the change is then
            the a posteriori estimate of the peak's discretization error. The edge
            criterion alone leaves the mesh at the peak as it was (``None``: no peak).
        geometry_degree: Degree of the geometry of the meshes given to ``build``: 2
            lifts every (refined, snapped) mesh to a quadratic geometry with its midside
            nodes on ``snap``'s geometry (:func:`~dolfinx_contact_s2s.meshing.curved_mesh`).
            Use 2 with quadratic displacements on a curved contact surface: on the
            chords of a linear geometry their multiplier sees the kinks between the
            facets (two elastic P2 spheres, a/h = 24.6: the peak pressure 7% off on the
            chords, 0.08% on the curved mesh).
        axis: 3D models: a point and a direction of the axis the contact fronts are
            measured from (e.g. the first touching point and the normal there).
        solve: The load path, called as ``solve(problem, first)`` on every process
            with the first active set of a restart (``None`` at the first step or
            without ``restart``; the markers of ``active=``), e.g. a normal load and then
            a tangential one (default: ``problem.solve(load_factors, active=first)``).
        on_step: Called as ``on_step(step, problem)`` on every process after every
            solve, before the problem is destroyed (to read or save each step).

    Returns:
        The last problem (solved; the caller destroys it), its meshes and tags, and the
        history of the steps.

    Raises:
        NotImplementedError: On every rank, for a mesh that is not made of simplices
            with a linear coordinate element (DOLFINx refines those only).
        ValueError: On every rank, for a bad argument or a problem without contact (in
            3D: without ``axis``).
        RefinementError: On every rank, if an edge is still too wide after
            ``max_steps`` refinements; it names the widest bracket reached.
    """
    single = isinstance(mesh, dolfinx.mesh.Mesh)
    meshes = [mesh] if single else list(mesh)
    ctags = [cell_tags] if single else list(cell_tags)  # type: ignore[list-item]
    ftags = [facet_tags] if single else list(facet_tags)  # type: ignore[list-item]
    if not (len(meshes) == len(ctags) == len(ftags)) or not meshes:
        raise ValueError("give as many cell tags and facet tags as meshes")
    if not (0.0 < tolerance < 1.0):
        raise ValueError(f"tolerance must lie in (0, 1), not {tolerance!r}")
    if int(max_steps) != max_steps or max_steps < 0:
        raise ValueError(f"max_steps must be an integer >= 0, not {max_steps!r}")
    if length is not None and not (length > 0.0 and np.isfinite(length)):
        raise ValueError(f"length must be positive and finite, not {length!r}")
    if not layers > 0.0:
        raise ValueError(f"layers must be positive, not {layers!r}")
    if pressure_tolerance is not None and not (0.0 < pressure_tolerance < 1.0):
        raise ValueError(f"pressure_tolerance must lie in (0, 1), not {pressure_tolerance!r}")
    if peak_tolerance is not None and not (0.0 < peak_tolerance < 1.0):
        raise ValueError(f"peak_tolerance must lie in (0, 1), not {peak_tolerance!r}")
    if geometry_degree not in (1, 2):
        raise ValueError(f"geometry_degree must be 1 or 2, not {geometry_degree!r}")
    if not all(f is None or callable(f) for f in (solve, on_step)):
        raise ValueError("solve and on_step must be callables (or None)")
    snaps = list(snap) if isinstance(snap, Sequence) else [snap] * len(meshes)
    if len(snaps) != len(meshes) or not all(p is None or callable(p) for p in snaps):
        raise ValueError("snap must be a projection, or one projection (or None) per mesh")
    for m in meshes:
        simplex = m.topology.cell_name() in ("interval", "triangle", "tetrahedron")
        degree = blocked_sub_element(m.ufl_domain().ufl_coordinate_element()).degree
        if not simplex or degree != 1:
            raise NotImplementedError(
                f"refine_contact_zone needs simplices with a linear geometry: DOLFINx "
                f"refines no {m.topology.cell_name()} mesh of geometry degree "
                f"{degree}; mesh the scene with triangles and linear geometry"
            )

    three = meshes[0].topology.dim == 3
    if three and axis is None:
        raise ValueError("a 3D model needs the axis (point, direction) of its contact fronts")
    if three:
        assert axis is not None
        c, n = (np.asarray(v, dtype=np.float64).reshape(-1) for v in axis)
        if c.size != 3 or n.size != 3 or not np.all(np.isfinite(np.r_[c, n])) or not n.any():
            raise ValueError(f"axis must be a point and a nonzero direction in 3D, not {axis!r}")

    history: list[AdaptiveStep] = []
    problem: UnilateralContactProblem | None = None
    first: list | None = None
    peaks: list[float] = []
    for step in range(int(max_steps) + 1):
        begin = time.perf_counter()
        if problem is not None:
            problem.destroy()
        given = list(zip(meshes, ctags, ftags, strict=True))
        if geometry_degree == 2:
            given = [curved_mesh(m, c, f, p) for (m, c, f), p in zip(given, snaps, strict=True)]
        args = given[0] if single else tuple(list(part) for part in zip(*given, strict=True))
        problem = build(*args)
        frictional = hasattr(problem, "stick")
        if not (isinstance(problem, UnilateralContactProblem) or frictional):
            raise ValueError(
                "build must return a UnilateralContactProblem or a FrictionalContactProblem"
            )
        if solve is not None:
            solve(problem, first)
        else:
            problem.solve(load_factors, active=first)
        wide: list[npt.NDArray[np.floating]] = []
        widest, relative = 0.0, 0.0
        if three:
            assert axis is not None
            profiles, zones, fronts = [], [], _fronts(problem, axis)
            if not any(f.points.shape[0] for f in fronts):
                raise ValueError("the solve has no contact front to refine")
        else:
            (profiles, zones), fronts = _zones(problem, estimate), []
            if not any(zones):
                raise ValueError("the solve has no contact zone with an edge to refine")
        stick_zones, stick_fronts = [], []
        if frictional and three:
            assert axis is not None
            stick_fronts = _fronts(problem, axis, stick=True)
        elif frictional:
            stick_zones = [
                contact_zones(pair, s, s, estimate="middle")
                for pair, s in zip(problem.pairs, problem.stick, strict=True)
            ]
        for front in (f for f in fronts + stick_fronts if f.points.shape[0]):
            reference = length if length is not None else max(front.radius, 1e-300)
            widest = max(widest, front.bracket)
            relative = max(relative, front.bracket / reference)
            if front.bracket > tolerance * reference:
                wide += [
                    np.append(p, layers * h)
                    for p, h in zip(front.points, front.edge_lengths, strict=True)
                ]
        for z in (z for pair_zones in zones + stick_zones for z in pair_zones):
            reference = length if length is not None else max(z.length, 1e-300)
            for edge in (z.start, z.end):
                widest = max(widest, edge.bracket)
                relative = max(relative, edge.bracket / reference)
                if edge.bracket > tolerance * reference:
                    radius = layers * edge.bracket
                    wide += [np.append(p, radius) for p in edge.bracket_points]
        indicator = 0.0
        if pressure_tolerance is not None and three:
            assert axis is not None
            indicator, balls = curvature_balls(
                problem, axis, fronts + stick_fronts, pressure_tolerance, layers
            )
            wide += balls
        if pressure_tolerance is not None:
            for profile, pair_zones in zip(profiles, zones, strict=True):
                eta, balls = pressure_balls(profile, pair_zones, pressure_tolerance, layers)
                indicator, wide = max(indicator, eta), wide + balls
        change = math.nan
        if peak_tolerance is not None:
            now = [f.peak for f in fronts] if three else [peak_ball(p)[0] for p in profiles]
            if peaks:
                change = max(
                    abs(b - a) / max(abs(b), 1e-300) for a, b in zip(peaks, now, strict=True)
                )
            if not change <= peak_tolerance:  # nan at the first step: refine
                wide += (
                    [np.append(f.peak_point, layers * f.peak_length) for f in fronts]
                    if three
                    else [peak_ball(p, layers)[1] for p in profiles]
                )
            peaks = now
        seconds = problem.comm.bcast(time.perf_counter() - begin, root=0)
        if on_step is not None:
            on_step(step, problem)
        solves = problem.history.iterations
        history.append(
            AdaptiveStep(
                _unknowns(problem),
                widest,
                relative,
                zones,
                seconds,
                solves,
                first is not None,
                fronts,
                change,
                stick_zones,
                stick_fronts,
            )
        )
        logger.info(
            "contact edge, step %d: %d unknowns, widest bracket %.3g (%.3g of the reference), "
            "pressure indicator %.3g, peak change %.3g, %d solves, %.2f s",
            step,
            history[-1].unknowns,
            widest,
            relative,
            indicator,
            change,
            solves,
            seconds,
        )
        if not wide:
            return AdaptiveResult(problem, args, history)
        if step == max_steps:
            break
        balls = np.array(wide)
        for k, m in enumerate(meshes):
            edges = marked_edges(m, balls)
            meshes[k], (ctags[k], ftags[k]) = refine_marked(m, edges, (ctags[k], ftags[k]))
            if snaps[k] is not None:
                snap_boundary(meshes[k], ftags[k], snaps[k])
        if not restart:
            continue
        if three:
            assert axis is not None
            first = [_inside_front(f, axis) for f in fronts]
        else:
            first = [inside_zones(p, z) for p, z in zip(profiles, zones, strict=True)]
    raise RefinementError(
        f"the contact edges were not resolved to {tolerance:g} in {max_steps} refinements"
        + ("" if pressure_tolerance is None else f" (pressure to {pressure_tolerance:g})")
        + ("" if peak_tolerance is None else f" (peak to {peak_tolerance:g})")
        + ": "
        f"the widest bracket is {history[-1].bracket:.3g}, {history[-1].relative:.3g} of its "
        f"reference length (steps: "
        + ", ".join(f"{s.relative:.3g}" for s in history)
        + "); allow more steps or a larger tolerance",
        history,
        problem,
    )

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Where :func:`~dolfinx_contact_s2s.unilateral.refine_contact_zone` refines inside a zone.

Balls ``(centre..., radius)`` around the nodes where the multiplier is poorly resolved
(2D: the second difference of the pressure along a zone; 3D: the distance from the plane
fitted to a node's neighbours), around the peak pressure, and the mesh edges of the cells
whose midpoints they hold.
"""

from __future__ import annotations

import typing
from collections.abc import Sequence

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.contact_front import ContactFront, curvature_indicator
from dolfinx_contact_s2s.postprocess import ContactZone, PressureProfile

__all__ = ["curvature_balls", "marked_edges", "peak_ball", "pressure_balls"]


def pressure_balls(
    profile: PressureProfile, zones: Sequence[ContactZone], tolerance: float, layers: float
) -> tuple[float, list[npt.NDArray[np.floating]]]:
    r"""The largest pressure indicator of the zones and the balls around the nodes above it.

    The indicator of an active node whose neighbours are active is the distance of its
    :math:`\lambda` from the line through its neighbours' (a second difference along the
    arclength), relative to the zone's largest :math:`\lambda`: it measures the
    interpolation error of the pressure and its oscillations (e.g. at the end of a
    contactor). Nodes within a tenth of the zone's length of a bracketed edge are left to
    the edge's own criterion: there the pressure falls like a square root, whose second
    difference shrinks only like the square root of the spacing.
    """
    worst, balls = 0.0, []
    for z in zones:
        sel = np.flatnonzero(
            (profile.chain == z.chain)
            & (profile.s >= z.start.inside - 1e-14)
            & (profile.s <= z.end.inside + 1e-14)
        )
        if sel.size < 3:
            continue
        s, p, x = profile.s[sel], profile.pressure[sel], profile.x[sel]
        top = max(float(np.max(np.abs(p))), 1e-300)
        left, right = s[1:-1] - s[:-2], s[2:] - s[1:-1]
        line = (p[:-2] * right + p[2:] * left) / np.maximum(left + right, 1e-300)
        eta = np.abs(p[1:-1] - line) / top
        layer = 0.1 * (z.end.inside - z.start.inside)
        if z.start.method != "end":
            eta[s[1:-1] < z.start.inside + layer] = 0.0
        if z.end.method != "end":
            eta[s[1:-1] > z.end.inside - layer] = 0.0
        worst = max(worst, float(np.max(eta)))
        for k in np.flatnonzero(eta > tolerance):
            radius = layers * max(left[k], right[k])
            balls += [np.append(x[k + m], radius) for m in (0, 1, 2)]
    return worst, balls


def curvature_balls(
    problem: typing.Any,
    axis: tuple[npt.ArrayLike, npt.ArrayLike],
    fronts: Sequence[ContactFront],
    tolerance: float,
    layers: float,
) -> tuple[float, list[npt.NDArray[np.floating]]]:
    r"""3D: the largest curvature indicator of every pair's multipliers and the balls above it.

    :func:`~dolfinx_contact_s2s.contact_front.curvature_indicator` of :math:`\lambda_n`
    and (friction) of the components of :math:`\lambda_t` on the active set; nodes within
    a tenth of a front's diameter of its radius are left to the front's own criterion, as
    in 2D.
    """
    c, n = (np.asarray(v, dtype=np.float64).reshape(3) for v in axis)
    n = n / np.linalg.norm(n)
    tangential = problem.tangential if hasattr(problem, "stick") else []
    nd = len(tangential) // len(problem.pairs)
    worst, balls = 0.0, []
    for j, active in enumerate(problem.active):
        for fields in ([problem.multipliers[j]], tangential[j * nd : (j + 1) * nd]):
            if not fields:
                continue
            points, eta, longest = curvature_indicator(fields, active)
            d = points - c
            r = np.linalg.norm(d - np.outer(d @ n, n), axis=1)
            for f in fronts:
                if f.points.shape[0]:
                    eta = np.where(np.abs(r - f.radius) < 0.2 * f.radius, 0.0, eta)
            worst = max(worst, float(np.max(eta, initial=0.0)))
            above = eta > tolerance
            balls += [
                np.append(p, layers * h) for p, h in zip(points[above], longest[above], strict=True)
            ]
    return worst, balls


def peak_ball(profile: PressureProfile, layers: float = 1.0) -> tuple[float, npt.NDArray]:
    """A 2D pair's largest lambda and the ball of ``layers`` node spacings around its node."""
    if not profile.pressure.size:
        return 0.0, np.full(profile.x.shape[1] + 1, np.nan)
    k = int(np.argmax(profile.pressure))
    same = np.flatnonzero(profile.chain == profile.chain[k])
    s = profile.s[same]
    j = int(np.searchsorted(s, profile.s[k]))
    gaps = np.diff(s)[max(j - 1, 0) : j + 1]
    spacing = float(gaps.max()) if gaps.size else 0.0
    return float(profile.pressure[k]), np.append(profile.x[k], layers * spacing)


def marked_edges(mesh: dolfinx.mesh.Mesh, balls: npt.NDArray[np.floating]) -> npt.NDArray[np.int32]:
    """Local edges of the cells whose midpoint lies in a ball ``(centre..., radius)``."""
    tdim, gdim = mesh.topology.dim, mesh.geometry.dim
    num = mesh.topology.index_map(tdim).size_local
    cells = np.arange(num, dtype=np.int32)
    mid = dolfinx.mesh.compute_midpoints(mesh, tdim, cells)[:, :gdim]
    near = np.zeros(num, dtype=bool)
    for ball in balls:
        near |= np.linalg.norm(mid - ball[:gdim], axis=1) <= ball[gdim]
    mesh.topology.create_entities(1)
    mesh.topology.create_connectivity(tdim, 1)
    return dolfinx.mesh.compute_incident_entities(mesh.topology, cells[near], tdim, 1)

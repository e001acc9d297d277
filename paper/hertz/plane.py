# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Hertz on a rigid plane with P1 and the adaptive contact edge.

The elastic half cylinder of :func:`paper.rigid.hertz_on_plane` (radius :math:`R`,
plane strain, symmetry :math:`u_x = 0` on :math:`x = 0`, traction on its flat top) on a
rigid floor :math:`y = 0`: the analytic :func:`~dolfinx_contact_s2s.plane_obstacle` or a
meshed :func:`~dolfinx_contact_s2s.rigid_surface`. Meshed by Gmsh as a user meshes it:
a uniform size :math:`h` within :math:`R/4` of the first contact point, no node placed
at :math:`x = a`. From about 10 P1 elements across :math:`2a`,
:func:`~dolfinx_contact_s2s.unilateral.refine_contact_zone` refines around the edge,
with the nodes it adds on the arc moved onto the circle (``snap``).

Hertz (plane strain): :math:`1/E^* = (1 - \nu^2)/E`, :math:`a = \sqrt{4 F R/(\pi E^*)}`,
:math:`p_0 = 2F/(\pi a)`, :math:`p(x) = p_0 \sqrt{1 - x^2/a^2}` (:math:`F` per unit
length on the whole cylinder).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import (
    Material,
    contact_pair,
    contact_surface,
    contact_zones,
    plane_obstacle,
    pressure_profile,
    rigid_surface,
)
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem, refine_contact_zone
from paper.hertz.exact import pressure_l2_error
from paper.rigid import CONTACT, LOADED, SYMMETRY, TARGET, quarter_disk

__all__ = ["PlaneCase", "adaptive_run", "build", "circle", "errors", "uniform_run"]


@dataclass(frozen=True)
class PlaneCase:
    """The scene: radius, design half-width, material, target and P1 elements across."""

    R: float = 1.0
    a_over_R: float = 0.025
    E: float = 1.0
    nu: float = 0.3
    target: str = "plane"
    elements_across: int = 10
    #: Displacement degree (the geometry stays linear: DOLFINx refines only that).
    degree: int = 1

    @property
    def E_star(self) -> float:
        """Plane-strain modulus of the cylinder on a rigid floor."""
        return self.E / (1.0 - self.nu**2)

    @property
    def a(self) -> float:
        """Hertz's half-width at :attr:`F`."""
        return self.a_over_R * self.R

    @property
    def F(self) -> float:
        """Force per unit length on the whole cylinder that gives :attr:`a`."""
        return math.pi * self.E_star * self.a**2 / (4.0 * self.R)

    @property
    def p0(self) -> float:
        """Hertz's peak pressure."""
        return 2.0 * self.F / (math.pi * self.a)


def circle(case: PlaneCase) -> Callable:
    """The projection of the contact arc onto the circle (``refine_contact_zone``'s ``snap``)."""
    centre = np.array([0.0, case.R, 0.0])

    def project(tag: int, points: np.ndarray) -> np.ndarray | None:
        if tag != CONTACT:
            return None
        r = points - centre
        return centre + case.R * r / np.linalg.norm(r, axis=1)[:, None]

    return project


def build(case: PlaneCase, prefix: str = "hertz_plane_") -> Callable:
    """The user's ``build(mesh, cell_tags, facet_tags)`` of the scene."""

    def make(mesh, cell_tags, facet_tags) -> UnilateralContactProblem:
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", case.degree, (2,)))
        a_form, _, v = Material(case.E, case.nu).forms(V)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        traction = dolfinx.fem.Constant(mesh, np.array([0.0, -case.F / (2 * case.R)]))
        L = ufl.inner(traction, v) * ds(LOADED)
        mesh.topology.create_connectivity(1, 2)
        axis = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, facet_tags.find(SYMMETRY))
        bcs = [dolfinx.fem.dirichletbc(0.0, axis, V.sub(0))]
        if case.target == "plane":
            floor = plane_obstacle([0.0, 0.0], [0.0, 1.0])
        else:
            width = 0.4 * case.R
            fmesh = dolfinx.mesh.create_rectangle(
                mesh.comm, [[-0.05 * width, -width], [width, 0.0]], [24, 6]
            )
            top = dolfinx.mesh.locate_entities_boundary(fmesh, 1, lambda x: np.isclose(x[1], 0))
            ftags = dolfinx.mesh.meshtags(
                fmesh, 1, np.sort(top).astype(np.int32), np.full(top.size, TARGET, np.int32)
            )
            floor = rigid_surface(fmesh, ftags, TARGET)
        pair = contact_pair(contact_surface(V, facet_tags, CONTACT), floor)
        return UnilateralContactProblem(a_form, L, [pair], bcs, petsc_options_prefix=prefix)

    return make


def errors(case: PlaneCase, problem: UnilateralContactProblem) -> dict:
    r"""Half-width (``contact_zones``), peak pressure and L2 pressure error against Hertz.

    The L2 error :math:`\|\lambda_h - p\| / \|p\|` is over the abscissae of the
    contactor's nodes up to beyond both edges, :math:`\lambda_h` piecewise linear.
    """
    pair, lam, act, gap = (
        problem.pairs[0],
        problem.multipliers[0],
        problem.active[0],
        problem.gaps[0],
    )
    profile = pressure_profile(pair, lam, act, gap)
    (zone,) = contact_zones(pair, lam, act, gap, profile=profile)
    a_h = float(zone.end.point[0])
    x, p = profile.x[:, 0], profile.pressure
    order = np.argsort(x)
    x, p = x[order], p[order]
    l2 = pressure_l2_error(x, p, case.a, case.p0, a_h)
    return {
        "a": a_h,
        "a_error": a_h / case.a - 1.0,
        "bracket_over_a": zone.end.bracket / case.a,
        "p0_error": float(p[0]) / case.p0 - 1.0,
        "l2_error": l2,
    }


def _scene(case: PlaneCase, comm: MPI.Comm, elements_across: int) -> tuple:
    return quarter_disk(comm, case.R, 2 * case.a / elements_across, 1)


def adaptive_run(
    case: PlaneCase = PlaneCase(),
    *,
    tolerance: float = 0.01,
    max_steps: int = 6,
    comm: MPI.Comm = MPI.COMM_WORLD,
    **options,
) -> dict:
    """Refine the edge until its bracket is ``tolerance`` of ``a``: steps and errors."""
    begin = time.perf_counter()
    mesh, cell_tags, facet_tags = _scene(case, comm, case.elements_across)
    result = refine_contact_zone(
        build(case),
        mesh,
        cell_tags,
        facet_tags,
        tolerance=tolerance,
        max_steps=max_steps,
        length=case.a,
        snap=circle(case),
        **({"geometry_degree": case.degree} | options),
    )
    with result.problem:
        final = errors(case, result.problem)
    steps = [
        {
            "unknowns": s.unknowns,
            "bracket_over_a": s.bracket / case.a,
            "a_error": s.zones[0][0].end.point[0] / case.a - 1.0,
            "seconds": s.seconds,
            "solves": s.solves,
        }
        for s in result.history
    ]
    return {
        "kind": "adaptive",
        "scene": "rigid_plane",
        "a_exact": case.a,
        "a_over_R": case.a_over_R,
        "steps": steps,
        **final,
        "unknowns": steps[-1]["unknowns"],
        "solves": sum(s["solves"] for s in steps),
        "seconds": time.perf_counter() - begin,
        "ranks": comm.size,
    }


def uniform_run(
    case: PlaneCase = PlaneCase(),
    n: int = 10,
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> dict:
    """One mesh of ``n`` P1 elements across (the same sizing): unknowns, errors, time."""
    begin = time.perf_counter()
    mesh, cell_tags, facet_tags = _scene(case, comm, n)
    with build(case, prefix=f"hertz_plane_uniform_{n}_")(mesh, cell_tags, facet_tags) as problem:
        problem.solve()
        final = errors(case, problem)
        unknowns = sum(V.dofmap.index_map.size_global * 2 for V in problem.spaces) + sum(
            q.function_space.dofmap.index_map.size_global for q in problem.multipliers
        )
    return {
        "kind": "uniform",
        "scene": "rigid_plane",
        "elements_across": n,
        "a_over_R": case.a_over_R,
        "unknowns": unknowns,
        **final,
        "seconds": time.perf_counter() - begin,
        "ranks": comm.size,
    }

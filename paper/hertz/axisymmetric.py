# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Axisymmetric Hertz: a sphere on a rigid plane, and two elastic spheres.

Half-sections in the :math:`(r, z)` plane, meshed with Gmsh as a user would: element
size :math:`h` within :math:`R/4` of the contact point, growing to :math:`R/8`; no node
placed at the contact edge, no grading built from the answer; triangles, or
quadrilaterals (Gmsh's recombination).

Each body is a hemisphere: a quarter disk about its centre on the axis, the pole at the
contact point, the flat face (its equatorial disk) far from the contact. The upper
body is pressed down by a uniform pressure on its flat face (total force :math:`F`);
the lower one (second sphere) has :math:`u_z = 0` on its flat face; both
:math:`u_r = 0` on the axis. Hertz's solution is that of two half-spaces: the
hemispheres' finite size is a model error of order :math:`a/R`, measured by
:func:`~paper.hertz.axisymmetric.model_error` (the README states it).

Exact (Hertz, 1882): :math:`1/R = 1/R_1 + 1/R_2`,
:math:`1/E^* = (1 - \nu_1^2)/E_1 + (1 - \nu_2^2)/E_2` (a rigid body contributes 0),
:math:`a = (3 F R / (4 E^*))^{1/3}`, :math:`p_0 = 3F / (2\pi a^2)`,
:math:`p(r) = p_0 \sqrt{1 - r^2/a^2}`.
"""

from __future__ import annotations

import math
import time
import typing
from dataclasses import dataclass, field

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import (
    Material,
    contact_force,
    contact_pair,
    contact_surface,
    contact_zones,
    gmsh_session,
    model_to_mesh,
    plane_obstacle,
    pressure_profile,
    rigid_surface,
)
from dolfinx_contact_s2s.meshing import Projection
from dolfinx_contact_s2s.postprocess import ESTIMATES
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem, refine_contact_zone
from paper.hertz.exact import pressure_l2_error
from paper.scenes import size_field

__all__ = [
    "ACROSS",
    "SCENES",
    "AxiResult",
    "adaptive",
    "build_sphere_on_plane",
    "build_two_spheres",
    "hemisphere",
    "hertz_exact",
    "hertz_measures",
    "model_error",
    "read",
    "run",
    "sphere",
    "sphere_on_plane",
    "two_spheres",
]

#: Facet tags of the scenes.
CONTACT, LOADED, AXIS, TARGET = 1, 2, 3, 4


@dataclass
class AxiResult:
    r"""A solved scene, read with the library's post-processing.

    Attributes:
        r: Radii of the multiplier's nodes (sorted, coincident nodes merged, all ranks),
            from :func:`~dolfinx_contact_s2s.pressure_profile`.
        pressure: The multiplier at those nodes.
        force: The axial contact force on the contactor,
            :math:`|F_z|` of :func:`~dolfinx_contact_s2s.contact_force` (with :math:`2\pi r`).
        unknowns: Global unknowns of the saddle point (displacements and multipliers).
        solves: Linear solves of the active-set loop (of every step, if adaptive).
        seconds: Wall time of the solve (assembly and refinement included), rank 0.
        edges: Per estimate of :data:`~dolfinx_contact_s2s.postprocess.ESTIMATES`, the
            outer contact edge (the one away from the axis) of
            :func:`~dolfinx_contact_s2s.contact_zones`: ``(r, r_inside, r_outside, method)``.
        extra: Anything else the scene reports.
    """

    r: np.ndarray
    pressure: np.ndarray
    force: float
    unknowns: int
    solves: int
    seconds: float
    edges: dict[str, tuple[float, float, float, str]]
    extra: dict[str, typing.Any] = field(default_factory=dict)


def hertz_exact(F: float, R: float, E_star: float) -> tuple[float, float]:
    """Hertz's contact radius and peak pressure :math:`(a, p_0)`."""
    a = (3 * F * R / (4 * E_star)) ** (1 / 3)
    return a, 3 * F / (2 * math.pi * a**2)


def hertz_measures(
    result: AxiResult, a: float, p0: float, estimate: str = "gap"
) -> dict[str, typing.Any]:
    r"""Relative errors of the contact radius, the peak and the L2 pressure.

    The radius is the library's edge estimate ``estimate``
    (:func:`~dolfinx_contact_s2s.contact_zones`), with its bracket (the radii of the last
    active and the first inactive node); the peak the multiplier at the axis node; the
    L2 error :math:`\|\lambda_h - p\| / \|p\|` over :math:`r \le 1.5 \max(a, a_h)`
    with the weight :math:`2\pi r`, :math:`\lambda_h` piecewise linear between the
    nodes of :func:`~dolfinx_contact_s2s.pressure_profile`.
    """
    r, p = result.r, result.pressure
    a_h, inside, outside, method = result.edges[estimate]
    l2 = pressure_l2_error(r, p, a, p0, a_h, radial=True)
    return {
        "a": a_h,
        "estimate": method,
        "bracket": (inside, outside),
        "bracket_over_a": (outside - inside) / a,
        "p0": float(p[0]),
        "a_error": abs(a_h / a - 1),
        "p0_error": abs(p[0] / p0 - 1),
        "L2_error": l2,
    }


def hemisphere(
    comm: MPI.Comm,
    R: float,
    pole: float,
    down: bool,
    h: float,
    geometry_degree: int,
    cell: str,
    reach: float | None = None,
) -> tuple:
    """Half-section of a hemisphere with its pole at ``(0, pole)`` (Gmsh).

    ``down``: the pole is the lowest point (the body lies above it). Tags: the arc from
    the pole to 0.4 rad :data:`CONTACT`, the flat face :data:`LOADED`, the axis
    :data:`AXIS`. Size ``h`` within ``reach`` (default ``R/4``) of the pole; the
    geometry of degree ``geometry_degree`` (1 for :func:`refine_contact_zone`).
    Returns ``(mesh, cell_tags, facet_tags)``.
    """
    s = 1.0 if down else -1.0
    zc = pole + s * R
    with gmsh_session() as gmsh:
        gmsh.model.add("hemisphere")
        if comm.rank == 0:
            geo = gmsh.model.geo
            centre, tip = geo.addPoint(0, zc, 0), geo.addPoint(0, pole, 0)
            equator = geo.addPoint(R, zc, 0)
            cut = geo.addPoint(R * math.sin(0.4), zc - s * R * math.cos(0.4), 0)
            arc1, arc2 = geo.addCircleArc(tip, centre, cut), geo.addCircleArc(cut, centre, equator)
            flat, axis = geo.addLine(equator, centre), geo.addLine(centre, tip)
            surface = geo.addPlaneSurface([geo.addCurveLoop([arc1, arc2, flat, axis])])
            geo.synchronize()
            gmsh.model.addPhysicalGroup(2, [surface], 1)
            for tag, curves in ((CONTACT, [arc1]), (LOADED, [flat]), (AXIS, [axis])):
                gmsh.model.addPhysicalGroup(1, curves, tag)
            size_field(gmsh, tip, h, R / 8, 0.25 * R if reach is None else reach)
            if cell == "quadrilateral":
                gmsh.option.setNumber("Mesh.RecombineAll", 1)
                gmsh.option.setNumber("Mesh.Algorithm", 8)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(geometry_degree)
            gmsh.option.setNumber("Mesh.RecombineAll", 0)
        return model_to_mesh(gmsh.model, comm, 0)


def sphere(R: float, pole: float, down: bool) -> Projection:
    """The projection of the contact arc of :func:`hemisphere` onto its circle (``snap``)."""
    centre = np.array([0.0, pole + (1.0 if down else -1.0) * R, 0.0])

    def project(tag: int, points: np.ndarray) -> np.ndarray | None:
        if tag != CONTACT:
            return None
        d = points - centre
        return centre + R * d / np.linalg.norm(d, axis=1)[:, None]

    return project


def _body(mesh, tags, degree, material):
    """Space, stiffness, test function and axis condition of one hemisphere's mesh."""
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a, _, v = material.forms(V)
    mesh.topology.create_connectivity(1, 2)
    axis = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, tags.find(AXIS))
    return V, a, v, [dolfinx.fem.dirichletbc(0.0, axis, V.sub(0))]


def _floor(comm: MPI.Comm, width: float, n: int) -> tuple:
    """The rigid block [0, width] x [-width/4, 0], its top tagged TARGET."""
    mesh = dolfinx.mesh.create_rectangle(
        comm, [[0.0, -width / 4], [width, 0.0]], [n, max(2, n // 4)]
    )
    top = dolfinx.mesh.locate_entities_boundary(mesh, 1, lambda x: np.isclose(x[1], 0.0))
    return mesh, dolfinx.mesh.meshtags(
        mesh, 1, np.sort(top).astype(np.int32), np.full(top.size, TARGET, np.int32)
    )


def build_sphere_on_plane(
    *,
    F: float,
    R: float = 1.0,
    degree: int = 2,
    material: Material = Material(1.0, 0.3, plane="axisymmetric"),  # noqa: B008
    target: str = "plane",
    start: str = "nearest",
    prefix: str = "axihertz_plane_",
) -> typing.Callable[..., UnilateralContactProblem]:
    r"""``build(mesh, cell_tags, facet_tags)`` of a hemisphere pressed by :math:`F` on a plane.

    For :func:`~dolfinx_contact_s2s.unilateral.refine_contact_zone` (mesh of
    :func:`hemisphere` with ``down=True``, pole at the origin) or a single solve.
    ``target``: ``"plane"`` (analytic) or ``"rigid"`` (a meshed rigid block).
    """

    def make(mesh, cell_tags, facet_tags) -> UnilateralContactProblem:
        V, a, v, bcs = _body(mesh, facet_tags, degree, material)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        q = dolfinx.fem.Constant(mesh, -F / (math.pi * R**2))
        L = q * v[1] * material.weight(mesh) * ds(LOADED)
        if target == "plane":
            floor = plane_obstacle([0.0, 0.0], [0.0, 1.0])
        else:
            floor = rigid_surface(*_floor(mesh.comm, 0.4 * R, 24), TARGET)
        pair = contact_pair(contact_surface(V, facet_tags, CONTACT), floor, axisymmetric=True)
        return UnilateralContactProblem(
            [a], [L], [pair], bcs, petsc_options_prefix=prefix, start=start
        )

    return make


def build_two_spheres(
    *,
    F: float,
    R2: float = 2.0,
    degree: int = 2,
    materials: tuple[Material, Material] = (
        Material(1.0, 0.3, plane="axisymmetric"),
        Material(2.0, 0.25, plane="axisymmetric"),
    ),
    start: str = "nearest",
    prefix: str = "axihertz_spheres_",
    multiplier: int | None = None,
) -> typing.Callable[..., UnilateralContactProblem]:
    r"""``build(meshes, cell_tags, facet_tags)`` of sphere 2 pressed by :math:`F` on sphere 1.

    The meshes (lists of two) of :func:`hemisphere`: sphere 1 below (``down=False``, the
    contactor, its flat face held, :math:`u_z = 0`), sphere 2 above (``down=True``,
    radius ``R2``, its flat face loaded), both poles at the origin. ``multiplier``: its
    degree (default: the displacement's).
    """

    def make(meshes, cell_tags, facet_tags) -> UnilateralContactProblem:
        (m1, m2), (t1, t2) = meshes, facet_tags
        V1, a1, v1, bcs1 = _body(m1, t1, degree, materials[0])
        V2, a2, v2, bcs2 = _body(m2, t2, degree, materials[1])
        held = dolfinx.fem.locate_dofs_topological(V1.sub(1), 1, t1.find(LOADED))
        bcs = [*bcs1, *bcs2, dolfinx.fem.dirichletbc(0.0, held, V1.sub(1))]
        L1 = dolfinx.fem.Constant(m1, 0.0) * v1[1] * ufl.dx
        ds2 = ufl.Measure("ds", domain=m2, subdomain_data=t2)
        q = dolfinx.fem.Constant(m2, -F / (math.pi * R2**2))
        L2 = q * v2[1] * materials[1].weight(m2) * ds2(LOADED)
        pair = contact_pair(
            contact_surface(V1, t1, CONTACT),
            contact_surface(V2, t2, CONTACT),
            axisymmetric=True,
            multiplier=None if multiplier is None else ("Lagrange", multiplier),
        )
        return UnilateralContactProblem(
            [a1, a2], [L1, L2], [pair], bcs, petsc_options_prefix=prefix, start=start
        )

    return make


def _unknowns(problem: UnilateralContactProblem) -> int:
    count = sum(V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces)
    return count + sum(q.function_space.dofmap.index_map.size_global for q in problem.multipliers)


def read(problem: UnilateralContactProblem) -> tuple[np.ndarray, np.ndarray, float, dict]:
    r"""Radii, pressure, axial force and outer edges of a solved problem (collective).

    The library's :func:`~dolfinx_contact_s2s.pressure_profile`,
    :func:`~dolfinx_contact_s2s.contact_force` (weighted by :math:`2\pi r`) and
    :func:`~dolfinx_contact_s2s.contact_zones` (every estimate), of its first pair.
    """
    pair, lam, act, gap = (
        problem.pairs[0],
        problem.multipliers[0],
        problem.active[0],
        problem.gaps[0],
    )
    profile = pressure_profile(pair, lam, act, gap)
    order = np.argsort(profile.x[:, 0], kind="stable")
    edges = {}
    for estimate in ESTIMATES:
        zones = contact_zones(pair, lam, act, gap, estimate=estimate, profile=profile)
        edge = max((e for z in zones for e in (z.start, z.end)), key=lambda e: e.point[0])
        inside, outside = sorted(float(x[0]) for x in edge.bracket_points)
        edges[estimate] = (float(edge.point[0]), inside, outside, edge.method)
    force = abs(float(contact_force(pair, lam).contactor[1]))
    return profile.x[order, 0], profile.pressure[order], force, edges


def _solve(build, mesh, cell_tags, facet_tags, hook=None) -> AxiResult:
    comm = (mesh if isinstance(mesh, dolfinx.mesh.Mesh) else mesh[0]).comm
    comm.Barrier()
    begin = time.perf_counter()
    with build(mesh, cell_tags, facet_tags) as problem:
        problem.solve([1.0])
        seconds = comm.bcast(time.perf_counter() - begin, root=0)
        iterations = [i for s in problem.history.steps for i in s.iterations]
        inspected = None if hook is None else hook(problem)
        r, p, force, edges = read(problem)
        unknowns = _unknowns(problem)
    residuals = [i.residual for i in iterations]
    return AxiResult(
        r,
        p,
        force,
        unknowns,
        len(iterations),
        seconds,
        edges,
        {"residuals": residuals, "hook": inspected},
    )


def sphere_on_plane(
    comm: MPI.Comm,
    *,
    F: float,
    R: float = 1.0,
    h: float = 0.01,
    degree: int = 2,
    cell: str = "triangle",
    material: Material = Material(1.0, 0.3, plane="axisymmetric"),  # noqa: B008
    target: str = "plane",
    start: str = "nearest",
    hook: typing.Callable | None = None,
    reach: float = 0.25,
) -> AxiResult:
    r"""An elastic hemisphere pressed by a total force :math:`F` onto a rigid plane.

    One solve on a curved mesh (geometry of degree ``degree``).

    Args:
        comm: Communicator.
        F: Total force (a uniform pressure :math:`F/(\pi R^2)` on the flat face).
        R: Radius.
        h: Element size within ``reach`` :math:`R` of the contact point.
        degree: Displacement and geometry degree.
        cell: ``"triangle"`` or ``"quadrilateral"``.
        material: The sphere's (axisymmetric) material.
        target: ``"plane"`` (analytic) or ``"rigid"`` (a meshed rigid block).
        start: First active set of the unilateral solve.
        hook: Called as ``hook(problem)`` after the solve; its value is ``extra["hook"]``.
        reach: Radius of the fine zone, relative to :math:`R`.
    """
    mesh, ct, ft = hemisphere(comm, R, 0.0, True, h, degree, cell, reach * R)
    build = build_sphere_on_plane(
        F=F,
        R=R,
        degree=degree,
        material=material,
        target=target,
        start=start,
        prefix=f"axihertz_{target}_",
    )
    return _solve(build, mesh, ct, ft, hook)


def two_spheres(
    comm: MPI.Comm,
    *,
    F: float,
    R1: float = 1.0,
    R2: float = 2.0,
    materials: tuple[Material, Material] = (
        Material(1.0, 0.3, plane="axisymmetric"),
        Material(2.0, 0.25, plane="axisymmetric"),
    ),
    h: float = 0.01,
    degree: int = 2,
    cell: str = "triangle",
    start: str = "nearest",
    hook: typing.Callable | None = None,
    reach: float = 0.25,
    multiplier: int | None = None,
) -> AxiResult:
    r"""Sphere 2 pressed by :math:`F` onto sphere 1 (its flat face held, :math:`u_z = 0`).

    Both are meshed with size ``h`` within ``reach`` :math:`\min(R_1, R_2)` of the contact point.
    Sphere 1 (below, radius ``R1``) is the contactor: the multiplier lives on it. The
    arguments as :func:`sphere_on_plane`; ``materials`` are sphere 1's and sphere 2's.
    """
    meshes, cts, fts = _sphere_meshes(comm, R1, R2, h, degree, cell, reach)
    build = build_two_spheres(
        F=F, R2=R2, degree=degree, materials=materials, start=start, multiplier=multiplier
    )
    return _solve(build, meshes, cts, fts, hook)


def _sphere_meshes(comm, R1, R2, h, geometry_degree, cell, reach=0.25):
    # The fine zone of both: a quarter of the smaller radius (the geometry, not a).
    reach = reach * min(R1, R2)
    one = hemisphere(comm, R1, 0.0, False, h, geometry_degree, cell, reach)
    two = hemisphere(comm, R2, 0.0, True, h, geometry_degree, cell, reach)
    return [one[0], two[0]], [one[1], two[1]], [one[2], two[2]]


#: The scenes' materials and radii: a rigid plane under sphere 1; sphere 2 on sphere 1.
SCENES = {
    "sphere-on-plane": {"R": 1.0, "E_star": 1 / (1 - 0.3**2)},
    "two-spheres": {"R": 1 / (1 / 1.0 + 1 / 2.0), "E_star": 1 / ((1 - 0.3**2) + (1 - 0.25**2) / 2)},
}

#: Elements of size h across the contact radius a of the users' meshes: a/h = 9.3,
#: deliberately not an integer (no node falls at r = a by construction).
ACROSS = 9.3


def adaptive(
    comm: MPI.Comm,
    scene: str,
    *,
    F: float,
    h: float,
    degree: int = 1,
    target: str = "plane",
    tolerance: float = 0.01,
    max_steps: int = 8,
    pressure_tolerance: float | None = None,
    estimate: str = "gap",
    reach: float = 0.1,
) -> AxiResult:
    r"""A scene with the adaptive contact edge, from a triangle mesh of size ``h``.

    The hemispheres are meshed with linear geometry (DOLFINx refines only those), each
    refined mesh lifted to a geometry of degree ``degree`` for the solve (midside nodes on
    the spheres), the displacements of degree ``degree``;
    :func:`~dolfinx_contact_s2s.unilateral.refine_contact_zone` refines around the
    contact edge until its bracket is ``tolerance`` of the zone's radius (and, with
    ``pressure_tolerance``, inside the zone), moving the nodes it adds on the contact arcs
    onto the spheres (``snap``, :func:`sphere`), each solve restarted from the last
    contact zone. ``extra["steps"]``: unknowns, bracket and solves per step.
    """
    comm.Barrier()
    begin = time.perf_counter()
    if scene == "sphere-on-plane":
        mesh, ct, ft = hemisphere(comm, 1.0, 0.0, True, h, 1, "triangle", reach)
        build = build_sphere_on_plane(
            F=F, degree=degree, target=target, prefix=f"axihertz_adaptive_{target}_"
        )
        snap: typing.Any = sphere(1.0, 0.0, True)
    else:
        mesh, ct, ft = _sphere_meshes(comm, 1.0, 2.0, h, 1, "triangle", reach)
        build = build_two_spheres(F=F, degree=degree, prefix="axihertz_adaptive_spheres_")
        snap = [sphere(1.0, 0.0, False), sphere(2.0, 0.0, True)]
    result = refine_contact_zone(
        build,
        mesh,
        ct,
        ft,
        tolerance=tolerance,
        max_steps=max_steps,
        estimate=estimate,
        snap=snap,
        restart=True,
        pressure_tolerance=pressure_tolerance,
        geometry_degree=degree,
    )
    with result.problem as problem:
        r, p, force, edges = read(problem)
    seconds = comm.bcast(time.perf_counter() - begin, root=0)
    steps = [
        {"unknowns": s.unknowns, "relative_bracket": s.relative, "solves": s.solves}
        for s in result.history
    ]
    return AxiResult(
        r,
        p,
        force,
        result.history[-1].unknowns,
        sum(s.solves for s in result.history),
        seconds,
        edges,
        {"steps": steps},
    )


def run(
    comm: MPI.Comm,
    scene: str,
    *,
    a_over_R1: float = 0.05,
    h: float | None = None,
    degree: int = 2,
    cell: str = "triangle",
    target: str = "plane",
    refine: bool = False,
    tolerance: float = 0.01,
    pressure_tolerance: float | None = None,
    estimate: str = "gap",
    reach: float = 0.1,
    max_steps: int = 8,
    keep_pressure: bool = False,
    multiplier: int | None = None,
) -> dict[str, typing.Any]:
    r"""Solve a scene with the load that gives Hertz's :math:`a = ` ``a_over_R1`` :math:`R_1`.

    ``h`` defaults to :math:`a/9.3` (:data:`ACROSS`: about 9 elements across the contact
    radius, deliberately not a divisor of :math:`a`), within ``reach`` :math:`R_1` of
    the contact point (a user's guess of the contact's size, :math:`2a` by default),
    growing to :math:`R/8`. ``refine``: triangles with linear geometry and the adaptive
    edge (:func:`adaptive`: bracket ``tolerance``, ``pressure_tolerance``, at most
    ``max_steps`` refinements);
    else one solve on a curved mesh (geometry of degree ``degree``).
    Returns a record for ``results/``: the exact and measured :math:`a`, :math:`p_0`, the
    errors of :func:`hertz_measures`, the unknowns, solves and seconds; with
    ``keep_pressure``, also ``r`` and ``pressure`` (arrays, for plots). ``multiplier``:
    the multiplier's degree of the two spheres' single solve (default: the
    displacement's).
    """
    if multiplier is not None and (refine or scene != "two-spheres"):
        raise ValueError("multiplier= is for the single solve of the two spheres")
    R, E_star = SCENES[scene]["R"], SCENES[scene]["E_star"]
    a = a_over_R1 * 1.0
    h = a / ACROSS if h is None else h
    F = 4 * E_star * a**3 / (3 * R)
    if refine:
        result = adaptive(
            comm,
            scene,
            F=F,
            h=h,
            degree=degree,
            target=target,
            tolerance=tolerance,
            pressure_tolerance=pressure_tolerance,
            estimate=estimate,
            reach=reach,
            max_steps=max_steps,
        )
    elif scene == "sphere-on-plane":
        result = sphere_on_plane(
            comm, F=F, h=h, degree=degree, cell=cell, target=target, reach=reach
        )
    else:
        result = two_spheres(
            comm, F=F, h=h, degree=degree, cell=cell, reach=reach, multiplier=multiplier
        )
    a_exact, p0_exact = hertz_exact(F, R, E_star)
    arrays = {"r": result.r, "pressure": result.pressure} if keep_pressure else {}
    return arrays | {
        "study": "axisymmetric-hertz",
        "scene": scene,
        "target": target if scene == "sphere-on-plane" else "elastic",
        "cell": "triangle" if refine else cell,
        "degree": degree,
        "mesh": "adaptive" if refine else "uniform",
        "h": h,
        "a_over_h": a / h,
        "a_over_R1": a_over_R1,
        "ranks": comm.size,
        "F": F,
        "a_exact": a_exact,
        "p0_exact": p0_exact,
        **hertz_measures(result, a_exact, p0_exact, estimate),
        "force_over_F": result.force / F,
        "unknowns": result.unknowns,
        "solves": result.solves,
        "seconds": result.seconds,
        **({"steps": result.extra["steps"]} if refine else {}),
    }


def model_error(comm: MPI.Comm, scene: str, *, cell: str = "triangle") -> dict[str, typing.Any]:
    r"""The change of the errors of :math:`a` and :math:`p_0` when :math:`a/R_1` halves.

    P2 at the same :math:`a/h = 10` (``h`` halved with :math:`a`, load divided by 8): the
    discretization error stays about the same, the finite-body error of order
    :math:`a/R` halves; the change bounds what the hemispheres' finite size adds.
    """
    big = run(comm, scene, a_over_R1=0.05, h=0.005, cell=cell)
    small = run(comm, scene, a_over_R1=0.025, h=0.0025, cell=cell)
    signed = {
        k: (big[k] / big[f"{k}_exact"] - 1, small[k] / small[f"{k}_exact"] - 1) for k in ("a", "p0")
    }
    return {
        "study": "axisymmetric-hertz-model-error",
        "scene": scene,
        "cell": cell,
        "ranks": comm.size,
        "relative_errors_at_5_and_2.5_percent": signed,
        "change_a": abs(signed["a"][0] - signed["a"][1]),
        "change_p0": abs(signed["p0"][0] - signed["p0"][1]),
    }

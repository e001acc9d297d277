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
    contact_pair,
    contact_surface,
    gmsh_session,
    model_to_mesh,
    plane_obstacle,
    rigid_surface,
)
from paper.rigid import edge_from_multiplier

__all__ = [
    "SCENES",
    "AxiResult",
    "hertz_exact",
    "hertz_measures",
    "model_error",
    "run",
    "sphere_on_plane",
    "two_spheres",
]

#: Facet tags of the scenes.
CONTACT, LOADED, AXIS, TARGET = 1, 2, 3, 4


@dataclass
class AxiResult:
    r"""A solved scene: the contact pressure along the contactor and the model's size.

    Attributes:
        r: Radii of the multiplier's nodes (sorted, all ranks), ``(n,)``.
        pressure: The multiplier at those nodes.
        force: :math:`\int \lambda\, 2\pi r\, ds`, the total contact force.
        unknowns: Global unknowns of the saddle point (displacements and multipliers).
        solves: Linear solves of the active-set loop.
        seconds: Wall time of the solve (assembly included), rank 0.
        extra: Anything else the scene reports.
    """

    r: np.ndarray
    pressure: np.ndarray
    force: float
    unknowns: int
    solves: int
    seconds: float
    extra: dict[str, typing.Any] = field(default_factory=dict)


def hertz_exact(F: float, R: float, E_star: float) -> tuple[float, float]:
    """Hertz's contact radius and peak pressure :math:`(a, p_0)`."""
    a = (3 * F * R / (4 * E_star)) ** (1 / 3)
    return a, 3 * F / (2 * math.pi * a**2)


def hertz_measures(result: AxiResult, a: float, p0: float) -> dict[str, float]:
    r"""Relative errors of the contact radius, the peak and the L2 pressure.

    The radius from the last two active nodes (:func:`~paper.rigid.edge_from_multiplier`,
    a square-root edge), the peak at the node on the axis, the L2 error over the contact
    disk (weight :math:`2\pi r`, trapezoidal rule on the multiplier's nodes, out to
    :math:`2a`); and the bracket of the edge: the radii of the last active and the first
    inactive node.
    """
    r, p = result.r, result.pressure
    exact = p0 * np.sqrt(np.clip(1 - (r / a) ** 2, 0.0, None))
    inside = r <= 2 * a
    w = r[inside]
    l2 = math.sqrt(
        np.trapezoid((p[inside] - exact[inside]) ** 2 * w, w)
        / np.trapezoid(exact[inside] ** 2 * w, w)
    )
    a_h = edge_from_multiplier(r, p)
    last = np.flatnonzero(p > 1e-12 * np.max(p))[-1]
    return {
        "a": a_h,
        "bracket": (float(r[last]), float(r[min(last + 1, r.size - 1)])),
        "p0": float(p[0]),
        "a_error": abs(a_h / a - 1),
        "p0_error": abs(p[0] / p0 - 1),
        "L2_error": l2,
    }


def _size_field(gmsh: typing.Any, point: int, near: float, far: float, reach: float) -> None:
    """Element size ``near`` within ``reach`` of ``point``, growing to ``far``."""
    f = gmsh.model.mesh.field
    distance = f.add("Distance")
    f.setNumbers(distance, "PointsList", [point])
    threshold = f.add("Threshold")
    f.setNumber(threshold, "InField", distance)
    f.setNumber(threshold, "SizeMin", near)
    f.setNumber(threshold, "SizeMax", far)
    f.setNumber(threshold, "DistMin", reach)
    f.setNumber(threshold, "DistMax", reach + (far - near) / 0.3)
    f.setAsBackgroundMesh(threshold)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)


def hemisphere(
    comm: MPI.Comm,
    R: float,
    pole: float,
    down: bool,
    h: float,
    degree: int,
    cell: str,
    reach: float | None = None,
) -> tuple:
    """Half-section of a hemisphere with its pole at ``(0, pole)`` (Gmsh).

    ``down``: the pole is the lowest point (the body lies above it). Tags: the arc from
    the pole to 0.4 rad :data:`CONTACT`, the flat face :data:`LOADED`, the axis
    :data:`AXIS`. Size ``h`` within ``reach`` (default ``R/4``) of the pole.
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
            _size_field(gmsh, tip, h, R / 8, 0.25 * R if reach is None else reach)
            if cell == "quadrilateral":
                gmsh.option.setNumber("Mesh.RecombineAll", 1)
                gmsh.option.setNumber("Mesh.Algorithm", 8)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(degree)
            gmsh.option.setNumber("Mesh.RecombineAll", 0)
        return model_to_mesh(gmsh.model, comm, 0)


def _body(comm, R, pole, down, h, degree, cell, material, reach=None):
    """Space, stiffness, axis condition and tags of one hemisphere."""
    mesh, _, tags = hemisphere(comm, R, pole, down, h, degree, cell, reach)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a, _, v = material.forms(V)
    axis = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, tags.find(AXIS))
    bcs = [dolfinx.fem.dirichletbc(0.0, axis, V.sub(0))]
    return V, a, v, bcs, tags


def _floor(comm: MPI.Comm, width: float, n: int) -> tuple:
    """The rigid block [0, width] x [-width/4, 0], its top tagged TARGET."""
    mesh = dolfinx.mesh.create_rectangle(
        comm, [[0.0, -width / 4], [width, 0.0]], [n, max(2, n // 4)]
    )
    top = dolfinx.mesh.locate_entities_boundary(mesh, 1, lambda x: np.isclose(x[1], 0.0))
    return mesh, dolfinx.mesh.meshtags(
        mesh, 1, np.sort(top).astype(np.int32), np.full(top.size, TARGET, np.int32)
    )


def gather_pressure(lam: dolfinx.fem.Function) -> tuple[np.ndarray, np.ndarray, float]:
    r"""The multiplier's values sorted by radius (all ranks), and :math:`\int \lambda 2\pi r`.

    Collective.
    """
    Q = lam.function_space
    n = Q.dofmap.index_map.size_local
    comm = Q.mesh.comm
    rs = np.concatenate(comm.allgather(Q.tabulate_dof_coordinates()[:n, 0]))
    ps = np.concatenate(comm.allgather(lam.x.array[:n].copy()))
    order = np.argsort(rs, kind="stable")
    r = ufl.SpatialCoordinate(Q.mesh)[0]
    form = dolfinx.fem.form(lam * 2 * math.pi * r * ufl.dx)
    force = comm.allreduce(dolfinx.fem.assemble_scalar(form))
    return rs[order], ps[order], float(force)


def _solve(a, L, pairs, bcs, *, prefix: str, start: str, hook=None) -> AxiResult:
    from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

    comm = pairs[0].contactor.comm
    comm.Barrier()
    begin = time.perf_counter()
    with UnilateralContactProblem(
        a, L, pairs, bcs, petsc_options_prefix=prefix, start=start
    ) as problem:
        _, multipliers = problem.solve([1.0])
        seconds = comm.bcast(time.perf_counter() - begin, root=0)
        unknowns = sum(
            V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces
        )
        unknowns += sum(p.Q.dofmap.index_map.size_global for p in pairs)
        iterations = [i for s in problem.history.steps for i in s.iterations]
        inspected = None if hook is None else hook(problem)
        r, p, force = gather_pressure(multipliers[0])
    residuals = [i.residual for i in iterations]
    return AxiResult(
        r, p, force, unknowns, len(iterations), seconds, {"residuals": residuals, "hook": inspected}
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
) -> AxiResult:
    r"""An elastic hemisphere pressed by a total force :math:`F` onto a rigid plane.

    Args:
        comm: Communicator.
        F: Total force (a uniform pressure :math:`F/(\pi R^2)` on the flat face).
        R: Radius.
        h: Element size within :math:`R/4` of the contact point.
        degree: Displacement and geometry degree.
        cell: ``"triangle"`` or ``"quadrilateral"``.
        material: The sphere's (axisymmetric) material.
        target: ``"plane"`` (analytic) or ``"rigid"`` (a meshed rigid block).
        start: First active set of the unilateral solve.
        hook: Called as ``hook(problem)`` after the solve; its value is ``extra["hook"]``.
    """
    V, a, v, bcs, tags = _body(comm, R, 0.0, True, h, degree, cell, material)
    mesh = V.mesh
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    q = dolfinx.fem.Constant(mesh, -F / (math.pi * R**2))
    L = q * v[1] * material.weight(mesh) * ds(LOADED)
    if target == "plane":
        floor = plane_obstacle([0.0, 0.0], [0.0, 1.0])
    else:
        floor = rigid_surface(*_floor(comm, 0.4 * R, 24), TARGET)
    pair = contact_pair(contact_surface(V, tags, CONTACT), floor, axisymmetric=True)
    return _solve([a], [L], [pair], bcs, prefix=f"axihertz_{target}_", start=start, hook=hook)


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
) -> AxiResult:
    r"""Sphere 2 pressed by :math:`F` onto sphere 1 (its flat face held, :math:`u_z = 0`).

    Both are meshed with size ``h`` within :math:`\min(R_1, R_2)/4` of the contact point.
    Sphere 1 (below, radius ``R1``) is the contactor: the multiplier lives on it. The
    arguments as :func:`sphere_on_plane`; ``materials`` are sphere 1's and sphere 2's.
    """
    # The fine zone of both: a quarter of the smaller radius (the geometry, not a).
    reach = 0.25 * min(R1, R2)
    V1, a1, v1, bcs1, tags1 = _body(comm, R1, 0.0, False, h, degree, cell, materials[0], reach)
    V2, a2, v2, bcs2, tags2 = _body(comm, R2, 0.0, True, h, degree, cell, materials[1], reach)
    held = dolfinx.fem.locate_dofs_topological(V1.sub(1), 1, tags1.find(LOADED))
    bcs = [*bcs1, *bcs2, dolfinx.fem.dirichletbc(0.0, held, V1.sub(1))]
    zero = dolfinx.fem.Constant(V1.mesh, 0.0)
    L1 = zero * v1[1] * ufl.dx
    ds2 = ufl.Measure("ds", domain=V2.mesh, subdomain_data=tags2)
    q = dolfinx.fem.Constant(V2.mesh, -F / (math.pi * R2**2))
    L2 = q * v2[1] * materials[1].weight(V2.mesh) * ds2(LOADED)
    pair = contact_pair(
        contact_surface(V1, tags1, CONTACT), contact_surface(V2, tags2, CONTACT), axisymmetric=True
    )
    return _solve(
        [a1, a2], [L1, L2], [pair], bcs, prefix="axihertz_spheres_", start=start, hook=hook
    )


#: The scenes' materials and radii: a rigid plane under sphere 1; sphere 2 on sphere 1.
SCENES = {
    "sphere-on-plane": {"R": 1.0, "E_star": 1 / (1 - 0.3**2)},
    "two-spheres": {"R": 1 / (1 / 1.0 + 1 / 2.0), "E_star": 1 / ((1 - 0.3**2) + (1 - 0.25**2) / 2)},
}


def run(
    comm: MPI.Comm,
    scene: str,
    *,
    a_over_R1: float = 0.05,
    h: float = 0.005,
    degree: int = 2,
    cell: str = "triangle",
    target: str = "plane",
    keep_pressure: bool = False,
) -> dict[str, typing.Any]:
    r"""Solve a scene with the load that gives Hertz's :math:`a = ` ``a_over_R1`` :math:`R_1`.

    Returns a record for ``results/``: the exact and measured :math:`a`, :math:`p_0`, the
    errors of :func:`hertz_measures`, the unknowns, solves and seconds; with
    ``keep_pressure``, also ``r`` and ``pressure`` (arrays, for plots).
    """
    R, E_star = SCENES[scene]["R"], SCENES[scene]["E_star"]
    a = a_over_R1 * 1.0
    F = 4 * E_star * a**3 / (3 * R)
    kwargs = {"F": F, "h": h, "degree": degree, "cell": cell}
    if scene == "sphere-on-plane":
        result = sphere_on_plane(comm, target=target, **kwargs)
    else:
        result = two_spheres(comm, **kwargs)
    a_exact, p0_exact = hertz_exact(F, R, E_star)
    arrays = {"r": result.r, "pressure": result.pressure} if keep_pressure else {}
    return arrays | {
        "study": "axisymmetric-hertz",
        "scene": scene,
        "target": target if scene == "sphere-on-plane" else "elastic",
        "cell": cell,
        "degree": degree,
        "h": h,
        "a_over_R1": a_over_R1,
        "ranks": comm.size,
        "F": F,
        "a_exact": a_exact,
        "p0_exact": p0_exact,
        **hertz_measures(result, a_exact, p0_exact),
        "force_over_F": result.force / F,
        "unknowns": result.unknowns,
        "solves": result.solves,
        "seconds": result.seconds,
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

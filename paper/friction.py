# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The friction scenes of issue [4/6] in 2D, shared by ``tests/friction`` and the demo.

- :func:`cattaneo_mindlin`: two identical half cylinders (:func:`paper.hertz.scene.hertz`
  with ``lower_radius=R``), plane strain, the upper flat face moved down by
  :math:`\delta` in four frictionless steps, then sideways in four steps with
  :math:`\mu = 0.2`; the stick half-width, :math:`q(x)` from :math:`\lambda_t` and
  :math:`p(x)` from :math:`\lambda_n` against Cattaneo and Mindlin's closed form.
- :func:`half_disks`: the other FEniCSx contact package's friction demo, two half disks
  :math:`R = 8` (:func:`half_disks_mesh`, a user's mesh refined around the poles) pressed
  by a normal traction in four frictionless steps, then sheared by a tangential traction
  in eight steps with :math:`\mu = 0.2` and the top's vertical motion held:
  Hertz's :math:`a`, :math:`p_0` and Cattaneo and Mindlin's :math:`c`, :math:`q(x)`.
- :func:`inclined_block`: a block pushed up a slope :math:`\tan\alpha = 0.1`, all of it
  sliding with :math:`\mu = 0.5`: the reaction's ratio
  :math:`(\mu + \tan\alpha)/(1 - \mu\tan\alpha)`.
- The frictional patch test's scene (:func:`patch_scene`, :func:`patch_pair`,
  :func:`patch_bcs`, :func:`patch_loads`, :func:`patch_exact`, :func:`patch_reference`,
  and :func:`patch_path` for a load path of uniform states) and its two cases
  :func:`patch_stick` and :func:`patch_slip`.
"""

from __future__ import annotations

import math
import time
import typing

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.meshing import gmsh_session, model_to_mesh
from dolfinx_contact_s2s.postprocess import contact_zones
from paper.hertz.scene import GRADING, TAGS, hertz
from paper.scenes_multi import two_blocks_one_mesh

__all__ = [
    "CM_DELTA",
    "CM_MU",
    "CM_SHIFT",
    "HD_OTHER_PACKAGE",
    "MATERIAL",
    "NU",
    "E",
    "G",
    "cattaneo_mindlin",
    "cattaneo_mindlin_measure",
    "cattaneo_mindlin_model",
    "cattaneo_mindlin_path",
    "cattaneo_mindlin_scene",
    "cattaneo_mindlin_shear",
    "half_disks",
    "half_disks_mesh",
    "inclined_block",
    "patch_bcs",
    "patch_exact",
    "patch_loads",
    "patch_pair",
    "patch_path",
    "patch_reference",
    "patch_scene",
    "patch_slip",
    "patch_stick",
]

#: Young's modulus and Poisson's ratio of every scene here.
E, NU = 1.0, 0.3
MATERIAL = Material(E=E, nu=NU)
G = E / (2 * (1 + NU))

#: Cattaneo-Mindlin: the radius, mu, the graded contact half-width, and the rigid motions
#: of the upper face (a about 0.05, Q / (mu P) about 0.5).
CM_R, CM_MU, CM_A = 1.0, 0.2, 0.05
CM_DELTA, CM_SHIFT = 0.009, 0.00147


def _gather(comm: MPI.Comm, values: np.ndarray) -> np.ndarray:
    return np.concatenate(comm.allgather(values))


def cattaneo_mindlin_shear(
    x: np.ndarray, a: float, c: float, p0: float, mu: float = CM_MU
) -> np.ndarray:
    r"""Cattaneo and Mindlin's shear :math:`\mu p_0/a [\sqrt{a^2-x^2} - \sqrt{c^2-x^2}]_+`."""
    return (
        mu
        * p0
        / a
        * (np.sqrt(np.clip(a**2 - x**2, 0, None)) - np.sqrt(np.clip(c**2 - x**2, 0, None)))
    )


def _relative_l2(x: np.ndarray, values: np.ndarray, exact: typing.Callable, a: float) -> float:
    """Relative L2 error over [-a, a] of the nodal values (linear interpolation)."""
    order = np.argsort(x)
    fine = np.linspace(-a, a, 20001)
    reference = exact(fine)
    error = np.interp(fine, x[order], values[order]) - reference
    return math.sqrt(np.trapezoid(error**2, fine) / np.trapezoid(reference**2, fine))


def _two_cylinders(
    P: float, Q: float, E: float, nu: float, R: float, mu: float
) -> tuple[float, float, float, typing.Callable]:
    r"""Hertz and Cattaneo-Mindlin for two identical cylinders of radius ``R``, per length.

    :math:`R_e = R/2`, :math:`E^* = E/(2(1-\nu^2))`: :math:`a = 2\sqrt{P R_e/(\pi E^*)}`,
    :math:`p_0 = 2P/(\pi a)`, :math:`c = a\sqrt{1 - Q/(\mu P)}` and :math:`p(x)`.
    """
    E_star, R_e = E / (2 * (1 - nu**2)), R / 2
    a = 2 * math.sqrt(P * R_e / (math.pi * E_star))
    p0 = 2 * P / (math.pi * a)

    def pressure(s):
        return p0 * np.sqrt(np.clip(1 - s**2 / a**2, 0, None))

    return a, p0, a * math.sqrt(1 - Q / (mu * P)), pressure


def cattaneo_mindlin_scene(comm: MPI.Comm, degree: int, across: int) -> tuple:
    r"""The forms, conditions, pair and the upper face's motion of :func:`cattaneo_mindlin`.

    Two half cylinders :math:`R = 1` graded for :math:`a = 0.05` at ``across`` elements
    across :math:`2a`, no mesh node placed at :math:`x = \pm a`; the lower flat face
    clamped, the upper one moved by the returned function ``motion``.
    """
    # No mesh nodes at x = +-a (edge_nodes=False): a user's mesh knows no contact edge.
    scene = hertz(
        comm,
        R=CM_R,
        a=CM_A,
        elements_across=across,
        lower_radius=CM_R,
        geometry_degree=degree,
        edge_nodes=False,
    )
    return cattaneo_mindlin_model(scene.mesh, scene.facet_tags, degree)


def cattaneo_mindlin_model(
    mesh: dolfinx.mesh.Mesh, tags: dolfinx.mesh.MeshTags, degree: int
) -> tuple:
    """The forms, conditions, pair and motion of :func:`cattaneo_mindlin_scene` on a mesh of it."""
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a_form, _, v = MATERIAL.forms(V)
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.zeros(2)), v) * ufl.dx
    motion = dolfinx.fem.Function(V)
    fdim = mesh.topology.dim - 1
    top = dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(TAGS["upper_top"]))
    bottom = dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(TAGS["lower_bottom"]))
    bcs = [
        dolfinx.fem.dirichletbc(motion, top),
        dolfinx.fem.dirichletbc(dolfinx.fem.Function(V), bottom),
    ]
    pair = contact_pair(
        contact_surface(V, tags, TAGS["contactor"]), contact_surface(V, tags, TAGS["target"])
    )
    return a_form, L, bcs, pair, motion


def cattaneo_mindlin_path(
    problem: FrictionalContactProblem, motion: dolfinx.fem.Function, first: list | None = None
) -> list[int]:
    """The load path: the upper face moved down in four frictionless steps, then sideways.

    ``first``: the first active set of the first step (``solve(active=...)``). Returns
    the linear solves of every step.
    """
    motion.interpolate(lambda x: np.stack([0.0 * x[0], -CM_DELTA + 0.0 * x[0]]))
    problem.solve([0.25, 0.5, 0.75, 1.0], mu=0.0, active=first)
    solves = [len(s.iterations) for s in problem.history.steps]
    for k in range(1, 5):
        motion.interpolate(
            lambda x, k=k: np.stack([0 * x[0] + k * CM_SHIFT / 4, -CM_DELTA + 0 * x[0]])
        )
        problem.solve([1.0], restart=False)
        solves += [len(s.iterations) for s in problem.history.steps]
    return solves


def cattaneo_mindlin(
    comm: MPI.Comm, degree: int, across: int = 20, *, keep_traction: bool = False
) -> dict[str, typing.Any]:
    r"""Cattaneo-Mindlin in 2D at about ``across`` elements across :math:`2a`.

    :math:`P` and :math:`Q` are the integrals of :math:`\lambda_n` and :math:`\lambda_t`;
    Hertz with :math:`R_e = R/2`, :math:`E^* = E/(2(1-\nu^2))` gives :math:`a` and
    :math:`p_0`, and :math:`c = a\sqrt{1 - Q/(\mu P)}`. The measured :math:`c` is the
    largest :math:`|x|` of a sticking multiplier node; ``c_middle`` the middles of the
    brackets of the stick zone's ends (last sticking and first slipping node,
    :func:`~dolfinx_contact_s2s.postprocess.contact_zones` on the stick set), within
    half a node spacing of :math:`c` where a bracket holds it (not always: the
    discrete stick zone can sit a node off centre).

    Returns:
        A record: ``P``, ``Q``, ``a``, ``p0``, ``c_exact``, ``c``, ``h``,
        ``c_error_elements``, ``c_error``, ``c_bracketed`` (every end's bracket holds
        :math:`c`), ``c_middle``, ``c_middle_error`` and ``c_middle_error_elements``
        (the brackets' middles, the larger error of the two ends, relative and in
        elements), ``q_L2_error``, ``p_L2_error``,
        ``solves_per_step``, ``unknowns``, ``seconds``; with ``keep_traction`` also
        ``x``, ``q``, ``p`` (gathered, every rank).
    """
    begin = time.perf_counter()
    a_form, L, bcs, pair, motion = cattaneo_mindlin_scene(comm, degree, across)
    with FrictionalContactProblem(
        a_form, L, [pair], bcs, mu=CM_MU, petsc_options_prefix=f"cm{degree}_"
    ) as problem:
        solves = cattaneo_mindlin_path(problem, motion)
        record = cattaneo_mindlin_measure(problem, 2 * CM_A / across)
    record.update(
        degree=degree,
        across=across,
        solves_per_step=solves,
        seconds=comm.allreduce(time.perf_counter() - begin, op=MPI.MAX),
    )
    if not keep_traction:
        for key in ("x", "q", "p"):
            record.pop(key)
    return record


def cattaneo_mindlin_measure(
    problem: FrictionalContactProblem, h: float | None = None
) -> dict[str, typing.Any]:
    """The record of :func:`cattaneo_mindlin` from a solved problem (collective).

    ``h`` is the element size at the contact; ``None`` takes it at the stick zone's
    ends (the widest of their brackets times the degree: a locally refined mesh).
    The record also has ``across_contact``, the contactor's elements within
    :math:`|x| < a`, and the gathered ``x``, ``q``, ``p``.
    """
    comm, (pair,) = problem.comm, problem.pairs
    V = pair.contactor.V

    def integral(f):
        return comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(f * ufl.dx)))

    (lam_n,), (lam_t,) = problem.multipliers, problem.tangential
    P, Q = integral(lam_n), integral(lam_t)
    n = pair.Q.dofmap.index_map.size_local
    x = _gather(comm, pair.Q.tabulate_dof_coordinates()[:n, 0])
    q, p = _gather(comm, lam_t.x.array[:n]), _gather(comm, lam_n.x.array[:n])
    stick = _gather(comm, problem.stick[0].x.array[:n]) > 0.5
    unknowns = V.dofmap.index_map.size_global * 2 + 2 * pair.Q.dofmap.index_map.size_global
    # The stick zone's ends, each bracketed by its last sticking and first slipping node.
    ends = [
        e
        for z in contact_zones(pair, problem.stick[0], problem.stick[0], estimate="middle")
        for e in (z.start, z.end)
    ]
    degree = pair.contactor.element.degree
    a, p0, c_exact, hertz_p = _two_cylinders(P, Q, E, NU, CM_R, CM_MU)
    if h is None:
        h = degree * max(e.bracket for e in ends)
    c = float(np.max(np.abs(x[stick]))) if stick.any() else 0.0
    inside, outside = (np.abs([e.bracket_points[k][0] for e in ends]) for k in (0, 1))
    middles = np.abs([e.point[0] for e in ends])
    return {
        "scene": "cattaneo-mindlin",
        "P": P,
        "Q": Q,
        "Q_over_muP": Q / (CM_MU * P),
        "a": a,
        "p0": p0,
        "c_exact": c_exact,
        "c": c,
        "h": h,
        "across_contact": int(np.count_nonzero(np.abs(x) < a)) / degree,
        "c_error_elements": abs(c - c_exact) / h,
        "c_error": abs(c - c_exact) / c_exact,
        "c_bracketed": bool(np.all((inside <= c_exact) & (c_exact <= outside))),
        "c_middle": float(np.mean(middles)),
        "c_middle_error": float(np.max(np.abs(middles - c_exact))) / c_exact,
        "c_middle_error_elements": float(np.max(np.abs(middles - c_exact))) / h,
        "q_L2_error": _relative_l2(x, q, lambda s: cattaneo_mindlin_shear(s, a, c_exact, p0), a),
        "p_L2_error": _relative_l2(x, p, hertz_p, a),
        "unknowns": unknowns,
        "x": x,
        "q": q,
        "p": p,
    }


#: The other package's half disks: radius, material, normal and tangential tractions on
#: the upper flat face (F = 10 and Q = 0.936 per unit thickness over its width 2R), mu.
HD_R, HD_E, HD_NU, HD_P, HD_Q, HD_MU = 8.0, 200.0, 0.3, 0.625, 0.05851, 0.2
#: The other package's own run of its half disks (its ``demo_friction_cylinders_force_driven.py``,
#: Wells-Group/asimov-contact v0.9.0, commit db958afe, built against DOLFINx 0.9 and run on
#: this machine on 28 November 2026, one rank, two cores shared with other work): Nitsche
#: with P1 quadrilaterals, Newton with GAMG-preconditioned CG and GMRES. Read from its raw
#: stresses at the contact quadrature points (those its writer outputs), upper disk:
#: ``c`` the half-width of the central interval with ``|q| < 0.95 mu P`` (0.57-0.59 at
#: 0.99: the stress noise moves one end), ``a`` and ``p0`` a weighted fit of Hertz's
#: profile, the L2 errors relative, as :func:`half_disks` defines them. A measurement, not
#: an input: the report prints it beside this package's numbers.
HD_OTHER_PACKAGE = {
    "unknowns": 816_932,
    "newton": 106,
    "linear": 3406,
    "seconds": 1868.0,
    "cpu_seconds": 912.0,
    "c": 0.512,
    "q_L2_error": 0.2425,
    "p_L2_error": 0.0445,
    "a": 0.670,
    "p0": 9.450,
}
#: Facet tags of :func:`half_disks_mesh` (the axes x = 0 are interior lines).
HD_TAGS = {"contactor": 10, "upper_top": 11, "upper_rest": 12, "target": 20, "lower_bottom": 21}


def _half_disk(geo: typing.Any, R: float, side: int) -> tuple[list[int], dict[str, list[int]]]:
    """The half of the disk about (0, side R) that touches the origin: quarters, curves."""
    centre, pole = geo.addPoint(0.0, side * R, 0.0), geo.addPoint(0.0, 0.0, 0.0)
    right, left = geo.addPoint(R, side * R, 0.0), geo.addPoint(-R, side * R, 0.0)
    x, y = R * math.sin(math.pi / 6), side * R * (1 - math.cos(math.pi / 6))
    r30, l30 = geo.addPoint(x, y, 0.0), geo.addPoint(-x, y, 0.0)
    near = [geo.addCircleArc(pole, centre, r30), geo.addCircleArc(l30, centre, pole)]
    rest = [geo.addCircleArc(r30, centre, right), geo.addCircleArc(left, centre, l30)]
    flat = [geo.addLine(right, centre), geo.addLine(centre, left)]
    axis = geo.addLine(centre, pole)
    loops = [[near[0], rest[0], flat[0], axis], [-axis, flat[1], rest[1], near[1]]]
    if side < 0:  # counterclockwise below the origin too
        loops = [[-c for c in reversed(loop)] for loop in loops]
    surfaces = [geo.addPlaneSurface([geo.addCurveLoop(loop)]) for loop in loops]
    return surfaces, {"near": near, "rest": rest, "flat": flat, "pole": [pole]}


def half_disks_mesh(
    comm: MPI.Comm, h: float, *, refine: float = 1.0, far: float = 1.0, geometry_degree: int = 1
) -> tuple[dolfinx.mesh.Mesh, dolfinx.mesh.MeshTags, dolfinx.mesh.MeshTags]:
    r"""Two half disks of radius :data:`HD_R` touching at their poles, as a user meshes them.

    The upper one is the lower half of the disk about :math:`(0, R)`, the lower one the
    upper half of the disk about :math:`(0, -R)`; each is two quarters (the axis
    :math:`x = 0` a mesh line). Triangles of size ``h`` within ``refine`` of the poles
    (a size field of the user's guess, not of the answer), growing at the slope
    :data:`paper.hertz.scene.GRADING` to ``far``. The contact surfaces are the arcs within
    30 degrees of the poles (:data:`HD_TAGS`).

    Returns:
        The mesh, its cell tags (upper 1, lower 2) and facet tags.
    """
    options = {
        "Mesh.MeshSizeExtendFromBoundary": 0,
        "Mesh.MeshSizeFromPoints": 0,
        "Mesh.MeshSizeFromCurvature": 0,
        "Mesh.Algorithm": 6,
    }
    with gmsh_session() as gmsh:
        saved = {name: gmsh.option.getNumber(name) for name in options}
        for name, value in options.items():
            gmsh.option.setNumber(name, value)
        gmsh.model.add("half_disks")
        if comm.rank == 0:
            geo = gmsh.model.geo
            upper, up = _half_disk(geo, HD_R, 1)
            lower, low = _half_disk(geo, HD_R, -1)
            geo.synchronize()
            gmsh.model.addPhysicalGroup(2, upper, 1, name="upper")
            gmsh.model.addPhysicalGroup(2, lower, 2, name="lower")
            for name, curves in (
                ("contactor", up["near"]),
                ("upper_top", up["flat"]),
                ("upper_rest", up["rest"]),
                ("target", low["near"]),
                ("lower_bottom", low["flat"]),
            ):
                gmsh.model.addPhysicalGroup(1, curves, HD_TAGS[name], name=name)
            field = gmsh.model.mesh.field
            distance = field.add("Distance")
            field.setNumbers(distance, "PointsList", up["pole"] + low["pole"])
            threshold = field.add("Threshold")
            field.setNumber(threshold, "InField", distance)
            field.setNumber(threshold, "SizeMin", h)
            field.setNumber(threshold, "SizeMax", far)
            field.setNumber(threshold, "DistMin", refine)
            field.setNumber(threshold, "DistMax", refine + (far - h) / GRADING)
            field.setAsBackgroundMesh(threshold)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(geometry_degree)
        mesh, cell_tags, facet_tags = model_to_mesh(gmsh.model, comm, 0, gdim=2)
        gmsh.model.remove()
        for name, value in saved.items():
            gmsh.option.setNumber(name, value)
    return mesh, cell_tags, facet_tags


def _resultant(
    pair: typing.Any, V: dolfinx.fem.FunctionSpace, cells: np.ndarray, lam: list
) -> np.ndarray:
    r"""The load on the body of ``cells`` that :math:`\lambda_n, \lambda_t` balance.

    The saddle point's :math:`\mathbf B_t^T \lambda_t - \mathbf B_n^T \lambda_n` on the
    body's rigid translations (:math:`\mathbf K \mathbf U` vanishes there): without a
    Dirichlet condition along a direction, the body's applied load, to round-off.
    """
    ops = [assemble_coupling(pair), assemble_coupling(pair, tangential=True)]
    blocks = np.unique(V.dofmap.list[cells])
    out = np.zeros(2)
    for k in range(2):
        e = dolfinx.fem.Function(V)
        e.x.array[2 * blocks + k] = 1.0
        for sign, op, values in zip((-1.0, 1.0), ops, lam, strict=True):
            w = op.G.duplicate()
            op.blocks[0][1].mult(e.x.petsc_vec, w)
            out[k] += sign * float(np.dot(values[: w.getLocalSize()], w.array_r))
            w.destroy()
    for op in ops:
        op.destroy()
    return pair.Q.mesh.comm.allreduce(out)


def half_disks(
    comm: MPI.Comm, degree: int, h: float = 0.1, *, keep_traction: bool = False
) -> dict[str, typing.Any]:
    r"""The other package's friction demo: two half disks, a normal then a tangential load.

    Plane strain, :math:`E = 200`, :math:`\nu = 0.3`, :math:`R = 8`
    (:func:`half_disks_mesh` with size ``h`` at the poles, geometry degree ``degree``),
    the lower flat face clamped. A normal traction :math:`0.625` on the upper flat face
    (:math:`F = 10`) in four frictionless steps, the axes :math:`x = 0` held at
    :math:`u_x = 0` (symmetry; nothing else holds the upper body sideways without
    friction); then a second problem on the same spaces, continuing the first
    (``solve(after=...)``) with the axes released and the top's vertical motion held:
    a tangential traction :math:`0.05851` (:math:`Q = 0.936`) in eight steps with
    :math:`\mu = 0.2`. Hertz with :math:`R_e = R/2`: :math:`a = 2\sqrt{F R_e/(\pi
    E^*)} = 0.681`, :math:`p_0 = 2F/(\pi a) = 9.35`; Cattaneo and Mindlin:
    :math:`c = a\sqrt{1 - Q/(\mu F)} = 0.729 a`.

    Returns:
        A record: the applied ``F``, ``Q``; the loads on the upper body that the contact
        tractions balance (from the couplings, :func:`_resultant`): ``P_normal``
        (downward) after the normal steps, ``P`` (downward) and ``Q_measured`` (along
        :math:`x`) at the end; ``a``, ``p0``, ``c_exact`` (from ``F``, ``Q``); the
        measured ``a_measured`` (outermost active node), ``p0_measured`` (largest
        :math:`\lambda_n`) and ``c`` (outermost sticking node),
        ``c_error_elements``, ``q_L2_error``, ``p_L2_error``, ``solves_per_step``,
        ``unknowns``, ``seconds``; with ``keep_traction`` also ``x``, ``q``, ``p``.
    """
    begin = time.perf_counter()
    mesh, cell_tags, tags = half_disks_mesh(comm, h, geometry_degree=degree)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a_form, _, v = Material(E=HD_E, nu=HD_NU).forms(V)
    traction = dolfinx.fem.Constant(mesh, np.zeros(2))
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    L = ufl.inner(traction, v) * ds(HD_TAGS["upper_top"])
    fdim = mesh.topology.dim - 1
    clamp = dolfinx.fem.dirichletbc(
        np.zeros(2),
        dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(HD_TAGS["lower_bottom"])),
        V,
    )
    axes = dolfinx.mesh.locate_entities(mesh, fdim, lambda x: np.isclose(x[0], 0.0))
    symmetry = dolfinx.fem.dirichletbc(
        dolfinx.default_scalar_type(0),
        dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, axes),
        V.sub(0),
    )
    Vy, to_y = V.sub(1).collapse()
    held = dolfinx.fem.Function(Vy)
    top = dolfinx.fem.locate_dofs_topological((V.sub(1), Vy), fdim, tags.find(HD_TAGS["upper_top"]))
    pair = contact_pair(
        contact_surface(V, tags, HD_TAGS["contactor"]), contact_surface(V, tags, HD_TAGS["target"])
    )
    upper = cell_tags.find(1)
    F, Q = 2 * HD_R * HD_P, 2 * HD_R * HD_Q
    solves = []
    with FrictionalContactProblem(
        a_form, L, [pair], [clamp, symmetry], mu=HD_MU, petsc_options_prefix=f"hd{degree}n_"
    ) as normal:
        traction.value[:] = (0.0, -HD_P)
        (u,), (lam_n,), (lam_t,) = normal.solve([0.25, 0.5, 0.75, 1.0], mu=0.0)
        solves += [len(s.iterations) for s in normal.history.steps]
        P_normal = -_resultant(pair, V, upper, [lam_n.x.array, lam_t.x.array])[1]
        held.x.array[:] = u.x.array[to_y]
        with FrictionalContactProblem(
            a_form,
            L,
            [pair],
            [clamp, dolfinx.fem.dirichletbc(held, top, V.sub(1))],
            mu=HD_MU,
            petsc_options_prefix=f"hd{degree}t_",
        ) as problem:
            for k in range(1, 9):
                traction.value[:] = (HD_Q * k / 8, -HD_P)
                (u,), (lam_n,), (lam_t,) = problem.solve(
                    [1.0], restart=False, after=normal if k == 1 else None
                )
                solves += [len(s.iterations) for s in problem.history.steps]
            Q_measured, P = _resultant(pair, V, upper, [lam_n.x.array, lam_t.x.array]) * [1, -1]
            n = pair.Q.dofmap.index_map.size_local
            x = _gather(comm, pair.Q.tabulate_dof_coordinates()[:n, 0])
            q, p = _gather(comm, lam_t.x.array[:n]), _gather(comm, lam_n.x.array[:n])
            stick = _gather(comm, problem.stick[0].x.array[:n]) > 0.5
            active = _gather(comm, problem.active[0].x.array[:n]) > 0.5
    unknowns = V.dofmap.index_map.size_global * 2 + 2 * pair.Q.dofmap.index_map.size_global
    a, p0, c_exact, hertz_p = _two_cylinders(F, Q, HD_E, HD_NU, HD_R, HD_MU)
    c = float(np.max(np.abs(x[stick]))) if stick.any() else 0.0

    record = {
        "scene": "half-disks",
        "degree": degree,
        "h": h,
        "F": F,
        "Q": Q,
        "P_normal": P_normal,
        "P": P,
        "Q_measured": Q_measured,
        "Q_over_muP": Q / (HD_MU * F),
        "a": a,
        "a_measured": float(np.max(np.abs(x[active]))),
        "p0": p0,
        "p0_measured": float(np.max(p)),
        "c_exact": c_exact,
        "c": c,
        "c_error_elements": abs(c - c_exact) / h,
        "q_L2_error": _relative_l2(
            x, q, lambda s: cattaneo_mindlin_shear(s, a, c_exact, p0, HD_MU), a
        ),
        "p_L2_error": _relative_l2(x, p, hertz_p, a),
        "solves_per_step": solves,
        "unknowns": unknowns,
        "seconds": comm.allreduce(time.perf_counter() - begin, op=MPI.MAX),
    }
    if keep_traction:
        record.update(x=x, q=q, p=p)
    return record


def inclined_block(
    comm: MPI.Comm, degree: int, *, tan: float = 0.1, mu: float = 0.5
) -> dict[str, typing.Any]:
    r"""A block pushed up a slope, all of it sliding: the reaction's ratio.

    The two blocks of :func:`paper.scenes_multi.two_blocks_one_mesh` (7/5 elements)
    sheared by :math:`y \mapsto y + x \tan\alpha`; the lower one clamped at its bottom,
    the upper one pressed by a vertical load :math:`V` on its top and pushed by
    :math:`u_x = 5` on its left side. The reaction :math:`R_x` of the push is the
    residual :math:`a(u, v) - L(v)` at the pushed dofs (not :math:`\lambda`).

    Returns:
        A record: ``ratio`` :math:`R_x / V`, ``expected``, ``error`` (relative),
        ``sliding`` (no multiplier sticks, some active), ``solves``, ``unknowns``.
    """
    part = two_blocks_one_mesh(comm, (7, 5)).parts["blocks"]
    mesh, tags = part.mesh, part.facet_tags
    mesh.geometry.x[:, 1] += tan * mesh.geometry.x[:, 0]
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a, _, v = MATERIAL.forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    load = 0.2
    L = -load * v[1] * ds(23)
    fdim = mesh.topology.dim - 1
    clamp = dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(1))
    # The left side's nodes off the contact line: their residual is the push's reaction.
    push = np.setdiff1d(
        dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, tags.find(24)),
        dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, tags.find(20)),
    )
    bcs = [
        dolfinx.fem.dirichletbc(np.zeros(2), clamp, V),
        dolfinx.fem.dirichletbc(dolfinx.default_scalar_type(5.0), push, V.sub(0)),
    ]
    pair = patch_pair(part, V, degree)
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=mu, petsc_options_prefix=f"incline{degree}_"
    ) as problem:
        (u,), _, _ = problem.solve()
        last = problem.history.steps[-1].iterations[-1]
        sliding = last.active[0] > 0 and last.stick == (0,)
        solves = problem.history.iterations
    residual = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(ufl.action(a, u) - L))
    residual.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    owned = push[push < residual.getLocalSize()]
    reaction = comm.allreduce(float(np.sum(residual.array_r[owned])))
    residual.destroy()
    V_load = comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(load * ds(23))))
    expected = (mu + tan) / (1 - mu * tan)
    return {
        "scene": "inclined-block",
        "degree": degree,
        "ratio": reaction / V_load,
        "expected": expected,
        "error": abs(reaction / V_load - expected) / expected,
        "sliding": bool(sliding),
        "solves": solves,
        "unknowns": V.dofmap.index_map.size_global * 2 + 2 * pair.Q.dofmap.index_map.size_global,
    }


def patch_scene(
    degree: int, comm: MPI.Comm = MPI.COMM_WORLD, elements: tuple[int, int] = (7, 5)
) -> tuple[typing.Any, dolfinx.fem.FunctionSpace]:
    """The patch test's two non-matching blocks (heights 0.5) and their P``degree`` space."""
    part = two_blocks_one_mesh(comm, elements, geometry_degree=1).parts["blocks"]
    V = dolfinx.fem.functionspace(part.mesh, ("Lagrange", degree, (2,)))
    return part, V


def patch_pair(part: typing.Any, V: dolfinx.fem.FunctionSpace, degree: int) -> typing.Any:
    """The upper block's bottom on the lower one's top, multipliers of degree ``degree``."""
    tags = part.facet_tags
    return contact_pair(
        contact_surface(V, tags, 20), contact_surface(V, tags, 10), multiplier=("Lagrange", degree)
    )


def patch_bcs(
    part: typing.Any, V: dolfinx.fem.FunctionSpace, top_x: typing.Callable | None = None
) -> list[dolfinx.fem.DirichletBC]:
    """Rollers under the lower block, its corner (0, 0) pinned; the top's u_x if given."""
    mesh, tags = part.mesh, part.facet_tags
    fdim = mesh.topology.dim - 1
    rollers = dolfinx.fem.locate_dofs_topological(V.sub(1), fdim, tags.find(1))
    corner = dolfinx.mesh.locate_entities_boundary(
        mesh, 0, lambda x: np.isclose(x[0], 0.0) & np.isclose(x[1], 0.0)
    )
    pin = dolfinx.fem.locate_dofs_topological(V.sub(0), 0, corner)
    zero = dolfinx.default_scalar_type(0)
    bcs = [dolfinx.fem.dirichletbc(zero, d, V.sub(c)) for c, d in ((1, rollers), (0, pin))]
    if top_x is not None:
        Vx, _ = V.sub(0).collapse()
        g = dolfinx.fem.Function(Vx)
        g.interpolate(top_x)
        dofs = dolfinx.fem.locate_dofs_topological((V.sub(0), Vx), fdim, tags.find(23))
        bcs.append(dolfinx.fem.dirichletbc(g, dofs, V.sub(0)))
    return bcs


def patch_loads(
    part: typing.Any, v: typing.Any, p: typing.Any, tau: typing.Any, top_shear: bool = True
) -> typing.Any:
    """Pressure p on the top, the shear tau on the sides and bottom (and top) of both.

    ``p`` and ``tau`` are numbers or :class:`dolfinx.fem.Constant` (a load path).
    """
    ds = ufl.Measure("ds", domain=part.mesh, subdomain_data=part.facet_tags)
    L = -p * v[1] * ds(23) - tau * v[0] * ds(1)
    L += tau * v[1] * (ds(2) + ds(22)) - tau * v[1] * (ds(4) + ds(24))
    return L + tau * v[0] * ds(23) if top_shear else L


def patch_exact(p: float, tau: float) -> typing.Callable:
    """The uniform state's displacement, without the upper block's c."""
    exx, eyy, gamma = NU * (1 + NU) * p / E, -(1 - NU**2) * p / E, tau / G
    return lambda x: np.stack([exx * x[0] + gamma * x[1], eyy * x[1]])


def patch_reference(
    part: typing.Any, V: dolfinx.fem.FunctionSpace, exact: typing.Callable, c: float
) -> dolfinx.fem.Function:
    """The uniform state in V, c added to u_x on the upper block's cells (tag 2)."""
    u = dolfinx.fem.Function(V)
    u.interpolate(exact)
    upper = np.unique(V.dofmap.list[part.cell_tags.find(2)])
    u.x.array[2 * upper] += c
    return u


def patch_path(
    part: typing.Any, V: dolfinx.fem.FunctionSpace, v: typing.Any
) -> tuple[typing.Any, list[dolfinx.fem.DirichletBC], typing.Callable[[float, float, float], None]]:
    r"""The patch test as a load path: its loads and the top's :math:`u_x`, set step by step.

    Returns:
        The linear form, the conditions (:func:`patch_bcs` and the top's :math:`u_x`) and
        ``state(p, tau, c)``, which sets the pressure :math:`p` on the top, the shear
        :math:`\tau` on the sides and bottom (:func:`patch_loads` without the top's) and
        the top's :math:`u_x` to that of the uniform state of :math:`p`, :math:`\tau`
        with the upper block slipped by :math:`c` (:func:`patch_exact` plus :math:`c`).
    """
    pressure, shear = (dolfinx.fem.Constant(part.mesh, 0.0) for _ in range(2))
    L = patch_loads(part, v, pressure, shear, top_shear=False)
    Vx, _ = V.sub(0).collapse()
    top = dolfinx.fem.Function(Vx)
    fdim = part.mesh.topology.dim - 1
    dofs = dolfinx.fem.locate_dofs_topological((V.sub(0), Vx), fdim, part.facet_tags.find(23))
    bcs = [*patch_bcs(part, V), dolfinx.fem.dirichletbc(top, dofs, V.sub(0))]

    def state(p: float, tau: float, c: float) -> None:
        pressure.value, shear.value = p, tau
        top.interpolate(lambda x: patch_exact(p, tau)(x)[0] + c)

    return L, bcs, state


def _patch_record(comm, problem, pair, V, u, lam_n, lam_t, p, tau, reference, case, degree):
    def owned_max(values):
        return comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)

    n = pair.Q.dofmap.index_map.size_local
    last = problem.history.steps[-1].iterations[-1]
    total = pair.Q.dofmap.index_map.size_global
    return {
        "scene": f"patch-{case}",
        "degree": degree,
        "lambda_n_error": owned_max(lam_n.x.array[:n] - p) / p,
        "lambda_t_error": owned_max(lam_t.x.array[:n] - tau) / abs(tau),
        "u_error": owned_max(u.x.array - reference.x.array) / owned_max(reference.x.array),
        "converged": bool(problem.history.steps[-1].converged),
        "multipliers": total,
        "active": int(last.active[0]),
        "stick": int(last.stick[0]),
        "solves": problem.history.iterations,
    }


def patch_stick(comm: MPI.Comm, degree: int) -> dict[str, typing.Any]:
    r"""Pressure :math:`p = 0.75`, shear :math:`\tau = 0.2 < \mu p` (:math:`\mu = 0.5`): all stick.

    Returns:
        A record: the relative max errors of :math:`\lambda_n`, :math:`\lambda_t`
        (against :math:`p`, :math:`\tau`) and :math:`u`, the sets and solves.
    """
    part, V = patch_scene(degree, comm)
    a, _, v = MATERIAL.forms(V)
    p, tau, mu = 0.75, 0.2, 0.5
    pair = patch_pair(part, V, degree)
    L, bcs = patch_loads(part, v, p, tau), patch_bcs(part, V)
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=mu, petsc_options_prefix="fr_st_"
    ) as problem:
        (u,), (lam_n,), (lam_t,) = problem.solve()
        reference = patch_reference(part, V, patch_exact(p, tau), 0.0)
        return _patch_record(
            comm, problem, pair, V, u, lam_n, lam_t, p, tau, reference, "stick", degree
        )


def patch_slip(comm: MPI.Comm, degree: int, direction: float = 1.0) -> dict[str, typing.Any]:
    r"""The top moved by :math:`0.2\,\mathrm{direction}` with :math:`\mu = 0.3`: all slip.

    Returns:
        As :func:`patch_stick`, :math:`\lambda_t` against :math:`\mu p\,\mathrm{direction}`.
    """
    part, V = patch_scene(degree, comm)
    a, _, v = MATERIAL.forms(V)
    p, mu, d = 0.75, 0.3, 0.2 * direction
    tau = mu * p * direction
    exact = patch_exact(p, tau)
    pair = patch_pair(part, V, degree)
    bcs = patch_bcs(part, V, lambda x: exact(x)[0] + d)
    L = patch_loads(part, v, p, tau, top_shear=False)
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=mu, petsc_options_prefix="fr_sl_"
    ) as problem:
        (u,), (lam_n,), (lam_t,) = problem.solve()
        reference = patch_reference(part, V, exact, d)
        return _patch_record(
            comm, problem, pair, V, u, lam_n, lam_t, p, tau, reference, "slip", degree
        )

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Hertz in 3D, read from the multiplier: contact radius, peak and L2 error; the runs.

Everything is read from :math:`\lambda` (the multiplier Function of the pair) and its
active set, gathered on every rank in global order (the same numbers on any number of
ranks):

- :math:`p_0`: :math:`\lambda` at the multiplier node on the axis (the pole);
- :math:`a`: Hertz's :math:`\lambda^2 = p_0^2 (1 - r^2/a^2)` is linear in :math:`r^2`;
  the least-squares line of :math:`\lambda^2` against :math:`r^2` through the active
  nodes crosses zero at :math:`r^2 = a_h^2` (the 3D form of the ``"pressure"`` estimate
  of :func:`~dolfinx_contact_s2s.contact_zones`); its bracket is the largest radius of
  an active node and the smallest radius of an inactive node on a cell with an active one;
- L2: :math:`\|\lambda_h - p\|_{L^2(\Gamma)} / \|p\|_{L^2(\Gamma)}` over the whole
  multiplier mesh (:math:`p = 0` outside :math:`r = a`), each cell cut into 16 and a
  Gauss rule of degree 8 on each piece, on the cells' own (curved) geometry;
- the force: :math:`F_z` of :func:`~dolfinx_contact_s2s.contact_force` (the pair's
  :math:`\mathbf B^T \Lambda`) and :math:`\int \lambda\, d\Gamma`.
"""

from __future__ import annotations

import math
import time
import typing

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import (
    Material,
    contact_force,
    contact_front,
    contact_pair,
    contact_surface,
    gmsh_session,
    model_to_mesh,
)
from dolfinx_contact_s2s.compat import blocked_sub_element, geometry_dofmap
from dolfinx_contact_s2s.quadrature import split_face_rule
from dolfinx_contact_s2s.unilateral import (
    RefinementError,
    UnilateralContactProblem,
    refine_contact_zone,
)
from paper import hertz3d
from paper.hertz import axisymmetric as axi
from paper.hertz.exact import pressure_l2_error
from paper.scenes import size_field

__all__ = ["adaptive", "axisymmetric", "nodes", "read", "run", "surface_l2"]


def nodes(problem: UnilateralContactProblem) -> dict[str, np.ndarray]:
    r"""Coordinates, :math:`\lambda` and active flags of every multiplier node, all ranks.

    In global dof order; also ``"cells"``: the global dofs of every cell (collective).
    """
    lam, act = problem.multipliers[0], problem.active[0]
    Q = lam.function_space
    imap = Q.dofmap.index_map
    n = imap.size_local
    start = imap.local_range[0]
    x = Q.tabulate_dof_coordinates()[:n]
    num = Q.mesh.topology.index_map(Q.mesh.topology.dim).size_local
    local = Q.dofmap.list[:num]
    cells = imap.local_to_global(local.reshape(-1)).reshape(local.shape)
    parts = Q.mesh.comm.allgather((start, x, lam.x.array[:n].real, act.x.array[:n].real, cells))
    out = {
        "x": np.zeros((imap.size_global, 3)),
        "pressure": np.zeros(imap.size_global),
        "active": np.zeros(imap.size_global, dtype=bool),
    }
    for s, xx, p, a, _ in parts:
        out["x"][s : s + p.size] = xx
        out["pressure"][s : s + p.size] = p
        out["active"][s : s + p.size] = a > 0.5
    out["cells"] = np.concatenate([c for *_, c in parts])
    return out


def _radius(data: dict[str, np.ndarray]) -> tuple[float, float, float]:
    """The fitted contact radius and its bracket ``(a_h, inside, outside)``."""
    r = np.hypot(data["x"][:, 0], data["x"][:, 1])
    on, lam = data["active"], data["pressure"]
    A = np.stack([np.ones(int(on.sum())), r[on] ** 2], axis=1)
    (alpha, beta), *_ = np.linalg.lstsq(A, lam[on] ** 2, rcond=None)
    a_h = math.sqrt(-alpha / beta) if alpha > 0 > beta else math.nan
    cells = data["cells"]
    mixed = cells[on[cells].any(axis=1) & ~on[cells].all(axis=1)]
    off = np.unique(mixed[~on[mixed]])
    outside = float(r[off].min()) if off.size else math.nan
    return a_h, float(r[on].max()), outside


def surface_l2(f: dolfinx.fem.Function, exact: typing.Callable) -> tuple[float, float]:
    r""":math:`\int (f - p)^2` and :math:`\int p^2` over the triangles of ``f``'s mesh (all ranks).

    ``p = exact(x)`` at points ``x`` of shape ``(..., 3)``.
    """
    Q = f.function_space
    mesh = Q.mesh
    num = mesh.topology.index_map(2).size_local
    # Degree 8 on each of 16 pieces of the reference triangle: the kink of p at the edge.
    s, w = split_face_rule("triangle", 8, 4)
    cmap = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element()).basix_element
    psi = cmap.tabulate(1, s)[:, :, :, 0]
    phi = Q.ufl_element().basix_element.tabulate(0, s)[0, :, :, 0]
    X = mesh.geometry.x[geometry_dofmap(mesh)[:num]]
    xq = np.einsum("qn,cnd->cqd", psi[0], X)
    jac = np.linalg.norm(
        np.cross(np.einsum("qn,cnd->cqd", psi[1], X), np.einsum("qn,cnd->cqd", psi[2], X)), axis=2
    )
    lq = f.x.array[Q.dofmap.list[:num]].real @ phi.T
    reference = exact(xq)
    local = np.array([np.sum((lq - reference) ** 2 * jac * w), np.sum(reference**2 * jac * w)])
    total = mesh.comm.allreduce(local, op=MPI.SUM)
    return float(total[0]), float(total[1])


def _l2(problem: UnilateralContactProblem, a: float, p0: float) -> tuple[float, float]:
    r""":math:`\int (\lambda_h - p)^2` and :math:`\int p^2` over the multiplier mesh (all ranks)."""

    def hertz(x):
        return p0 * np.sqrt(np.clip(1 - (x[..., 0] ** 2 + x[..., 1] ** 2) / a**2, 0, None))

    return surface_l2(problem.multipliers[0], hertz)


def read(
    problem: UnilateralContactProblem, a: float, p0: float, *, force: bool = True
) -> dict[str, typing.Any]:
    r"""The measures of the module docstring against Hertz's ``a`` and ``p0`` (collective).

    Also the :func:`~dolfinx_contact_s2s.contact_front` of :math:`\lambda` around the
    :math:`z`-axis: ``"a_gap"`` its gap estimate (the weighted gaps near the front),
    ``"a_front"`` the middle of its bracket, ``"front"`` the bracket, ``"a_level"`` the
    mean radius of the zero crossings. ``force=False`` skips the
    contact force (it integrates the coupling again).
    """
    data = nodes(problem)
    r = np.hypot(data["x"][:, 0], data["x"][:, 1])
    pole = int(np.argmin(r + np.abs(data["x"][:, 2])))
    a_h, inside, outside = _radius(data)
    error2, norm2 = _l2(problem, a, p0)
    front = contact_front(
        problem.multipliers[0],
        problem.active[0],
        centre=(0, 0, 0),
        axis=(0, 0, 1),
        gaps=problem.gaps[0],
    )
    out = {
        "a_gap": front.gap_radius,
        "a_gap_error": front.gap_radius / a - 1,
        "gap_nodes": front.gap_nodes,
        "a_front": front.middle,
        "a_front_error": front.middle / a - 1,
        "front": front.bounds,
        "front_over_a": front.bracket / front.radius,
        "a_level": front.radius,
    }
    if force:
        f = contact_force(problem.pairs[0], problem.multipliers[0])
        out |= {"force_z": float(f.contactor[2]), "pressure_integral": f.pressure_integral}
    return out | {
        "a": a_h,
        "bracket": (inside, outside),
        "p0": float(data["pressure"][pole]),
        "a_error": a_h / a - 1,
        "p0_error": float(data["pressure"][pole]) / p0 - 1,
        "L2_error": math.sqrt(error2 / norm2),
        "active_nodes": int(data["active"].sum()),
        "profile": (r, data["pressure"]),
    }


def _unknowns(problem: UnilateralContactProblem) -> int:
    count = sum(V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces)
    return count + sum(q.function_space.dofmap.index_map.size_global for q in problem.multipliers)


def run(
    comm: MPI.Comm,
    name: str,
    *,
    h: float,
    degree: int = 2,
    reach: float | None = None,
    keep_profile: bool = False,
) -> dict[str, typing.Any]:
    r"""Mesh and solve the quarter model of scene ``name`` with size ``h`` near the contact.

    ``reach`` (the fine zone's radius) defaults to a tenth of the smaller radius; the
    geometry is of degree ``degree``. Returns a record: the exact and measured
    :math:`a`, :math:`p_0`, the errors, the force balance (:math:`|F_z|` against the
    load as assembled, :math:`F/4` on the discrete flat face), unknowns, active-set
    solves and seconds (mesh, build and solve, rank 0's).
    """
    scene = hertz3d.SCENES[name]
    R = min(scene.R1, scene.R2)
    reach = 0.1 * R if reach is None else reach
    a, p0 = hertz3d.exact(scene)
    comm.Barrier()
    begin = time.perf_counter()
    mesh, ct, ft = hertz3d.mesh(comm, scene, h=h, reach=reach, geometry_degree=degree)
    with hertz3d.build(scene, degree=degree, prefix=f"hertz3d_{degree}_")(mesh, ct, ft) as problem:
        problem.solve([1.0])
        seconds = comm.bcast(time.perf_counter() - begin, root=0)
        measured = read(problem, a, p0)
        applied = _applied(scene, mesh, ft)
        unknowns = _unknowns(problem)
        solves = problem.history.iterations
    profile = measured.pop("profile")
    return ({"r": profile[0], "pressure": profile[1]} if keep_profile else {}) | {
        "study": "hertz-3d",
        "scene": name,
        "degree": degree,
        "multiplier": 1,
        "h": h,
        "a_over_h": a / h,
        "h_over_R": h / R,
        "reach_over_R": reach / R,
        "ranks": comm.size,
        "F": scene.F,
        "a_exact": a,
        "p0_exact": p0,
        **measured,
        "force_error": abs(abs(measured["force_z"]) - applied) / applied,
        "unknowns": unknowns,
        "solves": solves,
        "seconds": seconds,
        "cells": mesh.topology.index_map(3).size_global,
    }


def _applied(scene: hertz3d.Scene, mesh: dolfinx.mesh.Mesh, ft: dolfinx.mesh.MeshTags) -> float:
    """The load as assembled (the flat face's discrete area): what equilibrium balances."""
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft)
    q = scene.F / (math.pi * scene.R1**2)
    form = dolfinx.fem.form(q * ds(hertz3d.TAGS["upper_flat"]))
    return mesh.comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM)


def adaptive(
    comm: MPI.Comm,
    name: str,
    *,
    n: int = 40,
    degree: int = 2,
    tolerance: float = 0.12,
    max_steps: int = 3,
    layers: float = 2.0,
    peak_tolerance: float | None = None,
    pressure_tolerance: float | None = None,
) -> list[dict[str, typing.Any]]:
    r"""Scene ``name`` from a user's mesh (size :math:`R/n` near the contact), refined by λ.

    :func:`~dolfinx_contact_s2s.unilateral.refine_contact_zone` around the :math:`z`-axis
    until the contact front's bracket is at most ``tolerance`` times its radius and the
    peak of λ changes by at most ``peak_tolerance`` over a step, and no node's λ is
    farther than ``pressure_tolerance`` from the plane through its neighbours' (or
    ``max_steps`` refinements): new nodes on the spheres (:func:`paper.hertz3d.projection`),
    geometry of degree ``degree``. One record per step, read from :math:`\lambda`
    (:func:`read`, without the force); the last also has the force balance.
    """
    scene = hertz3d.SCENES[name]
    R = min(scene.R1, scene.R2)
    a, p0 = hertz3d.exact(scene)
    comm.Barrier()
    begin = time.perf_counter()
    mesh, ct, ft = hertz3d.mesh(comm, scene, h=R / n, reach=0.1 * R, geometry_degree=1)
    make = hertz3d.build(scene, degree=degree, prefix=f"hertz3d_adaptive_{degree}_")
    latest: list[tuple] = []
    records: list[dict[str, typing.Any]] = []

    def build(domain, cell_tags, facet_tags) -> UnilateralContactProblem:
        latest[:] = [(domain, facet_tags)]
        return make(domain, cell_tags, facet_tags)

    def on_step(step: int, problem: UnilateralContactProblem) -> None:
        measured = read(problem, a, p0, force=False)
        measured.pop("profile")
        records.append(
            {
                "study": "hertz-3d-adaptive",
                "scene": name,
                "degree": degree,
                "step": step,
                "h0_over_R": 1 / n,
                "ranks": comm.size,
                "a_exact": a,
                "p0_exact": p0,
                **measured,
                "unknowns": _unknowns(problem),
                "solves": problem.history.iterations,
                "cells": latest[0][0].topology.index_map(3).size_global,
                "seconds": comm.bcast(time.perf_counter() - begin, root=0),
            }
        )

    options = {"snap": hertz3d.projection(scene), "geometry_degree": degree, "on_step": on_step}
    options |= {"layers": layers, "peak_tolerance": peak_tolerance}
    options |= {"pressure_tolerance": pressure_tolerance}
    try:
        result = refine_contact_zone(
            build,
            mesh,
            ct,
            ft,
            tolerance=tolerance,
            max_steps=max_steps,
            axis=((0, 0, 0), (0, 0, 1)),
            **options,
        )
        problem, resolved, history = result.problem, True, result.history
    except RefinementError as error:
        problem, resolved, history = error.problem, False, error.history
    for rec, step in zip(records, history, strict=True):
        rec["peak_change"] = step.peak_change
        rec["step_estimate"] = step.fronts[0].estimate if step.fronts else math.nan
    with problem:
        f = contact_force(problem.pairs[0], problem.multipliers[0])
        applied = _applied(scene, *latest[0])
    records[-1] |= {
        "resolved": resolved,
        "tolerance": tolerance,
        "force_z": float(f.contactor[2]),
        "force_error": abs(abs(float(f.contactor[2])) - applied) / applied,
        "seconds_total": comm.bcast(time.perf_counter() - begin, root=0),
    }
    return records


def _axi_block(comm: MPI.Comm, W: float, D: float, h: float, reach: float, far: float) -> tuple:
    """Half-section ``[0, W] x [-D, 0]`` of the cylindrical block (Gmsh, triangles, P2 nodes).

    Tags: top 4 (:data:`~paper.hertz.axisymmetric.TARGET`), bottom 2, axis 3.
    """
    with gmsh_session() as gmsh:
        gmsh.model.add("block")
        if comm.rank == 0:
            geo = gmsh.model.geo
            p = [geo.addPoint(*xy, 0) for xy in ((0, 0), (W, 0), (W, -D), (0, -D))]
            lines = [geo.addLine(p[k], p[(k + 1) % 4]) for k in range(4)]
            surface = geo.addPlaneSurface([geo.addCurveLoop(lines)])
            geo.synchronize()
            gmsh.model.addPhysicalGroup(2, [surface], 1)
            for tag, curve in (
                (axi.TARGET, lines[0]),
                (axi.LOADED, lines[2]),
                (axi.AXIS, lines[3]),
            ):
                gmsh.model.addPhysicalGroup(1, [curve], tag)
            size_field(gmsh, p[0], h, far, reach)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(2)
        return model_to_mesh(gmsh.model, comm, 0)


def _axi_build(
    scene: hertz3d.Scene, multiplier: int | None = None
) -> typing.Callable[..., UnilateralContactProblem]:
    """``build(meshes, cell_tags, facet_tags)``: the axisymmetric hemisphere on the block."""
    m_up, m_lo = (Material(m.E, m.nu, plane="axisymmetric") for m in scene.materials)

    def make(meshes, cell_tags, facet_tags) -> UnilateralContactProblem:
        (sphere, block), (t_s, t_b) = meshes, facet_tags
        spaces, forms, bcs = [], [], []
        for domain, tags, material in ((sphere, t_s, m_up), (block, t_b, m_lo)):
            V = dolfinx.fem.functionspace(domain, ("Lagrange", 2, (2,)))
            a, _, v = material.forms(V)
            domain.topology.create_connectivity(1, 2)
            axis = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, tags.find(axi.AXIS))
            bcs.append(dolfinx.fem.dirichletbc(0.0, axis, V.sub(0)))
            spaces.append((V, v))
            forms.append(a)
        (V_s, v_s), (V_b, v_b) = spaces
        bottom = t_b.find(axi.LOADED)
        for c in (0, 1) if scene.clamped else (1,):
            dofs = dolfinx.fem.locate_dofs_topological(V_b.sub(c), 1, bottom)
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V_b.sub(c)))
        ds = ufl.Measure("ds", domain=sphere, subdomain_data=t_s)
        q = dolfinx.fem.Constant(sphere, -scene.F / (math.pi * scene.R1**2))
        L = [q * v_s[1] * m_up.weight(sphere) * ds(axi.LOADED)]
        L.append(dolfinx.fem.Constant(block, 0.0) * v_b[1] * ufl.dx)
        pair = contact_pair(
            contact_surface(V_s, t_s, axi.CONTACT),
            contact_surface(V_b, t_b, axi.TARGET),
            axisymmetric=True,
            multiplier=None if multiplier is None else ("Lagrange", multiplier),
        )
        return UnilateralContactProblem(forms, L, [pair], bcs, petsc_options_prefix="axi3d_")

    return make


def axisymmetric(
    comm: MPI.Comm,
    name: str,
    *,
    h: float,
    size: tuple[float, float] | None = None,
    multiplier: int | None = None,
) -> dict[str, typing.Any]:
    r"""The axisymmetric model of scene ``name`` (P2, triangles of size ``h`` near the contact).

    The same bodies (for the half-ball the box becomes the cylinder of radius half its
    width, or the block ``size = (W, D)``), read as in 3D: :math:`p_0` at the axis node,
    :math:`a` from the :math:`\lambda^2`-:math:`r^2` line through the active nodes, the
    L2 error over :math:`r \le 1.5 \max(a, a_h)` with the weight :math:`2\pi r`.
    ``multiplier``: its degree (default 2, the displacement's; the 3D models' is 1).
    """
    scene = hertz3d.SCENES[name]
    a, p0 = hertz3d.exact(scene)
    comm.Barrier()
    begin = time.perf_counter()
    if name == "two-spheres":
        rec = axi.run(
            comm,
            name,
            a_over_R1=a,
            h=h,
            estimate="pressure",
            keep_pressure=True,
            multiplier=multiplier,
        )
        r, p, unknowns, solves = rec["r"], rec["pressure"], rec["unknowns"], rec["solves"]
        inside, force = rec["bracket"][0], rec["force_over_F"] * scene.F
    else:
        W, D = (scene.width, scene.depth) if size is None else size
        reach, far = 0.1 * scene.R1, scene.R1 / 8
        sphere = axi.hemisphere(comm, scene.R1, 0.0, True, h, 2, "triangle", reach)
        block = _axi_block(comm, W, D, h, reach, far)
        meshes = [sphere[0], block[0]], [sphere[1], block[1]], [sphere[2], block[2]]
        with _axi_build(scene, multiplier)(*meshes) as problem:
            problem.solve([1.0])
            r, p, force, edges = axi.read(problem)
            unknowns, solves = _unknowns(problem), problem.history.iterations
        inside = edges["pressure"][1]
    on = r <= inside * (1 + 1e-12)
    (alpha, beta), *_ = np.linalg.lstsq(np.stack([np.ones(on.sum()), r[on] ** 2], 1), p[on] ** 2)
    a_h = math.sqrt(-alpha / beta) if alpha > 0 > beta else math.nan
    return {
        "study": "hertz-3d-axisymmetric",
        "scene": name,
        "size": size,
        "multiplier": 2 if multiplier is None else multiplier,
        "h": h,
        "a_over_h": a / h,
        "a_exact": a,
        "p0_exact": p0,
        "a": a_h,
        "p0": float(p[0]),
        "a_error": a_h / a - 1,
        "p0_error": float(p[0]) / p0 - 1,
        "L2_error": pressure_l2_error(r, p, a, p0, a_h, radial=True),
        "force_error": abs(force / scene.F - 1),
        "unknowns": unknowns,
        "solves": solves,
        "seconds": comm.bcast(time.perf_counter() - begin, root=0),
        "ranks": comm.size,
    }

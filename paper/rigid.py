# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Scenes with rigid obstacles: a cylinder on a rigid plane (Hertz) and a flat punch.

Both are half models (symmetry :math:`u_x = 0` on :math:`x = 0`), plane strain, meshed
with Gmsh as a user would: sizes chosen from the geometry, no node placed at the
contact edge, no grading built from the answer.

- :func:`hertz_on_plane`: the quarter disk :math:`x \ge 0` of radius :math:`R` about
  :math:`(0, R)`, touching :math:`y = 0` at the origin, loaded by a uniform traction on
  its flat top (total force :math:`F/2` on the half: :math:`F` per unit length on the
  whole cylinder). The target is a rigid floor: a meshed rigid block, an analytic plane,
  or the same block as a stiff elastic body (``target_E``).
- :func:`flat_punch`: the layer :math:`[0, W] \times [0, D]` lying on a rigid flat punch
  of half-width :math:`a` (its top :math:`[0, a] \times \{0\}`), pressed onto it by a
  uniform traction on its far face :math:`y = D` (total :math:`F/2` on the half).
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
from paper.scenes import size_field

__all__ = [
    "RigidResult",
    "edge_from_multiplier",
    "flat_punch",
    "hertz_on_plane",
    "pressure",
    "quarter_disk",
]

#: Facet tags of the scenes.
CONTACT, LOADED, SYMMETRY, TARGET, CLAMPED = 1, 2, 3, 4, 5


@dataclass
class RigidResult:
    """A solved scene: the contact pressure along the contactor and the model's size.

    Attributes:
        x: Abscissae of the multiplier's nodes (sorted, all ranks), ``(n,)``.
        pressure: The multiplier at those nodes.
        force: The integral of the multiplier, the total contact force on the half model.
        unknowns: Global unknowns of the saddle point (displacements and multipliers).
        seconds: Wall time of the solve (assembly included), rank 0.
        extra: Anything else the scene reports.
    """

    x: np.ndarray
    pressure: np.ndarray
    force: float
    unknowns: int
    seconds: float
    extra: dict[str, typing.Any] = field(default_factory=dict)


def pressure(
    lam: dolfinx.fem.Function, upto: float = math.inf
) -> tuple[np.ndarray, np.ndarray, float]:
    """The multiplier's nodal values sorted by abscissa (gathered), and its integral.

    The integral is over :math:`x < ` ``upto`` (the part facing a target that ends at a
    mesh node there): the multiplier of the last covered node extends beyond it.
    """
    Q = lam.function_space
    n = Q.dofmap.index_map.size_local
    x = Q.tabulate_dof_coordinates()[:n, 0]
    comm = Q.mesh.comm
    xs = np.concatenate(comm.allgather(x))
    ps = np.concatenate(comm.allgather(lam.x.array[:n].copy()))
    order = np.argsort(xs, kind="stable")
    inside = ufl.conditional(ufl.lt(ufl.SpatialCoordinate(Q.mesh)[0], upto), lam, 0.0)
    form = (
        dolfinx.fem.form(inside * ufl.dx) if np.isfinite(upto) else dolfinx.fem.form(lam * ufl.dx)
    )
    force = comm.allreduce(dolfinx.fem.assemble_scalar(form))
    return xs[order], ps[order], float(force)


def edge_from_multiplier(x: np.ndarray, p: np.ndarray) -> float:
    r"""The contact edge from the last two active nodes, assuming a square-root edge.

    Near a smooth contact edge :math:`p^2` is linear in :math:`x^2 - a^2` (Hertz:
    :math:`p^2 = p_0^2 (1 - x^2/a^2)`): the line through the last two active nodes'
    :math:`(x^2, p^2)` crosses zero at :math:`a^2`. Local: reads only those two nodes.
    """
    active = np.flatnonzero(p > 1e-12 * np.max(p))
    i2 = active[-1]
    i1 = i2 - 1
    while i1 > 0 and x[i1] >= x[i2] - 1e-12:
        i1 -= 1
    q1, q2 = p[i1] ** 2, p[i2] ** 2
    return float(math.sqrt((q1 * x[i2] ** 2 - q2 * x[i1] ** 2) / (q1 - q2)))


def _tag_curves(gmsh: typing.Any, groups: dict[int, list[int]]) -> None:
    for tag, curves in groups.items():
        gmsh.model.addPhysicalGroup(1, curves, tag)


def quarter_disk(comm: MPI.Comm, R: float, h: float, degree: int) -> tuple:
    """The quarter disk x >= 0, y <= R about (0, R), size h near the origin (Gmsh)."""
    with gmsh_session() as gmsh:
        gmsh.model.add("cylinder")
        if comm.rank == 0:
            geo = gmsh.model.geo
            centre, origin = geo.addPoint(0, R, 0), geo.addPoint(0, 0, 0)
            right, cut = (
                geo.addPoint(R, R, 0),
                geo.addPoint(R * math.sin(0.4), R - R * math.cos(0.4), 0),
            )
            arc1, arc2 = geo.addCircleArc(origin, centre, cut), geo.addCircleArc(cut, centre, right)
            top, axis = geo.addLine(right, centre), geo.addLine(centre, origin)
            surface = geo.addPlaneSurface([geo.addCurveLoop([arc1, arc2, top, axis])])
            geo.synchronize()
            gmsh.model.addPhysicalGroup(2, [surface], 1)
            _tag_curves(gmsh, {CONTACT: [arc1], LOADED: [top], SYMMETRY: [axis]})
            size_field(gmsh, origin, h, R / 8, 0.25 * R)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(degree)
        return model_to_mesh(gmsh.model, comm, 0)


def _floor(comm: MPI.Comm, width: float, depth: float, n: int) -> tuple:
    """The block [-0.05 width, width] x [-depth, 0], ``n`` cells along its top (tag TARGET)."""
    mesh = dolfinx.mesh.create_rectangle(
        comm,
        [[-0.05 * width, -depth], [width, 0.0]],
        [n, max(2, n // 4)],
        dolfinx.mesh.CellType.quadrilateral,
    )
    top = dolfinx.mesh.locate_entities_boundary(mesh, 1, lambda x: np.isclose(x[1], 0.0))
    bottom = dolfinx.mesh.locate_entities_boundary(mesh, 1, lambda x: np.isclose(x[1], -depth))
    facets = np.concatenate([top, bottom]).astype(np.int32)
    values = np.concatenate([np.full(top.size, TARGET), np.full(bottom.size, CLAMPED)])
    order = np.argsort(facets)
    tags = dolfinx.mesh.meshtags(mesh, 1, facets[order], values[order].astype(np.int32))
    return mesh, tags


def _solve(a, L, pairs, bcs, *, prefix, unilateral=True, upto=math.inf):
    """Solve (unilateral by default); the pressure, its force, unknowns and time."""
    from dolfinx_contact_s2s.problem import LinearContactProblem
    from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

    comm = pairs[0].contactor.comm
    comm.Barrier()
    begin = time.perf_counter()
    cls = UnilateralContactProblem if unilateral else LinearContactProblem
    with cls(a, L, pairs, bcs, petsc_options_prefix=prefix) as problem:
        _, multipliers = problem.solve() if not unilateral else problem.solve([1.0])
        seconds = comm.bcast(time.perf_counter() - begin, root=0)
        unknowns = sum(
            V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces
        )
        unknowns += sum(p.Q.dofmap.index_map.size_global for p in pairs)
        x, p, force = pressure(multipliers[0], upto)
    return RigidResult(x, p, force, unknowns, seconds)


def hertz_on_plane(
    comm: MPI.Comm,
    *,
    F: float,
    R: float = 1.0,
    h: float = 0.01,
    degree: int = 2,
    material: Material = Material(1.0, 0.3),  # noqa: B008
    target: str = "rigid",
    target_E: float = 1e6,
) -> RigidResult:
    r"""An elastic cylinder (plane strain) pressed by :math:`F` per unit length on a floor.

    Args:
        comm: Communicator.
        F: Force per unit length on the whole cylinder (:math:`F/2` on the half model).
        R: Radius.
        h: Element size within :math:`R/4` of the contact point (grows to :math:`R/8`).
        degree: Displacement degree (and geometry degree, curved arcs).
        material: The cylinder's material.
        target: ``"rigid"`` (a meshed rigid floor), ``"plane"`` (analytic) or
            ``"elastic"`` (the same floor mesh, Young's modulus ``target_E``, clamped
            at its bottom).
        target_E: Young's modulus of the elastic floor.
    """
    mesh, _, tags = quarter_disk(comm, R, h, degree)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a_form, _, v = material.forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    traction = dolfinx.fem.Constant(mesh, np.array([0.0, -F / (2 * R)]))
    L = [ufl.inner(traction, v) * ds(LOADED)]
    a = [a_form]
    axis = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, tags.find(SYMMETRY))
    bcs = [dolfinx.fem.dirichletbc(0.0, axis, V.sub(0))]
    contactor = contact_surface(V, tags, CONTACT)
    if target == "plane":
        floor = plane_obstacle([0.0, 0.0], [0.0, 1.0])
    else:
        fmesh, ftags = _floor(comm, 0.4 * R, 0.4 * R, 24)
        if target == "rigid":
            floor = rigid_surface(fmesh, ftags, TARGET)
        else:
            W = dolfinx.fem.functionspace(fmesh, ("Lagrange", 1, (2,)))
            aw, _, w = Material(target_E, material.nu).forms(W)
            zero = dolfinx.fem.Constant(fmesh, np.zeros(2))
            a.append(aw)
            L.append(ufl.inner(zero, w) * ufl.dx)
            clamped = dolfinx.fem.locate_dofs_topological(W, 1, ftags.find(CLAMPED))
            bcs.append(dolfinx.fem.dirichletbc(np.zeros(2), clamped, W))
            floor = contact_surface(W, ftags, TARGET)
    pair = contact_pair(contactor, floor)
    return _solve(a, L, [pair], bcs, prefix=f"hertz_{target}_")


def _layer(comm: MPI.Comm, W: float, D: float, a: float, h: float, degree: int) -> tuple:
    """The layer [0, W] x [0, D], size h within 1.2 a of the origin (Gmsh)."""
    with gmsh_session() as gmsh:
        gmsh.model.add("layer")
        if comm.rank == 0:
            geo = gmsh.model.geo
            # A node at the punch's corner x = a (known geometry, not the answer).
            p = [geo.addPoint(*xy, 0) for xy in ((0, 0), (a, 0), (W, 0), (W, D), (0, D))]
            lines = [geo.addLine(p[i], p[(i + 1) % 5]) for i in range(5)]
            surface = geo.addPlaneSurface([geo.addCurveLoop(lines)])
            geo.synchronize()
            gmsh.model.addPhysicalGroup(2, [surface], 1)
            groups = {CONTACT: lines[:2], LOADED: [lines[3]], SYMMETRY: [lines[4]]}
            _tag_curves(gmsh, groups)
            size_field(gmsh, p[0], h, max(W, D) / 10, 1.2 * a)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(degree)
        return model_to_mesh(gmsh.model, comm, 0)


def flat_punch(
    comm: MPI.Comm,
    *,
    F: float = 1.0,
    a: float = 1.0,
    width: float = 20.0,
    depth: float = 20.0,
    elements_under: int = 40,
    degree: int = 1,
    material: Material = Material(1.0, 0.3),  # noqa: B008
) -> RigidResult:
    r"""An elastic layer pressed by :math:`F` (per unit length) onto a rigid flat punch.

    Args:
        comm: Communicator.
        F: Total force on the whole layer (:math:`F/2` on the half model).
        a: The punch's half-width.
        width: The half layer's width :math:`W` (in units of the length, not of a).
        depth: The layer's depth :math:`D`.
        elements_under: About how many elements span the punch's width :math:`2a`.
        degree: Displacement degree.
        material: The layer's material.
    """
    mesh, _, tags = _layer(comm, width, depth, a, 2 * a / elements_under, degree)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a_form, _, v = material.forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    traction = dolfinx.fem.Constant(mesh, np.array([0.0, -F / (2 * width)]))
    L = ufl.inner(traction, v) * ds(LOADED)
    axis = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, tags.find(SYMMETRY))
    bcs = [dolfinx.fem.dirichletbc(0.0, axis, V.sub(0))]
    # The punch: a rigid block [0, a] x [-a, 0] under the layer; its top is the target.
    pmesh = dolfinx.mesh.create_rectangle(
        comm, [[0.0, -a], [a, 0.0]], [7, 3], dolfinx.mesh.CellType.triangle
    )
    top = dolfinx.mesh.locate_entities_boundary(pmesh, 1, lambda x: np.isclose(x[1], 0.0))
    ptags = dolfinx.mesh.meshtags(
        pmesh, 1, np.sort(top).astype(np.int32), np.full(top.size, TARGET, np.int32)
    )
    punch = rigid_surface(pmesh, ptags, TARGET)
    pair = contact_pair(contact_surface(V, tags, CONTACT), punch)
    return _solve([a_form], [L], [pair], bcs, prefix="punch_", upto=a)

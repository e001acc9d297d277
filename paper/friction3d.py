# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The friction scenes of issue [4/6] in 3D, shared by ``tests/friction`` and the demo.

- :func:`patch`: the frictional patch tests (below).
- :func:`inclined_block`: a block pushed up a slope :math:`\tan\alpha = 0.1` with
  :math:`\mu = 0.5`, all of it sliding: the reaction's ratio
  :math:`(\mu + \tan\alpha)/(1 - \mu\tan\alpha)`, on a tilted contact plane.
- :func:`extruded`: a partial-slip scene in 2D and the same scene extruded by one layer
  of hexahedra with :math:`u_z = 0` (plane strain): the 3D discrete problem is the 2D
  one times the layer's integrals, so the 3D multipliers equal the 2D ones node by node.
- :func:`cattaneo_mindlin`: two identical spheres (:math:`R = 1`, :math:`E = 1`,
  :math:`\nu = 0.3`; the half model :math:`y \ge 0` of :func:`paper.hertz3d.mesh`), the
  upper flat face moved down in one frictionless step (frictionless linear contact
  does not depend on the path), then along :math:`x` in four steps (or ``steps``) with
  :math:`\mu = 0.2`: the stick radius :math:`c = a (1 - Q/(\mu P))^{1/3}` and
  Mindlin's shear :math:`q(r) = \mu p_0/a [\sqrt{a^2 - r^2} - \sqrt{c^2 - r^2}]_+`
  against :math:`\lambda_t`. Identical bodies: the normal and tangential problems
  decouple. Mindlin takes the shear along :math:`Q` everywhere; with :math:`\nu > 0` the
  slip in the annulus is not quite along it, so his solution is itself approximate
  there (Johnson, Contact Mechanics, sec. 7.2); at ``nu=0`` Cerruti's kernel is
  isotropic and it is exact.
  :func:`cattaneo_mindlin_adaptive`: the same from a user's mesh refined by the solution
  around the contact and stick fronts.

The frictional patch test in 3D: the blocks of :mod:`paper.blocks3d` (:math:`[0, 1]^2
\times [0, 1/2]` and :math:`[0, 1]^2 \times [1/2, 1]`, meshed independently, tetrahedra or
hexahedra, optionally with the nodes moved at random in the plane of the contact) in the
uniform stress :math:`\sigma_{zz} = -p`, :math:`\sigma_{xz} = \tau_x`,
:math:`\sigma_{yz} = \tau_y` (the others zero), loaded by :math:`\sigma \mathbf n` on
every face but the contact, with

.. math:: u_x = \frac{\nu p}{E} x + \frac{\tau_x}{G} z + c_x, \quad
    u_y = \frac{\nu p}{E} y + \frac{\tau_y}{G} z + c_y, \quad u_z = -\frac{p}{E} z,

:math:`\mathbf c = 0` in the lower block, which is held by :math:`u_z = 0` on its bottom,
:math:`u_x = u_y = 0` at the origin and :math:`u_y = 0` at :math:`(1, 0, 0)` (all three
true of the state). Nothing but friction holds the upper block tangentially. Stick: the
shear :math:`|\tau| < \mu p` on the top: :math:`\mathbf c = 0`, :math:`\lambda_n = p` and
the shear the upper block (the contactor) exerts on the lower one is
:math:`(\tau_x, \tau_y)`. Slip: the top's tangential motion prescribed as the state's
plus :math:`\mathbf d` beyond the stick limit: :math:`\mathbf c = \mathbf d` and
:math:`\tau = \mu p\, \mathbf d / |\mathbf d|`.
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

from dolfinx_contact_s2s import Material, contact_front, contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.kernels.face_backend import tangents
from paper import hertz3d
from paper.blocks3d import BOTTOM, SIDE_X, TOP, block
from paper.friction_adaptive import refined_load_path
from paper.hertz3d_study import surface_l2

__all__ = [
    "CM_MU",
    "CM_SCENE",
    "NU",
    "E",
    "cattaneo_mindlin",
    "cattaneo_mindlin_adaptive",
    "cattaneo_mindlin_measure",
    "cattaneo_mindlin_model",
    "cattaneo_mindlin_path",
    "extruded",
    "extruded_scene",
    "inclined_block",
    "patch",
]

E, NU = 1.0, 0.3
G = E / (2 * (1 + NU))

#: Cattaneo-Mindlin: two identical spheres; mu, the approach of the flat faces (a about
#: 0.05) and their relative motion along x (Q / (mu P) about one half).
CM_SCENE = hertz3d.Scene(1.0, 1.0, 1.0, 1.0, False, (Material(E, NU),) * 2, 0.0, False)
CM_MU, CM_DELTA, CM_SHIFT = 0.2, 0.005, 4.5e-4


def _exact(p: float, tau: tuple[float, float], c: tuple[float, float]) -> typing.Callable:
    return lambda x: np.stack(
        [
            NU * p / E * x[0] + tau[0] / G * x[2] + c[0],
            NU * p / E * x[1] + tau[1] / G * x[2] + c[1],
            -p / E * x[2],
        ]
    )


def _vertex_dofs(V: dolfinx.fem.FunctionSpace, point: tuple[float, ...], component: int):
    mesh = V.mesh
    found = dolfinx.mesh.locate_entities_boundary(
        mesh, 0, lambda x: np.all(np.isclose(x, np.reshape(point, (3, 1))), axis=0)
    )
    return dolfinx.fem.locate_dofs_topological(V.sub(component), 0, found)


def patch(
    case: str,
    cells: tuple[str, str] = ("tet", "hex"),
    degree: int = 1,
    seed: int | None = None,
    n: tuple[int, int] = (3, 4),
    axis: typing.Sequence[float] | None = None,
    contactor: str = "upper",
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> dict[str, typing.Any]:
    r"""Solve the 3D frictional patch test ``case`` ("stick" or "slip") against its exact state.

    Stick: :math:`p = 1`, :math:`\tau = (0.2, 0.1)`, :math:`\mu = 0.5`. Slip:
    :math:`\mu = 0.3`, the top moved by :math:`\mathbf d = 0.2 (\cos 30^\circ,
    \sin 30^\circ)`, :math:`\tau = \mu p\, \mathbf d / |\mathbf d|`.

    Returns:
        A record: the largest errors of :math:`\lambda_n` (against :math:`p`),
        :math:`\lambda_t` (against the components of :math:`\pm\tau` along
        :math:`\mathbf T_1, \mathbf T_2` of the pair's tangent axis) relative to
        :math:`|\tau|`, of the displacement relative to its largest value, the sets of the
        last iteration, the solves and the unknowns.
    """
    p = 1.0
    if case == "stick":
        mu, tau, d = 0.5, (0.2, 0.1), (0.0, 0.0)
    else:
        mu, d = 0.3, (0.2 * np.cos(np.pi / 6), 0.2 * np.sin(np.pi / 6))
        tau = (mu * p * np.cos(np.pi / 6), mu * p * np.sin(np.pi / 6))
    sigma = ufl.as_matrix([[0.0, 0.0, tau[0]], [0.0, 0.0, tau[1]], [tau[0], tau[1], -p]])
    spaces, a, L, bcs = [], [], [], []
    for z0, cells_across, cell, upper in (
        (0.0, n[0], cells[0], False),
        (0.5, n[1], cells[1], True),
    ):
        mesh, tags = block(z0, cells_across, cell, seed, comm=comm)
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
        form, _, v = Material(E=E, nu=NU).forms(V)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
        traction = ufl.dot(sigma, ufl.FacetNormal(mesh))
        contact = BOTTOM if upper else TOP
        a.append(form)
        L.append(ufl.inner(traction, v) * ds - ufl.inner(traction, v) * ds(contact))
        if not upper:
            bottom = dolfinx.fem.locate_dofs_topological(V.sub(2), 2, tags.find(BOTTOM))
            pins = [(bottom, 2), (_vertex_dofs(V, (0, 0, 0), 0), 0)]
            pins += [(_vertex_dofs(V, (0, 0, 0), 1), 1), (_vertex_dofs(V, (1, 0, 0), 1), 1)]
            bcs += [dolfinx.fem.dirichletbc(0.0, dofs, V.sub(k)) for dofs, k in pins]
        elif case == "slip":
            for k in (0, 1):
                Vk, _ = V.sub(k).collapse()
                g = dolfinx.fem.Function(Vk)
                g.interpolate(lambda x, k=k: _exact(p, tau, d)(x)[k])
                dofs = dolfinx.fem.locate_dofs_topological((V.sub(k), Vk), 2, tags.find(TOP))
                bcs.append(dolfinx.fem.dirichletbc(g, dofs, V.sub(k)))
        spaces.append((V, tags, contact))
    surfaces = [contact_surface(V, tags, tag) for V, tags, tag in spaces]
    first, second = (surfaces[1], surfaces[0]) if contactor == "upper" else surfaces
    pair = contact_pair(first, second, multiplier=("Lagrange", degree))
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=mu, tangent_axis=axis, petsc_options_prefix="fr3_"
    ) as problem:
        us, (lam_n,), lam_t = problem.solve()
        normal = np.array([[0.0, 0.0, 1.0 if contactor == "upper" else -1.0]])
        axis_used = problem.tangent_axes[0]
        # The shear the contactor exerts on the target: tau from the upper block.
        shear = np.array([tau[0], tau[1], 0.0]) * (1.0 if contactor == "upper" else -1.0)
        expected = [float(shear @ tangents(normal, axis_used, k)[0]) for k in (1, 2)]
        owned = pair.Q.dofmap.index_map.size_local

        def worst(values):
            return comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)

        u_error, u_size = 0.0, 0.0
        for (V, _, _), u, c in zip(spaces, us, ((0.0, 0.0), d), strict=True):
            reference = dolfinx.fem.Function(V)
            reference.interpolate(_exact(p, tau, c))
            u_error = max(u_error, worst(u.x.array - reference.x.array))
            u_size = max(u_size, worst(reference.x.array))
        last = problem.history.steps[-1].iterations[-1]
        return {
            "case": case,
            "cells": "-".join(cells),
            "degree": degree,
            "seed": seed,
            "contactor": contactor,
            "axis": [float(t) for t in axis_used],
            "lambda_n_error": worst(lam_n.x.array[:owned] - p) / p,
            "lambda_t_error": max(
                worst(f.x.array[:owned] - e) for f, e in zip(lam_t, expected, strict=True)
            )
            / float(np.hypot(*tau)),
            "u_error": u_error / u_size,
            "converged": bool(problem.history.steps[-1].converged),
            "multipliers": pair.Q.dofmap.index_map.size_global,
            "active": int(last.active[0]),
            "stick": int(last.stick[0]),
            "solves": problem.history.iterations,
            "unknowns": sum(V.dofmap.index_map.size_global * 3 for V, _, _ in spaces)
            + 3 * pair.Q.dofmap.index_map.size_global,
        }


def _owned_nodes(f: dolfinx.fem.Function) -> tuple[np.ndarray, int]:
    Q = f.function_space
    n = Q.dofmap.index_map.size_local
    return Q.tabulate_dof_coordinates()[:n], n


def cattaneo_mindlin_model(
    mesh: dolfinx.mesh.Mesh, tags: dolfinx.mesh.MeshTags, degree: int, nu: float = NU
) -> tuple:
    """The forms, conditions, pair and the upper face's motion of :func:`cattaneo_mindlin`.

    On the half model of :func:`paper.hertz3d.mesh` (or a refinement of it): the lower
    far face clamped, :math:`u_y = 0` on the symmetry plane, the upper flat face moved by
    the returned function; P``degree`` displacements, the P1 multiplier on the lower
    sphere's cap; Poisson's ratio ``nu``.
    """
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
    form, _, v = Material(E=E, nu=nu).forms(V)
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.zeros(3)), v) * ufl.dx
    motion = dolfinx.fem.Function(V)
    mesh.topology.create_connectivity(2, 3)
    top = dolfinx.fem.locate_dofs_topological(V, 2, tags.find(hertz3d.TAGS["upper_flat"]))
    far_face = dolfinx.fem.locate_dofs_topological(V, 2, tags.find(hertz3d.TAGS["lower_far"]))
    symmetry = dolfinx.fem.locate_dofs_topological(V.sub(1), 2, tags.find(hertz3d.SYM_Y))
    bcs = [
        dolfinx.fem.dirichletbc(motion, top),
        dolfinx.fem.dirichletbc(dolfinx.fem.Function(V), far_face),
        dolfinx.fem.dirichletbc(0.0, symmetry, V.sub(1)),
    ]
    pair = contact_pair(
        contact_surface(V, tags, hertz3d.TAGS["lower_top"]),
        contact_surface(V, tags, hertz3d.TAGS["upper_sphere"]),
        multiplier=("Lagrange", 1),
    )
    return form, L, bcs, pair, motion


def cattaneo_mindlin_path(
    problem: FrictionalContactProblem,
    motion: dolfinx.fem.Function,
    first: list | None = None,
    steps: int = 4,
) -> list[int]:
    """The load path: the upper face moved down in one frictionless step, then along x.

    Frictionless linear contact does not depend on the path to its load: one step
    (from ``first``, the first active set of ``solve(active=...)``, if given). The
    tangential motion in ``steps`` equal steps: under a monotonic tangential load the
    stick zone only shrinks and the slips point along +x, so the end of the path hardly
    depends on them (one step against four, h = 0.014, nu = 0: the shear differs by
    8.8e-5 of its peak, from the slip directions' small turns over the path). Returns
    the linear solves of every step.
    """
    motion.interpolate(lambda x: np.stack([0 * x[0], 0 * x[0], -CM_DELTA + 0 * x[0]]))
    problem.solve([1.0], mu=0.0, active=first)
    solves = [len(s.iterations) for s in problem.history.steps]
    for k in range(1, steps + 1):
        motion.interpolate(
            lambda x, k=k: np.stack(
                [0 * x[0] + k * CM_SHIFT / steps, 0 * x[0], -CM_DELTA + 0 * x[0]]
            )
        )
        problem.solve([1.0], restart=False)
        solves += [len(s.iterations) for s in problem.history.steps]
    return solves


def cattaneo_mindlin_measure(
    problem: FrictionalContactProblem, h: float | None = None, nu: float = NU
) -> dict[str, typing.Any]:
    r"""The record of :func:`cattaneo_mindlin` from a solved problem (collective).

    ``h`` is the element size at the contact; ``None`` takes the longest multiplier edge
    that crosses the stick front (a locally refined mesh). ``c`` is the largest distance
    from the axis of a sticking node, ``c_middle`` the middle of the stick front's
    bracket (:func:`~dolfinx_contact_s2s.contact_front` of the stick set), ``a_middle``
    that of the contact front.
    """
    comm, (pair,) = problem.comm, problem.pairs
    (lam_n,), lam_t = problem.multipliers, problem.tangential
    # The shear along x from the components along T1, T2 at each node (the lower
    # sphere's normal there), with the sign of the force on the upper sphere.
    x, n = _owned_nodes(lam_n)
    centre = np.array([0.0, 0.0, -CM_SCENE.R2])
    N = -(x - centre) / np.linalg.norm(x - centre, axis=1)[:, None]
    axis = problem.tangent_axes[0]
    shear = sum(
        f.x.array[:n, None] * tangents(N, axis, k) for k, f in zip((1, 2), lam_t, strict=True)
    )
    q = dolfinx.fem.Function(lam_n.function_space)
    q.x.array[:n] = -shear[:, 0]
    q.x.scatter_forward()
    stick = problem.stick[0].x.array[:n] > 0.5
    V = pair.contactor.V
    unknowns = 3 * V.dofmap.index_map.size_global + 3 * pair.Q.dofmap.index_map.size_global
    fronts = [
        contact_front(f, f, centre=(0, 0, 0), axis=(0, 0, 1))
        for f in (problem.stick[0], problem.active[0])
    ]

    def total(f):
        local = dolfinx.fem.assemble_scalar(dolfinx.fem.form(f * ufl.dx))
        return 2 * comm.allreduce(local, op=MPI.SUM)

    P, Q = total(lam_n), total(q)
    E_star, R_star = E / (2 * (1 - nu**2)), CM_SCENE.R1 / 2
    a = (3 * P * R_star / (4 * E_star)) ** (1 / 3)
    p0 = 3 * P / (2 * math.pi * a**2)
    c_exact = a * (1 - Q / (CM_MU * P)) ** (1 / 3)

    def mindlin(y):
        r2 = y[..., 0] ** 2 + y[..., 1] ** 2
        root = np.sqrt(np.clip(a**2 - r2, 0, None)) - np.sqrt(np.clip(c_exact**2 - r2, 0, None))
        return CM_MU * p0 / a * root

    def hertz(y):
        return p0 * np.sqrt(np.clip(1 - (y[..., 0] ** 2 + y[..., 1] ** 2) / a**2, 0, None))

    q_l2, p_l2 = surface_l2(q, mindlin), surface_l2(lam_n, hertz)
    r = np.hypot(x[:, 0], x[:, 1])
    c = comm.allreduce(float(r[stick].max(initial=0.0)), op=MPI.MAX)
    if h is None:
        h = float(fronts[0].edge_lengths.max())
    gathered = [np.concatenate(comm.allgather(v)) for v in (r, q.x.array[:n], lam_n.x.array[:n])]
    return {
        "scene": "cattaneo-mindlin-3d",
        "h": h,
        "across": 2 * a / h,
        "P": P,
        "Q": Q,
        "Q_over_muP": Q / (CM_MU * P),
        "a": a,
        "p0": p0,
        "c_exact": c_exact,
        "c": c,
        "c_error_elements": abs(c - c_exact) / h,
        "c_error": abs(c - c_exact) / c_exact,
        "c_middle": fronts[0].middle,
        "c_bracket": fronts[0].bounds,
        "c_middle_error": abs(fronts[0].middle - c_exact) / c_exact,
        "a_middle": fronts[1].middle,
        "q_L2_error": math.sqrt(q_l2[0] / q_l2[1]),
        "p_L2_error": math.sqrt(p_l2[0] / p_l2[1]),
        "unknowns": unknowns,
        "r": gathered[0],
        "q": gathered[1],
        "p": gathered[2],
    }


def cattaneo_mindlin(
    comm: MPI.Comm,
    degree: int = 2,
    h: float = 0.01,
    reach: float = 0.1,
    *,
    far: float | None = None,
    nu: float = NU,
    steps: int = 4,
) -> dict[str, typing.Any]:
    r"""Cattaneo-Mindlin between two identical spheres: tetrahedra of size ``h`` near the contact.

    ``h`` within ``reach`` of the touching point, grading to ``far``
    (:func:`paper.hertz3d.mesh`): sizes from the geometry, not from :math:`a` or
    :math:`c`. P``degree`` displacements (geometry of the same degree), the P1 multiplier
    on the lower sphere's cap. :math:`P` and :math:`Q` are twice the integrals of
    :math:`\lambda_n` and of the shear along :math:`x` over the half model; Hertz with
    :math:`R^* = R/2` and :math:`E^* = E / (2(1 - \nu^2))` gives :math:`a` and :math:`p_0`
    from :math:`P`, and :math:`c = a (1 - Q/(\mu P))^{1/3}`. The measured :math:`c` is the
    largest distance from the axis of a sticking multiplier node. Poisson's ratio ``nu``
    (Mindlin's solution is exact at 0); the tangential motion in ``steps`` steps.

    Returns:
        The record of :func:`cattaneo_mindlin_measure` with ``degree``, ``nu``,
        ``solves_per_step`` and ``seconds``.
    """
    begin = time.perf_counter()
    mesh, _, tags = hertz3d.mesh(
        comm, CM_SCENE, h=h, reach=reach, far=far, geometry_degree=degree, half=True
    )
    form, L, bcs, pair, motion = cattaneo_mindlin_model(mesh, tags, degree, nu)
    with FrictionalContactProblem(
        form, L, [pair], bcs, mu=CM_MU, petsc_options_prefix=f"cm3d{degree}_"
    ) as problem:
        solves = cattaneo_mindlin_path(problem, motion, steps=steps)
        record = cattaneo_mindlin_measure(problem, h, nu)
    record.update(
        degree=degree,
        nu=nu,
        solves_per_step=solves,
        seconds=comm.allreduce(time.perf_counter() - begin, op=MPI.MAX),
    )
    return record


def cattaneo_mindlin_adaptive(
    comm: MPI.Comm,
    degree: int = 2,
    n: int = 40,
    *,
    tolerance: float = 0.1,
    max_steps: int = 3,
    nu: float = NU,
    steps: int = 4,
    petsc_options: dict[str, typing.Any] | None = None,
    **options: typing.Any,
) -> dict[str, typing.Any]:
    r""":func:`cattaneo_mindlin` from a user's mesh (size :math:`R/n`), refined by the solution.

    :func:`~dolfinx_contact_s2s.unilateral.adaptive.refine_contact_zone` around the
    :math:`z`-axis until the brackets of the contact front and the stick front are at
    most ``tolerance`` times their radii (or ``max_steps`` refinements): new nodes on the
    spheres (:func:`paper.hertz3d.projection`), geometry of degree ``degree``;
    ``options`` go to it (e.g. ``pressure_tolerance``). ``nu`` and ``steps`` as in
    :func:`cattaneo_mindlin`; ``petsc_options`` to every problem's linear solves (MUMPS
    out of core, ``{"mat_mumps_icntl_22": 1}``, where the factors outgrow the memory).

    Returns:
        The record of :func:`cattaneo_mindlin_measure` on the last mesh (``h`` the
        longest multiplier edge across the stick front), with ``steps`` (unknowns,
        widest relative bracket, the errors, solves and seconds of every solve) and
        ``resolved`` (False: the brackets were still wider than ``tolerance`` after
        ``max_steps`` refinements).
    """
    begin = time.perf_counter()
    mesh, ct, ft = hertz3d.mesh(
        comm, CM_SCENE, h=CM_SCENE.R1 / n, reach=0.1, geometry_degree=1, half=True
    )
    record = refined_load_path(
        lambda domain, tags: cattaneo_mindlin_model(domain, tags, degree, nu),
        lambda problem, motion, first: cattaneo_mindlin_path(problem, motion, first, steps),
        lambda problem: cattaneo_mindlin_measure(problem, nu=nu),
        ("unknowns", "across", "c_middle_error", "q_L2_error", "p_L2_error"),
        (mesh, ct, ft),
        mu=CM_MU,
        prefix=f"cm3da{degree}_",
        petsc_options=petsc_options,
        tolerance=tolerance,
        max_steps=max_steps,
        snap=hertz3d.projection(CM_SCENE),
        geometry_degree=degree,
        axis=((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
        **options,
    )
    record.update(
        scene="cattaneo-mindlin-3d-adaptive",
        degree=degree,
        nu=nu,
        n=n,
        tolerance=tolerance,
        seconds=comm.allreduce(time.perf_counter() - begin, op=MPI.MAX),
    )
    return record


def extruded_scene(
    gdim: int, degree: int, comm: MPI.Comm = MPI.COMM_WORLD, plane_strain: bool = True
) -> tuple[list, list, list, typing.Any, list]:
    """The forms, conditions, pair and spaces of :func:`extruded`'s scene."""
    cell = dolfinx.mesh.CellType.quadrilateral if gdim == 2 else dolfinx.mesh.CellType.hexahedron
    spaces, forms, bcs = [], [], []
    for box, n, fixed, top in (
        (((0.0, 0.0), (1.0, 0.5)), (6, 3), True, False),
        (((0.2, 0.5), (0.8, 1.0)), (5, 3), False, True),
    ):
        if gdim == 2:
            mesh = dolfinx.mesh.create_rectangle(comm, box, n, cell)
        else:
            corners = [(*box[0], 0.0), (*box[1], 0.25)]
            mesh = dolfinx.mesh.create_box(comm, corners, (*n, 1), cell)
        fdim = gdim - 1
        facets = [
            dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x, y=y: np.isclose(x[1], y))
            for y in (box[0][1], box[1][1])
        ]
        indices = np.concatenate(facets)
        values = np.concatenate(
            [np.full(f.size, t, np.int32) for f, t in zip(facets, (1, 2), strict=True)]
        )
        order = np.argsort(indices)
        tags = dolfinx.mesh.meshtags(mesh, fdim, indices[order], values[order])
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (gdim,)))
        form, _, v = Material(E=E, nu=NU).forms(V)
        forms.append((form, ufl.inner(dolfinx.fem.Constant(mesh, np.zeros(gdim)), v) * ufl.dx))
        mesh.topology.create_connectivity(fdim, gdim)
        if fixed:
            dofs = dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(1))
            bcs.append(dolfinx.fem.dirichletbc(np.zeros(gdim), dofs, V))
        if top:
            held = ((0, 0.004), (1, -0.01)) + (((2, 0.0),) if gdim == 3 else ())
            for k, value in held:
                dofs = dolfinx.fem.locate_dofs_topological(V.sub(k), fdim, tags.find(2))
                bcs.append(dolfinx.fem.dirichletbc(value, dofs, V.sub(k)))
        if gdim == 3 and plane_strain:
            mesh.topology.create_connectivity(3, 3)
            cells = np.arange(mesh.topology.index_map(3).size_local, dtype=np.int32)
            every = dolfinx.fem.locate_dofs_topological(V.sub(2), 3, cells)
            bcs.append(dolfinx.fem.dirichletbc(0.0, every, V.sub(2)))
        spaces.append((V, tags))
    (V_lo, t_lo), (V_up, t_up) = spaces
    pair = contact_pair(
        contact_surface(V_up, t_up, 1),
        contact_surface(V_lo, t_lo, 2),
        multiplier=("Lagrange", degree),
    )
    return [f for f, _ in forms], [f for _, f in forms], bcs, pair, spaces


def extruded(
    gdim: int,
    degree: int,
    comm: MPI.Comm = MPI.COMM_WORLD,
    mu: float = 0.3,
    plane_strain: bool = True,
    loads: typing.Sequence[float] = (0.5, 1.0),
) -> dict[str, typing.Any]:
    r"""A punch-like partial-slip scene in 2D (quadrilaterals) or extruded (hexahedra).

    The lower block :math:`[0, 1] \times [0, 1/2]` (6 x 3 cells, its bottom clamped), the
    narrower upper block :math:`[0.2, 0.8] \times [1/2, 1]` (5 x 3 cells, its top moved
    by :math:`(0.004, -0.01)` in two steps, :math:`u_z = 0` there in 3D), both
    P``degree`` (Q), one mesh each; in 3D each block is one layer of thickness 1/4 along
    :math:`z` with :math:`u_z = 0` everywhere (``plane_strain``; else :math:`u_z` is free
    but on the top and bottom: a slab). The contactor is
    the upper block's bottom, the multiplier of degree ``degree``; ``loads`` the factors
    of the top's motion.

    Returns:
        Every multiplier node (gathered, every rank): ``x`` (its coordinates),
        ``pressure``, ``shear`` (along :math:`x`, from the contactor on the target) and
        ``normal_shear`` (along :math:`z`, 3D), ``stick`` and ``active``, and the
        tangential components of :math:`\lambda_t` and of :math:`\mathbf B_t
        \mathbf U` (``traction``, ``slip``, ``(n, gdim - 1)``); the ``sets`` of every
        iteration.
    """
    a, L, bcs, pair, spaces = extruded_scene(gdim, degree, comm, plane_strain)
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=mu, petsc_options_prefix=f"ext{gdim}_"
    ) as problem:
        us, (lam_n,), lam_t = problem.solve(loads)
        x, n = _owned_nodes(lam_n)
        slips = []
        for k in range(1, gdim):
            op = assemble_coupling(pair, k, None if gdim == 2 else problem.tangent_axes[0])
            s = op.G.duplicate()
            s.set(0.0)
            for V, B in op.blocks:
                B.multAdd(us[[W for W, _ in spaces].index(V)].x.petsc_vec, s, s)
            slips.append(s.array_r.copy())
            for obj in (s, op):
                obj.destroy()
        if gdim == 2:
            shear, across = lam_t[0].x.array[:n], np.zeros(n)
        else:
            N = np.tile([0.0, 1.0, 0.0], (n, 1))  # -n_C of the upper block's bottom
            axis = problem.tangent_axes[0]
            vector = sum(
                f.x.array[:n, None] * tangents(N, axis, k)
                for k, f in zip((1, 2), lam_t, strict=True)
            )
            shear, across = vector[:, 0], vector[:, 2]
        values = (
            x[:, :gdim],
            lam_n.x.array[:n],
            shear,
            across,
            problem.stick[0].x.array[:n] > 0.5,
            problem.active[0].x.array[:n] > 0.5,
            np.stack([f.x.array[:n] for f in lam_t], axis=1),
            np.stack(slips, axis=1),
        )
        names = ("x", "pressure", "shear", "normal_shear", "stick", "active", "traction", "slip")
        out = {k: np.concatenate(comm.allgather(v)) for k, v in zip(names, values, strict=True)}
        out["sets"] = [
            [(it.active, it.stick) for it in s.iterations] for s in problem.history.steps
        ]
    return out


def inclined_block(
    comm: MPI.Comm,
    degree: int,
    *,
    tan: float = 0.1,
    mu: float = 0.5,
    cells: tuple[str, str] = ("tet", "hex"),
) -> dict[str, typing.Any]:
    r"""A block pushed up a slope in 3D, all of it sliding: the reaction's ratio.

    The blocks of :func:`paper.blocks3d.block` (3 and 4 across), sheared by
    :math:`z \mapsto z + x \tan\alpha`: the contact plane rises along :math:`x`. The lower
    block is clamped at its bottom; the upper one is pressed by a vertical load :math:`V`
    on its top and pushed by :math:`u_x = 5` on its side :math:`x = 0`; :math:`u_y = 0`
    in both, so that the slip runs along the slope as the formula assumes (with
    :math:`u_y` free the two blocks' Poisson expansions differ, the slip turns by a
    little and the ratio drops by 1e-4). The multipliers along :math:`\mathbf T_2 =
    \mathbf e_y` then meet only Dirichlet dofs: they are pinned to zero. The reaction
    :math:`R_x` of the push is the residual :math:`a(u, v) - L(v)` at the pushed dofs
    (not :math:`\lambda`).

    Returns:
        A record: ``ratio`` :math:`R_x / V`, ``expected``, ``error`` (relative),
        ``sliding`` (no multiplier sticks, some active), ``solves``, ``unknowns``.
    """
    load, spaces, a, L, bcs = 0.2, [], [], [], []
    for z0, n, cell, upper in ((0.0, 3, cells[0], False), (0.5, 4, cells[1], True)):
        mesh, tags = block(z0, n, cell, None, comm=comm)
        mesh.geometry.x[:, 2] += tan * mesh.geometry.x[:, 0]
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
        form, _, v = Material(E=E, nu=NU).forms(V)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
        a.append(form)
        zero = dolfinx.fem.Constant(mesh, np.zeros(3))
        L.append(-load * v[2] * ds(TOP) if upper else ufl.inner(zero, v) * ds)
        if upper:
            push = np.setdiff1d(
                dolfinx.fem.locate_dofs_topological(V.sub(0), 2, tags.find(SIDE_X)),
                dolfinx.fem.locate_dofs_topological(V.sub(0), 2, tags.find(BOTTOM)),
            )
            bcs.append(dolfinx.fem.dirichletbc(5.0, push, V.sub(0)))
        else:
            clamp = dolfinx.fem.locate_dofs_topological(V, 2, tags.find(BOTTOM))
            bcs.append(dolfinx.fem.dirichletbc(np.zeros(3), clamp, V))
        mesh.topology.create_connectivity(3, 3)
        cells_all = np.arange(mesh.topology.index_map(3).size_local, dtype=np.int32)
        plane = dolfinx.fem.locate_dofs_topological(V.sub(1), 3, cells_all)
        bcs.append(dolfinx.fem.dirichletbc(0.0, plane, V.sub(1)))
        spaces.append((V, tags, TOP if not upper else BOTTOM))
    surfaces = [contact_surface(V, tags, tag) for V, tags, tag in spaces]
    pair = contact_pair(surfaces[1], surfaces[0], multiplier=("Lagrange", degree))
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=mu, petsc_options_prefix=f"incline3d{degree}_"
    ) as problem:
        (_, u), _, _ = problem.solve()
        last = problem.history.steps[-1].iterations[-1]
        sliding = last.active[0] > 0 and last.stick == (0,)
        solves = problem.history.iterations
        axis = problem.tangent_axes[0]
    V, tags, _ = spaces[1]
    residual = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(ufl.action(a[1], u) - L[1]))
    residual.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    owned = push[push < residual.getLocalSize()]
    reaction = comm.allreduce(float(np.sum(residual.array_r[owned])))
    residual.destroy()
    ds = ufl.Measure("ds", domain=V.mesh, subdomain_data=tags)
    V_load = comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(load * ds(TOP))))
    expected = (mu + tan) / (1 - mu * tan)
    return {
        "scene": "inclined-block-3d",
        "degree": degree,
        "ratio": reaction / V_load,
        "expected": expected,
        "error": abs(reaction / V_load - expected) / expected,
        "sliding": bool(sliding),
        "solves": solves,
        "axis": [float(t) for t in axis],
        "unknowns": sum(3 * W.dofmap.index_map.size_global for W, _, _ in spaces)
        + 3 * pair.Q.dofmap.index_map.size_global,
    }

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The Hertz study: a half cylinder pressed on a block, solved as unilateral contact.

Plane strain, both bodies linear elastic, frictionless contact with an unknown contact
area (Eq. 1). The load is a force :math:`F` per unit length, applied as a uniform
traction on the cylinder's flat top (force control), chosen so that the exact Hertz
half-width is the design half-width ``a`` of the graded mesh (:math:`a/R = 5\%` by
default: small deformation, half-space assumptions). The cylinder's top has
:math:`u_x = 0`, and so do the nodes at the contact point (the symmetry
:math:`u_x(0, y) = 0`; without it a rotation about the cylinder's centre, which slides
the arc along itself, is free); vertically the cylinder is held by contact alone,
so the active-set iteration starts from the nearest points
(:data:`~dolfinx_contact_s2s.unilateral.STARTS`). The lower body is clamped at its
bottom.

Everything is read from the multiplier :math:`\lambda` (the package's pressure field):
the peak :math:`p_0`, the half-width and the relative :math:`L^2` error over
:math:`[-a, a]` (:func:`~paper.hertz.exact.measure`). The reported
half-width ``a`` is the moment half-width :math:`2 \sqrt{\int \lambda x^2 / \int
\lambda}`, which converges with the integral of :math:`\lambda`; the edge of the support
(``a_edge``) is resolved to a fraction of an element only.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, replace
from types import SimpleNamespace

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.convergence import ConvergenceTable, convergence_study, richardson
from dolfinx_contact_s2s.elasticity import Material, epsilon
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.hertz.exact import Hertz, measure
from paper.hertz.scene import HertzScene, hertz

__all__ = [
    "LEVELS",
    "HertzCase",
    "HertzModel",
    "add_energy_error",
    "energy_reference",
    "hertz_convergence",
    "hertz_model",
    "run_case",
]

#: Elements across the contact width of the convergence studies.
LEVELS = (10, 20, 40, 80)


@dataclass(frozen=True)
class HertzCase:
    r"""One Hertz run.

    Attributes:
        method: Contact discretization (``contact_pair``'s ``method``).
        degree: Displacement degree; the segment-to-segment multiplier is continuous of
            the same degree (:math:`M^1_{h,k}`, Eq. 16), and so is the geometry.
        cell: ``"triangle"`` or ``"quadrilateral"``.
        elements_across: Elements across the contact width :math:`2a`.
        algorithm: One of :data:`~dolfinx_contact_s2s.unilateral.ALGORITHMS`.
        penalty: Factor :math:`\\kappa` of the penalty algorithms (None: the default).
        a: Design half-width (the exact one at the applied force).
        R1: Cylinder radius.
        R2: Radius of the lower cylinder; ``math.inf`` for the block.
        size: Block half-width and depth.
        upper: :math:`(E, \\nu)` of the cylinder.
        lower: :math:`(E, \\nu)` of the lower body.
        far_size: Element size far from the contact (None: the scene's default).
        edge_nodes: Mesh nodes on the arc at the exact edges :math:`x = \\pm a`
            (:func:`~paper.hertz.scene.hertz`).
    """

    method: str = "segment-to-segment"
    degree: int = 1
    cell: str = "triangle"
    elements_across: int = 20
    algorithm: str = "active-set"
    penalty: float | None = None
    a: float = 0.05
    R1: float = 1.0
    R2: float = math.inf
    size: tuple[float, float] = (1.0, 1.0)
    upper: tuple[float, float] = (1.0, 0.3)
    lower: tuple[float, float] = (1.0, 0.3)
    edge_nodes: bool = True
    far_size: float | None = None

    @property
    def multiplier(self) -> tuple[str, int] | None:
        """The multiplier space argument of ``contact_pair``."""
        return ("Lagrange", self.degree) if self.method == "segment-to-segment" else None

    @property
    def exact(self) -> Hertz:
        """The Hertz solution whose half-width is :attr:`a`."""
        return Hertz.for_half_width(self.a, *self.upper, *self.lower, self.R1, self.R2)


@dataclass
class HertzModel:
    """The forms, supports and contact pair of a Hertz case on its scene."""

    case: HertzCase
    scene: HertzScene
    V: dolfinx.fem.FunctionSpace
    a: ufl.Form
    L: ufl.Form
    bcs: list[dolfinx.fem.DirichletBC]

    def pair(self):
        """A new contact pair: the cylinder's arc against the lower body's top."""
        tags, ft = self.scene.tags, self.scene.facet_tags
        return contact_pair(
            contact_surface(self.V, ft, tags["contactor"]),
            contact_surface(self.V, ft, tags["target"]),
            method=self.case.method,
            multiplier=self.case.multiplier,
            # Node-based methods: the multiplier a pressure, comparable with Hertz.
            **({"weight": "tributary"} if self.case.method == "node-to-segment" else {}),
        )


def hertz_model(
    case: HertzCase,
    comm: MPI.Comm = MPI.COMM_WORLD,
    partitioner: Callable | None = None,
) -> HertzModel:
    """Mesh the scene of ``case`` and set up its forms and supports.

    Args:
        case: The case.
        comm: Communicator of the mesh.
        partitioner: Cell partitioner of the mesh (see
            :func:`dolfinx_contact_s2s.meshing.model_to_mesh`); None: DOLFINx's.
    """
    scene = hertz(
        comm,
        R=case.R1,
        a=case.a,
        elements_across=case.elements_across,
        cell=case.cell,
        geometry_degree=min(case.degree, 2),
        size=case.size,
        lower_radius=case.R2,
        edge_nodes=case.edge_nodes,
        far_size=case.far_size,
        partitioner=partitioner,
    )
    mesh = scene.mesh
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", case.degree, (2,)))
    # Each body its material: piecewise-constant Lamé parameters by cell tag.
    Q0 = dolfinx.fem.functionspace(mesh, ("Discontinuous Lagrange", 0))
    mu, lmbda = dolfinx.fem.Function(Q0), dolfinx.fem.Function(Q0)
    for tag, (E, nu) in ((1, case.upper), (2, case.lower)):
        cells = scene.cell_tags.find(tag)
        m, lm = Material(E, nu).lame
        mu.x.array[cells], lmbda.x.array[cells] = m, lm
    mu.x.scatter_forward()
    lmbda.x.scatter_forward()
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    sigma = 2 * mu * epsilon(u) + lmbda * ufl.tr(epsilon(u)) * ufl.Identity(2)
    a = ufl.inner(sigma, epsilon(v)) * ufl.dx
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=scene.facet_tags)
    top = scene.tags["upper_top"]
    traction = case.exact.F / (2 * case.R1)  # F spread over the flat top of width 2 R1
    L = -traction * v[1] * ds(top)
    ft, fdim = scene.facet_tags, mesh.topology.dim - 1
    bottom = dolfinx.fem.locate_dofs_topological(V, fdim, ft.find(scene.tags["lower_bottom"]))
    top_x = dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, ft.find(top))
    # A rotation about the cylinder's centre moves its arc tangentially: frictionless
    # contact does not hold it, and u_x = 0 on the top (through the centre) neither.
    # The symmetry u_x(0, y) = 0 does, imposed at the contact point's nodes.
    axis = dolfinx.mesh.locate_entities(
        mesh, 0, lambda x: np.isclose(x[0], 0) & np.isclose(x[1], 0)
    )
    mesh.topology.create_connectivity(0, mesh.topology.dim)
    on_axis = dolfinx.fem.locate_dofs_topological(V.sub(0), 0, axis)
    zero = dolfinx.default_scalar_type(0)
    bcs = [
        dolfinx.fem.dirichletbc(np.zeros(2, dtype=dolfinx.default_scalar_type), bottom, V),
        dolfinx.fem.dirichletbc(zero, top_x, V.sub(0)),
        dolfinx.fem.dirichletbc(zero, on_axis, V.sub(0)),
    ]
    return HertzModel(case, scene, V, a, L, bcs)


def run_case(
    case: HertzCase,
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    prefix: str = "hertz_",
    keep: bool = False,
) -> dict:
    """Solve one case and measure it against Hertz.

    Args:
        case: The case.
        comm: Communicator of the mesh.
        prefix: PETSc options prefix of the solve.
        keep: Also return the solution under ``"functions"``: the displacement, the
            pressure, the active set and the multiplier's dof coordinates.

    Returns:
        The record of ``results/hertz.json`` (see the issue): method, multiplier, degree,
        solver, h, elements_across, a, a_exact, a_error, p0, p0_exact, p0_error,
        pressure_l2_error, iterations, ranks, seconds, and more: the strain energy
        ``energy`` and the problem's ``timings``.
    """
    begin = time.perf_counter()
    model = hertz_model(case, comm)
    pair = model.pair()
    exact = case.exact
    with UnilateralContactProblem(
        model.a,
        model.L,
        [pair],
        model.bcs,
        petsc_options_prefix=prefix,
        algorithm=case.algorithm,
        penalty=case.penalty,
        max_iterations=200,
    ) as problem:
        (u,), (lam,) = problem.solve()
        m = measure(lam, exact)
        # Strain energy 1/2 a(u, u) of both bodies.
        energy = comm.allreduce(
            dolfinx.fem.assemble_scalar(
                dolfinx.fem.form(0.5 * ufl.action(ufl.action(model.a, u), u))
            ),
            op=MPI.SUM,
        )
        timings = dict(problem.timings)
        history = problem.history
        Q = pair.Q
        n = Q.dofmap.index_map.size_local
        x = Q.tabulate_dof_coordinates()[:n, 0]
        active_x = np.sort(np.concatenate(comm.allgather(x[problem.active[0].x.array[:n] > 0])))
        functions = (u, lam, problem.active[0]) if keep else None
    record = {
        "method": case.method,
        "multiplier": list(case.multiplier) if case.multiplier else "nodal",
        "degree": case.degree,
        "cell": case.cell,
        "solver": case.algorithm,
        "penalty": problem.penalty,
        "h": model.scene.h,
        "elements_across": case.elements_across,
        "a": m.a_moment,
        "a_exact": exact.a,
        "a_error": m.a_moment / exact.a - 1,
        "a_edge": m.a,
        "a_edge_error": m.a_error,
        "p0": m.p0,
        "p0_exact": exact.p0,
        "p0_error": m.p0_error,
        "pressure_l2_error": m.pressure_l2_error,
        "F": exact.F,
        "energy": float(energy),
        "timings": timings,
        "iterations": history.iterations,
        "active_counts": [list(it.active) for s in history.steps for it in s.iterations],
        "active_x": active_x.tolist(),
        "dofs": model.V.dofmap.index_map.size_global * 2 + Q.dofmap.index_map.size_global,
        "ranks": comm.size,
        "seconds": time.perf_counter() - begin,
        # JSON has no infinity: a flat lower body has R2 = null.
        "case": {k: (None if v == math.inf else v) for k, v in asdict(case).items()},
    }
    if keep:
        record["functions"] = functions
    return record


def hertz_convergence(
    case: HertzCase,
    levels: Sequence[int] = LEVELS,
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    log: Callable[[str], None] | None = None,
) -> tuple[ConvergenceTable, list[dict]]:
    r"""Solve ``case`` at every level and measure it against Hertz (collective).

    The whole mesh refines with the level: :math:`h = 2a/n` at the contact and
    :math:`\min(R_1, W, D) / 8 \cdot 10/n` far from it, so that the strain energy
    converges too. Errors: ``"a"``, ``"p0"`` (relative, absolute values),
    ``"pressure_l2"`` (relative, over :math:`[-a, a]`). Each record (see
    :func:`run_case`) has the strain energy under ``"energy"``; add the energy error
    with :func:`add_energy_error` once a reference is known.

    Returns:
        The table and the records of the levels.
    """
    far = min(case.R1, case.R2, *case.size) / 8.0
    runs: list[dict] = []

    def solve(n: int) -> SimpleNamespace:
        level = replace(case, elements_across=n, far_size=far * 10.0 / n)
        record = run_case(level, comm, prefix=f"hertz_conv_{n}_")
        runs.append(record)
        return SimpleNamespace(record=record, timings=record["timings"])

    def error(key: str) -> Callable[[SimpleNamespace], float]:
        return lambda s: abs(float(s.record[key]))

    table = convergence_study(
        solve,
        list(levels),
        {"a": error("a_error"), "p0": error("p0_error"), "pressure_l2": error("pressure_l2_error")},
        h=lambda s: s.record["h"],
        unknowns=lambda s: s.record["dofs"],
        name=f"Hertz, {case.method}, {case.cell}, P{case.degree}",
        comm=comm,
        log=log,
        cleanup=lambda s: None,
    )
    return table, runs


def energy_reference(runs: Sequence[dict]) -> tuple[float, float]:
    """Strain energy of the limit and its order, by Richardson from the last three runs."""
    return richardson([r["h"] for r in runs], [r["energy"] for r in runs])


def add_energy_error(table: ConvergenceTable, runs: Sequence[dict], reference: float) -> None:
    r"""Add :math:`|E - E_h| / E` as the error ``"energy"`` of every level of ``table``."""
    for level, run in zip(table.levels, runs, strict=True):
        level.errors["energy"] = abs(run["energy"] / reference - 1.0)

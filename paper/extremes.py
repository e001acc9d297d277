# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The patch test at numerical extremes, each point against its round-off bound.

Two blocks of one Gmsh model, built the way the README builds them (one mesh, the
user's own forms and Dirichlet conditions, :func:`~dolfinx_contact_s2s.contact_surface`
and :func:`~dolfinx_contact_s2s.contact_pairs`), loaded so that the exact solution is a
uniform stress (section 3.2, Eq. 36):

- ``"uniaxial"``: a unit pressure on the upper block's top; :math:`\sigma_y = -1`,
  :math:`\sigma_x = 0`, contact pressure :math:`\lambda = 1`, with any materials;
- ``"hydrostatic"``: a unit pressure on every free boundary; :math:`\sigma = -\mathbf I`
  and :math:`\lambda = 1` on an interface of any shape (the curved points) and on the
  covered part of surfaces that cover each other only in part (zero on the multipliers
  that face no target).

The exact displacements are linear (plane strain, :math:`\varepsilon_{xx} =
((1-\nu^2)\sigma_x - \nu(1+\nu)\sigma_y)/E`), so every element represents them and the
only error left is round-off: each point passes when the errors of the displacements and
of the multipliers are within :func:`~dolfinx_contact_s2s.analysis.roundoff.round_off_bound` of
its solve. A point may instead raise a clear exception (the same on every rank), which
it must then name in :attr:`ExtremePoint.expect`; anything else is a failure.

The grid (:func:`grid`): Young's modulus ratios :math:`10^{\pm 3}, 10^{\pm 6}` between
the bodies; :math:`\nu` up to 0.4999; element-size ratios up to 1:64 across the
interface; the scene scaled by :math:`10^{\pm 6}` and translated by :math:`10^6`;
initial gaps and overlaps from :math:`10^{-14}` to the element size (tied: the gap
closes with the same pressure; unilateral: contact); interface nodes :math:`10^{-11}`
to :math:`10^{-13} h` apart, with segment-to-segment and two-pass node-to-segment;
surfaces that cover each other in part; curved (quadratic geometry) interfaces.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace

from mpi4py import MPI

import dolfinx
import dolfinx.fem
import numpy as np
import ufl

from dolfinx_contact_s2s.analysis.roundoff import round_off_bound
from dolfinx_contact_s2s.compat import geometry_dofmap
from dolfinx_contact_s2s.meshing import model_to_mesh
from dolfinx_contact_s2s.pair import contact_pairs
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.surface import contact_surface
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

__all__ = ["HEIGHT", "ExtremePoint", "build", "grid", "record_lines", "run_point", "solve"]

#: Height of each block before scaling; the blocks are one unit wide.
HEIGHT = 0.5

#: Facet tags of the model: lower block, then upper block.
_LOWER = {"bottom": 1, "right": 2, "covered": 10, "exposed": 11, "left": 4}
_UPPER = {"covered": 20, "exposed": 21, "right": 22, "top": 23, "left": 24}


@dataclass(frozen=True)
class ExtremePoint:
    r"""One point of the grid.

    Attributes:
        group: The extreme it probes, e.g. ``"E ratio"``.
        label: The value, e.g. ``"1e6"``.
        degree: Lagrange degree of the displacements.
        elements: Elements along the interface, lower and upper block.
        E: Young's moduli, lower and upper block.
        nu: Poisson's ratios, lower and upper block.
        scale: Factor on every coordinate.
        shift: Translation of the scene (after scaling).
        gap: Initial gap :math:`g_0` (negative: overlap), in units of the unscaled
            scene: the upper block is moved up by it after meshing.
        perturb: Interface nodes of the upper block moved along the interface by
            :math:`\pm` ``perturb`` times the element size (matching meshes).
        upper_span: Horizontal extent of the upper block (the lower is ``(0, 1)``).
        curved: Amplitude :math:`a` of the interface :math:`y = H + a \sin(\pi x)`,
            meshed with quadratic geometry (needs ``degree=2``).
        loading: ``"uniaxial"`` or ``"hydrostatic"``.
        unilateral: Solve unilateral contact (:class:`UnilateralContactProblem`)
            instead of tied contact.
        method: Contact discretization.
        expect: ``(exception type name, message fragment)`` of a point that must raise.
    """

    group: str
    label: str
    degree: int = 1
    elements: tuple[int, int] = (13, 9)
    E: tuple[float, float] = (1.0, 3.0)
    nu: tuple[float, float] = (0.3, 0.2)
    scale: float = 1.0
    shift: tuple[float, float] = (0.0, 0.0)
    gap: float = 0.0
    perturb: float = 0.0
    upper_span: tuple[float, float] = (0.0, 1.0)
    curved: float = 0.0
    loading: str = "uniaxial"
    unilateral: bool = False
    method: str = "segment-to-segment"
    expect: tuple[str, str] | None = None

    @property
    def name(self) -> str:
        """``group label P<degree>``, unique in :func:`grid`."""
        return f"{self.group} {self.label} P{self.degree}"


def grid(degrees: tuple[int, ...] = (1, 2), full: bool = True) -> list[ExtremePoint]:
    r"""Every point of the extremes grid, for each degree in ``degrees``.

    Args:
        degrees: Lagrange degrees of the displacements.
        full: Also the intermediate values (E ratios :math:`10^{\pm 3}`, :math:`\nu =
            0.49`, gaps and overlaps of :math:`10^{-10}`); without them, the ends of
            every range (the test suite's grid). Nodes :math:`10^{-11}, 10^{-12},
            10^{-13} h` apart are in both: the sub-segments between them are the
            shortest the segmentation must keep.
    """
    h = 1.0 / 13  # the lower block's element size along the interface
    base: list[ExtremePoint] = [ExtremePoint("reference", "README")]
    for ratio in (1e-6, 1e-3, 1e3, 1e6) if full else (1e-6, 1e6):
        base.append(ExtremePoint("E ratio", f"{ratio:.0e}", E=(1.0, ratio)))
    for nu in (0.49, 0.499, 0.4999) if full else (0.499, 0.4999):
        base.append(ExtremePoint("nu", f"{nu}", nu=(nu, nu)))
    for lower, upper in ((2, 32), (2, 128), (128, 2)):
        base.append(ExtremePoint("size ratio", f"{lower}:{upper}", elements=(lower, upper)))
    for scale in (1e-6, 1e6):
        base.append(ExtremePoint("scale", f"{scale:.0e}", scale=scale))
    base.append(ExtremePoint("translation", "(1e6, 1e6)", shift=(1e6, 1e6)))
    base.append(ExtremePoint("translation", "(1e6, 1e6) x 1e-6", shift=(1e6, 1e6), scale=1e-6))
    sizes = (1e-14, 1e-10, h) if full else (1e-14, h)
    for unilateral in (False, True):
        kind = "unilateral" if unilateral else "tied"
        for g in (*sizes, *(-g for g in sizes)):
            label = "h" if abs(g) == h else f"{abs(g):.0e}"
            group = f"{kind} {'gap' if g > 0 else 'overlap'}"
            base.append(ExtremePoint(group, label, gap=g, unilateral=unilateral))
    for delta in (1e-11, 1e-12, 1e-13):
        for method in ("segment-to-segment", "two-pass node-to-segment"):
            short = "S2S" if method == "segment-to-segment" else "two-pass NTS"
            base.append(
                ExtremePoint(
                    f"near nodes {short}",
                    f"{delta:.0e} h",
                    elements=(13, 13),
                    perturb=delta,
                    method=method,
                )
            )
    base.append(
        ExtremePoint(
            "partial cover", "upper (0.5, 1.5)", upper_span=(0.5, 1.5), loading="hydrostatic"
        )
    )
    base.append(
        ExtremePoint(
            "partial cover",
            "upper (0.5, 1.5) unilateral",
            upper_span=(0.5, 1.5),
            loading="hydrostatic",
            unilateral=True,
        )
    )
    base.append(
        ExtremePoint(
            "curved",
            "a = 0.1",
            elements=(8, 8),
            E=(1.0, 1.0),
            nu=(0.3, 0.3),
            curved=0.1,
            loading="hydrostatic",
        )
    )
    points = []
    for degree in degrees:
        for p in base:
            if p.curved and degree == 1:
                continue  # P1 on quadratic cells does not hold linear fields: no patch test
            points.append(replace(p, degree=degree))
    return points


def _model(point: ExtremePoint, elements: tuple[int, int]) -> None:
    """The two blocks in Gmsh (rank 0): interface pieces split where coverage changes."""
    import gmsh

    geo = gmsh.model.geo
    H, a = HEIGHT, point.curved
    spans = ((0.0, 1.0), point.upper_span)
    breaks = sorted({*spans[0], *spans[1]})
    ny = 4

    def y_interface(x: float) -> float:
        return H + a * math.sin(math.pi * x)

    def interface(x0: float, x1: float, n: int) -> tuple[list[tuple[int, bool]], int, int]:
        """Curves from x0 to x1 along the interface, split at ``breaks``, with coverage."""
        xs = [x0, *[b for b in breaks if x0 < b < x1], x1]
        other = spans[1] if (x0, x1) == spans[0] else spans[0]
        ends = [geo.addPoint(x, y_interface(x), 0) for x in xs]
        out = []
        for k, (s, e) in enumerate(itertools.pairwise(xs)):
            if a:
                inner = [geo.addPoint(x, y_interface(x), 0) for x in np.linspace(s, e, 33)[1:-1]]
                curve = geo.addSpline([ends[k], *inner, ends[k + 1]])
            else:
                curve = geo.addLine(ends[k], ends[k + 1])
            out.append((curve, other[0] <= 0.5 * (s + e) <= other[1], s, e))
        geo.synchronize()
        for curve, _, s, e in out:
            count = max(1, round(n * (e - s) / (x1 - x0)))
            gmsh.model.mesh.setTransfiniteCurve(curve, count + 1)
        return [(c, cov) for c, cov, _, _ in out], ends[0], ends[-1]

    surfaces = []
    for body, ((x0, x1), n) in enumerate(zip(spans, elements, strict=True)):
        pieces, ia, ib = interface(x0, x1, n)
        y_far = 0.0 if body == 0 else 2 * H
        fa, fb = geo.addPoint(x0, y_far, 0), geo.addPoint(x1, y_far, 0)
        far = geo.addLine(fa, fb)
        right = geo.addLine(fb, ib) if body == 0 else geo.addLine(ib, fb)
        left = geo.addLine(ia, fa) if body == 0 else geo.addLine(fa, ia)
        curves = [c for c, _ in pieces]
        # Counterclockwise loops: lower = far, right, interface reversed, left.
        if body == 0:
            loop = [far, right, *[-c for c in reversed(curves)], left]
        else:
            loop = [*curves, right, -far, left]
        surfaces.append(geo.addPlaneSurface([geo.addCurveLoop(loop)]))
        geo.synchronize()
        for c in (right, left):
            gmsh.model.mesh.setTransfiniteCurve(c, ny + 1)
        gmsh.model.mesh.setTransfiniteCurve(far, max(2, n // 2) + 1)
        tags = _LOWER if body == 0 else _UPPER
        covered = [c for c, cov in pieces if cov]
        exposed = [c for c, cov in pieces if not cov]
        gmsh.model.addPhysicalGroup(1, covered, tags["covered"])
        if exposed:
            gmsh.model.addPhysicalGroup(1, exposed, tags["exposed"])
        gmsh.model.addPhysicalGroup(1, [right], tags["right"])
        gmsh.model.addPhysicalGroup(1, [left], tags["left"])
        gmsh.model.addPhysicalGroup(1, [far], tags["bottom" if body == 0 else "top"])
        gmsh.model.addPhysicalGroup(2, [surfaces[-1]], body + 1)
    gmsh.model.mesh.generate(2)
    if a:
        gmsh.model.mesh.setOrder(2)


def _strains(point: ExtremePoint) -> list[tuple[float, float]]:
    r"""Plane-strain :math:`(\varepsilon_{xx}, \varepsilon_{yy})` of each block."""
    sx, sy = (-1.0, -1.0) if point.loading == "hydrostatic" else (0.0, -1.0)
    out = []
    for E, nu in zip(point.E, point.nu, strict=True):
        out.append(
            (
                ((1 - nu**2) * sx - nu * (1 + nu) * sy) / E,
                ((1 - nu**2) * sy - nu * (1 + nu) * sx) / E,
            )
        )
    return out


def build(
    point: ExtremePoint,
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    elements: tuple[int, int] | None = None,
    backend: str = "auto",
    prefix: str = "extremes_",
) -> tuple[LinearContactProblem, np.ndarray]:
    """The point's problem, built as a user builds the README example.

    Args:
        point: The grid point.
        comm: Communicator of the mesh.
        elements: Elements along the interface, instead of ``point.elements``.
        backend: Kernel backend of the contact surfaces.
        prefix: PETSc options prefix of the solver.

    Returns:
        The (unsolved) problem, which its caller destroys, and whether each node of the
        displacement space (owned and ghost) belongs to the upper block.
    """
    import gmsh

    elements = elements or point.elements
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        if comm.rank == 0:
            gmsh.model.add("extremes")
            _model(point, elements)
        mesh, cells, facets = model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()

    # The user moves the upper block's nodes: the gap, the near-coincident nodes.
    x = mesh.geometry.x
    upper = np.zeros(x.shape[0], dtype=bool)
    upper[np.unique(geometry_dofmap(mesh)[cells.find(2)])] = True
    if point.perturb:
        h = 1.0 / elements[1]
        on = upper & np.isclose(x[:, 1], HEIGHT, rtol=0, atol=1e-12)
        k = np.rint(x[:, 0] / h)
        inner = on & (k > 0) & (k < elements[1])
        x[inner, 0] += point.perturb * h * np.where(k[inner] % 2 == 0, 1.0, -1.0)
    x[upper, 1] += point.gap
    x[:, :2] = x[:, :2] * point.scale + np.asarray(point.shift)

    V = dolfinx.fem.functionspace(mesh, ("Lagrange", point.degree, (2,)))
    DG = dolfinx.fem.functionspace(mesh, ("DG", 0))
    E, nu = dolfinx.fem.Function(DG), dolfinx.fem.Function(DG)
    for body in (0, 1):
        body_dofs = DG.dofmap.list[cells.find(body + 1)].reshape(-1)
        E.x.array[body_dofs] = point.E[body]
        nu.x.array[body_dofs] = point.nu[body]
    E.x.scatter_forward()
    nu.x.scatter_forward()
    mu = E / (2 * (1 + nu))
    lmbda = E * nu / ((1 + nu) * (1 - 2 * nu))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)

    def eps(w):
        return ufl.sym(ufl.grad(w))

    def sigma(w):
        return 2 * mu * eps(w) + lmbda * ufl.tr(eps(w)) * ufl.Identity(2)

    a = ufl.inner(sigma(u), eps(v)) * ufl.dx
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
    n = ufl.FacetNormal(mesh)
    if point.loading == "uniaxial":
        loaded = [_UPPER["top"]]
    else:
        loaded = [_LOWER["right"], _LOWER["exposed"], _UPPER["exposed"]]
        loaded += [_UPPER["right"], _UPPER["top"]]
    L = sum(-ufl.inner(n, v) * ds(t) for t in loaded)

    _, (exx_u, _) = _strains(point)
    fdim = 1
    dofs = dolfinx.fem.locate_dofs_topological
    bcs = [
        dolfinx.fem.dirichletbc(0.0, dofs(V.sub(0), fdim, facets.find(_LOWER["left"])), V.sub(0)),
        dolfinx.fem.dirichletbc(0.0, dofs(V.sub(1), fdim, facets.find(_LOWER["bottom"])), V.sub(1)),
        dolfinx.fem.dirichletbc(
            exx_u * point.upper_span[0] * point.scale,
            dofs(V.sub(0), fdim, facets.find(_UPPER["left"])),
            V.sub(0),
        ),
    ]
    # One contact tag per body: covered and exposed pieces of its interface together.
    contact = [facets.indices[np.isin(facets.values, (10, 11))]]
    contact.append(facets.indices[np.isin(facets.values, (20, 21))])
    indices = np.concatenate(contact)
    values = np.concatenate(
        [np.full(c.size, t, dtype=np.int32) for c, t in zip(contact, (10, 20), strict=True)]
    )
    order = np.argsort(indices)
    contact_tags = dolfinx.mesh.meshtags(mesh, fdim, indices[order], values[order])
    target = contact_surface(V, contact_tags, 10, backend=backend)
    contactor = contact_surface(V, contact_tags, 20, backend=backend)
    pairs = contact_pairs(contactor, target, method=point.method)
    nodes = V.dofmap.index_map.size_local + V.dofmap.index_map.num_ghosts
    on_upper = np.zeros(nodes, dtype=bool)
    on_upper[np.unique(V.dofmap.list[cells.find(2)])] = True
    kind = UnilateralContactProblem if point.unilateral else LinearContactProblem
    return kind(a, L, pairs, bcs, petsc_options_prefix=prefix), on_upper


def _exact_displacement(point: ExtremePoint, X: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """The linear exact displacement at points ``X`` relative to the lower-left corner."""
    s, y0 = point.scale, point.shift[1]
    (exx_l, eyy_l), (exx_u, eyy_u) = _strains(point)
    # The interface as the nodes have it: rounded like them (x * scale + shift).
    top = (HEIGHT * s + y0) - y0
    bottom = ((HEIGHT + point.gap) * s + y0) - y0
    out = np.empty_like(X)
    out[:, 0] = np.where(upper, exx_u, exx_l) * X[:, 0]
    lower_y = eyy_l * X[:, 1]
    upper_y = eyy_l * top + eyy_u * (X[:, 1] - bottom) - (bottom - top)
    out[:, 1] = np.where(upper, upper_y, lower_y)
    return out


def solve(
    point: ExtremePoint,
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    elements: tuple[int, int] | None = None,
    backend: str = "auto",
    prefix: str = "extremes_",
) -> dict:
    r"""Solve one point and measure its errors against its round-off bound.

    Returns:
        ``displacement_scale`` (:math:`\max |u_{exact}|`), ``displacement_error``,
        ``displacement_bound``, ``multiplier_error`` and
        ``multiplier_bound`` (``None`` for a two-pass method, whose multipliers split the
        force between the passes), ``condition``, ``backward_error``, ``passed``,
        ``exception`` (``None``, or ``"Type: message"`` of the exception raised, the same
        on every rank) and ``seconds``; identical on every rank.
    """
    start = time.perf_counter()
    record: dict = {"exception": None}
    problem = None
    try:
        problem, on_upper = build(point, comm, elements=elements, backend=backend, prefix=prefix)
        problem.solve()
        bound = round_off_bound(problem)
        record.update(_errors(point, problem, on_upper, comm))
        record["displacement_bound"] = bound.displacement[0]
        two_pass = len(problem.pairs) > 1
        if point.perturb and point.method != "segment-to-segment":
            # Nodes within 1e-8 h count as coincident (two-pass drops one constraint of
            # each such pair): the kept one sits delta = perturb h away, a consistency
            # error of order delta (measured up to 1.02 delta), not round-off.
            delta = point.perturb * point.scale / point.elements[1]
            record["displacement_bound"] += 4.0 * delta
        record["multiplier_bound"] = None if two_pass else max(bound.multiplier)
        if two_pass:
            record["multiplier_error"] = None
        record["condition"] = bound.condition
        record["backward_error"] = bound.backward_error
    except (ValueError, RuntimeError) as error:
        record["exception"] = f"{type(error).__name__}: {error}"
    finally:
        if problem is not None:
            problem.destroy()
    if record["exception"] is None:
        ok = record["displacement_error"] <= record["displacement_bound"]
        if record["multiplier_error"] is not None:
            ok = ok and record["multiplier_error"] <= record["multiplier_bound"]
        record["passed"] = bool(ok) and point.expect is None
    else:
        record["passed"] = point.expect is not None and (
            record["exception"].startswith(point.expect[0] + ":")
            and point.expect[1] in record["exception"]
        )
    record["seconds"] = comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
    return record


def _dof_coordinates(V: dolfinx.fem.FunctionSpace, shift: tuple[float, float]) -> np.ndarray:
    """Dof coordinates relative to ``shift``, pushed forward on the mesh moved back by it.

    The push-forward of the reference points carries round-off of the coordinates'
    size (``1e-10`` at ``1e6``); moving the nodes by ``-shift`` and back is exact.
    """
    x = V.mesh.geometry.x
    x[:, :2] -= np.asarray(shift)
    try:
        return V.tabulate_dof_coordinates()[:, :2].copy()
    finally:
        x[:, :2] += np.asarray(shift)


def _errors(
    point: ExtremePoint, problem: LinearContactProblem, on_upper: np.ndarray, comm: MPI.Comm
) -> dict:
    """Max errors of the displacements and of the multipliers, over owned dofs."""
    u = problem.u[0]
    V = u.function_space
    n = V.dofmap.index_map.size_local
    X = _dof_coordinates(V, point.shift)[:n]
    exact = _exact_displacement(point, X, on_upper[:n])
    e_u = float(np.max(np.abs(u.x.array.reshape(-1, 2)[:n] - exact), initial=0.0))
    e_l = 0.0
    s = point.scale
    lo, hi = max(0.0, point.upper_span[0]) * s, min(1.0, point.upper_span[1]) * s
    for lam in problem.multipliers:
        Q = lam.function_space
        m = Q.dofmap.index_map.size_local
        xq = _dof_coordinates(Q, point.shift)[:m, 0]
        # Unit pressure where the surfaces face each other, none where they do not.
        # (up to a quarter element: the nodes carry the round-off of their coordinates)
        tol = 0.25 * s / max(point.elements)
        covered = (xq >= lo - tol) & (xq <= hi + tol)
        e_l = max(e_l, float(np.max(np.abs(lam.x.array[:m] - covered), initial=0.0)))
    return {
        "displacement_scale": comm.allreduce(float(np.max(np.abs(exact), initial=0.0)), op=MPI.MAX),
        "displacement_error": comm.allreduce(e_u, op=MPI.MAX),
        "multiplier_error": comm.allreduce(e_l, op=MPI.MAX),
    }


def run_point(point: ExtremePoint, comm: MPI.Comm = MPI.COMM_WORLD, **kwargs) -> dict:
    """:func:`solve` with the point's parameters, as one JSON record."""
    record = {"name": point.name, **asdict(point), "ranks": comm.size}
    record.update(solve(point, comm, **kwargs))
    return record


def record_lines(
    records: list[dict], fmt: Callable[[float | None], str] | None = None
) -> list[str]:
    """Markdown table rows of the records: point, ranks, errors, bounds, verdict."""

    def f(v: float | None) -> str:
        return "-" if v is None else f"{v:.1e}"

    fmt = fmt or f
    lines = [
        "| point | ranks | error u | bound u | error λ | bound λ | cond | result |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in records:
        if r["exception"] is not None:
            verdict = ("raises as expected: " if r["passed"] else "FAIL, raised: ") + r[
                "exception"
            ].split(". ")[0]
            lines.append(f"| {r['name']} | {r['ranks']} | - | - | - | - | - | {verdict} |")
            continue
        lines.append(
            f"| {r['name']} | {r['ranks']} | {fmt(r['displacement_error'])} | "
            f"{fmt(r['displacement_bound'])} | {fmt(r['multiplier_error'])} | "
            f"{fmt(r['multiplier_bound'])} | {fmt(r['condition'])} | "
            f"{'pass' if r['passed'] else 'FAIL'} |"
        )
    return lines

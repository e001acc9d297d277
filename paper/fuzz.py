# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Randomized patch tests: non-matching two-body models drawn at random, built as a user would.

A :class:`FuzzCase` is the patch test of section 3.2 (Figs. 4 and 6) with everything a
user chooses left free: one Gmsh model with both blocks in one mesh and one space, or a
model (a mesh, a space) per block; each block's cell type, displacement degree, number
of elements across its height and the nodes of its contact edge and of its far edge (a
few Gmsh curves at random break points, each with its own element count and geometric
grading, so the spacing is non-uniform and the two contact edges never match); the
materials (Young's moduli over several decades, Poisson's ratios up to 0.49); the
contactor; a small initial gap or overlap. :func:`build_problem` builds it the way the
README does (Gmsh on rank 0, DOLFINx's reader, the user's own elasticity forms,
:func:`~dolfinx_contact_s2s.contact_surface`, :func:`~dolfinx_contact_s2s.contact_pairs`,
:class:`~dolfinx_contact_s2s.problem.LinearContactProblem`), and :func:`check_case`
solves it with composite segment-to-segment and compares it with the exact solution:
:math:`\lambda = p` and the linear displacements of a uniaxial stress
:math:`\sigma_y = -p` (plane strain), which every element used here represents
exactly (Eq. 36). The errors are measured against the round-off bound of the solve
(:func:`~dolfinx_contact_s2s.analysis.roundoff.round_off_bound`): a ratio above 1 is a defect.

:func:`cases` is the Hypothesis strategy of these cases (Hypothesis is imported when it
is called); ``tests/reproductions/test_fuzz.py`` runs a few dozen and ``demos/fuzz_patch_test.py``
thousands.
"""

from __future__ import annotations

import argparse
import itertools
import json
import traceback
import typing
from dataclasses import asdict, dataclass
from pathlib import Path

from mpi4py import MPI

import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.meshing import gmsh_session, model_to_mesh
from dolfinx_contact_s2s.pair import contact_pairs
from dolfinx_contact_s2s.surface import contact_surface

__all__ = [
    "CELLS",
    "Block",
    "CaseResult",
    "FuzzCase",
    "Segment",
    "build_problem",
    "campaign_parser",
    "cases",
    "check_case",
    "guarded",
    "rerun_command",
    "run_campaign",
    "run_drawn_cases",
]

#: Cell types a block may have.
CELLS = ("triangle", "quadrilateral")

#: Facet tags (as the README's model): lower block bottom, right, top (contact), left;
#: upper block bottom (contact), right, top, left.
LOWER_TAGS = (1, 2, 10, 4)
UPPER_TAGS = (20, 22, 23, 24)

#: Width of both blocks and the applied pressure.
WIDTH, PRESSURE = 1.0, 1.0

#: Ceiling on the multiplier's round-off bound itself, relative to the pressure: the
#: comparison must still tell a pressure error of 1% (node-to-segment's are 10% and
#: more). The bound is usually far lower (1e-13 to 1e-8); it reaches 1e-3 where the
#: direct solve's backward error is itself large (1e-11 at a contrast of 1e5).
BOUND_CEILING = 1e-2


@dataclass(frozen=True)
class Segment:
    """One Gmsh curve of an edge: its share of the width, elements and grading.

    Attributes:
        weight: Relative length (the edge's curves share the width by weight).
        elements: Number of elements along the curve.
        progression: Gmsh's geometric progression of the element sizes (1: uniform).
    """

    weight: float
    elements: int
    progression: float


@dataclass(frozen=True)
class Block:
    """One block: cell type, displacement degree, edges, layers and material.

    Attributes:
        cell: ``"triangle"`` or ``"quadrilateral"``.
        degree: Displacement degree, 1 or 2.
        contact: The curves of the contact edge, left to right.
        far: The curves of the opposite edge (for quadrilaterals, with the same element
            counts: the mesh is transfinite).
        layers: Elements across the height.
        height: Height of the block.
        E: Young's modulus.
        nu: Poisson's ratio.
    """

    cell: str
    degree: int
    contact: tuple[Segment, ...]
    far: tuple[Segment, ...]
    layers: int
    height: float
    E: float
    nu: float

    @property
    def lame(self) -> tuple[float, float]:
        r"""Lamé parameters :math:`(\mu, \lambda)`, plane strain."""
        mu = self.E / (2 * (1 + self.nu))
        return mu, self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))

    @property
    def strains(self) -> tuple[float, float]:
        r"""Strains :math:`(\varepsilon_x, \varepsilon_y)` under :math:`\sigma_y = -p`.

        With :math:`\sigma_x = \sigma_{xy} = 0` and plane strain.
        """
        mu, lmbda = self.lame
        d = 4 * mu * (lmbda + mu)
        return PRESSURE * lmbda / d, -PRESSURE * (lmbda + 2 * mu) / d


@dataclass(frozen=True)
class FuzzCase:
    r"""A randomized patch test.

    Attributes:
        one_mesh: Both blocks in one Gmsh model, one mesh and one space (the README's
            model), or a model, mesh and space each.
        lower: The lower block, :math:`[0, W] \times [0, H_l]`.
        upper: The upper block, :math:`[0, W] \times [H_l + g_0, H_l + g_0 + H_u]`.
        contactor: ``"lower"`` or ``"upper"``.
        gap: Initial gap :math:`g_0` (negative: overlap).
    """

    one_mesh: bool
    lower: Block
    upper: Block
    contactor: str
    gap: float

    def to_json(self) -> str:
        """The case as one line of JSON (:meth:`from_json` reads it back exactly)."""
        return json.dumps(asdict(self), separators=(",", ":"))

    @classmethod
    def from_json(cls, text: str) -> FuzzCase:
        """Read a case written by :meth:`to_json`."""
        d = json.loads(text)

        def block(b: dict) -> Block:
            edges = {k: tuple(Segment(**s) for s in b[k]) for k in ("contact", "far")}
            return Block(**{**b, **edges})

        return cls(d["one_mesh"], block(d["lower"]), block(d["upper"]), d["contactor"], d["gap"])

    def describe(self) -> str:
        """A short human-readable summary."""

        def one(b: Block) -> str:
            n = sum(s.elements for s in b.contact)
            return f"{b.cell[:4]} P{b.degree} n={n}/{len(b.contact)} E={b.E:.2g} nu={b.nu:.3f}"

        mesh = "one mesh" if self.one_mesh else "two meshes"
        return (
            f"{mesh}, lower [{one(self.lower)}], upper [{one(self.upper)}], "
            f"contactor {self.contactor}, gap {self.gap:g}"
        )


@dataclass(frozen=True)
class CaseResult:
    r"""The outcome of one case (the same on every process).

    Attributes:
        pressure_error: :math:`\max |\lambda - p|`.
        pressure_bound: The round-off bound on it.
        displacement_error: Per space, :math:`\max |u - u_{exact}|`.
        displacement_bound: Per space, the round-off bound on it.
        condition: Condition estimate of the equilibrated saddle point.
        backward_error: The solve's componentwise backward error.
        unknowns: Size of the saddle point.
    """

    pressure_error: float
    pressure_bound: float
    displacement_error: list[float]
    displacement_bound: list[float]
    condition: float
    backward_error: float
    unknowns: int

    @property
    def ratio(self) -> float:
        """The largest error over its bound (at most 1 for a pass)."""
        pairs = [(self.pressure_error, self.pressure_bound)]
        pairs += list(zip(self.displacement_error, self.displacement_bound, strict=True))
        return max(e / b for e, b in pairs)

    @property
    def passed(self) -> bool:
        """Every error within its bound, and the pressure's bound not vacuous."""
        return self.ratio <= 1.0 and self.pressure_bound < BOUND_CEILING * PRESSURE


def _breakpoints(segments: tuple[Segment, ...]) -> npt.NDArray[np.floating]:
    w = np.cumsum([0.0] + [s.weight for s in segments])
    x = WIDTH * w / w[-1]
    x[-1] = WIDTH
    return x


def _add_block(
    gmsh: typing.Any, block: Block, y0: float, contact_on_top: bool, tags: tuple[int, ...]
) -> int:
    """Add the block ``[0, W] x [y0, y0 + height]`` to the current model (rank 0 only).

    ``tags`` are the physical tags of its bottom, right, top and left edges. Returns the
    plane surface.
    """
    geo = gmsh.model.geo
    y1 = y0 + block.height
    bottom, top = (block.far, block.contact) if contact_on_top else (block.contact, block.far)

    def edge(segments: tuple[Segment, ...], y: float) -> tuple[list[int], list[int]]:
        points = [geo.addPoint(x, y, 0) for x in _breakpoints(segments)]
        # Left to right, so that each curve's progression grows along +x.
        return points, [geo.addLine(a, b) for a, b in itertools.pairwise(points)]

    pb, lb = edge(bottom, y0)
    pt, lt = edge(top, y1)
    right = geo.addLine(pb[-1], pt[-1])
    left = geo.addLine(pb[0], pt[0])
    loop = geo.addCurveLoop(lb + [right] + [-c for c in reversed(lt)] + [-left])
    surface = geo.addPlaneSurface([loop])
    # Mesh constraints through the geo kernel: those set on the model are lost when a
    # second block is synchronized into the same model.
    for segments, curves in ((bottom, lb), (top, lt)):
        for s, c in zip(segments, curves, strict=True):
            geo.mesh.setTransfiniteCurve(c, s.elements + 1, "Progression", s.progression)
    for c in (left, right):
        geo.mesh.setTransfiniteCurve(c, block.layers + 1)
    if block.cell == "quadrilateral":
        geo.mesh.setTransfiniteSurface(surface, "Left", [pb[0], pb[-1], pt[-1], pt[0]])
        geo.mesh.setRecombine(2, surface)
    geo.synchronize()
    for curves, tag in zip((lb, [right], lt, [left]), tags, strict=True):
        gmsh.model.addPhysicalGroup(1, curves, tag)
    return surface


def _materials(
    block: Block, mesh: dolfinx.mesh.Mesh
) -> tuple[dolfinx.fem.Constant, dolfinx.fem.Constant]:
    mu, lmbda = block.lame
    return dolfinx.fem.Constant(mesh, mu), dolfinx.fem.Constant(mesh, lmbda)


def _forms(
    V: dolfinx.fem.FunctionSpace, mu: typing.Any, lmbda: typing.Any, ds: ufl.Measure, load: float
) -> tuple[ufl.Form, ufl.Form]:
    """A user's plane-strain elasticity and a pressure ``load`` on ``ds``."""
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)

    def eps(w):
        return ufl.sym(ufl.grad(w))

    sigma = 2 * mu * eps(u) + lmbda * ufl.tr(eps(u)) * ufl.Identity(2)
    t = dolfinx.fem.Constant(V.mesh, np.array([0.0, -load]))
    return ufl.inner(sigma, eps(v)) * ufl.dx, ufl.inner(t, v) * ds


def _rollers(V: dolfinx.fem.FunctionSpace, facets: dolfinx.mesh.MeshTags, left, bottom=None):
    """:math:`u_x = 0` on the ``left`` facets, :math:`u_y = 0` on ``bottom``."""
    out = []
    for component, tag in ((0, left), (1, bottom)):
        if tag is None:
            continue
        dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 1, facets.find(tag))
        out.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(component)))
    return out


@dataclass
class Built:
    """A built case: the problem and, per space, the body of every dof block.

    Attributes:
        problem: The (unsolved) problem.
        bodies: Per space, a map from ``"lower"``/``"upper"`` to local dof blocks.
    """

    problem: typing.Any
    bodies: list[dict[str, npt.NDArray[np.int32]]]


def _dofs_of_cells(V: dolfinx.fem.FunctionSpace, cells: npt.NDArray[np.int32]):
    dofmap = V.dofmap.list
    dofmap = dofmap.array if hasattr(dofmap, "array") else dofmap
    return np.unique(np.asarray(dofmap).reshape(-1, V.dofmap.dof_layout.num_dofs)[cells])


def build_problem(
    case: FuzzCase,
    comm: MPI.Comm,
    prefix: str = "fuzz_",
    method: str = "segment-to-segment",
) -> Built:
    """Build the case as a user would (collective); the problem is not yet solved.

    Args:
        case: The case.
        comm: Communicator of the meshes.
        prefix: The problem's ``petsc_options_prefix``.
        method: The contact discretization (composite segment-to-segment by default).
    """
    from dolfinx_contact_s2s.problem import LinearContactProblem

    # The meshes are rank 0's, the exact solution each rank's own: a case that differs
    # between the ranks would be checked against the wrong solution without an error.
    texts = comm.allgather(case.to_json())
    if any(t != texts[0] for t in texts):
        ranks = [r for r, t in enumerate(texts) if t != texts[0]]
        raise ValueError(f"the case differs between the ranks: ranks {ranks} differ from rank 0")
    lower, upper = case.lower, case.upper
    y_upper = lower.height + case.gap
    bodies: list[dict[str, npt.NDArray[np.int32]]] = []
    with gmsh_session() as gmsh:
        if case.one_mesh:
            gmsh.model.add("fuzz")
            if comm.rank == 0:
                s0 = _add_block(gmsh, lower, 0.0, True, LOWER_TAGS)
                s1 = _add_block(gmsh, upper, y_upper, False, UPPER_TAGS)
                gmsh.model.addPhysicalGroup(2, [s0], 1)
                gmsh.model.addPhysicalGroup(2, [s1], 2)
                gmsh.model.mesh.generate(2)
            mesh, cell_tags, facets = model_to_mesh(gmsh.model, comm, 0, gdim=2)
            gmsh.model.remove()
            meshes = [(mesh, facets)]
        else:
            meshes = []
            for name, block, y0, tags in (
                ("lower", lower, 0.0, LOWER_TAGS),
                ("upper", upper, y_upper, UPPER_TAGS),
            ):
                gmsh.model.add(name)
                if comm.rank == 0:
                    s = _add_block(gmsh, block, y0, name == "lower", tags)
                    gmsh.model.addPhysicalGroup(2, [s], 1)
                    gmsh.model.mesh.generate(2)
                mesh, _, facets = model_to_mesh(gmsh.model, comm, 0, gdim=2)
                gmsh.model.remove()
                meshes.append((mesh, facets))

    if case.one_mesh:
        (mesh, facets) = meshes[0]
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", lower.degree, (2,)))
        # Materials as cellwise constants from the cell tags, as a user of one mesh does.
        Q = dolfinx.fem.functionspace(mesh, ("DG", 0))
        mu, lmbda = dolfinx.fem.Function(Q), dolfinx.fem.Function(Q)
        cells = {name: cell_tags.find(tag) for name, tag in (("lower", 1), ("upper", 2))}
        for name, block in (("lower", lower), ("upper", upper)):
            mu.x.array[cells[name]], lmbda.x.array[cells[name]] = block.lame
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
        a, L = _forms(V, mu, lmbda, ds(UPPER_TAGS[2]), PRESSURE)
        bcs = _rollers(V, facets, LOWER_TAGS[3], LOWER_TAGS[0])
        bcs += _rollers(V, facets, UPPER_TAGS[3])
        surfaces = {
            "lower": contact_surface(V, facets, LOWER_TAGS[2]),
            "upper": contact_surface(V, facets, UPPER_TAGS[0]),
        }
        bodies.append({name: _dofs_of_cells(V, c) for name, c in cells.items()})
    else:
        a, L, bcs, surfaces = [], [], [], {}
        for name, block, (mesh, facets), tags in (
            ("lower", lower, meshes[0], LOWER_TAGS),
            ("upper", upper, meshes[1], UPPER_TAGS),
        ):
            V = dolfinx.fem.functionspace(mesh, ("Lagrange", block.degree, (2,)))
            ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
            load = PRESSURE if name == "upper" else 0.0
            a_i, L_i = _forms(V, *_materials(block, mesh), ds(tags[2]), load)
            a.append(a_i)
            L.append(L_i)
            bcs += _rollers(V, facets, tags[3], tags[0] if name == "lower" else None)
            contact = tags[2] if name == "lower" else tags[0]
            surfaces[name] = contact_surface(V, facets, contact)
            cells = np.arange(mesh.topology.index_map(2).size_local, dtype=np.int32)
            bodies.append({name: _dofs_of_cells(V, cells)})
    target = "lower" if case.contactor == "upper" else "upper"
    pairs = contact_pairs(surfaces[case.contactor], surfaces[target], method=method)
    problem = LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix=prefix)
    return Built(problem, bodies)


def _exact(case: FuzzCase, name: str, x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    """The exact displacement of block ``name`` at the points ``x`` (rows)."""
    exx_l, eyy_l = case.lower.strains
    if name == "lower":
        return np.column_stack([exx_l * x[:, 0], eyy_l * x[:, 1]])
    exx, eyy = case.upper.strains
    h, g = case.lower.height, case.gap
    # The tied surfaces close the gap: the upper block moves down by g0 (G = int mu g0).
    return np.column_stack([exx * x[:, 0], eyy_l * h - g + eyy * (x[:, 1] - h - g)])


def check_case(
    case: FuzzCase,
    comm: MPI.Comm,
    prefix: str = "fuzz_",
    method: str = "segment-to-segment",
) -> CaseResult:
    """Build and solve ``case``; its errors and round-off bounds (collective).

    The errors are maxima over every process, so the result is the same on all of them.

    Args:
        case: The case.
        comm: Communicator of the meshes.
        prefix: The problem's ``petsc_options_prefix``.
        method: The contact discretization; the patch test (Eq. 36) holds for the
            default, composite segment-to-segment.
    """
    from dolfinx_contact_s2s.analysis.roundoff import round_off_bound

    built = build_problem(case, comm, prefix, method)
    with built.problem as problem:
        us, (lam,) = problem.solve()
        bound = round_off_bound(problem)
        owned = lam.function_space.dofmap.index_map.size_local
        e_lam = float(np.max(np.abs(lam.x.array[:owned] - PRESSURE), initial=0.0))
        e_u = []
        for u, bodies in zip(us, built.bodies, strict=True):
            V = u.function_space
            x = V.tabulate_dof_coordinates()
            values = u.x.array.reshape(-1, 2)
            local = 0.0
            for name, dofs in bodies.items():
                exact = _exact(case, name, x[dofs])
                local = max(local, float(np.max(np.abs(values[dofs] - exact), initial=0.0)))
            e_u.append(local)
        unknowns = problem.A.getSize()[0]
    errors = np.zeros(1 + len(e_u))
    comm.Allreduce(np.array([e_lam, *e_u]), errors, op=MPI.MAX)
    return CaseResult(
        float(errors[0]),
        float(bound.multiplier[0]),
        [float(e) for e in errors[1:]],
        [float(b) for b in bound.displacement],
        float(bound.condition),
        float(bound.backward_error),
        int(unknowns),
    )


def cases(max_elements: int = 4, max_segments: int = 3, max_layers: int = 3) -> typing.Any:
    """The Hypothesis strategy of :class:`FuzzCase`.

    Args:
        max_elements: Most elements on one curve of an edge.
        max_segments: Most curves on one edge.
        max_layers: Most elements across a block's height.
    """
    from hypothesis import strategies as st

    def segments(draw, count: int | None = None) -> tuple[Segment, ...]:
        n = count if count is not None else draw(st.integers(1, max_segments))
        out = []
        for _ in range(n):
            out.append(
                Segment(
                    weight=draw(st.floats(0.2, 1.0)),
                    elements=draw(st.integers(1, max_elements)),
                    progression=draw(st.sampled_from([1.0, 0.8, 1.25, 0.67, 1.5])),
                )
            )
        return tuple(out)

    @st.composite
    def block(draw, cell: str, degree: int) -> Block:
        contact = segments(draw)
        if cell == "quadrilateral":
            # Transfinite: the far edge has the contact edge's element counts on curves
            # of its own break points and grading, so the cells are skewed trapezoids.
            far = tuple(
                Segment(f.weight, c.elements, f.progression)
                for c, f in zip(contact, segments(draw, len(contact)), strict=True)
            )
        else:
            far = segments(draw)
        return Block(
            cell=cell,
            degree=degree,
            contact=contact,
            far=far,
            layers=draw(st.integers(1, max_layers)),
            height=draw(st.floats(0.25, 1.0)),
            E=10.0 ** draw(st.floats(-3.0, 3.0)),
            nu=draw(st.floats(0.0, 0.49)),
        )

    @st.composite
    def case(draw) -> FuzzCase:
        one_mesh = draw(st.booleans())
        cell_l = draw(st.sampled_from(CELLS))
        degree_l = draw(st.sampled_from([1, 2]))
        cell_u = cell_l if one_mesh else draw(st.sampled_from(CELLS))
        degree_u = degree_l if one_mesh else draw(st.sampled_from([1, 2]))
        return FuzzCase(
            one_mesh=one_mesh,
            lower=draw(block(cell_l, degree_l)),
            upper=draw(block(cell_u, degree_u)),
            contactor=draw(st.sampled_from(["upper", "lower"])),
            gap=draw(st.sampled_from([0.0, 0.0, 1e-3, -1e-3, 1e-2, -1e-2])),
        )

    return case()


def run_drawn_cases(
    comm: MPI.Comm,
    strategy: typing.Any,
    body: typing.Callable[[typing.Any], float | None],
    hypothesis_settings: typing.Any,
    seed: int | None = None,
) -> None:
    """Run ``body`` on every rank for each example Hypothesis draws on rank 0 (collective).

    Hypothesis's draws depend on state of the process: it mixes in numeric constants of
    the local modules the process has imported, and a rank that imported one more module
    (a plotting one, say) draws other examples from the same seed. Ranks that each drew
    their own examples would then check different cases in one collective solve, a wrong
    answer without an error. Here Hypothesis runs on rank 0 only (generation, targeting,
    shrinking); it broadcasts each example and the other ranks run ``body`` on it.

    Args:
        comm: The communicator ``body`` is collective on.
        strategy: The Hypothesis strategy of the examples.
        body: The check of one example, collective; raises if it fails. A float it
            returns is Hypothesis's target (maximized in the targeted phase).
        hypothesis_settings: The ``hypothesis.settings`` of the run.
        seed: Hypothesis's seed (``hypothesis.seed``), unless derandomized.

    Raises:
        The failure, on every rank: on rank 0 Hypothesis's (after shrinking, with the
        falsifying example), on the others the last error of ``body``.
    """
    import hypothesis

    error: BaseException | None = None
    if comm.rank == 0:

        def example(value: typing.Any) -> None:
            comm.bcast((True, value), root=0)
            score = body(value)
            if score is not None:
                hypothesis.target(float(score))

        run = hypothesis_settings(hypothesis.given(strategy)(example))
        if seed is not None:
            run = hypothesis.seed(seed)(run)
        try:
            run()
        except BaseException as e:  # reported on every rank below
            error = e
        finally:
            comm.bcast((False, None), root=0)  # the end, also after an error
    else:
        while True:
            more, value = comm.bcast(None, root=0)
            if not more:
                break
            try:
                body(value)
            except Exception as e:  # rank 0 decides what to do with a failure
                error = e
    failed = comm.allgather(None if error is None else f"{type(error).__name__}: {error}")
    if error is not None:
        raise error
    reasons = [(r, m) for r, m in enumerate(failed) if m is not None]
    if reasons:
        rank, message = reasons[0]
        raise AssertionError(f"the drawn cases failed on rank {rank}: {message}")


def guarded(
    comm: MPI.Comm, check: typing.Callable[[], tuple[dict, str | None]]
) -> tuple[dict, str | None]:
    """``check()``'s record and failure message, the same on every rank (collective).

    An exception is a failure (the campaign goes on), and a failure on one rank only is a
    failure on all of them.
    """
    try:
        record, message = check()
    except Exception as error:  # every failure is recorded
        record, message = {}, "".join(traceback.format_exception_only(error)).strip()
    messages = [m for m in comm.allgather(message) if m is not None]
    return record, (messages[0] if messages else None)


def run_campaign(
    comm: MPI.Comm,
    strategy: typing.Any,
    visit: typing.Callable[[typing.Any, int], float | None],
    cases: int,
    chunk: int,
    seed: int,
    progress: typing.Callable[[int], None],
) -> tuple[int, int]:
    """Draw ``cases`` cases in chunks, each a Hypothesis run of its own seed (collective).

    Chunk ``k`` is seeded ``seed + k`` and runs :func:`run_drawn_cases`; nothing is
    shrunk (Hypothesis shrinks against a wall clock that the ranks would not share).

    Args:
        comm: The communicator the checks are collective on.
        strategy: The Hypothesis strategy of the cases.
        visit: Checks one case, given the chunk's seed; returns Hypothesis's target, or
            None for a failure.
        cases: How many cases to draw.
        chunk: Cases per Hypothesis run.
        seed: The seed of the first chunk.
        progress: Called with the number of cases drawn after each chunk.

    Returns:
        The number of cases drawn (fewer than ``cases`` if Hypothesis ran out of new ones)
        and the seed of the last chunk that drew one.
    """
    from hypothesis import HealthCheck, Phase, settings

    drawn, chunk_seed, count = 0, seed, [0]

    def body(case: typing.Any) -> float | None:
        count[0] += 1
        return visit(case, chunk_seed)

    while drawn < cases:
        chunk_settings = settings(
            max_examples=min(chunk, cases - drawn),
            derandomize=False,
            database=None,
            deadline=None,
            suppress_health_check=list(HealthCheck),
            phases=[Phase.generate, Phase.target],
            print_blob=False,
        )
        count[0] = 0
        # Hypothesis draws on rank 0 only; every rank checks the case it drew.
        run_drawn_cases(comm, strategy, body, chunk_settings, seed=chunk_seed)
        if count[0] == 0:  # Hypothesis found nothing new to draw
            break
        drawn += count[0]
        progress(drawn)
        chunk_seed += 1
    return drawn, chunk_seed - 1


def campaign_parser(description: str, cases: int) -> argparse.ArgumentParser:
    """The command line of a fuzz campaign; a driver adds the limits of its cases.

    ``--cases``, ``--seed``, ``--chunk``, ``--case`` (rerun one case, its JSON), ``--out``.
    """
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--cases", type=int, default=cases, help="number of cases to draw")
    parser.add_argument("--seed", type=int, default=0, help="seed of the first chunk")
    parser.add_argument("--chunk", type=int, default=50, help="cases per Hypothesis run")
    parser.add_argument("--case", type=str, default=None, help="rerun one case (its JSON)")
    parser.add_argument("--out", type=Path, default=Path("results"), help="output folder")
    return parser


def rerun_command(script: str, case: typing.Any, comm: MPI.Comm) -> str:
    """The command that reruns ``case`` with ``script`` on as many ranks as ``comm`` has."""
    run = "python3" if comm.size == 1 else f"mpirun -n {comm.size} python3 -m mpi4py"
    return f"{run} {script} --case '{case.to_json()}'"

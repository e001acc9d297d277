# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Finite deformation and large sliding: the large-sliding patch test and ironing.

**Large-sliding patch test.** A neo-Hookean block :math:`[0, 1] \times [1/2, 1]`
(:math:`E = 2`, :math:`\nu = 0.25`, 9 x 4 cells) pressed by :math:`P` onto a wider one
:math:`[-1, 2] \times [0, 1/2]` (:math:`E = 1`, :math:`\nu = 0.3`, 39 x 4), frictionless
and unilateral, the lateral sides held in :math:`x` (uniaxial strain: every state on the
way is homogeneous, :math:`F = \mathrm{diag}(1, \beta)` in each block with
:math:`P_{yy}(\beta) = -P`), the lower top the upper block leaves open loaded by
:math:`P`, then slid by whole lower elements (1/13). The Cauchy pressure from
:math:`\lambda` is :math:`P` at every step.

**Ironing** (after Yang, Laursen and Meng 2005): a neo-Hookean block 9 x 3 (:math:`E =
1`, :math:`\nu = 0.3`, its bottom clamped) ironed by a stiff half-ring die (outer radius
3, inner 2.8, :math:`E = 1000`, :math:`\nu = 0.3`) touching its top at :math:`x = 2.5`;
the die's top ends are pressed down by 1.4, then moved along :math:`x` by 4,
frictionless. The force on the die's top ends is recorded at every step. Its vertical
component's oscillation over the steady slide (:math:`1 \le s \le 3`, the contact zone
away from the block's ends) is measured as the range of its deviation from a least-squares
quartic in :math:`s`, over its mean; the horizontal one's over the same mean. The quartic
takes out the force's trend over the window (wavelengths of about half the window and
longer), and leaves the ripple of nodes passing facets (a few elements long): a smooth
force has none. The die may be meshed coarser than the block (``die_h``): a tool meshed
coarser than the workpiece, with the multiplier on the tool, is where node-to-segment's
force jumps as the block's nodes pass the die's nodes and segment-to-segment's integral
does not.
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
import numpy.typing as npt
import scipy.optimize
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.finite import NonlinearContactProblem
from dolfinx_contact_s2s.meshing import curved_mesh, gmsh_session, model_to_mesh

__all__ = [
    "IRONING",
    "SlidingScene",
    "ironing",
    "ironing_mesh",
    "neo_hookean",
    "newton_order_probe",
    "oscillation",
    "sliding_patch",
    "steady_window",
    "stretch",
]

#: The sliding patch test's pressure and materials (E, nu) of the lower and upper block.
P = 0.2
MATERIALS = ((1.0, 0.3), (2.0, 0.25))
TOP, BOTTOM, LEFT, RIGHT = 2, 1, 4, 3

#: The ironing scene: block, die radii, its first contact point, press, slide, materials.
IRONING = {
    "block": (9.0, 3.0),
    "radii": (3.0, 2.8),
    "x0": 2.5,
    "press": 1.4,
    "slide": 4.0,
    "block_material": (1.0, 0.3),
    "die_material": (1000.0, 0.3),
    "steady": (1.0, 3.0),
}
#: Facet tags of the ironing mesh.
BLOCK_TOP, BLOCK_BOTTOM, DIE_ARC, DIE_TOP = 1, 2, 3, 4


def lame(E: float, nu: float) -> tuple[float, float]:
    """Lamé's constants."""
    return E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))


def neo_hookean(u: dolfinx.fem.Function, E: float, nu: float) -> ufl.core.expr.Expr:
    r"""The stored energy density of a compressible neo-Hookean solid (plane strain in 2D).

    :math:`\psi = \frac{\mu}{2}(\operatorname{tr} C - 3) - \mu \ln J + \frac{\lambda}{2}
    (\ln J)^2`, with :math:`C_{33} = 1` in 2D (a user's own energy: the package takes any
    residual form).
    """
    mu, lmbda = lame(E, nu)
    d = len(u)
    F = ufl.Identity(d) + ufl.grad(u)
    J = ufl.det(F)
    return mu / 2 * (ufl.tr(F.T * F) + 3 - d - 3) - mu * ufl.ln(J) + lmbda / 2 * ufl.ln(J) ** 2


def stretch(E: float, nu: float, p: float) -> float:
    r"""The stretch :math:`\beta` of uniaxial strain with nominal stress :math:`-p` along it.

    :math:`F = \mathrm{diag}(1, \beta)` (2D) or :math:`\mathrm{diag}(1, 1, \beta)` (3D);
    :math:`P = \mu (\beta - 1/\beta) + \lambda \ln\beta / \beta` in both (closed form,
    increasing in :math:`\beta`, solved by bracketing).
    """
    mu, lmbda = lame(E, nu)
    return scipy.optimize.brentq(
        lambda b: mu * (b - 1 / b) + lmbda * np.log(b) / b + p, 0.2, 1.0, xtol=1e-15
    )


def _block(comm: MPI.Comm, lower: bool, degree: int):
    """A block of the patch test, tagged; P2 gets a quadratic geometry (its facets follow u)."""
    box = [[-1.0, 0.0], [2.0, 0.5]] if lower else [[0.0, 0.5], [1.0, 1.0]]
    mesh = dolfinx.mesh.create_rectangle(comm, box, [39, 4] if lower else [9, 4])
    (x0, y0), (x1, y1) = box
    markers = [
        (TOP, lambda x: np.isclose(x[1], y1)),
        (BOTTOM, lambda x: np.isclose(x[1], y0)),
        (LEFT, lambda x: np.isclose(x[0], x0)),
        (RIGHT, lambda x: np.isclose(x[0], x1)),
    ]
    found = [(dolfinx.mesh.locate_entities_boundary(mesh, 1, f), t) for t, f in markers]
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([np.full(f.size, t, dtype=np.int32) for f, t in found])
    order = np.argsort(facets, kind="stable")
    tags = dolfinx.mesh.meshtags(mesh, 1, facets[order], values[order])
    if degree == 2:
        imap = mesh.topology.index_map(2)
        cells = np.arange(imap.size_local, dtype=np.int32)
        mesh, _, tags = curved_mesh(
            mesh, dolfinx.mesh.meshtags(mesh, 2, cells, 1 + 0 * cells), tags
        )
    return mesh, tags


class SlidingScene:
    """The two blocks of the patch test: residuals, loads, conditions (collective).

    The lower top the upper block leaves open carries P (a DG0 factor on the cells at the
    top, updated with the slide: slides are whole lower elements, so the open part is
    whole facets).
    """

    def __init__(self, degree: int, comm: MPI.Comm = MPI.COMM_WORLD):
        """Build both blocks."""
        self.comm = comm
        self.F, self.u, self.bcs, self.spaces, self.tags = [], [], [], [], []
        for k, lower in enumerate((True, False)):
            mesh, tags = _block(comm, lower, degree)
            V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
            u = dolfinx.fem.Function(V, name=f"u{k}")
            v = ufl.TestFunction(V)
            ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
            load = dolfinx.fem.Function(dolfinx.fem.functionspace(mesh, ("DG", 0)))
            load.x.array[:] = 0.0 if lower else P
            # No lateral stretch, a horizontal top: the nominal load is the Cauchy one.
            energy = neo_hookean(u, *MATERIALS[k]) * ufl.dx
            self.F.append(ufl.derivative(energy, u, v) + load * v[1] * ds(TOP))
            if lower:
                self.load, self.lower_top = load, self._top_cells(mesh, tags)
                fixed = [(0, LEFT, 0.0), (0, RIGHT, 0.0), (1, BOTTOM, 0.0)]
            else:
                self.slide = dolfinx.fem.Constant(mesh, 0.0)
                fixed = [(0, LEFT, self.slide), (0, RIGHT, self.slide)]
            for component, tag, value in fixed:
                dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 1, tags.find(tag))
                self.bcs.append(dolfinx.fem.dirichletbc(value, dofs, V.sub(component)))
            self.u.append(u)
            self.spaces.append(V)
            self.tags.append(tags)

    @staticmethod
    def _top_cells(mesh: dolfinx.mesh.Mesh, tags: dolfinx.mesh.MeshTags) -> tuple:
        mesh.topology.create_connectivity(1, 2)
        f_to_c = mesh.topology.connectivity(1, 2)
        facets = tags.find(TOP)
        cells = np.array([f_to_c.links(f)[0] for f in facets], dtype=np.int32)
        return cells, dolfinx.mesh.compute_midpoints(mesh, 1, facets)[:, 0]

    def set_slide(self, shift: float) -> None:
        """Move the upper block's sides to ``shift`` and the open part of the lower top."""
        self.slide.value = shift
        cells, x = self.lower_top
        self.load.x.array[cells] = np.where((x < shift) | (x > 1 + shift), P, 0.0)
        self.load.x.scatter_forward()

    def pair(self, method: str = "segment-to-segment"):
        """The upper bottom on the lower top."""
        target = contact_surface(self.spaces[0], self.tags[0], TOP)
        contactor = contact_surface(self.spaces[1], self.tags[1], BOTTOM)
        return contact_pair(contactor, target, method=method)

    def errors(self, lam: dolfinx.fem.Function, shift: float) -> tuple[float, float]:
        """The largest |lambda - P| / P and |u - u_exact| (the homogeneous state)."""
        n = lam.function_space.dofmap.index_map.size_local
        lam_error = np.max(np.abs(lam.x.array[:n] - P), initial=0.0) / P
        beta = [stretch(*m, P) for m in MATERIALS]
        u_error = 0.0
        for k, (V, u) in enumerate(zip(self.spaces, self.u, strict=True)):
            X = V.tabulate_dof_coordinates()[:, :2]
            if k == 0:
                exact = np.stack([0 * X[:, 0], (beta[0] - 1) * X[:, 1]], axis=1)
            else:
                y = (beta[0] - 1) * 0.5 + (beta[1] - 1) * (X[:, 1] - 0.5)
                exact = np.stack([shift + 0 * X[:, 0], y], axis=1)
            m = V.dofmap.index_map.size_local
            error = np.max(np.abs(u.x.array[: 2 * m].reshape(-1, 2) - exact[:m]), initial=0.0)
            u_error = max(u_error, float(error))
        comm = self.comm
        return comm.allreduce(float(lam_error), op=MPI.MAX), comm.allreduce(u_error, op=MPI.MAX)


def sliding_patch(
    degree: int,
    method: str = "segment-to-segment",
    elements: typing.Sequence[int] = tuple(range(9)),
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> dict[str, typing.Any]:
    """The large-sliding patch test: slides of ``elements`` lower elements, in turn.

    Returns:
        Per slide: the errors of lambda and u, the Newton iterations, the measured
        orders of its residuals (Newton's full tangent) and ``probe``
        (:func:`newton_order_probe` at its solution); ``probe``: the last slide's.
    """
    scene = SlidingScene(degree, comm)
    linearization = "full"
    steps = []
    with NonlinearContactProblem(
        scene.F,
        scene.u,
        [scene.pair(method)],
        scene.bcs,
        linearization=linearization,
        max_iterations=80,
        petsc_options_prefix=f"sliding{degree}_{method[:4]}_",
    ) as problem:
        for k in elements:
            scene.set_slide(k / 13)
            _, (lam,) = problem.solve()
            lam_error, u_error = scene.errors(lam, k / 13)
            steps.append(
                {
                    "elements": int(k),
                    "lambda_error": lam_error,
                    "u_error": u_error,
                    "iterations": len(problem.step.iterations) - 1,
                    "orders": problem.step.orders,
                    "probe": newton_order_probe(problem),
                }
            )
        probe = steps[-1]["probe"]
    return {
        "scene": "large-sliding-patch",
        "degree": degree,
        "method": method,
        "linearization": linearization,
        "steps": steps,
        "probe": probe,
    }


def ironing_mesh(comm: MPI.Comm, h: float, die_h: float | None = None) -> tuple:
    """The block and the die in one Gmsh model, triangles of size ``h`` (collective).

    ``die_h``: the die's triangles' size, if not ``h`` (a Gmsh ``Constant`` field on it).
    """
    import gmsh

    (L, H), (R, r), x0 = IRONING["block"], IRONING["radii"], IRONING["x0"]
    with gmsh_session():
        gmsh.model.add("ironing")
        if comm.rank == 0:
            occ = gmsh.model.occ
            block = occ.addRectangle(0, 0, 0, L, H)
            outer = occ.addDisk(x0, H + R, 0, R, R)
            inner = occ.addDisk(x0, H + R, 0, r, r)
            ring, _ = occ.cut([(2, outer)], [(2, inner)])
            die, _ = occ.cut(ring, [(2, occ.addRectangle(x0 - R - 1, H + R, 0, 2 * R + 2, R))])
            occ.synchronize()
            die_tag = die[0][1]
            gmsh.model.addPhysicalGroup(2, [block], 1)
            gmsh.model.addPhysicalGroup(2, [die_tag], 2)
            groups: dict[int, list[int]] = {
                t: [] for t in (BLOCK_TOP, BLOCK_BOTTOM, DIE_ARC, DIE_TOP)
            }
            tol = 1e-5 * L
            for _, tag in gmsh.model.getBoundary([(2, block)], oriented=False):
                y = gmsh.model.occ.getCenterOfMass(1, tag)[1]
                if abs(y - H) < tol:
                    groups[BLOCK_TOP].append(tag)
                elif abs(y) < tol:
                    groups[BLOCK_BOTTOM].append(tag)
            for _, tag in gmsh.model.getBoundary([(2, die_tag)], oriented=False):
                box = gmsh.model.getBoundingBox(1, tag)
                if abs(box[4] - box[1]) < tol and abs(box[1] - H - R) < tol:
                    groups[DIE_TOP].append(tag)
                elif box[1] < H + (R - r) / 2:
                    # The outer arc reaches down to the block's top; the inner one does not.
                    groups[DIE_ARC].append(tag)
            for tag, curves in groups.items():
                gmsh.model.addPhysicalGroup(1, curves, tag)
            if die_h is None or die_h == h:
                gmsh.option.setNumber("Mesh.MeshSizeMax", h)
                gmsh.option.setNumber("Mesh.MeshSizeMin", h)
            else:
                field = gmsh.model.mesh.field.add("Constant")
                gmsh.model.mesh.field.setNumber(field, "VIn", die_h)
                gmsh.model.mesh.field.setNumber(field, "VOut", h)
                gmsh.model.mesh.field.setNumbers(field, "SurfacesList", [die_tag])
                gmsh.model.mesh.field.setAsBackgroundMesh(field)
                for option in ("FromPoints", "FromCurvature", "ExtendFromBoundary"):
                    gmsh.option.setNumber(f"Mesh.MeshSize{option}", 0)
            gmsh.model.mesh.generate(2)
        return model_to_mesh(gmsh.model, comm, 0, gdim=2)


def _held_force(F: dolfinx.fem.Form, dofs: np.ndarray, V: dolfinx.fem.FunctionSpace) -> np.ndarray:
    """The force on the held dofs ``dofs`` (blocks): the residual there, summed (collective)."""
    R = dolfinx.fem.petsc.assemble_vector(F)
    R.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    n = V.dofmap.index_map.size_local
    local = R.array_r.reshape(-1, 2)[dofs[dofs < n]].sum(axis=0)
    R.destroy()
    return V.mesh.comm.allreduce(local, op=MPI.SUM)


def ironing(
    comm: MPI.Comm,
    h: float,
    method: str = "segment-to-segment",
    press_steps: int = 14,
    slide_steps: int = 40,
    log: typing.Callable[[str], None] | None = None,
    contactor: str = "block",
    die_h: float | None = None,
    probe_steps: int = 0,
) -> dict[str, typing.Any]:
    """The ironing study on triangles of size ``h``: the die's force at every step.

    Newton with the full tangent for either method. ``contactor``: the surface that
    carries the multiplier, ``"block"`` (its top; the die's outer arc is the target) or
    ``"die"`` (its outer arc, on the block's top). ``die_h``: the die's triangles' size
    (default ``h``). ``probe_steps``: :func:`newton_order_probe` at the solution of every
    ``probe_steps``-th step (three more Newton iterations each), not only at the end
    (0).

    Returns:
        ``s`` and ``d`` (the die's slide and press), ``fx`` and ``fy`` (the force on the
        die's top ends), ``h`` and ``die_h``, ``iterations`` and ``orders`` per step,
        ``probes`` (per step, the probe's order and whether its set settled, or ``None``
        where it was not probed),
        ``probe`` (:func:`newton_order_probe` at the end of the slide), ``oscillation``,
        ``raw_oscillation`` and ``horizontal_oscillation`` (see :func:`oscillation`),
        ``unknowns``,
        ``contact_facets`` and ``seconds``.
    """
    begin = time.perf_counter()
    mesh, cell_tags, facet_tags = ironing_mesh(comm, h, die_h)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    u = dolfinx.fem.Function(V, name="u")
    dx = ufl.Measure("dx", domain=mesh, subdomain_data=cell_tags)
    energy = neo_hookean(u, *IRONING["block_material"]) * dx(1)
    energy += neo_hookean(u, *IRONING["die_material"]) * dx(2)
    F = ufl.derivative(energy, u, ufl.TestFunction(V))
    motion = dolfinx.fem.Function(V)
    mesh.topology.create_connectivity(1, 2)
    held = dolfinx.fem.locate_dofs_topological(V, 1, facet_tags.find(DIE_TOP))
    clamped = dolfinx.fem.locate_dofs_topological(V, 1, facet_tags.find(BLOCK_BOTTOM))
    bcs = [
        dolfinx.fem.dirichletbc(dolfinx.fem.Function(V), clamped),
        dolfinx.fem.dirichletbc(motion, held),
    ]
    surfaces = [contact_surface(V, facet_tags, tag) for tag in (BLOCK_TOP, DIE_ARC)]
    if contactor not in ("block", "die"):
        raise ValueError(f"contactor must be 'block' or 'die', not {contactor!r}")
    pair = contact_pair(*(surfaces if contactor == "block" else surfaces[::-1]), method=method)
    linearization = "full"
    press, slide = IRONING["press"], IRONING["slide"]
    path = [(0.0, press * k / press_steps) for k in range(1, press_steps + 1)]
    path += [(slide * k / slide_steps, press) for k in range(1, slide_steps + 1)]
    record: dict[str, typing.Any] = {k: [] for k in ("s", "d", "fx", "fy", "iterations")}
    record["orders"], record["probes"] = [], []
    # The die is 1000 times stiffer than the block: 1e-3 of the slide on it moves the
    # forces past their scale, outside the range where the slope means an order.
    sizes = (1e-4, 1e-5, 1e-6)
    form = dolfinx.fem.form(F)
    with NonlinearContactProblem(
        F,
        u,
        [pair],
        bcs,
        linearization=linearization,
        max_iterations=80,
        petsc_options_prefix=f"ironing_{method[:4]}_{contactor}_",
    ) as problem:
        for k, (s, d) in enumerate(path, start=1):
            motion.x.array.reshape(-1, 2)[:] = [s, -d]
            problem.solve()
            fx, fy = _held_force(form, held, V)
            step = problem.step
            record["s"].append(s)
            record["d"].append(d)
            record["fx"].append(float(fx))
            record["fy"].append(float(fy))
            record["iterations"].append(len(step.iterations) - 1)
            record["orders"].append(step.orders)
            probed = probe_steps > 0 and k % probe_steps == 0
            probe = newton_order_probe(problem, sizes) if probed else None
            record["probes"].append(None if probe is None else [probe["order"], probe["settled"]])
            if log is not None:
                log(
                    f"ironing h = {h:g} {method}: s = {s:.2f}, d = {d:.2f}: force "
                    f"({fx:+.5f}, {fy:+.5f}), {len(step.iterations) - 1} iterations"
                )
        record["probe"] = newton_order_probe(problem, sizes) if probe is None else probe
    record.update(
        scene="ironing",
        h=h,
        die_h=h if die_h is None else die_h,
        method=method,
        contactor=contactor,
        linearization=linearization,
        unknowns=2 * V.dofmap.index_map.size_global,
        contact_facets=comm.allreduce(
            int(facet_tags.find(BLOCK_TOP if contactor == "block" else DIE_ARC).size), op=MPI.SUM
        ),
        oscillation=oscillation(record),
        raw_oscillation=oscillation(record, raw=True),
        horizontal_oscillation=oscillation(record, "fx"),
        seconds=comm.allreduce(time.perf_counter() - begin, op=MPI.MAX),
    )
    return record


def steady_window(record: dict[str, typing.Any]) -> npt.NDArray[np.bool_]:
    """The pressed steps of an ironing record with ``s`` in :data:`IRONING`'s ``"steady"``."""
    s, d = np.asarray(record["s"]), np.asarray(record["d"])
    low, high = IRONING["steady"]
    return (d == IRONING["press"]) & (s >= low - 1e-12) & (s <= high + 1e-12)


def oscillation(record: dict[str, typing.Any], component: str = "fy", raw: bool = False) -> float:
    """A force component's oscillation over the steady slide (see the module's text).

    The range of ``component`` (``"fy"`` or ``"fx"``) minus its least-squares quartic in
    ``s`` (``raw``: the range itself), over the :func:`steady_window`, divided by the mean
    of ``|fy|`` there (the horizontal force changes sign). NaN with fewer than 8 steps in
    the window.
    """
    s, f, fy = (np.asarray(record[k]) for k in ("s", component, "fy"))
    window = steady_window(record)
    if np.count_nonzero(window) < 8:
        return math.nan
    x, y = s[window], f[window]
    deviation = y if raw else y - np.polyval(np.polyfit(x, y, 4), x)
    return float(np.ptp(deviation) / np.mean(np.abs(fy[window])))


def newton_order_probe(
    problem: NonlinearContactProblem, sizes: typing.Sequence[float] = (1e-3, 1e-4, 1e-5)
) -> dict[str, typing.Any]:
    r"""Newton's local order at a converged state, from starts at known distances.

    The three-point order :math:`\log(r_{k+1}/r_k) / \log(r_k/r_{k-1})` of one step's
    residuals assumes one constant :math:`C` in :math:`r_{k+1} = C r_k^p`; with the
    two or three iterations a step has between its first guess and round-off, a
    :math:`C` that changes with the direction of the error (measured on the P2 sliding
    patch: 0.15 then 1.5) moves it far from :math:`p`. Here the start is the converged
    :math:`\mathbf u^*` plus :math:`\varepsilon\, \|\mathbf u^*\|_\infty\, \mathbf w`
    for each size :math:`\varepsilon` (``w`` a fixed smooth field of the coordinates,
    so the same on any partition; the multipliers at their converged values): its
    residual :math:`r_1`, and :math:`r_2` after one Newton iteration with the full
    tangent (``solve(tangent_first=True, iterations=1)``) that left the active set
    alone; :math:`p` is the slope of :math:`\log r_2` against :math:`\log r_1` over
    the sizes (one direction of the error, so one :math:`C`; not after an iteration
    without the tangent, which turns the error's direction with its size). The state (displacements,
    multipliers, active sets and :attr:`~NonlinearContactProblem.step`) is restored
    afterwards, so the next load step starts where the solve left it (collective).

    Returns:
        ``order``, the pairs ``r1`` and ``r2`` per size (absolute: the force scale moves
        with the start), ``sizes``, ``settled`` (at every size the iteration took the
        tangent and changed no active multiplier) and ``above_floor`` (every
        :math:`r_2` a hundred times above the residual Newton stopped at, which may be
        anything up to its ``rtol``: a weak guard, not a round-off floor; the tests do
        not assert it).
    """
    u = problem.u
    floor = problem.step.iterations[-1] if problem.step.iterations else None
    if floor is None or not problem.step.converged:
        raise ValueError("probe a converged state: call solve() first")
    step = problem.step
    saved = [ui.x.array.copy() for ui in u]
    multipliers = [f.x.array.copy() for f in problem.multipliers]
    active = [f.x.array.copy() for f in problem.active]
    scale = problem.comm.allreduce(
        max(float(np.max(np.abs(a), initial=0.0)) for a in saved), op=MPI.MAX
    )

    def field(x):
        return np.stack(
            [
                np.sin(3.1 * x[i] + 1.7 * x[(i + 1) % x.shape[0]] + 0.3 * i)
                for i in range(u[0].function_space.mesh.geometry.dim)
            ]
        )

    directions = []
    for ui in u:
        w = dolfinx.fem.Function(ui.function_space)
        w.interpolate(field)
        directions.append(w.x.array.copy())
    r1, r2, settled = [], [], True
    try:
        for eps in sizes:
            for ui, base, w in zip(u, saved, directions, strict=True):
                ui.x.array[:] = base + eps * scale * w
            for functions, arrays in ((problem.multipliers, multipliers), (problem.active, active)):
                for f, a in zip(functions, arrays, strict=True):
                    f.x.array[:] = a
            problem.solve(tangent_first=True, iterations=1)
            its = problem.step.iterations
            if len(its) < 2:
                raise RuntimeError(
                    f"the probe's start at size {eps:g} had converged already: take larger sizes"
                )
            # Absolute residuals: the force scale moves with the start.
            r1.append(its[0].residual * its[0].scale)
            r2.append(its[1].residual * its[1].scale)
            # A start that moved the active set (or whose set cycled with the tangent, so
            # the iteration went without it) says nothing about the order.
            settled &= not (its[0].changed or its[0].frozen)
    finally:
        for functions, arrays in (
            (u, saved),
            (problem.multipliers, multipliers),
            (problem.active, active),
        ):
            for f, a in zip(functions, arrays, strict=True):
                f.x.array[:] = a
        problem.step = step
    order = float(np.polyfit(np.log(r1), np.log(r2), 1)[0])
    above_floor = min(r2) >= 100 * floor.residual * floor.scale
    return {
        "order": order,
        "r1": r1,
        "r2": r2,
        "sizes": list(sizes),
        "settled": settled,
        "above_floor": bool(above_floor),
    }

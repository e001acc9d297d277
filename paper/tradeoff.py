# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The speed-accuracy trade: wall time against error for every method and solver.

Every discretization of :func:`~dolfinx_contact_s2s.contact_pairs` (node-to-segment
with unit and tributary weights, at Gauss points, two-pass, the intermediate surface,
segment-to-segment with plain and composite Gauss and Newton-Cotes rules of 1 to 4
points; :data:`METHODS`) and every algorithm of
:class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem` (:data:`SOLVERS`:
active set, SNES VI, penalty at several :math:`\kappa`, augmented Lagrangian) is run
on the same meshes of three scenes, and its error and wall time recorded:

- ``"patch"``: the non-matching contact patch test (section 3.2, Figs. 4 and 6;
  :mod:`~paper.patch_test`), ``10n/7n`` elements along the
  contact, solved as unilateral contact (every multiplier ends active). Errors:
  ``pressure`` :math:`\max|\lambda - p|/p` (as
  :func:`~paper.patch_test.errors` defines it), ``stress``
  :math:`\max|\sigma - \sigma_{exact}|/p` and ``displacement``
  :math:`\max|u - u_{exact}| / \max|u_{exact}|`.
- ``"hertz"``: the Hertz line contact (:mod:`~paper.hertz.study`),
  ``n`` elements across the contact width. Errors: ``pressure_l2`` (relative
  :math:`L^2` over :math:`[-a, a]`), ``a`` and ``p0`` (relative), all read from the
  multiplier (:func:`~paper.hertz.exact.measure`).
- ``"fig16"``: the smooth variant of Fig. 16 (:mod:`~paper.fig16`),
  the inf-sup model of Fig. 2 with :math:`g_0 = 0` under a cosine top displacement,
  nested structured quadrilaterals, ``10n/7n`` elements along the contact. It is tied
  (:class:`~dolfinx_contact_s2s.problem.LinearContactProblem`, solver ``"tied"``), as
  the study of Fig. 16 solves it: the pressure is compressive everywhere, so the tied
  solution is the unilateral one and the unilateral solvers have nothing to decide.
  Errors against the closed-form solution
  (:class:`~paper.fig16.SmoothSolution`): ``energy_norm``
  :math:`\|\mathbf u - \mathbf u_h\|_E / \|\mathbf u\|_E` and ``strain_energy``
  :math:`|E - E_h|/E`, read from the displacements alone, so every discretization is
  measured (the two passes and the intermediate surface too).

Wall time: the stages of :attr:`~dolfinx_contact_s2s.problem.LinearContactProblem.timings`
(``stiffness``, ``contact``, ``system``, ``solve``; largest over the processes), and
``total``, from creating the contact pairs to the solved problem (the meshes are built
once per level and shared by every method); ``setup`` is ``total`` minus the stages
(pairs, forms, the problem's set-up). Each is the minimum over ``repeats`` runs.

:func:`pareto` marks the runs no other run of the same scene beats in both time and
error. This module needs petsc4py and is imported explicitly.
"""

from __future__ import annotations

import math
import time
import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s.pair import ContactPair, contact_pairs
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.surface import contact_surface
from dolfinx_contact_s2s.unilateral import DEFAULT_PENALTY, UnilateralContactProblem
from paper.blocks import (
    MATERIALS,
    NAMES,
    block_forms,
    block_pairs,
    block_spaces,
)
from paper.fig16 import (
    Fig16Model,
    energy_norm_error,
    fig16_model,
    strain_energy,
)
from paper.hertz.exact import measure
from paper.hertz.study import HertzCase, HertzModel, hertz_model
from paper.patch_test import (
    PatchTestCase,
    PatchTestSolution,
    errors,
    exact_displacement,
    nodal_pressure,
)
from paper.scenes import PatchTestScene, patch_test

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.analysis.dense import Solvability

__all__ = [
    "CELLS",
    "ERRORS",
    "METHODS",
    "PRIMARY",
    "SCENES",
    "SOLVERS",
    "TIED",
    "TIMES",
    "TradeoffRun",
    "cheapest",
    "describe",
    "fig16_levels",
    "grid",
    "guide",
    "hertz_levels",
    "markdown",
    "pareto",
    "patch_levels",
    "plot",
    "run_study",
]


def _methods() -> dict[str, dict[str, typing.Any]]:
    out: dict[str, dict[str, typing.Any]] = {
        "NTS, w = 1": {"method": "node-to-segment", "weight": "unit"},
        "NTS, tributary w": {"method": "node-to-segment", "weight": "tributary"},
        "NTS at Gauss points": {"method": "node-to-segment-gauss"},
        "two-pass NTS": {"method": "two-pass node-to-segment"},
        "intermediate surface": {"method": "intermediate-surface"},
    }
    for kind, name, first in (
        ("composite-gauss", "S2S composite Gauss", 1),
        ("composite-newton-cotes", "S2S composite Newton-Cotes", 2),
        ("gauss", "S2S Gauss", 1),
        ("newton-cotes", "S2S Newton-Cotes", 2),
    ):
        for n in range(first, 5):
            out[f"{name} {n}"] = {
                "method": "segment-to-segment",
                "quadrature": kind,
                "quadrature_points": n,
            }
    return out


#: Every discretization of the study: a label and the options of ``contact_pairs``.
#: Segment-to-segment has :math:`\mathcal M^1_{h,k}` on :math:`P_k` (the default).
METHODS: dict[str, dict[str, typing.Any]] = _methods()

#: Every solver: a label, the ``algorithm`` and the penalty factor :math:`\kappa`.
SOLVERS: dict[str, tuple[str, float | None]] = {
    "active-set": ("active-set", None),
    "snes-vi": ("snes-vi", None),
    "augmented-lagrangian": ("augmented-lagrangian", None),
    "penalty 1e1": ("penalty", 10.0),
    "penalty 1e2": ("penalty", 100.0),
    "penalty 1e3": ("penalty", 1000.0),
    "penalty 1e4": ("penalty", 10000.0),
}

#: The solver label of the tied solve (:class:`LinearContactProblem`, Fig. 16 only).
TIED = "tied"

#: The scenes of the study.
SCENES = ("patch", "hertz", "fig16")

#: The default cell of each scene (Fig. 16's meshes are nested structured quadrilaterals).
CELLS = {"patch": "triangle", "hertz": "triangle", "fig16": "quadrilateral"}

#: The errors of each scene; :data:`PRIMARY` is the one the Pareto front uses.
ERRORS = {
    "patch": ("pressure", "stress", "displacement"),
    "hertz": ("pressure_l2", "a", "p0"),
    "fig16": ("energy_norm", "strain_energy"),
}
PRIMARY = {"patch": "pressure", "hertz": "pressure_l2", "fig16": "energy_norm"}

#: The recorded wall times (s).
TIMES = ("stiffness", "contact", "system", "solve", "setup", "total")


@dataclass(frozen=True)
class TradeoffRun:
    """One point of the study.

    Attributes:
        scene: One of :data:`SCENES`.
        method: A label of :data:`METHODS`.
        degree: Displacement degree (of both bodies).
        solver: A label of :data:`SOLVERS`, or :data:`TIED` (Fig. 16).
        level: ``n``: ``10n/7n`` elements (patch, Fig. 16) or ``n`` across the contact
            (Hertz).
        cell: ``"triangle"`` or ``"quadrilateral"``.
    """

    scene: str
    method: str
    degree: int
    solver: str
    level: int
    cell: str = "triangle"

    @property
    def options(self) -> dict[str, typing.Any]:
        """Options of ``contact_pairs``."""
        return dict(METHODS[self.method])

    def applies(self) -> str | None:
        """Why the run does not apply, or None."""
        if self.options["method"] == "intermediate-surface" and self.degree != 1:
            return "the intermediate surface is for linear surfaces"
        if (self.scene == "fig16") != (self.solver == TIED):
            return "Fig. 16 is solved tied, the other scenes by a unilateral solver"
        return None


def patch_levels(level: int) -> tuple[int, int]:
    """Elements along the contact, lower and upper block: ``10n/7n`` (non-matching)."""
    return (10 * level, 7 * level)


def hertz_levels(level: int) -> int:
    """Elements across the Hertz contact width."""
    return level


def fig16_levels(level: int) -> tuple[int, int]:
    """Elements along the contact of Fig. 16, lower and upper block (``n`` even: nested)."""
    return (10 * level, 7 * level)


def _max(comm: MPI.Comm, value: float) -> float:
    return comm.allreduce(float(value), op=MPI.MAX)


def _problem(
    a, L, pairs, bcs, solver: str, prefix: str
) -> LinearContactProblem | UnilateralContactProblem:
    if solver == TIED:
        return LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix=prefix)
    algorithm, kappa = SOLVERS[solver]
    return UnilateralContactProblem(
        a,
        L,
        pairs,
        bcs,
        petsc_options_prefix=prefix,
        algorithm=algorithm,
        penalty=kappa,
        max_iterations=200,
    )


def _unknowns(problem: UnilateralContactProblem) -> int:
    n = sum(V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces)
    return n + sum(p.Q.dofmap.index_map.size_global for p in problem.pairs)


class _Timer:
    """Minimum over repeats of each stage (largest over the processes)."""

    def __init__(self):
        self.best: dict[str, float] = {}

    def add(self, comm: MPI.Comm, timings: dict[str, float], total: float) -> None:
        times = {k: _max(comm, v) for k, v in timings.items()}
        times["total"] = _max(comm, total)
        times["setup"] = max(times["total"] - sum(timings[k] for k in timings), 0.0)
        for k, v in times.items():
            self.best[k] = min(self.best.get(k, math.inf), v)


def _run(
    run: TradeoffRun,
    comm: MPI.Comm,
    build: Callable[[], tuple[list[ContactPair], typing.Any]],
    measure_errors: Callable[[UnilateralContactProblem, list[ContactPair]], dict],
    repeats: int,
) -> dict:
    """Build and solve ``repeats`` times; errors of the last solve, minimal times."""
    algorithm, kappa = SOLVERS.get(run.solver, (run.solver, None))
    record: dict[str, typing.Any] = {
        "scene": run.scene,
        "method": run.method,
        "options": run.options,
        "degree": run.degree,
        "cell": run.cell,
        "solver": run.solver,
        "algorithm": algorithm,
        # The penalty factor of the unilateral algorithms; none for the tied solve.
        "kappa": kappa if kappa is not None else DEFAULT_PENALTY.get(algorithm),
        "level": run.level,
        "ranks": comm.size,
    }
    reason = run.applies()
    if reason:
        return record | {"skipped": reason}
    timer = _Timer()
    stage = "solve"
    try:
        for _ in range(repeats):
            stage = "solve"
            begin = time.perf_counter()
            pairs, forms = build()
            with _problem(*forms[:2], pairs, forms[2], run.solver, "tradeoff_") as problem:
                problem.solve()
                total = time.perf_counter() - begin
                timer.add(comm, problem.timings, total)
                record["unknowns"] = _unknowns(problem)
                history = getattr(problem, "history", None)
                record["iterations"] = history.iterations if history is not None else 1
                record["multiplier"] = pairs[0].multiplier_label
                stage = "measure"
                errs = measure_errors(problem, pairs)
    except (ValueError, RuntimeError) as e:
        # Raised on every process (the package's checks, solver failures, a multiplier
        # the scene's measures cannot read).
        record["failed"] = f"{stage}: {str(e).splitlines()[0][:200]}"
        if timer.best:
            record["seconds"] = timer.best
        return record
    record["errors"] = errs
    record["error"] = errs.get(PRIMARY[run.scene])
    record["seconds"] = timer.best
    return record


# --- the patch test -----------------------------------------------------------------


def _patch_run(comm: MPI.Comm, scene: PatchTestScene, run: TradeoffRun, repeats: int) -> dict:
    case = PatchTestCase(
        degrees=(run.degree, run.degree),
        elements=patch_levels(run.level),
        cell=run.cell,
        contactor="upper",
        **run.options,
    )

    def build():
        spaces = block_spaces(scene, case.degrees)
        a, L, bcs = block_forms(scene, spaces, support="rollers", pressure=case.pressure)
        pairs = block_pairs(scene, spaces, case.contactor, **run.options)
        return pairs, (a, L, bcs)

    def measure_patch(problem: UnilateralContactProblem, pairs: list[ContactPair]) -> dict:
        from dolfinx_contact_s2s.elasticity import stress_function

        u = dict(zip(NAMES, problem.u, strict=True))
        forces = dict(zip(NAMES, problem.contact_forces(), strict=True))
        nodal = {n: nodal_pressure(scene.bodies[n], forces[n]) for n in NAMES}
        stress = {n: stress_function(u[n], MATERIALS[n]) for n in NAMES}
        # The released multipliers (none, when every one stays in contact) count as
        # inactive, beside those that carry no constraint.
        inactive = []
        for op, act in zip(problem.operators, problem.active, strict=True):
            imap = act.function_space.dofmap.index_map
            off = np.flatnonzero(act.x.array[: imap.size_local] == 0) + imap.local_range[0]
            inactive.append(np.union1d(op.inactive, off.astype(np.int64)))
        solvability = typing.cast("Solvability", None)
        solution = PatchTestSolution(
            case,
            scene,
            pairs,
            solvability,
            u,
            stress,
            list(problem.multipliers),
            nodal,
            inactive,
        )
        err = errors(solution)
        e_u = scale = 0.0
        for name, f in u.items():
            ref = f.copy()
            ref.interpolate(exact_displacement(case, scene.height, name))
            e_u = max(e_u, float(np.max(np.abs(f.x.array - ref.x.array), initial=0.0)))
            scale = max(scale, float(np.max(np.abs(ref.x.array), initial=0.0)))
        e_u = _max(comm, e_u) / _max(comm, scale)
        return {"pressure": err.pressure, "stress": err.stress, "displacement": e_u}

    record = _run(run, comm, build, measure_patch, repeats)
    record["elements"] = list(case.elements)
    record["h"] = 1.0 / case.elements[1]
    return record


# --- Hertz --------------------------------------------------------------------------


def _pressure(pair: ContactPair, lam: dolfinx.fem.Function) -> dolfinx.fem.Function:
    """The multiplier as a pressure: nodal forces (unit weights) over tributary lengths."""
    if not (pair.nodal and pair.weight == "unit"):
        return lam
    Q = lam.function_space
    length = dolfinx.fem.assemble_vector(
        dolfinx.fem.form(ufl.TestFunction(Q) * ufl.dx(domain=Q.mesh))
    )
    length.scatter_reverse(dolfinx.la.InsertMode.add)
    length.scatter_forward()
    p = dolfinx.fem.Function(Q)
    with np.errstate(divide="ignore", invalid="ignore"):
        p.x.array[:] = np.where(length.array > 0, lam.x.array / length.array, 0.0)
    return p


def _hertz_run(comm: MPI.Comm, model: HertzModel, run: TradeoffRun, repeats: int) -> dict:
    exact = model.case.exact
    tags, ft = model.scene.tags, model.scene.facet_tags

    def build():
        pairs = contact_pairs(
            contact_surface(model.V, ft, tags["contactor"]),
            contact_surface(model.V, ft, tags["target"]),
            **run.options,
        )
        return pairs, (model.a, model.L, model.bcs)

    def measure_hertz(problem: UnilateralContactProblem, pairs: list[ContactPair]) -> dict:
        if len(pairs) > 1:
            raise ValueError("not measured: the two passes split the pressure between them")
        m = measure(_pressure(pairs[0], problem.multipliers[0]), exact)
        return {
            "pressure_l2": m.pressure_l2_error,
            "a": abs(m.a_moment / exact.a - 1),
            "p0": abs(m.p0_error),
        }

    record = _run(run, comm, build, measure_hertz, repeats)
    record["elements_across"] = run.level
    record["h"] = model.scene.h
    return record


# --- Fig. 16 ------------------------------------------------------------------------


def _fig16_run(comm: MPI.Comm, model: Fig16Model, run: TradeoffRun, repeats: int) -> dict:
    exact = model.exact
    assert exact is not None  # the smooth variant
    energy, norm = exact.energy, math.sqrt(2 * exact.energy)

    def build():
        # Upper block the contactor, as in Fig. 16.
        pairs = block_pairs(model.scene, model.spaces, "upper", **run.options)
        return pairs, (model.a, model.L, model.bcs)

    def measure_fig16(problem: LinearContactProblem, pairs: list[ContactPair]) -> dict:
        return {
            "energy_norm": energy_norm_error(problem, exact) / norm,
            "strain_energy": abs(energy - strain_energy(problem)) / energy,
        }

    record = _run(run, comm, build, measure_fig16, repeats)
    record["elements"] = list(fig16_levels(run.level))
    record["h"] = model.scene.width / fig16_levels(run.level)[1]
    return record


# --- the study ----------------------------------------------------------------------


def run_study(
    comm: MPI.Comm,
    runs: Sequence[TradeoffRun],
    *,
    repeats: int = 2,
    log: Callable[[str], None] | None = None,
) -> list[dict]:
    """Run every :class:`TradeoffRun`; one record each (collective).

    The meshes of a scene, degree, cell and level are built once and shared.

    Returns:
        The records of ``results/tradeoff.json``: scene, method, options, degree, cell,
        solver, algorithm, kappa, level, h, unknowns, iterations, ``errors`` (every
        error of the scene), ``error`` (the primary one, :data:`PRIMARY`),
        ``seconds`` (:data:`TIMES`), ranks; or ``failed``/``skipped`` with the reason.
    """
    out = []
    order = sorted(range(len(runs)), key=lambda i: (runs[i].scene, runs[i].degree, runs[i].level))
    scenes: dict[tuple, typing.Any] = {}
    for count, i in enumerate(order, 1):
        run = runs[i]
        if run.scene not in SCENES:
            raise ValueError(f"unknown scene {run.scene!r}; choose from {SCENES}")
        key = (run.scene, run.degree, run.cell, run.level)
        if key not in scenes:
            scenes.clear()
            if run.scene == "patch":
                scenes[key] = patch_test(comm, patch_levels(run.level), cell=run.cell)
            elif run.scene == "fig16":
                scenes[key] = fig16_model(comm, run.degree, run.cell, "smooth", run.level)
            else:
                case = HertzCase(
                    degree=run.degree, cell=run.cell, elements_across=hertz_levels(run.level)
                )
                scenes[key] = hertz_model(case, comm)
        if run.scene == "patch":
            record = _patch_run(comm, scenes[key], run, repeats)
        elif run.scene == "fig16":
            record = _fig16_run(comm, scenes[key], run, repeats)
        else:
            record = _hertz_run(comm, scenes[key], run, repeats)
        out.append((i, record))
        if log is not None:
            log(f"[{count}/{len(runs)}] {describe(record)}")
    return [r for _, r in sorted(out, key=lambda t: t[0])]


def describe(record: dict) -> str:
    """One line of a record for the terminal."""
    head = (
        f"{record['scene']} P{record['degree']} n={record['level']} {record['method']}, "
        f"{record['solver']}"
    )
    if "skipped" in record or "failed" in record:
        return f"{head}: {record.get('skipped') or record.get('failed')}"
    return (
        f"{head}: {PRIMARY[record['scene']]} error {record['error']:.2e}, "
        f"{record['seconds']['total']:.3f} s ({record['unknowns']} unknowns)"
    )


def pareto(records: Sequence[dict], floor: float = 1e-14) -> None:
    """Mark ``record["pareto"]``: no run of the same scene and ranks is faster and better.

    Errors below ``floor`` (round-off) count as equal.
    """
    groups: dict[tuple, list[dict]] = {}
    for r in records:
        if r.get("error") is not None:
            groups.setdefault((r["scene"], r["ranks"]), []).append(r)
    for group in groups.values():
        for r in group:
            e, t = max(r["error"], floor), r["seconds"]["total"]
            r["pareto"] = not any(
                (max(o["error"], floor) <= e and o["seconds"]["total"] <= t)
                and (max(o["error"], floor) < e or o["seconds"]["total"] < t)
                for o in group
            )


def _family(method: str) -> str:
    for prefix in ("S2S composite", "S2S", "two-pass", "NTS", "intermediate"):
        if method.startswith(prefix):
            return prefix
    return method


def plot(path: Path | str, records: Sequence[dict], scene: str) -> None:
    """Log-log error against total wall time of a scene, the Pareto front drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in records if r["scene"] == scene and r.get("error") is not None]
    fig, ax = plt.subplots(figsize=(8, 5.5))
    colours = {
        "S2S composite": "tab:blue",
        "S2S": "tab:cyan",
        "NTS": "tab:red",
        "two-pass": "tab:orange",
        "intermediate": "tab:green",
    }
    floor = 1e-16
    for family, colour in colours.items():
        for degree, marker in ((1, "o"), (2, "s")):
            for lagrange in (True, False):
                sel = [
                    r
                    for r in rows
                    if _family(r["method"]) == family
                    and r["degree"] == degree
                    and (r["algorithm"] in ("active-set", "snes-vi", TIED)) == lagrange
                ]
                if not sel:
                    continue
                ax.scatter(
                    [r["seconds"]["total"] for r in sel],
                    [max(r["error"], floor) for r in sel],
                    c=colour if lagrange else "none",
                    edgecolors=colour,
                    marker=marker,
                    s=28,
                    label=f"{family} P{degree}" + ("" if lagrange else " (penalty/AL)"),
                )
    front = sorted(
        (r for r in rows if r.get("pareto")), key=lambda r: (r["seconds"]["total"], r["error"])
    )
    if front:
        ax.step(
            [r["seconds"]["total"] for r in front],
            [max(r["error"], floor) for r in front],
            where="post",
            color="k",
            lw=1,
            label="Pareto front",
        )
        # One label per step of the front: runs with the same error within 1% (the rules
        # that integrate the same polynomials exactly) share the first one's label.
        steps: list[list[dict]] = []
        for r in front:
            e = max(r["error"], floor)
            if steps and abs(e - max(steps[-1][0]["error"], floor)) <= 0.01 * e:
                steps[-1].append(r)
            else:
                steps.append([r])
        for step in steps:
            r = step[0]
            ax.annotate(
                f"{r['method']} P{r['degree']} n={r['level']}"
                + ("" if r["solver"] in ("active-set", TIED) else f" {r['solver']}")
                + (f" (+{len(step) - 1} alike)" if len(step) > 1 else ""),
                (r["seconds"]["total"], max(r["error"], floor)),
                fontsize=6,
                xytext=(3, 3),
                textcoords="offset points",
            )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time (s, min over repeats)")
    ranks = sorted({r["ranks"] for r in rows})
    ax.set_ylabel(f"{PRIMARY[scene]} error")
    ax.set_title(f"{scene}: error against wall time, {ranks} rank(s)")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)


def markdown(records: Sequence[dict], scene: str, *, only_front: bool = False) -> list[str]:
    """A Markdown table of the scene's records, fastest first."""
    names = ERRORS[scene]
    lines = [
        "| method | P | solver | n | unknowns | "
        + " | ".join(f"{e} error" for e in names)
        + " | contact s | solve s | total s | Pareto |",
        "|---|---|---|---|---|" + "---|" * len(names) + "---|---|---|---|",
    ]
    rows = [r for r in records if r["scene"] == scene]
    rows.sort(key=lambda r: r.get("seconds", {}).get("total", math.inf))
    for r in rows:
        if only_front and not r.get("pareto"):
            continue
        if r.get("errors") is None:
            why = r.get("skipped") or r.get("failed")
            blanks = [""] * (len(names) - 1 + 4)
            cells = [r["method"], str(r["degree"]), r["solver"], str(r["level"]), "", why]
            lines.append("| " + " | ".join(cells + blanks) + " |")
            continue
        s = r["seconds"]
        lines.append(
            f"| {r['method']} | {r['degree']} | {r['solver']} | {r['level']} | "
            f"{r['unknowns']} | "
            + " | ".join(f"{r['errors'][e]:.1e}" for e in names)
            + f" | {s['contact']:.3f} | {s['solve']:.3f} | {s['total']:.3f} | "
            + ("yes" if r.get("pareto") else "")
            + " |"
        )
    return lines


def cheapest(
    records: Sequence[dict],
    scene: str,
    target: float,
    family: str | None = None,
    ranks: int | None = None,
) -> dict | None:
    """The fastest run of ``scene`` whose primary error is at most ``target``.

    Args:
        records: Records of :func:`run_study`.
        scene: One of :data:`SCENES`.
        target: Largest primary error (:data:`PRIMARY`).
        family: Only methods whose label starts with this (e.g. ``"NTS"``).
        ranks: Only runs on this many processes.
    """
    rows = [
        r
        for r in records
        if r["scene"] == scene
        and r.get("error") is not None
        and r["error"] <= target
        and (family is None or r["method"].startswith(family))
        and (ranks is None or r["ranks"] == ranks)
    ]
    return min(rows, key=lambda r: r["seconds"]["total"], default=None)


def guide(records: Sequence[dict], ranks: int, targets: dict[str, Sequence[float]]) -> list[str]:
    """Markdown lines: per scene and target error, the cheapest run of each family."""
    families = (
        "S2S composite",
        "S2S Gauss",
        "S2S Newton-Cotes",
        "NTS",
        "two-pass NTS",
        "intermediate surface",
    )
    lines = [
        f"| scene | error at most | {' | '.join(families)} |",
        "|---|---|" + "---|" * len(families),
    ]
    for scene, values in targets.items():
        for target in values:
            cells = []
            for family in families:
                r = cheapest(records, scene, target, family, ranks)
                cells.append(
                    "not reached"
                    if r is None
                    else f"{r['method']} P{r['degree']} n={r['level']} {r['solver']}: "
                    f"{r['seconds']['total']:.3f} s"
                )
            lines.append(f"| {scene} ({PRIMARY[scene]}) | {target:g} | {' | '.join(cells)} |")
    return lines


def grid(
    scenes: Sequence[str],
    degrees: Sequence[int],
    levels: dict[str, Sequence[int]],
    methods: Sequence[str],
    solvers: Sequence[str],
    solver_methods: Sequence[str],
    cell: str | None = None,
) -> list[TradeoffRun]:
    """Every method with the active set, and every solver with ``solver_methods``.

    Fig. 16 runs every method tied (:data:`TIED`) and no unilateral solver. ``cell``
    defaults to :data:`CELLS` of each scene.
    """
    runs = []
    for scene in scenes:
        first = TIED if scene == "fig16" else "active-set"
        for degree in degrees:
            for level in levels[scene]:
                base = TradeoffRun(scene, methods[0], degree, first, level, cell or CELLS[scene])
                for m in methods:
                    runs.append(replace(base, method=m))
                if scene == "fig16":
                    continue
                for m in solver_methods:
                    for s in solvers:
                        if s != "active-set":
                            runs.append(replace(base, method=m, solver=s))
    return runs

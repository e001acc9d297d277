# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The solvability and inf-sup studies of section 3.1 on the model of Fig. 2.

Each discretization is evaluated on families of meshes of the inf-sup model (two
blocks, meshed independently, overlapping by :math:`-g_0`, the lower block clamped
at its bottom and the upper one at its top). A family fixes how the element counts on
the two surfaces grow with the level :math:`n`; :math:`h` is the element size on the
lower surface (as in Fig. 8). The verdicts of Tables 1-2 follow from the numbers:

- *solvable* if :math:`\mathbf B` has full rank on every mesh of every family (Eq. 35);
- *stable* if it is solvable and :math:`\beta^*_h` stays bounded away from zero as
  :math:`h \to 0` on every family and with either surface as contactor: the slope
  :math:`s` of :math:`\log \beta^*_h` against :math:`\log h`, fitted on the finer
  levels, stays below :data:`STABLE_SLOPE` (a :math:`\beta^*_h \sim h^s` with
  :math:`s > 0` decays to zero). "If any mesh configuration fails the inf-sup test,
  then the algorithm fails" (section 3).
"""

from __future__ import annotations

import typing
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass

from mpi4py import MPI

import numpy as np

from paper.blocks import block_problem
from paper.scenes import inf_sup_model

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.problem import LinearContactProblem

__all__ = [
    "FAMILIES",
    "FIT_FROM",
    "LEVELS",
    "STABLE_SLOPE",
    "TABLES",
    "InfSupCase",
    "inf_sup_problem",
    "level_record",
    "run_case",
    "slope",
    "study_cases",
    "table",
    "verdicts",
]

#: Element counts (lower, upper) on the contact surfaces at level n.
FAMILIES: dict[str, Callable[[int], tuple[int, int]]] = {
    # A fixed ratio: every level repeats the same pattern of nodes (Figs. 8, 10, 11(a)).
    "10n/7n": lambda n: (10 * n, 7 * n),
    # Fig. 11(b): nodes of the two surfaces come ever closer; at n = 2 the lower surface
    # has 10 elements and the upper one five, and the meshes match.
    "5n/(2n+1)": lambda n: (5 * n, 2 * n + 1),
}

#: Mesh levels of every study.
LEVELS = (1, 2, 3, 4, 6, 8)

#: The slope of log beta against log h is fitted on the levels n >= FIT_FROM.
FIT_FROM = 3

#: Largest fitted slope of a stable discretization.
STABLE_SLOPE = 0.3

#: Tables 1 and 2 of the paper: (displacement degree, multiplier) -> (stable, solvable).
TABLES: dict[tuple[int, tuple[str, int]], tuple[bool, bool]] = {
    (1, ("DG", 0)): (False, True),
    (1, ("Lagrange", 1)): (True, True),
    (1, ("DG", 1)): (False, False),
    (2, ("DG", 0)): (True, True),
    (2, ("Lagrange", 1)): (True, True),
    (2, ("DG", 1)): (False, True),
    (2, ("Lagrange", 2)): (True, True),
    (2, ("DG", 2)): (False, False),
}


@dataclass(frozen=True)
class InfSupCase:
    """A discretization on one family of the inf-sup model.

    Attributes:
        method: As for :func:`~dolfinx_contact_s2s.contact_pairs`, including
            ``"two-pass node-to-segment"``.
        multiplier: Multiplier space, e.g. ``("DG", 0)``; ``None`` for the default.
        degree: Displacement degree of both bodies.
        family: Key of :data:`FAMILIES`.
        contactor: ``"upper"`` or ``"lower"``.
        cell: ``"triangle"`` or ``"quadrilateral"``.
        weight: ``"unit"`` or ``"tributary"``, for node-to-segment.
    """

    method: str = "segment-to-segment"
    multiplier: tuple[str, int] | None = None
    degree: int = 1
    family: str = "10n/7n"
    contactor: str = "upper"
    cell: str = "quadrilateral"
    weight: str = "unit"

    def record(self) -> dict:
        """The case as a JSON-ready dict."""
        rec = asdict(self)
        rec["multiplier"] = list(self.multiplier) if self.multiplier else None
        return rec


def inf_sup_problem(comm: MPI.Comm, case: InfSupCase, n: int) -> tuple[LinearContactProblem, float]:
    """The contact problem of ``case`` at level ``n`` and its element size :math:`h`."""
    if case.family not in FAMILIES:
        raise ValueError(f"unknown family {case.family!r}; choose from {list(FAMILIES)}")
    elements = FAMILIES[case.family](n)
    scene = inf_sup_model(comm, elements, cell=case.cell)
    # Pair facets across the overlap even where it exceeds the element size.
    options: dict[str, typing.Any] = {
        "method": case.method,
        "search_radius": abs(scene.gap) + scene.width / min(elements),
    }
    if case.multiplier is not None:
        options["multiplier"] = case.multiplier
    if case.weight != "unit":
        options["weight"] = case.weight
    problem = block_problem(
        scene,
        (case.degree, case.degree),
        case.contactor,
        support="clamped",
        petsc_options_prefix="infsup_model_",
        **options,
    )
    return problem, scene.width / elements[0]


def level_record(
    comm: MPI.Comm, case: InfSupCase, n: int, *, dense_limit: int = 2600, full: bool = True
) -> dict:
    r"""Solvability and inf-sup values of ``case`` at level ``n``.

    ``beta`` and ``pressure_modes`` come from the scalable test (one MUMPS
    factorization, SLEPc); ``rank_deficiency`` from a dense SVD of :math:`\mathbf B`
    (Eq. 35). Where the free displacements number at most ``dense_limit``, the dense
    reference of Eqs. (30)-(32) runs too (``beta_dense``, ``pressure_modes_dense``).
    ``beta_full`` is :math:`\beta_h` of Eq. (22) (with ``full``).
    """
    from dolfinx_contact_s2s.analysis.dense import inf_sup_dense, solvability
    from dolfinx_contact_s2s.analysis.infsup import InfSupTest

    problem, h = inf_sup_problem(comm, case, n)
    test = InfSupTest(problem, h)
    try:
        scalable = test.solve()
        beta_full = test.beta_full(problem) if full else None
        rec = {
            "n": n,
            "elements": list(FAMILIES[case.family](n)),
            "h": h,
            "displacements": test.displacements,
            "constraints": test.constraints,
            "beta": scalable.beta,
            "beta_full": beta_full,
            "pressure_modes": test.pressure_modes,
            "rank_deficiency": solvability(problem).redundant,
            "solves": scalable.solves,
        }
        if test.displacements <= dense_limit:
            dense = inf_sup_dense(problem, h, full=False)
            rec.update(beta_dense=dense.beta, pressure_modes_dense=dense.pressure_modes)
    finally:
        test.destroy()
        problem.destroy()
    return rec


def slope(levels: Sequence[dict]) -> float | None:
    r"""Least-squares slope of :math:`\log \beta^*_h` against :math:`\log h`.

    Fitted on the levels :math:`n \ge` :data:`FIT_FROM`; ``None`` if some
    :math:`\beta^*_h` is zero.
    """
    fine = [rec for rec in levels if rec["n"] >= FIT_FROM] or list(levels)
    if len(fine) < 2 or any(rec["beta"] <= 0 for rec in fine):
        return None
    x = np.log([rec["h"] for rec in fine])
    y = np.log([rec["beta"] for rec in fine])
    return float(np.polyfit(x, y, 1)[0])


def verdicts(levels: Sequence[dict]) -> dict:
    """``slope``, ``solvable`` and ``stable`` of one family from its level records."""
    solvable = all(rec["rank_deficiency"] == 0 for rec in levels)
    s = slope(levels) if solvable else None
    return {"slope": s, "solvable": solvable, "stable": s is not None and s < STABLE_SLOPE}


def run_case(
    comm: MPI.Comm,
    case: InfSupCase,
    levels: Sequence[int] = LEVELS,
    progress: Callable[[dict], None] | None = None,
    **options,
) -> dict:
    """Run ``case`` on ``levels``: the record of ``results/infsup.json``."""
    rec = case.record()
    rec["levels"] = []
    for n in levels:
        level = level_record(comm, case, n, **options)
        rec["levels"].append(level)
        if progress is not None:
            progress(level)
    rec.update(verdicts(rec["levels"]))
    return rec


def table(records: Sequence[dict], degree: int) -> list[dict]:
    """Table 1 (``degree`` 1) or 2 (``degree`` 2) from S2S records, beside the paper's.

    A multiplier space is solvable (stable) if it is so on every family and with
    either contactor.
    """
    rows = []
    for (k, multiplier), (stable, solvable) in TABLES.items():
        if k != degree:
            continue
        mine = [
            r
            for r in records
            if r["method"] == "segment-to-segment"
            and r["degree"] == degree
            and tuple(r["multiplier"] or ("Lagrange", degree)) == multiplier
        ]
        if not mine:
            continue
        computed_solvable = all(r["solvable"] for r in mine)
        computed_stable = computed_solvable and all(r["stable"] for r in mine)
        rows.append(
            {
                "multiplier": list(multiplier),
                "paper_stable": stable,
                "paper_solvable": solvable,
                "stable": computed_stable,
                "solvable": computed_solvable,
                "agrees": (computed_stable, computed_solvable) == (stable, solvable),
                "families": len(mine),
            }
        )
    return rows


def study_cases(families: Sequence[str] = tuple(FAMILIES)) -> list[InfSupCase]:
    """The cases of the study, on every family with either surface as contactor.

    Every multiplier of Tables 1-2 with S2S, single- and two-pass node-to-segment (Figs. 8
    and 11) and the intermediate surface.
    """
    cases = []
    for family in families:
        for contactor in ("upper", "lower"):
            base = {"family": family, "contactor": contactor}
            for degree, multiplier in TABLES:
                cases.append(InfSupCase(multiplier=multiplier, degree=degree, **base))
            for method in ("node-to-segment", "two-pass node-to-segment", "intermediate-surface"):
                cases.append(InfSupCase(method=method, **base))
    return cases

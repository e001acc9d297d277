# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The paper's patch-test matrix: every discretization, multiplier, mesh and contactor.

The verdicts of sections 4-5 beside the computed ones (:func:`case_record`); the cases
are solved by :func:`paper.patch_test.solve_patch_test`.
"""

from __future__ import annotations

import numpy as np

from paper.patch_test import PatchTestCase, PatchTestSolution, errors

__all__ = [
    "DEGREES",
    "DISCRETIZATIONS",
    "EXTRA_MULTIPLIERS",
    "PASS_TOLERANCE",
    "RATIOS",
    "case_record",
    "nested",
    "paper_verdict",
    "study_cases",
]


#: The discretizations of the study: a label and the :class:`PatchTestCase` options.
DISCRETIZATIONS: dict[str, dict] = {
    "S2S composite Gauss": {"quadrature": "composite-gauss"},
    "S2S composite Newton-Cotes": {"quadrature": "composite-newton-cotes"},
    # Fig. 15(a): second-order Gauss; its Newton-Cotes sibling is the trapezoidal rule.
    "S2S Gauss (Fig. 15a)": {"quadrature": "gauss", "quadrature_points": 2},
    "S2S Newton-Cotes (Fig. 15a)": {"quadrature": "newton-cotes", "quadrature_points": 2},
    "NTS, w = 1": {"method": "node-to-segment", "weight": "unit"},
    "NTS, tributary w": {"method": "node-to-segment", "weight": "tributary"},
    "NTS at Gauss points": {"method": "node-to-segment-gauss"},
    "two-pass NTS": {"method": "two-pass node-to-segment"},
    "intermediate surface": {"method": "intermediate-surface"},
    "node-to-node": {"method": "node-to-node"},
}

#: Multiplier spaces of Eq. (16) tried with composite S2S besides the default
#: :math:`\mathcal M^1_{h,k}`, for contactor degree ``k``.
EXTRA_MULTIPLIERS: dict[int, list[tuple[str, int]]] = {
    1: [("DG", 0), ("DG", 1)],
    2: [("DG", 0), ("Lagrange", 1), ("DG", 1), ("DG", 2)],
}

#: Degrees (lower, upper): linear on linear, quadratic on quadratic, linear on quadratic
#: (Fig. 6(b)-(d)).
DEGREES = ((1, 1), (2, 2), (2, 1))

#: Elements along the contact (lower, upper): non-nested, nested and matching.
RATIOS = ((10, 7), (7, 10), (10, 5), (3, 8), (10, 10))


def nested(elements: tuple[int, int]) -> bool:
    """Whether the nodes of one surface are among those of the other (e.g. 10/5, 10/10)."""
    a, b = elements
    return a % b == 0 or b % a == 0


def paper_verdict(label: str, case: PatchTestCase) -> str:
    """What the paper says of a case: ``"pass"``, ``"fail"`` or ``"either"``.

    Composite S2S passes whatever the meshes with the stable multiplier spaces of
    Tables 1-2 (section 5). Node-to-segment
    (section 4.2) and non-composite S2S (Fig. 15(a)) fail on meshes whose nodes do not
    nest. Two-pass node-to-segment passes for linear elements and fails for quadratic
    ones (section 4.3, Fig. 12); so does the intermediate surface for linear ones (4.4).
    Node-to-node passes on matching meshes (section 4.1).
    On nested meshes any method may pass by coincidence (cf. Fig. 11).
    """
    matching = case.elements[0] == case.elements[1]
    if label.startswith("S2S composite"):
        k = case.degrees[0] if case.contactor == "lower" else case.degrees[1]
        family, degree = case.multiplier or ("Lagrange", k)
        continuous = family == "Lagrange"
        # Tables 1-2: the stable multiplier spaces.
        stable = (continuous and degree >= 1) or (k == 2 and degree == 0)
        return "pass" if stable else "either"
    if label == "node-to-node":
        return "pass" if matching else "either"
    if label == "intermediate surface":
        return "pass"
    if label == "two-pass NTS":
        if case.degrees == (1, 1):
            return "pass"
        if case.degrees == (2, 2) and not nested(case.elements):
            return "fail"
        return "either"
    return "either" if nested(case.elements) else "fail"


def study_cases(
    cells: tuple[str, ...] = ("triangle", "quadrilateral"),
    ratios: tuple[tuple[int, int], ...] = RATIOS,
) -> list[tuple[str, PatchTestCase]]:
    """The patch-test matrix: every discretization, multiplier, mesh and contactor."""
    out = []
    for degrees in DEGREES:
        for cell in cells:
            for elements in ratios:
                for contactor in ("upper", "lower"):
                    base = {"degrees": degrees, "cell": cell, "elements": elements}
                    base["contactor"] = contactor
                    k = degrees[0] if contactor == "lower" else degrees[1]
                    for label, options in DISCRETIZATIONS.items():
                        if label == "node-to-node" and (
                            elements[0] != elements[1] or degrees[0] != degrees[1]
                        ):
                            continue
                        if label == "intermediate surface" and degrees != (1, 1):
                            continue
                        out.append((label, PatchTestCase(**base, **options)))
                    for multiplier in EXTRA_MULTIPLIERS[k]:
                        out.append(
                            ("S2S composite Gauss", PatchTestCase(**base, multiplier=multiplier))
                        )
    return out


def case_record(label: str, case: PatchTestCase, solution: PatchTestSolution) -> dict:
    """JSON record of a solved (or unsolvable) case, with the paper's verdict beside it."""
    rec = case.record()
    rec["discretization"] = label
    rec["method"] = label
    rec["multiplier"] = solution.pair.multiplier_label
    rec["paper"] = paper_verdict(label, case)
    rec["ranks"] = solution.pair.Q.mesh.comm.size
    check = solution.solvability
    rec.update(constraints=check.constraints, redundant=check.redundant, solvable=check.solvable)
    rec["condition"] = check.condition if np.isfinite(check.condition) else None
    if check.solvable:
        err = errors(solution)
        rec.update(
            pressure_error=err.pressure,
            stress_error=err.stress,
            force_error=err.force,
            # The patch test: a constant stress state, and the constant traction
            # transmitted exactly (section 3.2). Whether the multipliers themselves
            # are exact is a matter of stability, reported separately.
            passed=bool(max(err.stress, err.force) <= PASS_TOLERANCE),
            multiplier_exact=bool(err.pressure <= PASS_TOLERANCE),
        )
    else:
        rec.update(
            pressure_error=None,
            stress_error=None,
            force_error=None,
            passed=False,
            multiplier_exact=False,
        )
    outcome = "pass" if rec["passed"] else "fail"
    rec["agrees"] = rec["paper"] in ("either", outcome)
    return rec


#: Largest pressure and stress error of a passing case.
PASS_TOLERANCE = 1e-10

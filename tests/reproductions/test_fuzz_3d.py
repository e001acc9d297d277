# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Randomized 3D patch tests (issue 21): Hypothesis draws two non-matching blocks.

Each example (paper.fuzz3d) is the patch test of section 3.2 in 3D: tetrahedra or
hexahedra (faces warped or not), P1 or P2, tied or unilateral, either contactor, E and P
over decades; composite segment-to-segment must transmit the pressure P and give the
displacements of uniaxial stress (Eq. 36) to 1e-10 relative. Drawn on rank 0 and
checked on every rank (paper.fuzz.run_drawn_cases); ``make fuzz`` runs hundreds
(demos/fuzz_patch_test_3d.py).
"""

from mpi4py import MPI

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, settings

from dolfinx_contact_s2s import contact_rule
from paper.fuzz import run_drawn_cases
from paper.fuzz3d import FuzzCase3D, cases, check_case

comm = MPI.COMM_WORLD

#: A handful of examples: about 0.5 s each on one rank.
FUZZ_SETTINGS = settings(
    max_examples=5,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=list(HealthCheck),
    phases=[Phase.explicit, Phase.generate],
    print_blob=False,
)


def _reproduce(case: FuzzCase3D) -> str:
    return f"python3 demos/fuzz_patch_test_3d.py --case '{case.to_json()}'"


def test_random_3d_patch_test_to_round_off():
    def check(case: FuzzCase3D) -> float:
        result = check_case(case, comm, prefix="fuzz3d_test_")
        assert result.passed, (result, _reproduce(case))
        return result.ratio

    run_drawn_cases(comm, cases(max_cells=4, max_layers=2), check, FUZZ_SETTINGS)


def test_case_round_trips_through_json():
    case = FuzzCase3D("tet", "hex", 2, (3, 5), 2, None, "lower", "unilateral", 1, 0.0123, 45.6)
    assert FuzzCase3D.from_json(case.to_json()) == case
    moved = FuzzCase3D("hex", "hex", 1, (4, 2), 1, 3, "upper", "tied", 1, 1.0, 1.0, warp=True)
    assert FuzzCase3D.from_json(moved.to_json()) == moved


def test_the_check_catches_warped_hexahedra(monkeypatch):
    """Hexahedra moved at random have faces that are not parallelograms, whose rational
    inverse maps the rule of the polynomial degree misses: with the pair's measurement
    of its rule switched off the case fails the check by far; with it, it passes."""
    warped = FuzzCase3D("hex", "hex", 1, (3, 4), 2, 1, "upper", "tied", 1, 1.0, 1.0, warp=True)
    assert check_case(warped, comm, prefix="fuzz3d_warp_").passed
    monkeypatch.setattr(contact_rule, "RULE_TOLERANCE", np.inf)
    failing = check_case(warped, comm, prefix="fuzz3d_warp_")
    assert not failing.passed
    assert failing.ratio > 1e3


def test_cases_that_differ_between_ranks_are_refused():
    if comm.size == 1:
        pytest.skip("needs two ranks")
    case = FuzzCase3D("tet", "hex", 1, (2, 3), 1, None, "upper", "tied", 1, 1.0 + comm.rank, 1.0)
    with pytest.raises(ValueError, match="differs between the ranks"):
        check_case(case, comm)

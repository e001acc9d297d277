# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""E = 0 (or E < 0) in the user's own form: named before the factorization, on every rank.

On DOLFINx 0.11 with 2 ranks, MUMPS reported a zero stiffness as a workspace error
("MUMPS ran out of workspace ... raise it") after retries up to ICNTL(14) = 280.
"""

import functools

import pytest
from test_bad_input import raises_everywhere, readme_mesh, readme_problem, solve_once
from user_scenes import quad_tri_patch

from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

PROBLEMS = {"linear": LinearContactProblem, "unilateral": UnilateralContactProblem}


@pytest.fixture(scope="module")
def model():
    return readme_mesh()


@pytest.mark.parametrize("problem", PROBLEMS)
def test_zero_young_modulus_in_the_users_form(model, problem):
    mesh, facets = model
    message = raises_everywhere(
        ValueError,
        r"^the stiffness of body 0 of space 0 is zero \(largest diagonal entry of K on its "
        r"free dofs: 0\): check E in your form a\[0\]",
        lambda: readme_problem(
            mesh, facets, E=0.0, problem=PROBLEMS[problem], prefix="e0_"
        ).solve(),
    )
    assert "MUMPS" not in message and "workspace" not in message


def test_negative_young_modulus_in_the_users_form(model):
    mesh, facets = model
    raises_everywhere(
        ValueError,
        r"^the stiffness of body 0 of space 0 is not positive .*check E in your form a\[0\]",
        lambda: solve_once(readme_problem(mesh, facets, E=-1.0, prefix="eneg_")),
    )


@pytest.mark.parametrize("problem", PROBLEMS)
def test_one_body_with_zero_young_modulus(problem):
    """Two spaces, E = 0 in the upper block's form only: space 1 is named."""
    a, L, pairs, bcs = quad_tri_patch(E=(1.0, 0.0))
    cls = functools.partial(PROBLEMS[problem], petsc_options_prefix="e0_upper_")

    def solve():
        with cls(a, L, pairs, bcs) as p:
            p.solve()

    raises_everywhere(
        ValueError, r"^the stiffness of body 0 of space 1 is zero .*form a\[1\]", solve
    )


def test_nonzero_young_moduli_still_solve():
    a, L, pairs, bcs = quad_tri_patch(E=(1.0, 1e-6))
    with LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix="e_small_") as p:
        p.solve()

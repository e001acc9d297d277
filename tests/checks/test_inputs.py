# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Defects users met: misspelt solver types, arguments in LinearProblem's order, E = 0.

Each case raises one exception with one message on every rank (compared by allgather),
before PETSc or the set-up sees the bad input.
"""

import functools

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import pytest
from test_bad_input import raises_everywhere, readme_mesh, readme_problem

from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

comm = MPI.COMM_WORLD

PROBLEMS = {"linear": LinearContactProblem, "unilateral": UnilateralContactProblem}


@pytest.fixture(scope="module")
def model():
    return readme_mesh()


# --- 1. unknown solver types ------------------------------------------------------------


@pytest.mark.parametrize("problem", PROBLEMS)
@pytest.mark.parametrize(("key", "value"), [("pc_type", "mumsp"), ("ksp_type", "gmress")])
def test_unknown_solver_type_in_petsc_options(model, problem, key, value):
    mesh, facets = model
    cls = functools.partial(PROBLEMS[problem], petsc_options={key: value})
    message = raises_everywhere(
        ValueError,
        rf"unknown (PC|KSP) type '{value}' for the option {key} under the prefix 'typo_'",
        readme_problem,
        mesh,
        facets,
        problem=cls,
        prefix="typo_",
    )
    assert f"-typo_{key}" in message
    # Nothing of the refused problem stays in the options database.
    assert not PETSc.Options().hasName(f"typo_{key}")
    assert not PETSc.Options().hasName("typo_pc_factor_mat_solver_type")


@pytest.mark.parametrize("problem", PROBLEMS)
def test_unknown_solver_type_in_the_options_database(model, problem):
    """``-db_pc_type nonsense`` on the command line: the same error, naming the prefix."""
    mesh, facets = model
    database = PETSc.Options()
    database["db_pc_type"] = "nonsense"
    try:
        raises_everywhere(
            ValueError,
            r"unknown PC type 'nonsense' for the option pc_type under the prefix 'db_'.*"
            r"PETSc knows .*cholesky",
            readme_problem,
            mesh,
            facets,
            problem=PROBLEMS[problem],
            prefix="db_",
        )
        # The user's own entry is left as it was.
        assert database.getString("db_pc_type") == "nonsense"
    finally:
        database.delValue("db_pc_type")


def test_unknown_snes_type_for_snes_vi(model):
    mesh, facets = model
    cls = functools.partial(
        UnilateralContactProblem, algorithm="snes-vi", petsc_options={"snes_type": "vinewton"}
    )
    raises_everywhere(
        ValueError,
        r"unknown SNES type 'vinewton' for the option snes_type under the prefix 'snes_typo_'",
        readme_problem,
        mesh,
        facets,
        problem=cls,
        prefix="snes_typo_",
    )


@pytest.mark.parametrize("problem", PROBLEMS)
def test_known_solver_types_solve(model, problem):
    """A registered choice other than the default passes and solves the patch test."""
    mesh, facets = model
    options = {"pc_type": "lu", "ksp_type": "preonly"}
    cls = functools.partial(PROBLEMS[problem], petsc_options=options)
    with readme_problem(mesh, facets, problem=cls, prefix="known_") as p:
        (_,), (pressure,) = p.solve()
        owned = pressure.function_space.dofmap.index_map.size_local
        error = float(abs(pressure.x.array[:owned] - 1.0).max(initial=0.0))
        assert comm.allreduce(error, op=MPI.MAX) < 1e-10


# --- 2. the order of the arguments ------------------------------------------------------


def _model_arguments(mesh, facets):
    """a, L, pairs and bcs of the README problem, taken apart."""
    seen = {}

    def capture(a, L, pairs, bcs, **kwargs):
        seen.update(a=a, L=L, pairs=pairs, bcs=bcs)

    readme_problem(mesh, facets, problem=capture)
    return seen["a"], seen["L"], seen["pairs"], seen["bcs"]


@pytest.mark.parametrize("problem", PROBLEMS)
def test_pairs_and_bcs_swapped(model, problem):
    """``(a, L, bcs, pairs)``, LinearProblem's habit: a TypeError naming both."""
    a, L, pairs, bcs = _model_arguments(*model)
    name = PROBLEMS[problem].__name__
    message = raises_everywhere(
        TypeError,
        rf"^{name}: argument 3, pairs, must be a list of ContactPair objects \(from "
        r"contact_pair or contact_pairs\); got list of DirichletBC: did you swap pairs and "
        rf"bcs\? The order is {name}\(a, L, pairs, bcs\)",
        PROBLEMS[problem],
        a,
        L,
        bcs,
        pairs,
        petsc_options_prefix="swap_",
    )
    assert "AttributeError" not in message


#: Arguments in the wrong place or of the wrong kind: ``(a, L, pairs, bcs)`` -> the
#: positional arguments given, and the message.
WRONG_ARGUMENTS = {
    "bcs given as pairs": (
        lambda a, L, pairs, bcs: (a, L, pairs, pairs),
        r"argument 4, bcs, must be a list of DirichletBC objects .*got list of ContactPair: "
        r"did you swap pairs and bcs\?",
    ),
    "LinearProblem's order": (
        lambda a, L, pairs, bcs: (a, L, bcs),
        r"argument 3, pairs.*got list of DirichletBC: did you swap",
    ),
    "compiled a": (
        lambda a, L, pairs, bcs: (dolfinx.fem.form(a), L, pairs, bcs),
        r"argument 1, a, must be a UFL form .*got Form",
    ),
    "a condition as L": (
        lambda a, L, pairs, bcs: (a, bcs[0], pairs, bcs),
        r"argument 2, L, must be a UFL form .*got DirichletBC",
    ),
    "one pair": (
        lambda a, L, pairs, bcs: (a, L, pairs[0], bcs),
        r"got one ContactPair: give \[pair\]",
    ),
    "one condition": (
        lambda a, L, pairs, bcs: (a, L, pairs, bcs[0]),
        r"got one DirichletBC: give \[bc\]",
    ),
}


@pytest.mark.parametrize("problem", PROBLEMS)
@pytest.mark.parametrize("case", WRONG_ARGUMENTS)
def test_wrong_arguments(model, problem, case):
    """Each wrong argument named by its position, for both problems, on every rank."""
    arrange, match = WRONG_ARGUMENTS[case]
    arguments = arrange(*_model_arguments(*model))
    prefix = "wrong_" + "".join(c for c in case if c.isalnum()) + "_"
    raises_everywhere(TypeError, match, PROBLEMS[problem], *arguments, petsc_options_prefix=prefix)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Randomized patch tests (issue 12, item 4): Hypothesis draws non-matching two-body models.

Each example is built as a user builds it (Gmsh, DOLFINx's reader, the user's own forms,
contact_surface, contact_pairs, LinearContactProblem; see
paper.fuzz) and must pass the patch test of composite
segment-to-segment: the exact uniform pressure and linear displacements, within the
round-off bound of its solve (dolfinx_contact_s2s.analysis.roundoff). Every rank draws the same
examples (derandomized, no database, no deadline or timing health check); on more than
one rank nothing is shrunk, since Hypothesis stops shrinking on a wall-clock limit that
the ranks would not reach together. ``make fuzz`` runs thousands of these
(demos/fuzz_patch_test.py).
"""

import importlib.util
import sys

from mpi4py import MPI

import basix
import basix.ufl
import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, settings
from hypothesis import strategies as st

from dolfinx_contact_s2s.analysis.roundoff import round_off_bound
from dolfinx_contact_s2s.edges import facet_monomials
from dolfinx_contact_s2s.la import gather_dense
from paper.fuzz import (
    BOUND_CEILING,
    Block,
    FuzzCase,
    Segment,
    build_problem,
    cases,
    check_case,
    run_drawn_cases,
)

comm = MPI.COMM_WORLD

#: Examples per run: a case costs about 0.2 s on one rank and 1-2 s on two (small
#: collectives on 2 shared cores); ``make fuzz`` runs thousands.
FUZZ_SETTINGS = settings(
    max_examples=30 if comm.size == 1 else 12,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=list(HealthCheck),
    phases=[Phase.explicit, Phase.generate, Phase.shrink],
    print_blob=False,
)


def _reproduce(case: FuzzCase) -> str:
    return f"python3 demos/fuzz_patch_test.py --case '{case.to_json()}'"


def test_random_patch_test_within_round_off():
    def check(case: FuzzCase) -> float:
        assert FuzzCase.from_json(case.to_json()) == case
        result = check_case(case, comm, prefix="fuzz_test_")
        # The same numbers on every rank (reduced in check_case): all ranks fail together.
        assert result.pressure_bound < BOUND_CEILING, (result, _reproduce(case))
        assert result.ratio <= 1.0, (result, _reproduce(case))
        return result.ratio

    run_drawn_cases(comm, cases(max_elements=4, max_segments=3, max_layers=3), check, FUZZ_SETTINGS)


def _import_constants_on_rank_0(tmp_path) -> None:
    """Rank 0 only imports a local module of float constants, which Hypothesis mixes into
    its draws: from the same seed the ranks' own draws now differ."""
    if comm.rank != 0:
        return
    path = tmp_path / "fuzz_rank0_constants.py"
    values = ", ".join(f"{0.25 + 0.0137 * k!r}" for k in range(40))
    path.write_text(f"VALUES = ({values})\n")
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    spec.loader.exec_module(module)


def test_every_rank_checks_the_case_rank_0_drew(tmp_path):
    _import_constants_on_rank_0(tmp_path)
    seen = []

    def record(value):
        seen.append(value)

    quick = settings(FUZZ_SETTINGS, max_examples=60, phases=[Phase.generate])
    # None among the examples: it must not end the other ranks' loop.
    values = st.none() | st.lists(st.floats(0.0, 1.0), max_size=4)
    run_drawn_cases(comm, values, record, quick)
    assert None in seen and len(seen) > 1
    assert all(s == seen for s in comm.allgather(seen))


def test_a_failure_is_raised_on_every_rank():
    def fails_above_half(value):
        assert value <= 0.5, "above one half"

    with pytest.raises(AssertionError, match="above one half"):
        run_drawn_cases(comm, st.floats(0.0, 1.0), fails_above_half, FUZZ_SETTINGS)


def test_cases_that_differ_between_ranks_are_refused():
    if comm.size == 1:
        pytest.skip("needs two ranks")
    case = FuzzCase(
        one_mesh=True,
        lower=Block(
            "triangle",
            1,
            (Segment(1.0, 2, 1.0),),
            (Segment(1.0, 2, 1.0),),
            1,
            1.0 + comm.rank,
            1.0,
            0.3,
        ),
        upper=Block(
            "triangle", 1, (Segment(1.0, 3, 1.0),), (Segment(1.0, 3, 1.0),), 1, 1.0, 1.0, 0.3
        ),
        contactor="upper",
        gap=0.0,
    )
    with pytest.raises(ValueError, match="differs between the ranks"):
        check_case(case, comm)


@pytest.mark.parametrize("one_mesh", [True, False])
def test_the_check_catches_a_discretization_that_fails_the_patch_test(one_mesh):
    """Node-to-segment does not transmit a uniform pressure across non-matching meshes
    (section 4.2): on the same models its errors are far above the round-off bound."""
    lower = Block(
        "triangle",
        1,
        contact=(Segment(0.3, 2, 1.25), Segment(0.7, 3, 1.0)),
        far=(Segment(1.0, 4, 1.0),),
        layers=2,
        height=0.5,
        E=1.0,
        nu=0.3,
    )
    upper = Block(
        "triangle",
        1,
        contact=(Segment(1.0, 3, 0.8),),
        far=(Segment(1.0, 3, 1.0),),
        layers=2,
        height=0.5,
        E=3.0,
        nu=0.2,
    )
    case = FuzzCase(one_mesh, lower, upper, contactor="upper", gap=0.0)
    passing = check_case(case, comm, prefix="fuzz_s2s_")
    failing = check_case(case, comm, prefix="fuzz_nts_", method="node-to-segment")
    assert passing.ratio <= 1.0
    assert failing.ratio > 1e3


def _simplest(one_mesh: bool, lower_cell: str, far_elements: int) -> FuzzCase:
    def block(cell: str, far: int) -> Block:
        one, far_edge = (Segment(1.0, 1, 1.0),), (Segment(1.0, far, 1.0),)
        return Block(cell, 1, one, far_edge, layers=1, height=1.0, E=1.0, nu=0.0)

    lower, upper = block(lower_cell, far_elements), block("triangle", 1)
    return FuzzCase(one_mesh, lower, upper, contactor="upper", gap=0.0)


@pytest.mark.parametrize(
    "case",
    [_simplest(False, "quadrilateral", 1), _simplest(True, "triangle", 2)],
    ids=["abs-x", "zero-row"],
)
def test_backward_error_of_exactly_zero_unknowns(case):
    """Regression, the first two examples the fuzz test failed on (nu = 0: u_x = 0 exactly,
    its computed values round-off of either sign). The backward error took |A| x for
    |A||x|, which cancelled (omega = 1, the pressure's bound 96 on a unit pressure); then
    rows whose |A||x| + |b| is itself round-off gave omega = 0.11 (bound 14) until they got
    Arioli-Demmel-Duff's normwise term. Dense NumPy: omega by the same rule is round-off."""
    built = build_problem(case, comm, prefix="fuzz_omega_")
    with built.problem as problem:
        problem.solve()
        bound = round_off_bound(problem)
        A = gather_dense(problem.A)
        x = np.concatenate(comm.allgather(problem.x.array_r.copy()))
        b = np.concatenate(comm.allgather(problem.b.array_r.copy()))
    eps = np.finfo(float).eps
    r = np.abs(b - A @ x)
    g = np.abs(A) @ np.abs(x) + np.abs(b)
    normwise = np.abs(A).sum(axis=1) * np.abs(x).max()
    small = (g <= 1000 * x.size * eps * (normwise + np.abs(b))) & (r > 0)
    omega = np.max(r / np.where(small, g + normwise, np.where(g > 0, g, 1.0)))
    assert omega < 10 * eps
    assert bound.backward_error < 10 * eps
    assert bound.multiplier[0] < 1e-12
    assert check_case(case, comm, prefix="fuzz_omega_check_").ratio <= 1.0


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
@pytest.mark.parametrize("degree", [1, 2])
def test_facet_basis_of_dofs_off_the_facet_is_zero(cell, degree):
    """Regression: Basix's round-off (up to 8e-16) on the basis functions of the dofs off a
    facet entered its monomial table, so B coupled the far nodes of the cell. A Lagrange
    function whose dof is off the facet vanishes on it identically; the others are a
    partition of unity along it."""
    element = basix.ufl.element("Lagrange", cell, degree)
    cell_type = basix.CellType[cell]
    vertices, facets = basix.geometry(cell_type), basix.topology(cell_type)[1]
    a = vertices[[f[0] for f in facets]]
    b = vertices[[f[1] for f in facets]]
    table = facet_monomials(element, a, b)
    closure = element.basix_element.entity_closure_dofs[1]
    for f in range(len(facets)):
        assert np.all(np.delete(table[f], closure[f], axis=1) == 0.0)
        np.testing.assert_allclose(table[f].sum(axis=1), np.eye(degree + 1)[0], atol=1e-14)


def test_soft_target_under_stiff_contactor():
    """Regression, found by the fuzz campaign (chunk seed 29): a soft quadrilateral target
    (E = 1e-3, its top moving by 1e3) under a stiff P2 contactor (E = 32). The far nodes'
    round-off entries in B (1e-19) times their displacements put 3e-9 into the pressure,
    180 times its round-off bound; now 7e-13."""
    lower = Block(
        "triangle",
        2,
        contact=(Segment(1.0, 1, 0.8), Segment(0.82, 6, 1.0), Segment(1.0, 1, 1.5)),
        far=(Segment(1.0, 1, 1.5),),
        layers=3,
        height=0.25,
        E=31.6,
        nu=0.0,
    )
    upper = Block(
        "quadrilateral",
        1,
        contact=(Segment(1.0, 3, 0.67),),
        far=(Segment(1.0, 3, 1.0),),
        layers=1,
        height=1.0,
        E=1e-3,
        nu=0.0,
    )
    result = check_case(FuzzCase(False, lower, upper, "lower", 0.0), comm, prefix="fuzz_soft_")
    assert result.ratio <= 1.0, result

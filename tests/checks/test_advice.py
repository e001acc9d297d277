# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Advice that fits the cause: a body frictionless contact cannot hold, a tied pair in tension.

- A block resting on a block with no horizontal Dirichlet condition: contact holds its
  vertical motion and its rotation, never its sliding, whatever the contact area. The
  error says so and names the condition it misses (the advice for contact that opened,
  ``start="tied"`` or smaller steps, cannot help; that advice stays for a body whose
  contact opens, ``tests/test_bad_input.py::test_body_held_only_by_contact_that_opens``).
- A tied problem on surfaces with initial gaps closes them and pulls the surfaces
  together: negative pressures, and a ``UserWarning`` (none on the matching patch test).
"""

import functools
import warnings

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
from readme_model import LOWER, UPPER
from test_bad_input import raises_everywhere, readme_mesh, readme_problem

from dolfinx_contact_s2s.compat import geometry_dofmap
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

comm = MPI.COMM_WORLD

PROBLEMS = {"linear": LinearContactProblem, "unilateral": UnilateralContactProblem}


@pytest.fixture(scope="module")
def model():
    return readme_mesh()


def _arguments(mesh, facets, **options):
    """a, L, pairs and bcs of the README problem (``readme_problem``'s options)."""
    seen = {}

    def capture(a, L, pairs, bcs, **kwargs):
        seen.update(a=a, L=L, pairs=pairs, bcs=bcs)

    readme_problem(mesh, facets, problem=capture, **options)
    return seen["a"], seen["L"], seen["pairs"], seen["bcs"]


@pytest.mark.parametrize("problem", PROBLEMS)
def test_block_on_block_without_horizontal_support(model, problem):
    """The lower block held at its bottom and left side, the upper one by contact alone."""
    mesh, facets = model
    a, L, pairs, bcs = _arguments(mesh, facets, directions=(1,))
    V = a.arguments()[0].ufl_function_space()
    left = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, facets.find(LOWER["left"]))
    bcs = [*bcs, dolfinx.fem.dirichletbc(0.0, left, V.sub(0))]

    def solve():
        with PROBLEMS[problem](a, L, pairs, bcs, petsc_options_prefix="slide_") as p:
            p.solve()

    message = raises_everywhere(
        ValueError,
        r"the problem is singular: these rigid motions .*\n"
        r"  - body 1 of space 0 \(nodes in \[0, 1\] x \[0\.5, 1\]\) can move freely: "
        r"translation along \(1, 0\)\n"
        r"Frictionless contact cannot hold body 1 of space 0 .* tangential to every one of "
        r"them even with every multiplier active.* Add a Dirichlet condition on its x "
        r"component \(V\.sub\(0\)",
        solve,
    )
    assert "start='tied'" not in message and "smaller" not in message
    # Only the upper block's sliding: the lower one is held, the rotation by contact.
    assert message.count("can move freely") == 1


def test_opened_contact_keeps_its_advice(model):
    """The upper block pulled up: held by the full set of rows, free once they open."""
    mesh, facets = model
    cls = functools.partial(UnilateralContactProblem, algorithm="active-set")
    message = None
    try:
        with readme_problem(mesh, facets, load=(0.0, 1.0), problem=cls, prefix="opened_") as p:
            p.solve()
    except Exception as e:  # compared below, on every rank
        message = str(e)
    messages = comm.allgather(message)
    assert len(set(messages)) == 1 and messages[0] is not None
    assert "the active set leaves these rigid motions free" in messages[0]
    assert "start='tied'" in messages[0]
    assert "Frictionless contact cannot hold" not in messages[0]


def _min_owned(f):
    owned = f.function_space.dofmap.index_map.size_local
    return comm.allreduce(float(np.min(f.x.array[:owned], initial=np.inf)), op=MPI.MIN)


def test_tied_pair_with_initial_gaps_warns():
    """A curved punch: the upper block's nodes lifted by (x - 1/2)^2, pressed down.

    Tied, its bottom is pulled onto the lower block: negative pressures at its ends.
    """
    mesh, facets = readme_mesh()
    x = mesh.geometry.x
    # The upper block's nodes: its cells are those above y = 0.5.
    cell_map = mesh.topology.index_map(2)
    cells = np.arange(cell_map.size_local + cell_map.num_ghosts)
    dofmap = geometry_dofmap(mesh)
    upper = np.unique(dofmap[cells][np.mean(x[dofmap[cells], 1], axis=1) > 0.5])
    x[upper, 1] += (x[upper, 0] - 0.5) ** 2
    with pytest.warns(UserWarning) as record:
        with readme_problem(mesh, facets, prefix="punch_") as problem:
            _, (pressure,) = problem.solve()
            lowest = _min_owned(pressure)
    assert lowest < -1.0  # measured: -5.03 at the ends
    texts = [str(w.message) for w in record if "initial gaps" in str(w.message)]
    assert len(texts) == 1, texts
    text = texts[0]
    assert f"pair 0 (contactor tag {UPPER['bottom']}) has initial gaps (up to " in text
    assert "closes them and pulls the surfaces together" in text
    assert f"the smallest pressure is {lowest:.3g}" in text
    assert "UnilateralContactProblem, which imposes g >= 0" in text
    assert len(set(comm.allgather(text))) == 1


def test_matching_tied_patch_test_does_not_warn(model):
    mesh, facets = model
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        with readme_problem(mesh, facets, prefix="tied_patch_") as problem:
            _, (pressure,) = problem.solve()
            assert abs(_min_owned(pressure) - 1.0) < 1e-10

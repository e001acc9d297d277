# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""A contactor side split into two tags, one facet lying over both targets (a user's report).

The scene is the three-block patch test of Fig. 3 (:func:`paper.scenes_multi.three_blocks`)
with the joint of the lower blocks at :math:`x = c = 0.4137`, inside the upper facet
:math:`[2/7, 3/7]`. The user tags the upper block's bottom as two contactor surfaces by
facet midpoint (:math:`x < c` and :math:`x \ge c`), each paired with the block under it.
The facet :math:`[2/7, 3/7]` then belongs to the left tag but its part
:math:`[c, 3/7]` lies over the right block, which its pair does not know: nothing
constrains it, and the patch test fails by a stress error of 0.07 to 0.5 and a pressure
error of 0.35 to 0.75 (P1 and P2, triangles and quadrilaterals) without a word. It must
raise instead; the two remedies pass the patch test: one contactor surface with both
targets, or tags split at a node where the target changes.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
from test_pair_arrangements import THREE_BLOCK_MATERIALS, Model, patch_errors

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.checks import unconstrained_parts
from paper.scenes_multi import three_blocks

#: The user's joint, between the upper nodes 2/7 and 3/7.
C = 0.4137

#: The tags the user gives the two halves of the upper block's bottom.
LEFT, RIGHT = 301, 302

#: Patch-test bound of the issue, for a pressure p = 1.
BOUND = 1e-10


def split_scene(cell: str, degree: int, joint: float = C, split: float | None = None):
    """The three blocks with the joint at ``joint``, the upper bottom split at ``split``.

    Returns the model (p = 1), the two contactor surfaces and the two lower tops.
    """
    comm = MPI.COMM_WORLD
    scene = three_blocks(comm, widths=(joint, 1.0 - joint), cell=cell)
    model = Model(scene, degree, p=1.0, materials=THREE_BLOCK_MATERIALS)
    part = scene.part("upper")
    tag = scene.tag("upper", "bottom")
    tags = part.facet_tags
    x = dolfinx.mesh.compute_midpoints(part.mesh, 1, tags.indices)[:, 0]
    values = tags.values.copy()
    bottom = values == tag
    split = joint if split is None else split
    values[bottom & (x < split)] = LEFT
    values[bottom & (x >= split)] = RIGHT
    split_tags = dolfinx.mesh.meshtags(part.mesh, 1, tags.indices, values)
    V = model.V[part.name]
    halves = [contact_surface(V, split_tags, t) for t in (LEFT, RIGHT)]
    lowers = [model.surface("lower_left", "top"), model.surface("lower_right", "top")]
    return model, halves, lowers


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
def test_split_contactor_raises(cell, degree):
    comm = MPI.COMM_WORLD
    model, (left, right), (a, b) = split_scene(cell, degree)
    pairs = [contact_pair(left, a), contact_pair(right, b)]
    with pytest.raises(ValueError) as error:
        model.problem(pairs)
    message = str(error.value)
    # The same message on every rank.
    assert len(set(comm.allgather(message))) == 1
    assert f"contactor surface {LEFT}" in message
    assert f"face contact surface(s) {b.tag} but not the pair's own target(s) {a.tag}" in message
    # The facet [2/7, 3/7] on y = 0.5, and its part [c, 3/7] over the right block.
    assert "1 facet(s)" in message
    assert "(0.285714, 0.5) to (0.428571, 0.5)" in message
    assert f"({C:g}, 0.5) to (0.428571, 0.5)" in message
    assert f"over a length of {3 / 7 - C:.6g}" in message
    assert "contact_pair(contactor, [target_a, target_b])" in message
    assert "split the contactor's tags at that node" in message

    (found,) = unconstrained_parts(pairs)
    assert (found.pair, found.contactor, found.targets, found.faces) == (
        0,
        LEFT,
        (a.tag,),
        (b.tag,),
    )
    assert found.facets == 1
    assert np.isclose(found.length, 3 / 7 - C, rtol=1e-12)


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
def test_one_contactor_two_targets_passes(cell, degree):
    """The remedy: the whole upper bottom (one tag) against both lower tops."""
    model, _, lowers = split_scene(cell, degree)
    pair = contact_pair(model.surface("upper", "bottom"), lowers)
    assert unconstrained_parts([pair]) == []
    e_sig, e_lam, tol = patch_errors(model, [pair])
    assert e_lam <= tol <= BOUND
    assert e_sig <= tol


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
def test_split_at_a_node_passes(cell):
    """Tags split at the node 3/7 where the target changes: each tag faces its own target."""
    joint = 3.0 / 7.0
    model, (left, right), (a, b) = split_scene(cell, 1, joint=joint)
    pairs = [contact_pair(left, a), contact_pair(right, b)]
    assert unconstrained_parts(pairs) == []
    e_sig, e_lam, tol = patch_errors(model, pairs)
    assert e_lam <= tol <= BOUND
    assert e_sig <= tol


def test_split_at_a_node_with_both_targets_passes():
    """The joint at c, the tags split at the node 3/7: the left tag takes both targets."""
    model, (left, right), (a, b) = split_scene("triangle", 1, split=3.0 / 7.0)
    pairs = [contact_pair(left, [a, b]), contact_pair(right, b)]
    e_sig, e_lam, tol = patch_errors(model, pairs)
    assert e_lam <= tol <= BOUND
    assert e_sig <= tol


def test_interval_arithmetic():
    from dolfinx_contact_s2s.checks.cover import _merge, _subtract

    rows = np.array([1, 0, 1, 1, 0], dtype=np.int32)
    lo = np.array([0.5, 0.0, 0.0, 0.2, 0.6])
    hi = np.array([0.7, 0.3, 0.3, 0.4, 1.0])
    merged = _merge(rows, lo, hi)
    assert merged[0].tolist() == [0, 0, 1, 1]
    np.testing.assert_array_equal(merged[1], [0.0, 0.6, 0.0, 0.5])
    np.testing.assert_array_equal(merged[2], [0.3, 1.0, 0.4, 0.7])
    # Pieces facing another surface, less the cover: what is left unconstrained.
    r, a, b = _subtract(
        np.array([0, 1, 2], dtype=np.int32),
        np.array([0.1, 0.0, 0.2]),
        np.array([0.9, 1.0, 0.5]),
        merged,
    )
    assert r.tolist() == [0, 1, 1, 2]
    np.testing.assert_allclose(a, [0.3, 0.4, 0.7, 0.2])
    np.testing.assert_allclose(b, [0.6, 0.5, 1.0, 0.5])

"""Each process meets only the target facets within its reach (ContactSurface.gather_near).

The near facets are checked against a selection made from the whole gathered target,
and the coupling blocks assembled from them against those assembled from the whole
target (an independent path through the same kernels): the same to the last bit.
"""

import dataclasses

from mpi4py import MPI

import numpy as np
import pytest
from test_system_checks import readme_problem

from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.surface import ContactSurface

comm = MPI.COMM_WORLD


def _blocks(pair):
    op = assemble_coupling(pair)
    dense = [gather_dense(B) for _, B in op.blocks]
    dense.append(op.uncovered)
    gap = np.concatenate(comm.allgather(op.G.array_r.copy()))
    op.destroy()
    return dense, gap


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("method", ["segment-to-segment", "node-to-segment"])
def test_near_facets_give_the_whole_coupling(monkeypatch, degree, method):
    with readme_problem(degree=degree, method=method, elements=(40, 27)) as problem:
        (pair,) = problem.pairs
        (target,) = pair.targets
        region = pair.reach()
        near = target.gather_near(region)
        whole = target.gather()
        # The reference selection: the whole target's facets whose boxes meet the region.
        boxes = target.bounding_boxes(whole)
        if region is None:
            expected = np.zeros(len(whole), dtype=bool)
        else:
            expected = np.all((boxes[:, 0] <= region[1]) & (region[0] <= boxes[:, 1]), axis=1)
        if comm.size == 1:
            expected[:] = True
        assert np.array_equal(near.dofs, whole.dofs[expected])
        assert np.array_equal(near.coefficients, whole.coefficients[expected])
        reached = comm.allreduce(len(near), op=MPI.SUM)
        blocks, gap = _blocks(pair)
        monkeypatch.setattr(ContactSurface, "gather_near", lambda self, region: self.gather())
        reference, reference_gap = _blocks(pair)
    for B, R in zip(blocks, reference, strict=True):
        assert np.array_equal(B, R)
    assert np.array_equal(gap, reference_gap)
    # Each process holds at most the whole target.
    assert reached <= comm.size * len(whole)


def test_regions_of_pairs_sharing_a_target_are_kept():
    """Pairs sharing a target ask for their regions in turn: each is gathered once."""
    with readme_problem(degree=1, method="segment-to-segment", elements=(40, 27)) as problem:
        (pair,) = problem.pairs
        (target,) = pair.targets
        whole = target.gather()
        lo, hi = whole.coefficients[:, 0].min(axis=0), whole.coefficients[:, 0].max(axis=0)
        middle = 0.5 * (lo + hi)
        # Each process names its own halves: the left and the right of the target.
        left = np.array([lo - 1.0, [middle[0], hi[1] + 1.0]])
        right = np.array([[middle[0], lo[1] - 1.0], hi + 1.0])
        first = [target.gather_near(left), target.gather_near(right)]
        again = [target.gather_near(left), target.gather_near(right)]
        assert all(a is b for a, b in zip(first, again, strict=True)) or comm.size == 1
        for near, region in zip(again, (left, right), strict=True):
            boxes = target.bounding_boxes(whole)
            meets = np.all((boxes[:, 0] <= region[1]) & (region[0] <= boxes[:, 1]), axis=1)
            if comm.size == 1:
                meets[:] = True
            assert np.array_equal(near.dofs, whole.dofs[meets])
        # A new surface state drops the regions.
        target.data = dataclasses.replace(target.data)
        assert target.gather_near(left) is not first[0] or comm.size == 1

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""A block pushed up a slope: the reaction's ratio of Coulomb sliding on an incline.

The two blocks of :func:`paper.scenes_multi.two_blocks_one_mesh` (the scene
:func:`paper.friction.inclined_block`) sheared by
:math:`y \mapsto y + x \tan\alpha`, :math:`\tan\alpha = 0.1`: their contact line rises
at the angle :math:`\alpha`. The lower block is clamped at its bottom; the upper one is
pressed by a vertical load on its top and pushed up the slope by a prescribed
:math:`u_x = d` on its left side, far beyond the stick limit, so that all of it slides
with :math:`\mu = 0.5`. The contact force on the sliding block then has the ratio
:math:`|F_x| / F_y = (\mu + \tan\alpha) / (1 - \mu \tan\alpha) = 0.6316`, and by the
block's equilibrium so has the reaction :math:`R_x` of the push to the vertical load
:math:`V`: measured from the residual :math:`a(u, v) - L(v)` at the pushed dofs, not
from :math:`\lambda`.
"""

from mpi4py import MPI

import pytest

from paper.friction import inclined_block


@pytest.mark.parametrize("degree", [1, 2])
def test_inclined_block(degree):
    rec = inclined_block(MPI.COMM_WORLD, degree)
    assert rec["sliding"]
    assert rec["error"] <= 1e-8

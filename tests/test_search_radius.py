# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Messages users meet name the argument that fixes them."""

from mpi4py import MPI

import dolfinx
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from paper.scenes import BOTTOM, TOP, patch_test


def _surface(body, tag):
    V = dolfinx.fem.functionspace(body.mesh, ("Lagrange", 1, (2,)))
    return contact_surface(V, body.facet_tags, tag)


@pytest.mark.parametrize("radius", [None, 0.05])
def test_out_of_reach_names_search_radius(radius):
    """Blocks 5 apart: the message names search_radius= and its value now.

    The default radius is the largest facet: 1/3 (3 upper elements over a width of 1).
    """
    comm = MPI.COMM_WORLD
    far = patch_test(comm, (4, 3), gap=5.0)
    pair = contact_pair(_surface(far.upper, BOTTOM), _surface(far.lower, TOP), search_radius=radius)
    now = "0.333333" if radius is None else "0.05"
    with pytest.raises(ValueError) as error:
        assemble_coupling(pair)
    message = str(error.value)
    assert len(set(comm.allgather(message))) == 1
    assert message.startswith(
        "the contactor and target surfaces never face each other within the search radius"
    )
    assert f"contactor tag {BOTTOM}, target tag(s) {TOP}" in message
    assert message.endswith(f"pass a larger search_radius= to contact_pair (now {now})")
    # The remedy works: a radius beyond the gap of 5.
    assemble_coupling(
        contact_pair(_surface(far.upper, BOTTOM), _surface(far.lower, TOP), search_radius=5.5)
    ).destroy()

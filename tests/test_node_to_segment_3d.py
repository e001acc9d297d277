# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Node-to-segment on faces (Eqs. 38-39): the baseline of the 3D patch test.

The blocks of ``paper/blocks3d.py`` under a uniform pressure P, with one constraint per
contactor node (of the displacement's degree) projected along its normal onto the target
faces. The paper (section 4.2) says node-to-segment does not pass the contact patch test,
"in 2D and 3D problems" alike, because the forces are not transferred consistently; on
matching meshes every node meets a target node and the method is node-to-node, which
passes (section 4.1: for quadratic elements too when corner nodes meet corner nodes and
midside nodes midside nodes). Whatever the meshes, the forces balance: the upper block is
held only by the contact in z, so the contact forces on it sum to the load P (its area
1), and every constraint hands its force :math:`\\lambda_i w_i` to the target by
interpolation functions that sum to one (Eq. 38), so the target receives the same total.
"""

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.problem import LinearContactProblem
from paper.blocks3d import BOTTOM, COMM, TOP, E, P, errors, scene

#: Largest displacement error (relative to P/E) of a passing case, and smallest of a
#: failing one (the 2D patch matrix's FAIL, tests/reproductions/test_patch_matrix.py).
PASS, FAIL = 1e-10, 1e-3


def solve(cells, degree, contactor, across, weight):
    """Displacement and multiplier errors, the contact forces' totals in z, the pair."""
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, None, across)
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    surfaces = (upper, lower) if contactor == "upper" else (lower, upper)
    pair = contact_pair(*surfaces, method="node-to-segment", weight=weight)
    with LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="n3d_") as problem:
        us, (lam,) = problem.solve()
        _, worst_u = errors(us, lam)
        totals = []
        for f in problem.contact_forces():
            imap = f.function_space.dofmap.index_map
            z = f.x.array[: imap.size_local * 3].reshape(-1, 3)[:, 2]
            totals.append(COMM.allreduce(float(z.sum())))
        # The traction at each node: unit weights make the multiplier the node's force.
        Q = lam.function_space
        area = dolfinx.fem.assemble_vector(
            dolfinx.fem.form(ufl.TestFunction(Q) * ufl.dx(domain=Q.mesh))
        )
        area.scatter_reverse(dolfinx.la.InsertMode.add)
        n = Q.dofmap.index_map.size_local
        lam_values, area_values = lam.x.array[:n].copy(), area.array[:n].copy()
    return worst_u, totals, lam_values, area_values


@pytest.mark.parametrize(
    "degree, weight", [(1, "unit"), (1, "tributary"), (2, "unit")], ids=["P1", "P1-tributary", "P2"]
)
@pytest.mark.parametrize("contactor", ["upper", "lower"])
@pytest.mark.parametrize("cells", [("hex", "tet"), ("tet", "hex")])
def test_fails_on_non_matching_meshes(cells, degree, weight, contactor):
    """3 against 4 cells across: not exact (section 4.2); the forces balance all the same."""
    worst_u, (lower, upper), _, _ = solve(cells, degree, contactor, (3, 4), weight)
    assert worst_u > FAIL * P / E
    # Eq. (38)'s interpolation sums to one: the total force reaches the target whole.
    assert abs(upper - P) <= PASS * P
    assert abs(lower + P) <= PASS * P


MATCHING = [
    (cells, degree, weight)
    for cells in (("hex", "hex"), ("tet", "tet"))
    for degree in (1, 2)
    for weight in ("unit", "tributary")
    # The vertex nodes of P2 triangles have no tributary area (refused).
    if not (weight == "tributary" and degree == 2 and cells[0] == "tet")
]


@pytest.mark.parametrize("cells, degree, weight", MATCHING)
def test_passes_on_matching_meshes(cells, degree, weight):
    """4 against 4 cells across (the same faces): exact (section 4.1).

    The multiplier is the pressure P with tributary weights, and the node's consistent
    force, P times the integral of its basis function, with unit weights (zero at the
    vertices of P2 triangles, whose tributary weight is refused).
    """
    worst_u, (lower, upper), lam, area = solve(cells, degree, "upper", (4, 4), weight)
    assert worst_u <= PASS * P / E
    expected = P * area if weight == "unit" else np.full(lam.size, P)
    worst = COMM.allreduce(float(np.max(np.abs(lam - expected), initial=0.0)), op=max)
    assert worst <= PASS * P
    assert abs(upper - P) <= PASS * P and abs(lower + P) <= PASS * P

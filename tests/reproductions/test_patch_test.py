# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The contact patch test (section 3.2, Figs. 4 and 6) against its analytical solution.

Exact: uniform sigma_y = -p, sigma_x = sigma_xy = 0, contact pressure p, linear
displacements. The segment-to-segment algorithm with composite quadrature and a
continuous multiplier of the displacement degree must reproduce them to round-off
on non-matching meshes (section 5).
"""

from mpi4py import MPI

import numpy as np
import pytest

from paper.patch_test import (
    PatchTestCase,
    exact_displacement,
    solve_patch_test,
)

# Errors are O(eps * condition); 1e-10 is the bound and leaves that margin.
TOL = 1e-10


def max_errors(sol):
    comm = MPI.COMM_WORLD
    p = sol.case.pressure
    lam = sol.pressure
    owned = lam.function_space.dofmap.index_map.size_local
    e_lam = np.max(np.abs(lam.x.array[:owned] - p), initial=0.0) / p
    e_sig = 0.0
    for s in sol.stress.values():
        sig = s.x.array.reshape(-1, 2, 2)
        exact = np.array([[0.0, 0.0], [0.0, -p]])
        e_sig = max(e_sig, np.max(np.abs(sig - exact), initial=0.0) / p)
    e_u = 0.0
    for name, u in sol.displacement.items():
        ref = u.copy()
        ref.interpolate(exact_displacement(sol.case, sol.scene.height, name))
        e_u = max(e_u, np.max(np.abs(u.x.array - ref.x.array), initial=0.0))
    return [comm.allreduce(e, op=MPI.MAX) for e in (e_lam, e_sig, e_u)]


@pytest.mark.parametrize("contactor", ["upper", "lower"])
@pytest.mark.parametrize("elements", [(10, 7), (7, 10)])
@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
@pytest.mark.parametrize("degree", [1, 2])
def test_s2s_patch_test(degree, cell, elements, contactor):
    case = PatchTestCase(
        degrees=(degree, degree), elements=elements, cell=cell, contactor=contactor
    )
    sol = solve_patch_test(MPI.COMM_WORLD, case)
    e_lam, e_sig, e_u = max_errors(sol)
    assert e_lam < TOL
    assert e_sig < TOL
    # Displacements are O(p/E) = O(1) here.
    assert e_u < TOL


@pytest.mark.parametrize(
    "case",
    [
        PatchTestCase(gap=0.01),
        PatchTestCase(gap=-0.02, contactor="lower", cell="quadrilateral"),
        PatchTestCase(degrees=(2, 2), geometry_degree=2, elements=(3, 8)),
        PatchTestCase(degrees=(2, 1), elements=(5, 9), contactor="lower"),
        PatchTestCase(degrees=(1, 2), elements=(9, 4), cell="quadrilateral", gap=0.005),
        PatchTestCase(pressure=1e3, elements=(13, 6)),
    ],
    ids=[
        "gap",
        "overlap-quad-lower",
        "curved-geometry",
        "quadratic-on-linear",
        "linear-on-quadratic-gap",
        "large-load",
    ],
)
def test_s2s_patch_test_variants(case):
    sol = solve_patch_test(MPI.COMM_WORLD, case)
    e_lam, e_sig, e_u = max_errors(sol)
    assert e_lam < TOL
    assert e_sig < TOL
    assert e_u < TOL * case.pressure

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The augmented Lagrangian with its defaults on a user's non-matching patch test.

The user's scene: quadrilateral lower block [0, 1] x [0, 0.5] with 13 elements along the
contact, triangular upper block [0, 1] x [0.5, 1] with 9, P1, pressure 1 on top (two
meshes: one mesh of two cell types is refused by the Gmsh reader). The exact contact
pressure is 1; the active set gets it to 1e-10, and so must the augmented Lagrangian
with its defaults, with the contraction rate of every update in its history.
"""

from mpi4py import MPI

import numpy as np
import pytest
from user_scenes import quad_tri_patch

from dolfinx_contact_s2s.unilateral import DEFAULT_PENALTY, UnilateralContactProblem

comm = MPI.COMM_WORLD


def _pressure_error(lam):
    owned = lam.function_space.dofmap.index_map.size_local
    local = float(np.max(np.abs(lam.x.array[:owned] - 1.0), initial=0.0))
    return comm.allreduce(local, op=MPI.MAX)


@pytest.mark.parametrize("penalty", [None, 1.0], ids=["default", "small"])
def test_augmented_lagrangian_patch_test(penalty):
    """Defaults converge to p = 1 (1e-10); a poor penalty is raised when it contracts slowly."""
    a, L, pairs, bcs = quad_tri_patch()
    with UnilateralContactProblem(
        a,
        L,
        pairs,
        bcs,
        petsc_options_prefix="al_patch_",
        algorithm="augmented-lagrangian",
        penalty=penalty,
    ) as problem:
        _, (lam,) = problem.solve()
        step = problem.history.steps[-1]
        assert step.converged
        assert _pressure_error(lam) < 1e-10
        rates = [u.rate for u in step.updates if u.rate is not None]
        # One rate per update from the second on, shown by describe().
        updates = step.iterations[-1].outer
        assert len(rates) == updates - 1 >= 1
        assert f"rate {rates[-1]:.3g}" in problem.history.describe()
        assert rates[-1] < 1.0
        if penalty is None:
            assert problem.penalty == DEFAULT_PENALTY["augmented-lagrangian"] == 100.0
            # Measured: 8 updates, every rate below 0.04 (17 updates at the old default 10).
            assert updates <= 10
            assert max(rates) < 0.1
            assert step.updates[-1].penalty_factor == 1.0
        else:
            # kappa = 1 contracts by 0.4-0.5 per update (80 updates, and a change below
            # the tolerance with an error of 3.8e-10); raised tenfold where the rate is poor.
            assert step.updates[-1].penalty_factor > 1.0
            assert "penalty x" in problem.history.describe()
            assert updates <= 20

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The saddle-point problem: solver options, failures, and the README's example."""

import re
from pathlib import Path

from mpi4py import MPI

import numpy as np
import pytest

from dolfinx_contact_s2s.patch_test import PatchTestCase, solve_patch_test


def test_petsc_options_under_prefix():
    """Options given under the prefix reach the solver; GMRES on the MUMPS LU is exact too."""
    options = {"ksp_type": "gmres", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}
    case = PatchTestCase(elements=(5, 3))
    sol = solve_patch_test(
        MPI.COMM_WORLD, case, petsc_options_prefix="gmres_lu_", petsc_options=options
    )
    owned = sol.pressure.function_space.dofmap.index_map.size_local
    err = np.max(np.abs(sol.pressure.x.array[:owned] - case.pressure), initial=0.0)
    assert MPI.COMM_WORLD.allreduce(err, op=MPI.MAX) < 1e-10


def test_solver_failure_is_an_exception():
    """A solver that cannot converge raises on every rank instead of returning garbage."""
    options = {
        "ksp_type": "cg",
        "pc_type": "none",
        "ksp_max_it": 2,
        "ksp_rtol": 1e-14,
        "ksp_error_if_not_converged": False,
    }
    with pytest.raises(RuntimeError, match="failed to converge"):
        solve_patch_test(
            MPI.COMM_WORLD,
            PatchTestCase(elements=(5, 3)),
            petsc_options_prefix="bad_",
            petsc_options=options,
        )


def test_readme_example():
    """The README's API example runs as written (and asserts the patch test itself)."""
    readme = (Path(__file__).parents[1] / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    assert blocks, "the README has no Python example"
    # The self-contained examples (the others are fragments of the first).
    for block in (b for b in blocks if "import" in b):
        exec(compile(block, "README.md", "exec"), {})

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""MUMPS's iterative refinement on any number of processes.

MUMPS refines only a centralized solution; PETSc keeps it distributed on more than one
process, so ICNTL(10) is ignored there and
:func:`~dolfinx_contact_s2s.options.refine_distributed` takes the steps. The bound on
the refined backward error is the accuracy of the residual that drives the refinement
(Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., Thm. 12.3): a row
of :math:`k` entries is summed with an error of :math:`\\gamma_{k+1}(|\\mathbf
A||\\mathbf x| + |\\mathbf b|)`, so refinement settles at a normwise backward error of
a small multiple of :math:`(k + 1)\\epsilon` (asserted: twice that); without it the
3-process P1 patch test reached 115 :math:`\\epsilon`.
"""

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import pytest

from dolfinx_contact_s2s.la import backward_error
from dolfinx_contact_s2s.options import mumps_factor, refine_distributed
from paper.blocks import block_problem
from paper.scenes import patch_test

EPS = np.finfo(np.float64).eps


def _row_length(A: PETSc.Mat) -> int:
    """Largest number of stored entries in a row, over all processes."""
    start, end = A.getOwnershipRange()
    local = max((A.getRow(i)[0].size for i in range(start, end)), default=0)
    return A.getComm().tompi4py().allreduce(local, op=MPI.MAX)


def _patch_test(degree: int, prefix: str, options: dict | None = None):
    """The P``degree`` patch test (pressure 1 on rollers), a user's mesh of 10 x 7."""
    return block_problem(
        patch_test(MPI.COMM_WORLD, (10, 7)),
        (degree, degree),
        "lower",
        support="rollers",
        pressure=1.0,
        petsc_options_prefix=prefix,
        petsc_options=options,
    )


@pytest.mark.parametrize("degree", [1, 2])
def test_refined_on_any_number_of_processes(degree):
    """The patch test's saddle point solved to the residual's own accuracy.

    One process: MUMPS's two steps (INFOG(15) = 2). Several: MUMPS reports none
    (ICNTL(21) = 1, INFOG(15) = 0) and the package takes them; the backward error is
    within the same a-priori bound either way.
    """
    with _patch_test(degree, "refinement_") as problem:
        problem.solve()
        F = mumps_factor(problem.solver)
        assert F.getMumpsIcntl(10) == -2
        if MPI.COMM_WORLD.size == 1:
            assert (F.getMumpsIcntl(21), F.getMumpsInfog(15)) == (0, 2)
        else:
            assert (F.getMumpsIcntl(21), F.getMumpsInfog(15)) == (1, 0)
        omega = backward_error(problem.A, problem.b, problem.x)
        k = _row_length(problem.A)
        assert omega <= 2 * (k + 1) * EPS, (omega / EPS, k)


def test_refinement_count_follows_icntl_10():
    """ICNTL(10) = -n: n fixed steps on several processes, none on one (MUMPS's own);
    ICNTL(10) = 0: none anywhere."""
    for icntl in (-3, 0):
        with _patch_test(1, "refinement_count_", {"mat_mumps_icntl_10": icntl}) as problem:
            problem.solve()
            x = problem.x.copy()
            steps = refine_distributed(problem.solver, problem.b, x)
            F = mumps_factor(problem.solver)
            parallel = MPI.COMM_WORLD.size > 1
            assert steps == (-icntl if parallel else 0)
            assert F.getMumpsInfog(15) == (0 if parallel else -icntl)
            x.destroy()


def test_refinement_until_round_off():
    """ICNTL(10) = n > 0: up to n steps, stopping at round-off. From a solution off by
    1e-6 relative, in parallel: at least one step and fewer than n, and the bound of
    :func:`test_refined_on_any_number_of_processes`; on one process nothing (MUMPS's
    own steps)."""
    with _patch_test(1, "refinement_until_", {"mat_mumps_icntl_10": 10}) as problem:
        problem.solve()
        x = problem.x.copy()
        x.array[:] *= 1.0 + 1e-6 * np.cos(np.arange(x.array.size))
        steps = refine_distributed(problem.solver, problem.b, x)
        if MPI.COMM_WORLD.size == 1:
            assert steps == 0
        else:
            assert 1 <= steps < 10
            omega = backward_error(problem.A, problem.b, x)
            assert omega <= 2 * (_row_length(problem.A) + 1) * EPS, omega / EPS
        x.destroy()

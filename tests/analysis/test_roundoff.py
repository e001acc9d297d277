"""The round-off bound of a solve (dolfinx_contact_s2s.analysis.roundoff).

The 1-norm estimates are compared with NumPy's dense computation of the same quantities
(an independent implementation); the patch test (a uniform unit
pressure, Eq. 18 with the paper's data) must hold within the bound at any material
contrast, and the bound must follow the contrast rather than be vacuous.
"""

from mpi4py import MPI

import numpy as np
import pytest
import test_system_checks
from test_system_checks import max_pressure_error, readme_problem

from dolfinx_contact_s2s import Material
from dolfinx_contact_s2s.analysis.roundoff import _equilibration, round_off_bound
from dolfinx_contact_s2s.la import gather_dense

comm = MPI.COMM_WORLD


@pytest.mark.parametrize("degree", [1, 2])
def test_condition_estimate_agrees_with_dense(degree):
    with readme_problem(degree=degree, prefix=f"roundoff_{degree}_") as problem:
        problem.solve()
        bound = round_off_bound(problem)
        A = gather_dense(problem.A)
        d = np.concatenate(comm.allgather(_equilibration(problem.A).array_r))
        x = np.concatenate(comm.allgather(problem.x.array_r.copy()))
        b = np.concatenate(comm.allgather(problem.b.array_r.copy()))
        lam = np.concatenate(comm.allgather(problem.fields["lambda0"].getIndices()))
    exact = np.linalg.cond(d[:, None] * A * d[None, :], 1)
    # Higham's estimator is a lower bound, rarely off by more than a factor 3.
    assert exact / 3 <= bound.condition <= exact * (1 + 1e-8)
    # The multiplier bound: 3 omega max_i (|inv(A)| (|A||x| + |b|))_i over the multipliers.
    g = np.abs(A) @ np.abs(x) + np.abs(b)
    reach = np.max((np.abs(np.linalg.inv(A)) @ g)[lam])
    assert reach <= bound.multiplier[0] / bound.backward_error <= 3 * reach * (1 + 1e-8)


@pytest.mark.parametrize("contrast", [1e-4, 1.0, 1e4])
def test_patch_test_within_the_bound(monkeypatch, contrast):
    materials = {"lower": Material(E=1.0, nu=0.3), "upper": Material(E=contrast, nu=0.2)}
    monkeypatch.setattr(test_system_checks, "MATERIALS", materials)
    with readme_problem(degree=2, prefix="roundoff_contrast_") as problem:
        problem.solve()
        bound = round_off_bound(problem)
        error = max_pressure_error(problem)
    assert error <= bound.multiplier[0]
    # Not vacuous: far below the unit pressure; the conditioning follows the contrast.
    assert bound.multiplier[0] < 1e-5
    assert bound.condition >= 0.1 * max(contrast, 1 / contrast)
    assert np.finfo(float).eps <= bound.backward_error < 1e-10

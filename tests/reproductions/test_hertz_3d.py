# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Hertz in 3D, coarse: equilibrium, convergence, and the axisymmetric model of the same bodies.

The quarter model of a sphere (:math:`R = 1`) on a cylindrical block (``paper/hertz3d.py``),
P2 tetrahedra with curved geometry and a P1 multiplier, at :math:`h = R/40` and
:math:`R/80` near the touching point (:math:`a/h = 2` and 4, no node at :math:`r = a`).
Read from :math:`\lambda` (``paper/hertz3d_study.py``). The accuracy study (1%, 2%, 5%) is
``demos/demo_hertz_3d.py``.
"""

from mpi4py import MPI

import pytest

from paper.hertz3d_study import axisymmetric, run


@pytest.fixture(scope="module")
def levels():
    """The two 3D levels and the axisymmetric model at h = R/250."""
    comm = MPI.COMM_WORLD
    coarse = run(comm, "sphere-on-block", h=1 / 40)
    fine = run(comm, "sphere-on-block", h=1 / 80)
    return coarse, fine, axisymmetric(comm, "sphere-on-block", h=1 / 250)


def test_equilibrium(levels):
    """The pair's contact force (B^T Lambda) balances the assembled load to round-off."""
    for rec in levels:
        assert rec["force_error"] <= 1e-10


def test_errors_decrease(levels):
    """The L2 error of lambda against Hertz falls from h = R/40 to R/80."""
    coarse, fine, _ = levels
    assert fine["L2_error"] < coarse["L2_error"]


def test_agrees_with_axisymmetric(levels):
    """3D and axisymmetric models of the same bodies agree within the 3D discretization error.

    The bound: the change of the 3D answer from h = R/40 to R/80 (the a posteriori
    estimate of the finer level's error for a rate of at least 1), plus the axisymmetric
    model's own change from its value against Hertz (its discretization and the finite
    bodies, measured by ``demo_hertz_3d.py`` at 0.1% or less at h = R/500).
    """
    coarse, fine, axi = levels
    for key in ("a", "p0"):
        bound = abs(fine[key] - coarse[key]) + abs(axi[f"{key}_error"]) * axi[f"{key}_exact"]
        assert abs(fine[key] - axi[key]) <= bound, (key, fine[key], axi[key], bound)

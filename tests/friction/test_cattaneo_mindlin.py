# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Cattaneo-Mindlin in 2D: two identical cylinders, a normal load, then a tangential one.

The scene of :func:`paper.friction.cattaneo_mindlin`: two half cylinders of radius
:math:`R = 1` (:func:`paper.hertz.scene.hertz` with ``lower_radius=R``, graded for
:math:`a = 0.05`, no node placed at the contact edges), plane strain, :math:`E = 1`,
:math:`\nu = 0.3`, the lower flat face clamped, the upper one moved rigidly: first by
:math:`(0, -\delta)` in four frictionless steps (Hertz: :math:`a = 2 \sqrt{P R_e /
(\pi E^*)}`, :math:`p_0 = 2 P / (\pi a)`, :math:`R_e = R/2`, :math:`E^* = E / (2 (1 -
\nu^2))`), then by :math:`(d, -\delta)` in four steps with :math:`\mu = 0.2`. Identical
bodies: the normal and tangential problems decouple, and Cattaneo and Mindlin's shear
for a tangential force :math:`Q < \mu P` is

.. math:: q(x) = \frac{\mu p_0}{a} \left[\sqrt{a^2 - x^2} - \sqrt{c^2 - x^2}\right]
    \text{ for } |x| < c, \qquad \mu p(x) \text{ for } c < |x| < a, \qquad
    c = a \sqrt{1 - Q / (\mu P)},

:math:`P` and :math:`Q` read from :math:`\lambda_n` and :math:`\lambda_t` (their
integrals). The issue's bounds: the stick half-width within one element (the middle of
the brackets of the stick zone's ends: last sticking, first slipping node), and (P2) the
shear within 5% relative L2 over :math:`[-a, a]`.

On a mesh refined by the solution (:func:`paper.friction_adaptive.cattaneo_mindlin_adaptive`:
the user's mesh of 20 P1 or 10 P2 elements across :math:`2a`, refined around the ends of
the contact and stick zones until their brackets are 1% of :math:`a`), the issue's
bounds for P1 and P2: :math:`c` within 2% and within one element of the user's mesh,
:math:`q` within 5% relative L2.
"""

import itertools

from mpi4py import MPI

import pytest

from paper.friction import CM_A, cattaneo_mindlin
from paper.friction_adaptive import cattaneo_mindlin_adaptive


@pytest.mark.parametrize("degree", [1, 2])
def test_cattaneo_mindlin(degree):
    rec = cattaneo_mindlin(MPI.COMM_WORLD, degree, across=20)
    assert 0.3 < rec["Q_over_muP"] < 0.7
    assert rec["c_middle_error_elements"] <= 1.0
    if degree == 2:
        assert rec["q_L2_error"] <= 0.05


@pytest.mark.parametrize("degree, across", [(1, 20), (2, 10)])
def test_cattaneo_mindlin_refined_by_the_solution(degree, across):
    rec = cattaneo_mindlin_adaptive(MPI.COMM_WORLD, degree, across, tolerance=0.01)
    assert 0.3 < rec["Q_over_muP"] < 0.7
    # Every step but the first refines: the brackets halve until 1% of a.
    relative = [s["relative"] for s in rec["steps"]]
    assert relative[-1] <= 0.01 < relative[-2]
    assert all(b <= 0.55 * a for a, b in itertools.pairwise(relative))
    assert rec["c_middle_error"] <= 0.02
    assert rec["c_middle_error"] * rec["c_exact"] <= 2 * CM_A / across
    assert rec["q_L2_error"] <= 0.05

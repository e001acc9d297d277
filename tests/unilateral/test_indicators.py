# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Where refine_contact_zone refines inside a 3D zone, against closed forms.

Hertz's :math:`p = p_0 \sqrt{1 - r^2/a^2}` as a P1 multiplier on the top face of a
tetrahedral unit cube (edges :math:`h = 1/N` along :math:`x` and :math:`y`, one diagonal
per square), centred on a node. The fitted plane of a centrally symmetric ring passes
through its neighbours' mean, so the indicator of the centre node is
:math:`1 - \frac16 [4 \sqrt{1 - h^2/a^2} + 2 \sqrt{1 - 2h^2/a^2}]` (relative to
:math:`p_0`); the balls are around the nodes above the tolerance, none within a tenth of
the front's diameter of the front.
"""

import types

from mpi4py import MPI

import dolfinx
import numpy as np

from dolfinx_contact_s2s import contact_front
from dolfinx_contact_s2s.contact_front import curvature_indicator
from dolfinx_contact_s2s.unilateral.indicators import curvature_balls

N, A, P0 = 16, 0.3, 2.5
CENTRE = np.array([0.5, 0.5, 1.0])


def _hertz():
    cube = dolfinx.mesh.create_unit_cube(MPI.COMM_WORLD, N, N, 4)
    cube.topology.create_connectivity(2, 3)
    top = dolfinx.mesh.locate_entities_boundary(cube, 2, lambda x: np.isclose(x[2], 1.0))
    Q = dolfinx.fem.functionspace(dolfinx.mesh.create_submesh(cube, 2, top)[0], ("Lagrange", 1))
    lam, flags = dolfinx.fem.Function(Q), dolfinx.fem.Function(Q)

    def r2(x):
        return (x[0] - CENTRE[0]) ** 2 + (x[1] - CENTRE[1]) ** 2

    lam.interpolate(lambda x: P0 * np.sqrt(np.clip(1 - r2(x) / A**2, 0, None)))
    flags.interpolate(lambda x: (r2(x) < A**2).astype(float))
    return lam, flags


def test_centre_of_hertz_and_the_balls():
    """The centre node's indicator in closed form; balls above the tolerance, off the band."""
    lam, flags = _hertz()
    h = 1.0 / N
    exact = 1 - (4 * np.sqrt(1 - h**2 / A**2) + 2 * np.sqrt(1 - 2 * h**2 / A**2)) / 6
    points, eta, longest = curvature_indicator([lam], flags)
    at = np.flatnonzero(np.linalg.norm(points - CENTRE, axis=1) < 1e-12)
    assert at.size == 1
    assert abs(eta[at[0]] - exact) <= 1e-12
    assert abs(longest[at[0]] - np.sqrt(2) * h) <= 1e-15

    axis = (CENTRE, (0.0, 0.0, 1.0))
    front = contact_front(lam, flags, centre=axis[0], axis=axis[1])
    problem = types.SimpleNamespace(active=[flags], multipliers=[lam], pairs=[None])
    for tolerance, has_centre in ((0.99 * exact, True), (1.01 * exact, False)):
        worst, balls = curvature_balls(problem, axis, [front], tolerance, layers=2.0)
        centres = np.array([b[:3] for b in balls]).reshape(-1, 3)
        r = np.linalg.norm(centres[:, :2] - CENTRE[:2], axis=1)
        assert np.any(r < 1e-12) == has_centre
        assert np.all(r <= 0.8 * front.radius)  # the front's band is its own criterion
        assert worst >= exact and all(b[3] > 0 for b in balls)
        # Every node off the band above the tolerance has its ball.
        outside = np.hypot(*(points[:, :2] - CENTRE[:2]).T)
        expected = (eta > tolerance) & (np.abs(outside - front.radius) >= 0.2 * front.radius)
        assert len(balls) == np.count_nonzero(expected)

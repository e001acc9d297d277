# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The other FEniCSx contact package's friction demo, solved here, on a coarse mesh.

The scene of :func:`paper.friction.half_disks`: two identical half disks of radius
:math:`R = 8` touching at their poles, :math:`E = 200`, :math:`\nu = 0.3`, plane
strain, the lower flat face clamped; a normal traction :math:`0.625` on the upper flat
face (:math:`F = 10` per unit thickness) in four frictionless steps with the axes
:math:`x = 0` held sideways, then, continuing in a second problem with the axes released
and the top's vertical motion held, :math:`\mu = 0.2` and a tangential traction
:math:`0.05851` (:math:`Q = 0.936`, :math:`Q/(\mu F) = 0.468`) in eight steps. Hertz
(:math:`R_e = R/2`): :math:`a = 0.681`, :math:`p_0 = 9.35`; Cattaneo and Mindlin:
:math:`c = a \sqrt{1 - Q/(\mu F)} = 0.729 a = 0.4965`. P2 on the user's mesh of
:func:`paper.friction.half_disks_mesh` with :math:`h = 0.1` within 1 of the poles
(about 14 elements across :math:`2a`).

Asserted: the upper body's equilibrium, the load the contact tractions balance (read
from the couplings) equal to :math:`F` after the normal steps and to :math:`Q` at the
end, to :math:`\min(10^{-10}, 100 \epsilon n)` relative (:math:`n` unknowns); the stick
half-width (the outermost sticking node) within one element of :math:`c`; the shear
within 10% relative L2 over :math:`[-a, a]` of Cattaneo and Mindlin's :math:`q(x)`, a
bound stated before the first run (measured: 6.9%).
"""

from mpi4py import MPI

import numpy as np

from paper.friction import half_disks


def test_half_disks():
    rec = half_disks(MPI.COMM_WORLD, 2, 0.1)
    tol = min(1e-10, 100 * np.finfo(np.float64).eps * rec["unknowns"])
    assert abs(rec["P_normal"] - rec["F"]) <= tol * rec["F"]
    assert abs(rec["Q_measured"] - rec["Q"]) <= tol * rec["Q"]
    assert rec["c_error_elements"] <= 1.0
    assert rec["q_L2_error"] <= 0.10

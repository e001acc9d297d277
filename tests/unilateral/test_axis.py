# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""A point contact on the axis of an axisymmetric P2 model: the first active set and c_k.

The P2 vertex function on the axis, on its facet [0, h], has a zero r-weighted integral
(int_0^h (1 - s)(1 - 2s) r dr = 0, s = r/h): alone, the multiplier of that vertex
transmits no force. The scene is a coarse P2 sphere on a rigid plane (paper/hertz), held
by the contact alone.
"""

import math

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl

from paper.hertz.axisymmetric import sphere_on_plane

comm = MPI.COMM_WORLD
F = 4 * 0.05**3 / (3 * (1 - 0.3**2))  # a = 0.05 on R = 1, E = 1, nu = 0.3


def first_set(problem):
    """The first active set's radii and r-weighted integrals, computed here (all ranks)."""
    Q = problem.pairs[0].Q
    n = Q.dofmap.index_map.size_local
    start = Q.dofmap.index_map.local_range[0]
    first = problem.history.steps[0].iterations[0].active_sets[0] - start
    mu = ufl.TestFunction(Q)
    r = ufl.SpatialCoordinate(Q.mesh)[0]
    forces = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(mu * 2 * math.pi * r * ufl.dx))
    forces.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    values = forces.array_r[:n][first].copy()
    forces.destroy()
    radii = Q.tabulate_dof_coordinates()[:n, 0][first]
    scales = problem.scales[0].array_r
    constrained = scales > 0
    return {
        "radii": np.concatenate(comm.allgather(radii)),
        "forces": np.concatenate(comm.allgather(values)),
        "scales": np.concatenate(comm.allgather(scales[constrained])),
        "scale_radii": np.concatenate(
            comm.allgather(Q.tabulate_dof_coordinates()[:n, 0][constrained])
        ),
    }


def test_nearest_start_transmits_a_force():
    """The default start works; its set holds the axis vertex and transmits a force.

    Before: the set was the axis vertex alone, and the first solve raised "rigid motions
    free" for a well-posed problem.
    """
    result = sphere_on_plane(comm, F=F, h=0.02, degree=2, hook=first_set)
    found = result.extra["hook"]
    assert np.min(found["radii"]) < 1e-12  # the axis vertex (r = 0 up to round-off)
    assert found["radii"].size >= 2
    assert np.sum(found["forces"]) > 0.0
    # Equilibrium: the plane's normal is the load's: the contact force is F.
    assert abs(result.force / F - 1) < 1e-9


def test_axis_scale_not_amplified():
    r"""c_k of the axis vertex is of the order of its neighbours', and the residual is round-off.

    The axis vertex's ring area is O(h^2), its neighbours' O(h r): c_k may be larger there,
    by the ratio of those areas (about 1e2 at this h), not by 1e7 (the round-off row sum
    of 1e-11 taken as its area). The converged residual is then of round-off size, not the
    1e-10 that stalled the loop at a finer mesh.
    """
    result = sphere_on_plane(comm, F=F, h=0.02, degree=2, hook=first_set, start="tied")
    found = result.extra["hook"]
    near = found["scale_radii"] <= 0.1
    assert np.max(found["scales"][near]) < 1e3 * np.median(found["scales"][near])
    assert result.extra["residuals"][-1] < 1e-13

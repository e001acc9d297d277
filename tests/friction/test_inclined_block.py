# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""A block pushed up a slope: the reaction's ratio of Coulomb sliding on an incline.

The two blocks of :func:`paper.scenes_multi.two_blocks_one_mesh` sheared by
:math:`y \mapsto y + x \tan\alpha`, :math:`\tan\alpha = 0.1`: their contact line rises
at the angle :math:`\alpha`. The lower block is clamped at its bottom; the upper one is
pressed by a vertical load on its top and pushed up the slope by a prescribed
:math:`u_x = d` on its left side, far beyond the stick limit, so that all of it slides
with :math:`\mu = 0.5`. The contact force on the sliding block then has the ratio
:math:`|F_x| / F_y = (\mu + \tan\alpha) / (1 - \mu \tan\alpha) = 0.6316`, and by the
block's equilibrium so has the reaction :math:`R_x` of the push to the vertical load
:math:`V`: measured from the residual :math:`a(u, v) - L(v)` at the pushed dofs, not
from :math:`\lambda`.
"""

import math

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from paper.scenes_multi import two_blocks_one_mesh

TAN, MU = 0.1, 0.5


@pytest.mark.parametrize("degree", [1, 2])
def test_inclined_block(degree):
    part = two_blocks_one_mesh(MPI.COMM_WORLD, (7, 5)).parts["blocks"]
    mesh, tags = part.mesh, part.facet_tags
    mesh.geometry.x[:, 1] += TAN * mesh.geometry.x[:, 0]
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a, _, v = Material(1.0, 0.3).forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    load = 0.2
    L = -load * v[1] * ds(23)
    fdim = mesh.topology.dim - 1
    clamp = dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(1))
    # The left side's nodes off the contact line: their residual is the push's reaction.
    push = np.setdiff1d(
        dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, tags.find(24)),
        dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, tags.find(20)),
    )
    bcs = [
        dolfinx.fem.dirichletbc(np.zeros(2), clamp, V),
        dolfinx.fem.dirichletbc(dolfinx.default_scalar_type(5.0), push, V.sub(0)),
    ]
    pair = contact_pair(
        contact_surface(V, tags, 20), contact_surface(V, tags, 10), multiplier=("Lagrange", degree)
    )
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=MU, petsc_options_prefix=f"incline{degree}_"
    ) as problem:
        (u,), _, _ = problem.solve()
        last = problem.history.steps[-1].iterations[-1]
        assert last.active[0] > 0 and last.stick == (0,)
    residual = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(ufl.action(a, u) - L))
    residual.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    owned = push[push < residual.getLocalSize()]
    reaction = MPI.COMM_WORLD.allreduce(float(np.sum(residual.array_r[owned])))
    residual.destroy()
    V_load = MPI.COMM_WORLD.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(load * ds(23))))
    expected = (MU + TAN) / (1 - MU * TAN)
    assert math.isclose(reaction / V_load, expected, rel_tol=1e-8)

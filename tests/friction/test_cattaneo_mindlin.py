# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Cattaneo-Mindlin in 2D: two identical cylinders, a normal load, then a tangential one.

Two half cylinders of radius :math:`R = 1` (:func:`paper.hertz.scene.hertz` with
``lower_radius=R``, graded for :math:`a = 0.05`), plane strain, :math:`E = 1`,
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
integrals). The issue's bounds: the stick half-width within one element, and (P2) the
shear within 5% relative L2 over :math:`[-a, a]`.
"""

import math

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from paper.hertz.scene import TAGS, hertz

E, NU, R, MU, ACROSS = 1.0, 0.3, 1.0, 0.2, 20
#: The rigid motions of the upper face: a about 0.05, Q / (mu P) about 0.5.
DELTA, SHIFT = 0.009, 0.00147


def _gather(values):
    return np.concatenate(MPI.COMM_WORLD.allgather(values))


@pytest.mark.parametrize("degree", [1, 2])
def test_cattaneo_mindlin(degree):
    scene = hertz(
        MPI.COMM_WORLD,
        R=R,
        a=0.05,
        elements_across=ACROSS,
        lower_radius=R,
        geometry_degree=degree,
    )
    mesh, tags = scene.mesh, scene.facet_tags
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    a_form, _, v = Material(E, NU).forms(V)
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.zeros(2)), v) * ufl.dx
    motion = dolfinx.fem.Function(V)
    fdim = mesh.topology.dim - 1
    top = dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(TAGS["upper_top"]))
    bottom = dolfinx.fem.locate_dofs_topological(V, fdim, tags.find(TAGS["lower_bottom"]))
    bcs = [
        dolfinx.fem.dirichletbc(motion, top),
        dolfinx.fem.dirichletbc(dolfinx.fem.Function(V), bottom),
    ]
    pair = contact_pair(
        contact_surface(V, tags, TAGS["contactor"]), contact_surface(V, tags, TAGS["target"])
    )

    def integral(f):
        return MPI.COMM_WORLD.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(f * ufl.dx)))

    with FrictionalContactProblem(
        a_form, L, [pair], bcs, mu=MU, petsc_options_prefix=f"cm{degree}_"
    ) as problem:
        motion.interpolate(lambda x: np.stack([0.0 * x[0], -DELTA + 0.0 * x[0]]))
        problem.solve([0.25, 0.5, 0.75, 1.0], mu=0.0)
        for k in range(1, 5):
            motion.interpolate(
                lambda x, k=k: np.stack([0 * x[0] + k * SHIFT / 4, -DELTA + 0 * x[0]])
            )
            (_,), (lam_n,), (lam_t,) = problem.solve([1.0], restart=False)
            assert problem.history.steps[-1].converged
        P, Q = integral(lam_n), integral(lam_t)
        n = pair.Q.dofmap.index_map.size_local
        x = _gather(pair.Q.tabulate_dof_coordinates()[:n, 0])
        q, stick = _gather(lam_t.x.array[:n]), _gather(problem.stick[0].x.array[:n]) > 0.5
    E_star, R_e = E / (2 * (1 - NU**2)), R / 2
    a = 2 * math.sqrt(P * R_e / (math.pi * E_star))
    p0 = 2 * P / (math.pi * a)
    c = a * math.sqrt(1 - Q / (MU * P))
    h = 2 * 0.05 / ACROSS  # the element size at the contact
    assert 0.3 < Q / (MU * P) < 0.7
    assert abs(np.max(np.abs(x[stick])) - c) <= h
    if degree == 2:
        order = np.argsort(x)
        fine = np.linspace(-a, a, 20001)
        exact = (
            MU
            * p0
            / a
            * (
                np.sqrt(np.clip(a**2 - fine**2, 0, None))
                - np.sqrt(np.clip(c**2 - fine**2, 0, None))
            )
        )
        error = np.interp(fine, x[order], q[order]) - exact
        assert math.sqrt(np.trapezoid(error**2, fine) / np.trapezoid(exact**2, fine)) <= 0.05

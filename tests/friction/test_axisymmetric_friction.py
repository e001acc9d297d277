# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Coulomb friction in axisymmetry: the rings of two coaxial cylinders.

The axisymmetric patch test's scene (:func:`paper.scenes.patch_test` in the
:math:`(r, z)` half-section, non-matching, solid or hollow): the upper cylinder pressed by
:math:`p` on its top, the lower one's base on :math:`u_z = 0`. The tangent of the
contact face is radial, and every row of the coupling carries the ring length
:math:`2\pi r` (``contact_pair(..., axisymmetric=True)``).

- Identical materials: the uniform state :math:`\sigma_{zz} = -p` expands both bodies
  alike (:math:`u_r = \nu p r / E`), so nothing slips and nothing shears:
  :math:`\lambda_n = p`, :math:`\lambda_t = 0`, every multiplier sticks, exactly.
- Different materials (:math:`E = 1, \nu = 0.3` below, :math:`E = 3, \nu = 0.2` above):
  the lower body expands more; :math:`\mu = 0` gives the frictionless answer, and with
  :math:`\mu = 0.1` (some nodes stick, some slip) the converged multipliers obey
  Coulomb's law node by node against the ring-weighted slips
  :math:`\tilde s = \mathbf B_t \mathbf U`.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper import scenes

BOUND = 1e-10
P = 0.6


def _worst(values):
    return MPI.COMM_WORLD.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def _scene(degree, shift, materials):
    """Forms, conditions and the pair of the two cylinders, moved out by ``shift``."""
    scene = scenes.patch_test(MPI.COMM_WORLD, (7, 5), cell="triangle")
    a, L, bcs, surfaces = [], [], [], {}
    for name, body in scene.bodies.items():
        body.mesh.geometry.x[:, 0] += shift
        V = dolfinx.fem.functionspace(body.mesh, ("Lagrange", degree, (2,)))
        material = Material(*materials[name], "axisymmetric")
        form, _, v = material.forms(V)
        ds = ufl.Measure("ds", domain=body.mesh, subdomain_data=body.facet_tags)
        load = dolfinx.fem.Constant(body.mesh, -P if name == "upper" else 0.0)
        a.append(form)
        L.append(load * v[1] * material.weight(body.mesh) * ds(scenes.TOP))
        fdim = body.mesh.topology.dim - 1
        held = [(1, scenes.BOTTOM)] if name == "lower" else []
        held += [(0, scenes.LEFT)] if shift == 0.0 else []  # u_r = 0 on the axis
        for component, tag in held:
            dofs = dolfinx.fem.locate_dofs_topological(
                V.sub(component), fdim, body.facet_tags.find(tag)
            )
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(component)))
        surfaces[name] = contact_surface(V, body.facet_tags, body.contact)
    pair = contact_pair(surfaces["upper"], surfaces["lower"], axisymmetric=True)
    return a, L, bcs, pair


SAME = {"lower": (1.0, 0.3), "upper": (1.0, 0.3)}
DIFFERENT = {"lower": (1.0, 0.3), "upper": (3.0, 0.2)}


@pytest.mark.parametrize(("degree", "shift"), [(1, 0.0), (2, 0.0), (2, 0.5)])
def test_identical_rings_stick_without_shear(degree, shift):
    """Identical materials: lambda_n = p, lambda_t = 0, all stick, to 1e-10 relative."""
    a, L, bcs, pair = _scene(degree, shift, SAME)
    with FrictionalContactProblem(a, L, [pair], bcs, mu=0.3, petsc_options_prefix="ax_") as pb:
        _, (lam_n,), (lam_t,) = pb.solve()
        n = pair.Q.dofmap.index_map.size_local
        assert _worst(lam_n.x.array[:n] - P) <= BOUND * P
        assert _worst(lam_t.x.array[:n]) <= BOUND * P
        assert _worst(pb.stick[0].x.array[:n] - 1.0) == 0.0


@pytest.mark.parametrize("degree", [1, 2])
def test_frictionless_rings(degree):
    """mu = 0 with different materials: the frictionless unilateral answer, lambda_t = 0."""
    a, L, bcs, pair = _scene(degree, 0.0, DIFFERENT)
    with UnilateralContactProblem(a, L, [pair], bcs, petsc_options_prefix="ax0_") as ref:
        us_ref, (lam_ref,) = ref.solve()
        expected = [u.x.array.copy() for u in us_ref], lam_ref.x.array.copy()
    a, L, bcs, pair = _scene(degree, 0.0, DIFFERENT)
    with FrictionalContactProblem(a, L, [pair], bcs, mu=0.0, petsc_options_prefix="ax1_") as pb:
        us, (lam_n,), (lam_t,) = pb.solve()
        for u, e in zip(us, expected[0], strict=True):
            assert _worst(u.x.array - e) <= BOUND * _worst(e)
        assert _worst(lam_n.x.array - expected[1]) <= BOUND * P
        assert _worst(lam_t.x.array) == 0.0


@pytest.mark.parametrize("degree", [1, 2])
def test_coulomb_law_on_rings(degree):
    r"""Different materials, mu = 0.1: Coulomb's law node by node on the ring-weighted slips.

    :math:`|\lambda_t| \le \mu \lambda_n`; :math:`\tilde s = 0` where a node sticks;
    :math:`\lambda_t = \mu \lambda_n\, \mathrm{sign}(\tilde s)` where it slips; some of
    each (the outer nodes slip, the lower body expanding more).
    """
    mu = 0.1
    a, L, bcs, pair = _scene(degree, 0.0, DIFFERENT)
    with FrictionalContactProblem(a, L, [pair], bcs, mu=mu, petsc_options_prefix="ax2_") as pb:
        us, (lam_n,), (lam_t,) = pb.solve()
        n = pair.Q.dofmap.index_map.size_local
        p, t = lam_n.x.array[:n], lam_t.x.array[:n]
        stick, active = pb.stick[0].x.array[:n] > 0.5, pb.active[0].x.array[:n] > 0.5
        op = assemble_coupling(pair, tangential=1)
        s = op.G.duplicate()
        s.set(0.0)
        for V, B in op.blocks:
            B.multAdd(us[pb.spaces.index(V)].x.petsc_vec, s, s)
        slip = s.array_r.copy()
        for obj in (s, op):
            obj.destroy()
    total = MPI.COMM_WORLD.allreduce
    assert total(int(stick.sum())) > 0 and total(int((active & ~stick).sum())) > 0
    assert _worst(np.maximum(np.abs(t) - mu * p, 0.0)) <= BOUND * P
    assert _worst(slip[stick]) <= BOUND * _worst(slip)
    sliding = active & ~stick
    assert _worst(t[sliding] - mu * p[sliding] * np.sign(slip[sliding])) <= BOUND * P

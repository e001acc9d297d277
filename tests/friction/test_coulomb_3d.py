# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Coulomb friction in 3D (issue [4/6]): patch tests, the tangent basis, the coupling.

The frictional patch tests of :mod:`paper.friction3d`: two non-matching blocks
(tetrahedra against hexahedra, optionally with the nodes moved at random in the plane of
the contact) in the uniform state :math:`\sigma_{zz} = -p`, :math:`\sigma_{xz} = \tau_x`,
:math:`\sigma_{yz} = \tau_y`. Stick (:math:`|\tau| < \mu p`): :math:`\lambda_n = p`,
:math:`\lambda_t = \tau` and the displacement of the uniform state; slip (the top moved
beyond the stick limit along 30 degrees): :math:`\lambda_t = \mu p\, \mathbf d /
|\mathbf d|`, the upper block displaced by :math:`\mathbf d`. Every number is exact, so
the bound is the issue's: 1e-10 relative (the conditioning bound of the patch tests on
well-conditioned meshes, issue 12).
"""

from mpi4py import MPI

import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.friction.coulomb import tangent_axis
from dolfinx_contact_s2s.kernels.face_backend import tangents
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.blocks3d import BOTTOM, TOP, scene
from paper.friction3d import extruded, extruded_scene, inclined_block, patch

BOUND = 1e-10


def check(record):
    bound = BOUND
    assert record["converged"]
    assert record["lambda_n_error"] <= bound
    assert record["lambda_t_error"] <= bound
    assert record["u_error"] <= bound
    assert record["active"] == record["multipliers"]
    assert record["stick"] == (record["multipliers"] if record["case"] == "stick" else 0)


@pytest.mark.parametrize("seed", [None, 1])
@pytest.mark.parametrize(
    "cells, degree",
    [(("tet", "hex"), 1), (("hex", "tet"), 1), (("tet", "hex"), 2), (("hex", "hex"), 2)],
)
@pytest.mark.parametrize("case", ["stick", "slip"])
def test_patch(case, cells, degree, seed):
    """Full stick and full slip on non-matching faces, exact to the conditioning bound.

    The contactor (the upper block) is a hexahedron with P2: the vertex functions of a P2
    multiplier on triangles integrate to zero, which inequality contact refuses.
    """
    check(patch(case, cells, degree, seed))


@pytest.mark.parametrize("axis", [(0.0, 1.0, 0.0), (1.0, 2.0, 0.5)])
@pytest.mark.parametrize("case", ["stick", "slip"])
def test_answer_does_not_depend_on_the_tangent_basis(case, axis):
    """Another axis turns the components of lambda_t, not the state (Coulomb's disk)."""
    record = patch(case, ("tet", "hex"), 1, seed=2, axis=axis)
    assert np.allclose(record["axis"], np.asarray(axis) / np.linalg.norm(axis))
    check(record)


@pytest.mark.parametrize("case", ["stick", "slip"])
def test_lower_block_as_contactor(case):
    """The shear the lower block exerts on the upper one: minus tau, exact."""
    check(patch(case, ("hex", "tet"), 1, contactor="lower"))


def _pair(degree=1):
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene("tet", "hex", degree, seed=1)
    pair = contact_pair(contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP))
    return pair, (V_lo, V_up), a, L, bcs


@pytest.mark.parametrize("degree", [1, 2])
def test_tangential_coupling_of_a_translation(degree):
    r"""B_t of a rigid translation e of the contactor: (e . T_k) times B_n of a motion N.

    Row by row, :math:`\int \mu_j \phi_i (\mathbf e \cdot \mathbf T_k)` summed over the
    contactor's nodes against :math:`\int \mu_j \phi_i (\mathbf N \cdot \mathbf N)`; the
    target's block gives minus the same (the face is covered), and the rows sum to
    :math:`\mathbf e \cdot \mathbf T_k` times the contact area, 1.
    """
    pair, (V_lo, V_up), *_ = _pair(degree)
    axis = tangent_axis(pair)
    normal = np.array([0.0, 0.0, 1.0])  # N = -n_C of the upper block's bottom
    e = np.array([0.3, -0.7, 0.2])
    ops = [assemble_coupling(pair)] + [assemble_coupling(pair, k, axis) for k in (1, 2)]

    def row_sums(op, V, vector):
        block = op.block(V)
        x, y = block.createVecs()
        x.array[:] = np.tile(vector, x.getLocalSize() // 3)
        block.mult(x, y)
        return y.array_r.copy()

    try:
        reference = row_sums(ops[0], V_up, normal)
        for k in (1, 2):
            along = float(e @ tangents(normal[None], axis, k)[0])
            upper = row_sums(ops[k], V_up, e)
            lower = row_sums(ops[k], V_lo, e)
            scale = np.max(np.abs(reference))
            assert np.max(np.abs(upper - along * reference), initial=0) <= 1e-13 * scale
            assert np.max(np.abs(lower + along * reference), initial=0) <= 1e-13 * scale
            total = MPI.COMM_WORLD.allreduce(float(upper.sum()), op=MPI.SUM)
            assert abs(total - along) <= 1e-13
    finally:
        for op in ops:
            op.destroy()


def test_degenerate_tangent_basis_is_refused():
    """An axis along the contact normal: a clear error on every rank, naming the surface."""
    pair, _, a, L, bcs = _pair()
    with pytest.raises(ValueError, match=r"tangent basis of friction degenerates on contact"):
        with FrictionalContactProblem(
            a, L, [pair], bcs, mu=0.3, tangent_axis=(0, 0, 1), petsc_options_prefix="dg_"
        ) as problem:
            problem.solve()
    with pytest.raises(ValueError, match="nonzero 3-vector"):
        tangent_axis(pair, (0.0, float("nan"), 1.0))


@pytest.mark.parametrize("degree", [1, 2])
def test_extruded_equals_plane_strain(degree):
    r"""One layer of hexahedra with :math:`u_z = 0`: the 2D problem times the layer's integrals.

    The 2D plane-strain solution extended along :math:`z` solves the 3D discrete problem
    (stiffness, coupling and loads are the 2D ones times the layer's integrals, the
    multiplier constant along :math:`z`), which has one solution: the 3D multipliers
    (face kernels, two tangents, the Newton rows of slip on faces) equal the 2D ones
    (edge kernels, one tangent) node by node, and the sets repeat the 2D ones on every
    layer of nodes, on a punch with partial slip.
    """
    two, three = extruded(2, degree), extruded(3, degree)
    layers = degree + 1
    assert three["sets"] == [
        [((layers * a[0],), (layers * s[0],)) for a, s in step] for step in two["sets"]
    ]
    assert 0 < np.count_nonzero(two["stick"]) < np.count_nonzero(two["active"])  # partial
    place = {tuple(np.round(x, 9)): i for i, x in enumerate(two["x"])}
    at = np.array([place[tuple(np.round(x[:2], 9))] for x in three["x"]])
    scale = np.max(np.abs(two["pressure"]))
    for key in ("pressure", "shear"):
        assert np.max(np.abs(three[key] - two[key][at])) <= BOUND * scale
    assert np.max(np.abs(three["normal_shear"])) <= BOUND * scale
    np.testing.assert_array_equal(three["stick"], two["stick"][at])


@pytest.mark.parametrize("degree", [1, 2])
def test_coulomb_disk_node_by_node(degree):
    r"""A slab (:math:`u_z` free) with partial slip: Coulomb's disk at every node.

    One load step from rest, :math:`\tilde s = \mathbf B_t \mathbf U` recomputed from the
    tangential couplings: :math:`|\lambda_t| \le \mu \lambda_n`; :math:`\tilde s = 0` where
    a node sticks; where it slips, :math:`\lambda_t = \mu \lambda_n \tilde s / |\tilde
    s|` (the direction of the slip, both components); :math:`\lambda = 0` off contact.
    """
    mu = 0.3
    r = extruded(3, degree, mu=mu, plane_strain=False, loads=(1.0,))
    p, t, s = r["pressure"], r["traction"], r["slip"]
    stick, active = r["stick"], r["active"]
    assert 0 < np.count_nonzero(stick) < np.count_nonzero(active)
    scale, size = np.max(np.abs(p)), np.linalg.norm(s, axis=1)
    assert np.max(np.linalg.norm(t, axis=1) - mu * p) <= BOUND * scale
    assert np.max(size[stick]) <= BOUND * np.max(size)
    sliding = active & ~stick
    assert np.all(size[sliding] > 1e-6 * np.max(size))
    expected = mu * p[sliding, None] * s[sliding] / size[sliding, None]
    assert np.max(np.abs(t[sliding] - expected)) <= BOUND * scale
    assert np.max(np.abs(p[~active]), initial=0.0) == 0.0


def test_ranks_agree():
    """The slab on all ranks and on each rank alone: the same sets and values."""
    world = extruded(3, 2, MPI.COMM_WORLD, plane_strain=False)
    alone = extruded(3, 2, MPI.COMM_SELF, plane_strain=False)
    assert world["sets"] == alone["sets"]
    place = {tuple(np.round(x, 9)): i for i, x in enumerate(alone["x"])}
    at = np.array([place[tuple(np.round(x, 9))] for x in world["x"]])
    scale = np.max(np.abs(alone["pressure"]))
    for key in ("pressure", "traction", "slip"):
        size = scale if key != "slip" else np.max(np.abs(alone["slip"]))
        assert np.max(np.abs(world[key] - alone[key][at])) <= BOUND * size
    np.testing.assert_array_equal(world["stick"], alone["stick"][at])


@pytest.mark.parametrize(
    "cells, degree", [(("tet", "hex"), 1), (("hex", "tet"), 1), (("tet", "hex"), 2)]
)
def test_inclined_block(cells, degree):
    """Pushed up a tilted plane, all sliding: R_x / V = (mu + tan a)/(1 - mu tan a) to 1e-8."""
    record = inclined_block(MPI.COMM_WORLD, degree, cells=cells)
    assert record["sliding"]
    assert record["error"] <= 1e-8


@pytest.mark.parametrize("degree", [1, 2])
def test_mu_zero_is_frictionless(degree):
    """The slab with mu = 0: the frictionless unilateral answer, lambda_t = 0, to 1e-10."""
    a, L, bcs, pair, _ = extruded_scene(3, degree, plane_strain=False)
    with UnilateralContactProblem(a, L, [pair], bcs, petsc_options_prefix="mu0u_") as ref:
        us, (lam,) = ref.solve([0.5, 1.0])
        expected = [u.x.array.copy() for u in us], lam.x.array.copy()
    a, L, bcs, pair, _ = extruded_scene(3, degree, plane_strain=False)
    with FrictionalContactProblem(a, L, [pair], bcs, mu=0.0, petsc_options_prefix="mu0f_") as pb:
        us, (lam_n,), lam_t = pb.solve([0.5, 1.0])
        worst = MPI.COMM_WORLD.allreduce
        scale = worst(float(np.max(np.abs(expected[1]))), op=MPI.MAX)
        assert worst(float(np.max(np.abs(lam_n.x.array - expected[1]))), op=MPI.MAX) <= (
            BOUND * scale
        )
        for u, e in zip(us, expected[0], strict=True):
            size = worst(float(np.max(np.abs(e))), op=MPI.MAX)
            assert worst(float(np.max(np.abs(u.x.array - e))), op=MPI.MAX) <= BOUND * size
        assert all(worst(float(np.max(np.abs(f.x.array))), op=MPI.MAX) == 0.0 for f in lam_t)

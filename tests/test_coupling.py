# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The coupling block B of Eq. (40) against UFL-assembled facet integrals and closed forms."""

from mpi4py import MPI

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.coupling import box_pairs
from dolfinx_contact_s2s.petsc import assemble_coupling, gather_dense
from dolfinx_contact_s2s.scenes import patch_test

# Gmsh places transfinite nodes within a few 1e-12 of i * W / n, not exactly there.
GEOMETRY_NOISE = 1e-10


def _dof_coordinates(V):
    """Coordinates of every global dof of a scalar space, on every rank."""
    imap = V.dofmap.index_map
    n = imap.size_local
    x = V.tabulate_dof_coordinates()[:n, :2]
    parts = V.mesh.comm.allgather((imap.local_range[0], x))
    out = np.zeros((imap.size_global, 2))
    for start, xs in parts:
        out[start : start + xs.shape[0]] = xs
    return out


def _ufl_trace_block(V, facet_tags, tag, degree, sign):
    """sign * int_Gamma w (v . n) ds with w in P_degree on the body: a standard facet form."""
    mesh = V.mesh
    W = dolfinx.fem.functionspace(mesh, ("Lagrange", degree))
    w, u = ufl.TestFunction(W), ufl.TrialFunction(V)
    n = ufl.FacetNormal(mesh)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
    A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(sign * w * ufl.dot(u, n) * ds(tag)))
    A.assemble()
    D = gather_dense(A)
    A.destroy()
    return D, _dof_coordinates(W)


def _rows_by_coordinates(x_from, x_to):
    """Index in x_to of each point of x_from (the same points, numbered differently)."""
    d = np.linalg.norm(x_from[:, None, :] - x_to[None, :, :], axis=2)
    idx = np.argmin(d, axis=1)
    assert np.max(d[np.arange(idx.size), idx]) < GEOMETRY_NOISE
    return idx


@pytest.mark.parametrize("contactor", ["upper", "lower"])
@pytest.mark.parametrize(
    ("elements", "degree", "cell", "matching"),
    [
        ((6, 6), 1, "triangle", True),
        ((5, 5), 2, "quadrilateral", True),
        ((4, 4), 2, "triangle", True),
        ((10, 7), 1, "quadrilateral", False),
        ((3, 8), 2, "triangle", False),
    ],
)
def test_coupling_matches_ufl(elements, degree, cell, matching, contactor):
    """B_C equals the UFL trace integral on any mesh; B_T does so on matching meshes.

    With N = -n_C: B_C = -int mu v_C . n_C, and on matching flat surfaces n_T = -n_C, so
    B_T = -int mu v_T . N = -int mu v_T . n_T.
    """
    comm = MPI.COMM_WORLD
    scene = patch_test(comm, elements, cell=cell)
    bodies = scene.bodies
    target = "lower" if contactor == "upper" else "upper"
    spaces = {
        n: dolfinx.fem.functionspace(b.mesh, ("Lagrange", degree, (2,))) for n, b in bodies.items()
    }
    surf = {n: contact_surface(spaces[n], bodies[n].facet_tags, bodies[n].contact) for n in bodies}
    pair = contact_pair(surf[contactor], surf[target])
    B_c, B_t, G = assemble_coupling(pair)
    Bc, Bt = gather_dense(B_c), gather_dense(B_t)
    for obj in (B_c, B_t, G):
        obj.destroy()
    xq = _dof_coordinates(pair.Q)

    ref_c, xw = _ufl_trace_block(
        spaces[contactor], bodies[contactor].facet_tags, bodies[contactor].contact, degree, -1.0
    )
    scale = np.max(np.abs(ref_c))
    eps = np.finfo(float).eps
    assert np.max(np.abs(Bc - ref_c[_rows_by_coordinates(xq, xw)])) < 100 * eps * scale

    if matching:
        ref_t, xw_t = _ufl_trace_block(
            spaces[target], bodies[target].facet_tags, bodies[target].contact, degree, -1.0
        )
        # The scene gives both blocks bit-identical nodes on a shared line here.
        mapped = ref_t[_rows_by_coordinates(xq, xw_t)]
        assert np.max(np.abs(Bt - mapped)) < 100 * eps * scale
    else:
        # Constant pressure transmission (Eq. 36): a rigid vertical motion of both bodies
        # leaves the gap unchanged, so B_C e_y + B_T e_y = 0 row by row.
        ey_c = np.tile([0.0, 1.0], Bc.shape[1] // 2)
        ey_t = np.tile([0.0, 1.0], Bt.shape[1] // 2)
        assert np.max(np.abs(Bc @ ey_c + Bt @ ey_t)) < 100 * eps * scale
        assert np.max(np.abs(Bc @ ey_c)) > 0.1 * scale


@pytest.mark.parametrize("gap", [0.0, 0.03, -0.01])
@pytest.mark.parametrize("degree", [1, 2])
def test_gap_vector_is_integral_of_g0(gap, degree):
    """G = int mu g0, and the multiplier basis sums to one: sum(G) = g0 * W (closed form)."""
    comm = MPI.COMM_WORLD
    scene = patch_test(comm, (10, 7), gap=gap)
    spaces = {
        n: dolfinx.fem.functionspace(b.mesh, ("Lagrange", degree, (2,)))
        for n, b in scene.bodies.items()
    }
    surf = {n: contact_surface(spaces[n], b.facet_tags, b.contact) for n, b in scene.bodies.items()}
    B_c, B_t, G = assemble_coupling(contact_pair(surf["upper"], surf["lower"]))
    assert np.isclose(G.sum(), gap * scene.width, rtol=0, atol=1e-14)
    for obj in (B_c, B_t, G):
        obj.destroy()


@pytest.mark.skip_in_parallel
def test_sub_segments_are_the_merged_nodes():
    """Fig. 15(b): the sub-segment ends are the union of both surfaces' corner nodes."""
    comm = MPI.COMM_SELF
    for elements in [(10, 7), (7, 10), (3, 8)]:
        scene = patch_test(comm, elements, cell="quadrilateral")
        spaces = {
            n: dolfinx.fem.functionspace(b.mesh, ("Lagrange", 1, (2,)))
            for n, b in scene.bodies.items()
        }
        surf = {
            n: contact_surface(spaces[n], b.facet_tags, b.contact) for n, b in scene.bodies.items()
        }
        pair = contact_pair(surf["upper"], surf["lower"])
        seg = pair.sub_segments()
        data = surf["upper"].data
        _, x_lo, _ = surf["upper"].evaluate(data, seg.contactor, seg.lo)
        _, x_hi, _ = surf["upper"].evaluate(data, seg.contactor, seg.hi)
        ends = np.unique(np.round(np.concatenate([x_lo[:, 0], x_hi[:, 0]]), 12))
        nodes = np.unique(
            np.round(
                np.concatenate(
                    [np.linspace(0, 1, elements[0] + 1), np.linspace(0, 1, elements[1] + 1)]
                ),
                12,
            )
        )
        np.testing.assert_allclose(ends, nodes, atol=GEOMETRY_NOISE)
        # Sub-segments tile the contact line exactly once.
        assert np.isclose(np.sum(x_hi[:, 0] - x_lo[:, 0]), 1.0, atol=1e-12)


def test_box_pairs_equals_brute_force():
    rng = np.random.default_rng(7)
    for _ in range(5):
        a_lo = rng.uniform(0, 10, (40, 2))
        b_lo = rng.uniform(0, 10, (55, 2))
        a = np.stack([a_lo, a_lo + rng.uniform(0, 2, (40, 2))], axis=1)
        b = np.stack([b_lo, b_lo + rng.uniform(0, 2, (55, 2))], axis=1)
        ia, ib = box_pairs(a, b)
        overlap = np.all(
            (a[:, None, 0] <= b[None, :, 1]) & (b[None, :, 0] <= a[:, None, 1]), axis=2
        )
        assert set(zip(ia.tolist(), ib.tolist(), strict=True)) == set(
            zip(*np.nonzero(overlap), strict=True)
        )

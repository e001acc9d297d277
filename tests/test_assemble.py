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
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.search import box_pairs
from paper.scenes import patch_test

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


def _dense(pair, *spaces):
    """Dense coupling block of each space (in the order given) and the gap vector."""
    op = assemble_coupling(pair)
    assert len(op.blocks) == len(spaces)
    out = [gather_dense(op.block(V)) for V in spaces]
    g = np.concatenate(pair.contactor.comm.allgather(op.G.array_r.copy()))
    op.destroy()
    return (*out, g)


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
    Bc, Bt, _ = _dense(pair, spaces[contactor], spaces[target])
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
    op = assemble_coupling(contact_pair(surf["upper"], surf["lower"]))
    assert np.isclose(op.G.sum(), gap * scene.width, rtol=0, atol=1e-14)
    assert op.uncovered.size == 0 and op.inactive.size == 0
    op.destroy()


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


@pytest.mark.parametrize("quadrature", ["composite-gauss", "composite-newton-cotes"])
def test_hand_computed_block(quadrature):
    """One linear contactor segment [0, 1] against two target segments [0, 1/2], [1/2, 1].

    Multiplier mu_0 = 1 - x, mu_1 = x; target hats A (at 0), B (at 1/2), C (at 1); N = e_y.
    Closed forms, integrating the piecewise polynomials by hand:
        int mu_0 A = int_0^{1/2} (1 - x)(1 - 2x) dx                       = 5/24
        int mu_0 B = int_0^{1/2} (1 - x) 2x dx + int_{1/2}^1 2(1 - x)^2 dx = 1/4
        int mu_0 C = int_{1/2}^1 (1 - x)(2x - 1) dx                       = 1/24
    and mu_1 by symmetry; the contactor block is the 1D mass matrix [[1/3, 1/6], [1/6, 1/3]].
    """
    comm = MPI.COMM_WORLD
    H = 0.5
    # DOLFINx's rectangles put the nodes exactly at i/n (Gmsh is ~1e-12 off).
    spaces, surf = {}, {}
    for name, y0, nx, side in (("lower", 0.0, 2, H), ("upper", H, 1, H)):
        mesh = dolfinx.mesh.create_rectangle(
            comm, [[0.0, y0], [1.0, y0 + H]], [nx, 1], dolfinx.mesh.CellType.quadrilateral
        )
        facets = dolfinx.mesh.locate_entities_boundary(
            mesh, 1, lambda x, s=side: np.isclose(x[1], s)
        )
        tags = dolfinx.mesh.meshtags(mesh, 1, facets, np.full(facets.size, 7, dtype=np.int32))
        spaces[name] = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
        surf[name] = contact_surface(spaces[name], tags, 7)
    pair = contact_pair(surf["upper"], surf["lower"], quadrature=quadrature)
    Bc, Bt, _ = _dense(pair, spaces["upper"], spaces["lower"])

    xq = _dof_coordinates(pair.Q)[:, 0]
    rows = np.argsort(xq)  # multiplier at x = 0, then x = 1

    def contact_columns(V):
        """y-dofs of the nodes on y = H, ordered by x; x-dofs of the same nodes."""
        imap = V.dofmap.index_map
        coords = V.tabulate_dof_coordinates()[: imap.size_local]
        parts = comm.allgather((imap.local_range[0], coords))
        x = np.zeros((imap.size_global, 3))
        for start, c in parts:
            x[start : start + c.shape[0]] = c
        on = np.flatnonzero(np.isclose(x[:, 1], H))
        on = on[np.argsort(x[on, 0])]
        return 2 * on + 1, 2 * on, x[on, 0]

    y_t, x_t, pos_t = contact_columns(spaces["lower"])
    y_c, x_c, pos_c = contact_columns(spaces["upper"])
    np.testing.assert_allclose(pos_t, [0.0, 0.5, 1.0], atol=1e-12)
    np.testing.assert_allclose(pos_c, [0.0, 1.0], atol=1e-12)

    exact_t = -np.array([[5, 6, 1], [1, 6, 5]]) / 24  # B_T = -int mu v_T . N
    exact_c = np.array([[2, 1], [1, 2]]) / 6
    tol = 10 * np.finfo(float).eps
    np.testing.assert_allclose(Bt[np.ix_(rows, y_t)], exact_t, rtol=0, atol=tol)
    np.testing.assert_allclose(Bc[np.ix_(rows, y_c)], exact_c, rtol=0, atol=tol)
    # Nothing else: no tangential coupling, no other dofs.
    assert np.abs(Bt).sum() == pytest.approx(np.abs(exact_t).sum(), abs=tol)
    assert np.abs(Bc).sum() == pytest.approx(np.abs(exact_c).sum(), abs=tol)
    assert np.max(np.abs(Bt[:, x_t]), initial=0.0) < tol
    assert np.max(np.abs(Bc[:, x_c]), initial=0.0) < tol


def _tagged_rectangle(corner, size, cells, y_tag):
    """A rectangle of triangles whose facets on the line ``y = y_tag[0]`` carry ``y_tag[1]``."""
    (x0, y0), (w, h) = corner, size
    mesh = dolfinx.mesh.create_rectangle(
        MPI.COMM_WORLD, [[x0, y0], [x0 + w, y0 + h]], cells, dolfinx.mesh.CellType.triangle
    )
    fdim = mesh.topology.dim - 1
    facets = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], y_tag[0]))
    values = np.full(facets.size, y_tag[1], dtype=np.int32)
    return mesh, dolfinx.mesh.meshtags(mesh, fdim, facets, values)


@pytest.mark.parametrize("degree", [1, 2])
def test_partly_covered_multipliers(degree):
    """Multipliers whose support a target covers only in part: read off the geometry.

    The contactor, the top of [0, 3] x [0, 1] (facets of length 0.5), faces the bottom of
    [0.2, 2.3] x [1, 1.5]: its facets [0.5, 1], [1, 1.5] and [1.5, 2] are covered whole,
    [0, 0.5] and [2, 2.5] in part, [2.5, 3] not at all. A multiplier is partly covered
    unless every facet of its support is covered whole, and uncovered if none is touched.
    """
    lower = _tagged_rectangle((0.0, 0.0), (3.0, 1.0), (6, 2), (1.0, 1))
    upper = _tagged_rectangle((0.2, 1.0), (2.1, 0.5), (7, 2), (1.0, 2))
    surfaces = []
    for (mesh, tags), tag in ((lower, 1), (upper, 2)):
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
        surfaces.append(contact_surface(V, tags, tag))
    pair = contact_pair(*surfaces, search_radius=0.1)
    op = assemble_coupling(pair)
    x = _dof_coordinates(pair.Q)[:, 0]
    # The support of the multiplier at x: the facets within h = 0.5 of its node (vertex
    # functions), or its own facet (P2 midpoints).
    lo = np.where(np.isclose(x * 2, np.round(x * 2)), x - 0.5, np.floor(x * 2) / 2)
    hi = np.where(np.isclose(x * 2, np.round(x * 2)), x + 0.5, np.ceil(x * 2) / 2)
    whole = (lo >= 0.5 - 1e-12) & (hi <= 2.0 + 1e-12)
    none = lo >= 2.3 - 1e-12
    np.testing.assert_array_equal(np.sort(op.partial), np.flatnonzero(~whole))
    np.testing.assert_array_equal(np.sort(op.uncovered), np.flatnonzero(none))
    # P2: the vertex functions at 0 and 2.5 integrate to h f^2 (2f/3 - 1/2) < 0 over the
    # fraction f = 0.6 of their cut facet that the target covers (away from them).
    unsigned = np.isclose(x, 0.0) | np.isclose(x, 2.5) if degree == 2 else np.zeros_like(none)
    np.testing.assert_array_equal(np.sort(op.unsigned), np.flatnonzero(unsigned))
    assert np.count_nonzero(whole) == (2 if degree == 1 else 5)
    op.destroy()


@pytest.mark.parametrize("degree", [1, 2])
def test_reassembly_keeps_the_structure_only(degree, monkeypatch):
    """Later assemblies reuse the blocks' CSR structure, never their values.

    Against a new pair's first assembly (its own structure found by ``coo_to_csr``): the
    same pair assembled again, then with its upper surface tilted (new values on the
    same pieces: the kept structure), then slid by a third of an element (new pieces:
    a new structure). Equal to the last bit.
    """
    comm = MPI.COMM_WORLD
    scene = patch_test(comm, (10, 7), cell="quadrilateral", geometry_degree=degree)
    spaces = {
        n: dolfinx.fem.functionspace(b.mesh, ("Lagrange", degree, (2,)))
        for n, b in scene.bodies.items()
    }
    surf = {n: contact_surface(spaces[n], b.facet_tags, b.contact) for n, b in scene.bodies.items()}
    pair = contact_pair(surf["upper"], surf["lower"])
    backend = surf["upper"].backend
    structures = []
    coo_to_csr = backend.coo_to_csr
    monkeypatch.setattr(backend, "coo_to_csr", lambda *a: structures.append(1) or coo_to_csr(*a))

    def check(expected_structures: int) -> None:
        del structures[:]
        again = _dense(pair, spaces["upper"], spaces["lower"])
        assert len(structures) == expected_structures
        fresh = _dense(contact_pair(surf["upper"], surf["lower"]), spaces["upper"], spaces["lower"])
        for a, b in zip(again, fresh, strict=True):
            np.testing.assert_array_equal(a, b)

    _dense(pair, spaces["upper"], spaces["lower"])
    check(0)
    u = dolfinx.fem.Function(spaces["upper"])
    u.interpolate(lambda x: np.stack([np.zeros_like(x[0]), 1e-3 * x[0]]))
    surf["upper"].set_displacement(u)
    check(0)
    u.interpolate(lambda x: np.stack([np.full_like(x[0], 0.3 / 10), np.zeros_like(x[0])]))
    surf["upper"].set_displacement(u)
    check(2)

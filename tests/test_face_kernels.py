# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The compiled face kernels (``kernels.face_c_backend``) against the NumPy reference.

``face_backend`` (NumPy, Basix and LAPACK) and ``face_c_backend`` (``_faces.c``) share
their signatures; the C geometry must agree with the reference to round-off: the face
points and tangents (and Basix's own tabulation), the Newton pull-back along lines
(Eq. 38) on flat, bilinear and curved faces with the same refusals, the projection of
candidate pairs, the pull-back of the pieces' rule, the box search, the fused local
blocks (``face_coupling``), the pieces of ``PolygonSegmentation.cut`` and, through the
whole pair, the assembled B and G of Eqs. (40)-(42) on the non-matching 3D blocks of the
patch test (serial and on 2 ranks). The fused blocks are also checked against the
composition of the per-step kernels with Basix's multiplier basis.
"""

import shutil
import sysconfig

from mpi4py import MPI

import basix
import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.face_basis import face_basis
from dolfinx_contact_s2s.kernels import face_backend, get_backend, numpy_backend, polygon
from dolfinx_contact_s2s.search import box_pairs
from dolfinx_contact_s2s.segmentation import PolygonSegmentation
from paper.blocks3d import BOTTOM, TOP, scene

EPS = np.finfo(np.float64).eps


@pytest.fixture(scope="module")
def face_c():
    """The compiled face kernels; skipped only if CFFI or a C compiler is missing."""
    pytest.importorskip("cffi")
    compiler = (sysconfig.get_config_var("CC") or "cc").split()[0]
    if shutil.which(compiler) is None:
        pytest.skip(f"no C compiler ({compiler})")
    return get_backend("c", MPI.COMM_WORLD, facet_dim=2)


def smooth_faces(num_nodes, rng, count=20, bulge=0.05):
    """Faces near the reference cell, tilted, moved, with nodes off the plane by ``bulge``."""
    ref = polygon.face_element(num_nodes).points
    X = np.concatenate([ref, np.zeros((num_nodes, 1))], axis=1)
    faces = []
    for _ in range(count):
        q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
        y = X + 0.1 * rng.uniform(-1, 1, X.shape) * [1, 1, 0]
        y[:, 2] += bulge * rng.uniform(-1, 1, num_nodes)
        faces.append((y @ q.T) * rng.uniform(0.5, 2.0) + rng.uniform(-5, 5, 3))
    return np.array(faces)


def test_get_backend_gives_the_compiled_faces(face_c):
    assert face_c.FACET_DIM == 2 and face_c.NAME == "c"
    assert get_backend("numpy", facet_dim=2) is face_backend
    assert sorted(face_c.__all__) == sorted(face_backend.__all__)
    for name in face_backend.__all__:
        assert hasattr(face_c, name), name


@pytest.mark.parametrize("num_nodes", [3, 4, 6, 9])
def test_evaluate_agrees_with_basix(face_c, num_nodes):
    rng = np.random.default_rng(num_nodes)
    nodes = smooth_faces(num_nodes, rng)
    rows = rng.integers(0, nodes.shape[0], 200).astype(np.int32)
    xi = rng.random((200, 2))
    x_ref, dx_ref = face_backend.evaluate(nodes, rows, xi)
    x, dx = face_c.evaluate(nodes, rows, xi)
    size = np.max(np.abs(nodes))
    assert np.max(np.abs(x - x_ref)) <= 16 * EPS * size
    assert np.max(np.abs(dx - dx_ref)) <= 64 * EPS * size


@pytest.mark.parametrize("num_nodes", [3, 4, 6, 9])
def test_intersect_agrees_with_the_reference(face_c, num_nodes):
    rng = np.random.default_rng(10 + num_nodes)
    nodes = smooth_faces(num_nodes, rng)
    rows = rng.integers(0, nodes.shape[0], 300).astype(np.int32)
    xi0 = rng.random((300, 2)) * (0.5 if num_nodes in (3, 6) else 1.0)
    x, dx = face_backend.evaluate(nodes, rows, xi0)
    n = np.cross(dx[:, :, 0], dx[:, :, 1])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    d = n + 0.2 * rng.uniform(-1, 1, n.shape)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    origins = x - 0.3 * d
    xi_ref, t_ref = polygon.intersect(nodes, rows, origins, d)
    xi, t = face_c.intersect_lines(nodes, rows, origins, d)
    assert np.max(np.abs(xi - xi_ref)) <= 1e-12
    assert np.max(np.abs(t - t_ref)) <= 1e-12
    assert np.max(np.abs(xi - xi0)) <= 1e-10  # both found the point the line started from
    np.testing.assert_array_equal(face_c.intersect(nodes, rows, origins, d), xi)


@pytest.mark.parametrize("num_nodes", [3, 4])
def test_line_along_the_face_is_refused_by_both(face_c, num_nodes):
    nodes = smooth_faces(num_nodes, np.random.default_rng(3), count=2, bulge=0.0)
    rows = np.array([0, 1], dtype=np.int32)
    x, dx = face_backend.evaluate(nodes, rows, np.full((2, 2), 0.25))
    along = dx[:, :, 0] / np.linalg.norm(dx[:, :, 0], axis=1, keepdims=True)
    for module in (face_backend, face_c):
        with pytest.raises(RuntimeError, match="target face 0, 1: no point met"):
            module.intersect_lines(nodes, rows, x, along, name="target face")


def facing_faces(num_c, num_t, rng, count=12):
    """Contactor faces near z = 0 facing up, target faces near z = 0.05 facing down."""
    c = smooth_faces(num_c, rng, count, bulge=0.02)
    t = smooth_faces(num_t, rng, count, bulge=0.02)
    for nodes, up in ((c, 1.0), (t, -1.0)):
        ref = polygon.face_element(nodes.shape[1]).points
        for f in range(count):
            y = np.zeros((nodes.shape[1], 3))
            y[:, :2] = ref + 0.05 * rng.uniform(-1, 1, ref.shape)
            y[:, 2] = 0.02 * rng.uniform(-1, 1, nodes.shape[1]) + (0.05 if up < 0 else 0.0)
            nodes[f] = y
    # Orientation: +1 where d1 x d2 points along `up` (the reference faces' d1 x d2 is +z).
    return c, np.ones(count), t, -np.ones(count)


@pytest.mark.parametrize("num_nodes", [(3, 4), (4, 3), (6, 9), (9, 6)])
def test_project_faces_agrees_with_the_reference(face_c, num_nodes):
    rng = np.random.default_rng(sum(num_nodes))
    c, co, t, to = facing_faces(*num_nodes, rng)
    ic = np.sort(rng.integers(0, c.shape[0], 60)).astype(np.int32)
    it = rng.integers(0, t.shape[0], 60).astype(np.int32)
    co[::3] = -1.0  # some pairs that do not face each other
    ref = polygon.project_faces(c, co, t, to, ic, it)
    out = face_c.project_faces(c, co, t, to, ic, it)
    for a, b in zip(out[:4], ref[:4], strict=True):
        assert np.max(np.abs(a - b)) <= 16 * EPS
    np.testing.assert_array_equal(out[4], ref[4])
    assert 0 < np.count_nonzero(ref[4]) < ic.size
    flat = c.copy()
    flat[1, :, :] = flat[1, :1, :]  # a face of zero area, named as the reference names it
    with pytest.raises(ValueError, match="contactor face 1 has zero area"):
        face_c.project_faces(flat, co, t, to, ic, it)


@pytest.mark.parametrize("num_nodes", [3, 4, 6, 9])
def test_piece_points_agree_with_the_reference(face_c, num_nodes):
    """A rule on plane triangles pulled back to the faces, and the gaps at their centroids."""
    rng = np.random.default_rng(20 + num_nodes)
    c, co, t, _ = facing_faces(num_nodes, 3, rng)
    ic = np.arange(c.shape[0], dtype=np.int32)
    origin, frame, c_poly, _, _ = polygon.project_faces(c, co, t, -co, ic, ic)
    triangles = np.ascontiguousarray(c_poly[:, :3])
    rule = basix.make_quadrature(basix.CellType.triangle, 4)
    xi_ref, w_ref = face_backend.piece_points(c, ic, triangles, origin, frame, rule)
    xi, w = face_c.piece_points(c, ic, triangles, origin, frame, rule)
    assert np.max(np.abs(xi - xi_ref)) <= 1e-13
    assert np.max(np.abs(w - w_ref)) <= 1e-14 * np.max(w_ref)
    assert np.all(w > 0.0)
    gap_ref = face_backend.piece_gaps(c, co, t, (ic, ic), triangles, origin, frame)
    gap = face_c.piece_gaps(c, co, t, (ic, ic), triangles, origin, frame)
    assert np.max(np.abs(gap - gap_ref)) <= 1e-13
    assert np.all((gap > 0.0) & (gap < 0.1))  # the targets lie 0.01 to 0.09 above


def test_box_overlaps_agree(face_c):
    rng = np.random.default_rng(5)
    lo_a, lo_b = rng.random((300, 3)), rng.random((200, 3))
    a = np.stack([lo_a, lo_a + 0.1 * rng.random((300, 3))], axis=1)
    b = np.stack([lo_b, lo_b + 0.1 * rng.random((200, 3))], axis=1)
    ref = box_pairs(a, b, numpy_backend)
    out = box_pairs(a, b, face_c)
    for x, y in zip(out, ref, strict=True):
        np.testing.assert_array_equal(x, y)
    brute = np.all((a[:, None, 0] <= b[None, :, 1]) & (b[None, :, 0] <= a[:, None, 1]), axis=2)
    np.testing.assert_array_equal(brute[ref], np.ones(ref[0].size, bool))
    assert ref[0].size == np.count_nonzero(brute)


@pytest.mark.parametrize("tangent", [None, 1, 2])
@pytest.mark.parametrize("num_nodes", [(3, 4), (4, 3), (6, 9), (9, 6)])
def test_face_coupling_agrees_with_the_reference(face_c, num_nodes, tangent):
    """The fused blocks, C against NumPy, with runs of groups on one pair of faces summed.

    Also friction's tangential blocks (``tangent``: the direction T1 or T2 of an axis).
    """
    rng = np.random.default_rng(30 + sum(num_nodes))
    c, co, t, _ = facing_faces(*num_nodes, rng)
    S, Q = 40, 6
    rows_c = np.sort(rng.integers(0, c.shape[0], S)).astype(np.int32)
    rows_t = rng.integers(0, 2, S).astype(np.int32)  # runs of equal (contactor, target)
    xi = 0.3 * rng.random((S, Q, 2))
    weights = rng.random((S, Q))
    tables = [
        (rng.standard_normal((G, m, n)), rng.integers(0, G, S).astype(np.int32))
        for G, m, n in ((c.shape[0], 4, 3), (4, 9, 6), (6, 4, 4))
    ]
    tables[0] = (tables[0][0], rows_c)
    args = (c, co, t, (rows_c, rows_t), xi, weights, tables)
    direction = None if tangent is None else (np.array([0.3, -0.8, 0.5]), tangent)
    ref = face_backend.face_coupling(*args, zero_below=1e-12, tangent=direction)
    out = face_c.face_coupling(*args, zero_below=1e-12, tangent=direction)
    if tangent is not None:
        assert np.all(ref[2] == 0.0)  # no gap in the tangential coupling
    np.testing.assert_array_equal(out[4], ref[4])
    assert ref[4].size < S  # some runs were summed
    for a, b in zip(out[:4], ref[:4], strict=True):
        assert a.shape == b.shape
        assert np.max(np.abs(a - b)) <= 1e-13 * np.max(np.abs(b))


def test_zero_face_nodes_are_refused(face_c):
    with pytest.raises(ValueError, match="faces with 5 nodes are not supported"):
        face_c.evaluate(np.zeros((1, 5, 3)), np.zeros(1, np.int32), np.zeros((1, 2)))


def surfaces(cells, degree, backends, seed=1):
    """The upper and lower contact surfaces of one scene, for each backend of ``backends``."""
    ((V_lo, t_lo), (V_up, t_up)), *_ = scene(*cells, degree, seed, cells=(3, 4))
    return [
        (
            contact_surface(V_up, t_up, BOTTOM, backend=backend),
            contact_surface(V_lo, t_lo, TOP, backend=backend),
        )
        for backend in backends
    ]


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cells", [("hex", "tet"), ("tet", "hex"), ("hex", "hex")])
def test_pieces_agree(face_c, cells, degree):
    """The same triangles (the clipping is bit-identical) and gaps to round-off."""
    ((upper, lower),) = surfaces(cells, degree, ["numpy"])
    pair = contact_pair(upper, lower)
    seg = PolygonSegmentation()
    T = lower.gather()
    ic, it = box_pairs(pair.swept_boxes(), lower.bounding_boxes(T))
    ref = seg.cut(upper.data, T, ic, it, pair.search_radius, face_backend)
    out = seg.cut(upper.data, T, ic, it, pair.search_radius, face_c)
    np.testing.assert_array_equal(out.contactor, ref.contactor)
    np.testing.assert_array_equal(out.target, ref.target)
    np.testing.assert_array_equal(out.triangles, ref.triangles)
    assert np.max(np.abs(out.gap - ref.gap), initial=0.0) <= 1e-13
    xi_ref, w_ref = seg.points(upper.data, ref, pair.rule, face_backend)
    xi, w = seg.points(upper.data, out, pair.rule, face_c)
    assert np.max(np.abs(xi - xi_ref), initial=0.0) <= 1e-13
    assert np.max(np.abs(w - w_ref), initial=0.0) <= 1e-14 * np.max(w_ref, initial=1.0)


def _matrices(operator):
    """Each block of B and G as local CSR arrays (this process's rows)."""
    out = [B.getValuesCSR() for _, B in operator.blocks]
    return out, operator.G.array.copy()


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cells", [("hex", "tet"), ("tet", "hex"), ("tet", "tet")])
def test_pair_blocks_agree(face_c, cells, degree):
    """B (both spaces) and G of a whole pair, C against NumPy, to round-off (any ranks)."""
    results = []
    for upper, lower in surfaces(cells, degree, ["numpy", "c"]):
        operator = assemble_coupling(contact_pair(upper, lower))
        results.append(_matrices(operator))
        operator.destroy()
    (ref_blocks, ref_g), (blocks, g) = results
    comm = MPI.COMM_WORLD
    for (ip_r, j_r, v_r), (ip, j, v) in zip(ref_blocks, blocks, strict=True):
        np.testing.assert_array_equal(ip, ip_r)
        np.testing.assert_array_equal(j, j_r)
        scale = comm.allreduce(np.max(np.abs(v_r), initial=0.0), op=MPI.MAX)
        worst = comm.allreduce(np.max(np.abs(v - v_r), initial=0.0), op=MPI.MAX)
        assert worst <= 1e-14 * scale, worst / scale
    scale = comm.allreduce(np.max(np.abs(ref_g), initial=0.0), op=MPI.MAX)
    worst = comm.allreduce(np.max(np.abs(g - ref_g), initial=0.0), op=MPI.MAX)
    assert worst <= 1e-14 * max(scale, 1.0)


@pytest.mark.parametrize("backend", ["numpy", "c"])
@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("cells", [("hex", "tet"), ("tet", "hex")])
def test_fused_blocks_agree_with_the_steps(face_c, backend, cells, degree):
    """The blocks of ``face_coupling`` against the per-step kernels and Basix's multiplier.

    The multiplier evaluated by Basix at each point (``MultiplierSpace.basis``), the face
    bases, the target points and ``segment_to_segment`` per piece, then the pieces of one
    pair of faces summed: what the pair's fused blocks must hold, to round-off.
    """
    ((upper, lower),) = surfaces(cells, degree, [backend])
    pair = contact_pair(upper, lower)
    kernels = upper.backend
    T = pair.discretization.gathered(pair)[0]
    g = pair.discretization.points(pair, [T])[0]
    (blocks,) = pair.coupling_blocks()
    C = upper.data
    S, Q = g.weights.shape
    rows_c, rows_t = np.repeat(g.contactor, Q), np.repeat(g.target, Q)
    xi = g.xi.reshape(-1, 2)
    normals = -kernels.outward_normals(C.coefficients, C.orientation, rows_c, xi)
    # Relative to each contactor face's node 0, as the pair does (the gaps vanish here).
    origin, local = C.coefficients[rows_c, 0], np.arange(rows_c.size, dtype=np.int32)
    c_local = kernels.shift(C.coefficients[rows_c], -origin)
    t_local = kernels.shift(T.coefficients[rows_t], -origin)
    x_c, _ = kernels.evaluate(c_local, local, xi)
    eta = np.clip(kernels.intersect(t_local, local, x_c, normals), 0.0, 1.0)
    x_t, _ = kernels.evaluate(t_local, local, eta)
    gaps = np.einsum("pg,pg->p", x_c - x_t, normals)
    mu = pair.multiplier.basis(rows_c, xi, kernels).reshape(S, Q, -1)
    phi_c, _ = face_basis(upper, C, g.contactor, Q, xi)
    phi_t, _ = face_basis(lower, T, g.target, Q, eta)
    b_c, b_t, gap = numpy_backend.segment_to_segment(
        mu,
        phi_c.reshape(S, Q, -1),
        phi_t.reshape(S, Q, -1),
        normals.reshape(S, Q, 3),
        g.weights,
        gaps.reshape(S, Q),
    )
    coverage = np.einsum("sqk,sq->sk", mu**2, g.weights)
    run = np.concatenate([[0], np.cumsum((np.diff(g.contactor) != 0) | (np.diff(g.target) != 0))])
    for steps, fused in (
        (b_c, blocks.values_contactor),
        (b_t, blocks.values_target),
        (gap, blocks.gap),
        (coverage, blocks.coverage),
    ):
        summed = np.zeros(fused.shape)
        np.add.at(summed, run, steps)
        # A gap of zero is compared with the size of the other integrals.
        scale = max(np.max(np.abs(summed), initial=0.0), np.max(blocks.coverage))
        assert np.max(np.abs(fused - summed), initial=0.0) <= 1e-13 * scale
    np.testing.assert_array_equal(blocks.rows, g.rows[np.flatnonzero(np.diff(run, prepend=-1))])

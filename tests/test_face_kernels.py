# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The compiled face kernels (``kernels.face_c_backend``) against the NumPy reference.

``face_backend`` (NumPy, Basix and LAPACK) and ``face_c_backend`` (``_faces.c``) share
their signatures; the C geometry must agree with the reference to round-off: the face
points and tangents (and Basix's own tabulation), the Newton pull-back along lines
(Eq. 38) on flat, bilinear and curved faces with the same refusals, the pieces of
``PolygonSegmentation.cut`` and, through the whole pair, the assembled B and G of
Eqs. (40)-(42) on the non-matching 3D blocks of the patch test (serial and on 2 ranks).
"""

import shutil
import sysconfig

from mpi4py import MPI

import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.kernels import face_backend, get_backend, polygon
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

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Facet geometry of the kernel backends against closed forms and direct evaluation."""

from mpi4py import MPI

import basix
import basix.ufl
import dolfinx
import numpy as np
import pytest

from dolfinx_contact_s2s import contact_surface
from dolfinx_contact_s2s.kernels import BACKENDS, get_backend

EPS = np.finfo(float).eps


@pytest.fixture(params=BACKENDS)
def backend(request):
    return get_backend(request.param)


def test_unknown_backend():
    with pytest.raises(ValueError, match="unknown kernel backend"):
        get_backend("fortran")


def _straight(rng, n):
    """Random straight facets: x(xi) = a + xi (b - a) as coefficients (n, 2, 2)."""
    a = rng.uniform(-1, 1, (n, 2))
    b = a + rng.uniform(0.2, 1.0, (n, 1)) * np.stack(
        [np.cos(t := rng.uniform(0, 2 * np.pi, n)), np.sin(t)], axis=1
    )
    return a, b, np.ascontiguousarray(np.stack([a, b - a], axis=1))


def test_straight_facets_are_exact(backend):
    """Points, derivatives, normals, projection and intersection in closed form."""
    rng = np.random.default_rng(3)
    n = 50
    a, b, c = _straight(rng, n)
    rows = rng.integers(0, n, 200).astype(np.int32)
    xi = rng.uniform(-0.5, 1.5, rows.size)
    t = b[rows] - a[rows]
    tol = 10 * EPS

    x, dx, ddx = backend.evaluate(c, rows, xi, 2)
    np.testing.assert_allclose(x, a[rows] + xi[:, None] * t, atol=tol)
    np.testing.assert_allclose(dx, t, atol=tol)
    assert np.max(np.abs(ddx)) == 0.0

    orientation = rng.choice([-1.0, 1.0], n)
    normals = backend.outward_normals(c, orientation, rows, xi)
    turned = np.stack([t[:, 1], -t[:, 0]], axis=1) / np.linalg.norm(t, axis=1)[:, None]
    np.testing.assert_allclose(normals, orientation[rows, None] * turned, atol=tol)

    # Closest point on the line through a and b: xi = (p - a) . t / |t|^2.
    p = rng.uniform(-2, 2, (rows.size, 2))
    exact = np.einsum("pg,pg->p", p - a[rows], t) / np.einsum("pg,pg->p", t, t)
    np.testing.assert_allclose(backend.project(c, rows, p), exact, atol=100 * EPS)

    # Line o + s d meets a + eta t where (a + eta t - o) x d = 0.
    o = rng.uniform(-2, 2, (rows.size, 2))
    d = rng.normal(size=(rows.size, 2))
    cross = t[:, 0] * d[:, 1] - t[:, 1] * d[:, 0]
    keep = np.abs(cross) > 0.1 * np.linalg.norm(t, axis=1) * np.linalg.norm(d, axis=1)
    r = o - a[rows]
    exact = (r[:, 0] * d[:, 1] - r[:, 1] * d[:, 0]) / cross
    eta = backend.intersect(c, rows, o, d)
    np.testing.assert_allclose(eta[keep], exact[keep], atol=1e3 * EPS)


def test_coupling_kernel_closed_form(backend):
    """One point, one multiplier, one basis function each: B_C = w mu phi N, B_T = -that."""
    mu = np.full((1, 1, 1), 0.5)
    phi = np.full((1, 1, 1), 0.25)
    normals = np.array([[[0.6, 0.8]]])
    w, g = np.array([[2.0]]), np.array([[0.1]])
    b_c, b_t, gap = backend.segment_to_segment(mu, phi, phi, normals, w, g)
    np.testing.assert_allclose(b_c, [[[0.15, 0.2]]], atol=EPS)
    np.testing.assert_allclose(b_t, -b_c, atol=0)
    np.testing.assert_allclose(gap, [[0.1]], atol=EPS)


@pytest.fixture(scope="module")
def curved():
    """A quadratic triangle whose facet from (1, 0) to (0, 1) bulges onto the unit circle."""
    comm = MPI.COMM_WORLD
    c = np.sqrt(0.5)
    if comm.rank == 0:
        # Vertices, then the midpoints of edges (1, 2), (0, 2), (0, 1) (Basix order).
        x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [c, c], [0.0, 0.5], [0.5, 0.0]])
        cells = np.arange(6, dtype=np.int64)[None, :]
    else:
        x, cells = np.empty((0, 2)), np.empty((0, 6), dtype=np.int64)
    e = basix.ufl.element("Lagrange", "triangle", 2, shape=(2,))
    mesh = dolfinx.mesh.create_mesh(comm, cells=cells, x=x, e=e)
    # The curved facet only: the other two touch the origin.
    facets = dolfinx.mesh.locate_entities_boundary(mesh, 1, lambda x: x[0] + x[1] > 0.99)
    tags = dolfinx.mesh.meshtags(mesh, 1, facets, np.full(facets.size, 3, dtype=np.int32))
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2, (2,)))
    return contact_surface(V, tags, 3)


def _direct(surface, xi):
    """x, x' by tabulating the coordinate element at X(xi) (the reference evaluation)."""
    data = surface.data
    lf = data.local_facet[0]
    verts = basix.geometry(basix.CellType.triangle)[basix.topology(basix.CellType.triangle)[1][lf]]
    X = verts[0] + xi[:, None] * (verts[1] - verts[0])
    tab = basix.create_element(basix.ElementFamily.P, basix.CellType.triangle, 2).tabulate(1, X)
    coords = data.coords[0]
    x = tab[0, :, :, 0] @ coords
    d = verts[1] - verts[0]
    dx = (d[0] * tab[1, :, :, 0] + d[1] * tab[2, :, :, 0]) @ coords
    return x, dx, tab, coords


def test_quadratic_facet_against_direct_evaluation(curved):
    """Points, tangents, normals and both Newton solves on a curved P2 facet."""
    s = curved
    if len(s.data) == 0:
        return
    assert len(s.data) == 1
    xi = np.linspace(-0.2, 1.2, 15)
    rows = np.zeros(xi.size, dtype=np.int32)
    x_ref, dx_ref, tab, coords = _direct(s, xi)
    _, x, dx = s.evaluate(s.data, rows, xi)
    tol = 100 * EPS
    np.testing.assert_allclose(x, x_ref, atol=tol)
    np.testing.assert_allclose(dx, dx_ref, atol=tol)
    # Nodes of the facet: (1, 0) or (0, 1) at the ends, the circle at the middle.
    np.testing.assert_allclose(np.linalg.norm(x[[2, 7, 12]], axis=1), 1.0, atol=tol)

    # Outward normals: J^-T n_ref, and away from the origin at the middle.
    normals = s.outward_normals(s.data, rows, xi)
    lf = int(s.data.local_facet[0])
    n_ref = np.asarray(basix.cell.facet_outward_normals(basix.CellType.triangle))[lf]
    J = np.einsum("kg,dpk->pgd", coords, tab[1:3, :, :, 0])
    expected = np.linalg.solve(
        np.swapaxes(J, 1, 2), np.broadcast_to(n_ref, (xi.size, 2))[..., None]
    )
    expected = expected[:, :, 0] / np.linalg.norm(expected[:, :, 0], axis=1)[:, None]
    np.testing.assert_allclose(normals, expected, atol=tol)
    assert normals[7] @ x[7] > 0.9

    # Projection: (x(xi) - p) . x'(xi) = 0 at the result; intersection: on the ray.
    theta = np.linspace(0.2, 1.3, 9)
    p = 1.3 * np.stack([np.cos(theta), np.sin(theta)], axis=1)
    r9 = np.zeros(theta.size, dtype=np.int32)
    xi_p = s.project(s.data, r9, p)
    xp, dxp, _, _ = _direct(s, xi_p)
    np.testing.assert_allclose(np.einsum("pg,pg->p", xp - p, dxp), 0.0, atol=tol)
    eta = s.intersect(s.data, r9, np.zeros_like(p), p)
    xe, _, _, _ = _direct(s, eta)
    np.testing.assert_allclose(xe[:, 0] * p[:, 1] - xe[:, 1] * p[:, 0], 0.0, atol=tol)
    assert np.all((eta > 0) & (eta < 1))

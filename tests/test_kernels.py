# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The compiled (C) and NumPy kernel backends: closed forms, and agreement on random meshes."""

from mpi4py import MPI

import basix.ufl
import dolfinx
import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.kernels import BACKENDS, ENV_BACKEND, get_backend, numpy_backend

EPS = np.finfo(float).eps


def _parabola(a: float) -> np.ndarray:
    """One facet x(xi) = (xi, a xi^2) as coefficients (1, 3, 2)."""
    return np.array([[[0.0, 0.0], [1.0, 0.0], [0.0, a]]])


@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)
def test_parabolic_facet_closed_form(kernel_backend):
    """Projection and intersection on x(xi) = (xi, a xi^2) against points built from xi*.

    A point p = x(xi*) + t n(xi*) on the normal at xi* (t below the radius of curvature)
    projects to xi*; the line through x(xi*) along any direction d not tangent to the
    facet, and not too far from its normal, crosses it at xi* (Eq. 38).
    """
    rng = np.random.default_rng(11)
    a = 0.7
    c = _parabola(a)
    xi_star = rng.uniform(0.05, 0.95, 40)
    rows = np.zeros(xi_star.size, dtype=np.int32)
    x_star = np.stack([xi_star, a * xi_star**2], axis=1)
    tangent = np.stack([np.ones_like(xi_star), 2 * a * xi_star], axis=1)
    normal = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    t = rng.uniform(-0.3, 0.3, xi_star.size)  # radius of curvature >= 1 / (2a) > 0.7
    xi = kernel_backend.project(c, rows, x_star + t[:, None] * normal)
    np.testing.assert_allclose(xi, xi_star, atol=20 * EPS)

    # Directions within 0.5 rad of the normal: the second crossing of the line lies
    # far outside the facet.
    angle = rng.uniform(np.pi / 2 - 0.5, np.pi / 2 + 0.5, xi_star.size)
    unit = tangent / np.linalg.norm(tangent, axis=1)[:, None]
    d = np.cos(angle)[:, None] * unit + np.sin(angle)[:, None] * normal
    s = rng.uniform(-0.2, 0.2, xi_star.size)
    eta = kernel_backend.intersect(c, rows, x_star + s[:, None] * d, d)
    np.testing.assert_allclose(eta, xi_star, atol=20 * EPS)


@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)
def test_straight_facet_as_quadratic(kernel_backend):
    """A straight facet stored with a zero quadratic coefficient: closed forms still hold."""
    c = np.array([[[1.0, 2.0], [3.0, -1.0], [0.0, 0.0]]])
    rows = np.zeros(3, dtype=np.int32)
    p = np.array([[1.0, 2.0], [4.0, 1.0], [-2.0, 3.0]])
    t = c[0, 1]
    exact = (p - c[0, 0]) @ t / (t @ t)
    np.testing.assert_allclose(kernel_backend.project(c, rows, p), exact, atol=10 * EPS)
    d = np.array([[0.0, 1.0], [1.0, 1.0], [-1.0, 2.0]])
    perp = np.stack([-d[:, 1], d[:, 0]], axis=1)
    exact = np.einsum("pg,pg->p", p - c[0, 0], perp) / (perp @ t)
    np.testing.assert_allclose(kernel_backend.intersect(c, rows, p, d), exact, atol=10 * EPS)


def test_numpy_newton_stops_when_converged(monkeypatch):
    """On straight facets the reference Newton loop takes the exact step and one check."""
    calls = []
    evaluate = numpy_backend.evaluate

    def counted(*args, **kwargs):
        calls.append(1)
        return evaluate(*args, **kwargs)

    monkeypatch.setattr(numpy_backend, "evaluate", counted)
    c = np.array([[[0.0, 0.0], [2.0, 1.0]]])
    rows = np.zeros(5, dtype=np.int32)
    p = np.random.default_rng(0).uniform(-1, 2, (5, 2))
    numpy_backend.project(c, rows, p)
    assert len(calls) == 2
    calls.clear()
    numpy_backend.intersect(c, rows, p, np.tile([[0.0, 1.0]], (5, 1)))
    assert len(calls) == 2


def test_backend_choice(monkeypatch):
    monkeypatch.setenv(ENV_BACKEND, "numpy")
    assert get_backend() is numpy_backend
    assert get_backend("auto") is numpy_backend
    monkeypatch.setenv(ENV_BACKEND, "fortran")
    with pytest.raises(ValueError, match=ENV_BACKEND):
        get_backend()
    monkeypatch.delenv(ENV_BACKEND)
    assert get_backend("auto") in (numpy_backend, get_backend("c"))
    assert get_backend("c").__name__.endswith("c_backend")


# Random non-matching two-body scenes.


def _strip(comm, xs, y_lo, y_hi, layers, geometry_degree):
    """Triangles between the curves y_lo(x) and y_hi(x) over the columns xs (rank 0 builds).

    With ``geometry_degree=2`` every edge midpoint is placed on the image of the edge's
    parametric middle, so facets along a curved boundary are curved.
    """
    e = basix.ufl.element("Lagrange", "triangle", geometry_degree, shape=(2,))
    if comm.rank != 0:
        nodes = 3 if geometry_degree == 1 else 6
        return dolfinx.mesh.create_mesh(
            comm, cells=np.empty((0, nodes), dtype=np.int64), x=np.empty((0, 2)), e=e
        )

    def point(x, t):
        return np.array([x, (1 - t) * y_lo(x) + t * y_hi(x)])

    ts = np.linspace(0.0, 1.0, layers + 1)
    grid = {(i, j): (x, t) for i, x in enumerate(xs) for j, t in enumerate(ts)}
    ids = {key: k for k, key in enumerate(grid)}
    x = [point(*grid[key]) for key in grid]
    mids: dict = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in mids:
            (xa, ta), (xb, tb) = grid[key[0]], grid[key[1]]
            mids[key] = len(x)
            x.append(point(0.5 * (xa + xb), 0.5 * (ta + tb)))
        return mids[key]

    cells = []
    for i in range(len(xs) - 1):
        for j in range(layers):
            for tri in (((i, j), (i + 1, j), (i + 1, j + 1)), ((i, j), (i + 1, j + 1), (i, j + 1))):
                cell = [ids[v] for v in tri]
                if geometry_degree == 2:
                    cell += [mid(tri[1], tri[2]), mid(tri[0], tri[2]), mid(tri[0], tri[1])]
                cells.append(cell)
    return dolfinx.mesh.create_mesh(comm, cells=np.array(cells, dtype=np.int64), x=np.array(x), e=e)


def _bodies(comm, rng, geometry_degree):
    """Two strips meeting along a random wavy line, with random non-matching nodes."""
    amplitude = rng.uniform(0.0, 0.05) if geometry_degree == 2 else 0.0
    phase = rng.uniform(0, 2 * np.pi)
    gap = rng.uniform(-0.01, 0.02)

    def line(x):
        return amplitude * np.sin(2 * np.pi * x + phase)

    bodies = []
    for lower in (True, False):
        n = int(rng.integers(2, 8))
        xs = np.linspace(0.0, 1.0, n + 1)
        xs[1:-1] += rng.uniform(-0.3, 0.3, n - 1) / n
        if lower:
            mesh = _strip(comm, xs, lambda x: line(x) - 0.3, line, 1, geometry_degree)
            on = lambda x, line=line: np.isclose(x[1], line(x[0]), atol=1e-9)  # noqa: E731
        else:
            mesh = _strip(comm, xs, lambda x: line(x) + gap, lambda x: line(x) + 0.3, 1,
                          geometry_degree)  # fmt: skip
            on = lambda x, line=line: np.isclose(x[1], line(x[0]) + gap, atol=1e-9)  # noqa: E731
        facets = dolfinx.mesh.locate_entities_boundary(mesh, 1, on)
        tags = dolfinx.mesh.meshtags(mesh, 1, facets, np.full(facets.size, 1, dtype=np.int32))
        bodies.append((mesh, tags))
    return bodies


SCENES = [(1, 1), (2, 1), (2, 2)]
MULTIPLIERS = [None, ("DG", 0), ("DG", 1), ("Lagrange", 1)]
QUADRATURES = [None, "composite-newton-cotes", "gauss"]


def _max_error(a, b, scale):
    return float(np.max(np.abs(a - b), initial=0.0)) / scale if a.size else 0.0


@pytest.mark.parametrize(("degree", "geometry_degree"), SCENES, ids=["P1", "P2", "P2-curved"])
def test_backends_agree_on_random_meshes(degree, geometry_degree):
    """C and NumPy give the same B and G (1e-13 relative) on 35 random scenes each.

    Both backends integrate the same sub-segments; they differ in the order of
    operations, in the closed-form projections on straight facets (C) against Newton
    (NumPy), and in compiled against vectorised arithmetic.
    """
    comm = MPI.COMM_WORLD
    rng = np.random.default_rng(2026 + 10 * degree + geometry_degree)
    worst, checked = 0.0, 0
    for case in range(35):
        bodies = _bodies(comm, rng, geometry_degree)
        spaces = [dolfinx.fem.functionspace(m, ("Lagrange", degree, (2,))) for m, _ in bodies]
        upper_contacts = bool(rng.integers(2))
        multiplier = MULTIPLIERS[case % len(MULTIPLIERS)]
        quadrature = QUADRATURES[(case // len(MULTIPLIERS)) % len(QUADRATURES)]
        surf = {
            name: [
                contact_surface(V, tags, 1, backend=name)
                for V, (_, tags) in zip(spaces, bodies, strict=True)
            ]
            for name in BACKENDS
        }
        # The facet geometry of each backend (Basix-free in C).
        geometry = 0.0
        for s_np, s_c in zip(surf["numpy"], surf["c"], strict=True):
            scale = max(np.max(np.abs(s_np.data.coefficients), initial=0.0), EPS)
            geometry = max(
                geometry, _max_error(s_c.data.coefficients, s_np.data.coefficients, scale)
            )
            same_orientation = np.array_equal(s_c.data.orientation, s_np.data.orientation)
            geometry = geometry if same_orientation else np.inf
        geometry = comm.allreduce(geometry, op=MPI.MAX)
        assert geometry <= 1e-13, f"case {case}: facet geometry differs by {geometry:.2e}"
        # One pair (and multiplier space) integrated by each backend in turn.
        lower, upper = surf["numpy"]
        contactor, target = (upper, lower) if upper_contacts else (lower, upper)
        pair = contact_pair(contactor, target, multiplier=multiplier, quadrature=quadrature)
        blocks = {}
        for name in BACKENDS:
            contactor.backend = target.backend = get_backend(name)
            blocks[name] = pair.coupling_blocks()[0]
        ref, c = blocks["numpy"], blocks["c"]
        same = (
            ref.rows.shape == c.rows.shape
            and np.array_equal(ref.rows, c.rows)
            and np.array_equal(ref.cols_contactor, c.cols_contactor)
            and np.array_equal(ref.cols_target, c.cols_target)
        )
        scale_b = max(np.max(np.abs(ref.values_contactor), initial=0.0), EPS)
        scale_g = max(np.max(np.abs(ref.gap), initial=0.0), EPS)
        error = max(
            _max_error(c.values_contactor, ref.values_contactor, scale_b),
            _max_error(c.values_target, ref.values_target, scale_b),
            _max_error(c.gap, ref.gap, scale_g),
            _max_error(c.coverage, ref.coverage, max(np.max(ref.coverage, initial=0.0), EPS)),
        )
        # Reduce before asserting: every rank fails together.
        same = comm.allreduce(same, op=MPI.LAND)
        error = comm.allreduce(error if same else np.inf, op=MPI.MAX)
        assert same, f"case {case}: the backends integrate different groups"
        assert error <= 1e-13, f"case {case}: relative difference {error:.2e}"
        worst = max(worst, error)
        checked += comm.allreduce(ref.rows.shape[0], op=MPI.SUM) > 0
    assert checked == 35


@pytest.mark.parametrize("degree", [1, 2])
def test_fused_edge_kernel_with_dual_multipliers_and_tangents(degree):
    """The C kernels' one-pass edge_coupling against the NumPy composition (1e-13).

    The cases the random scenes above leave out: dual multipliers (their table combined
    before the points) and friction's tangential coupling (T and no gap), with the
    integrals of mu_k (``signed``) compared too.
    """
    comm = MPI.COMM_WORLD
    rng = np.random.default_rng(77 + degree)
    for case in range(6):
        bodies = _bodies(comm, rng, 1)
        spaces = [dolfinx.fem.functionspace(m, ("Lagrange", degree, (2,))) for m, _ in bodies]
        lower, upper = (
            contact_surface(V, tags, 1, backend="numpy")
            for V, (_, tags) in zip(spaces, bodies, strict=True)
        )
        dual = case % 2 == 0
        multiplier = ("Dual", degree) if dual else ("Lagrange", degree)
        pair = contact_pair(upper, lower, multiplier=multiplier)
        tangent = None if dual else (None, 1)
        blocks = {}
        for name in BACKENDS:
            upper.backend = lower.backend = get_backend(name)
            blocks[name] = pair.coupling_blocks(tangent)[0]
        ref, c = blocks["numpy"], blocks["c"]
        assert np.array_equal(ref.cols_contactor, c.cols_contactor)
        assert np.array_equal(ref.cols_target, c.cols_target)
        scale = max(np.max(np.abs(ref.values_contactor), initial=0.0), EPS)
        error = max(
            _max_error(c.values_contactor, ref.values_contactor, scale),
            _max_error(c.values_target, ref.values_target, scale),
            _max_error(c.gap, ref.gap, scale),
            _max_error(c.coverage, ref.coverage, max(np.max(ref.coverage, initial=0.0), EPS)),
            _max_error(c.signed, ref.signed, max(np.max(np.abs(ref.signed), initial=0.0), EPS)),
        )
        error = comm.allreduce(error, op=MPI.MAX)
        assert error <= 1e-13, f"case {case}: relative difference {error:.2e}"


@pytest.mark.parametrize("name", BACKENDS)
def test_facet_basis_against_basix(name):
    """Monomial facet bases equal Basix tabulation at the mapped reference points."""
    comm = MPI.COMM_WORLD
    mesh, tags = _bodies(comm, np.random.default_rng(5), 2)[0]
    for degree in (1, 2):
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
        s = contact_surface(V, tags, 1, backend=name)
        rows = np.repeat(np.arange(len(s.data), dtype=np.int32), 7)
        xi = np.tile(np.linspace(-0.1, 1.1, 7), len(s.data))
        expected = s.basis(s.reference_points(s.data, rows, xi))
        np.testing.assert_allclose(s.facet_basis(s.data, rows, xi), expected, atol=20 * EPS)


@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)
def test_no_slivers_between_coinciding_nodes(kernel_backend):
    """Far from the origin, nodes that coincide up to round-off make no extra sub-segment.

    Contactor nodes at x0 + i h and target nodes at x0 + 2 j h / 3 along one line: every
    third target node meets a contactor node, so the sub-segments are the n + m - 1 - k
    intervals between the distinct nodes (Fig. 15(b)), k the interior coincidences.
    """
    x0, h, n = 1e4, 1e-3, 30
    m = 3 * n // 2
    xc = x0 + h * np.arange(n + 1)
    xt = x0 + (2 * h / 3) * np.arange(m + 1)[::-1]  # the target runs the other way

    def line(x, y):
        return np.ascontiguousarray(np.stack([np.stack([x[:-1], np.full(x.size - 1, y)], 1),
                                              np.stack([np.diff(x), np.zeros(x.size - 1)], 1)],
                                             axis=1))  # fmt: skip

    cc, tc = line(xc, 0.0), line(xt, 1e-4)
    ic, it = (a.reshape(-1).astype(np.int32) for a in np.meshgrid(np.arange(n), np.arange(m)))
    # Contactor below with outward normal +y, target above with outward normal -y.
    c_orient, t_orient = -np.ones(n), -np.ones(m)
    lo, hi, keep = kernel_backend.clip_segments(cc, c_orient, tc, t_orient, ic, it, 2 * h, 1e-12)
    assert np.count_nonzero(keep) == n + m - 1 - (n // 2 - 1)
    # The kept pieces tile every contactor facet.
    lengths = np.bincount(ic[keep], weights=(hi - lo)[keep], minlength=n)
    np.testing.assert_allclose(lengths, 1.0, atol=1e-8)


def _random_coo(seed: int):
    """3000 random entries of a 50 x 90 matrix (with duplicates) and SciPy's CSR of them."""
    scipy_sparse = pytest.importorskip("scipy.sparse")
    rng = np.random.default_rng(seed)
    rows = rng.integers(0, 40, 3000)
    cols = rng.integers(0, 90, 3000)
    values = rng.normal(size=3000)
    ref = scipy_sparse.coo_matrix((values, (rows, cols)), shape=(50, 90)).tocsr()
    ref.sum_duplicates()
    ref.sort_indices()
    return rows, cols, values, ref


@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)
def test_coo_to_csr_against_scipy(kernel_backend):
    """Duplicates summed, columns sorted: the CSR matrix SciPy builds from the same COO."""
    rows, cols, values, ref = _random_coo(4)
    indptr, indices, data = kernel_backend.coo_to_csr(50, rows, cols, values)
    np.testing.assert_array_equal(indptr, ref.indptr)
    np.testing.assert_array_equal(indices, ref.indices)
    np.testing.assert_allclose(data, ref.data, rtol=1e-14, atol=1e-14)
    empty = kernel_backend.coo_to_csr(3, np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0))
    np.testing.assert_array_equal(empty[0], np.zeros(4))
    assert empty[1].size == empty[2].size == 0


@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)
def test_csr_slots_sum_into_the_structure(kernel_backend):
    """Values summed at their slots give SciPy's CSR data; an entry outside is refused."""
    rows, cols, values, ref = _random_coo(5)
    indptr, indices, _ = kernel_backend.coo_to_csr(50, rows, cols, values)
    slots = kernel_backend.csr_slots(indptr, indices, rows, cols)
    summed = np.bincount(slots, weights=values, minlength=indices.size)
    np.testing.assert_allclose(summed, ref.data, rtol=1e-14, atol=1e-14)
    absent = np.setdiff1d(np.arange(90), cols[rows == 7])[0]
    with pytest.raises(ValueError, match="not in the CSR structure"):
        kernel_backend.csr_slots(indptr, indices, np.array([7]), np.array([absent]))

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The geometry of the 3D composite quadrature (Fig. 15(b) on faces), against closed forms.

Every expected number comes from outside the module: areas and integrals in closed form,
hand-computed vertices, exact polynomial antiderivatives, line-plane intersections.
"""

import basix
import numpy as np
import pytest
from numpy.polynomial import Polynomial

from dolfinx_contact_s2s.kernels.polygon import clip_convex, intersect, overlap_rule, triangulate

EPS = np.finfo(np.float64).eps


def shoelace(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def square(x0=0.0, y0=0.0, size=1.0):
    return np.array([[x0, y0], [x0 + size, y0], [x0 + size, y0 + size], [x0, y0 + size]])


def random_convex(rng, n):
    """A convex polygon: points on a random ellipse at sorted random angles, CCW."""
    angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    a, b = rng.uniform(0.3, 1.5, 2)
    rot = rng.uniform(0.0, np.pi)
    pts = np.stack([a * np.cos(angles), b * np.sin(angles)], axis=1)
    R = np.array([[np.cos(rot), -np.sin(rot)], [np.sin(rot), np.cos(rot)]])
    return pts @ R.T + rng.uniform(-0.5, 0.5, 2)


def inside(points, poly, tol):
    """Whether every point lies left of every edge of the CCW polygon (within tol)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    e = b - a
    d = e[None, :, 0] * (points[:, None, 1] - a[None, :, 1]) - e[None, :, 1] * (
        points[:, None, 0] - a[None, :, 0]
    )
    return bool(np.all(d >= -tol))


# -- clipping ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "a, b", [(0.3, 0.6), (-0.25, 0.1), (0.0, -0.7), (0.5, 0.5), (-0.9, -0.05), (0.0, 0.0)]
)
def test_clip_offset_unit_squares_area(a, b):
    overlap = clip_convex(square(a, b), square())
    assert abs(shoelace(overlap) - (1 - abs(a)) * (1 - abs(b))) <= 1e-14
    # The overlap is the box [max(0, a), min(1, 1 + a)] x [...]: its corners are vertices.
    lo = np.array([max(0.0, a), max(0.0, b)])
    hi = np.array([min(1.0, 1 + a), min(1.0, 1 + b)])
    expected = {(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])}
    assert {tuple(v) for v in np.round(overlap, 14)} == {
        tuple(v) for v in np.round(np.array(list(expected)), 14)
    }


def test_clip_triangle_inside_square():
    tri = np.array([[0.2, 0.1], [0.9, 0.3], [0.4, 0.8]])
    area = 0.5 * abs((0.9 - 0.2) * (0.8 - 0.1) - (0.4 - 0.2) * (0.3 - 0.1))
    for overlap in (clip_convex(tri, square()), clip_convex(square(), tri)):
        assert abs(shoelace(overlap) - area) <= 1e-15


def test_clip_by_hand():
    # The triangle x, y >= 0, x + y <= 2 cut by [0.5, 1.5]^2: its hypotenuse runs
    # through (1.5, 0.5) and (0.5, 1.5), leaving the right triangle of legs 1.
    tri = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    overlap = clip_convex(tri, square(0.5, 0.5))
    assert overlap.shape == (3, 2)
    assert {tuple(v) for v in np.round(overlap, 15)} == {(0.5, 0.5), (1.5, 0.5), (0.5, 1.5)}
    assert shoelace(overlap) == pytest.approx(0.5, abs=1e-15)


@pytest.mark.parametrize("offset", [(2.0, 0.0), (1.5, 1.5), (-0.2, 3.0)])
def test_clip_disjoint_is_empty(offset):
    assert clip_convex(square(*offset), square()).shape == (0, 2)
    far = np.array([[3.0, 3.0], [4.0, 3.0], [3.0, 4.0]])
    assert clip_convex(far, square()).shape == (0, 2)


@pytest.mark.parametrize(
    "subject",
    [
        square(1.0, 0.0),  # shares the edge x = 1
        square(1.0, 0.3),  # shares part of it
        square(1.0, 1.0),  # shares the vertex (1, 1)
        square(0.0, -1.0 + 3e-15),  # overlaps by round-off only
        np.array([[1.0, 0.5], [2.0, 0.0], [2.0, 1.0]]),  # a vertex on the edge
    ],
)
def test_clip_touching_is_empty(subject):
    for overlap in (clip_convex(subject, square()), clip_convex(square(), subject)):
        assert overlap.shape == (0, 2)


def test_clip_degenerate_inputs():
    line = np.array([[0.0, 0.0], [0.5, 0.5], [1.0, 1.0]])  # zero area
    assert clip_convex(line, square()).shape == (0, 2)
    assert clip_convex(square(), line).shape == (0, 2)
    assert clip_convex(np.zeros((0, 2)), square()).shape == (0, 2)


def test_clip_shared_edges_exact():
    # Identical polygons; a triangle sharing two edges of the square; clockwise input.
    assert shoelace(clip_convex(square(), square())) == pytest.approx(1.0, abs=1e-15)
    half = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    overlap = clip_convex(half, square())
    assert overlap.shape == (3, 2) and shoelace(overlap) == pytest.approx(0.5, abs=1e-15)
    overlap = clip_convex(square()[::-1], half[::-1])
    assert shoelace(overlap) == pytest.approx(0.5, abs=1e-15)


def test_clip_random_convex_is_symmetric_and_inside_both():
    rng = np.random.default_rng(20260521)
    worst = 0.0
    for _ in range(300):
        A = random_convex(rng, rng.integers(3, 9))
        B = random_convex(rng, rng.integers(3, 9))
        ab, ba = clip_convex(A, B), clip_convex(B, A)
        area_ab = shoelace(ab) if ab.size else 0.0
        area_ba = shoelace(ba) if ba.size else 0.0
        worst = max(worst, abs(area_ab - area_ba))
        assert area_ab >= 0.0
        assert area_ab <= min(shoelace(A), shoelace(B)) + 1e-14
        if ab.size:
            assert inside(ab, A, 1e-13) and inside(ab, B, 1e-13)
            assert shoelace(ab) > 0.0  # counter-clockwise
    assert worst <= 1e-13


# -- triangulation ----------------------------------------------------------------------


def test_triangulate_hexagon_and_collinear_vertices():
    angles = np.arange(6) * np.pi / 3
    hexagon = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    tris = triangulate(hexagon)
    assert tris.shape == (6, 3, 2)
    areas = np.array([shoelace(t) for t in tris])
    assert np.all(areas > 0) and areas.sum() == pytest.approx(1.5 * np.sqrt(3), abs=1e-14)
    # A vertex in the middle of an edge: the centroid is off that edge's line, all five
    # triangles have area; a repeated vertex: its flat triangle is dropped.
    pentagon = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.5, 1.0], [0.0, 1.0]])
    tris = triangulate(pentagon)
    assert tris.shape[0] == 5
    assert sum(shoelace(t) for t in tris) == pytest.approx(1.0, abs=1e-15)
    repeated = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 1.0 + 1e-16], [0.0, 1.0]])
    tris = triangulate(repeated)
    assert tris.shape[0] == 4
    assert sum(shoelace(t) for t in tris) == pytest.approx(1.0, abs=1e-15)
    assert triangulate(np.zeros((2, 2))).shape == (0, 3, 2)


# -- the composite rule on overlaps -----------------------------------------------------


def quad_face(x0, y0, x1, y1, z=0.0):
    """A flat rectangle's Q1 nodes in Basix order: (0, 0), (1, 0), (0, 1), (1, 1)."""
    return np.array([[x0, y0, z], [x1, y0, z], [x0, y1, z], [x1, y1, z]])


def tri_face(p0, p1, p2, z=0.0):
    return np.array([[*p0, z], [*p1, z], [*p2, z]], dtype=np.float64)


def rule_of(c_face, t_face, degree):
    """One contactor face (outward +z) against one target face (outward -z)."""
    return overlap_rule(
        c_face[None], np.array([1.0]), t_face[None], np.array([-1.0]), [0], [0], degree
    )


def interval_moment(i, lo, hi):
    return (hi ** (i + 1) - lo ** (i + 1)) / (i + 1)


DEGREES = [1, 2, 3, 4, 6]


@pytest.mark.parametrize("degree", DEGREES)
@pytest.mark.parametrize("a, b", [(0.3, 0.6), (-0.25, 0.1), (0.45, -0.7)])
def test_rule_integrates_monomials_on_offset_squares(degree, a, b):
    rule = rule_of(quad_face(0, 0, 1, 1), quad_face(a, b, 1 + a, 1 + b, z=0.1), degree)
    x = rule.xi  # the unit square's map is the identity
    lo, hi = (max(0.0, a), max(0.0, b)), (min(1.0, 1 + a), min(1.0, 1 + b))
    for i in range(degree + 1):
        for j in range(degree + 1 - i):
            got = np.sum(rule.surface_weights * x[..., 0] ** i * x[..., 1] ** j)
            exact = interval_moment(i, lo[0], hi[0]) * interval_moment(j, lo[1], hi[1])
            assert abs(got - exact) <= 1e-13, (i, j)
    # Eq. (38) on parallel flat faces: the target point straight above, the gap 0.1.
    assert np.allclose(rule.eta, rule.xi - [a, b], rtol=0, atol=1e-14)
    assert np.allclose(rule.gap, 0.1, rtol=0, atol=1e-14)
    assert np.allclose(rule.normals, [0, 0, 1], rtol=0, atol=1e-15)
    assert np.array_equal(rule.weights, rule.surface_weights)


def triangle_square_moment(i, j):
    """Integral of x^i y^j over the triangle x + y <= 2 clipped to [0.5, 1.5]^2, that is
    x in [0.5, 1.5], y in [0.5, 2 - x]: exact polynomial antiderivatives."""
    x = Polynomial([0.0, 1.0])
    inner = ((2 - x) ** (j + 1) - 0.5 ** (j + 1)) / (j + 1)
    antiderivative = (x**i * inner).integ()
    return antiderivative(1.5) - antiderivative(0.5)


@pytest.mark.parametrize("degree", DEGREES)
@pytest.mark.parametrize("contactor", ["square", "triangle"])
def test_rule_integrates_monomials_on_triangle_square_overlap(degree, contactor):
    # The target 0.05 below the contactor (which faces up): overlapping, gap -0.05.
    if contactor == "square":
        rule = rule_of(
            quad_face(0.5, 0.5, 1.5, 1.5), tri_face((0, 0), (2, 0), (0, 2), -0.05), degree
        )
        x = 0.5 + rule.xi
    else:
        rule = rule_of(
            tri_face((0, 0), (2, 0), (0, 2)), quad_face(0.5, 0.5, 1.5, 1.5, -0.05), degree
        )
        x = 2.0 * rule.xi
    for i in range(degree + 1):
        for j in range(degree + 1 - i):
            got = np.sum(rule.surface_weights * x[..., 0] ** i * x[..., 1] ** j)
            exact = triangle_square_moment(i, j)
            assert abs(got - exact) <= 1e-13 * max(1.0, abs(exact)), (i, j)
    assert np.allclose(rule.gap, -0.05, rtol=0, atol=1e-14)


def test_contactor_facing_down():
    """Orientation -1: the contactor's outward normal is -z, its target 0.1 below."""
    c, t = quad_face(0, 0, 1, 1), quad_face(0.3, -0.4, 1.3, 0.6, z=-0.1)
    rule = overlap_rule(c[None], -np.ones(1), t[None], np.ones(1), [0], [0], 2)
    assert abs(rule.surface_weights.sum() - 0.7 * 0.6) <= 1e-15
    assert np.allclose(rule.normals, [0, 0, -1], rtol=0, atol=1e-15)
    assert np.allclose(rule.gap, 0.1, rtol=0, atol=1e-15)
    assert np.allclose(rule.eta, rule.xi - [0.3, -0.4], rtol=0, atol=1e-15)


def test_non_facing_targets_are_dropped():
    c, t = quad_face(0, 0, 1, 1), quad_face(0.2, 0.2, 1.2, 1.2, z=0.1)
    same_side = overlap_rule(c[None], np.ones(1), t[None], np.ones(1), [0], [0], 2)
    assert len(same_side) == 0 and same_side.xi.shape[0] == 0
    assert len(rule_of(c, t, 2)) > 0


# -- the patch-test identity: a non-matching tiling of the unit square ------------------


def triangle_mesh(n, rng):
    """The unit square's (n + 1)^2 grid, interior vertices moved, cells cut in two."""
    g = np.linspace(0.0, 1.0, n + 1)
    X, Y = np.meshgrid(g, g, indexing="ij")
    xy = np.stack([X.ravel(), Y.ravel()], axis=1)
    interior = np.all((xy > 0) & (xy < 1), axis=1)
    xy[interior] += rng.uniform(-0.3, 0.3, (interior.sum(), 2)) / n
    v = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    cells = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = v[i, j], v[i + 1, j], v[i + 1, j + 1], v[i, j + 1]
            cells += [[a, b, c], [a, c, d]] if (i + j) % 2 else [[a, b, d], [b, c, d]]
    return xy, np.array(cells)


def rectangle_mesh(xs, ys):
    """Rectangles of a tensor grid, vertices in Basix's order."""
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    xy = np.stack([X.ravel(), Y.ravel()], axis=1)
    v = np.arange(xs.size * ys.size).reshape(xs.size, ys.size)
    cells = [
        [v[i, j], v[i + 1, j], v[i, j + 1], v[i + 1, j + 1]]
        for i in range(xs.size - 1)
        for j in range(ys.size - 1)
    ]
    return xy, np.array(cells)


def basis(xi, num_nodes):
    """P1 triangle or Q1 quadrilateral shape functions, Basix node order, by hand."""
    s, t = xi[..., 0], xi[..., 1]
    if num_nodes == 3:
        return np.stack([1 - s - t, s, t], axis=-1)
    return np.stack([(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t], axis=-1)


def cell_areas(xy, cells):
    p = xy[cells]
    if cells.shape[1] == 3:
        e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
        return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])


def poly_integral_unit_square(coefficients):
    """Integral over [0, 1]^2 of sum c[i, j] x^i y^j."""
    i, j = np.indices(coefficients.shape)
    return np.sum(coefficients / ((i + 1) * (j + 1)))


def poly_product(p, q):
    out = np.zeros((p.shape[0] + q.shape[0] - 1, p.shape[1] + q.shape[1] - 1))
    for (i, j), c in np.ndenumerate(p):
        out[i : i + q.shape[0], j : j + q.shape[1]] += c * q
    return out


def poly_eval(c, xy):
    i, j = np.indices(c.shape)
    return np.sum(c[None] * xy[:, 0, None, None] ** i * xy[:, 1, None, None] ** j, axis=(1, 2))


LINEAR = np.array([[1.0, -1.0], [2.0, 0.0]])  # 1 + 2x - y
BILINEAR = np.array([[3.0, 0.5], [-1.0, 1.0]])  # 3 - x + 0.5y + xy


@pytest.mark.parametrize("shift", [(0.0, 0.0, 0.0), (100.0, -40.0, 7.0)])
@pytest.mark.parametrize("contactor", ["triangles", "rectangles"])
def test_patch_identity_on_non_matching_tiling(contactor, shift):
    """Fig. 15(b) on faces: the pieces tile the square and integrate N^C N^T exactly."""
    rng = np.random.default_rng(7)
    tri = triangle_mesh(3, rng)
    rect = rectangle_mesh(np.array([0.0, 0.3, 0.55, 1.0]), np.array([0.0, 0.2, 0.7, 0.85, 1.0]))
    (xy_c, cells_c), (xy_t, cells_t) = (tri, rect) if contactor == "triangles" else (rect, tri)
    # A rigid motion: the pieces live in the faces' (tilted) planes.
    angle = 0.7
    R = np.array([[np.cos(angle), 0, np.sin(angle)], [0, 1, 0], [-np.sin(angle), 0, np.cos(angle)]])
    R = R @ np.array([[1, 0, 0], [0, np.cos(0.4), -np.sin(0.4)], [0, np.sin(0.4), np.cos(0.4)]])
    # Far from the origin the nodes themselves are rounded by eps |x|: areas move as much.
    far = np.max(np.abs(shift))
    tol = 1e-14 + 4 * EPS * far

    def nodes(xy, cells, z):
        return np.concatenate([xy[cells], np.full((*cells.shape, 1), z)], axis=2) @ R.T + shift

    gap = 0.1
    c_nodes, t_nodes = nodes(xy_c, cells_c, 0.0), nodes(xy_t, cells_t, gap)
    ic, it = (a.ravel().astype(np.int32) for a in np.indices((len(cells_c), len(cells_t))))
    rule = overlap_rule(c_nodes, np.ones(len(cells_c)), t_nodes, -np.ones(len(cells_t)), ic, it, 3)
    w = rule.surface_weights
    assert abs(w.sum() - 1.0) <= tol
    assert np.allclose(rule.gap, gap, rtol=0, atol=tol)
    # The mixed mass matrix M[I, J] = integral of N_I^C N_J^T, assembled from the pieces.
    phi_c = basis(rule.xi, cells_c.shape[1])
    phi_t = basis(rule.eta, cells_t.shape[1])
    M = np.zeros((len(xy_c), len(xy_t)))
    local = np.einsum("sq,sqa,sqb->sab", w, phi_c, phi_t)
    for s in range(len(rule)):
        M[np.ix_(cells_c[rule.contactor[s]], cells_t[rule.target[s]])] += local[s]
    # Partition of unity: row sums are the integrals of N_I^C, by hand (|T|/3, |R|/4).
    for xy, cells, sums in ((xy_c, cells_c, M.sum(axis=1)), (xy_t, cells_t, M.sum(axis=0))):
        exact = np.zeros(len(xy))
        np.add.at(exact, cells, cell_areas(xy, cells)[:, None] / cells.shape[1])
        assert np.max(np.abs(sums - exact)) <= tol
    # Interpolants reproduced exactly by each space: a^T M b = integral of u v.
    u = LINEAR if contactor == "triangles" else BILINEAR
    v = BILINEAR if contactor == "triangles" else LINEAR
    value = poly_eval(u, xy_c) @ M @ poly_eval(v, xy_t)
    assert abs(value - poly_integral_unit_square(poly_product(u, v))) <= 10 * tol


# -- inverse maps and Eq. (38) ------------------------------------------------------------


def smooth(X):
    """A smooth map of the reference plane to a curved surface."""
    s, t = X[:, 0], X[:, 1]
    return np.stack(
        [
            s + 0.15 * t**2 + 0.05 * s * t,
            t - 0.1 * s * t + 0.08 * s**2,
            0.3 * s**2 - 0.2 * s * t + 0.1 * t,
        ],
        axis=1,
    )


@pytest.mark.parametrize(
    "cell, degree", [("triangle", 2), ("quadrilateral", 2), ("quadrilateral", 1)]
)
def test_newton_inverts_curved_faces(cell, degree):
    element = basix.create_element(
        basix.ElementFamily.P, basix.CellType[cell], degree, basix.LagrangeVariant.gll_warped
    )
    nodes = smooth(element.points)
    rng = np.random.default_rng(3)
    xi_true = rng.uniform(0.0, 1.0, (200, 2))
    if cell == "triangle":
        xi_true = xi_true[xi_true.sum(axis=1) <= 1.0]
    x = element.tabulate(0, xi_true)[0, :, :, 0] @ nodes
    # Lines through the points along the corner polygon's normal.
    corners = nodes[[0, 1, 2]] if cell == "triangle" else nodes[[0, 1, 3, 2]]
    rel = corners - corners.mean(axis=0)
    n = np.cross(rel, np.roll(rel, -1, axis=0)).sum(axis=0)
    n = np.tile(n / np.linalg.norm(n), (len(x), 1))
    rows = np.zeros(len(x), dtype=np.int32)
    xi, t = intersect(nodes[None], rows, x, n)
    back = element.tabulate(0, xi)[0, :, :, 0] @ nodes
    assert np.max(np.linalg.norm(back - x, axis=1)) <= 1e-12
    assert np.max(np.abs(t)) <= 1e-12
    assert np.max(np.abs(xi - xi_true)) <= 1e-12


@pytest.mark.parametrize("num_nodes", [3, 4])
def test_ray_meets_tilted_flat_face_as_line_meets_plane(num_nodes):
    rng = np.random.default_rng(11)
    p0 = np.array([0.3, -0.2, 0.5])
    a, b = np.array([1.0, 0.2, 0.4]), np.array([-0.3, 0.9, 0.6])
    face = np.array([p0, p0 + a, p0 + b, p0 + a + b])[:num_nodes]
    origins = rng.uniform(-1.0, 1.0, (50, 3))
    d = rng.normal(size=(50, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    normal = np.cross(a, b)
    keep = np.abs(d @ normal) > 0.2 * np.linalg.norm(normal)
    origins, d = origins[keep], d[keep]
    xi, t = intersect(face[None], np.zeros(len(d), dtype=np.int32), origins, d)
    # Closed form: t from the plane's equation, then xi by Cramer's rule on the Gram system.
    t_exact = (p0 - origins) @ normal / (d @ normal)
    r = origins + t_exact[:, None] * d - p0
    G = np.array([[a @ a, a @ b], [a @ b, b @ b]])
    rhs = np.stack([r @ a, r @ b], axis=1)
    det = G[0, 0] * G[1, 1] - G[0, 1] ** 2
    xi_exact = np.stack(
        [
            (rhs[:, 0] * G[1, 1] - rhs[:, 1] * G[0, 1]) / det,
            (G[0, 0] * rhs[:, 1] - G[0, 1] * rhs[:, 0]) / det,
        ],
        axis=1,
    )
    assert np.max(np.abs(t - t_exact)) <= 1e-12
    assert np.max(np.abs(xi - xi_exact)) <= 1e-12


# -- bad input ------------------------------------------------------------------------------


def test_zero_area_face_raises_naming_it():
    good = quad_face(0, 0, 1, 1)
    flat = np.array([[0.0, 0, 0], [1, 1, 0], [2, 2, 0]])  # collinear corners
    tri = tri_face((0, 0), (1, 0), (0, 1), z=0.1)
    c = np.stack([tri, flat])
    with pytest.raises(ValueError, match="contactor face 1 has zero area"):
        overlap_rule(c, np.ones(2), good[None], -np.ones(1), [0, 1], [0, 0], 2)
    point = np.zeros((4, 3))  # all corners coincide
    with pytest.raises(ValueError, match="target face 1 has zero area"):
        overlap_rule(
            good[None], np.ones(1), np.stack([good, point]), -np.ones(2), [0, 0], [0, 1], 2
        )
    with pytest.raises(ValueError, match="5 nodes are not supported"):
        overlap_rule(np.zeros((1, 5, 3)), np.ones(1), good[None], -np.ones(1), [0], [0], 2)


@pytest.mark.parametrize("num_nodes", [3, 4])
def test_line_along_the_face_raises_naming_it(num_nodes):
    faces = np.stack([quad_face(0, 0, 1, 1), quad_face(0, 0, 1, 1, z=1.0)])[:, :num_nodes]
    rows = np.array([0, 1], dtype=np.int32)
    origins = np.array([[0.2, 0.2, 0.5], [0.2, 0.2, 1.0]])
    along = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])  # face 1's line lies in its plane
    with pytest.raises(RuntimeError, match="target face 1: no point met along the line"):
        intersect(faces, rows, origins, along, name="target face")


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
def test_curved_contactor_pulled_back_along_its_plane_normal(cell):
    """A P2/Q2 contactor under a flat target plane z = 1 that covers it."""
    element = basix.create_element(
        basix.ElementFamily.P, basix.CellType[cell], 2, basix.LagrangeVariant.gll_warped
    )
    c_nodes = smooth(element.points)
    t_nodes = quad_face(-1.0, -1.0, 2.0, 2.0, z=1.0)
    rule = rule_of(c_nodes, t_nodes, 4)
    # The contactor plane, as documented: origin at the corners' centroid, n their unit
    # vector area, e1 the first corner edge made orthogonal to n, e2 = n x e1.
    corners = c_nodes[[0, 1, 2]] if cell == "triangle" else c_nodes[[0, 1, 3, 2]]
    origin = corners.mean(axis=0)
    vector_area = 0.5 * np.cross(corners - origin, np.roll(corners, -1, axis=0) - origin).sum(0)
    n = vector_area / np.linalg.norm(vector_area)
    e1 = corners[1] - corners[0]
    e1 = e1 - (e1 @ n) * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    # The pieces tile the corner polygon's shadow on the plane.
    assert abs(rule.weights.sum() - np.linalg.norm(vector_area)) <= 1e-14
    xi = rule.xi.reshape(-1, 2)
    table = element.tabulate(1, xi)[:, :, :, 0]
    x_c = table[0] @ c_nodes
    # Each point of the plane is pulled back along n onto the curved face.
    in_plane = np.stack([(x_c - origin) @ e1, (x_c - origin) @ e2], axis=1)
    assert np.max(np.abs(in_plane - rule.points.reshape(-1, 2))) <= 1e-13
    # The outward normal at the point and the area element relative to the plane's.
    dx = np.stack([table[1] @ c_nodes, table[2] @ c_nodes], axis=2)
    cross = np.cross(dx[:, :, 0], dx[:, :, 1])
    n_c = cross / np.linalg.norm(cross, axis=1)[:, None]
    assert np.max(np.abs(rule.normals.reshape(-1, 3) - n_c)) <= 1e-14
    ratio = np.linalg.norm(cross, axis=1) / np.abs(cross @ n)
    assert np.allclose(rule.surface_weights.reshape(-1), rule.weights.reshape(-1) * ratio)
    # Eq. (38): the line from x_c along n_c meets z = 1 at gap (1 - z_c) / n_z.
    gap = (1.0 - x_c[:, 2]) / n_c[:, 2]
    assert np.max(np.abs(rule.gap.reshape(-1) - gap)) <= 1e-13
    x_t = x_c + gap[:, None] * n_c
    assert np.max(np.abs(rule.eta.reshape(-1, 2) - (x_t[:, :2] + 1.0) / 3.0)) <= 1e-13

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The geometry of the 3D composite quadrature (Fig. 15(b) on faces), against closed forms.

Every expected number comes from outside the module: areas and integrals in closed form,
hand-computed vertices, exact polynomial antiderivatives, line-plane intersections.
"""

import numpy as np
import pytest

from dolfinx_contact_s2s.kernels.polygon import clip_convex, triangulate

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

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The compiled clipping and triangulation of polygons against the NumPy reference.

``kernels.clipping`` (NumPy, tested against closed forms in test_polygon_overlap.py) and
``kernels.c_backend`` expose ``clip_polygons`` and ``triangulate_polygons`` with one
signature; here the C versions must give the same vertex counts, vertices, areas and
rules: on the closed-form cases, on random convex pairs built to hit the snapping rule
(vertices on the other polygon's edges, shared vertices and edges, lattice polygons),
and inside ``overlap_rule`` on a non-matching tiling.
"""

import shutil
import sysconfig

import numpy as np
import pytest
from test_polygon_overlap import rectangle_mesh, square, triangle_mesh

from dolfinx_contact_s2s.kernels import clipping
from dolfinx_contact_s2s.kernels.polygon import overlap_rule

# Relative agreement asked of the two backends (they compute in the same order, so they
# are expected to agree to the last bit; this is the promised bound).
REL = 1e-14


@pytest.fixture(scope="module")
def c_kernels():
    """The loaded C backend; skipped only if CFFI or a C compiler is missing."""
    pytest.importorskip("cffi")
    compiler = (sysconfig.get_config_var("CC") or "cc").split()[0]
    if shutil.which(compiler) is None:
        pytest.skip(f"no C compiler ({compiler})")
    from dolfinx_contact_s2s.kernels import c_backend

    return c_backend.load()


@pytest.fixture(params=["numpy", "c"])
def polygon_backend(request):
    """The module providing clip_polygons and triangulate_polygons."""
    return clipping if request.param == "numpy" else request.getfixturevalue("c_kernels")


def shoelace(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def pad(polygons, width):
    """Polygons of any vertex counts as a padded array (NaN beyond the counts) and counts."""
    out = np.full((len(polygons), width, 2), np.nan)
    counts = np.array([len(p) for p in polygons], dtype=np.int32)
    for p, v in enumerate(polygons):
        out[p, : len(v)] = v
    return out, counts


def compare(c_kernels, subjects, clips):
    """Clip with both backends; assert the same counts, vertices and areas.

    Returns the worst vertex difference relative to the pair's size and the worst area
    difference relative to its size squared.
    """
    s, ns = pad(subjects, max(len(v) for v in subjects))
    c, nc = pad(clips, max(len(v) for v in clips))
    ref, ref_counts = clipping.clip_polygons(s, c, ns, nc)
    out, counts = c_kernels.clip_polygons(s, c, ns, nc)
    assert out.shape == ref.shape == (len(subjects), s.shape[1] + c.shape[1], 2)
    np.testing.assert_array_equal(counts, ref_counts)
    worst_x = worst_area = 0.0
    for p in range(len(subjects)):
        size = max(np.max(np.abs(subjects[p]), initial=0.0), np.max(np.abs(clips[p])))
        size = max(size, np.finfo(float).tiny)
        k = counts[p]
        assert np.all(out[p, k:] == 0.0) and np.all(ref[p, k:] == 0.0)
        worst_x = max(worst_x, np.max(np.abs(out[p, :k] - ref[p, :k]), initial=0.0) / size)
        if k:
            worst_area = max(worst_area, abs(shoelace(out[p, :k]) - shoelace(ref[p, :k])) / size**2)
    assert worst_x <= REL and worst_area <= REL, (worst_x, worst_area)
    # The triangles of the overlaps, too.
    tris, owner = clipping.triangulate_polygons(ref, ref_counts)
    c_tris, c_owner = c_kernels.triangulate_polygons(out, counts)
    np.testing.assert_array_equal(c_owner, owner)
    assert c_tris.shape == tris.shape
    assert np.all(np.abs(c_tris - tris) <= REL * (1.0 + np.abs(tris)))
    return worst_x, worst_area


# -- (a) the closed-form cases of test_polygon_overlap.py ---------------------------------


def closed_form_cases():
    """(subject, clip, area of the overlap) of test_polygon_overlap.py's clipping tests."""
    unit = square()
    cases = []
    for a, b in [(0.3, 0.6), (-0.25, 0.1), (0.0, -0.7), (0.5, 0.5), (-0.9, -0.05), (0.0, 0.0)]:
        cases.append((square(a, b), unit, (1 - abs(a)) * (1 - abs(b))))
    tri = np.array([[0.2, 0.1], [0.9, 0.3], [0.4, 0.8]])
    area = 0.5 * abs((0.9 - 0.2) * (0.8 - 0.1) - (0.4 - 0.2) * (0.3 - 0.1))
    cases += [(tri, unit, area), (unit, tri, area)]
    cases.append((np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]), square(0.5, 0.5), 0.5))
    for offset in [(2.0, 0.0), (1.5, 1.5), (-0.2, 3.0)]:
        cases.append((square(*offset), unit, 0.0))
    cases.append((np.array([[3.0, 3.0], [4.0, 3.0], [3.0, 4.0]]), unit, 0.0))
    touching = [
        square(1.0, 0.0),
        square(1.0, 0.3),
        square(1.0, 1.0),
        square(0.0, -1.0 + 3e-15),
        np.array([[1.0, 0.5], [2.0, 0.0], [2.0, 1.0]]),
    ]
    cases += [(t, unit, 0.0) for t in touching] + [(unit, t, 0.0) for t in touching]
    line = np.array([[0.0, 0.0], [0.5, 0.5], [1.0, 1.0]])
    cases += [(line, unit, 0.0), (unit, line, 0.0), (np.zeros((0, 2)), unit, 0.0)]
    half = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    cases += [(unit, unit, 1.0), (half, unit, 0.5), (unit[::-1], half[::-1], 0.5)]
    return cases


def test_closed_form_cases_both_backends(polygon_backend):
    """Each backend, batched and padded, gives the closed-form areas."""
    subjects, clips, areas = zip(*closed_form_cases(), strict=True)
    s, ns = pad(subjects, 4)
    c, nc = pad(clips, 4)
    out, counts = polygon_backend.clip_polygons(s, c, ns, nc)
    got = [shoelace(out[p, : counts[p]]) if counts[p] else 0.0 for p in range(len(areas))]
    np.testing.assert_allclose(got, areas, rtol=0, atol=1e-14)
    assert np.all((counts == 0) == (np.array(areas) == 0.0))
    tris, owner = polygon_backend.triangulate_polygons(out, counts)
    sums = np.bincount(owner, [shoelace(t) for t in tris], minlength=len(areas))
    np.testing.assert_allclose(sums, areas, rtol=0, atol=1e-14)


def test_closed_form_cases_c_equals_numpy(c_kernels):
    subjects, clips, _ = zip(*closed_form_cases(), strict=True)
    compare(c_kernels, list(subjects), list(clips))


def test_nan_vertex_gives_empty_overlap(polygon_backend):
    """A NaN coordinate makes the tolerance NaN: no overlap, and no triangle, in both."""
    unit = square()
    bad = square(0.3, 0.6)
    bad[2, 0] = np.nan
    s, ns = pad([bad, unit, unit], 4)
    c, nc = pad([unit, bad, unit], 4)
    out, counts = polygon_backend.clip_polygons(s, c, ns, nc)
    np.testing.assert_array_equal(counts, [0, 0, 4])
    out[2, 1, 1] = np.nan
    tris, owner = polygon_backend.triangulate_polygons(out, counts)
    assert tris.shape == (0, 3, 2) and owner.shape == (0,)


# -- (b) random convex pairs, built to meet the snapping rule ----------------------------


def hull(points):
    """Convex hull, counter-clockwise, without collinear points (Andrew's monotone chain)."""
    pts = sorted(map(tuple, points))

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2:
                (ax, ay), (bx, by) = out[-2], out[-1]
                if (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax) > 0:
                    break
                out.pop()
            out.append(p)
        return out[:-1]

    return np.array(half(pts) + half(pts[::-1]))


def rotation(angle):
    return np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])


def random_polygon(rng, n):
    """A triangle or quadrilateral on a random rotated ellipse, either orientation."""
    angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    axes = rng.uniform(0.3, 1.5, 2)
    poly = np.stack([axes[0] * np.cos(angles), axes[1] * np.sin(angles)], axis=1)
    poly = poly @ rotation(rng.uniform(0, np.pi)).T + rng.uniform(-0.5, 0.5, 2)
    return poly if rng.random() < 0.5 else poly[::-1]


def around(rng, anchors, n):
    """The hull of the anchor points and random ones, if a triangle or quadrilateral."""
    while True:
        extra = rng.uniform(-1.5, 1.5, (n - len(anchors), 2))
        poly = hull(np.concatenate([anchors, extra]))
        if len(poly) >= 3 and abs(shoelace(poly)) > 1e-3:
            return np.roll(poly, rng.integers(len(poly)), axis=0)


def random_pair(rng, kind):
    """A (subject, clip) pair of triangles or quadrilaterals of the given kind."""
    n_s, n_c = rng.integers(3, 5, 2)
    clip = random_polygon(rng, n_c)
    if kind == "generic":
        return random_polygon(rng, n_s), clip
    k = rng.integers(len(clip))
    a, b = clip[k], clip[(k + 1) % len(clip)]
    if kind == "on edge":  # a vertex on an edge of the clip polygon (to round-off)
        anchors = [a + rng.uniform(0.1, 0.9) * (b - a)]
    elif kind == "shared vertex":
        anchors = [a]
    elif kind == "shared edge":
        anchors = [a, b]
    else:  # "two on edges": vertices on two edges of the clip polygon
        c = clip[(k + 2) % len(clip)]
        anchors = [a + rng.uniform(0.1, 0.9) * (b - a), b + rng.uniform(0.1, 0.9) * (c - b)]
    return around(rng, np.array(anchors), n_s), clip


def lattice_pair(rng):
    """Triangles and quadrilaterals with vertices on a small integer lattice: exact shared
    edges, vertices on edges and collinear vertices; rotated half the time (both alike),
    which turns the exact coincidences into round-off ones."""
    while True:
        s = hull(rng.integers(0, 4, (rng.integers(3, 5), 2)).astype(float))
        c = hull(rng.integers(0, 4, (rng.integers(3, 5), 2)).astype(float))
        if len(s) >= 3 and len(c) >= 3:
            break
    if rng.random() < 0.5:
        R = rotation(rng.uniform(0, 2 * np.pi))
        shift = rng.uniform(-1, 1, 2)
        s, c = s @ R.T + shift, c @ R.T + shift
    return s, c


KINDS = ["generic", "on edge", "shared vertex", "shared edge", "two on edges"]


def test_random_pairs_c_equals_numpy(c_kernels):
    rng = np.random.default_rng(2026_21)
    subjects, clips = [], []
    for i in range(2000):
        if i % 6 == 5:
            s, c = lattice_pair(rng)
        else:
            s, c = random_pair(rng, KINDS[i % 6])
        # Also the other way round, and scaled far from the unit size.
        if rng.random() < 0.3:
            s, c = c, s
        scale = 10.0 ** rng.integers(-3, 4)
        subjects.append(s * scale)
        clips.append(c * scale)
    worst_x, worst_area = compare(c_kernels, subjects, clips)
    # The pairs meet every branch: overlaps, empty ones, and 3 to 8 vertices.
    s, ns = pad(subjects, 4)
    c, nc = pad(clips, 4)
    _, counts = clipping.clip_polygons(s, c, ns, nc)
    assert np.count_nonzero(counts == 0) > 100
    assert {3, 4, 5, 6} <= set(counts.tolist())
    print(f"worst relative vertex difference {worst_x:.3g}, area {worst_area:.3g}")


# -- (c) overlap_rule with either clipping -------------------------------------------------


@pytest.mark.parametrize("shift", [(0.0, 0.0, 0.0), (100.0, -40.0, 7.0)])
@pytest.mark.parametrize("contactor", ["triangles", "rectangles"])
def test_overlap_rule_c_equals_numpy_on_non_matching_tiling(c_kernels, contactor, shift):
    """The tiling of test_patch_identity_on_non_matching_tiling, clipped by either backend."""
    rng = np.random.default_rng(7)
    tri = triangle_mesh(3, rng)
    rect = rectangle_mesh(np.array([0.0, 0.3, 0.55, 1.0]), np.array([0.0, 0.2, 0.7, 0.85, 1.0]))
    (xy_c, cells_c), (xy_t, cells_t) = (tri, rect) if contactor == "triangles" else (rect, tri)
    R = np.array([[np.cos(0.7), 0, np.sin(0.7)], [0, 1, 0], [-np.sin(0.7), 0, np.cos(0.7)]])
    R = R @ np.array([[1, 0, 0], [0, np.cos(0.4), -np.sin(0.4)], [0, np.sin(0.4), np.cos(0.4)]])

    def nodes(xy, cells, z):
        return np.concatenate([xy[cells], np.full((*cells.shape, 1), z)], axis=2) @ R.T + shift

    c_nodes, t_nodes = nodes(xy_c, cells_c, 0.0), nodes(xy_t, cells_t, 0.1)
    ic, it = (a.ravel().astype(np.int32) for a in np.indices((len(cells_c), len(cells_t))))
    args = (c_nodes, np.ones(len(cells_c)), t_nodes, -np.ones(len(cells_t)), ic, it, 3)
    ref = overlap_rule(*args)
    got = overlap_rule(*args, backend=c_kernels)
    assert len(got) == len(ref) > 0
    for name in ("pair", "contactor", "target"):
        np.testing.assert_array_equal(getattr(got, name), getattr(ref, name))
    worst = 0.0
    for name in ("points", "weights", "xi", "surface_weights", "normals", "eta", "gap"):
        a, b = getattr(got, name), getattr(ref, name)
        worst = max(worst, np.max(np.abs(a - b)))
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-14, err_msg=name)
    print(f"worst difference {worst:.3g}")


# -- bad input ------------------------------------------------------------------------------


def test_bad_input_both_backends(polygon_backend):
    unit = square()[None]
    with pytest.raises(ValueError, match="padded polygons"):
        polygon_backend.clip_polygons(square(), square())
    with pytest.raises(ValueError, match="1 subject polygons but 2 clip"):
        polygon_backend.clip_polygons(unit, np.concatenate([unit, unit]))
    with pytest.raises(ValueError, match="counts must be"):
        polygon_backend.clip_polygons(unit, unit, np.array([5]))
    with pytest.raises(ValueError, match="counts must be"):
        polygon_backend.triangulate_polygons(unit, np.array([-1]))
    empty, counts = polygon_backend.clip_polygons(np.zeros((0, 4, 2)), np.zeros((0, 3, 2)))
    assert empty.shape == (0, 7, 2) and counts.shape == (0,)
    tris, owner = polygon_backend.triangulate_polygons(empty, counts)
    assert tris.shape == (0, 3, 2) and owner.shape == (0,)


def test_c_vertex_limit(c_kernels):
    big = np.zeros((1, c_kernels.MAX_POLYGON_VERTICES, 2))
    with pytest.raises(ValueError, match="at most"):
        c_kernels.clip_polygons(big, square()[None])

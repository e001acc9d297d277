# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The zero level set of a multiplier on faces (contact_front) against closed forms.

A P1 field on the top face :math:`z = 1` of a tetrahedral unit cube (a submesh, as a
pair's multiplier lives on the contactor's faces):

- a linear field :math:`\lambda = c - x` is its own interpolant: every crossing lies at
  :math:`x = c` exactly, whose distance from the axis :math:`y`-direction through
  :math:`(0, 0, 1)` is :math:`c` (:math:`c` between the nodes);
- Hertz's :math:`p_0 \sqrt{\max(0, 1 - r^2/a^2)}`: every active node lies inside
  :math:`r = a` and every inactive one outside, so the bracket holds :math:`a`;
- :math:`1 - r^2/a^2` (negative outside): the crossings of the interpolant lie within
  :math:`L^2/(4a)` of :math:`r = a` (the interpolation error of a quadratic,
  :math:`L^2 \max|f''|/8` with :math:`|f''| \le 2/a^2`, over the slope
  :math:`|\nabla f| \ge 1/a` near :math:`r = a`, for edges of length :math:`L`).

The gap estimate (``gaps=``) from weighted gaps :math:`\int \mu_k g` assembled by DOLFINx
(a rule of degree 12 on whole faces, an implementation of its own): for the power law
:math:`g = (r - a)_+^{3/2}` that the estimate assumes, :math:`a` itself to a small
fraction of an edge (the two rules' errors at the kink), with the Lagrange basis and with
the dual basis of P1 triangles (:math:`\psi_k = 4 \mu_k - 1` on each face of node
:math:`k`); for Hertz's own gap outside :math:`r = a` (a sphere of radius :math:`R` on a plane:
:math:`\pi R g = (2a^2 - r^2) \arcsin(a/r) + a \sqrt{r^2 - a^2} - \pi a^2 + \pi r^2 / 2`),
closer to :math:`a` than the bracket's middle.

The curvature indicator on the same faces (edges of length :math:`h = 1/N` along
:math:`x` and :math:`y`, one diagonal per square, so every interior ring is the six
offsets :math:`\pm h(1, 0), \pm h(0, 1), \pm h(1, 1)` or :math:`\pm h(1, -1)`): on a
centrally symmetric ring the fitted plane passes through the neighbours' mean, so the
indicator of :math:`\lambda` is :math:`|\overline{\lambda(\mathbf x + \mathbf d)} -
\lambda(\mathbf x)|` over the offsets, :math:`\frac{4}{3}h^2` for :math:`x^2 + y^2`
and zero for a linear field and for :math:`x^2 - y^2`.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import contact_front
from dolfinx_contact_s2s.contact_front import curvature_indicator

N = 16


def _face_space():
    cube = dolfinx.mesh.create_unit_cube(MPI.COMM_WORLD, N, N, 4)
    cube.topology.create_connectivity(2, 3)
    top = dolfinx.mesh.locate_entities_boundary(cube, 2, lambda x: np.isclose(x[2], 1.0))
    face = dolfinx.mesh.create_submesh(cube, 2, top)[0]
    return dolfinx.fem.functionspace(face, ("Lagrange", 1))


def _field(Q, f):
    lam = dolfinx.fem.Function(Q)
    lam.interpolate(f)
    return lam


def test_linear_field_crossings_are_exact():
    """lambda = c - x: crossings at x = c, the radius c, bracket one edge around it."""
    Q = _face_space()
    c = 0.37
    front = contact_front(_field(Q, lambda x: c - x[0]), centre=(0, 0, 1), axis=(0, 2.0, 0))
    assert front.points.shape[0] > N
    assert np.allclose(front.points[:, 0], c, atol=1e-13)
    assert np.allclose(front.points[:, 2], 1.0, atol=1e-13)
    assert front.radius == pytest.approx(c, abs=1e-13)
    lo, hi = front.bounds
    assert lo < c < hi and front.bracket <= 1.0 / N + 1e-12
    assert front.face_radii[0] < c < front.face_radii[1]
    assert front.spread <= 2.0 / N + 1e-12
    # The same front from the active flags of a Function.
    flags = _field(Q, lambda x: (x[0] < c).astype(float))
    again = contact_front(_field(Q, lambda x: c - x[0]), flags, centre=(0, 0, 1), axis=(0, 1, 0))
    assert np.allclose(np.sort(again.radii), np.sort(front.radii), atol=1e-13)


def test_hertz_pressure_bracket_holds_the_radius():
    """p0 sqrt(1 - r^2/a^2)_+: the crossings at the first inactive nodes, a inside the bracket."""
    Q = _face_space()
    a, p0 = 0.3, 2.5

    def hertz(x):
        r2 = (x[0] - 0.5) ** 2 + (x[1] - 0.5) ** 2
        return p0 * np.sqrt(np.clip(1 - r2 / a**2, 0, None))

    front = contact_front(_field(Q, hertz), centre=(0.5, 0.5, 1), axis=(0, 0, 1))
    assert np.all(front.inside < a) and np.all(front.outside > a)
    assert np.allclose(front.radii, front.outside)  # lambda_o = 0: at the inactive node
    lo, hi = front.bounds
    assert lo < a < hi and hi - lo <= np.sqrt(2) / N
    assert lo <= front.radius <= hi and front.radius == pytest.approx(hi)
    assert abs(front.middle - a) <= 0.5 * front.bracket
    # The peak: p0 at the node on the axis, the faces' diagonals around it.
    assert front.peak == pytest.approx(p0, rel=1e-14)
    assert np.allclose(front.peak_point, (0.5, 0.5, 1.0), atol=1e-14)
    assert front.peak_length == pytest.approx(np.sqrt(2) / N, rel=1e-12)


def test_quadratic_field_crossings_near_the_circle():
    """1 - r^2/a^2: every crossing within L^2/(4a) of r = a."""
    Q = _face_space()
    a = 0.3
    front = contact_front(
        _field(Q, lambda x: 1 - ((x[0] - 0.5) ** 2 + (x[1] - 0.5) ** 2) / a**2),
        centre=(0.5, 0.5, 1),
        axis=(0, 0, -1),
    )
    L = front.edge_lengths.max()
    assert L == pytest.approx(np.sqrt(2) / N)
    assert np.max(np.abs(front.radii - a)) <= L**2 / (4 * a)
    assert front.radius == pytest.approx(a, abs=L**2 / (4 * a))
    # A quarter of the circle's crossings at least: every x- and y-grid line meets it.
    assert front.points.shape[0] >= 4 * int(2 * a * N)


CENTRE, A = (0.5, 0.5), 0.3


def _radius(x):
    return ufl.sqrt((x[0] - CENTRE[0]) ** 2 + (x[1] - CENTRE[1]) ** 2)


def _weighted_gaps(Q, gap, dual=False):
    r"""DOLFINx's :math:`\int \mu_k g` (dual: :math:`4 \int \mu_k g - \int_{star(k)} g`)."""
    dx = ufl.dx(domain=Q.mesh, metadata={"quadrature_degree": 12})
    g = gap(ufl.SpatialCoordinate(Q.mesh))
    out = dolfinx.fem.Function(Q)
    dolfinx.fem.assemble_vector(out.x.array, dolfinx.fem.form(g * ufl.TestFunction(Q) * dx))
    if dual:
        W = dolfinx.fem.functionspace(Q.mesh, ("DG", 0))
        per_cell = dolfinx.fem.assemble_vector(dolfinx.fem.form(g * ufl.TestFunction(W) * dx))
        num = Q.mesh.topology.index_map(2).size_local
        star = np.zeros_like(out.x.array)
        np.add.at(star, Q.dofmap.list[:num].reshape(-1), np.repeat(per_cell.array[:num], 3))
        out.x.array[:] = 4.0 * out.x.array - star
    out.x.scatter_reverse(dolfinx.la.InsertMode.add)
    out.x.scatter_forward()
    return out


def _hertz_front(gap, dual=False):
    """The front of Hertz's pressure (radius A) with the weighted gaps of ``gap``."""
    Q = _face_space()

    def pressure(x):
        return np.sqrt(
            np.clip(1 - ((x[0] - CENTRE[0]) ** 2 + (x[1] - CENTRE[1]) ** 2) / A**2, 0, None)
        )

    gaps = _weighted_gaps(Q, gap, dual)
    return contact_front(
        _field(Q, pressure), centre=(*CENTRE, 1), axis=(0, 0, 1), gaps=gaps, dual=dual
    )


@pytest.mark.parametrize("dual", [False, True])
def test_gap_estimate_of_its_own_law(dual):
    """g = (r - a)_+^{3/2}: the gap estimate finds a to 2% of an edge (the bracket: four)."""
    front = _hertz_front(lambda x: ufl.max_value(_radius(x) - A, 0.0) ** 1.5, dual)
    assert front.method == "gap" and front.estimate == front.gap_radius
    # The inactive nodes of three rings around a circle of about 2 pi A N edges.
    assert front.gap_nodes >= 3 * int(2 * np.pi * A * N)
    assert abs(front.gap_radius - A) <= 0.02 / N, front.gap_radius - A


def test_gap_estimate_of_hertz_gap():
    """Hertz's gap outside r = a (a sphere of radius R on a plane): nearer a than the middle."""
    R = 2.0

    def gap(x):
        r = ufl.max_value(_radius(x), A)
        shape = (2 * A**2 - r**2) * ufl.asin(A / r) + A * ufl.sqrt(r**2 - A**2)
        return shape / (np.pi * R) - A**2 / R + r**2 / (2 * R)

    front = _hertz_front(gap)
    lo, hi = front.bounds
    assert lo < A < hi and lo <= front.gap_radius <= hi
    assert abs(front.gap_radius - A) < abs(front.middle - A)
    # Without the gaps: the middle.
    without = contact_front(
        _field(_face_space(), lambda x: A - x[0]), centre=(0, 0, 1), axis=(0, 0, 1)
    )
    assert without.method == "middle" and without.estimate == without.middle


def test_bad_input():
    """A 2D multiplier, a zero axis, a bad centre: ValueError on every rank."""
    Q = _face_space()
    lam = _field(Q, lambda x: 1 - x[0])
    with pytest.raises(ValueError, match="zero length"):
        contact_front(lam, centre=(0, 0, 0), axis=(0, 0, 0))
    with pytest.raises(ValueError, match="3 finite"):
        contact_front(lam, centre=(0, np.nan, 0), axis=(0, 0, 1))
    square = dolfinx.mesh.create_unit_square(MPI.COMM_WORLD, 2, 2)
    flat = dolfinx.fem.Function(dolfinx.fem.functionspace(square, ("Lagrange", 1)))
    with pytest.raises(ValueError, match="faces of a 3D model"):
        contact_front(flat, centre=(0, 0, 0), axis=(0, 0, 1))
    quadratic = dolfinx.fem.functionspace(Q.mesh, ("Lagrange", 2))
    with pytest.raises(ValueError, match="degree 1"):
        contact_front(
            _field(quadratic, lambda x: 1 - x[0]),
            centre=(0, 0, 0),
            axis=(0, 0, 1),
            gaps=dolfinx.fem.Function(quadratic),
        )


def test_curvature_indicator_closed_forms():
    """4/3 h^2 for x^2 + y^2 (relative to its largest value), zero for linear and x^2 - y^2."""
    Q = _face_space()
    h = 1.0 / N

    def interior(points):  # the nodes off the face's boundary (their rings: six offsets)
        return np.all((points[:, :2] > 0.5 * h) & (points[:, :2] < 1 - 0.5 * h), axis=1)

    def r2(x):
        return x[0] ** 2 + x[1] ** 2

    points, eta, longest = curvature_indicator([_field(Q, r2)])
    inner = interior(points)
    assert np.count_nonzero(inner) == (N - 1) ** 2  # all active: the field is positive
    top = 2.0  # x^2 + y^2 at the corner (1, 1)
    assert np.allclose(eta[inner], 4.0 / 3.0 * h**2 / top, rtol=1e-10)
    assert np.allclose(longest[inner], np.sqrt(2) * h, rtol=1e-12)
    for f in (lambda x: 3.0 + x[0] - 2 * x[1], lambda x: 3.0 + x[0] ** 2 - x[1] ** 2):
        points, eta, _ = curvature_indicator([_field(Q, f)])
        assert np.max(eta[interior(points)]) < 1e-13
    # Two components: the norms of the values and of the residuals.
    parts = [_field(Q, lambda x: 0.6 * r2(x)), _field(Q, lambda x: 0.8 * r2(x))]
    points, eta, _ = curvature_indicator(parts)
    assert np.allclose(eta[interior(points)], 4.0 / 3.0 * h**2 / top, rtol=1e-10)
    # Only nodes whose whole ring is active: x < 0.5 active leaves x <= 6 h.
    flags = _field(Q, lambda x: (x[0] < 0.5 - 0.25 * h).astype(float))
    points, _, _ = curvature_indicator([_field(Q, lambda x: x[0] ** 2)], flags)
    assert np.all(points[:, 0] < 0.5 - 1.5 * h)
    assert np.count_nonzero(interior(points)) == 6 * (N - 1)

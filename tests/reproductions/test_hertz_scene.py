# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The Hertz scene, the exact Hertz line contact and the measurements of a multiplier.

The numbers asserted come from outside the code under test: quadrature of the pressure
(SciPy), hand-computed moduli and radii, the circle equations, the Gmsh size field, the
interpolation error of a square-root edge on a uniform lattice, and UFL-assembled
moments.
"""

import dataclasses
import functools
import math

from mpi4py import MPI

import basix
import dolfinx
import numpy as np
import pytest
import ufl
from scipy.integrate import quad

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.compat import blocked_sub_element, geometry_dofmap
from paper.hertz.exact import Hertz, measure
from paper.hertz.scene import GRADING, TAGS, hertz

EPS = np.finfo(np.float64).eps

# ---------------------------------------------------------------------------------------
# The exact solution


@pytest.mark.parametrize(
    "data",
    [(1.0, 0.3, 1.0, 0.3, 1.0, math.inf, 1e-3), (200.0, 0.3, 70.0, 0.33, 1.0, 2.0, 0.5)],
)
def test_force_is_the_integral_of_the_pressure(data):
    exact = Hertz(*data)
    a, p0 = exact.a, exact.p0
    force, _ = quad(exact.pressure, -a, a, epsabs=0.0, epsrel=1e-13, limit=200)
    assert force == pytest.approx(exact.F, rel=1e-10)
    # Zero outside the contact: the same force over a wider interval.
    wider, _ = quad(exact.pressure, -2 * a, 2 * a, points=[-a, a], epsabs=0.0, limit=200)
    assert wider == pytest.approx(exact.F, rel=1e-10)
    assert p0 == pytest.approx(2.0 * exact.F / (math.pi * a), rel=4 * EPS)
    values = exact.pressure([0.0, 0.5 * a, -0.5 * a, a, -a, 1.5 * a, -3 * a])
    expected = [p0, p0 * math.sqrt(3) / 2, p0 * math.sqrt(3) / 2, 0, 0, 0, 0]
    np.testing.assert_allclose(values, expected, rtol=4 * EPS, atol=0.0)
    again = Hertz.for_half_width(a, *data[:6])
    assert again.F == pytest.approx(exact.F, rel=8 * EPS)
    assert Hertz.for_half_width(0.05, *data[:6]).a == pytest.approx(0.05, rel=8 * EPS)


def test_moduli_and_radii_by_hand():
    # 1/E* = (1 - 0.09)/200 + (1 - 0.1089)/70 = 0.00455 + 0.01273 = 0.01728; 1/R = 1 + 1/2.
    two = Hertz(200.0, 0.3, 70.0, 0.33, 1.0, 2.0, F=1.0)
    assert two.E_star == pytest.approx(1 / 0.01728, rel=1e-14)
    assert two.R == pytest.approx(2 / 3, rel=1e-14)
    # a = 2 sqrt(F R / (pi E*)) = 2 sqrt(0.01152 / pi), p0 = 2 / (pi a).
    assert two.a == pytest.approx(0.12111036105696768, rel=1e-14)
    assert two.p0 == pytest.approx(5.256526087542, rel=1e-12)
    # A cylinder on a block of the same material: R = R1, E* = E / (2 (1 - nu^2)).
    block = Hertz(1.0, 0.3, 1.0, 0.3, 0.5, math.inf, F=1.0)
    assert block.R == 0.5
    assert block.E_star == pytest.approx(1 / 1.82, rel=1e-14)


@pytest.mark.parametrize(
    "data",
    [
        (0.0, 0.3, 1.0, 0.3, 1.0, 1.0, 1.0),
        (1.0, 0.5, 1.0, 0.3, 1.0, 1.0, 1.0),
        (1.0, 0.3, 1.0, 0.3, math.inf, 1.0, 1.0),
        (1.0, 0.3, 1.0, 0.3, 1.0, -1.0, 1.0),
        (1.0, 0.3, 1.0, 0.3, 1.0, 1.0, -1.0),
    ],
)
def test_exact_rejects_bad_data(data):
    with pytest.raises(ValueError):
        Hertz(*data)


# ---------------------------------------------------------------------------------------
# The scene

A, R1 = 0.1, 1.0  # contact half-width and upper radius of the small scenes


@functools.cache
def _scene(cell, degree, lower_radius, n, comm="world"):
    """Scenes are collective: every rank builds them in the same order."""
    return hertz(
        MPI.COMM_WORLD if comm == "world" else MPI.COMM_SELF,
        R=R1,
        a=A,
        elements_across=n,
        cell=cell,
        geometry_degree=degree,
        lower_radius=lower_radius,
    )


SCENES = [
    ("triangle", 1, math.inf),
    ("quadrilateral", 1, math.inf),
    ("triangle", 2, math.inf),
    ("quadrilateral", 2, math.inf),
    ("triangle", 2, 2.0),
    ("quadrilateral", 1, 2.0),
]


def _facets(scene, name):
    """Geometry nodes ``(facets, nodes, 2)`` of the owned facets tagged ``name``."""
    mesh = scene.mesh
    owned = mesh.topology.index_map(1).size_local
    facets = scene.facet_tags.find(scene.tags[name])
    facets = facets[facets < owned]
    num_nodes = 1 + scene.geometry_degree
    if facets.size == 0:  # DOLFINx 0.9's entities_to_geometry divides by zero on no entity
        return np.empty((0, num_nodes, 2))
    mesh.topology.create_connectivity(1, 2)
    nodes = dolfinx.mesh.entities_to_geometry(mesh, 1, facets)
    return mesh.geometry.x[nodes][:, :, :2].reshape(facets.size, -1, 2)


def _count(comm, n):
    return comm.allreduce(int(n), op=MPI.SUM)


@pytest.mark.parametrize("case", SCENES)
def test_scene_tags_and_geometry(case):
    cell, degree, R2 = case
    scene = _scene(*case, 10)
    comm = scene.mesh.comm
    assert scene.tags == TAGS
    assert scene.mesh.topology.cell_name() == cell
    coordinate = blocked_sub_element(scene.mesh.ufl_domain().ufl_coordinate_element())
    assert coordinate.degree == degree
    assert scene.h == pytest.approx(2 * A / 10)
    counts = {name: _count(comm, len(_facets(scene, name))) for name in TAGS}
    assert all(counts[k] > 0 for k in TAGS if k != "lower_sides")
    assert (counts["lower_sides"] > 0) == math.isinf(R2)
    # Tagged facets are exterior facets of the body they belong to.
    mesh = scene.mesh
    mesh.topology.create_connectivity(1, 2)
    f_to_c = mesh.topology.connectivity(1, 2)
    body = np.zeros(mesh.topology.index_map(2).size_local + mesh.topology.index_map(2).num_ghosts)
    body[scene.cell_tags.indices] = scene.cell_tags.values
    for name, tag in TAGS.items():
        facets = scene.facet_tags.find(tag)
        cells = [f_to_c.links(f) for f in facets]
        assert all(len(c) == 1 for c in cells)
        owner = 1 if name in ("contactor", "upper_top", "upper_rest") else 2
        assert all(body[c[0]] == owner for c in cells)

    tol = 1e-12 * R1

    def on_circle(x, centre, radius):
        return np.all(np.abs(np.linalg.norm(x - centre, axis=-1) - radius) <= tol)

    upper = (0.0, R1)
    contactor, rest = _facets(scene, "contactor"), _facets(scene, "upper_rest")
    assert on_circle(contactor, upper, R1) and on_circle(rest, upper, R1)
    assert np.all(np.abs(contactor[..., 0]) <= 4 * A + tol)
    assert np.all(np.abs(rest[..., 0]) >= 4 * A - tol)
    assert np.all(_facets(scene, "upper_top")[..., 1] == R1)
    target, top_rest = _facets(scene, "target"), _facets(scene, "lower_top_rest")
    bottom = _facets(scene, "lower_bottom")
    assert np.all(np.abs(target[..., 0]) <= 5 * A + tol)
    assert np.all(np.abs(top_rest[..., 0]) >= 5 * A - tol)
    if math.isinf(R2):
        assert np.all(target[..., 1] == 0.0) and np.all(top_rest[..., 1] == 0.0)
        assert np.all(bottom[..., 1] == -scene.depth)
        assert np.all(np.abs(_facets(scene, "lower_sides")[..., 0]) == scene.width)
    else:
        lower = (0.0, -R2)
        assert on_circle(target, lower, R2) and on_circle(top_rest, lower, R2)
        assert np.all(bottom[..., 1] == -R2)
    if degree == 2:
        # The midpoint nodes are on the circle; the chord midpoints are not: curved cells.
        for x in (contactor, rest):
            assert on_circle(x[:, 2], upper, R1)
            chord = 0.5 * (x[:, 0] + x[:, 1])
            sagitta = np.linalg.norm(x[:, 1] - x[:, 0], axis=1) ** 2 / (8 * R1)
            gap = R1 - np.linalg.norm(chord - upper, axis=1)
            np.testing.assert_allclose(gap, sagitta, rtol=0.01)


@pytest.mark.parametrize("case", SCENES)
def test_scene_contact_point_and_bodies(case):
    scene = _scene(*case, 10)
    mesh, comm = scene.mesh, scene.mesh.comm
    x = mesh.geometry.x[:, :2]
    dofmap = geometry_dofmap(mesh)
    original = np.asarray(mesh.geometry.input_global_indices, dtype=np.int64)
    nodes = {}
    for body in (1, 2):
        cells = scene.cell_tags.find(body)
        local = np.unique(dofmap[cells])
        at_origin = local[np.linalg.norm(x[local], axis=1) == 0.0]
        nodes[body] = set(np.concatenate(comm.allgather(original[local])).tolist())
        origin = set(np.concatenate(comm.allgather(original[at_origin])).tolist())
        assert len(origin) == 1, f"body {body} has {len(origin)} nodes at (0, 0)"
    assert not nodes[1] & nodes[2], "the bodies share nodes"
    # Both contact surfaces have a vertex at the origin (two facets meet there).
    for name in ("contactor", "target"):
        facets = _facets(scene, name)[:, :2]
        assert _count(comm, np.sum(np.linalg.norm(facets, axis=-1) == 0.0)) == 2


def _size_field_cells(scene):
    r"""Triangles the size field asks for, :math:`\int dA / (\sqrt{3} s^2 / 4)`, bounded above.

    The field is :math:`s = h` within :math:`1.5 a` of the contact point, growing at
    :data:`GRADING` up to :math:`S`; the area beyond is counted at size :math:`S`.
    """
    h, a = scene.h, scene.a
    far = min(scene.R1, scene.R2, scene.width, scene.depth) / 8
    r_far = 1.5 * a + (far - h) / GRADING
    near, _ = quad(
        lambda r: 2 * np.pi * r / min(far, h + GRADING * max(0, r - 1.5 * a)) ** 2, 0, r_far
    )
    lower = 2 * scene.width * scene.depth if math.isinf(scene.R2) else np.pi * scene.R2**2 / 2
    area = np.pi * scene.R1**2 / 2 + lower
    return (near + area / far**2) / (np.sqrt(3) / 4), area


@pytest.mark.parametrize("case", SCENES)
def test_scene_element_sizes(case):
    scene = _scene(*case, 10)
    comm = scene.mesh.comm
    h = scene.h
    for name in ("contactor", "target"):
        x = _facets(scene, name)
        length = np.linalg.norm(x[:, 1] - x[:, 0], axis=1)
        near = np.abs(0.5 * (x[:, 0, 0] + x[:, 1, 0])) < scene.a
        across = _count(comm, near.sum())  # about 2a/h = 10 facets across the contact
        assert 0.5 * 2 * scene.a / h <= across <= 1.5 * 2 * scene.a / h
        assert np.all((0.5 * h <= length[near]) & (length[near] <= 1.5 * h)), name
    # Far away the cells reach R/8 (the block and the cylinders are at least R here).
    far = min(scene.R1, scene.R2, scene.width, scene.depth) / 8
    for name in ("upper_top", "lower_bottom"):
        x = _facets(scene, name)
        length = np.linalg.norm(x[:, 1] - x[:, 0], axis=1)
        assert np.all((0.5 * far <= length) & (length <= 1.5 * far)), name
    # The cell count follows the graded field, far below a uniform mesh of size h.
    cells = scene.mesh.topology.index_map(2).size_global
    bound, area = _size_field_cells(scene)
    assert cells <= 2 * bound
    assert cells < area / (np.sqrt(3) / 4 * h**2) / 5


@pytest.mark.parametrize("case", SCENES)
@pytest.mark.parametrize("n", [10, 20])
def test_scene_nodes_at_the_exact_edges(case, n):
    """The arc has nodes at x = +-a, spaced uniformly (h = 2a/n up to rounding) inside."""
    scene = _scene(*case, n)
    comm = scene.mesh.comm
    x = _facets(scene, "contactor")[:, :, 0].ravel()
    x = np.unique(np.concatenate(comm.allgather(x)))
    for edge in (-scene.a, 0.0, scene.a):
        assert np.min(np.abs(x - edge)) < 1e-12
    inside = np.sort(x[np.abs(x) <= scene.a + 1e-12])
    # Degree 2: midside nodes halve the spacing; the arc's x = R sin(theta) is
    # uniform in theta, which leaves a relative spread of (a/R)^2/2 in x.
    steps = np.diff(inside)
    assert np.ptp(steps) <= 0.01 * steps.mean()
    cells = (inside.size - 1) / scene.geometry_degree
    assert abs(cells - n) <= 0.25 * n


@pytest.mark.parametrize("case", SCENES)
def test_scene_cells_not_inverted(case):
    scene = _scene(*case, 10)
    mesh = scene.mesh
    cell = basix.CellType[mesh.topology.cell_name()]
    X = np.vstack([basix.make_quadrature(cell, 4)[0], basix.geometry(cell)])
    detJ = dolfinx.fem.Expression(ufl.JacobianDeterminant(mesh), X)
    cells = np.arange(mesh.topology.index_map(2).size_local, dtype=np.int32)
    d = detJ.eval(mesh, cells)
    assert np.all(d > 0.0)
    assert np.min(d.min(axis=1) / d.max(axis=1)) > 0.1


@pytest.mark.parametrize(
    "kwargs",
    [
        {"cell": "tetrahedron"},
        {"geometry_degree": 3},
        {"a": 0.25},
        {"a": 0.0},
        {"R": -1.0},
        {"elements_across": 0},
        {"elements_across": 2.5},
        {"size": (0.2, 1.0)},
        {"size": (1.0, 0.0)},
        {"lower_radius": 0.2},
        {"rank": 7},
    ],
)
def test_scene_rejects_bad_input(kwargs):
    with pytest.raises(ValueError):
        hertz(MPI.COMM_WORLD, **kwargs)


# ---------------------------------------------------------------------------------------
# Measurements of a multiplier

#: (cell, geometry degree, lower radius, displacement degree, multiplier)
PAIRS = {
    "P1": ("triangle", 1, math.inf, 1, None),
    "P1 quadrilateral cylinders": ("quadrilateral", 1, 2.0, 1, None),
    "P2 curved": ("triangle", 2, math.inf, 2, ("Lagrange", 2)),
}


@functools.cache
def _pair(name, n, comm="world"):
    cell, degree, R2, k, multiplier = PAIRS[name]
    scene = _scene(cell, degree, R2, n, comm)
    V = dolfinx.fem.functionspace(scene.mesh, ("Lagrange", k, (2,)))
    contactor = contact_surface(V, scene.facet_tags, scene.tags["contactor"])
    target = contact_surface(V, scene.facet_tags, scene.tags["target"])
    return scene, contact_pair(contactor, [target], multiplier=multiplier)


def _exact(scene):
    return Hertz.for_half_width(scene.a, 1.0, 0.3, 1.0, 0.3, scene.R1, scene.R2)


@functools.cache
def _interpolant(name, n, comm="world"):
    scene, pair = _pair(name, n, comm)
    exact = _exact(scene)
    lam = dolfinx.fem.Function(pair.Q)
    lam.interpolate(lambda x: exact.pressure(x[0]))
    return scene, pair, exact, lam, measure(lam, exact)


def _gathered_dofs(lam):
    Q = lam.function_space
    n = Q.dofmap.index_map.size_local
    x = np.concatenate(Q.mesh.comm.allgather(Q.tabulate_dof_coordinates()[:n, 0]))
    v = np.concatenate(Q.mesh.comm.allgather(lam.x.array[:n]))
    order = np.argsort(x)
    return x[order], v[order]


@functools.cache
def _edge_model(degree, phases=32, cells=200):
    r"""Interpolation error of :math:`g(t) = \sqrt{\max(t, 0)}` on the unit lattice.

    Lagrange interpolation of degree ``degree`` (equispaced nodes) on cells
    :math:`[j - \theta, j + 1 - \theta]`, over the phases :math:`\theta` of the edge in
    its cell. With :math:`t = u^2` every piece is a polynomial in :math:`u`, integrated
    exactly by Gauss-Legendre.

    Returns:
        The largest :math:`E = \int_{t > 0} (\Pi g - g)^2 dt` and the largest
        :math:`|M|`, :math:`M = \int (\Pi g - g) dt`, over the phases.
    """
    u, w = np.polynomial.legendre.leggauss(16)
    u, w = 0.5 * (u + 1), 0.5 * w
    loc = np.linspace(0.0, 1.0, degree + 1)
    E, M = [], []
    for theta in np.arange(phases) / phases:
        start = np.arange(cells) - theta  # cell starts
        values = np.sqrt(np.clip(start[:, None] + loc[None, :], 0, None))

        def interpolant(t, start=start, values=values):
            s = t - start[:, None]
            out = np.zeros_like(t)
            for i in range(degree + 1):
                li = np.prod(
                    [(s - loc[m]) / (loc[i] - loc[m]) for m in range(degree + 1) if m != i], axis=0
                )
                out += values[:, i, None] * li
            return out

        ua = np.sqrt(np.clip(start, 0, None))[:, None]
        ub = np.sqrt(start + 1)[:, None]
        uu = ua + (ub - ua) * u
        e = interpolant(uu**2) - uu
        jac = 2 * uu * (ub - ua) * w
        outside = start[0] + (0 - start[0]) * u  # t in [-theta, 0): g = 0
        m_out = np.sum(interpolant(np.broadcast_to(outside, (cells, u.size)))[0] * w) * theta
        E.append(np.sum(e**2 * jac))
        M.append(np.sum(e * jac) + m_out)
    return max(E), max(np.abs(M))


def _edge_spacing(scene):
    """Largest horizontal length of the contactor facets within 1.5a of the contact point."""
    x = _facets(scene, "contactor")
    mid = np.abs(0.5 * (x[:, 0, 0] + x[:, 1, 0]))
    local = np.max(np.abs(x[:, 1, 0] - x[:, 0, 0])[mid < 1.5 * scene.a], initial=0.0)
    return scene.mesh.comm.allreduce(local, op=MPI.MAX)


@pytest.mark.parametrize("n", [10, 20, 40])
@pytest.mark.parametrize("name", list(PAIRS))
def test_measure_interpolant(name, n):
    scene, pair, exact, lam, m = _interpolant(name, n)
    comm = scene.mesh.comm
    a = exact.a
    assert a == pytest.approx(scene.a, rel=8 * EPS)
    # The same numbers on every rank.
    values = dataclasses.astuple(m)
    assert all(other == values for other in comm.allgather(values))

    # p0: a node sits at x = 0, where the interpolant is p0 itself.
    assert abs(m.p0_error) <= 4 * EPS

    # a: lam^2 = p0^2 (1 - x^2/a^2) at the dofs is quadratic in x, so the secant through
    # the two outermost positive dofs x1, x2 (distances d1 > d2 from the edge) finds the
    # edge beyond a by d1 d2 / (x1 + x2): 0 <= a_meas - a <= the mean over both sides.
    x, v = _gathered_dofs(lam)
    positive = np.flatnonzero(v > 0)
    right = x[positive[-2:]]
    left = -x[positive[1::-1]]
    bound = np.mean([(a - s[0]) * (a - s[1]) / (s[0] + s[1]) for s in (right, left)])
    assert -4 * EPS * a <= m.a - a <= bound + 4 * EPS * a
    assert m.a_error == pytest.approx((m.a - a) / a, rel=1e-12, abs=EPS)

    # a_moment against the moments assembled by UFL (horizontal measure |dx/ds| ds).
    sub = pair.Q.mesh
    X, J = ufl.SpatialCoordinate(sub), ufl.Jacobian(sub)
    horizontal = abs(J[0, 0]) / ufl.sqrt(J[0, 0] ** 2 + J[1, 0] ** 2)
    dx = ufl.Measure("dx", domain=sub, metadata={"quadrature_degree": 12})
    m0, m2 = (
        comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form(lam * w * horizontal * dx)), op=MPI.SUM
        )
        for w in (1.0, X[0] ** 2)
    )
    assert m.a_moment == pytest.approx(2 * math.sqrt(m2 / m0), rel=1e-12)

    # The interpolation error of the square-root edges (the rest is O(h^2)): with lattice
    # spacing s, ||Pi p - p|| / ||p|| = (s/a) sqrt(3 E) and a_moment/a - 1 =
    # (6 sqrt(2)/pi) M (s/a)^(3/2) to leading order (_edge_model). The factors (1 + 2s/a)
    # and 2 cover the next order (relative s/a and sqrt(s/a)).
    s = _edge_spacing(scene)
    degree = pair.multiplier_degree
    E, M = _edge_model(degree)
    assert m.pressure_l2_error <= (s / a) * math.sqrt(3 * E) * (1 + 2 * s / a)
    assert abs(m.a_moment / a - 1) <= 2 * (6 * math.sqrt(2) / math.pi) * M * (s / a) ** 1.5


def _l2_reference(lam, exact):
    """The L2 error of a P1 multiplier on straight cells: piecewise linear in x (np.interp)."""
    x, v = _gathered_dofs(lam)
    a = exact.a
    inside = x[np.abs(x) < a]

    def error2(t):
        return (np.interp(t, x, v) - exact.pressure(t)) ** 2

    e2, _ = quad(error2, -a, a, points=inside, limit=4 * x.size, epsabs=0.0, epsrel=1e-12)
    return math.sqrt(e2 / (4 * a * exact.p0**2 / 3))


@pytest.mark.parametrize("n", [10, 40])
def test_measure_l2_error_against_quadpack(n):
    _, _, exact, lam, m = _interpolant("P1", n)
    assert m.pressure_l2_error == pytest.approx(_l2_reference(lam, exact), rel=1e-8)


@pytest.mark.parametrize("name", list(PAIRS))
def test_measure_converges(name):
    errors = [_interpolant(name, n)[-1].pressure_l2_error for n in (10, 20, 40)]
    # O(h): the square-root edges limit every degree to first order. The constant depends
    # on where the edge falls in its cell (a factor 4 for P1, 7 for P2 over the phases of
    # _edge_model), so only P1 decreases at every step on these meshes.
    assert errors[2] < errors[0] / 2
    if PAIRS[name][4] is None:
        assert errors[0] > errors[1] > errors[2]


@pytest.mark.parametrize("name", ["P1", "P2 curved"])
def test_measure_known_values(name):
    _, pair, exact, _, _ = _interpolant(name, 10)
    a, p0 = exact.a, exact.p0
    lam = dolfinx.fem.Function(pair.Q)
    m = measure(lam, exact)
    assert m.pressure_l2_error == pytest.approx(1.0, rel=1e-13)
    assert m.p0 == 0.0 and math.isnan(m.a) and math.isnan(m.a_moment)
    # lam = p0 on the contactor |x| <= 4a: int_{-a}^{a} (p0 - p)^2 dx = a p0^2 (10/3 - pi),
    # and with the horizontal measure the moment is that of a uniform load on [-4a, 4a].
    lam.x.array[:] = p0
    m = measure(lam, exact)
    assert m.pressure_l2_error == pytest.approx(math.sqrt((10 - 3 * math.pi) / 4), rel=1e-12)
    assert m.a_moment == pytest.approx(2 * math.sqrt((4 * a) ** 2 / 3), rel=1e-12)
    assert m.a == pytest.approx(4 * a, rel=1e-12)
    assert m.p0_error == pytest.approx(0.0, abs=4 * EPS)


def test_measure_independent_of_partition():
    """The mesh on COMM_WORLD and the same mesh on each rank alone give the same numbers.

    measure() computes from the gathered, sorted cells, so equal data give equal bits
    (observed); the tolerance leaves room for the interpolated data, whose dof
    coordinates may be pushed forward from another cell on another partition.
    """
    for name in ("P1", "P2 curved"):
        world = dataclasses.astuple(_interpolant(name, 20)[-1])
        alone = dataclasses.astuple(_interpolant(name, 20, "self")[-1])
        np.testing.assert_allclose(world, alone, rtol=1e-13, atol=0.0)


def test_measure_rejects():
    scene, pair, exact, lam, _ = _interpolant("P1", 10)
    wide = Hertz.for_half_width(5 * scene.a, 1.0, 0.3, 1.0, 0.3, scene.R1, scene.R2)
    with pytest.raises(ValueError, match="covers"):
        measure(lam, wide)
    V = dolfinx.fem.functionspace(pair.Q.mesh, ("Lagrange", 1, (2,)))
    with pytest.raises(ValueError, match="scalar"):
        measure(dolfinx.fem.Function(V), exact)

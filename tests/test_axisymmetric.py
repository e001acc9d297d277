# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Axisymmetric elasticity and contact with the ring weight 2 pi r, against closed forms.

The mesh lies in the (r, z) half-plane, r = x[0] >= 0. Every number asserted here comes
from a closed form: the uniform stress of a compressed cylinder, Lamé's thick cylinder,
the uniform contact pressure of the patch test, the press-fit pressure derived below, and
integrals of polynomials times 2 pi r.
"""

import math

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import (
    Material,
    contact_force,
    contact_pair,
    contact_surface,
    stress_function,
)
from dolfinx_contact_s2s.assemble import assemble_coupling, multiplier_mass
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper import scenes

comm = MPI.COMM_WORLD
EPS = np.finfo(float).eps
BOTTOM, RIGHT, TOP, LEFT = 1, 2, 3, 4
CELLS = {
    "triangle": dolfinx.mesh.CellType.triangle,
    "quadrilateral": dolfinx.mesh.CellType.quadrilateral,
}


def rectangle(corners, n, cell="triangle"):
    """A structured rectangle with facet tags bottom 1, right 2, top 3, left 4."""
    (x0, y0), (x1, y1) = corners
    mesh = dolfinx.mesh.create_rectangle(comm, [list(corners[0]), list(corners[1])], n, CELLS[cell])
    fdim = 1
    mesh.topology.create_connectivity(fdim, 2)
    found = []
    for tag, where in (
        (BOTTOM, lambda x: np.isclose(x[1], y0)),
        (RIGHT, lambda x: np.isclose(x[0], x1)),
        (TOP, lambda x: np.isclose(x[1], y1)),
        (LEFT, lambda x: np.isclose(x[0], x0)),
    ):
        facets = dolfinx.mesh.locate_entities_boundary(mesh, fdim, where)
        found.append((facets, np.full(facets.size, tag, dtype=np.int32)))
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([v for _, v in found])
    order = np.argsort(facets)
    return mesh, dolfinx.mesh.meshtags(mesh, fdim, facets[order], values[order])


def fix(V, component, tags, facet_tags, value=0.0):
    """u[component] = value on the facets of ``tags``."""
    facets = np.concatenate([facet_tags.find(t) for t in tags])
    dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 1, facets)
    return dolfinx.fem.dirichletbc(value, dofs, V.sub(component))


def solve_linear(V, a, L, bcs):
    """Direct solve of one body's problem (no contact)."""
    a, L = dolfinx.fem.form(a), dolfinx.fem.form(L)
    A = dolfinx.fem.petsc.assemble_matrix(a, bcs=bcs)
    A.assemble()
    b = dolfinx.fem.petsc.assemble_vector(L)
    dolfinx.fem.petsc.apply_lifting(b, [a], bcs=[bcs])
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    dolfinx.fem.petsc.set_bc(b, bcs)
    u = dolfinx.fem.Function(V)
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.solve(b, u.x.petsc_vec)
    u.x.scatter_forward()
    for obj in (ksp, A, b):
        obj.destroy()
    return u


def total(form):
    """A scalar form summed over all ranks."""
    return comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(form)), op=MPI.SUM)


# --- the forms --------------------------------------------------------------------------


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
@pytest.mark.parametrize("degree", [1, 2])
def test_compressed_cylinder_is_exact(degree, cell):
    """A solid cylinder r <= R, 0 <= z <= H under axial pressure p on its top.

    Exact: sigma_zz = -p, the other stresses 0; u_z = -p z / E, u_r = nu p r / E: linear,
    so the Galerkin solution is exact to round-off with P1 and P2; the hoop stress is 0
    and the reaction at the base is the total force p pi R^2 (the forms carry 2 pi).
    """
    E, nu, p, R, H = 2.0, 0.3, 0.7, 1.0, 2.0
    mesh, facets = rectangle(((0.0, 0.0), (R, H)), (3, 5), cell)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    material = Material(E, nu, plane="axisymmetric")
    a, _, v = material.forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
    w = material.weight(mesh)
    L = -p * v[1] * w * ds(TOP)
    u = solve_linear(V, a, L, [fix(V, 0, [LEFT], facets), fix(V, 1, [BOTTOM], facets)])
    x = V.tabulate_dof_coordinates()
    exact = np.stack([nu * p * x[:, 0] / E, -p * x[:, 1] / E], axis=1)
    error = np.max(np.abs(u.x.array.reshape(-1, 2) - exact), initial=0.0)
    assert comm.allreduce(error, op=MPI.MAX) < 100 * EPS * p * H / E
    # The stress, hoop included (at the axis too), by stress_function.
    s = stress_function(u, material)
    values = s.x.array.reshape(-1, 3, 3)
    expected = np.zeros((3, 3))
    expected[1, 1] = -p
    local = np.max(np.abs(values - expected), initial=0.0)
    assert comm.allreduce(local, op=MPI.MAX) < 1e3 * EPS * p
    # The base's reaction, the traction sigma n integrated with 2 pi r: p pi R^2.
    n = ufl.FacetNormal(mesh)
    force = total(ufl.dot(material.sigma(u), ufl.as_vector([n[0], n[1], 0.0]))[1] * w * ds(BOTTOM))
    assert abs(force - p * math.pi * R**2) < 1e-10 * p * math.pi * R**2


def lame_error(degree, n):
    """Relative L2 error (weighted by r) of u_r on Lamé's thick cylinder with n x 2 cells."""
    E, nu, p, a, b = 1.0, 0.3, 1.0, 1.0, 2.0
    mesh, facets = rectangle(((a, 0.0), (b, 0.25)), (n, 2), "triangle")
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    material = Material(E, nu, plane="axisymmetric")
    form, _, v = material.forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
    w = material.weight(mesh)
    L = p * v[0] * w * ds(LEFT)  # pressure on the bore r = a: traction +p e_r
    u = solve_linear(V, form, L, [fix(V, 1, [BOTTOM, TOP], facets)])
    r = ufl.SpatialCoordinate(mesh)[0]
    # Plane strain (u_z = 0 on both ends): u_r = (1 + nu) p a^2 / (E (b^2 - a^2))
    # * ((1 - 2 nu) r + b^2 / r).
    exact = (1 + nu) * p * a**2 / (E * (b**2 - a**2)) * ((1 - 2 * nu) * r + b**2 / r)
    dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 8})
    # The best the elements can do: the nodal interpolant of the exact u_r.
    ui = dolfinx.fem.Function(V)
    coefficient = (1 + nu) * p * a**2 / (E * (b**2 - a**2))
    ui.sub(0).interpolate(lambda x: coefficient * ((1 - 2 * nu) * x[0] + b**2 / x[0]))
    norm = math.sqrt(total(exact**2 * r * dx))
    error = math.sqrt(total((u[0] - exact) ** 2 * r * dx)) / norm
    interpolation = math.sqrt(total((ui[0] - exact) ** 2 * r * dx)) / norm
    return error, interpolation


@pytest.mark.parametrize("degree", [1, 2])
def test_lame_thick_cylinder(degree):
    """Lamé's thick cylinder a = 1 <= r <= b = 2 under internal pressure, plane strain.

    The error in L2 falls as h^(k+1) (the exact u_r = A r + B / r is smooth); asserted:
    the observed rate over one halving within 0.3 of k + 1, and the error on the finer
    mesh below C h^(k+1) with C = 0.05 (P1) and 0.01 (P2), a bound of the interpolation
    error of B / r (|u''| / |u| <= 2 / a^2 on [1, 2]) with a margin.
    """
    (coarse, _), (fine, interpolation) = lame_error(degree, 4), lame_error(degree, 8)
    rate = math.log2(coarse / fine)
    assert abs(rate - (degree + 1)) < 0.3, (coarse, fine, rate)
    assert fine < 3 * interpolation, (fine, interpolation)


# --- the coupling against UFL and closed forms --------------------------------------------


def _dof_coordinates(V):
    imap = V.dofmap.index_map
    x = V.tabulate_dof_coordinates()[: imap.size_local, :2]
    out = np.zeros((imap.size_global, 2))
    for start, xs in comm.allgather((imap.local_range[0], x)):
        out[start : start + xs.shape[0]] = xs
    return out


@pytest.mark.parametrize("degree", [1, 2])
def test_coupling_matches_ufl_with_ring_weight(degree):
    """On matching meshes B_C = -int mu (v . n_C) 2 pi r ds (UFL), and closed forms.

    The contactor is the upper block's bottom, r in [0, 1], touching the axis: the sum
    of the multiplier mass is int 2 pi r dr = pi, and a rigid motion e_z of the
    contactor gives the rows' sum int 2 pi r (e_z . N) = pi (N = e_z there).
    """
    scene = scenes.patch_test(comm, (6, 6), cell="triangle", gap=0.02)
    spaces = {
        n: dolfinx.fem.functionspace(b.mesh, ("Lagrange", degree, (2,)))
        for n, b in scene.bodies.items()
    }
    surf = {n: contact_surface(spaces[n], b.facet_tags, b.contact) for n, b in scene.bodies.items()}
    pair = contact_pair(surf["upper"], surf["lower"], axisymmetric=True)
    op = assemble_coupling(pair)
    Bc = gather_dense(op.block(spaces["upper"]))
    G = np.concatenate(comm.allgather(op.G.array_r.copy()))
    op.destroy()
    upper = scene.upper
    W = dolfinx.fem.functionspace(upper.mesh, ("Lagrange", degree))
    mu, u = ufl.TestFunction(W), ufl.TrialFunction(spaces["upper"])
    ds = ufl.Measure("ds", domain=upper.mesh, subdomain_data=upper.facet_tags)
    r = ufl.SpatialCoordinate(upper.mesh)[0]
    weight = 2 * math.pi * r
    A = dolfinx.fem.petsc.assemble_matrix(
        dolfinx.fem.form(-mu * ufl.dot(u, ufl.FacetNormal(upper.mesh)) * weight * ds(upper.contact))
    )
    A.assemble()
    ref = gather_dense(A)
    A.destroy()
    xq, xw = _dof_coordinates(pair.Q), _dof_coordinates(W)
    d = np.linalg.norm(xq[:, None] - xw[None], axis=2)
    rows = np.argmin(d, axis=1)
    assert np.max(d[np.arange(rows.size), rows]) < 1e-10
    scale = np.max(np.abs(ref))
    assert np.max(np.abs(Bc - ref[rows])) < 100 * EPS * scale
    ez = np.tile([0.0, 1.0], Bc.shape[1] // 2)
    assert abs(np.sum(Bc @ ez) - math.pi) < 100 * EPS * math.pi
    # G = int mu g0 2 pi r with g0 = +0.02 (open, along N = e_z): sum G = 0.02 pi.
    assert abs(np.sum(G) - 0.02 * math.pi) < 1e-10 * 0.02 * math.pi
    P = multiplier_mass(pair)
    ones = P.createVecRight()
    ones.set(1.0)
    y = P.createVecLeft()
    P.mult(ones, y)
    assert abs(y.sum() - math.pi) < 100 * EPS * math.pi
    for obj in (P, ones, y):
        obj.destroy()


# --- contact: the patch test and the press-fit ---------------------------------------------

MATERIALS = {
    "lower": Material(1.0, 0.3, "axisymmetric"),
    "upper": Material(3.0, 0.2, "axisymmetric"),
}


def patch_problem(
    degree, cell, shift, kind, p=0.6, elements=(7, 5), plane="axisymmetric", **options
):
    """Two coaxial cylinders pressed by p on the upper's top; the lower's base on u_z = 0.

    ``shift`` moves both radially (0: solid cylinders touching the axis, which carries
    u_r = 0; > 0: hollow cylinders, no condition in r: the hoop stiffness holds them).
    """
    scene = scenes.patch_test(comm, elements, cell=cell)
    a, L, bcs, surf = [], [], [], {}
    for name, body in scene.bodies.items():
        body.mesh.geometry.x[:, 0] += shift
        V = dolfinx.fem.functionspace(body.mesh, ("Lagrange", degree, (2,)))
        material = Material(MATERIALS[name].E, MATERIALS[name].nu, plane)
        form, _, v = material.forms(V)
        ds = ufl.Measure("ds", domain=body.mesh, subdomain_data=body.facet_tags)
        a.append(form)
        load = dolfinx.fem.Constant(body.mesh, -p if name == "upper" else 0.0)
        L.append(load * v[1] * material.weight(body.mesh) * ds(scenes.TOP))
        if shift == 0.0:
            bcs.append(fix(V, 0, [scenes.LEFT], body.facet_tags))
        if name == "lower":
            bcs.append(fix(V, 1, [scenes.BOTTOM], body.facet_tags))
        surf[name] = contact_surface(V, body.facet_tags, body.contact)
    options.setdefault("axisymmetric", True)
    pair = contact_pair(surf["upper"], surf["lower"], **options)
    cls = LinearContactProblem if kind == "tied" else UnilateralContactProblem
    return cls(a, L, [pair], bcs, petsc_options_prefix=f"axi_{kind}_")


@pytest.mark.parametrize("kind", ["tied", "unilateral"])
@pytest.mark.parametrize(
    ("degree", "cell", "shift"),
    [(1, "triangle", 0.0), (2, "triangle", 0.0), (1, "quadrilateral", 0.0), (2, "triangle", 0.5)],
)
def test_axisymmetric_patch_test(degree, cell, shift, kind):
    """Non-matching plane contact face of two coaxial cylinders: lambda = p everywhere.

    The uniform state sigma_zz = -p is exact in both bodies (u linear), so composite
    segment-to-segment transmits lambda = p to round-off (Eq. 36) with the 2 pi r weight,
    and the total contact force on the lower body is p pi (R_o^2 - R_i^2).
    """
    p = 0.6
    with patch_problem(degree, cell, shift, kind, p) as problem:
        (_, _), (lam,) = problem.solve()
        n = lam.function_space.dofmap.index_map.size_local
        error = np.max(np.abs(lam.x.array[:n] - p), initial=0.0)
        assert comm.allreduce(error, op=MPI.MAX) < 1e-10 * p
        forces = problem.contact_forces()
        V = problem.spaces[0]
        bs = V.dofmap.index_map_bs
        owned = forces[0].x.array[: V.dofmap.index_map.size_local * bs].reshape(-1, 2)
        fz = comm.allreduce(float(owned[:, 1].sum()), op=MPI.SUM)
        area = math.pi * ((1 + shift) ** 2 - shift**2)
        assert abs(abs(fz) - p * area) < 1e-10 * p * area
        # The pair's resultant and its ring-weighted pressure integral (post-processing).
        resultant = contact_force(problem.pairs[0], lam)
        assert abs(resultant.contactor[1] - p * area) < 1e-10 * p * area
        assert abs(resultant.contactor[0]) < 1e-10 * p * area
        assert abs(resultant.pressure_integral - p * area) < 1e-10 * p * area


@pytest.mark.parametrize(
    "options",
    [
        {"quadrature": "composite-newton-cotes"},
        {"method": "intermediate-surface"},
        {"method": "node-to-segment", "weight": "tributary"},
        {"method": "node-to-segment", "weight": "unit"},
    ],
)
def test_other_discretizations_on_matching_meshes(options):
    """P1 on matching meshes (6 facets of h = 1/6 on r in [0, 1]), tied, p = 0.6.

    The default rule has one more point for the weight r (one Gauss point, exact for a
    DG0 multiplier in the plane, is not with r). Pressures: lambda = p; unit weights
    make lambda the node's total ring force, p int 2 pi r N_i dr: p 2 pi h^2 / 6 on the
    axis, p 2 pi h r_i inside, p 2 pi (h / 2 - h^2 / 6) at r = 1.
    """
    p, h = 0.6, 1 / 6
    with patch_problem(1, "triangle", 0.0, "tied", p, (6, 6), **options) as problem:
        (_, _), (lam,) = problem.solve()
        Q = lam.function_space
        n = Q.dofmap.index_map.size_local
        values = lam.x.array[:n]
        if options.get("weight") == "unit":
            r = Q.tabulate_dof_coordinates()[:n, 0]
            inside = 2 * math.pi * h * r
            on_axis = 2 * math.pi * h**2 / 6
            outside = 2 * math.pi * (h / 2 - h**2 / 6)
            expected = p * np.where(r < h / 2, on_axis, np.where(r > 1 - h / 2, outside, inside))
        else:
            expected = np.full(n, p)
        error = np.max(np.abs(values - expected), initial=0.0)
        assert comm.allreduce(error, op=MPI.MAX) < 1e-10 * p


def press_fit(degree, kind, b=1.0, c=2.0, delta=1e-3, E=1.0, nu=0.3):
    """A ring (bore a = b - delta, outer c) on a solid shaft of radius b: the pressure."""
    H = 0.5
    a_in = b - delta
    shaft, shaft_tags = rectangle(((0.0, 0.0), (b, H)), (3, 5))
    ring, ring_tags = rectangle(((a_in, 0.0), (c, H)), (8, 3))
    material = Material(E, nu, "axisymmetric")
    forms, L, bcs, surf = [], [], [], {}
    for name, mesh, tags, contact in (
        ("shaft", shaft, shaft_tags, RIGHT),
        ("ring", ring, ring_tags, LEFT),
    ):
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
        form, _, v = material.forms(V)
        forms.append(form)
        L.append(dolfinx.fem.Constant(mesh, 0.0) * v[0] * material.weight(mesh) * ufl.ds)
        bcs.append(fix(V, 1, [BOTTOM, TOP], tags))
        if name == "shaft":
            bcs.append(fix(V, 0, [LEFT], tags))
        surf[name] = contact_surface(V, tags, contact)
    pair = contact_pair(surf["ring"], surf["shaft"], axisymmetric=True, search_radius=0.5)
    cls = LinearContactProblem if kind == "tied" else UnilateralContactProblem
    with cls(forms, L, [pair], bcs, petsc_options_prefix=f"fit_{kind}_") as problem:
        (_, _), (lam,) = problem.solve()
        n = lam.function_space.dofmap.index_map.size_local
        values = lam.x.array[:n]
        lo = comm.allreduce(float(np.min(values, initial=np.inf)), op=MPI.MIN)
        hi = comm.allreduce(float(np.max(values, initial=-np.inf)), op=MPI.MAX)
    return lo, hi


@pytest.mark.parametrize("kind", ["tied", "unilateral"])
def test_press_fit_lame(kind):
    r"""Ring (bore a = b - delta, outer radius c) on a solid shaft (radius b), plane strain.

    Both ends carry u_z = 0, so eps_z = 0 and Lamé's plane-strain solution is exact. With
    p the pressure on the ring's bore (the contactor, radius a), the shaft's surface
    (radius b) carries p a / b (the same total ring force). Plane strain, same E and nu:

    - shaft (solid, uniform state, sigma_rr = sigma_tt = -q, sigma_zz = -2 nu q):
      u_s(b) = -q b (1 + nu)(1 - 2 nu) / E with q = p a / b;
    - ring under bore pressure p: u_r(a) = (1 + nu) p a ((1 - 2 nu) a^2 + c^2)
      / (E (c^2 - a^2));
    - contact (the gap g0 = a - b = -delta along N = e_r closes): u_r(a) - u_s(b) = delta,

    so p (1 + nu) a / E [((1 - 2 nu) a^2 + c^2) / (c^2 - a^2) + 1 - 2 nu] = delta, i.e.

    .. math:: p = \frac{E\,\delta\,(c^2 - a^2)}{2 (1 - \nu^2)\, a\, c^2},

    the classic press-fit formula with E / (1 - nu^2). The pressure is uniform along z;
    with P2 within 1% of it at every multiplier.
    """
    b, c, delta, E, nu = 1.0, 2.0, 1e-3, 1.0, 0.3
    a = b - delta
    exact = E * delta * (c**2 - a**2) / (2 * (1 - nu**2) * a * c**2)
    lo, hi = press_fit(2, kind, b, c, delta, E, nu)
    assert abs(lo - exact) < 0.01 * exact and abs(hi - exact) < 0.01 * exact, (lo, hi, exact)


# --- bad input ----------------------------------------------------------------------------


def raises_everywhere(pattern, call, *args, **kwargs):
    """``call`` raises ValueError matching ``pattern`` on every rank, with one message."""
    message = None
    try:
        call(*args, **kwargs)
    except ValueError as e:
        message = str(e)
    messages = comm.allgather(message)
    assert all(m is not None for m in messages), messages
    assert len(set(messages)) == 1, messages
    assert pattern in messages[0], messages[0]


def test_mesh_behind_the_axis():
    """A mesh with nodes at r < 0: Material.forms and an axisymmetric pair refuse it."""
    mesh, tags = rectangle(((-0.3, 0.0), (1.0, 0.5)), (4, 2))
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    raises_everywhere("node(s) at r = x[0] < 0", Material(plane="axisymmetric").forms, V)
    Material(plane="strain").forms(V)  # plane models do not care
    other, other_tags = rectangle(((0.0, 0.5), (1.0, 1.0)), (3, 2))
    W = dolfinx.fem.functionspace(other, ("Lagrange", 1, (2,)))
    contactor = contact_surface(W, other_tags, BOTTOM)
    # The target's mesh lies partly at r < 0, its contact surface (the top) too: it crosses.
    target = contact_surface(V, tags, TOP)
    raises_everywhere("crosses the axis", contact_pair, contactor, target, axisymmetric=True)
    # Its right side lies at r = 1 > 0: the surface is fine, the mesh is not.
    right = contact_surface(V, tags, RIGHT)
    raises_everywhere("node(s) at r = x[0] < 0", contact_pair, contactor, right, axisymmetric=True)


@pytest.mark.parametrize(("plane", "axisymmetric"), [("axisymmetric", False), ("strain", True)])
def test_ring_weight_contradicting_the_forms(plane, axisymmetric):
    """A pair whose ``axisymmetric`` contradicts its bodies' forms is named, not solved.

    Solved, the multiplier would be the pressure times (or over) 2 pi r: a plausible
    answer, wrong by a factor. The forms tell: an axisymmetric stiffness stores energy
    in a radial translation (the hoop strain u_r / r), a plane one in none.
    """

    def solve():
        with patch_problem(2, "triangle", 0.0, "tied", plane=plane, axisymmetric=axisymmetric) as p:
            p.solve()

    raises_everywhere(f"its pair has axisymmetric={axisymmetric}", solve)


def test_surface_on_the_axis():
    """A contact tag on the axis itself (r = 0 along the facets) has no area: refused."""
    mesh, tags = rectangle(((0.0, 0.0), (1.0, 0.5)), (4, 2))
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    other, other_tags = rectangle(((0.0, 0.5), (1.0, 1.0)), (3, 2))
    W = dolfinx.fem.functionspace(other, ("Lagrange", 1, (2,)))
    on_axis = contact_surface(V, tags, LEFT)
    raises_everywhere(
        "on the axis r = 0",
        contact_pair,
        contact_surface(W, other_tags, BOTTOM),
        on_axis,
        axisymmetric=True,
    )

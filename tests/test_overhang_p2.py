# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The contact patch test when the target ends inside a contactor facet (2D, P1 and P2).

The upper block :math:`[s, s + W] \times [H, 2H]` of :func:`paper.scenes_multi.overhang`
hangs over the end :math:`x = W` of the lower block; with :math:`s = 0.2` and 8 upper
elements the target's end cuts the contactor facet :math:`[a, b] = [0.95, 1.075]`,
covering the fraction :math:`f = 0.4` of it away from :math:`b` (6 upper elements:
:math:`f = 0.8`). To keep the exact solution of the patch test (:math:`\sigma =
\mathrm{diag}(0, -p)`, :math:`\lambda = p`), the parts that touch nothing carry the
traction the missing body would give: :math:`+p` on the upper bottom beyond :math:`W`
(upwards) and :math:`p` on the lower top before :math:`s` (downwards). On the cut facet
that traction acts on :math:`[W, b]` only; it is replaced by its :math:`L^2` projection
onto the facet polynomials of the displacement degree, which has the same moments
against every test function there: the load vector is exact.

Every multiplier whose support meets :math:`[s, W]` must stay, and equal :math:`p`. A
P2 vertex function :math:`\phi(\xi) = \xi(2\xi - 1)` (:math:`\xi = 1` at :math:`b`)
integrates to :math:`f^2(2f/3 - 1/2) \le 0` over the covered part for :math:`f \le
3/4`: measured by :math:`\int \mu_k` (as it was on edges), the multiplier at
:math:`b` would be called uncovered and pinned to zero, and the patch test fail. On
quadratic edges the coverage is :math:`\int \mu_k^2`
(:attr:`~dolfinx_contact_s2s.pair.ContactPair.squared_coverage`); tied contact keeps the
multiplier (unilateral contact leaves it out:
:attr:`~dolfinx_contact_s2s.assemble.CouplingOperator.unsigned`).
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.problem import LinearContactProblem
from paper.scenes_multi import overhang

EPS = np.finfo(np.float64).eps

#: Load of the patch test; not 1, so that a missing factor p shows.
PRESSURE = 0.75

#: (E, nu) by cell tag: lower 1, upper 2 (the exact stress ignores them).
MATERIALS = {1: (1.0, 0.3), 2: (3.0, 0.2)}

W, H, SHIFT, LOWER_ELEMENTS = 1.0, 0.5, 0.2, 10

#: Facet tags of the loads (the contact surfaces keep the scene's tags).
TOP, BEYOND, CUT, BEFORE = 901, 902, 903, 904


def sigma(u, mu, lmbda):
    eps = ufl.sym(ufl.grad(u))
    return 2 * mu * eps + lmbda * ufl.tr(eps) * ufl.Identity(2)


def projection(f: float, degree: int) -> np.ndarray:
    r"""Monomial coefficients of :math:`q(t)` with the moments of :math:`1[t > f]` on [0, 1].

    :math:`\int_0^1 q\, t^j = \int_f^1 t^j` for :math:`j \le` ``degree``.
    """
    n = degree + 1
    gram = np.array([[1.0 / (i + j + 1) for j in range(n)] for i in range(n)])
    moments = np.array([(1.0 - f ** (i + 1)) / (i + 1) for i in range(n)])
    return np.linalg.solve(gram, moments)


def conditioning(f: float, degree: int) -> float:
    r"""How much a cut facet amplifies round-off in its multipliers, relative to a whole one.

    The ratio of the condition numbers of the mass matrix of the facet's Lagrange basis
    over :math:`[0, f]` and over :math:`[0, 1]`: the pressure on the covered part
    determines the multipliers through it (:math:`f = 0.4`, P2: about 250).
    """
    nodes = np.linspace(0.0, 1.0, degree + 1)
    x, w = np.polynomial.legendre.leggauss(degree + 2)

    def cond(length: float) -> float:
        t = 0.5 * length * (x + 1.0)
        basis = np.array(
            [np.prod([(t - m) / (n - m) for m in nodes if m != n], axis=0) for n in nodes]
        )
        return float(np.linalg.cond((basis * (0.5 * length * w)) @ basis.T))

    return cond(f) / cond(1.0)


def lame(part):
    Q0 = dolfinx.fem.functionspace(part.mesh, ("Discontinuous Lagrange", 0))
    mu, lmbda = dolfinx.fem.Function(Q0), dolfinx.fem.Function(Q0)
    for tag in np.unique(part.cell_tags.values):
        m, lm = Material(*MATERIALS[int(tag)]).lame
        dofs = Q0.dofmap.list[part.cell_tags.find(tag)].ravel()
        mu.x.array[dofs], lmbda.x.array[dofs] = m, lm
    mu.x.scatter_forward()
    lmbda.x.scatter_forward()
    return mu, lmbda


def load_tags(scene, part, a: float, b: float):
    """Facet tags of the loaded top, the parts touching nothing and the cut facet."""
    facets, values = [], []

    def add(side_facets, keep, tag):
        facets.append(side_facets[keep])
        values.append(np.full(int(np.count_nonzero(keep)), tag, dtype=np.int32))

    if "upper" in part.blocks:
        top = part.facet_tags.find(scene.tag("upper", "top"))
        add(top, np.ones(top.size, dtype=bool), TOP)
        bottom = part.facet_tags.find(scene.tag("upper", "bottom"))
        x = dolfinx.mesh.compute_midpoints(part.mesh, 1, bottom)[:, 0]
        add(bottom, x > b, BEYOND)
        add(bottom, (x > a) & (x < b), CUT)
    if "lower" in part.blocks:
        top = part.facet_tags.find(scene.tag("lower", "top"))
        x = dolfinx.mesh.compute_midpoints(part.mesh, 1, top)[:, 0]
        add(top, x < SHIFT, BEFORE)
    f = np.concatenate(facets).astype(np.int32)
    v = np.concatenate(values)
    order = np.argsort(f)
    return dolfinx.mesh.meshtags(part.mesh, 1, f[order], v[order])


def overhang_model(degree: int, upper_elements: int, multiplier=None):
    """The supported overhang's forms, pair, conditions and the cut facet's data."""
    comm = MPI.COMM_WORLD
    p = PRESSURE
    scene = overhang(
        comm, (LOWER_ELEMENTS, upper_elements), SHIFT, arrangement="separate", width=W, height=H
    )
    h = W / upper_elements
    a = SHIFT + np.floor((W - SHIFT) / h) * h
    b = a + h
    f = (W - a) / h
    coefficients = projection(f, degree)
    V, forms_a, forms_L, lames = {}, [], [], {}
    for name, part in scene.parts.items():
        V[name] = Vi = dolfinx.fem.functionspace(part.mesh, ("Lagrange", degree, (2,)))
        lames[name] = mu, lmbda = lame(part)
        u, v = ufl.TrialFunction(Vi), ufl.TestFunction(Vi)
        ds = ufl.Measure("ds", domain=part.mesh, subdomain_data=load_tags(scene, part, a, b))
        L = ufl.inner(dolfinx.fem.Constant(part.mesh, np.zeros(2)), v) * ufl.dx
        if "upper" in part.blocks:
            t = (ufl.SpatialCoordinate(part.mesh)[0] - a) / h
            q = sum(float(c) * t**i for i, c in enumerate(coefficients))
            L += -p * v[1] * ds(TOP) + p * v[1] * ds(BEYOND) + p * q * v[1] * ds(CUT)
        else:
            L += -p * v[1] * ds(BEFORE)
        forms_a.append(ufl.inner(sigma(u, mu, lmbda), ufl.sym(ufl.grad(v))) * ufl.dx)
        forms_L.append(L)
    bcs = []
    for component, sides in enumerate((scene.fixed_x, scene.fixed_y)):
        for block, side in sides:
            part = scene.part(block)
            Vi = V[part.name]
            facets = part.facet_tags.find(scene.tag(block, side))
            dofs = dolfinx.fem.locate_dofs_topological(Vi.sub(component), 1, facets)
            zero = dolfinx.default_scalar_type(0)
            bcs.append(dolfinx.fem.dirichletbc(zero, dofs, Vi.sub(component)))

    upper, lower = scene.part("upper"), scene.part("lower")
    pair = contact_pair(
        contact_surface(V[upper.name], upper.facet_tags, scene.tag("upper", "bottom")),
        contact_surface(V[lower.name], lower.facet_tags, scene.tag("lower", "top")),
        multiplier=multiplier,
    )
    return V, forms_a, forms_L, pair, bcs, lames, (h, b, f)


def overhang_problem(upper_elements: int, degree: int = 1, multiplier=None):
    """The overhang patch test as a tied problem (not yet solved)."""
    _, a, L, pair, bcs, _, _ = overhang_model(degree, upper_elements, multiplier)
    return LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="ovp2_problem_")


def overhang_patch(degree: int, upper_elements: int, multiplier=None) -> dict:
    """Solve the supported overhang; the multipliers pinned and the patch-test errors."""
    comm = MPI.COMM_WORLD
    p = PRESSURE
    V, forms_a, forms_L, pair, bcs, lames, (h, b, f) = overhang_model(
        degree, upper_elements, multiplier
    )
    unknowns = sum(Vi.dofmap.index_map.size_global * 2 for Vi in V.values())
    unknowns += pair.Q.dofmap.index_map.size_global
    tol = min(1e-10, 100 * EPS * unknowns)
    with LinearContactProblem(forms_a, forms_L, [pair], bcs, petsc_options_prefix="ovp2_") as pb:
        us, (lam,) = pb.solve()
        Q = pair.Q
        n = Q.dofmap.index_map.size_local
        owned = np.arange(n, dtype=np.int32)
        x = np.concatenate(comm.allgather(Q.tabulate_dof_coordinates()[:n, 0]))
        dofs = np.concatenate(comm.allgather(Q.dofmap.index_map.local_to_global(owned)))
        values = np.concatenate(comm.allgather(lam.x.array[:n]))
        uncovered = np.sort(pb.operators[0].uncovered)
        e_sig = 0.0
        for name, ui in zip(V, us, strict=True):
            T = dolfinx.fem.functionspace(ui.function_space.mesh, ("DG", degree, (2, 2)))
            points = T.element.interpolation_points
            s = dolfinx.fem.Function(T)
            s.interpolate(
                dolfinx.fem.Expression(
                    sigma(ui, *lames[name]), points() if callable(points) else points
                )
            )
            m = T.dofmap.index_map.size_local * T.dofmap.index_map_bs
            error = np.abs(s.x.array[:m].reshape(-1, 2, 2) - np.array([[0.0, 0.0], [0.0, -p]]))
            e_sig = max(e_sig, comm.allreduce(np.max(error, initial=0.0) / p, op=MPI.MAX))
    tiny = 1e-9 * h
    # The multipliers whose support lies beyond b face nothing; all others touch [s, W].
    beyond = x > b + tiny
    return {
        "fraction": f,
        "b": b,
        "pinned": np.sort(x[np.isin(dofs, uncovered)]),
        "beyond": np.sort(x[beyond]),
        "e_lam": float(np.max(np.abs(values[~beyond] - p)) / p),
        "lam_b": float(values[np.argmin(np.abs(x - b))]),
        "e_sig": e_sig,
        "tol": tol,
        # The multipliers of the cut facet take the round-off amplified by its conditioning.
        "tol_lam": tol * max(1.0, conditioning(f, degree)),
    }


def check(result: dict) -> None:
    """The multipliers beyond b pinned, no other; then the patch test to round-off."""
    pinned, beyond = result["pinned"], result["beyond"]
    assert np.array_equal(pinned, beyond), (
        f"pinned multipliers at x = {pinned}, expected {beyond} (the target's end cuts "
        f"the facet ending at b = {result['b']:.6g}, fraction {result['fraction']:.3g})"
    )
    assert result["e_lam"] <= result["tol_lam"], f"pressure error {result['e_lam']:.3g}"
    assert result["e_sig"] <= result["tol"], f"stress error {result['e_sig']:.3g}"


@pytest.mark.parametrize(
    "degree, upper_elements",
    [(1, 8), (1, 7), (2, 8), (2, 7), (2, 6)],
    ids=["P1-f0.4", "P1-f0.6", "P2-f0.4", "P2-f0.6", "P2-f0.8"],
)
def test_target_end_inside_facet(degree, upper_elements):
    """The target's end inside a contactor facet, at any fraction: exact."""
    check(overhang_patch(degree, upper_elements))


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("upper_elements", [8, 7, 6], ids=["f0.4", "f0.6", "f0.8"])
def test_target_end_inside_facet_dual(upper_elements, degree):
    """Dual P1 and P2 multipliers (P1: psi = 2 mu_i - mu_j; both negative in part): exact.

    Their coefficients are the pressure p where it is constant (sum psi_i = 1), and the
    coverage by psi^2 keeps every multiplier whose support meets the target.
    """
    check(overhang_patch(degree, upper_elements, multiplier=("Dual", degree)))

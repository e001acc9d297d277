# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Numerical extremes (issue [8/8], items 1-3): every point correct within its bound.

The README example translated by (1e6, 1e6) must pass the patch test as well as the
untranslated one, with either kernel backend; every point of the extremes grid
(:mod:`paper.extremes`: material contrast, near
incompressibility, element-size ratio, scale, translation, gaps and overlaps, nearly
coincident nodes, partial cover, curved interfaces) must reproduce the exact uniform
stress state within the round-off bound of its own solve
(:func:`~dolfinx_contact_s2s.analysis.roundoff.round_off_bound`), or raise the exception it names.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import test_system_checks
import ufl
from readme_model import readme_mesh
from test_system_checks import max_pressure_error, readme_problem

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.analysis.roundoff import round_off_bound
from dolfinx_contact_s2s.kernels import BACKENDS
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.problem import BACKWARD_TOLERANCE, LinearContactProblem
from paper.extremes import grid, run_point

comm = MPI.COMM_WORLD


def readme_example(degree, shift, backend):
    """The README example as a user writes it, with the mesh moved by ``shift``.

    Returns the owned pressure values with their dof coordinates less ``shift``.
    """
    mesh, facets = readme_mesh()
    mesh.geometry.x[:, :2] += shift  # the user's translation

    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    material = Material(E=1.0, nu=0.3)
    a, _, v = material.forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.array([0.0, -1.0])), v) * ds(23)  # p = 1 on top
    left = np.concatenate([facets.find(4), facets.find(24)])
    dofs = dolfinx.fem.locate_dofs_topological
    bcs = [
        dolfinx.fem.dirichletbc(0.0, dofs(V.sub(0), 1, left), V.sub(0)),
        dolfinx.fem.dirichletbc(0.0, dofs(V.sub(1), 1, facets.find(1)), V.sub(1)),
    ]
    pair = contact_pair(
        contact_surface(V, facets, 20, backend=backend),
        contact_surface(V, facets, 10, backend=backend),
    )
    prefix = f"translated_{backend}_{degree}_"
    with LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix=prefix) as problem:
        _, (pressure,) = problem.solve()
        m = pressure.function_space.dofmap.index_map.size_local
        xq = _relative_dof_coordinates(pressure.function_space, shift)[:m]
        return xq, pressure.x.array[:m].copy()


def _relative_dof_coordinates(V, shift):
    """Dof coordinates less ``shift``, on the space's mesh moved back and forth (exact)."""
    x = V.mesh.geometry.x
    x[:, :2] -= shift
    coordinates = V.tabulate_dof_coordinates()[:, :2].copy()
    x[:, :2] += shift
    return coordinates


def _by_position(x, values):
    """Values sorted by dof position, gathered on every rank (a partition-free order)."""
    x = np.concatenate(comm.allgather(x))
    values = np.concatenate(comm.allgather(values))
    order = np.lexsort((np.round(x[:, 1], 9), np.round(x[:, 0], 9)))
    return x[order], values[order]


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("backend", BACKENDS)
def test_translated_readme_example(backend, degree):
    """Translated by (1e6, 1e6), the README example passes the patch test within 1e-12
    of the untranslated one, with either kernel backend.

    Before the coupling geometry worked relative to each facet pair, the NumPy backend
    left 1.3e-9 (P1) and 5.3e-9 (P2), the C backend 2.5e-9 (P2). The displacements are
    not compared: the translated nodes carry the round-off of the translation (up to
    6e-11), so the exact linear displacements differ by that much times the strain (the
    translated points of the grid check them against the closed form).
    """
    results = [readme_example(degree, shift, backend) for shift in (0.0, 1e6)]
    (xq0, p0), (xq1, p1) = (_by_position(*r) for r in results)
    np.testing.assert_allclose(xq1, xq0, rtol=0, atol=1e-9)
    assert np.max(np.abs(p1 - 1.0)) <= 1e-12
    assert np.max(np.abs(p1 - p0)) <= 1e-12


@pytest.mark.parametrize("point", grid(full=False), ids=lambda p: p.name.replace(" ", "_"))
def test_extremes_grid(point):
    """Each point: the exact uniform-stress solution within its round-off bound.

    The errors are against the closed form (linear displacements, unit pressure where
    the surfaces face each other); the bound is not vacuous (far below the solution).
    """
    prefix = "extremes_" + "".join(c if c.isalnum() else "_" for c in point.name) + "_"
    record = run_point(point, comm, prefix=prefix)
    if point.expect is not None:
        assert record["exception"] is not None, "expected an exception"
        assert record["exception"].startswith(point.expect[0] + ":")
        assert point.expect[1] in record["exception"]
        return
    assert record["exception"] is None, record["exception"]
    assert record["displacement_error"] <= record["displacement_bound"]
    # Not vacuous: the bound stays far below the solution (at E ratio 1e6, P2: 1e-4 of it).
    assert record["displacement_bound"] <= 1e-3 * record["displacement_scale"]
    if record["multiplier_error"] is not None:
        assert record["multiplier_error"] <= record["multiplier_bound"]
        assert record["multiplier_bound"] <= 1e-3
    assert record["passed"]


@pytest.mark.parametrize("degree", [1, 2])
def test_contrast_1e6_trusted_by_its_backward_error(monkeypatch, degree):
    """Young's modulus ratio 1e6 (the README bodies): MUMPS is backward stable, and the
    solve is trusted on its normwise backward error even when the relative residual is
    above the tolerance; its pressure is within the round-off bound.

    The backward error is checked against a dense NumPy evaluation of the same formula.
    """
    materials = {"lower": Material(E=1.0, nu=0.3), "upper": Material(E=1e6, nu=0.2)}
    monkeypatch.setattr(test_system_checks, "MATERIALS", materials)
    # A tolerance no solve of this system meets: only the backward error can trust it.
    with readme_problem(degree=degree, prefix="contrast6_", residual_tolerance=1e-14) as problem:
        problem.solve()
        residual, backward = problem.residual(), problem.backward_error()
        bound = round_off_bound(problem)
        error = max_pressure_error(problem)
        A = gather_dense(problem.A)
        x = np.concatenate(comm.allgather(problem.x.array_r.copy()))
        b = np.concatenate(comm.allgather(problem.b.array_r.copy()))
    dense = np.max(np.abs(b - A @ x)) / (
        np.max(np.sum(np.abs(A), axis=1)) * np.max(np.abs(x)) + np.max(np.abs(b))
    )
    assert residual > 1e-14
    assert backward == pytest.approx(dense, rel=0.5)
    assert backward <= BACKWARD_TOLERANCE
    assert error <= bound.multiplier[0]


@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)
def test_kernels_do_not_see_a_translation(kernel_backend):
    """Projection, intersection and clipping give the same parameters for a pair of
    curved facets and the same pair translated by (1e6, 1e6).

    Node positions and points on a grid of 2^-20 are exact after the translation, so any
    difference is round-off of the kernels' own arithmetic at the translated magnitude
    (about 1e-10 / h before the kernels worked relative to each facet's first point).
    """
    rng = np.random.default_rng(12)
    grid = 2.0**-20
    F = 40
    c = np.zeros((F, 3, 2))
    c[:, 0] = np.round(rng.uniform(0, 1, (F, 2)) / grid) * grid
    c[:, 1] = np.round(rng.uniform(0.05, 0.1, (F, 2)) / grid) * grid
    c[:, 2] = np.round(rng.uniform(-0.01, 0.01, (F, 2)) / grid) * grid
    rows = np.arange(F, dtype=np.int32)
    offsets = np.round(rng.uniform(-0.05, 0.15, (F, 2)) / grid) * grid
    points = c[:, 0] + offsets
    directions = rng.normal(size=(F, 2))
    # Target facets: the contactor facets moved a little along their normals.
    t = c.copy()
    t[:, 0] += np.round(0.01 * np.stack([c[:, 1, 1], -c[:, 1, 0]], axis=1) / grid) * grid
    t[:, 1:] *= -1.0  # running the other way
    t[:, 0] -= t[:, 1] + t[:, 2]
    t[:, 0] = np.round(t[:, 0] / grid) * grid
    shift = np.array([1e6, 1e6])
    results = []
    for s in (np.zeros(2), shift):
        cs, ts = c.copy(), t.copy()
        cs[:, 0] += s
        ts[:, 0] += s
        xi = kernel_backend.project(cs, rows, np.ascontiguousarray(points + s))
        eta = kernel_backend.intersect(cs, rows, np.ascontiguousarray(points + s), directions)
        lo, hi, keep = kernel_backend.clip_segments(
            cs, np.ones(F), ts, np.ones(F), rows, rows, 0.5, 1e-12
        )
        results.append((xi, eta, lo, hi, keep))
    for a, b in zip(*results, strict=True):
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-13)
    assert np.count_nonzero(results[0][4]) > F // 2  # the clipping keeps pieces

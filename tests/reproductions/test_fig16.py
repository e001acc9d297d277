# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Fig. 16 (section 5.3), reduced: rates in the energy norm on the smooth variant.

The smooth variant has an exact solution (:class:`SmoothSolution`), so the rates below
are those of the contact discretization alone. Levels 2, 4, 8: 20/14 to 80/56
elements along the contact line.
"""

import math

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s.convergence import assert_rate
from paper.blocks import MATERIALS, NAMES
from paper.fig16 import (
    Fig16Case,
    Reference,
    SmoothSolution,
    fig16_problem,
    fig16_scene,
    run_case,
    strain_energy,
)

LEVELS = (2, 4, 8)


@pytest.fixture(scope="module")
def tables():
    comm = MPI.COMM_WORLD
    cases = {
        (method, k): Fig16Case(method, k)
        for method in ("segment-to-segment", "node-to-segment")
        for k in (1, 2)
    }
    return {key: run_case(comm, case, "smooth", LEVELS) for key, case in cases.items()}


def test_exact_solution():
    """Boundary and interface conditions, positive pressure, and E from the fields."""
    exact = SmoothSolution()
    x = np.linspace(0.0, 1.0, 7)
    H = exact.height
    below = exact("lower", np.vstack([x, np.full_like(x, H), 0 * x]))
    above = exact("upper", np.vstack([x, np.full_like(x, H), 0 * x]))
    assert np.allclose(below[1], above[1], rtol=0, atol=1e-15)  # u_y continuous
    top = exact("upper", np.vstack([x, np.full_like(x, 2 * H), 0 * x]))
    assert np.allclose(top[1], exact.top(np.vstack([x])), rtol=0, atol=1e-15)
    bottom = exact("lower", np.vstack([x, 0 * x, 0 * x]))
    assert np.allclose(bottom[1], 0.0, atol=1e-15)
    sides = exact("lower", np.vstack([[0.0, 1.0], [0.2, 0.3], [0, 0]]))
    assert np.allclose(sides[0], 0.0, atol=1e-15)
    assert np.all(exact.pressure(x) > 0)  # compressive: the tied solution is unilateral too
    # The closed-form energy (work of the top traction) against the integrated fields,
    # which also checks equilibrium and the interface tractions.
    scene = fig16_scene(MPI.COMM_WORLD, 4)
    energy = 0.0
    for name in NAMES:
        mesh = scene.bodies[name].mesh
        u = exact.ufl(name, mesh)
        dx = ufl.dx(domain=mesh, metadata={"quadrature_degree": 12})
        form = dolfinx.fem.form(0.5 * ufl.inner(MATERIALS[name].sigma(u), ufl.grad(u)) * dx)
        energy += mesh.comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM)
    assert abs(energy - exact.energy) < 1e-10 * exact.energy


def test_quadratic_s2s(tables):
    """S2S P2 with M^1_{h,2}: quadratic in the energy norm, |E - E_h|/E at twice that."""
    table = tables["segment-to-segment", 2]
    assert_rate(table, "energy_norm", 2.0, tolerance=0.2)
    assert_rate(table, "strain_energy", 4.0, tolerance=0.4)


def test_linear_s2s(tables):
    """S2S P1 with M^1_{h,1}: linear in the energy norm."""
    assert_rate(tables["segment-to-segment", 1], "energy_norm", 1.0, tolerance=0.1)


@pytest.mark.parametrize("degree", [1, 2])
def test_node_to_segment_below_s2s(tables, degree):
    """Single-pass node-to-segment: clearly below S2S of the same degree.

    An O(1) consistency error in a layer of width h gives h^(1/2) in the energy norm;
    quadratic node-to-segment shows exactly that, linear approaches it from above.
    """
    nts, s2s = tables["node-to-segment", degree], tables["segment-to-segment", degree]
    rate = nts.fitted_rate("energy_norm")
    assert rate <= s2s.fitted_rate("energy_norm") - 0.3, nts.markdown()
    assert np.all(nts.errors("energy_norm") > s2s.errors("energy_norm"))
    assert_rate(nts, "energy_norm", 0.5, tolerance=0.1 if degree == 2 else 0.2)


def test_paper_variant_nested():
    """The paper's setup: nested interpolation is exact, the reference error falls."""
    comm = MPI.COMM_WORLD
    reference = Reference(comm, 8)
    try:
        assert reference.order > 0
        problem = fig16_problem(comm, Fig16Case("segment-to-segment", 1), "paper", 2)
        problem.solve()
        # A coarse P1 solution lies in the fine P2 space: its energy is unchanged there.
        fine = reference.interpolate(problem)
        energy = 0.0
        for name, f in zip(NAMES, fine, strict=True):
            form = 0.5 * ufl.inner(MATERIALS[name].sigma(f), ufl.grad(f)) * ufl.dx
            energy += comm.allreduce(
                dolfinx.fem.assemble_scalar(dolfinx.fem.form(form)), op=MPI.SUM
            )
        assert math.isclose(energy, strain_energy(problem), rel_tol=1e-10)
        problem.destroy()
        table = run_case(
            comm, Fig16Case("segment-to-segment", 2), "paper", (2, 4), reference=reference
        )
        e = table.errors("energy_norm")
        assert e[1] < e[0]
    finally:
        reference.destroy()

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""What a user reads after a solve, checked against numbers from outside the code.

The force against the applied load and the support reactions (UFL-assembled
``K u - F`` on the clamped dofs), the pressure integral against UFL, the profile on 2
ranks against the same scene solved on one, and the edge estimate against Hertz's
closed form on several meshes without nodes at the exact edges.
"""

import functools
from dataclasses import replace

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import contact_force, contact_zones, pressure_profile
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.hertz.adaptive import CASE
from paper.hertz.study import hertz_model

#: The two-cylinder scene of issue 9 at a/R1 = 5% (as measured in the report).
SCENE = replace(CASE, a=0.05)


@functools.cache
def _solved(n, comm="world"):
    """Model, problem (solved) and pair; every rank builds them in the same order."""
    model = hertz_model(
        replace(SCENE, elements_across=n), MPI.COMM_WORLD if comm == "world" else MPI.COMM_SELF
    )
    pair = model.pair()
    problem = UnilateralContactProblem(
        model.a, model.L, [pair], model.bcs, petsc_options_prefix=f"post_{n}_{comm}_"
    )
    problem.solve()
    return model, problem, pair


def test_force_balances_load_and_reactions():
    model, problem, pair = _solved(10)
    force = contact_force(pair, problem.multipliers[0])
    # The upper body has no vertical support: the contact carries the applied load F.
    F = SCENE.exact.F
    assert force.contactor[1] == pytest.approx(F, rel=1e-10)
    # The lower body: the vertical reaction of its clamped bottom, from UFL.
    (u,) = problem.u
    V = model.V
    residual = dolfinx.fem.assemble_vector(dolfinx.fem.form(ufl.action(model.a, u) - model.L))
    residual.scatter_reverse(dolfinx.la.InsertMode.add)
    tags, ft = model.scene.tags, model.scene.facet_tags
    bottom = dolfinx.fem.locate_dofs_topological(V, 1, ft.find(tags["lower_bottom"]))
    bottom = bottom[bottom < V.dofmap.index_map.size_local]
    reaction = MPI.COMM_WORLD.allreduce(float(np.sum(residual.array[2 * bottom + 1])))
    assert force.contactor[1] == pytest.approx(reaction, rel=1e-10)
    np.testing.assert_allclose(force.targets[0], -force.contactor, rtol=0, atol=1e-14 * F)
    # The pressure integral against UFL on the multiplier's mesh.
    lam = problem.multipliers[0]
    form = dolfinx.fem.form(lam * ufl.dx(domain=lam.function_space.mesh))
    ufl_integral = MPI.COMM_WORLD.allreduce(dolfinx.fem.assemble_scalar(form))
    assert force.pressure_integral == pytest.approx(ufl_integral, rel=1e-12)
    # On a curved contact it exceeds the resultant, by about (a/R)^2 / 6 (here 0.03%).
    assert 1.0 < force.pressure_integral / force.normal < 1.0 + 0.05**2


def test_profile_sorted_and_the_same_on_every_partition():
    _, problem, pair = _solved(10)
    profile = pressure_profile(pair, *problem.multipliers, problem.active[0], problem.gaps[0])
    assert profile.closed == (False,)
    assert profile.s.size == pair.Q.dofmap.index_map.size_global  # P1: no coincident nodes
    assert np.all(np.diff(profile.s) > 0)
    # Nodes on the upper arc, arclength along its chords from its left end.
    radius = np.linalg.norm(profile.x - [0.0, SCENE.R1], axis=1)
    np.testing.assert_allclose(radius, SCENE.R1, rtol=1e-12)
    chords = np.linalg.norm(np.diff(profile.x, axis=0), axis=1)
    np.testing.assert_allclose(profile.s[1:], np.cumsum(chords), rtol=1e-12)
    assert profile.x[0, 0] < profile.x[-1, 0]
    assert np.all(profile.pressure[~profile.active] == 0.0)
    assert np.all(profile.gap[profile.active] <= 1e-12 * np.abs(profile.gap).max())
    # The same scene solved on one process.
    _, serial, serial_pair = _solved(10, "self")
    reference = pressure_profile(serial_pair, *serial.multipliers, serial.active[0], serial.gaps[0])
    np.testing.assert_allclose(profile.s, reference.s, rtol=1e-13)
    np.testing.assert_allclose(profile.x, reference.x, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(profile.active, reference.active)
    scale = reference.pressure.max()
    np.testing.assert_allclose(profile.pressure, reference.pressure, rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize("estimate", ["gap", "pressure", "middle"])
def test_zone_brackets(estimate):
    _, problem, pair = _solved(10)
    zones = contact_zones(
        pair, *problem.multipliers, problem.active[0], problem.gaps[0], estimate=estimate
    )
    assert len(zones) == 1
    profile = pressure_profile(pair, *problem.multipliers, problem.active[0])
    active = np.flatnonzero(profile.active)
    (zone,) = zones
    # The bracket: the outermost active nodes and their inactive neighbours.
    assert zone.start.inside == profile.s[active[0]]
    assert zone.start.outside == profile.s[active[0] - 1]
    assert zone.end.inside == profile.s[active[-1]]
    assert zone.end.outside == profile.s[active[-1] + 1]
    for edge in (zone.start, zone.end):
        assert min(edge.inside, edge.outside) <= edge.estimate <= max(edge.inside, edge.outside)
        assert edge.method == estimate
    assert zone.length_bounds[0] <= zone.length <= zone.length_bounds[1]


def test_gap_estimate_beats_the_middle_of_the_bracket():
    """Against Hertz's a on meshes of 10-13 elements across, no node at +-a."""
    a = SCENE.exact.a
    errors = {"gap": [], "middle": []}
    for n in (10, 11, 12, 13):
        _, problem, pair = _solved(n)
        for estimate, found in errors.items():
            (zone,) = contact_zones(
                pair, *problem.multipliers, problem.active[0], problem.gaps[0], estimate=estimate
            )
            half = 0.5 * (zone.end.point[0] - zone.start.point[0])
            found.append(abs(half / a - 1.0))
    gap, middle = np.array(errors["gap"]), np.array(errors["middle"])
    assert np.all(gap < middle)
    assert gap.mean() < 0.75 * middle.mean()


def test_bad_input():
    _, problem, pair = _solved(10)
    lam, active = problem.multipliers[0], problem.active[0]
    with pytest.raises(ValueError, match="estimate must be one of"):
        contact_zones(pair, lam, active, estimate="nearest")
    with pytest.raises(ValueError, match="needs the weighted gaps"):
        contact_zones(pair, lam, active)
    with pytest.raises(ValueError, match="multiplier space"):
        contact_force(pair, problem.u[0])

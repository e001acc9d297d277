# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Adaptive refinement of the contact edge, against Hertz's half-width.

The two-cylinder scene of issue 9 (R1 = 1, R2 = 3, unequal materials) meshed as a user
meshes it: 10 P1 triangles across the contact, no node at the exact edges.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest

from dolfinx_contact_s2s.postprocess import pressure_profile
from dolfinx_contact_s2s.unilateral import RefinementError, refine_contact_zone
from paper.hertz.adaptive import CASE, arcs, build
from paper.hertz.scene import hertz


def _scene():
    return hertz(
        MPI.COMM_WORLD,
        R=CASE.R1,
        a=CASE.a,
        elements_across=CASE.elements_across,
        lower_radius=CASE.R2,
        edge_nodes=False,
    )


def test_edge_to_one_percent_of_a():
    scene = _scene()
    a = CASE.exact.a
    result = refine_contact_zone(
        build(CASE),
        scene.mesh,
        scene.cell_tags,
        scene.facet_tags,
        tolerance=0.01,
        length=a,
        snap=arcs(CASE),
    )
    with result.problem:
        history = result.history
        assert len(history) <= 6  # within 5 refinements
        # Every step after the first restarts from the previous zones: fewer solves.
        assert not history[0].restarted and all(s.restarted for s in history[1:])
        assert max(s.solves for s in history[1:]) < history[0].solves
        assert history[0].bracket > 0.1 * a  # 10 elements across: a bracket of 0.2 a
        (zone,) = history[-1].zones[0]
        for edge in (zone.start, zone.end):
            x0, x1 = edge.bracket_points[:, 0]
            assert abs(x1 - x0) <= 0.01 * a
        half = 0.5 * (zone.end.point[0] - zone.start.point[0])
        assert half == pytest.approx(a, rel=0.01)
        assert [s.unknowns for s in history] == sorted(s.unknowns for s in history)
        mesh = result.meshes[0]
        assert mesh.topology.index_map(2).size_global > scene.mesh.topology.index_map(2).size_global


def test_tolerance_not_reached_says_how_far():
    scene = _scene()
    with pytest.raises(RefinementError, match="widest bracket") as raised:
        refine_contact_zone(
            build(CASE, prefix="adaptive_fail_"),
            scene.mesh,
            scene.cell_tags,
            scene.facet_tags,
            tolerance=0.01,
            length=CASE.exact.a,
            max_steps=1,
        )
    assert len(raised.value.history) == 2
    assert raised.value.history[-1].relative > 0.01
    raised.value.problem.destroy()


def test_quadrilaterals_and_bad_arguments():
    mesh = dolfinx.mesh.create_unit_square(
        MPI.COMM_WORLD, 2, 2, dolfinx.mesh.CellType.quadrilateral
    )
    tags = dolfinx.mesh.meshtags(mesh, 2, np.empty(0, np.int32), np.empty(0, np.int32))
    with pytest.raises(NotImplementedError, match="simplices"):
        refine_contact_zone(lambda *args: None, mesh, tags, tags)
    scene = _scene()
    for bad in (
        {"tolerance": 0.0},
        {"max_steps": -1},
        {"length": -1.0},
        {"layers": 0.0},
        {"geometry_degree": 3},
    ):
        with pytest.raises(ValueError):
            refine_contact_zone(build(CASE), scene.mesh, scene.cell_tags, scene.facet_tags, **bad)
    with pytest.raises(ValueError, match="callables"):
        refine_contact_zone(build(CASE), scene.mesh, scene.cell_tags, scene.facet_tags, solve=1)
    with pytest.raises(ValueError, match="build must return"):
        refine_contact_zone(lambda *args: None, scene.mesh, scene.cell_tags, scene.facet_tags)
    with pytest.raises(ValueError, match="as many"):
        refine_contact_zone(build(CASE), [scene.mesh], [scene.cell_tags], [])
    with pytest.raises(ValueError, match="snap"):
        refine_contact_zone(build(CASE), scene.mesh, scene.cell_tags, scene.facet_tags, snap=1)
    with pytest.raises(ValueError, match="pressure_tolerance"):
        refine_contact_zone(
            build(CASE), scene.mesh, scene.cell_tags, scene.facet_tags, pressure_tolerance=2.0
        )
    with (
        build(CASE, prefix="adaptive_bad_active_")(
            scene.mesh, scene.cell_tags, scene.facet_tags
        ) as problem,
        pytest.raises(ValueError, match="one entry per pair"),
    ):
        problem.solve(active=[None, None])
    with (
        build(CASE, prefix="adaptive_bad_shape_")(
            scene.mesh, scene.cell_tags, scene.facet_tags
        ) as problem,
        pytest.raises(ValueError, match="owned dofs"),
    ):
        problem.solve(active=[np.ones(10**7, dtype=bool)])


def test_bad_axis_of_a_3d_model():
    """A tetrahedral model needs a point and a nonzero direction."""
    cube = dolfinx.mesh.create_unit_cube(MPI.COMM_WORLD, 1, 1, 1)
    tags = dolfinx.mesh.meshtags(cube, 2, np.empty(0, np.int32), np.empty(0, np.int32))
    for bad, match in (
        ({}, "needs the axis"),
        ({"axis": ((0, 0, 0), (0, 0, 0))}, "nonzero direction"),
        ({"axis": ((0, 0), (0, 0, 1))}, "nonzero direction"),
    ):
        with pytest.raises(ValueError, match=match):
            refine_contact_zone(lambda *args: None, cube, tags, tags, **bad)


def test_peak_refined_until_it_settles():
    """peak_tolerance refines at the largest lambda too, until it settles.

    The edge criterion alone leaves the 10 elements across the contact at the peak
    (spacing a/5); with the peak refined until it changes by at most 0.5% over a step,
    the multiplier nodes around the peak are at least four times closer, and the peak
    pressure is within 2% of Hertz's (issue 9's tolerance; measured: 1.55% with the edge
    criterion alone, 1.27% with the peak, the rest being the finite bodies' model error).
    """
    scene = _scene()
    result = refine_contact_zone(
        build(CASE, prefix="adaptive_peak_"),
        scene.mesh,
        scene.cell_tags,
        scene.facet_tags,
        tolerance=0.05,
        length=CASE.exact.a,
        snap=arcs(CASE),
        peak_tolerance=0.005,
    )
    with result.problem as problem:
        history = result.history
        assert np.isnan(history[0].peak_change)
        assert history[-1].peak_change <= 0.005
        profile = pressure_profile(problem.pairs[0], problem.multipliers[0])
        k = int(np.argmax(profile.pressure))
        spacing = np.diff(profile.s)[k - 1 : k + 1]
        assert spacing.max() <= 0.25 * (2 * CASE.exact.a / CASE.elements_across)
        assert profile.pressure[k] == pytest.approx(CASE.exact.p0, rel=0.02)
    with pytest.raises(ValueError, match="peak_tolerance"):
        refine_contact_zone(
            build(CASE), scene.mesh, scene.cell_tags, scene.facet_tags, peak_tolerance=1.5
        )

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Bad input raises a clear Python exception on every rank."""

from mpi4py import MPI

import dolfinx
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.petsc import assemble_coupling
from dolfinx_contact_s2s.scenes import BOTTOM, TOP, patch_test


@pytest.fixture(scope="module")
def scene():
    return patch_test(MPI.COMM_WORLD, (4, 3))


def _space(body, degree=1):
    return dolfinx.fem.functionspace(body.mesh, ("Lagrange", degree, (2,)))


def test_missing_tag(scene):
    with pytest.raises(ValueError, match="no facet of the mesh carries contact tag 42"):
        contact_surface(_space(scene.upper), scene.upper.facet_tags, 42)


def test_empty_tag(scene):
    mesh = scene.upper.mesh
    empty = dolfinx.mesh.meshtags(mesh, 1, [], [])
    with pytest.raises(ValueError, match="no facet of the mesh carries contact tag 1"):
        contact_surface(_space(scene.upper), empty, 1)


def test_cell_tags_are_not_facet_tags(scene):
    with pytest.raises(ValueError, match="must mark facets"):
        contact_surface(_space(scene.upper), scene.upper.cell_tags, 1)


def test_scalar_space(scene):
    V = dolfinx.fem.functionspace(scene.upper.mesh, ("Lagrange", 1))
    with pytest.raises(ValueError, match="vector-valued"):
        contact_surface(V, scene.upper.facet_tags, BOTTOM)


def test_contactor_equal_to_target(scene):
    V = _space(scene.upper)
    s = contact_surface(V, scene.upper.facet_tags, BOTTOM)
    with pytest.raises(ValueError, match="must differ from its target"):
        contact_pair(s, s)
    with pytest.raises(ValueError, match="must differ from its target"):
        contact_pair(s, contact_surface(V, scene.upper.facet_tags, BOTTOM))


def test_surfaces_not_facing(scene):
    # Both top surfaces have upward normals: they can never touch.
    upper_top = contact_surface(_space(scene.upper), scene.upper.facet_tags, TOP)
    lower_top = contact_surface(_space(scene.lower), scene.lower.facet_tags, TOP)
    with pytest.raises(ValueError, match="never face each other"):
        assemble_coupling(contact_pair(upper_top, lower_top))


def test_surfaces_out_of_reach(scene):
    upper = contact_surface(_space(scene.upper), scene.upper.facet_tags, BOTTOM)
    lower = contact_surface(_space(scene.lower), scene.lower.facet_tags, TOP)
    far = patch_test(MPI.COMM_WORLD, (4, 3), gap=5.0)
    far_upper = contact_surface(_space(far.upper), far.upper.facet_tags, BOTTOM)
    assemble_coupling(contact_pair(upper, lower))  # in reach: fine
    with pytest.raises(ValueError, match="never face each other"):
        assemble_coupling(contact_pair(far_upper, lower))

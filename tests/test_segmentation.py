# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The seam for the facet dimension: segmentations and kernels registered per dimension.

A segmentation registered in :data:`~dolfinx_contact_s2s.segmentation.SEGMENTATIONS` is
what every pair built afterwards uses, down to the assembly and the solve, with no
change to the problem layer; a dimension without one is refused clearly.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.kernels import BACKENDS, KernelBackend, get_backend
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.segmentation import (
    SEGMENTATIONS,
    Segmentation,
    SubSegments,
    get_segmentation,
)
from paper.patch_test import PatchTestCase, solve_patch_test
from paper.scenes import patch_test


class Recording:
    """The real segmentation of edges, recording each stage it is asked for."""

    facet_dim = 1

    def __init__(self, real: Segmentation):
        self.real = real
        self.calls: list[str] = []

    def sweep(self, contactor, boxes, radius):
        self.calls.append("sweep")
        return self.real.sweep(contactor, boxes, radius)

    def cut(self, contactor, target, ic, it, radius, backend):
        self.calls.append("cut")
        return self.real.cut(contactor, target, ic, it, radius, backend)

    def points(self, contactor, pieces, rule, backend):
        self.calls.append("points")
        return self.real.points(contactor, pieces, rule, backend)


class WholeFacets(Recording):
    """Matching meshes: each contactor edge uncut, against the target edge it coincides with.

    No clipping kernel: a candidate pair is kept when the two edges' midpoints coincide.
    """

    def cut(self, contactor, target, ic, it, radius, backend):
        self.calls.append("cut")
        half = np.full(ic.size, 0.5)
        x_c, _ = backend.evaluate(contactor.coefficients, ic, half)
        x_t, _ = backend.evaluate(target.coefficients, it, half)
        same = np.linalg.norm(x_c - x_t, axis=1) < 1e-8
        n = int(np.count_nonzero(same))
        self.pieces = n
        return SubSegments(ic[same], it[same], np.zeros(n), np.ones(n))


def _surfaces(scene, degree):
    spaces = {
        n: dolfinx.fem.functionspace(b.mesh, ("Lagrange", degree, (2,)))
        for n, b in scene.bodies.items()
    }
    return {n: contact_surface(spaces[n], b.facet_tags, b.contact) for n, b in scene.bodies.items()}


@pytest.mark.parametrize("degree", [1, 2])
def test_registered_segmentation_is_used_by_assemble_coupling(monkeypatch, degree):
    """A wrapper registered for dimension 1 is called, and B is the real segmentation's."""
    scene = patch_test(MPI.COMM_WORLD, (10, 7), cell="quadrilateral", geometry_degree=2)
    surf = _surfaces(scene, degree)
    op = assemble_coupling(contact_pair(surf["upper"], surf["lower"]))
    expected = [gather_dense(B) for _, B in op.blocks]
    op.destroy()

    recording = Recording(SEGMENTATIONS[1])
    monkeypatch.setitem(SEGMENTATIONS, 1, recording)
    pair = contact_pair(surf["upper"], surf["lower"])
    assert pair.segmentation is recording
    op = assemble_coupling(pair)
    got = [gather_dense(B) for _, B in op.blocks]
    op.destroy()
    assert recording.calls == ["sweep", "cut", "points"]
    assert len(got) == len(expected)
    scale = max(np.max(np.abs(B)) for B in expected)
    for B, ref in zip(got, expected, strict=True):
        assert np.max(np.abs(B - ref), initial=0.0) <= 1e-14 * scale


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
def test_uncut_segmentation_passes_the_matching_patch_test(monkeypatch, cell):
    """Whole facets on matching meshes: the contact pressure is the applied p (section 3.2)."""
    whole = WholeFacets(SEGMENTATIONS[1])
    monkeypatch.setitem(SEGMENTATIONS, 1, whole)
    case = PatchTestCase(elements=(10, 10), cell=cell, pressure=1.0)
    sol = solve_patch_test(MPI.COMM_WORLD, case)
    assert "cut" in whole.calls and "points" in whole.calls
    # One piece per contactor facet: the 10 elements along the contact line.
    assert MPI.COMM_WORLD.allreduce(whole.pieces, op=MPI.SUM) == 10
    lam = sol.pressure
    owned = lam.function_space.dofmap.index_map.size_local
    error = np.max(np.abs(lam.x.array[:owned] - case.pressure), initial=0.0) / case.pressure
    assert MPI.COMM_WORLD.allreduce(error, op=MPI.MAX) < 1e-10


def test_unregistered_facet_dimension_is_refused(monkeypatch):
    """No segmentation or kernels for a dimension: NotImplementedError naming it."""
    with pytest.raises(NotImplementedError, match="dimension 3"):
        get_segmentation(3)
    with pytest.raises(NotImplementedError, match="dimension 3"):
        get_backend("numpy", MPI.COMM_WORLD, facet_dim=3)
    scene = patch_test(MPI.COMM_WORLD, (4, 3))
    surf = _surfaces(scene, 1)
    monkeypatch.delitem(SEGMENTATIONS, 1)
    with pytest.raises(NotImplementedError, match="dimension 1"):
        contact_pair(surf["upper"], surf["lower"])


@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)
def test_backends_satisfy_the_protocols(kernel_backend):
    assert isinstance(kernel_backend, KernelBackend)
    assert kernel_backend.FACET_DIM == 1
    assert isinstance(get_segmentation(1), Segmentation)


def test_moved_search_names():
    """The names that left ``search`` say where they went."""
    from dolfinx_contact_s2s import search

    with pytest.raises(ImportError, match=r"import it from dolfinx_contact_s2s"):
        from dolfinx_contact_s2s.search import SubSegments as _  # noqa: F401
    with pytest.raises(ImportError, match=r"ContactPair\.sub_segments"):
        search.sub_segments  # noqa: B018

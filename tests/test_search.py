# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Several targets per contactor, targets in the contactor's own space, uncovered multipliers."""

from mpi4py import MPI

import basix.ufl
import dolfinx
import numpy as np
import pytest

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.la import gather_dense

TAG = 7
EPS = np.finfo(float).eps


def _strips(comm, strips):
    """One mesh of one-cell-high quadrilateral strips ``(xs, y0, y1)``, disconnected.

    Nodes sit exactly at the given coordinates (no mesh generator noise).
    """
    x, cells, offset = [], [], 0
    for xs, y0, y1 in strips:
        n = len(xs)
        x.append(np.concatenate([np.stack([xs, np.full(n, y)], axis=1) for y in (y0, y1)]))
        i = np.arange(n - 1)
        cells.append(offset + np.stack([i, i + 1, n + i, n + i + 1], axis=1))
        offset += 2 * n
    if comm.rank == 0:
        x, cells = np.concatenate(x), np.concatenate(cells).astype(np.int64)
    else:
        x, cells = np.empty((0, 2)), np.empty((0, 4), dtype=np.int64)
    e = basix.ufl.element("Lagrange", "quadrilateral", 1, shape=(2,))
    return dolfinx.mesh.create_mesh(comm, cells=cells, x=x, e=e)


def _surface(V, y, tag=TAG, x_range=(-np.inf, np.inf)):
    """Contact surface of the boundary facets on the line ``y`` within ``x_range``."""
    mesh = V.mesh

    def on(x):
        return np.isclose(x[1], y) & (x[0] >= x_range[0] - 1e-12) & (x[0] <= x_range[1] + 1e-12)

    facets = dolfinx.mesh.locate_entities_boundary(mesh, 1, on)
    tags = dolfinx.mesh.meshtags(mesh, 1, facets, np.full(facets.size, tag, dtype=np.int32))
    return contact_surface(V, tags, tag)


def _coordinates(V):
    """Coordinates of every global node (block) of a space, on every rank."""
    imap = V.dofmap.index_map
    x = V.tabulate_dof_coordinates()[: imap.size_local, :2]
    out = np.zeros((imap.size_global, 2))
    for start, xs in V.mesh.comm.allgather((imap.local_range[0], x)):
        out[start : start + xs.shape[0]] = xs
    return out


def _match(x_from, x_to):
    """Index in ``x_to`` of each point of ``x_from``."""
    d = np.linalg.norm(x_from[:, None, :] - x_to[None, :, :], axis=2)
    idx = np.argmin(d, axis=1)
    assert np.max(d[np.arange(idx.size), idx], initial=0.0) < 1e-12
    return idx


def _columns(V, W):
    """Unrolled dof of ``W`` at the coordinates of each unrolled dof of ``V``."""
    nodes = _match(_coordinates(V), _coordinates(W))
    return (2 * nodes[:, None] + np.arange(2)).reshape(-1)


def _assemble(pair):
    """Dense blocks by space, dense G and the uncovered dofs."""
    op = assemble_coupling(pair)
    blocks = [(V, gather_dense(B)) for V, B in op.blocks]
    G = np.concatenate(pair.contactor.comm.allgather(op.G.array_r.copy()))
    uncovered, inactive = op.uncovered.copy(), op.inactive.copy()
    op.destroy()
    assert np.array_equal(inactive, np.union1d(pair.duplicates, uncovered))
    return blocks, G, uncovered


UPPER = np.linspace(0.0, 1.0, 5)  # contactor nodes 0, 1/4, ..., 1
LOWER = np.array([0.0, 0.2, 0.35, 0.6, 0.8, 1.0])  # the joint at 0.35 is no contactor node


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize(
    ("method", "options"),
    [
        ("segment-to-segment", {}),
        ("segment-to-segment", {"quadrature": "composite-newton-cotes"}),
        ("segment-to-segment", {"multiplier": ("DG", 1)}),
        ("node-to-segment", {"weight": "tributary"}),
        ("node-to-segment-gauss", {}),
    ],
)
def test_two_targets_equal_one(degree, method, options):
    """A flat target split at x = 0.35 into two meshes gives the B and G of the whole one.

    Columns of the two targets are summed at equal coordinates (the joint node is in
    both); the contactor block, G and the multiplier space are unchanged.
    """
    comm = MPI.COMM_WORLD
    H, g = 0.5, 0.01
    upper = dolfinx.fem.functionspace(_strips(comm, [(UPPER, H + g, 2 * H)]), ("P", degree, (2,)))
    whole = dolfinx.fem.functionspace(_strips(comm, [(LOWER, 0.0, H)]), ("P", degree, (2,)))
    parts = [
        dolfinx.fem.functionspace(_strips(comm, [(xs, 0.0, H)]), ("P", degree, (2,)))
        for xs in (LOWER[:3], LOWER[2:])
    ]
    contactor = _surface(upper, H + g)
    ref = contact_pair(contactor, _surface(whole, H), method=method, **options)
    split = contact_pair(contactor, [_surface(V, H) for V in parts], method=method, **options)
    assert len(split.targets) == 2 and split.Q.dofmap.index_map.size_global == (
        ref.Q.dofmap.index_map.size_global
    )
    (_, Bc_ref), (_, Bt_ref) = _assemble(ref)[0]
    blocks, G, uncovered = _assemble(split)
    _, G_ref, _ = _assemble(ref)
    assert [V for V, _ in blocks] == [upper, *parts]
    Bt = np.zeros_like(Bt_ref)
    for V, B in blocks[1:]:
        np.add.at(Bt.T, _columns(V, whole), B.T)
    # The two pairs build their multiplier spaces alike on the same contactor facets.
    np.testing.assert_array_equal(_coordinates(split.Q), _coordinates(ref.Q))
    rows = np.arange(G.size)
    scale = np.max(np.abs(Bc_ref))
    tol = 100 * EPS * scale
    assert np.max(np.abs(blocks[0][1] - Bc_ref[rows])) < tol
    assert np.max(np.abs(Bt - Bt_ref[rows])) < tol
    assert np.max(np.abs(G - G_ref[rows])) < tol
    assert uncovered.size == 0


def test_contactor_facet_over_a_joint():
    """One contactor facet above the joint of two targets is integrated on both pieces.

    Contactor [0, 1] (one P1 facet, mu_0 = 1 - x, mu_1 = x) over targets [0, 0.35] and
    [0.35, 1]: the contactor block is the full mass matrix [[1/3, 1/6], [1/6, 1/3]], and
    each target carries int mu_k over its own piece.
    """
    comm = MPI.COMM_WORLD
    H = 0.5
    upper = dolfinx.fem.functionspace(_strips(comm, [([0.0, 1.0], H, 2 * H)]), ("P", 1, (2,)))
    parts = [
        dolfinx.fem.functionspace(_strips(comm, [(xs, 0.0, H)]), ("P", 1, (2,)))
        for xs in ([0.0, 0.35], [0.35, 1.0])
    ]
    pair = contact_pair(_surface(upper, H), [_surface(V, H) for V in parts])
    blocks, _, _ = _assemble(pair)
    order = np.argsort(_coordinates(pair.Q)[:, 0])
    a = 0.35
    # int_0^a (1 - x) dx, int_0^a x dx and the rest: the y columns of each target summed.
    expected = [
        np.array([a - a * a / 2, a * a / 2]),
        np.array([0.5 - a + a * a / 2, 0.5 - a * a / 2]),
    ]
    Bc = blocks[0][1][order]
    np.testing.assert_allclose(Bc[:, 1::2].sum(axis=1), [0.5, 0.5], atol=10 * EPS)
    for (_, B), e in zip(blocks[1:], expected, strict=True):
        np.testing.assert_allclose(-B[order][:, 1::2].sum(axis=1), e, atol=10 * EPS)


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("method", ["segment-to-segment", "node-to-segment"])
def test_same_space_equals_two_meshes(degree, method):
    """Two blocks in one mesh and one space give the B of the two-mesh version.

    With the contactor and the target in one space there is one block, holding both
    contributions; its columns at the contactor's and the target's nodes equal B_C and
    B_T of separate meshes (matched by coordinates; the gap keeps them apart).
    """
    comm = MPI.COMM_WORLD
    H, g = 0.5, 0.01
    lower_x, upper_x = np.linspace(0.0, 1.0, 4), UPPER
    both = dolfinx.fem.functionspace(
        _strips(comm, [(lower_x, 0.0, H), (upper_x, H + g, 2 * H)]), ("P", degree, (2,))
    )
    upper = dolfinx.fem.functionspace(_strips(comm, [(upper_x, H + g, 2 * H)]), ("P", degree, (2,)))
    lower = dolfinx.fem.functionspace(_strips(comm, [(lower_x, 0.0, H)]), ("P", degree, (2,)))
    one = contact_pair(_surface(both, H + g, tag=2), _surface(both, H, tag=1), method=method)
    two = contact_pair(_surface(upper, H + g), _surface(lower, H), method=method)
    blocks, G, _ = _assemble(one)
    assert len(blocks) == 1 and blocks[0][0] is both
    B = blocks[0][1]
    (_, Bc), (_, Bt) = _assemble(two)[0]
    _, G_two, _ = _assemble(two)
    rows = _match(_coordinates(one.Q), _coordinates(two.Q))
    tol = 100 * EPS * np.max(np.abs(Bc))
    assert np.max(np.abs(B[:, _columns(upper, both)] - Bc[rows])) < tol
    assert np.max(np.abs(B[:, _columns(lower, both)] - Bt[rows])) < tol
    # Nothing else: the two column sets cover every nonzero of B.
    assert np.isclose(np.abs(B).sum(), np.abs(Bc).sum() + np.abs(Bt).sum(), rtol=1e-13)
    assert np.max(np.abs(G - G_two[rows])) < tol


@pytest.mark.parametrize(
    ("method", "options", "degree"),
    [
        ("segment-to-segment", {}, 1),
        ("segment-to-segment", {}, 2),
        ("segment-to-segment", {"quadrature": "gauss"}, 1),
        ("node-to-segment", {}, 1),
        ("node-to-segment", {"weight": "tributary"}, 2),
        ("node-to-segment-gauss", {}, 1),
    ],
)
def test_uncovered_beyond_the_target_end(method, options, degree):
    """A contactor hanging over the target's end: its multipliers there are uncovered.

    Contactor nodes 0.5, 0.75, ..., 1.5 over a target ending at x = 1: the uncovered
    multipliers are exactly those at x > 1 (their support lies beyond the end).
    """
    comm = MPI.COMM_WORLD
    H, g = 0.5, 0.01
    upper = dolfinx.fem.functionspace(
        _strips(comm, [(np.linspace(0.5, 1.5, 5), H + g, 2 * H)]), ("P", degree, (2,))
    )
    lower = dolfinx.fem.functionspace(
        _strips(comm, [(np.linspace(0.0, 1.0, 4), 0.0, H)]), ("P", degree, (2,))
    )
    pair = contact_pair(_surface(upper, H + g), _surface(lower, H), method=method, **options)
    _, _, uncovered = _assemble(pair)
    beyond = np.flatnonzero(_coordinates(pair.Q)[:, 0] > 1.0 + 1e-12)
    assert beyond.size > 0
    np.testing.assert_array_equal(uncovered, beyond)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Distributed dofs and matrices in a numbering that does not depend on the partition.

A run on several ranks and one on ``COMM_SELF`` number their dofs differently; they are
compared by keys: every dof block by its label (a body, a connected component) and its
coordinates, every multiplier by its coordinates. Used by ``tests/test_ranks.py`` (2D)
and ``tests/test_contact_3d.py`` (3D).
"""

from __future__ import annotations

from mpi4py import MPI

import dolfinx
import numpy as np
import scipy.sparse
import scipy.spatial


def gather(comm: MPI.Comm, array: np.ndarray) -> np.ndarray:
    """Concatenate the processes' arrays in rank order (owned blocks: the global order)."""
    return np.concatenate(comm.allgather(np.asarray(array)))


def keys(V: dolfinx.fem.FunctionSpace, labels: np.ndarray | None) -> np.ndarray:
    """``(label, x, y[, z])`` of every global dof block of ``V``, on every process.

    ``labels``: one per local cell (e.g. its connected component), or ``None`` (all 0).
    """
    imap = V.dofmap.index_map
    n = imap.size_local
    label = np.zeros(n + imap.num_ghosts)
    if labels is not None:
        cells = V.dofmap.list[: labels.size]
        label[cells.reshape(-1)] = np.repeat(labels, cells.shape[1])
    x = V.tabulate_dof_coordinates()[:n, : V.mesh.geometry.dim]
    return gather(V.mesh.comm, np.column_stack([label[:n], x]))


def match(world: np.ndarray, serial: np.ndarray) -> np.ndarray:
    """Index in ``serial`` of every row of ``world`` (:func:`keys`).

    Labels must agree exactly, coordinates to 1e-12 of the scene's size; the map must
    be one to one.
    """
    assert world.shape == serial.shape, (world.shape, serial.shape)
    size = max(np.ptp(serial[:, 1:], axis=0).max(), 1.0)
    perm = np.full(world.shape[0], -1, dtype=np.int64)
    for label in np.unique(serial[:, 0]):
        s = np.flatnonzero(serial[:, 0] == label)
        w = np.flatnonzero(world[:, 0] == label)
        assert s.size == w.size, (label, s.size, w.size)
        distance, nearest = scipy.spatial.cKDTree(serial[s, 1:]).query(world[w, 1:])
        assert np.all(distance <= 1e-12 * size), distance.max()
        perm[w] = s[nearest]
    assert np.array_equal(np.sort(perm), np.arange(serial.shape[0])), "keys are not one to one"
    return perm


def dof_perm(block_perm: np.ndarray, bs: int) -> np.ndarray:
    """The permutation of dofs of a permutation of their blocks of size ``bs``."""
    return (block_perm[:, None] * bs + np.arange(bs)[None, :]).reshape(-1)


def matrix_entries(B) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Global ``(rows, cols, values)`` of a distributed PETSc AIJ matrix, on every process."""
    comm = B.getComm().tompi4py()
    indptr, cols, vals = B.getValuesCSR()
    r0, r1 = B.getOwnershipRange()
    rows = r0 + np.repeat(np.arange(r1 - r0), np.diff(indptr))
    return (
        gather(comm, rows.astype(np.int64)),
        gather(comm, cols.astype(np.int64)),
        gather(comm, vals),
    )


def matrix_difference(
    world: tuple, serial: tuple, row_perm: np.ndarray, col_perm: np.ndarray
) -> scipy.sparse.csr_matrix:
    """``|B_world - B_serial|`` entrywise, in the serial numbering (:func:`matrix_entries`).

    ``row_perm`` and ``col_perm`` take the world's rows and columns to the serial ones.
    """
    shape = (row_perm.size, col_perm.size)
    rs, cs, vs = serial
    rw, cw, vw = world
    Bs = scipy.sparse.csr_matrix((vs, (rs, cs)), shape=shape)
    Bw = scipy.sparse.csr_matrix((vw, (row_perm[rw], col_perm[cw])), shape=shape)
    return abs(Bs - Bw).tocsr()

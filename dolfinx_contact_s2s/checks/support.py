# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Rigid motions that nothing resists (Eq. 33): a body that is not properly supported."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.la
import numpy as np
import numpy.typing as npt
import scipy.linalg
import scipy.sparse
import scipy.sparse.csgraph

from dolfinx_contact_s2s.checks.bodies import Bodies, body_set
from dolfinx_contact_s2s.checks.linalg import (
    csr_rows,
    echelon,
    petsc_vector,
    unit_rows,
)

__all__ = [
    "UNSUPPORTED_TOL",
    "RigidMotion",
    "SupportGram",
    "UnsupportedMotion",
    "support_gram",
    "unsupported_motions",
]

UNSUPPORTED_TOL: float = 1e-10
"""Relative eigenvalue of the normalized Gram matrix below which a rigid motion is free."""


def _fmt(values: npt.ArrayLike) -> str:
    values = np.atleast_1d(np.asarray(values, dtype=np.float64))
    return "(" + ", ".join(f"{v + 0.0:.4g}" for v in values) + ")"


@dataclass(frozen=True)
class RigidMotion:
    r"""Rigid motion of one body.

    :math:`\mathbf u(\mathbf x) = \mathbf t + \omega\times(\mathbf x - \mathbf c)`.

    Attributes:
        space: Index of the displacement space.
        component: Connected component (body) of the space's mesh.
        coefficients: Coefficients of the component's modes of :func:`rigid_body_modes`.
        translation: :math:`\mathbf t`, the displacement of the centroid.
        rotation: :math:`\omega` (one value in 2D, a vector in 3D, none in 1D) per unit
            length.
        centroid: :math:`\mathbf c`, the centroid of the component's nodes.
        bounding_box: Lower and upper corner of the component's nodes, shape ``(2, gdim)``.
        description: "translation along (0, 1)", "rotation about (0.5, 0.25)", ...
    """

    space: int
    component: int
    coefficients: npt.NDArray[np.floating]
    translation: npt.NDArray[np.floating]
    rotation: npt.NDArray[np.floating]
    centroid: npt.NDArray[np.floating]
    bounding_box: npt.NDArray[np.floating]
    description: str

    def displacement(self, x: npt.ArrayLike) -> npt.NDArray[np.floating]:
        """The motion's displacement at points ``x`` of shape ``(num_points, gdim)``."""
        d = np.atleast_2d(np.asarray(x, dtype=np.float64))[:, : self.translation.size]
        d = d - self.centroid
        u = np.tile(self.translation, (d.shape[0], 1))
        if self.translation.size == 2:
            u += self.rotation[0] * np.stack([-d[:, 1], d[:, 0]], axis=1)
        elif self.translation.size == 3:
            u += np.cross(self.rotation, d)
        return u

    def body(self) -> str:
        """The body in words: space, component and bounding box."""
        box = np.array(self.bounding_box, dtype=np.float64)
        box[np.abs(box) <= 1e-12 * max(np.abs(box).max(initial=0.0), 1e-300)] = 0.0
        box_text = " x ".join(f"[{lo + 0.0:.4g}, {hi + 0.0:.4g}]" for lo, hi in box.T.tolist())
        return f"body {self.component} of space {self.space} (nodes in {box_text})"


def _describe(t: npt.NDArray, w: npt.NDArray, c: npt.NDArray, size: float) -> str:
    scale = np.linalg.norm(t) + np.linalg.norm(w) * size
    if np.linalg.norm(w) * size <= 1e-8 * scale:
        return f"translation along {_fmt(t / np.linalg.norm(t))}"
    if t.size == 2:
        point = c + np.array([-t[1], t[0]]) / w[0]
        if np.linalg.norm(point - c) <= 1e3 * size:
            return f"rotation about {_fmt(point)}"
        return (
            f"translation along {_fmt(t / np.linalg.norm(t))} combined with a rotation "
            f"about {_fmt(c)}"
        )
    axis = w / np.linalg.norm(w)
    point = c + np.cross(w, t) / np.dot(w, w)
    along = np.dot(t, axis)
    text = f"rotation about the axis {_fmt(axis)} through {_fmt(point)}"
    if abs(along) > 1e-8 * scale:
        text += f" with a translation of {along + 0.0:.4g} along it"
    if np.linalg.norm(point - c) > 1e3 * size:
        text = f"translation along {_fmt(t / np.linalg.norm(t))} combined with a rotation"
    return text


@dataclass(frozen=True)
class UnsupportedMotion:
    """A combination of rigid motions resisted by nothing (Eq. 33 fails).

    Attributes:
        motions: The bodies that move, largest motion first (several when bodies are
            tied to each other by constraints but not to the ground).
        eigenvalue: Its normalized stiffness, below the threshold.
    """

    motions: tuple[RigidMotion, ...]
    eigenvalue: float

    @property
    def space(self) -> int:
        """Space index of the body that moves most."""
        return self.motions[0].space

    @property
    def component(self) -> int:
        """Component (body) label of the body that moves most."""
        return self.motions[0].component

    @property
    def description(self) -> str:
        """Description of the motion of the body that moves most."""
        return self.motions[0].description

    @property
    def coefficients(self) -> npt.NDArray[np.floating]:
        """Rigid mode coefficients of the body that moves most."""
        return self.motions[0].coefficients

    def displacement(self, x: npt.ArrayLike) -> npt.NDArray[np.floating]:
        """Displacement of the body that moves most at points ``x``."""
        return self.motions[0].displacement(x)

    def describe(self) -> str:
        """Text for an error message: which body can move how."""
        first, *others = self.motions
        text = f"{first.body()} can move freely: {first.description}"
        for other in others:
            text += f"; together with {other.body()}: {other.description}"
        return text


def unsupported_motions(
    spaces: Sequence[dolfinx.fem.FunctionSpace],
    stiffness: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec],
    constraints: Sequence[Sequence[tuple[int, PETSc.Mat]]],
    inactive: Sequence[npt.ArrayLike | None],
    *,
    labels: Sequence[npt.NDArray[np.int32] | None] | None = None,
    tol: float = UNSUPPORTED_TOL,
) -> list[UnsupportedMotion]:
    r"""Rigid motions of the bodies that nothing resists (Eq. 33 fails).

    A combination :math:`\mathbf R\alpha` of the rigid modes of all bodies
    (:func:`rigid_body_modes`) is unsupported iff it vanishes at the Dirichlet dofs,
    :math:`\mathbf B\mathbf R\alpha = 0` on the active multiplier rows of every pair,
    and :math:`(\mathbf R\alpha)^T\mathbf K(\mathbf R\alpha) = 0`. These are the null
    vectors of :math:`\mathbf G = \mathbf G_D + \mathbf G_B + \mathbf G_K` with

    * :math:`\mathbf G_D = \sum_{j \in D} \mathbf r_j\mathbf r_j^T/|\mathbf r_j|^2`, the
      rows :math:`\mathbf r_j` of :math:`\mathbf R` at the Dirichlet dofs;
    * :math:`\mathbf G_B = \sum_i \mathbf b_i\mathbf b_i^T/w_i` with
      :math:`\mathbf b_i = (\mathbf B\mathbf R)_i` and
      :math:`w_i = \sum_j B_{ij}^2|\mathbf r_j|^2`: scale-free, and (Cauchy-Schwarz)
      a row whose :math:`\mathbf b_i` is round-off stays round-off instead of being
      blown up to unit length;
    * :math:`\mathbf G_K = \mathbf S\mathbf R_f^T\mathbf K\mathbf R_f\mathbf S / k_{max}`
      with :math:`\mathbf R_f` the modes with Dirichlet rows zeroed, :math:`k_{max}`
      the largest diagonal entry of :math:`\mathbf K` at a free dof and
      :math:`S_{jj} = n^{1/(2d)}/|\mathbf R_{:j}|` for a mode of a body with :math:`n`
      nodes in dimension :math:`d`: the Rayleigh quotient of the motion relative to
      :math:`k_{max} h`, :math:`h \sim n^{-1/d}` (between the stiffest dof,
      :math:`k_{max}`, and the softest elastic mode, :math:`\sim k_{max} h^2`, of a body
      of unit size).

    :math:`\mathbf G` is block diagonal over groups of bodies coupled by constraints;
    each group's eigenvalues below ``tol * max(1, largest eigenvalue of the group)``
    give its unsupported motions, reported in a reduced echelon basis (a free body gives
    its translations along the axes and its rotation about its centroid). The work is
    :math:`O(\text{dofs})` sparse products plus dense algebra of the order of
    :math:`\mathbf G`.

    Args:
        spaces: Displacement spaces (vector Lagrange).
        stiffness: Assembled :math:`\mathbf K_i` of each space, Dirichlet rows and
            columns replaced by a unit diagonal (as
            ``dolfinx.fem.petsc.assemble_matrix(a, bcs=bcs)``).
        dirichlet_masks: Per space, 1 at free dofs and 0 at Dirichlet dofs.
        constraints: Per contact pair, its blocks ``(space index, B)`` with ``B`` the
            pair's multipliers by the space's dofs (not Dirichlet-eliminated).
        inactive: Per pair, global indices of the multiplier rows to ignore (each
            process may pass any subset; their union is used), or ``None``.
        labels: Per space, the component of each local cell (default
            :func:`connected_components` of the space's mesh). A component must be a
            union of connected components: no cell joins two, so that :math:`\mathbf K`
            has no entry between them.
        tol: Relative eigenvalue threshold.

    Returns:
        The unsupported motions, the same on every process; empty if Eq. (33) holds.
    """
    gram = support_gram(spaces, stiffness, dirichlet_masks, constraints, labels=labels, tol=tol)
    return gram.motions(inactive)


@dataclass(frozen=True)
class SupportGram:
    r"""The parts of :math:`\mathbf G` of :func:`unsupported_motions` (Eq. 33), kept.

    :math:`\mathbf G_D + \mathbf G_K` does not depend on which contact rows are active,
    and :math:`\mathbf G_B` is a sum over rows: :meth:`motions` checks any active set
    (an iteration of unilateral contact) with one small reduction, without :math:`\mathbf K`.

    Attributes:
        fixed: :math:`\mathbf G_D + \mathbf S\mathbf G_K\mathbf S`, the same on every process.
        rows: Per pair, the unit rows of :math:`\mathbf B\mathbf R` this process owns.
        ranges: Per pair, the global range of the rows this process owns.
        bodies: The bodies of every space.
        comm: The communicator.
        tol: Relative eigenvalue threshold.
    """

    fixed: npt.NDArray[np.floating]
    rows: list[scipy.sparse.csr_matrix | None]
    ranges: list[tuple[int, int]]
    bodies: list[Bodies]
    comm: MPI.Comm
    tol: float

    def motions(self, inactive: Sequence[npt.ArrayLike | None]) -> list[UnsupportedMotion]:
        """The unsupported motions with the rows ``inactive`` of each pair left out.

        Args:
            inactive: Per pair, global indices of the multiplier rows to ignore (each
                process may pass any subset; their union is used), or ``None``.

        Returns:
            The unsupported motions, the same on every process (collective).
        """
        G = np.zeros_like(self.fixed)
        for p, (Bn, (start, end)) in enumerate(zip(self.rows, self.ranges, strict=True)):
            listed = inactive[p] if p < len(inactive) else None
            listed = np.zeros(0, np.int64) if listed is None else np.asarray(listed, np.int64)
            listed = np.unique(np.concatenate(self.comm.allgather(listed.ravel())))
            if Bn is None:
                continue
            active = np.ones(end - start, dtype=np.bool_)
            active[listed[(listed >= start) & (listed < end)] - start] = False
            rows = Bn[active]
            G += (rows.T @ rows).toarray()
        G = self.comm.allreduce(G) + self.fixed
        G = self.comm.bcast(0.5 * (G + G.T), root=0)  # identical input: identical results
        return _null_motions(G, self.bodies, self.tol)


def support_gram(
    spaces: Sequence[dolfinx.fem.FunctionSpace],
    stiffness: Sequence[PETSc.Mat],
    dirichlet_masks: Sequence[PETSc.Vec],
    constraints: Sequence[Sequence[tuple[int, PETSc.Mat]]],
    *,
    labels: Sequence[npt.NDArray[np.int32] | None] | None = None,
    tol: float = UNSUPPORTED_TOL,
) -> SupportGram:
    """The :class:`SupportGram` of the arguments of :func:`unsupported_motions` (collective)."""
    comm = spaces[0].mesh.comm if spaces else MPI.COMM_SELF
    if len(spaces) == 0:
        return SupportGram(np.zeros((0, 0)), [], [], [], comm, tol)
    bodies = [body_set(V, None if labels is None else labels[s]) for s, V in enumerate(spaces)]
    offsets = np.cumsum([0] + [b.count * b.modes for b in bodies])
    N = int(offsets[-1])
    col_sizes = (N if comm.rank == 0 else 0, N)
    G = np.zeros((2, N, N))  # G_D, G_K

    R_petsc, q_petsc = [], []
    colnorm2 = np.zeros(N)
    kmax = []
    for s, b in enumerate(bodies):
        # Each owned dof carries the m modes of its own component only: the rigid modes
        # are the dense (n, m) values with column offset + component * m + mode.
        values, m = b.values(), b.modes
        dof_labels = np.repeat(b.labels, b.bs)
        n = values.shape[0]
        offset = int(offsets[s])
        cols = offset + dof_labels[:, None] * m + np.arange(m)[None, :]
        fixed = dirichlet_masks[s].array_r[:n] < 0.5
        rownorm2 = np.einsum("ik,ik->i", values, values)
        colnorm2 += np.bincount(cols.ravel(), weights=(values * values).ravel(), minlength=N)
        U = values[fixed] / np.sqrt(rownorm2[fixed])[:, None]
        _add_blocks(G[0], offset, dof_labels[fixed], b.count, U, U)
        # Energy of the motions over the free dofs: K is block diagonal over the
        # components (no cell joins two), so m products K (sum of mode k over all
        # components) give every component's block.
        free_values = np.where(fixed[:, None], 0.0, values)
        K = stiffness[s]
        x, y = K.createVecRight(), K.createVecLeft()
        KR = np.empty_like(free_values)
        for k in range(m):
            x.array[:] = free_values[:, k]
            K.mult(x, y)
            KR[:, k] = y.array_r
        x.destroy()
        y.destroy()
        _add_blocks(G[1], offset, dof_labels, b.count, free_values, KR)
        diag = K.getDiagonal()
        kmax.append(comm.allreduce(float(diag.array_r[:n][~fixed].max(initial=0.0)), op=MPI.MAX))
        diag.destroy()
        R = PETSc.Mat().createAIJ(
            size=((n, PETSc.DETERMINE), col_sizes),
            csr=(
                np.arange(0, n * m + 1, m, dtype=PETSc.IntType),
                cols.ravel().astype(PETSc.IntType),
                values.ravel(),
            ),
            comm=comm,
        )
        R.assemble()
        R_petsc.append(R)
        q_petsc.append(petsc_vector(comm, rownorm2, 1))

    rows: list[scipy.sparse.csr_matrix | None] = []
    ranges: list[tuple[int, int]] = []
    for pair in constraints:
        if len(pair) == 0:
            rows.append(None)
            ranges.append((0, 0))
            continue
        BR = None
        w = None
        for s, B in pair:
            P = B.matMult(R_petsc[s])
            part = csr_rows(P, N)
            P.destroy()
            indptr, indices, data = B.getValuesCSR()
            B2 = PETSc.Mat().createAIJ(
                size=B.getSizes(), csr=(indptr, indices, data * data), comm=comm
            )
            B2.assemble()
            wv = B2.createVecLeft()
            B2.mult(q_petsc[s], wv)
            w = wv.array_r.copy() if w is None else w + wv.array_r
            BR = part if BR is None else BR + part
            wv.destroy()
            B2.destroy()
        assert BR is not None and w is not None
        rows.append(unit_rows(BR, w).tocsr())
        ranges.append(pair[0][1].getOwnershipRange())
    for M in R_petsc:
        M.destroy()
    for v in q_petsc:
        v.destroy()

    G = comm.allreduce(G)
    colnorm2 = comm.allreduce(colnorm2)
    nodes = np.concatenate([np.repeat(b.nodes, b.modes) ** (0.5 / b.bs) for b in bodies])
    S = nodes / np.sqrt(np.where(colnorm2 > 0.0, colnorm2, 1.0))
    for s in range(len(spaces)):
        cols = slice(offsets[s], offsets[s + 1])
        if kmax[s] > 0.0:
            G[1][cols] /= kmax[s]
    fixed = G[0] + S[:, None] * G[1] * S[None, :]
    return SupportGram(fixed, rows, ranges, bodies, comm, tol)


def _add_blocks(
    G: npt.NDArray[np.floating],
    offset: int,
    labels: npt.NDArray[np.int32],
    count: int,
    left: npt.NDArray[np.floating],
    right: npt.NDArray[np.floating],
) -> None:
    r"""Add :math:`\sum_{i \in c} l_i r_i^T` to the block of each component ``c``.

    The block of component ``c`` holds rows and columns ``offset + c * m + (0..m-1)``.
    """
    m = left.shape[1]
    blocks = np.empty((count, m, m))
    for k in range(m):
        for j in range(m):
            blocks[:, k, j] = np.bincount(labels, weights=left[:, k] * right[:, j], minlength=count)
    index = offset + np.arange(count)[:, None] * m + np.arange(m)[None, :]
    G[index[:, :, None], index[:, None, :]] += blocks


def _null_motions(
    G: npt.NDArray[np.floating], bodies: list[Bodies], tol: float
) -> list[UnsupportedMotion]:
    # Columns -> (space, component); group the components coupled in G.
    owners = [(s, c) for s, b in enumerate(bodies) for c in range(b.count) for _ in range(b.modes)]
    keys = sorted(set(owners))
    index = {key: i for i, key in enumerate(keys)}
    column_body = np.array([index[o] for o in owners], dtype=np.int64)
    rows, cols = np.nonzero(G)
    coupling = scipy.sparse.coo_matrix(
        (np.ones(rows.size, dtype=np.int8), (column_body[rows], column_body[cols])),
        shape=(len(keys), len(keys)),
    )
    _, group = scipy.sparse.csgraph.connected_components(coupling, directed=False)
    motions = []
    for g in np.unique(group):
        columns = np.flatnonzero(group[column_body] == g)
        eigenvalues, vectors = scipy.linalg.eigh(G[np.ix_(columns, columns)])
        null = eigenvalues < tol * max(1.0, float(eigenvalues[-1]))
        if not null.any():
            continue
        for alpha in echelon(vectors[:, null]):
            alpha = alpha / np.linalg.norm(alpha)
            stiffness = float(alpha @ G[np.ix_(columns, columns)] @ alpha)
            parts = []
            for key in sorted({owners[j] for j in columns}):
                s, c = key
                b = bodies[s]
                local = np.array([j for j in range(columns.size) if owners[columns[j]] == key])
                coeff = alpha[local]
                size = np.linalg.norm(coeff)
                if size <= 1e-8:
                    continue
                t = coeff[: b.bs].copy()
                w = coeff[b.bs :] / b.size[c]
                parts.append(
                    (
                        -size,
                        RigidMotion(
                            space=s,
                            component=c,
                            coefficients=coeff,
                            translation=t,
                            rotation=w,
                            centroid=b.centroid[c],
                            bounding_box=np.stack([b.lower[c], b.upper[c]]),
                            description=_describe(t, w, b.centroid[c], float(b.size[c])),
                        ),
                    )
                )
            parts.sort(key=lambda item: item[0])
            motions.append(UnsupportedMotion(tuple(m for _, m in parts), stiffness))
    return motions


# --------------------------------------------------------------------------------------
# Redundant constraints (Eqs. 34-35)
# --------------------------------------------------------------------------------------

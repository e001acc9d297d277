# SPDX-License-Identifier: MIT
r"""The bases on facets: the facet's dofs only, no Basix per point; the blocks on faces.

On a face only its dofs' functions are nonzero, polynomials in :math:`Q_p` of the face
coordinates :math:`\xi` (:func:`~dolfinx_contact_s2s.faces.reference_vertices`): their
monomial coefficients are fitted once per local face from Basix's tabulation
(:func:`fit_monomials`; the multiplier's once per contactor face). :func:`face_blocks`
hands them to the kernels' ``face_coupling``, which integrates Eqs. (40)-(42) in one
pass over the points. On the edges of 2D cells the same holds with polynomials in the
edge's parameter (:func:`~dolfinx_contact_s2s.edges.facet_monomials`): the coupling
blocks carry the edge's dofs only, not the zero columns of the cell's other dofs.
"""

from __future__ import annotations

import weakref

import basix
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s import faces
from dolfinx_contact_s2s.compat import tabulate
from dolfinx_contact_s2s.edges import facet_monomials
from dolfinx_contact_s2s.kernels.face_backend import monomials

# Values below this are Basix's round-off, as ContactSurface.facet_basis drops them.
ROUNDOFF = 1e-12
_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def fit_monomials(element, degree: int, vertices: npt.NDArray[np.floating]) -> npt.NDArray:
    r"""Monomial coefficients of ``element``'s functions on faces, ``(G, (degree + 1)^2, dim)``.

    Face ``g`` is the map :math:`X_0 + \xi_1 (X_1 - X_0) + \xi_2 (X_2 - X_0)` of its
    reference ``vertices[g]`` ``(G, 3, D)``; the row :math:`j (p + 1) + i` holds the
    coefficient of :math:`\xi_1^i \xi_2^j`, fitted to Basix's tabulation (checked exact).
    """
    s = np.linspace(0.0, 1.0, degree + 2)
    grid = np.stack(np.meshgrid(s, s, indexing="ij"), axis=-1).reshape(-1, 2)
    V = monomials(grid, degree)
    v = np.asarray(vertices, dtype=np.float64)
    X = v[:, None, 0] + grid[None, :, :1] * (v[:, None, 1] - v[:, None, 0])
    X = X + grid[None, :, 1:] * (v[:, None, 2] - v[:, None, 0])
    table = tabulate(element, 0, X.reshape(-1, v.shape[2]))[0]
    table = table.reshape(v.shape[0], grid.shape[0], element.dim)  # explicit: G may be 0
    coef = np.einsum("mn,gnk->gmk", np.linalg.pinv(V), table)
    coef[np.abs(coef) < ROUNDOFF] = 0.0
    if not np.allclose(np.einsum("nm,gmk->gnk", V, coef), table, rtol=0.0, atol=1e-13):
        raise ValueError("the basis on a face is not in Q_p of its coordinates")
    return coef


class FaceBasis:
    """Monomial coefficients ``coef[f]`` of the nonzero functions ``cols[f]`` on face ``f``."""

    def __init__(self, element, cell) -> None:
        """Fit ``element``'s functions on each face of ``cell`` (exact: checked)."""
        p = element.degree
        self.powers = np.array([(i, j) for j in range(p + 1) for i in range(p + 1)])
        coef, cols = [], []
        for c in fit_monomials(element, p, faces.reference_vertices(cell)):
            keep = np.flatnonzero(np.any(c != 0.0, axis=0))
            coef.append(c[:, keep])
            cols.append(keep)
        if len({k.size for k in cols}) != 1:
            raise ValueError("faces with different numbers of dofs")
        self.coef = np.stack(coef)
        self.cols = np.stack(cols).astype(np.int64)
        self.dofs: dict[int, tuple] = {}  # by _face_dofs

    def monomials(self, xi: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        r""":math:`\xi_1^i \xi_2^j` at points ``xi``, ``(n, (p + 1)^2)``."""
        return xi[:, :1] ** self.powers[:, 0] * xi[:, 1:2] ** self.powers[:, 1]

    def values(
        self, local_facet: npt.NDArray[np.int32], xi: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        """The functions ``cols[local_facet]`` at face coordinates ``xi``, ``(n, nf)``."""
        M = self.monomials(xi)
        out = np.empty((xi.shape[0], self.cols.shape[1]))
        for f in range(self.coef.shape[0]):
            on = np.flatnonzero(local_facet == f)
            if on.size:
                out[on] = M[on] @ self.coef[f]
        out[np.abs(out) < ROUNDOFF] = 0.0
        return out


class EdgeBasis:
    """Coefficients ``table[l]`` in the edge parameter of the functions ``cols[l]`` on edge l."""

    def __init__(self, element, cell) -> None:
        """Keep, on each reference edge of ``cell``, the functions of ``element`` nonzero on it."""
        x = basix.geometry(cell)
        ends = np.array(basix.topology(cell)[1])
        table = facet_monomials(element, x[ends[:, 0]], x[ends[:, 1]])
        cols = [np.flatnonzero(np.any(t != 0.0, axis=0)) for t in table]
        if len({c.size for c in cols}) != 1:
            raise ValueError("edges with different numbers of dofs")
        self.cols = np.stack(cols).astype(np.int64)
        self.table = np.ascontiguousarray(np.take_along_axis(table, self.cols[:, None], axis=2))
        self.dofs: dict[int, tuple] = {}  # by _face_dofs


def _basis(surface) -> FaceBasis | EdgeBasis:
    """The :class:`FaceBasis` (:class:`EdgeBasis`) of a surface's element, once per surface."""
    basis = _CACHE.get(surface)
    if basis is None:
        kind = FaceBasis if surface.facet_dim == 2 else EdgeBasis
        basis = _CACHE[surface] = kind(surface.element, surface.cell_type)
    return basis


def face_nodes(surface) -> npt.NDArray[np.int64]:
    """The displacement nodes of each local facet of the surface's cell, in facet-dof order."""
    return _basis(surface).cols


def _face_dofs(surface, data, groups, basis) -> npt.NDArray[np.int64]:
    """The unrolled dofs of the functions ``basis.cols`` of each group's facet.

    From the dofs of every facet of ``data``, kept for the last two ``data`` of the
    surface (its own facets and those it is gathered as).
    """
    kept = basis.dofs.get(id(data))
    if kept is None or kept[0] is not data:
        bs = surface.V.dofmap.index_map_bs
        unrolled = (basis.cols[:, :, None] * bs + np.arange(bs)).reshape(len(basis.cols), -1)
        flat = unrolled[data.local_facet]
        flat += (np.arange(len(data), dtype=np.int64) * data.dofs.shape[1])[:, None]
        kept = (data, np.take(data.dofs.reshape(-1), flat))
        basis.dofs = {k: v for k, v in list(basis.dofs.items())[-1:]} | {id(data): kept}
    return kept[1][groups]


def face_basis(surface, data, groups, nq, xi):
    """The scalar basis at the points of ``groups`` (``nq`` each) and their unrolled dofs.

    Returns ``(phi, dofs)``: ``(len(groups) * nq, nf)`` and ``(len(groups), nf * bs)``, the
    facet's own ``nf`` dofs (:func:`face_nodes`).
    """
    basis = _basis(surface)
    lf = data.local_facet[groups]
    xi = np.ascontiguousarray(xi, dtype=np.float64)
    if isinstance(basis, EdgeBasis):
        phi = surface.backend.facet_basis(basis.table, np.repeat(lf, nq), xi)
    else:
        phi = basis.values(np.repeat(lf, nq), xi)
    return phi, _face_dofs(surface, data, groups, basis)


def face_blocks(
    multiplier, contactor, C, target, T, groups, tangent=None
) -> tuple[npt.NDArray, ...]:
    """The local blocks of Eqs. (40)-(42) on faces, by the kernels' ``face_coupling``.

    Args:
        multiplier: The pair's :class:`~dolfinx_contact_s2s.multiplier.MultiplierSpace`.
        contactor: The contactor surface.
        C: Its data.
        target: The target surface.
        T: The target data cut against.
        groups: The :class:`~dolfinx_contact_s2s.discretizations.PointGroups`.
        tangent: ``(axis, which)`` for friction's tangential coupling (``face_coupling``).

    Returns:
        ``(rows, dofs_c, b_c, dofs_t, b_t, gap, coverage)``, the fields of
        :class:`~dolfinx_contact_s2s.pair.CouplingBlocks`, one block per run of
        consecutive groups on the same pair of faces (their sum).
    """
    sides = ((contactor, C, groups.contactor), (target, T, groups.target))
    bases = [_basis(surface) for surface, _, _ in sides]
    lfs = [data.local_facet[rows] for _, data, rows in sides]
    mu = (multiplier.face_coefficients, groups.contactor)
    first = np.zeros(0, dtype=np.int32)
    if len(groups.contactor):
        b_c, b_t, gap, coverage, first = contactor.backend.face_coupling(
            C.coefficients,
            C.orientation,
            T.coefficients,
            (groups.contactor, groups.target),
            groups.xi,
            groups.weights,
            (mu, *((b.coef, lf) for b, lf in zip(bases, lfs, strict=True))),
            square=True,
            zero_below=ROUNDOFF,
            tangent=tangent,
        )
    dofs = [
        _face_dofs(surface, data, rows[first], basis)
        for (surface, data, rows), basis in zip(sides, bases, strict=True)
    ]
    if first.size == 0:  # Explicit sizes: a rank may have no groups.
        nk = mu[0].shape[2]
        b_c, b_t = (np.zeros((0, nk, d.shape[1])) for d in dofs)
        gap = coverage = np.zeros((0, nk))
    return groups.rows[first], dofs[0], b_c, dofs[1], b_t, gap, coverage


def edge_blocks(multiplier, contactor, C, target, T, groups, square, tangent=None) -> tuple:
    r"""The local blocks of Eqs. (40)-(42) on edges, by the C kernels' ``edge_coupling``.

    The fields of :class:`~dolfinx_contact_s2s.pair.CouplingBlocks` after the target,
    as :func:`face_blocks`, with ``signed``; the groups' points and weights are those of
    Eq. (40) without a ring weight (not in axisymmetry). ``square``: coverage of
    :math:`\mu_k^2`.
    """
    mu = multiplier.edge_table[0]
    if multiplier.dual:
        mu = mu @ multiplier.dual_coefficients.T
    bases = [_basis(contactor), _basis(target)]
    b_c, b_t, gap, signed, coverage = contactor.backend.edge_coupling(
        (C.coefficients, C.orientation),
        T.coefficients,
        (groups.contactor, groups.target),
        groups.xi,
        groups.weights,
        ((mu, multiplier.flip), (bases[0].table, C.local_facet), (bases[1].table, T.local_facet)),
        square,
        tangent is not None,
    )
    dofs = [
        _face_dofs(s, data, rows, b)
        for s, data, rows, b in zip(
            (contactor, target), (C, T), (groups.contactor, groups.target), bases, strict=True
        )
    ]
    return groups.rows, dofs[0], b_c, dofs[1], b_t, gap, coverage, signed

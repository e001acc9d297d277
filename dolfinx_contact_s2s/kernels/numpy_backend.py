# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""NumPy reference backend of the contact kernels.

Facet geometry works on *facet coefficients*: along a straight reference facet
:math:`X(\xi) = X_a + \xi (X_b - X_a)` the coordinate map of a degree-:math:`p`
Lagrange cell is a polynomial of degree :math:`p` in :math:`\xi`, so each facet is
stored as :math:`x(\xi) = \sum_m c_m \xi^m` with ``coefficients[f, m, :]`` :math:`= c_m`
(computed once from the coordinate element's Basix tables and the cell's nodes by
:func:`facet_coefficients`). Points, tangents, second derivatives, normals and the two
Newton solves then need no tabulation at all, which is what a compiled backend needs.

Every function takes C-contiguous ``float64`` arrays and ``int32`` row indices and
returns new arrays; ``rows`` selects one facet per point.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = [
    "cell_normals",
    "evaluate",
    "facet_coefficients",
    "intersect",
    "outward_normals",
    "project",
    "segment_to_segment",
]

_Array = npt.NDArray[np.float64]


def facet_coefficients(basis: _Array, local_facet: npt.NDArray[np.int32], coords: _Array) -> _Array:
    r"""Monomial coefficients of the facets' geometry in the facet parameter :math:`\xi`.

    Args:
        basis: Coefficients of the coordinate element's basis functions along each
            reference facet, ``basis[l, m, k]`` the :math:`\xi^m` coefficient of
            :math:`\phi_k(X_l(\xi))`, shape ``(num_reference_facets, p + 1, K)``.
        local_facet: Local facet index of each facet in its cell, shape ``(F,)``.
        coords: Cell geometry nodes of each facet, shape ``(F, K, gdim)``.

    Returns:
        ``(F, p + 1, gdim)``.
    """
    return np.einsum("fmk,fkg->fmg", basis[local_facet], coords)


def _horner(c: _Array, xi: _Array) -> _Array:
    """Value of the polynomials ``sum_m c[:, m] xi^m``, shape ``(P, gdim)``."""
    value = c[:, -1].copy()
    for m in range(c.shape[1] - 2, -1, -1):
        value = value * xi[:, None] + c[:, m]
    return value


def evaluate(
    coefficients: _Array, rows: npt.NDArray[np.int32], xi: _Array, derivatives: int = 1
) -> tuple[_Array, ...]:
    r"""Points and derivatives along facets.

    Args:
        coefficients: Facet coefficients, ``(F, p + 1, gdim)``.
        rows: Facet of each point, ``(P,)``.
        xi: Facet parameter of each point, ``(P,)``.
        derivatives: 1 for :math:`(x, x')`, 2 for :math:`(x, x', x'')`.

    Returns:
        Arrays of shape ``(P, gdim)``.
    """
    c = coefficients[rows]
    powers = np.arange(c.shape[1], dtype=np.float64)[None, :, None]
    x = _horner(c, xi)
    dc = (c * powers)[:, 1:]
    if dc.shape[1] == 0:
        dc = np.zeros_like(c[:, :1])
    dx = _horner(dc, xi)
    if derivatives == 1:
        return x, dx
    ddc = (dc * (powers[:, : dc.shape[1]]))[:, 1:]
    ddx = _horner(ddc, xi) if ddc.shape[1] else np.zeros_like(x)
    return x, dx, ddx


def cell_normals(tables: _Array, coords: _Array, reference_normals: _Array) -> _Array:
    r"""Unit outward normals :math:`J^{-T} \hat n / |J^{-T} \hat n|` from the cell map.

    Args:
        tables: First derivatives of the coordinate basis at the points,
            ``(tdim, P, K)``.
        coords: Cell geometry nodes of each point, ``(P, K, gdim)``.
        reference_normals: Outward normal of the reference facet of each point,
            ``(P, tdim)``.

    Returns:
        ``(P, gdim)``.
    """
    J = np.einsum("pkg,dpk->pgd", coords, tables)
    n = np.linalg.solve(np.swapaxes(J, 1, 2), reference_normals[:, :, None])[:, :, 0]
    return n / np.linalg.norm(n, axis=1)[:, None]


def outward_normals(
    coefficients: _Array,
    orientation: _Array,
    rows: npt.NDArray[np.int32],
    xi: _Array,
) -> _Array:
    r"""Unit outward normals of 2D facets, the tangent :math:`x'` turned by a right angle.

    In 2D :math:`J^{-T}\hat n` is orthogonal to :math:`x' = J (X_b - X_a)`, so the normal
    is :math:`\pm (x'_1, -x'_0) / |x'|`; the sign of each facet (``orientation``, from
    :func:`cell_normals` once) makes it point out of the cell.

    Args:
        coefficients: Facet coefficients, ``(F, p + 1, 2)``.
        orientation: ``+1`` or ``-1`` per facet, ``(F,)``.
        rows: Facet of each point, ``(P,)``.
        xi: Facet parameter of each point, ``(P,)``.

    Returns:
        ``(P, 2)``.
    """
    _, dx = evaluate(coefficients, rows, xi)
    n = np.stack([dx[:, 1], -dx[:, 0]], axis=1) * orientation[rows, None]
    return n / np.linalg.norm(n, axis=1)[:, None]


def project(
    coefficients: _Array,
    rows: npt.NDArray[np.int32],
    points: _Array,
    iterations: int = 8,
) -> _Array:
    r"""Closest-point parameters :math:`\xi` of ``points`` on the (extended) facets.

    Solves :math:`(x(\xi) - p) \cdot x'(\xi) = 0` by Newton's method from
    :math:`\xi = 1/2`, stopping when every step is below :math:`10^{-15}`; one step
    is exact on straight facets.
    """
    xi = np.full(rows.size, 0.5)
    for _ in range(iterations):
        x, dx, ddx = evaluate(coefficients, rows, xi, derivatives=2)
        r = x - points
        f = np.einsum("pg,pg->p", r, dx)
        df = np.einsum("pg,pg->p", dx, dx) + np.einsum("pg,pg->p", r, ddx)
        step = f / df
        xi = xi - step
        if np.all(np.abs(step) < 1e-15):
            break
    return xi


def intersect(
    coefficients: _Array,
    rows: npt.NDArray[np.int32],
    origins: _Array,
    directions: _Array,
    iterations: int = 8,
) -> _Array:
    r"""Parameters :math:`\eta` where the lines ``origins + t * directions`` cross the facets.

    Solves :math:`(x(\eta) - o) \times N = 0` by Newton's method from :math:`\eta = 1/2`
    (Eq. 38, Fig. 7(b)), stopping when every step is below :math:`10^{-15}`.
    """
    perp = np.stack([-directions[:, 1], directions[:, 0]], axis=1)
    eta = np.full(rows.size, 0.5)
    for _ in range(iterations):
        x, dx = evaluate(coefficients, rows, eta)
        f = np.einsum("pg,pg->p", x - origins, perp)
        df = np.einsum("pg,pg->p", dx, perp)
        step = f / df
        eta = eta - step
        if np.all(np.abs(step) < 1e-15):
            break
    return eta


def segment_to_segment(
    mu: _Array,
    phi_c: _Array,
    phi_t: _Array,
    normals: _Array,
    weights: _Array,
    gaps: _Array,
) -> tuple[_Array, _Array, _Array]:
    r"""Local coupling blocks of Eqs. (40)-(42) on a batch of (sub-)segments.

    For sub-segment :math:`s` with integration points :math:`i`, multiplier basis
    :math:`H^{ik}_C` (Eq. 42), contactor basis :math:`h^{ij}_C` (Eq. 41), target basis
    :math:`h^{ij}_T` at the target points :math:`x^{i*}_T` (Eq. 38), normal
    :math:`N^i` and weight :math:`w^i`:

    .. math::
        B_C[s, k, j c] = \sum_i w^i H^{ik}_C h^{ij}_C N^i_c, \quad
        B_T[s, k, j c] = -\sum_i w^i H^{ik}_C h^{ij}_T N^i_c, \quad
        G[s, k] = \sum_i w^i H^{ik}_C g_0^{i}.

    Args:
        mu: Multiplier basis, shape ``(S, Q, nk)``.
        phi_c: Contactor displacement basis (scalar), shape ``(S, Q, nc)``.
        phi_t: Target displacement basis (scalar), shape ``(S, Q, nt)``.
        normals: Contact normals :math:`N`, shape ``(S, Q, gdim)``.
        weights: Quadrature weights including the facet Jacobian, shape ``(S, Q)``.
        gaps: Initial gap :math:`g_0` at the points, shape ``(S, Q)``.

    Returns:
        ``(B_C, B_T, G)`` of shapes ``(S, nk, nc * gdim)``, ``(S, nk, nt * gdim)`` and
        ``(S, nk)``; displacement columns are blocked as ``j * gdim + c``, the
        interleaved layout of DOLFINx vector spaces.
    """
    S, _, nk = mu.shape
    gdim = normals.shape[2]
    wmu = mu * weights[:, :, None]
    b_c = np.einsum("sqk,sqj,sqc->skjc", wmu, phi_c, normals).reshape(S, nk, phi_c.shape[2] * gdim)
    b_t = -np.einsum("sqk,sqj,sqc->skjc", wmu, phi_t, normals).reshape(S, nk, phi_t.shape[2] * gdim)
    g = np.einsum("sqk,sq->sk", wmu, gaps)
    return b_c, b_t, g

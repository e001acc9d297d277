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

Projections, intersections and clipping work relative to a local origin, the first
point :math:`c_0 = x(0)` of the facet a point is projected on (:func:`_local`): the
Newton residuals :math:`x(\xi) - p` are then differences of numbers of the size of the
facet, not of the scene's coordinates, and a scene translated far from the origin
gives the same parameters up to the round-off of the translation itself.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = [
    "DEGENERATE_TOLERANCE",
    "FACET_DIM",
    "NEWTON_TOL",
    "ROUND_OFF",
    "bounding_boxes",
    "box_overlaps",
    "cell_normals",
    "clip_segments",
    "coo_to_csr",
    "csr_slots",
    "evaluate",
    "facet_basis",
    "facet_coefficients",
    "intersect",
    "outward_normals",
    "project",
    "segment_to_segment",
    "shift",
]

_Array = npt.NDArray[np.float64]

#: Relative Newton stopping test: stop after a step :math:`|\delta| \le` ``NEWTON_TOL``
#: :math:`(1 + |\xi|)`. Newton converges quadratically, so the error left after such a
#: step is of the order of its square, far below round-off.
NEWTON_TOL = 1e-10

#: Relative round-off of a projected node, in units of the coordinates' magnitude: a
#: sub-segment no longer than this (times the coordinates' magnitude over the facet's
#: chord, in the facet parameter) is a sliver made by round-off, between nodes that
#: coincide, and is dropped (:func:`clip_segments`).
ROUND_OFF = 32 * np.finfo(np.float64).eps

#: A contact facet whose chord (edges) or corner area (faces) is smaller than this
#: fraction of its cell's extent (squared) is degenerate (nodes coincide): it has no normal.
DEGENERATE_TOLERANCE = 1e-12

#: Topological dimension of the facets these kernels handle: edges of 2D cells,
#: parametrised by :math:`\xi \in [0, 1]`.
FACET_DIM = 1


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


def shift(coefficients: _Array, offset: _Array) -> _Array:
    """The facets moved by ``offset`` ``(F, gdim)``: their constant coefficient (a new array)."""
    moved = coefficients.copy()
    moved[:, 0] += offset
    return moved


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


def facet_basis(table: _Array, local_facet: npt.NDArray[np.int32], xi: _Array) -> _Array:
    r"""Scalar basis functions restricted to reference facets, from their monomial coefficients.

    A degree-:math:`k` Lagrange basis function restricted to a straight reference facet
    is a polynomial of degree :math:`k` in the facet parameter, so no tabulation at
    mapped reference points is needed (the bases :math:`h^{ij}` and :math:`H^{ik}` of
    Eqs. 41-42).

    Args:
        table: ``table[l, m, k]``, the :math:`\xi^m` coefficient of basis function
            :math:`k` along reference facet :math:`l`, ``(L, m_max + 1, K)``.
        local_facet: Reference facet of each point, ``(P,)``.
        xi: Facet parameter of each point, ``(P,)``.

    Returns:
        ``(P, K)``.
    """
    c = table[local_facet]
    value = c[:, -1].copy()
    for m in range(c.shape[1] - 2, -1, -1):
        value = value * xi[:, None] + c[:, m]
    return value


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


def _local(
    coefficients: _Array, rows: npt.NDArray[np.int32], *points: _Array
) -> tuple[_Array, npt.NDArray[np.int32], list[_Array]]:
    r"""Each point's facet relative to its first point :math:`c_0`, and the points too.

    Returns:
        The coefficients of facet ``rows[p]`` with :math:`c_0` removed, one row per
        point ``(P, p + 1, gdim)``, the rows ``0..P-1`` selecting them, and each array of
        ``points`` minus :math:`c_0`.
    """
    local = coefficients[rows]
    origin = local[:, 0].copy()
    local[:, 0] = 0.0
    return local, np.arange(rows.size, dtype=np.int32), [p - origin for p in points]


def _converged(step: _Array, xi: _Array, tol: float) -> bool:
    """Whether every Newton step passes the relative test (also for no points)."""
    return bool(np.all(np.abs(step) <= tol * (1.0 + np.abs(xi))))


def project(
    coefficients: _Array,
    rows: npt.NDArray[np.int32],
    points: _Array,
    iterations: int = 8,
    tol: float = NEWTON_TOL,
) -> _Array:
    r"""Closest-point parameters :math:`\xi` of ``points`` on the (extended) facets.

    Solves :math:`(x(\xi) - p) \cdot x'(\xi) = 0` by Newton's method from
    :math:`\xi = 1/2`, stopping after at most ``iterations`` steps, or once every step
    :math:`\delta` satisfies :math:`|\delta| \le` ``tol`` :math:`(1 + |\xi|)`; one step is
    exact on straight facets (the second one then stops the loop). Relative to the
    facet's first point (see the module docstring).
    """
    coefficients, rows, (points,) = _local(coefficients, rows, points)
    xi = np.full(rows.size, 0.5)
    for _ in range(iterations):
        x, dx, ddx = evaluate(coefficients, rows, xi, derivatives=2)
        r = x - points
        f = np.einsum("pg,pg->p", r, dx)
        df = np.einsum("pg,pg->p", dx, dx) + np.einsum("pg,pg->p", r, ddx)
        step = f / df
        xi = xi - step
        if _converged(step, xi, tol):
            break
    return xi


def intersect(
    coefficients: _Array,
    rows: npt.NDArray[np.int32],
    origins: _Array,
    directions: _Array,
    iterations: int = 8,
    tol: float = NEWTON_TOL,
) -> _Array:
    r"""Parameters :math:`\eta` where the lines ``origins + t * directions`` cross the facets.

    Solves :math:`(x(\eta) - o) \times N = 0` by Newton's method from :math:`\eta = 1/2`
    (Eq. 38, Fig. 7(b)), with the stopping test of :func:`project`, relative to the
    facet's first point.
    """
    coefficients, rows, (origins,) = _local(coefficients, rows, origins)
    perp = np.stack([-directions[:, 1], directions[:, 0]], axis=1)
    eta = np.full(rows.size, 0.5)
    for _ in range(iterations):
        x, dx = evaluate(coefficients, rows, eta)
        f = np.einsum("pg,pg->p", x - origins, perp)
        df = np.einsum("pg,pg->p", dx, perp)
        step = f / df
        eta = eta - step
        if _converged(step, eta, tol):
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


def clip_segments(
    c_coefficients: _Array,
    c_orientation: _Array,
    t_coefficients: _Array,
    t_orientation: _Array,
    ic: npt.NDArray[np.int32],
    it: npt.NDArray[np.int32],
    radius: float,
    min_length: float,
    round_off: float = ROUND_OFF,
    iterations: int = 8,
    tol: float = NEWTON_TOL,
) -> tuple[_Array, _Array, npt.NDArray[np.bool_]]:
    r"""The sub-segment of each candidate pair of facets (Fig. 15(b)).

    The target facet's end nodes are projected onto the contactor facet
    (:func:`project`); the sub-segment is the part of :math:`[0, 1]` between them. A
    pair is kept when the facets' outward normals (at their middles) oppose, the piece
    is longer than ``min_length`` and than the round-off of the projections,
    ``round_off`` :math:`(s + L) / L` with :math:`L` the contactor facet's chord and
    :math:`s` the largest coordinate of its ends (a sliver between coinciding nodes),
    and its middle lies within ``radius`` of the target facet's middle along the
    contactor normal. Both facets are taken relative to the contactor facet's first
    point.

    Args:
        c_coefficients: Contactor facet coefficients, ``(Fc, pc + 1, 2)``.
        c_orientation: Contactor orientation signs, ``(Fc,)``.
        t_coefficients: Target facet coefficients, ``(Ft, pt + 1, 2)``.
        t_orientation: Target orientation signs, ``(Ft,)``.
        ic: Contactor facet of each pair, ``(N,)``.
        it: Target facet of each pair, ``(N,)``.
        radius: Largest normal distance.
        min_length: Shortest piece kept, in the contactor parameter.
        round_off: Relative round-off of a projected point (see :data:`ROUND_OFF`).
        iterations: Newton iterations of the projection at most.
        tol: Relative Newton stopping test.

    Returns:
        ``(lo, hi, keep)``, each ``(N,)``.
    """
    half = np.full(ic.size, 0.5)
    n_c = outward_normals(c_coefficients, c_orientation, ic, half)
    n_t = outward_normals(t_coefficients, t_orientation, it, half)
    facing = np.einsum("pg,pg->p", n_c, n_t) < 0.0
    c0 = c_coefficients[ic, 0]
    c1 = evaluate(c_coefficients, ic, np.ones(ic.size))[0]
    # Both facets of each pair relative to the contactor's first point.
    c_local, rows, _ = _local(c_coefficients, ic)
    t_local = t_coefficients[it]
    t_local[:, 0] -= c0
    # Only the corner (edge) nodes bound sub-segments, also for quadratic facets.
    xa = evaluate(t_local, rows, np.zeros(it.size))[0]
    xb = evaluate(t_local, rows, np.ones(it.size))[0]
    xi_a = project(c_local, rows, xa, iterations, tol)
    xi_b = project(c_local, rows, xb, iterations, tol)
    lo = np.clip(np.minimum(xi_a, xi_b), 0.0, 1.0)
    hi = np.clip(np.maximum(xi_a, xi_b), 0.0, 1.0)
    xm = evaluate(c_local, rows, 0.5 * (lo + hi))[0]
    xt = evaluate(t_local, rows, half)[0]
    near = np.abs(np.einsum("pg,pg->p", xt - xm, n_c)) <= radius
    chord = np.hypot(c1[:, 0] - c0[:, 0], c1[:, 1] - c0[:, 1])
    # The round-off of the nodes themselves grows with the scene's coordinates.
    scale = np.maximum(
        np.max(np.abs(c0), axis=1, initial=0.0), np.max(np.abs(c1), axis=1, initial=0.0)
    )
    shortest = np.maximum(min_length, round_off * (scale + chord) / chord)
    keep = facing & (hi - lo > shortest) & near
    lo = np.where(facing, lo, 0.0)
    hi = np.where(facing, hi, 0.0)
    return lo, hi, keep


def bounding_boxes(coefficients: _Array, samples: int, pad: float) -> _Array:
    """Axis-aligned boxes of 2D facets from equispaced sample points.

    The samples bound a straight facet (higher coefficients exactly zero) exactly; the
    box of a curved facet is padded to cover its bulge between samples.

    Args:
        coefficients: Facet coefficients, ``(F, p + 1, 2)``.
        samples: Sample points per facet (both ends included).
        pad: The box of a curved facet grows by ``pad`` times its diagonal in every
            direction.

    Returns:
        Lower and upper corners, ``(F, 2, 2)``.
    """
    n = coefficients.shape[0]
    rows = np.repeat(np.arange(n, dtype=np.int32), samples)
    xi = np.tile(np.linspace(0.0, 1.0, samples), n)
    x = evaluate(coefficients, rows, xi)[0].reshape(n, samples, 2)
    lo, hi = x.min(axis=1, initial=np.inf), x.max(axis=1, initial=-np.inf)
    width = np.sqrt(np.sum((hi - lo) ** 2, axis=1))[:, None]
    width[np.all(coefficients[:, 2:] == 0.0, axis=(1, 2))] = 0.0
    return np.stack([lo - pad * width, hi + pad * width], axis=1)


def box_overlaps(
    a: _Array,
    b: _Array,
    order: npt.NDArray[np.int64],
    start: npt.NDArray[np.int64],
    stop: npt.NDArray[np.int64],
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
    """The overlapping pairs among the candidates of a sweep and prune.

    Args:
        a: Boxes ``(na, 2, gdim)`` (lower and upper corners).
        b: Boxes ``(nb, 2, gdim)``.
        order: The boxes of ``b`` in the sweep's order.
        start: First candidate of each box of ``a`` in ``order``, ``(na,)``.
        stop: One past its last candidate (none if ``stop <= start``), ``(na,)``.

    Returns:
        ``(ia, ib)``: the overlapping pairs, by ``ia`` then in the order of ``order``.
    """
    counts = np.maximum(stop - start, 0)
    ia = np.repeat(np.arange(a.shape[0], dtype=np.int32), counts)
    offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    ib = order[np.repeat(start, counts) + offsets].astype(np.int32)
    overlap = np.all((a[ia, 0] <= b[ib, 1]) & (b[ib, 0] <= a[ia, 1]), axis=1)
    return ia[overlap], ib[overlap]


def coo_to_csr(
    num_rows: int, rows: npt.NDArray[np.int64], cols: npt.NDArray[np.int64], values: _Array
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], _Array]:
    """Sum the entries ``values`` at ``(rows, cols)`` into a CSR matrix with sorted columns.

    Args:
        num_rows: Number of rows; ``0 <= rows < num_rows``.
        rows: Row of each entry, ``(n,)``.
        cols: Column of each entry (nonnegative), ``(n,)``.
        values: The entries, ``(n,)``; duplicates are summed.

    Returns:
        ``(indptr, indices, data)``.
    """
    rows = np.asarray(rows, dtype=np.int64)
    cols = np.asarray(cols, dtype=np.int64)
    if rows.size and (rows.min() < 0 or rows.max() >= num_rows):
        raise ValueError("row index out of range")
    width = int(cols.max(initial=-1)) + 1
    keys, inverse = np.unique(rows * width + cols, return_inverse=True)
    data = np.bincount(inverse.reshape(-1), weights=values, minlength=keys.size)
    local_rows, indices = np.divmod(keys, max(width, 1))
    indptr = np.searchsorted(local_rows, np.arange(num_rows + 1)).astype(np.int64)
    return indptr, indices.astype(np.int64), data


def csr_slots(
    indptr: npt.NDArray[np.int64],
    indices: npt.NDArray[np.int64],
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
) -> npt.NDArray[np.int64]:
    """Position in ``indices`` of each entry ``(rows[e], cols[e])`` of a CSR structure.

    The structure's columns are sorted in each row (:func:`coo_to_csr`'s), so that the
    values of entries at those indices are summed into it by
    ``np.bincount(slots, values, indices.size)``.

    Raises:
        ValueError: If an entry is not in the structure.
    """
    rows = np.asarray(rows, dtype=np.int64)
    cols = np.asarray(cols, dtype=np.int64)
    if rows.size and (rows.min() < 0 or rows.max() >= indptr.size - 1):
        raise ValueError("row index out of range")
    width = int(max(indices.max(initial=-1), cols.max(initial=-1))) + 1
    keys = np.repeat(np.arange(indptr.size - 1, dtype=np.int64), np.diff(indptr)) * width
    keys += indices
    slots = np.minimum(np.searchsorted(keys, rows * width + cols), max(keys.size - 1, 0))
    if rows.size and not np.array_equal(keys[slots], rows * width + cols):
        raise ValueError("an entry is not in the CSR structure")
    return slots

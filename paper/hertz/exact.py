# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The Hertz line contact: exact plane-strain solution and measurements of a multiplier.

Two cylinders of radii :math:`R_1, R_2` (:math:`R_2 = \infty` for a flat body) pressed
together by a force :math:`F` per unit length touch over :math:`|x| \le a` with the
elliptical pressure (Johnson, *Contact Mechanics*, 1985, sections 4.2 and 5.4)

.. math:: p(x) = p_0 \sqrt{1 - x^2 / a^2}, \quad
    a = 2 \sqrt{\frac{F R}{\pi E^*}}, \quad p_0 = \frac{2 F}{\pi a},

with :math:`1/E^* = (1 - \nu_1^2)/E_1 + (1 - \nu_2^2)/E_2` and
:math:`1/R = 1/R_1 + 1/R_2`. :func:`measure` reads the half-width, the peak pressure
and the :math:`L^2` error of the pressure from a contact multiplier (a pressure on the
contactor facets, Eq. 16), with :math:`x` the horizontal coordinate and
:math:`dx = |dx/ds|\, ds` the horizontal measure along the (curved) contactor.
"""

from __future__ import annotations

import math
import typing
from dataclasses import dataclass

import basix
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import blocked_sub_element, geometry_dofmap

__all__ = ["Hertz", "HertzMeasures", "measure", "pressure_l2_error"]

#: Gauss points per (half) cell of the integrals in :func:`measure`.
_POINTS = 12


@dataclass(frozen=True)
class Hertz:
    r"""The plane-strain Hertz line contact of two cylinders (or a cylinder and a block).

    Attributes:
        E1: Young's modulus :math:`E_1` of the first body.
        nu1: Poisson's ratio :math:`\nu_1` of the first body.
        E2: Young's modulus :math:`E_2` of the second body.
        nu2: Poisson's ratio :math:`\nu_2` of the second body.
        R1: Radius :math:`R_1` of the first body.
        R2: Radius :math:`R_2` of the second body; ``math.inf`` for a flat body.
        F: Force per unit length :math:`F` pressing the bodies together.
    """

    E1: float
    nu1: float
    E2: float
    nu2: float
    R1: float
    R2: float
    F: float

    def __post_init__(self):
        """Check the data."""
        for name in ("E1", "E2"):
            if not (getattr(self, name) > 0.0 and math.isfinite(getattr(self, name))):
                raise ValueError(f"{name} must be positive and finite")
        for name in ("nu1", "nu2"):
            if not -1.0 < getattr(self, name) < 0.5:
                raise ValueError(f"{name} must lie in (-1, 0.5)")
        if not (self.R1 > 0.0 and self.R2 > 0.0) or math.isinf(self.R1):
            raise ValueError("R1 must be positive and finite, R2 positive (math.inf: flat)")
        if not (self.F >= 0.0 and math.isfinite(self.F)):
            raise ValueError("the force F must be non-negative and finite")

    @classmethod
    def for_half_width(
        cls, a: float, E1: float, nu1: float, E2: float, nu2: float, R1: float, R2: float
    ) -> Hertz:
        r"""The contact of half-width ``a``: :math:`F = \pi E^* a^2 / (4 R)`."""
        E_star = 1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2)
        R = 1.0 / (1.0 / R1 + 1.0 / R2)
        return cls(E1, nu1, E2, nu2, R1, R2, math.pi * E_star * a**2 / (4.0 * R))

    @property
    def E_star(self) -> float:
        r"""Contact modulus :math:`E^*`, :math:`1/E^* = (1 - \nu_1^2)/E_1 + (1 - \nu_2^2)/E_2`."""
        return 1.0 / ((1.0 - self.nu1**2) / self.E1 + (1.0 - self.nu2**2) / self.E2)

    @property
    def R(self) -> float:
        r"""Relative radius :math:`R`, :math:`1/R = 1/R_1 + 1/R_2`."""
        return 1.0 / (1.0 / self.R1 + 1.0 / self.R2)

    @property
    def a(self) -> float:
        r"""Half-width :math:`a = 2 \sqrt{F R / (\pi E^*)}` of the contact."""
        return 2.0 * math.sqrt(self.F * self.R / (math.pi * self.E_star))

    @property
    def p0(self) -> float:
        r"""Peak pressure :math:`p_0 = 2 F / (\pi a)` (zero for no force)."""
        a = self.a
        return 2.0 * self.F / (math.pi * a) if a > 0.0 else 0.0

    def pressure(self, x: npt.ArrayLike) -> npt.NDArray[np.floating]:
        r"""Pressure :math:`p_0 \sqrt{1 - x^2/a^2}` for :math:`|x| < a`, zero outside."""
        x = np.asarray(x, dtype=np.float64)
        a = self.a
        if a == 0.0:
            return np.zeros_like(x)
        return self.p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None))


@dataclass(frozen=True)
class HertzMeasures:
    r"""What :func:`measure` reads from a multiplier.

    Attributes:
        a: Half-width :math:`(x_R - x_L)/2` from the edges :math:`x_L, x_R` where
            :math:`\lambda^2` extrapolates to zero; ``nan`` if a side has fewer than two
            positive degrees of freedom.
        a_moment: :math:`2 \sqrt{\int \lambda x^2 dx / \int \lambda dx}` (``nan`` if
            :math:`\int \lambda dx \le 0`).
        p0: Largest degree-of-freedom value of :math:`\lambda`.
        a_error: :math:`(a - a^{ex}) / a^{ex}`.
        p0_error: :math:`(p_0 - p_0^{ex}) / p_0^{ex}`.
        pressure_l2_error: :math:`\|\lambda - p\|_{L^2(-a, a)} / \|p\|_{L^2(-a, a)}`.
    """

    a: float
    a_moment: float
    p0: float
    a_error: float
    p0_error: float
    pressure_l2_error: float


def _reversal(points: npt.NDArray[np.floating]) -> npt.NDArray[np.int32]:
    r"""The permutation of an interval element's nodes under :math:`\xi \to 1 - \xi`."""
    X = np.asarray(points, dtype=np.float64).reshape(-1)
    d = np.abs(X[None, :] - (1.0 - X[:, None]))
    perm = np.argmin(d, axis=1).astype(np.int32)
    if np.any(d[np.arange(X.size), perm] > 1e-12) or np.unique(perm).size != X.size:
        raise ValueError("the element's nodes must be symmetric on the interval")
    return perm


def _cells(lam: dolfinx.fem.Function) -> tuple[npt.NDArray, npt.NDArray, typing.Any, typing.Any]:
    """Geometry nodes and multiplier values of every cell, the same on every process.

    The cells of all processes are gathered, turned so that :math:`x` increases from
    their first to their second vertex, and sorted by their first vertex: the numbers
    that follow depend neither on the process nor on the partition.

    Returns:
        ``(nodes, values, cmap, element)``: nodes ``(num_cells, num_nodes, 2)``, values
        ``(num_cells, num_dofs)`` and the Basix elements of geometry and multiplier.
    """
    Q = lam.function_space
    mesh = Q.mesh
    comm = mesh.comm
    if mesh.topology.dim != 1 or mesh.geometry.dim < 2:
        raise ValueError("the multiplier must live on a mesh of intervals in 2D")
    element = Q.ufl_element()
    if getattr(element, "block_size", 1) != 1 or Q.dofmap.index_map_bs != 1:
        raise ValueError("the multiplier must be a scalar function")
    element = element.basix_element
    cmap = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element()).basix_element
    perm_q, perm_x = _reversal(element.points), _reversal(cmap.points)

    lam.x.scatter_forward()
    num_cells = mesh.topology.index_map(1).size_local
    nodes = mesh.geometry.x[geometry_dofmap(mesh)[:num_cells]][:, :, :2]
    values = lam.x.array[Q.dofmap.list[:num_cells]].real
    parts = comm.allgather((nodes, values))
    nodes = np.concatenate([p[0] for p in parts])
    values = np.concatenate([p[1] for p in parts])
    flip = nodes[:, 0, 0] > nodes[:, 1, 0]
    nodes[flip] = nodes[flip][:, perm_x]
    values[flip] = values[flip][:, perm_q]
    order = np.lexsort((nodes[:, 0, 1], nodes[:, 0, 0]))
    return nodes[order], values[order], cmap, element


def _dofs(lam: dolfinx.fem.Function) -> tuple[npt.NDArray, npt.NDArray]:
    """Horizontal coordinate and value of every degree of freedom, sorted, on every process."""
    Q = lam.function_space
    n = Q.dofmap.index_map.size_local
    x = Q.tabulate_dof_coordinates()[:n, 0]
    v = lam.x.array[:n].real
    parts = Q.mesh.comm.allgather((x, v))
    x = np.concatenate([p[0] for p in parts])
    v = np.concatenate([p[1] for p in parts])
    order = np.lexsort((v, x))
    return x[order], v[order]


def _edge(x: npt.NDArray, v: npt.NDArray, outer: int, inner: int, beyond: int | None) -> float:
    r"""Where :math:`\lambda^2` through dofs ``inner`` and ``outer`` extrapolates to zero.

    The edge is kept between the outer positive dof and the next dof ``beyond`` (where
    :math:`\lambda \le 0`); if :math:`\lambda^2` does not decrease outward it is that dof.
    """
    x2, x1, l2, l1 = x[outer], x[inner], v[outer] ** 2, v[inner] ** 2
    limit = x[beyond] if beyond is not None else x2
    if l2 >= l1:
        return float(limit)
    edge = x2 - l2 * (x2 - x1) / (l2 - l1)
    lo, hi = min(x2, limit), max(x2, limit)
    return float(np.clip(edge, lo, hi))


def _solve(coefficients: npt.NDArray, target: float) -> npt.NDArray:
    """Parameters in [0, 1] where the increasing polynomials ``coefficients`` reach ``target``.

    Bisection, vectorized over the rows of ``coefficients`` (monomials in the parameter);
    rows that do not cross ``target`` get 0 (below) or 1 (above).
    """
    lo = np.zeros(coefficients.shape[0])
    hi = np.ones(coefficients.shape[0])
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        below = np.polynomial.polynomial.polyval(mid, coefficients.T, tensor=False) < target
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def measure(lam: dolfinx.fem.Function, exact: Hertz) -> HertzMeasures:
    r"""Half-width, peak pressure and pressure error of a contact multiplier (collective).

    The multiplier lives on a mesh of intervals in 2D (the contactor facets of a contact
    pair, :attr:`~dolfinx_contact_s2s.pair.ContactPair.Q`), with a Lagrange element
    of any degree; :math:`x` is the horizontal coordinate, centred at the contact point.

    - ``p0``: the largest degree-of-freedom value.
    - ``a``: on each side, :math:`\lambda^2` at the two outermost degrees of freedom with
      :math:`\lambda > 0` is extrapolated linearly in :math:`x` to zero, giving the
      edges :math:`x_L, x_R` (kept before the next degree of freedom outward), and
      :math:`a = (x_R - x_L)/2`. Exact to :math:`O(h^2/a)` for an elliptical
      :math:`\lambda`, whose square is quadratic in :math:`x`.
    - ``a_moment``: :math:`2 \sqrt{\int \lambda x^2 dx / \int \lambda dx}`, which is
      :math:`a` for an elliptical distribution.
    - ``pressure_l2_error``: :math:`\sqrt{\int_{|x| < a} (\lambda - p)^2 dx}` divided by
      :math:`\sqrt{4 a p_0^2 / 3}`, with the exact :math:`a, p_0`. The cells are cut at
      :math:`x = \pm a`, and each piece is split at its midpoint and integrated with a
      Gauss rule in :math:`t`, :math:`\xi - \xi_e \propto t^2` toward its ends
      :math:`\xi_e`, which makes the square-root edges of :math:`p` smooth.

    The integrals use the horizontal measure :math:`dx = |dx/d\xi|\, d\xi` along the
    (possibly curved) cells. Every process gathers the whole multiplier (a line of
    cells) and computes the same numbers in the same order, whatever the partition.

    Args:
        lam: The multiplier :math:`\lambda` (a pressure).
        exact: The exact solution it approximates.

    Returns:
        The measures, identical on every process.

    Raises:
        ValueError: If ``lam`` is not a scalar function on intervals in 2D with
            symmetric nodes, or its mesh does not cover :math:`[-a, a]` (the exact
            :math:`a`).
    """
    nodes, values, cmap, element = _cells(lam)
    a_ex, p0_ex = exact.a, exact.p0
    if not a_ex > 0.0:
        raise ValueError("the exact solution has no contact (F = 0)")

    # Degrees of freedom: the peak and the edges.
    x, v = _dofs(lam)
    p0 = float(v.max()) if v.size else math.nan
    positive = np.flatnonzero(v > 0.0)
    if positive.size >= 2:
        r, l = positive[-1], positive[0]  # noqa: E741
        x_r = _edge(x, v, r, positive[-2], r + 1 if r + 1 < x.size else None)
        x_l = _edge(x, v, l, positive[1], l - 1 if l > 0 else None)
        a = 0.5 * (x_r - x_l)
    else:
        a = math.nan

    # Whole cells: the moments.
    s, w = basix.make_quadrature(
        basix.CellType.interval, 2 * _POINTS - 1, rule=basix.QuadratureType.gauss_jacobi
    )
    s = s[:, 0]
    psi = cmap.tabulate(1, s[:, None])[:, :, :, 0]  # (2, points, nodes)
    phi = element.tabulate(0, s[:, None])[0, :, :, 0]
    xq = nodes[:, :, 0] @ psi[0].T  # (cells, points)
    jac = np.abs(nodes[:, :, 0] @ psi[1].T)
    lq = values @ phi.T
    m0 = float(np.sum(lq * jac * w))
    m2 = float(np.sum(lq * xq**2 * jac * w))
    a_moment = 2.0 * math.sqrt(m2 / m0) if m0 > 0.0 and m2 >= 0.0 else math.nan

    # The part |x| < a of every cell, in two halves graded toward their ends.
    xi_nodes = np.asarray(cmap.points, dtype=np.float64)[:, 0]
    vandermonde = np.vander(xi_nodes, xi_nodes.size, increasing=True)
    monomials = np.linalg.solve(vandermonde, nodes[:, :, 0].T).T  # (cells, degree + 1)
    start = _solve(monomials, -a_ex)
    stop = _solve(monomials, a_ex)
    inside = stop > start
    start, stop = start[inside], stop[inside]
    mid = 0.5 * (start + stop)
    t2 = s**2
    xi = np.concatenate(
        [start[:, None] + (mid - start)[:, None] * t2, stop[:, None] - (stop - mid)[:, None] * t2],
        axis=1,
    )
    dxi = np.concatenate(
        [(mid - start)[:, None] * 2.0 * s * w, (stop - mid)[:, None] * 2.0 * s * w], axis=1
    )
    cells_in = np.flatnonzero(inside)
    shape = xi.shape
    psi = cmap.tabulate(1, xi.reshape(-1, 1))[:, :, :, 0].reshape(2, *shape, -1)
    phi = element.tabulate(0, xi.reshape(-1, 1))[0, :, :, 0].reshape(*shape, -1)
    X = nodes[cells_in, :, 0]
    xq = np.einsum("cqn,cn->cq", psi[0], X)
    jac = np.abs(np.einsum("cqn,cn->cq", psi[1], X))
    lq = np.einsum("cqk,ck->cq", phi, values[cells_in])
    covered = float(np.sum(jac * dxi))
    if not math.isclose(covered, 2.0 * a_ex, rel_tol=1e-8):
        raise ValueError(
            f"the multiplier's mesh covers {covered:.6g} of the contact width 2a = {2 * a_ex:.6g}"
        )
    error2 = float(np.sum((lq - exact.pressure(xq)) ** 2 * jac * dxi))
    l2 = math.sqrt(error2 / (4.0 * a_ex * p0_ex**2 / 3.0))

    return HertzMeasures(
        a=float(a),
        a_moment=float(a_moment),
        p0=p0,
        a_error=float((a - a_ex) / a_ex),
        p0_error=float((p0 - p0_ex) / p0_ex),
        pressure_l2_error=l2,
    )


def pressure_l2_error(
    x: npt.NDArray[np.floating],
    pressure: npt.NDArray[np.floating],
    a: float,
    p0: float,
    a_h: float,
    radial: bool = False,
) -> float:
    r"""Relative L2 error :math:`\|\lambda_h - p\| / \|p\|` of a pressure profile against Hertz.

    :math:`p = p_0 \sqrt{1 - x^2/a^2}` inside the contact, 0 outside; :math:`\lambda_h`
    piecewise linear between the sorted abscissae ``x`` of the multiplier's nodes
    (:func:`~dolfinx_contact_s2s.pressure_profile`), both integrated over
    :math:`0 \le x \le 1.5 \max(a, a_h)` on 20001 points (trapezoidal rule), with the
    weight :math:`x` (the axisymmetric :math:`2\pi r`) if ``radial``.
    """
    fine = np.linspace(0.0, 1.5 * max(a, a_h), 20001)
    exact = p0 * np.sqrt(np.clip(1.0 - (fine / a) ** 2, 0.0, None))
    diff = np.interp(fine, x, pressure) - exact
    weight = fine if radial else np.ones_like(fine)
    return math.sqrt(np.trapezoid(diff**2 * weight, fine) / np.trapezoid(exact**2 * weight, fine))

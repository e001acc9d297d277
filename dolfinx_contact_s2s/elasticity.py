# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Small-strain linear elasticity for the bodies: plane strain, plane stress or axisymmetry.

In axisymmetry (``Material(..., plane="axisymmetric")``) the mesh lies in the
:math:`(r, z)` half-plane, :math:`r = x_0 \ge 0`, :math:`z = x_1`; the displacement is
:math:`(u_r, u_z)` and the strains are :math:`\varepsilon_{rr}, \varepsilon_{zz},
\varepsilon_{rz}` and the hoop strain :math:`\varepsilon_{\theta\theta} = u_r / r`. Every
integral carries the full ring weight :math:`2\pi r` (:meth:`Material.weight`), so loads,
reactions and contact forces are total forces of the 3D body, and the contact multiplier
of a pair made with ``axisymmetric=True`` is the contact pressure.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import dolfinx
import ufl

from dolfinx_contact_s2s.axisymmetry import check_axisymmetric_mesh

__all__ = ["PLANES", "Material", "epsilon", "stress_function"]

#: The 2D models of :class:`Material`.
PLANES = ("strain", "stress", "axisymmetric")


def epsilon(u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    r"""Small strain :math:`\varepsilon(u) = (\nabla u + \nabla u^T)/2`."""
    return ufl.sym(ufl.grad(u))


@dataclass(frozen=True)
class Material:
    r"""Isotropic linear elastic material.

    ``plane="axisymmetric"`` is one value of the same field, not a separate flag: plane
    strain, plane stress and axisymmetry are the three mutually exclusive reductions of
    3D elasticity to a 2D mesh (a flag beside ``plane`` would allow "axisymmetric plane
    stress", which means nothing).

    In axisymmetry the forms of :meth:`forms` carry :math:`2\pi r`, and a user's own
    loads must carry it too, through :meth:`weight`:
    ``L = ufl.inner(t, v) * material.weight(mesh) * ds(k)``. On the axis (:math:`r = 0`) of
    a solid body a Dirichlet condition :math:`u_r = 0` is all a user adds. It belongs
    there: the hoop energy :math:`\int u_r^2 / r\, 2\pi\, dr\, dz` is finite only for
    :math:`u_r = 0` on the axis, but the quadrature (no point at :math:`r = 0`) gives
    the axis a finite stiffness, so without it :math:`u_r` comes out nonzero there, of
    the size of the discretization error (measured for a load peaked at the axis on a
    unit cylinder: 1%, 0.3%, 0.09% of the largest displacement with P1 on 4, 8, 16
    cells across; 0.1%, 0.02%, 0.003% with P2). :meth:`forms` raises
    :class:`ValueError` on every rank for a mesh with :math:`r < 0`.

    Attributes:
        E: Young's modulus.
        nu: Poisson's ratio.
        plane: One of :data:`PLANES`: ``"strain"`` (the default), ``"stress"`` or
            ``"axisymmetric"`` (coordinates :math:`(r, z)`, ring weight :math:`2\pi r`).
    """

    E: float = 1.0
    nu: float = 0.3
    plane: str = "strain"

    def __post_init__(self) -> None:
        """Check the parameters."""
        if self.plane not in PLANES:
            raise ValueError(f"plane must be one of {PLANES}, not {self.plane!r}")
        # Written so that NaN fails every comparison: E = nan and nu = nan are refused.
        if not (0 < self.E < math.inf):
            raise ValueError(
                f"Young's modulus must be positive and finite, not E = {self.E!r}: give E in "
                "the units of the loads (E > 0)"
            )
        if not (-1 < self.nu < 0.5):
            raise ValueError(
                f"Poisson's ratio must lie in (-1, 1/2), not nu = {self.nu!r}: nu = 1/2 "
                "(incompressible) makes the stiffness infinite"
            )

    @property
    def axisymmetric(self) -> bool:
        """Whether the model is axisymmetric (``plane="axisymmetric"``)."""
        return self.plane == "axisymmetric"

    @property
    def lame(self) -> tuple[float, float]:
        r"""Lamé parameters :math:`(\mu, \lambda)` of the 2D model (3D ones but in plane stress)."""
        mu = self.E / (2 * (1 + self.nu))
        lmbda = self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))
        if self.plane == "stress":
            lmbda = 2 * mu * lmbda / (lmbda + 2 * mu)
        return mu, lmbda

    def weight(self, mesh: dolfinx.mesh.Mesh) -> ufl.core.expr.Expr | float:
        r"""The weight of every integral: :math:`2\pi r` in axisymmetry, else 1.

        Multiply the user's load forms by it, e.g. ``inner(t, v) * material.weight(mesh)
        * ds(k)``: then the loads are total forces on the 3D body, as the stiffness of
        :meth:`forms` and the coupling of a pair with ``axisymmetric=True`` are.
        """
        if not self.axisymmetric:
            return 1.0
        return 2 * math.pi * ufl.SpatialCoordinate(mesh)[0]

    def strain(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        r"""The strain :math:`\varepsilon(u)`; in axisymmetry 3x3 in :math:`(r, z, \theta)`.

        The hoop strain is :math:`\varepsilon_{\theta\theta} = u_r / r`. On the axis
        itself (:math:`r = 0`, where only point evaluations such as
        :func:`stress_function` look) it is its limit :math:`\partial u_r / \partial r`
        (with :math:`u_r = 0` there).
        """
        eps = epsilon(u)
        if not self.axisymmetric:
            return eps
        r = ufl.SpatialCoordinate(_domain(u))[0]
        hoop = ufl.conditional(ufl.gt(r, 0.0), u[0] / r, u[0].dx(0))
        return ufl.as_tensor(
            [[eps[0, 0], eps[0, 1], 0.0], [eps[1, 0], eps[1, 1], 0.0], [0.0, 0.0, hoop]]
        )

    def sigma(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        r"""Cauchy stress :math:`2\mu\varepsilon + \lambda\,\mathrm{tr}\,\varepsilon\, I`.

        A 2x2 tensor in plane strain and plane stress; in axisymmetry the 3x3 tensor in
        :math:`(r, z, \theta)`: :math:`\sigma_{rr}, \sigma_{rz}, \sigma_{zz}` and the hoop
        stress :math:`\sigma_{\theta\theta}` at ``[2, 2]`` (:meth:`strain`).
        """
        mu, lmbda = self.lame
        eps = self.strain(u)
        return 2 * mu * eps + lmbda * ufl.tr(eps) * ufl.Identity(eps.ufl_shape[0])

    def forms(self, V: dolfinx.fem.FunctionSpace) -> tuple[ufl.Form, ufl.Argument, ufl.Argument]:
        r"""Stiffness form :math:`a(u, v) = \int \sigma(u) : \varepsilon(v)\, w` and its arguments.

        The weight :math:`w` is :meth:`weight`: 1, or :math:`2\pi r` in axisymmetry (the
        form is then the 3D body's total strain energy, :math:`2\pi` included).

        Raises:
            ValueError: On every rank (collective in axisymmetry), for an axisymmetric
                mesh with a node at :math:`r < 0`
                (:func:`~dolfinx_contact_s2s.axisymmetry.check_axisymmetric_mesh`).
        """
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        if self.axisymmetric:
            check_axisymmetric_mesh(V.mesh)
        w = self.weight(V.mesh)
        return ufl.inner(self.sigma(u), self.strain(v)) * w * ufl.dx, u, v


def _domain(u: ufl.core.expr.Expr) -> ufl.AbstractDomain:
    """The mesh (UFL domain) of an expression in a function or argument."""
    return ufl.domain.extract_unique_domain(u)


def stress_function(u: dolfinx.fem.Function, material: Material) -> dolfinx.fem.Function:
    r"""Stress of ``u`` interpolated into discontinuous Lagrange tensors of ``u``'s degree.

    The interpolation is exact pointwise at the element's points, so constant and
    linear stress fields are reproduced to round-off. In plane strain and plane stress
    the tensor is 2x2; in axisymmetry it is 3x3 in :math:`(r, z, \theta)`:
    ``[[s_rr, s_rz, 0], [s_rz, s_zz, 0], [0, 0, s_tt]]``, the hoop stress at ``[2, 2]``
    (:meth:`Material.sigma`).
    """
    V = u.function_space
    mesh = V.mesh
    degree = V.ufl_element().degree
    n = 3 if material.axisymmetric else mesh.geometry.dim
    W = dolfinx.fem.functionspace(mesh, ("Discontinuous Lagrange", degree, (n, n)))
    s = dolfinx.fem.Function(W, name="stress")
    points = W.element.interpolation_points
    if callable(points):
        points = points()
    s.interpolate(dolfinx.fem.Expression(material.sigma(u), points))
    return s

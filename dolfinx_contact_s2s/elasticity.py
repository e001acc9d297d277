# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Small-strain linear elasticity for the bodies, in plane strain or plane stress."""

from __future__ import annotations

import math
from dataclasses import dataclass

import dolfinx
import ufl

__all__ = ["Material", "epsilon", "stress_function"]


def epsilon(u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    r"""Small strain :math:`\varepsilon(u) = (\nabla u + \nabla u^T)/2`."""
    return ufl.sym(ufl.grad(u))


@dataclass(frozen=True)
class Material:
    """Isotropic linear elastic material.

    Attributes:
        E: Young's modulus.
        nu: Poisson's ratio.
        plane: ``"strain"`` or ``"stress"``.
    """

    E: float = 1.0
    nu: float = 0.3
    plane: str = "strain"

    def __post_init__(self) -> None:
        """Check the parameters."""
        if self.plane not in ("strain", "stress"):
            raise ValueError(f"plane must be 'strain' or 'stress', not {self.plane!r}")
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
    def lame(self) -> tuple[float, float]:
        r"""Lamé parameters :math:`(\mu, \lambda)` of the 2D model."""
        mu = self.E / (2 * (1 + self.nu))
        lmbda = self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))
        if self.plane == "stress":
            lmbda = 2 * mu * lmbda / (lmbda + 2 * mu)
        return mu, lmbda

    def sigma(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        r"""Cauchy stress :math:`2\mu\varepsilon + \lambda\,\mathrm{tr}\,\varepsilon\, I`."""
        mu, lmbda = self.lame
        eps = epsilon(u)
        return 2 * mu * eps + lmbda * ufl.tr(eps) * ufl.Identity(len(u))

    def forms(self, V: dolfinx.fem.FunctionSpace) -> tuple[ufl.Form, ufl.Argument, ufl.Argument]:
        r"""Stiffness form :math:`a(u, v) = \int \sigma(u) : \varepsilon(v)` and its arguments."""
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        return ufl.inner(self.sigma(u), epsilon(v)) * ufl.dx, u, v


def stress_function(u: dolfinx.fem.Function, material: Material) -> dolfinx.fem.Function:
    """Stress of ``u`` interpolated into discontinuous Lagrange tensors of ``u``'s degree.

    The interpolation is exact pointwise at the element's points, so constant and
    linear stress fields are reproduced to round-off.
    """
    V = u.function_space
    mesh = V.mesh
    degree = V.ufl_element().degree
    gdim = mesh.geometry.dim
    W = dolfinx.fem.functionspace(mesh, ("Discontinuous Lagrange", degree, (gdim, gdim)))
    s = dolfinx.fem.Function(W, name="stress")
    points = W.element.interpolation_points
    if callable(points):
        points = points()
    s.interpolate(dolfinx.fem.Expression(material.sigma(u), points))
    return s

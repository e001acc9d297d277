# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Frictionless unilateral contact: an unknown contact area (Eq. 1).

The contact conditions of Eq. (1), :math:`g \ge 0`, :math:`\lambda \ge 0`,
:math:`g \lambda = 0`, are imposed on the weighted gaps of the coupling (Eqs. 15 and
17), one per multiplier dof :math:`j`:

.. math::
    \tilde g_j = \int_{\Gamma_C} \mu_j \left[(\mathbf u_C - \mathbf u_T^*) \cdot
    \mathbf N + g_0\right] d\Gamma = (\mathbf B \mathbf U + \mathbf G)_j, \qquad
    \lambda_j \ge 0, \quad \tilde g_j \ge 0, \quad \lambda_j \tilde g_j = 0,

with every discretization of the coupling. Six algorithms share one interface
(:class:`UnilateralContactProblem`), one module each (:mod:`.active_set`,
:mod:`.condensed`, :mod:`.snes_vi`, :mod:`.penalty`):

- ``"active-set"``: semismooth Newton on the complementarity function
  :math:`C_j = \lambda_j - \max(0, \lambda_j - c_j \tilde g_j)` (the primal-dual active
  set method). For linear elastic bodies every iteration is one saddle-point solve of
  Eq. (18) with the inactive multipliers set to zero, and the iteration ends when the
  active set repeats, which makes :math:`C = 0` up to round-off.
- ``"condensed-active-set"``: the same iterations (the same sets, the same answer) from
  one factorization of the tied saddle point instead of one per iteration: the
  multiplier block of its inverse (MUMPS's selected entries of the inverse) turns every
  active set into a dense solve on the multipliers. Linear bodies and MUMPS only.
- ``"dual-active-set"``: the same iterations with dual multipliers, each active set's
  saddle point condensed to a symmetric positive definite system on the displacements
  and solved by CG + GAMG (:class:`~dolfinx_contact_s2s.condensation.DualCondensation`).
- ``"snes-vi"``: the same mixed complementarity problem handed to PETSc's reduced-space
  variational-inequality Newton method (``SNESVINEWTONRSLS``) with the bounds
  :math:`\lambda \ge 0` and free displacements.
- ``"penalty"``: :math:`\lambda_j = c_j \max(0, -\tilde g_j)` from the penetration, no
  multiplier unknowns in the solve; the error falls like :math:`1/\varepsilon`.
- ``"augmented-lagrangian"``: Uzawa updates
  :math:`\lambda_j \leftarrow \max(0, \lambda_j - c_j \tilde g_j)` around penalty solves,
  until :math:`\lambda` stops changing: the Lagrange solution for any :math:`\varepsilon`.

The parameter :math:`c_j = \varepsilon_j / m_j` turns a weighted gap into a pressure:
:math:`m_j` is the row sum of the multiplier's mass (Eq. 29: the integral of
:math:`\mu_j`, or the tributary length of a node) and :math:`\varepsilon_j = \kappa
\bar E / h_j` a stiffness per length, with :math:`\bar E` the median diagonal entry of
the free stiffness, :math:`h_j = (\int \mu_j)^2 / \int \mu_j^2` (proportional to the
contactor's facet size around :math:`j`: :math:`1.5 h` for P1) and :math:`\kappa` the
``penalty`` factor.

This package needs petsc4py and must be imported explicitly.
"""

from dolfinx_contact_s2s.unilateral.adaptive import (
    AdaptiveResult,
    AdaptiveStep,
    RefinementError,
    inside_zones,
    refine_contact_zone,
)
from dolfinx_contact_s2s.unilateral.history import (
    ContactConvergenceError,
    ContactHistory,
    Iteration,
    LoadStep,
    Update,
)
from dolfinx_contact_s2s.unilateral.problem import (
    ALGORITHMS,
    DEFAULT_PENALTY,
    STARTS,
    UnilateralContactProblem,
)

__all__ = [
    "ALGORITHMS",
    "DEFAULT_PENALTY",
    "STARTS",
    "AdaptiveResult",
    "AdaptiveStep",
    "ContactConvergenceError",
    "ContactHistory",
    "Iteration",
    "LoadStep",
    "RefinementError",
    "UnilateralContactProblem",
    "Update",
    "inside_zones",
    "refine_contact_zone",
]

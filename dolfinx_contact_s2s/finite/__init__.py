# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Finite deformation: nonlinear bodies in contact on the current configuration.

:class:`NonlinearContactProblem` runs Newton's method on the user's residual forms
(any UFL hyperelastic energy), with the contact surfaces placed at :math:`X + u` in
every iteration (:mod:`~dolfinx_contact_s2s.finite.problem`).

This package needs petsc4py and must be imported explicitly.
"""

from dolfinx_contact_s2s.finite.problem import (
    NewtonIteration,
    NonlinearContactProblem,
    NonlinearConvergenceError,
)

__all__ = ["NewtonIteration", "NonlinearContactProblem", "NonlinearConvergenceError"]

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Frictional contact: Coulomb's law on tangential multipliers (2D, first increment).

:class:`FrictionalContactProblem` adds to the unilateral conditions of Eq. (1) a
tangential multiplier :math:`\lambda_t` in the space of :math:`\lambda_n` and Coulomb's
law on the weighted tangential slip increments of each load step
(:mod:`~dolfinx_contact_s2s.friction.coulomb`), solved by semismooth Newton (a
primal-dual active set with inactive, stick and slip sets).

This package needs petsc4py and must be imported explicitly.
"""

from dolfinx_contact_s2s.friction.coulomb import CoulombFriction
from dolfinx_contact_s2s.friction.problem import FrictionalContactProblem
from dolfinx_contact_s2s.friction.regularized import RegularizedFrictionProblem

__all__ = ["CoulombFriction", "FrictionalContactProblem", "RegularizedFrictionProblem"]

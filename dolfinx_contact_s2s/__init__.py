# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Segment-to-segment Lagrange-multiplier contact for DOLFINx.

After N. El-Abbasi and K.-J. Bathe, "Stability and patch test performance of contact
discretizations and a new solution algorithm", Computers & Structures 79 (2001).

The PETSc layer (assembly of the coupling block and the saddle-point solve) lives in
:mod:`dolfinx_contact_s2s.petsc`, which must be imported explicitly.
"""

from dolfinx_contact_s2s import scenes
from dolfinx_contact_s2s.coupling import (
    METHODS,
    ContactPair,
    CouplingBlocks,
    SubSegments,
    contact_pair,
    contact_pairs,
)
from dolfinx_contact_s2s.elasticity import Material, epsilon, stress_function
from dolfinx_contact_s2s.surface import ContactSurface, contact_surface

__version__ = "0.1.0"

__all__ = [
    "METHODS",
    "ContactPair",
    "ContactSurface",
    "CouplingBlocks",
    "Material",
    "SubSegments",
    "contact_pair",
    "contact_pairs",
    "contact_surface",
    "epsilon",
    "scenes",
    "stress_function",
]

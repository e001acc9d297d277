# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Segment-to-segment Lagrange-multiplier contact for DOLFINx.

After N. El-Abbasi and K.-J. Bathe, "Stability and patch test performance of contact
discretizations and a new solution algorithm", Computers & Structures 79 (2001).

The PETSc layer (assembly of the coupling block and the saddle-point solve) lives in
:mod:`dolfinx_contact_s2s.petsc`, which must be imported explicitly.
"""

import importlib.metadata as _metadata
import pathlib as _pathlib
import re as _re

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


def _read_version() -> str:
    """The installed package's version; in a source checkout, pyproject.toml's."""
    try:
        return _metadata.version("dolfinx-contact-s2s")
    except _metadata.PackageNotFoundError:
        pyproject = _pathlib.Path(__file__).parents[1] / "pyproject.toml"
        text = pyproject.read_text() if pyproject.exists() else ""
        found = _re.search(r'^version = "(.+)"', text, flags=_re.M)
        return found.group(1) if found else "unknown"


__version__ = _read_version()

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

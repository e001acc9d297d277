# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Segment-to-segment Lagrange-multiplier contact for DOLFINx.

After N. El-Abbasi and K.-J. Bathe, "Stability and patch test performance of contact
discretizations and a new solution algorithm", Computers & Structures 79 (2001).

The modules that need petsc4py are imported explicitly, as ``dolfinx.fem.petsc``:
:mod:`~dolfinx_contact_s2s.problem` (the tied problem of Eq. 18, holding a
:class:`~dolfinx_contact_s2s.system.ContactSystem`),
:mod:`~dolfinx_contact_s2s.unilateral` (Eq. 1), :mod:`~dolfinx_contact_s2s.friction`
(Coulomb, 2D), :mod:`~dolfinx_contact_s2s.assemble`
(the coupling block), :mod:`~dolfinx_contact_s2s.fieldsplit` (the iterative solver) and
:mod:`~dolfinx_contact_s2s.analysis` (solvability, inf-sup, round-off).
"""

import importlib.metadata as _metadata
import pathlib as _pathlib
import re as _re

from dolfinx_contact_s2s import _moved
from dolfinx_contact_s2s.axisymmetry import check_axis_surface, check_axisymmetric_mesh
from dolfinx_contact_s2s.contact_front import ContactFront, contact_front
from dolfinx_contact_s2s.elasticity import PLANES, Material, epsilon, stress_function
from dolfinx_contact_s2s.meshing import (
    Projection,
    curved_mesh,
    gmsh_projection,
    gmsh_session,
    model_to_mesh,
    snap_boundary,
)
from dolfinx_contact_s2s.obstacles import (
    AnalyticObstacle,
    RigidSurface,
    circle_obstacle,
    obstacle,
    plane_obstacle,
    rigid_surface,
)
from dolfinx_contact_s2s.pair import (
    METHODS,
    ContactPair,
    CouplingBlocks,
    SubSegments,
    contact_pair,
    contact_pairs,
)
from dolfinx_contact_s2s.postprocess import (
    ContactEdge,
    ContactForce,
    ContactZone,
    PressureProfile,
    contact_force,
    contact_zones,
    pressure_profile,
)
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

_moved.install()

__all__ = [
    "METHODS",
    "PLANES",
    "AnalyticObstacle",
    "ContactEdge",
    "ContactForce",
    "ContactFront",
    "ContactPair",
    "ContactSurface",
    "ContactZone",
    "CouplingBlocks",
    "Material",
    "PressureProfile",
    "Projection",
    "RigidSurface",
    "SubSegments",
    "check_axis_surface",
    "check_axisymmetric_mesh",
    "circle_obstacle",
    "contact_force",
    "contact_front",
    "contact_pair",
    "contact_pairs",
    "contact_surface",
    "contact_zones",
    "curved_mesh",
    "epsilon",
    "gmsh_projection",
    "gmsh_session",
    "model_to_mesh",
    "obstacle",
    "plane_obstacle",
    "pressure_profile",
    "rigid_surface",
    "snap_boundary",
    "stress_function",
]

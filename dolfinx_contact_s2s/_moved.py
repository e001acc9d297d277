# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The modules of release 0.2 that moved in 0.3: a ``DeprecationWarning`` or an ``ImportError``.

A module that was renamed inside the library still imports under its old name for one
release, with a ``DeprecationWarning`` naming the new place. The paper's scenes and
studies left the library for the repository's ``paper/`` folder (not installed): their
old names raise an ``ImportError`` that says where they went.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings

__all__ = ["MOVED", "RENAMED", "install"]

#: Renamed in the library: old module -> new module (imports, with a DeprecationWarning).
RENAMED = {
    "coupling": "dolfinx_contact_s2s.pair",
    "infsup": "dolfinx_contact_s2s.analysis.infsup",
    "roundoff": "dolfinx_contact_s2s.analysis.roundoff",
    "solvers": "dolfinx_contact_s2s.fieldsplit",
    "stability": "dolfinx_contact_s2s.analysis.dense",
}

#: Split or moved out of the library: old module -> where its names went (ImportError).
MOVED = {
    "petsc": "dolfinx_contact_s2s.assemble (assemble_coupling, CouplingOperator, "
    "multiplier_mass), dolfinx_contact_s2s.la (gather_dense, is_symmetric) and "
    "dolfinx_contact_s2s.mumps (set_schur_indices, schur_complement)",
    "scenes": "dolfinx_contact_s2s.meshing (model_to_mesh, gmsh_session); the paper's "
    "scenes are in the repository's paper/scenes.py, which is not installed",
    "scenes_multi": "the repository's paper/scenes_multi.py, which is not installed",
    "scenes_hertz": "the repository's paper/hertz/scene.py, which is not installed",
    "studies": "the repository's paper/ folder, which is not installed",
}


class _Alias(importlib.abc.Loader):
    """Load an old module name as the module it was renamed to."""

    def __init__(self, new: str):
        self.new = new

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        old = spec.name
        warnings.warn(
            f"{old} is deprecated and will be removed in the next release: import {self.new}",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.import_module(self.new)

    def exec_module(self, module: types.ModuleType) -> None:
        """Nothing to run: the new module is loaded already."""


class _Finder(importlib.abc.MetaPathFinder):
    """Find the old module names of :data:`RENAMED` and :data:`MOVED`."""

    def find_spec(self, fullname: str, path=None, target=None):
        package, _, name = fullname.partition(".")
        if package != "dolfinx_contact_s2s" or "." in name:
            head = name.split(".")[0]
            if package != "dolfinx_contact_s2s" or head not in MOVED:
                return None
            name = head
        if name in RENAMED:
            return importlib.machinery.ModuleSpec(fullname, _Alias(RENAMED[name]))
        if name in MOVED:
            raise ImportError(
                f"{fullname} was removed in dolfinx_contact_s2s 0.3: see {MOVED[name]}",
                name=fullname,
            )
        return None


def install() -> None:
    """Put the finder of the old names after the regular ones (once)."""
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.append(_Finder())

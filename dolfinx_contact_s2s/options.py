# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""One options policy for every PETSc solver of the package.

As :class:`dolfinx.fem.petsc.LinearProblem`: a mandatory, non-empty prefix, and
``petsc_options`` set under it. Unlike a set-then-delete policy, the options stay in
PETSc's database for as long as the solver that reads them lives: PETSc reads some of
them only when the solver is set up (MUMPS reads ``mat_mumps_icntl_*`` when the factor
is created, inside ``KSPSetUp``), so deleting them right after ``setFromOptions()``
would silently drop them. :meth:`PETScOptions.clear` removes them and restores any
value they had replaced.

Precedence, highest first: ``petsc_options``; the options database (the command line,
``PETSC_OPTIONS``); the package's defaults.
"""

from __future__ import annotations

import typing

from petsc4py import PETSc

__all__ = ["PETScOptions"]


class PETScOptions:
    """Options under one prefix, kept in the database while the solver needs them."""

    def __init__(
        self,
        prefix: str,
        options: dict[str, typing.Any] | None = None,
        defaults: dict[str, typing.Any] | None = None,
    ):
        """Set ``options``, and the ``defaults`` the database does not already set.

        Args:
            prefix: Options prefix, e.g. ``"contact_"``. Must be the same on all ranks.
            options: Options set under the prefix; they override the database.
            defaults: Options set under the prefix unless the database or ``options``
                already set them.

        Raises:
            ValueError: If the prefix is empty.
        """
        if not isinstance(prefix, str) or prefix == "":
            raise ValueError("a non-empty petsc_options_prefix is required, e.g. 'contact_'")
        self.prefix = prefix
        self._db = PETSc.Options()
        # name -> value it had before (None: not set), to restore on clear().
        self._replaced: dict[str, str | None] = {}
        options = dict(options or {})
        for key, value in (defaults or {}).items():
            if key not in options and not self._db.hasName(self.name(key)):
                self.set(key, value)
        for key, value in options.items():
            self.set(key, value)

    def name(self, key: str) -> str:
        """Full database name of ``key`` under the prefix."""
        return f"{self.prefix}{key.lstrip('-')}"

    def set(self, key: str, value: typing.Any) -> None:
        """Set ``key`` under the prefix (until :meth:`clear`)."""
        name = self.name(key)
        if name not in self._replaced:
            self._replaced[name] = self._db.getString(name) if self._db.hasName(name) else None
        if isinstance(value, bool):
            value = "true" if value else "false"
        self._db[name] = value

    def get(self, key: str, default: str | None = None) -> str | None:
        """Value of ``key`` under the prefix in the database."""
        name = self.name(key)
        return self._db.getString(name) if self._db.hasName(name) else default

    def apply(self, *objects: typing.Any, suffixes: typing.Sequence[str] | None = None) -> None:
        """Give each PETSc object the prefix (plus its suffix) and call ``setFromOptions``."""
        suffixes = suffixes or [""] * len(objects)
        for obj, suffix in zip(objects, suffixes, strict=True):
            obj.setOptionsPrefix(f"{self.prefix}{suffix}")
            obj.setFromOptions()

    def clear(self) -> None:
        """Remove the options set here; restore the values they replaced."""
        for name, previous in self._replaced.items():
            if previous is None:
                if self._db.hasName(name):
                    self._db.delValue(name)
            else:
                self._db[name] = previous
        self._replaced.clear()

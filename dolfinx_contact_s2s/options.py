# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""One options policy, and one account of a failed solve, for every PETSc solver.

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

import logging
import typing
from collections.abc import Callable

from petsc4py import PETSc

import numpy as np

from dolfinx_contact_s2s.la import backward_error

__all__ = [
    "MUMPS_WORKSPACE_ERRORS",
    "PETScOptions",
    "mumps_factor",
    "refine_distributed",
    "solve_retrying",
    "solver_failure",
]

_EPS = float(np.finfo(np.float64).eps)

# Under the name of the problem module, where these messages were always logged.
logger = logging.getLogger("dolfinx_contact_s2s.problem")


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
        #: Keys whose value is the package's default (neither ``options`` nor the
        #: database set them): the package may still adapt them, see :meth:`set_default`.
        self.defaulted: set[str] = set()
        options = dict(options or {})
        for key, value in (defaults or {}).items():
            if key not in options and not self._db.hasName(self.name(key)):
                self._put(key, value)
                self.defaulted.add(key.lstrip("-"))
        for key, value in options.items():
            self.set(key, value)

    def name(self, key: str) -> str:
        """Full database name of ``key`` under the prefix."""
        return f"{self.prefix}{key.lstrip('-')}"

    def set(self, key: str, value: typing.Any) -> None:
        """Set ``key`` under the prefix (until :meth:`clear`): the caller's choice."""
        self.defaulted.discard(key.lstrip("-"))
        self._put(key, value)

    def _put(self, key: str, value: typing.Any) -> None:
        name = self.name(key)
        if name not in self._replaced:
            self._replaced[name] = self._db.getString(name) if self._db.hasName(name) else None
        if isinstance(value, bool):
            value = "true" if value else "false"
        self._db[name] = value

    def set_default(self, key: str, value: typing.Any) -> bool:
        """Set ``key`` if its value is the package's default; return whether it was.

        The caller's choice (``petsc_options``, the command line) always wins.
        """
        if key.lstrip("-") not in self.defaulted:
            return False
        self._put(key, value)
        return True

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
        self.defaulted.clear()


#: MUMPS errors that more workspace cures (INFOG(1), MUMPS user's guide, section 8).
MUMPS_WORKSPACE_ERRORS = (-8, -9, -11, -12, -14, -15, -17, -20)

_KSP_REASONS = {
    v: k for k, v in vars(PETSc.KSP.ConvergedReason).items() if isinstance(v, int) and k.isupper()
}


def mumps_factor(ksp: PETSc.KSP) -> PETSc.Mat | None:
    """The MUMPS factor of a direct solver, or ``None``."""
    pc = ksp.getPC()
    if pc.getType() not in ("lu", "cholesky") or pc.getFactorSolverType() != "mumps":
        return None
    return pc.getFactorMatrix()


def solver_failure(ksp: PETSc.KSP, prefix: str) -> str:
    """Why a KSP solve failed, in words, naming the option to change where there is one."""
    reason = ksp.getConvergedReason()
    text = f"KSP reason {_KSP_REASONS.get(reason, reason)} ({reason})"
    F = mumps_factor(ksp)
    if F is None:
        return f"{text} after {ksp.getIterationNumber()} iterations"
    info = F.getMumpsInfog(1)
    if info in MUMPS_WORKSPACE_ERRORS:
        return (
            f"{text}: MUMPS ran out of workspace (INFOG(1) = {info}) with ICNTL(14) = "
            f"{F.getMumpsIcntl(14)}; raise it with petsc_options={{'mat_mumps_icntl_14': ...}} "
            f"or -{prefix}mat_mumps_icntl_14"
        )
    if info == -13:
        return f"{text}: MUMPS could not allocate memory (INFOG(1) = -13)"
    if info == -10:
        return f"{text}: MUMPS found the matrix numerically singular (INFOG(1) = -10)"
    return f"{text}: MUMPS INFOG(1) = {info}, INFOG(2) = {F.getMumpsInfog(2)}"


def refine_distributed(ksp: PETSc.KSP, b: PETSc.Vec, x: PETSc.Vec) -> int:
    r"""MUMPS's iterative refinement (ICNTL(10)) where MUMPS leaves it out: in parallel.

    MUMPS refines only a solution it returns on the host process, and PETSc has MUMPS
    keep the solution distributed on more than one process (ICNTL(21) = 1): ICNTL(10)
    is then ignored (INFOG(15) = 0). The P1 patch test's saddle point on 3 processes had
    a backward error of 83-115 eps without the steps, 0.3 eps with. This takes them on the
    same factor, :math:`\mathbf x \leftarrow \mathbf x + \mathbf F^{-1}(\mathbf b -
    \mathbf A \mathbf x)`: :math:`|n|` of them for ICNTL(10) = :math:`n < 0`; for
    :math:`n > 0` up to :math:`n`, stopping as MUMPS does once the backward error
    (:func:`~dolfinx_contact_s2s.la.backward_error`) is at round-off or no longer halves.

    Args:
        ksp: A solver that has just solved ``A x = b``.
        b: Right-hand side.
        x: Solution, refined in place.

    Returns:
        The number of steps taken (0 without a MUMPS factor, on one process, or with
        ICNTL(10) = 0 or a Schur complement).
    """
    F = mumps_factor(ksp)
    if F is None or ksp.getConvergedReason() < 0 or F.getMumpsIcntl(21) != 1:
        return 0
    steps = F.getMumpsIcntl(10)
    if steps == 0 or F.getMumpsIcntl(19) != 0 or F.getMumpsInfog(15) != 0:
        return 0
    A = ksp.getOperators()[0]
    pc = ksp.getPC()
    r, dx = b.duplicate(), x.duplicate()
    previous, taken = float("inf"), 0
    for _ in range(abs(steps)):
        omega = backward_error(A, b, x, r)
        if steps > 0 and (omega <= 2.0 * _EPS or omega > 0.5 * previous):
            break
        pc.apply(r, dx)
        x.axpy(1.0, dx)
        previous, taken = omega, taken + 1
    r.destroy()
    dx.destroy()
    return taken


def solve_retrying(
    ksp: PETSc.KSP,
    configure: Callable[[], None],
    b: PETSc.Vec,
    x: PETSc.Vec,
    options: PETScOptions,
    retries: int,
) -> None:
    """``ksp.solve(b, x)``; a MUMPS workspace error is met by doubling ICNTL(14).

    Up to ``retries`` times, raising ICNTL(14) in ``options`` (the solver's, or another
    KSP's under the same options: a penalty solve). In parallel, MUMPS's iterative
    refinement is then taken by :func:`refine_distributed`.

    Args:
        ksp: The solver, configured.
        configure: Gives the reset ``ksp`` its operator and options again.
        b: Right-hand side.
        x: Solution.
        options: The options ``ksp`` reads.
        retries: Largest number of retries.
    """
    ksp.solve(b, x)
    for _ in range(retries):
        F = mumps_factor(ksp)
        if ksp.getConvergedReason() >= 0 or F is None:
            break
        if F.getMumpsInfog(1) not in MUMPS_WORKSPACE_ERRORS:
            break
        icntl = max(2 * F.getMumpsIcntl(14), F.getMumpsIcntl(14) + 50)
        logger.info("MUMPS workspace too small: retrying with ICNTL(14) = %d", icntl)
        options.set("mat_mumps_icntl_14", icntl)
        # A new factor reads the raised ICNTL(14) from the database.
        ksp.reset()
        configure()
        ksp.solve(b, x)
    refine_distributed(ksp, b, x)

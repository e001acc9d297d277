# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The tied contact problem of Eq. (18), shaped like :class:`dolfinx.fem.petsc.LinearProblem`.

Every constraint of every pair is active (Eq. 15 with a known contact surface): the
surfaces are tied in the normal direction and :math:`\lambda` is the contact pressure,
positive in compression. A solve checks itself: the model's support and the rank of
the constraints are checked when the system is assembled, and the residual of the
saddle-point system after every solve; a problem that cannot be trusted raises on
every rank with the cause named, never returns a plausible wrong answer.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import typing
from collections.abc import Callable, Sequence

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import ufl

from dolfinx_contact_s2s import checks, system_checks
from dolfinx_contact_s2s.assemble import CouplingOperator
from dolfinx_contact_s2s.checks.advice import warn_tied_gaps
from dolfinx_contact_s2s.checks.inputs import check_problem_arguments
from dolfinx_contact_s2s.options import PETScOptions
from dolfinx_contact_s2s.pair import ContactPair
from dolfinx_contact_s2s.system import DEFAULT_OPTIONS, TIMINGS, ContactSystem
from dolfinx_contact_s2s.system_checks import BACKWARD_TOLERANCE

__all__ = [
    "BACKWARD_TOLERANCE",
    "DEFAULT_OPTIONS",
    "TIMINGS",
    "ContactProblemBase",
    "LinearContactProblem",
]

_Problem = typing.TypeVar("_Problem", bound="ContactProblemBase")


class ContactProblemBase:
    """The public face of a problem that holds a :class:`~dolfinx_contact_s2s.system.ContactSystem`.

    The constructor takes the arguments of every contact problem and builds the system
    (with the defaults of :meth:`solver_defaults`); every attribute here reads it
    (:attr:`system`). The problems built on it
    (:class:`LinearContactProblem`,
    :class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem`) add their own
    ``solve``. Usable as a context manager; otherwise call :meth:`destroy`.
    """

    #: Whether the contact conditions read the sign of the weighted gaps (Eq. 1).
    signed_conditions = False

    def __init__(
        self,
        a: ufl.Form | Sequence[ufl.Form],
        L: ufl.Form | Sequence[ufl.Form],
        pairs: Sequence[ContactPair],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        *,
        petsc_options_prefix: str,
        petsc_options: dict[str, typing.Any] | None = None,
        kind: str = "aij",
        residual_tolerance: float = 1e-8,
        workspace_retries: int = 3,
        form_compiler_options: dict | None = None,
        jit_options: dict | None = None,
    ):
        """Set up the forms, the solution functions and the solver.

        Args:
            a: Bilinear form of each displacement space (a single form for one space).
            L: Linear form of each displacement space, in the same order.
            pairs: Contact pairs between surfaces of these spaces.
            bcs: Dirichlet conditions on any of the spaces.
            petsc_options_prefix: Non-empty prefix of the solver's options.
            petsc_options: Options set under the prefix, e.g. ``{"ksp_type": "gmres"}``;
                they reach every object that reads them, the factorization included.
                Defaults: :data:`DEFAULT_OPTIONS` (MUMPS :math:`LDL^T` for a symmetric
                system, LU otherwise), each yielding to these and to the options
                database (command line, ``PETSC_OPTIONS``).
            kind: ``"aij"`` (one assembled matrix, for direct solvers) or ``"nest"``
                (the ``MatNest`` of the blocks, for field-split solvers).
            residual_tolerance: Largest relative residual of a trusted solve.
            workspace_retries: Times a MUMPS workspace error is met by doubling
                ICNTL(14) before raising.
            form_compiler_options: Passed to :func:`dolfinx.fem.form`.
            jit_options: Passed to :func:`dolfinx.fem.form`.

        Raises:
            ValueError: On every rank, for inconsistent input or a mesh with NaN or
                infinite coordinates.
            TypeError: If ``a``, ``L``, ``pairs`` or ``bcs`` is not what it should be
                (e.g. ``pairs`` and ``bcs`` swapped).
        """
        check_problem_arguments(a, L, pairs, bcs, type(self).__name__)
        self._system = ContactSystem(
            a,
            L,
            pairs,
            bcs,
            petsc_options_prefix=petsc_options_prefix,
            petsc_options=petsc_options,
            kind=kind,
            residual_tolerance=residual_tolerance,
            workspace_retries=workspace_retries,
            default_options=self.solver_defaults(),
            form_compiler_options=form_compiler_options,
            jit_options=jit_options,
            signed=self.signed_conditions,
        )

    def solver_defaults(self) -> dict[str, typing.Any]:
        """The solver's defaults, below ``petsc_options`` and the options database."""
        return dict(DEFAULT_OPTIONS)

    @property
    def system(self) -> ContactSystem:
        """The saddle-point system of Eq. (18) the problem solves."""
        return self._system

    # --- what the problem was given -----------------------------------------------

    @property
    def spaces(self) -> list[dolfinx.fem.FunctionSpace]:
        """The displacement spaces, in the order of the forms ``a``."""
        return self._system.spaces

    @property
    def comm(self) -> MPI.Comm:
        """The communicator of the meshes."""
        return self._system.comm

    @property
    def a(self) -> list[dolfinx.fem.Form]:
        """The compiled bilinear forms, one per space."""
        return self._system.a

    @property
    def L(self) -> list[dolfinx.fem.Form]:
        """The compiled linear forms, one per space."""
        return self._system.L

    @property
    def pairs(self) -> list[ContactPair]:
        """The contact pairs."""
        return self._system.pairs

    @property
    def bcs(self) -> list[dolfinx.fem.DirichletBC]:
        """The Dirichlet conditions."""
        return self._system.bcs

    @property
    def bcs_by_space(self) -> list[list[dolfinx.fem.DirichletBC]]:
        """The Dirichlet conditions of each space."""
        return self._system.bcs_by_space

    @property
    def kind(self) -> str:
        """``"aij"`` or ``"nest"``, as given to the constructor."""
        return self._system.kind

    @property
    def residual_tolerance(self) -> float:
        """Largest relative residual of a trusted solve."""
        return self._system.residual_tolerance

    @property
    def workspace_retries(self) -> int:
        """Times a MUMPS workspace error is met by doubling ICNTL(14) before raising."""
        return self._system.workspace_retries

    @property
    def options(self) -> PETScOptions:
        """The solver's options under the prefix."""
        return self._system.options

    @property
    def solver(self) -> PETSc.KSP:
        """The KSP of the saddle-point solves."""
        return self._system.solver

    @property
    def near_nullspaces(self) -> list[PETSc.NullSpace]:
        """The rigid modes of each space (given to GAMG)."""
        return self._system.near_nullspaces

    # --- results and the assembled system --------------------------------------------

    @property
    def u(self) -> list[dolfinx.fem.Function]:
        """The displacement of every space."""
        return self._system.u

    @property
    def multipliers(self) -> list[dolfinx.fem.Function]:
        """The multiplier (contact pressure) of every pair."""
        return self._system.multipliers

    @property
    def A(self) -> PETSc.Mat | None:
        """The saddle-point matrix (after assembly)."""
        return self._system.A

    @property
    def b(self) -> PETSc.Vec | None:
        """The right-hand side (after assembly)."""
        return self._system.b

    @property
    def x(self) -> PETSc.Vec | None:
        """The solution vector (after assembly)."""
        return self._system.x

    @property
    def fields(self) -> dict[str, PETSc.IS]:
        """Index set of every field of :attr:`A`: ``u0``, ..., ``lambda0``, ..."""
        return self._system.fields

    @property
    def operators(self) -> list[CouplingOperator]:
        """The coupling operators of the pairs (after assembly)."""
        return self._system.operators

    @property
    def constraints(self) -> list[list[tuple[int, PETSc.Mat]]]:
        """Per pair, ``(space index, masked B)`` of the current system."""
        return self._system.constraints

    @property
    def symmetric(self) -> bool:
        r"""Whether every assembled :math:`\mathbf K` is symmetric."""
        return self._system.symmetric

    @property
    def timings(self) -> dict[str, float]:
        """Wall time (s, this process) of each stage of :data:`TIMINGS`, summed over solves."""
        return self._system.timings

    @property
    def support(self) -> checks.SupportGram | None:
        """The support data of the last checked assembly (Eq. 33), else None."""
        return self._system.support

    @property
    def stiffness(self) -> list[PETSc.Mat]:
        r"""Assembled :math:`\mathbf K` of every space (see ``ContactSystem.stiffness``)."""
        return self._system.stiffness

    def stiffness_matrix(self, i: int) -> PETSc.Mat:
        r"""A copy of the assembled :math:`\mathbf K` of space ``i``; the caller destroys it."""
        return self._system.stiffness_matrix(i)

    def stiffness_diagonal(self, i: int) -> PETSc.Vec:
        r"""The diagonal of :math:`\mathbf K` of space ``i``; the caller destroys it."""
        return self._system.stiffness_diagonal(i)

    def space_index(self, V: dolfinx.fem.FunctionSpace) -> int:
        """Position of ``V`` among :attr:`spaces` (ValueError if absent)."""
        return self._system.space_index(V)

    def dirichlet_mask(self, i: int) -> PETSc.Vec:
        """1 at the free dofs of space ``i``, 0 at its Dirichlet dofs; destroy it."""
        return self._system.dirichlet_mask(i)

    def dirichlet_values(self, i: int) -> PETSc.Vec:
        """The Dirichlet values of space ``i``, zero elsewhere (owned layout); destroy it."""
        return self._system.dirichlet_values(i)

    def set_solver_setup(self, setup: Callable[[ContactSystem], None] | None) -> None:
        """Call ``setup(system)`` each time the solver is configured for a new system.

        E.g. :class:`dolfinx_contact_s2s.fieldsplit.SchurComplementSetup`, installed by
        :func:`~dolfinx_contact_s2s.fieldsplit.use_schur_complement`.
        """
        self._system.set_solver_setup(setup)

    def residual(self) -> float:
        r"""Relative residual :math:`\|\mathbf b - \mathbf A \mathbf x\|_2 / \|\mathbf b\|_2`."""
        system = self._system
        assert system.A is not None and system.b is not None and system.x is not None
        return system_checks.relative_residual(system.A, system.b, system.x)

    def backward_error(self) -> float:
        r"""Normwise backward error of the last solve (Rigal-Gaches).

        :math:`\eta = \|\mathbf b - \mathbf A\mathbf x\|_\infty / (\|\mathbf A\|_\infty
        \|\mathbf x\|_\infty + \|\mathbf b\|_\infty)`, the smallest relative normwise
        perturbation of :math:`\mathbf A` and :math:`\mathbf b` of which :attr:`x` is the
        exact solution. Collective. Needs the assembled saddle point (``kind="aij"``):
        ``inf`` for a ``"nest"`` matrix.
        """
        system = self._system
        assert system.A is not None and system.b is not None and system.x is not None
        return system_checks.backward_error(system.A, system.b, system.x)

    def contact_forces(self) -> list[dolfinx.fem.Function]:
        r"""Nodal contact force on every space, :math:`\sum_j \mathbf B_{j}^T \Lambda_j`.

        Call after ``solve``. Includes the forces at Dirichlet dofs (taken by the
        supports).
        """
        system = self._system
        forces = [
            dolfinx.fem.Function(V, name=f"contact_force{i}") for i, V in enumerate(self.spaces)
        ]
        for op, lam in zip(system.operators, system.multipliers, strict=True):
            for V, B in op.blocks:
                f = forces[system.space_index(V)]
                y = B.createVecRight()
                B.multTranspose(lam.x.petsc_vec, y)
                f.x.array[: y.getLocalSize()] += y.array_r
                y.destroy()
        for f in forces:
            f.x.scatter_forward()
        return forces

    def destroy(self) -> None:
        """Destroy the PETSc objects and remove the problem's options from the database."""
        self._system.destroy()

    def __enter__(self: _Problem) -> _Problem:
        """Use as a context manager: :meth:`destroy` on exit."""
        return self

    def __exit__(self, *exc: object) -> None:
        """Destroy the PETSc objects."""
        self.destroy()


class LinearContactProblem(ContactProblemBase):
    r"""Linear elastic bodies tied by Lagrange-multiplier contact (Eq. 18).

    Assembles and solves

    .. math::
        \begin{bmatrix} \mathbf K & -\mathbf B^T \\ -\mathbf B & \mathbf 0 \end{bmatrix}
        \begin{Bmatrix} \mathbf U \\ \mathbf \Lambda \end{Bmatrix} =
        \begin{Bmatrix} \mathbf F \\ \mathbf G \end{Bmatrix},

    Eq. (18) with the signs of Eq. (15): :math:`a(\mathbf u, \mathbf v) - b(\mathbf v,
    \lambda) = (\mathbf f, \mathbf v)` and a zero gap :math:`b(\mathbf u, \mu) + \int \mu
    g_0 = 0`, with :math:`\mathbf B` the coupling of Eq. (40) and :math:`\mathbf G =
    \int \mu g_0`. Rows: the displacement spaces in the order of ``a``, then the pairs.

    A displacement space may hold several bodies (one mesh with several connected
    components), and a pair may couple a contactor to several targets in any spaces.

    Rules:

    - Dirichlet conditions are applied to :math:`\mathbf K` as
      :func:`dolfinx.fem.petsc.assemble_matrix` does (unit diagonal); in :math:`\mathbf
      B` their columns are masked in a copy and their values moved to the right-hand
      side: :math:`-\mathbf B \mathbf U_0 = \mathbf G + \mathbf B \mathbf U_D`.
    - A multiplier whose support faces no target (a contactor hanging over the end of
      its target) carries no constraint: its row reads :math:`\lambda_k = 0`. So do the
      duplicates of a two-pass method (section 4.3).
    - At assembly, a body that some rigid motion moves without resistance (Eq. 33:
      the structure must be properly supported) and redundant constraints (Eq. 35:
      :math:`\mathbf B` of all pairs stacked must have full row rank; the two passes of
      a two-pass method on quadratic elements have not) raise :class:`ValueError`.
    - After every solve, a failed KSP, or a relative residual
      :math:`\|\mathbf b - \mathbf A \mathbf x\| / \|\mathbf b\|` above
      ``residual_tolerance`` together with a normwise backward error above
      :data:`BACKWARD_TOLERANCE` (:meth:`backward_error`), raises :class:`RuntimeError`.
      A MUMPS workspace error is met by doubling ICNTL(14), up to
      :attr:`workspace_retries` times.
    - The system is symmetric when every :math:`\mathbf K` is (an inactive multiplier
      loses its column with its row): :attr:`symmetric`, decided on the assembled
      :math:`\mathbf K` (:func:`~dolfinx_contact_s2s.la.is_symmetric`). The default
      factorization is then MUMPS :math:`LDL^T`, else LU (logged). A ``pc_type`` in
      ``petsc_options`` or the options database is never changed.
    - With ``kind="aij"``, :math:`\mathbf K` is stored once: inside :attr:`A` once the
      saddle point is built (:attr:`stiffness` is then released;
      :meth:`stiffness_matrix` gives a copy).

    Usable as a context manager; otherwise call :meth:`destroy`.
    """

    def assemble(self, check: bool = True) -> None:
        r"""Assemble :math:`\mathbf K`, :math:`\mathbf F`, the coupling and the saddle point.

        Args:
            check: Check the support of every body (Eq. 33) and the rank of the
                constraints (Eq. 35). Only diagnostics of singular discretizations
                (:mod:`dolfinx_contact_s2s.analysis.dense`) leave it out.

        Raises:
            ValueError: On every rank, if some :math:`\mathbf K` or :math:`\mathbf F`
                has NaN or infinite entries; with ``check``, if a body is not supported
                or constraints are redundant.
        """
        self._system.assemble(check)

    def solve(self) -> tuple[list[dolfinx.fem.Function], list[dolfinx.fem.Function]]:
        """Assemble and solve Eq. (18), then check the solve.

        Returns:
            The displacement of every space and the multiplier (contact pressure) of
            every pair.

        Raises:
            ValueError: On every rank, if the model is singular (see :meth:`assemble`).
            RuntimeError: On every rank, if the solver fails or its residual is too large.
        """
        self.assemble()
        self._system.solve()
        warn_tied_gaps(self)
        return self.u, self.multipliers

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The saddle-point system of Eq. (18) as an object, shared by the contact problems.

:class:`ContactSystem` holds the spaces and forms, the stiffness :math:`\mathbf K` and
loads :math:`\mathbf F`, the coupling operators
(:func:`~dolfinx_contact_s2s.assemble.assemble_coupling`), the Dirichlet masks and
values, the saddle point built for a load factor and a set of released multipliers, the
KSP and its options, the checked solve and the timings. The problems hold one by
composition and use its public methods only.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import contextlib
import logging
import time
import typing
from collections.abc import Callable, Iterator, Sequence

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s import checks, system_checks
from dolfinx_contact_s2s.assemble import CouplingOperator, assemble_coupling
from dolfinx_contact_s2s.checks.inputs import check_solver_types, check_stiffness
from dolfinx_contact_s2s.compat import create_petsc_vector
from dolfinx_contact_s2s.la import KeptPattern, add_scaled, indicator, owned_vector, plain_vector
from dolfinx_contact_s2s.options import PETScOptions, solve_retrying, solver_failure
from dolfinx_contact_s2s.pair import ContactPair

__all__ = ["DEFAULT_OPTIONS", "TIMINGS", "ContactSystem", "add_scaled"]

# Under the name of the problem module, where these messages were always logged.
logger = logging.getLogger("dolfinx_contact_s2s.problem")

#: Solver defaults; each yields to ``petsc_options`` and to the options database. The
#: default ``pc_type`` is MUMPS :math:`LDL^T` (``"cholesky"`` on an AIJ matrix: MUMPS's
#: general symmetric mode, SYM = 2, for the indefinite saddle point) when every
#: :math:`\mathbf K` is symmetric, and ``"lu"`` otherwise; two steps of iterative
#: refinement (ICNTL(10) = -2): the pivots follow how B is stored, and a patch test of a
#: few hundred unknowns kept 1e-11 of round-off without them (1e-13 with them); on
#: several processes, where MUMPS skips them, :func:`~.options.refine_distributed`.
DEFAULT_OPTIONS = {
    "ksp_type": "preonly",
    "pc_type": "cholesky",
    "pc_factor_mat_solver_type": "mumps",
    "mat_mumps_icntl_10": -2,
}

#: The stages of :attr:`ContactSystem.timings`.
TIMINGS = ("stiffness", "contact", "system", "solve")


def _as_list(forms: typing.Any) -> list:
    return list(forms) if isinstance(forms, Sequence) else [forms]


class ContactSystem:
    r"""The saddle point of Eq. (18): its blocks, its solver and its checked solve.

    The rules of :class:`~dolfinx_contact_s2s.problem.LinearContactProblem` (Dirichlet
    conditions, inactive multipliers, checks, symmetry, storage of :math:`\mathbf K`) are
    implemented here. :meth:`assemble` assembles :math:`\mathbf K`, :math:`\mathbf F`
    and the coupling; :meth:`build` makes the saddle point for a load factor and a set of
    released multipliers; :meth:`solve` solves and checks it. Call :meth:`destroy`.
    """

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
        default_options: dict[str, typing.Any] | None = None,
        form_compiler_options: dict | None = None,
        jit_options: dict | None = None,
        signed: bool = False,
    ):
        r"""Set up the forms, the solution functions and the solver.

        Args:
            a: Bilinear form of each displacement space (a single form for one space).
            L: Linear form of each displacement space, in the same order.
            pairs: Contact pairs between surfaces of these spaces.
            bcs: Dirichlet conditions on any of the spaces.
            petsc_options_prefix: Non-empty prefix of the solver's options.
            petsc_options: Options set under the prefix.
            kind: ``"aij"`` or ``"nest"``.
            residual_tolerance: Largest relative residual of a trusted solve.
            workspace_retries: Times a MUMPS workspace error is met by doubling ICNTL(14)
                before raising.
            default_options: Solver defaults; :data:`DEFAULT_OPTIONS` if None.
            form_compiler_options: Passed to :func:`dolfinx.fem.form`.
            jit_options: Passed to :func:`dolfinx.fem.form`.
            signed: Whether the contact conditions read the sign of :math:`\int \mu_k g`
                (unilateral, friction): the multipliers of
                :attr:`~dolfinx_contact_s2s.assemble.CouplingOperator.unsigned` are left out.

        Raises:
            ValueError: On every rank, for inconsistent input or a mesh with NaN or
                infinite coordinates.
        """
        a, L = _as_list(a), _as_list(L)
        self.signed = bool(signed)
        self.spaces = system_checks.check_forms(a, L, kind)
        self.comm: MPI.Comm = self.spaces[0].mesh.comm
        system_checks.check_coordinates(self.spaces)
        options = {"form_compiler_options": form_compiler_options, "jit_options": jit_options}
        self.a = [dolfinx.fem.form(ai, **options) for ai in a]
        self.L = [dolfinx.fem.form(Li, **options) for Li in L]
        self.pairs = list(pairs)
        system_checks.check_pairs(self.pairs, self.space_index)
        self.bcs = list(bcs)
        self.bcs_by_space = system_checks.bcs_by_space(self.spaces, self.bcs)
        self.kind = kind
        self.residual_tolerance = float(residual_tolerance)
        #: Times a MUMPS workspace error is met by doubling ICNTL(14) before raising.
        self.workspace_retries = int(workspace_retries)

        self.u = [dolfinx.fem.Function(V, name=f"u{i}") for i, V in enumerate(self.spaces)]
        self.multipliers = [
            dolfinx.fem.Function(pair.Q, name=f"lambda{j}") for j, pair in enumerate(self.pairs)
        ]
        self._K: list[PETSc.Mat] = []
        #: Whether every assembled :math:`\mathbf K` is symmetric (set by :meth:`assemble`).
        self.symmetric = True
        self._loads = [create_petsc_vector(V) for V in self.spaces]
        # The bodies (connected components) and their rigid modes depend on the meshes
        # only: found once, used by the support check and given to GAMG.
        self._labels = [checks.connected_components(V.mesh)[0] for V in self.spaces]
        self.near_nullspaces = [
            checks.near_nullspace(V, labels)
            for V, labels in zip(self.spaces, self._labels, strict=True)
        ]
        self._create_stiffness()
        self.operators: list[CouplingOperator] = []
        self.constraints: list[list[tuple[int, PETSc.Mat]]] = []
        self.A: PETSc.Mat | None = None
        self.b: PETSc.Vec | None = None
        self.x: PETSc.Vec | None = None
        self.load = 1.0
        # Finite deformation's Newton terms (set_linearization).
        self._coupling: Callable[[ContactPair], CouplingOperator] = assemble_coupling
        self._extra: Callable[[list, list, list], None] | None = None
        self._plain = True  # no extra fields (build)
        self.fields: dict[str, PETSc.IS] = {}
        self._support: checks.SupportGram | None = None
        # PETSc objects of one assembly (kept across the systems built from it), and of
        # the current saddle-point system.
        self._owned: list[typing.Any] = []
        self._system: list[typing.Any] = []
        self._masks: list[PETSc.Vec] = []
        self._values: list[PETSc.Vec] = []

        #: Wall time (s, this process) spent so far in each stage, summed over solves:
        #: ``"stiffness"`` (K and F), ``"contact"`` (search, segmentation and the
        #: coupling, :func:`~dolfinx_contact_s2s.assemble.assemble_coupling`), ``"system"``
        #: (the saddle point and the checks) and ``"solve"`` (factorizations and solves).
        self.timings: dict[str, float] = dict.fromkeys(TIMINGS, 0.0)

        self._solver_setup: Callable[[ContactSystem], None] | None = None
        defaults = dict(DEFAULT_OPTIONS) if default_options is None else dict(default_options)
        self.options = PETScOptions(petsc_options_prefix, petsc_options, defaults)
        # An unknown type would stop PETSc with a traceback that differs between ranks.
        check_solver_types(self.options, self.comm)
        self.solver = PETSc.KSP().create(self.comm)
        self.options.apply(self.solver)
        #: The saddle point's kept pattern (:meth:`keep_pattern`), else None.
        self.kept: KeptPattern | None = None

    @contextlib.contextmanager
    def timed(self, stage: str) -> Iterator[None]:
        """Add the wall time of the block to :attr:`timings` ``[stage]``."""
        begin = time.perf_counter()
        try:
            yield
        finally:
            self.timings[stage] += time.perf_counter() - begin

    def set_linearization(
        self,
        coupling: Callable[[ContactPair], CouplingOperator] | None = None,
        extra: Callable[[list, list, list], None] | None = None,
    ) -> None:
        """The coupling every assembly makes and the terms every build adds (Newton's).

        ``None``: :func:`~dolfinx_contact_s2s.assemble.assemble_coupling`, nothing.
        """
        self._coupling = assemble_coupling if coupling is None else coupling
        self._extra = extra

    @property
    def linearized(self) -> bool:
        """Whether Newton's terms are set (:meth:`set_linearization`)."""
        return self._extra is not None or self._coupling is not assemble_coupling

    def keep_pattern(self) -> KeptPattern | None:
        """Keep one matrix, and so one factorization, across builds (:class:`KeptPattern`).

        The rank check (Eq. 35, a factorization of its own) then runs at the first
        assembly after each :meth:`KeptPattern.renew` only. None with ``kind="nest"``.
        """
        if self.kept is None and self.kind == "aij":
            self.kept = KeptPattern()
        return self.kept

    def set_solver_setup(self, setup: Callable[[ContactSystem], None] | None) -> None:
        """Call ``setup(self)`` each time the solver is configured for a new system.

        E.g. :class:`dolfinx_contact_s2s.fieldsplit.SchurComplementSetup`; it receives this
        system, which has the public attributes of the problems (``solver``, ``A``,
        ``fields``, ``options``, ``operators``, ``stiffness``, ...).
        """
        self._solver_setup = setup

    @property
    def support(self) -> checks.SupportGram | None:
        """The support data of the last checked assembly (Eq. 33), else None."""
        return self._support

    @property
    def masks(self) -> list[PETSc.Vec]:
        """Per space, the Dirichlet mask of the current assembly (:meth:`dirichlet_mask`)."""
        return self._masks

    @property
    def values(self) -> list[PETSc.Vec]:
        """Per space, the Dirichlet values of the current assembly (:meth:`dirichlet_values`)."""
        return self._values

    # --- the stiffness ----------------------------------------------------------------

    def _create_stiffness(self) -> None:
        r"""Allocate :math:`\mathbf K` of every space, with its rigid modes for GAMG."""
        self._K = [dolfinx.fem.petsc.create_matrix(ai) for ai in self.a]
        for K, ns in zip(self._K, self.near_nullspaces, strict=True):
            K.setNearNullSpace(ns)

    def _release_stiffness(self) -> None:
        for K in self._K:
            K.destroy()
        self._K = []

    @property
    def stiffness(self) -> list[PETSc.Mat]:
        r"""Assembled :math:`\mathbf K` of every space (Dirichlet rows and columns unit).

        With ``kind="aij"`` only until the saddle point is built: :math:`\mathbf K` is
        then stored in :attr:`A` alone; use :meth:`stiffness_matrix`.

        Raises:
            RuntimeError: If it was released into :attr:`A`.
        """
        if not self._K:
            raise RuntimeError(
                "K is stored only in the saddle-point matrix A (kind='aij'): use "
                "problem.stiffness_matrix(i) for a copy"
            )
        return self._K

    def stiffness_matrix(self, i: int) -> PETSc.Mat:
        r"""A copy of the assembled :math:`\mathbf K` of space ``i``; the caller destroys it."""
        if self._K:
            return self._K[i].copy()
        if self.A is None:
            raise RuntimeError("assemble the problem first")
        is_ = list(self.fields.values())[i]
        K = self.A.createSubMatrix(is_, is_)
        K.setNearNullSpace(self.near_nullspaces[i])
        return K

    def stiffness_diagonal(self, i: int) -> PETSc.Vec:
        r"""The diagonal of :math:`\mathbf K` of space ``i``; the caller destroys it."""
        if self._K:
            return self._K[i].getDiagonal()
        if self.A is None:
            raise RuntimeError("assemble the problem first")
        d = self.A.getDiagonal()
        is_ = list(self.fields.values())[i]
        sub = d.getSubVector(is_)
        out = sub.copy()
        d.restoreSubVector(is_, sub)
        d.destroy()
        return out

    def space_index(self, V: dolfinx.fem.FunctionSpace) -> int:
        """Position of ``V`` among :attr:`spaces`.

        Raises:
            ValueError: If ``V`` is not one of the problem's spaces.
        """
        for i, W in enumerate(self.spaces):
            if W is V:
                return i
        raise ValueError(
            "a contact surface is on a function space that carries no form of the problem: "
            "create the surfaces on the same space objects as the forms a"
        )

    # --- assembly -------------------------------------------------------------------

    def dirichlet_mask(self, i: int) -> PETSc.Vec:
        """1 at the free dofs of space ``i``, 0 at its Dirichlet dofs (owned layout).

        The caller must ``destroy()`` it.
        """
        keep = dolfinx.fem.Function(self.spaces[i])
        keep.x.array[:] = 1.0
        for bc in self.bcs_by_space[i]:
            keep.x.array[bc.dof_indices()[0]] = 0.0
        return owned_vector(self.spaces[i], keep.x.array)

    def dirichlet_values(self, i: int) -> PETSc.Vec:
        """The Dirichlet values of space ``i``, zero elsewhere (owned layout); destroy it."""
        values = dolfinx.fem.Function(self.spaces[i])
        for bc in self.bcs_by_space[i]:
            bc.set(values.x.array)
        return owned_vector(self.spaces[i], values.x.array)

    def _destroy_system(self) -> None:
        for obj in self._system:
            obj.destroy()
        self._system, self.constraints, self.fields = [], [], {}
        self.A = self.b = self.x = None

    def _destroy_assembly(self) -> None:
        self._destroy_system()
        for obj in self._owned:
            obj.destroy()
        for op in self.operators:
            op.destroy()
        self._owned, self.operators, self._masks, self._values = [], [], [], []

    def assemble(self, check: bool = True) -> None:
        r"""Assemble :math:`\mathbf K`, :math:`\mathbf F`, the coupling and the saddle point.

        Args:
            check: Check the support of every body (Eq. 33) and the rank of the
                constraints (Eq. 35).

        Raises:
            ValueError: On every rank, if some :math:`\mathbf K` or :math:`\mathbf F`
                has NaN or infinite entries; with ``check``, if a body is not supported
                or constraints are redundant.
        """
        self._destroy_assembly()
        if self.kept is None:
            self.solver.reset()  # the sizes may change (build(extra=) before)
        if not self._K:
            self._create_stiffness()
        with self.timed("stiffness"):
            for K, F, ai, Li, bcs in zip(
                self._K, self._loads, self.a, self.L, self.bcs_by_space, strict=True
            ):
                K.zeroEntries()
                dolfinx.fem.petsc.assemble_matrix(K, ai, bcs=bcs)
                K.assemble()
                with F.localForm() as f:
                    f.set(0.0)
                dolfinx.fem.petsc.assemble_vector(F, Li)
                dolfinx.fem.petsc.apply_lifting(F, [ai], bcs=[bcs])
                F.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
                dolfinx.fem.petsc.set_bc(F, bcs)
            system_checks.check_finite(self._K, self._loads)
        with self.timed("system"):
            self.symmetric = system_checks.all_symmetric(self._K)
            self._masks = [self.dirichlet_mask(i) for i in range(len(self.spaces))]
            self._values = [self.dirichlet_values(i) for i in range(len(self.spaces))]
            self._owned.extend(self._masks + self._values)
            # Before any factorization: MUMPS would report a zero body as lost workspace.
            check_stiffness(self.spaces, self._K, self._masks, self._labels)
        with self.timed("contact"):
            self.operators = [self._coupling(pair) for pair in self.pairs]
            for op in self.operators if self.signed else []:
                op.uncovered = np.union1d(op.uncovered, op.unsigned).astype(np.int64)
        for j, op in enumerate(self.operators):
            if op.uncovered.size:
                logger.info(
                    "pair %d: %d multipliers face no target and are set to zero",
                    j,
                    op.uncovered.size,
                )
        if check:
            with self.timed("system"):
                # Kept: a unilateral iteration checks its active sets against it (without K).
                self._support = system_checks.check_support(
                    self.spaces,
                    self._K,
                    self._masks,
                    self.operators,
                    self.space_index,
                    self._labels,
                )
                if self.kept is None or self.kept.fresh:
                    system_checks.check_redundancy(
                        self.pairs, self.operators, self._masks, self.space_index
                    )
        self.build()

    def build(
        self,
        released: Sequence[npt.NDArray[np.int64]] | None = None,
        load: float = 1.0,
        extra: Callable[[list, list, list], None] | None = None,
    ) -> None:
        r"""The saddle point of Eq. (18) from the assembled blocks.

        Args:
            released: Per pair, global multipliers set to zero besides the pair's
                inactive ones (the inactive set of a unilateral contact iteration).
            load: Factor on :math:`\mathbf F` and the Dirichlet values.
            extra: Fields after the multipliers (friction): ``extra(blocks, rhs, names)``
                appends its rows and columns to the block lists (its matrices stay its
                own) before the system is made, then solved as unsymmetric (None: the default).
        """
        extra = self._extra if extra is None else extra
        with self.timed("system"):
            self.load = float(load)  # the load factor of the current saddle point
            self._plain = extra is None
            self._assemble_system(released, load, extra)

    def _assemble_system(
        self, released: Sequence[npt.NDArray[np.int64]] | None, load: float, extra: typing.Any
    ) -> None:
        nb, npairs = len(self.spaces), len(self.pairs)
        # K lives in the previous A only (kind="aij"): take it out before A goes, and free
        # the previous factorization first, so that K is never stored twice beside a factor.
        # A field split of the nest holds the previous blocks: freed before they go too.
        extracted = [] if self._K else [self.stiffness_matrix(i) for i in range(nb)]
        if (extracted or self.A is not None) and self.kept is None:
            self.solver.reset()
        self._destroy_system()
        blocks: list[list[PETSc.Mat | None]] = [[None] * (nb + npairs) for _ in range(nb + npairs)]
        for i, K in enumerate(self._K or extracted):
            blocks[i][i] = K
        rhs: list[PETSc.Vec] = []
        for F in self._loads:
            f = F.copy()
            f.scale(load)
            rhs.append(f)
            self._system.append(f)
        for j, op in enumerate(self.operators):
            off = op.inactive if released is None else np.union1d(op.inactive, released[j])
            active = indicator(op.G, off)
            G = op.gap(load)  # with the rigid targets' motions at this load
            masked = []
            for V, B in op.blocks:
                i = self.space_index(V)
                # -B U = G with U = U_free + t U_D  =>  -B U_free = G + t B U_D.
                add_scaled(B, self._values[i], load, G)
                Bm = B.copy()
                Bm.diagonalScale(active, self._masks[i])
                masked.append((i, Bm))
                minus = Bm.copy()
                minus.scale(-1.0)
                minus_t = minus.transpose(PETSc.Mat())
                blocks[nb + j][i] = minus
                blocks[i][nb + j] = minus_t
                self._system.extend([Bm, minus, minus_t])
            G.pointwiseMult(G, active)
            rhs.append(G)
            self.constraints.append(masked)
            # ``released`` holds each process's own multipliers: decide on all together.
            if self.comm.allreduce(off.size):  # inactive multipliers: rows lambda_k = 0
                inactive = active.duplicate()
                inactive.set(1.0)
                inactive.axpy(-1.0, active)
                D = PETSc.Mat().createAIJ(
                    [[G.getLocalSize(), G.getSize()]] * 2, nnz=(1, 0), comm=self.comm
                )
                D.setDiagonal(inactive)
                D.assemble()
                blocks[nb + j][nb + j] = D
                self._system.extend([D, inactive])
            self._system.extend([G, active])

        names = [f"u{i}" for i in range(nb)] + [f"lambda{j}" for j in range(npairs)]
        if extra is not None:
            extra(blocks, rhs, names)
        nest = PETSc.Mat().createNest(blocks, comm=self.comm)
        nest.assemble()
        index_sets = nest.getNestISs()[0]
        self.fields = dict(zip(names, index_sets, strict=True))
        self._system.extend(index_sets)
        if self.kind == "nest":
            self.A = nest
            self.b = plain_vector(nest)
            self._system.append(nest)
        else:
            self.A = nest.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())
            # K now lives in A: no second copy (the nest, K and the extracted copies).
            nest.destroy()
            for K in extracted:
                K.destroy()
            self._release_stiffness()
            if self.kept is None:
                self._system.append(self.A)
            else:
                self.A = self.kept.take(self.A, self.solver)
            self.b = self.A.createVecLeft()
        self.x = self.b.duplicate()
        self._system.extend([self.b, self.x])
        for is_, v in zip(index_sets, rhs, strict=True):
            sub = self.b.getSubVector(is_)
            sub.array[:] = v.array_r[: sub.getLocalSize()]
            self.b.restoreSubVector(is_, sub)
        for is_, ns in zip(index_sets[:nb], self.near_nullspaces, strict=True):
            # PCFieldSplit reads a near-null space composed on the field's index set.
            is_.compose("nearnullspace", ns)
        self._configure_solver()

    def _choose_factorization(self) -> None:
        """The default ``pc_type``: :math:`LDL^T` if :attr:`symmetric`, else LU.

        Only a default factorization is adapted: a ``pc_type`` from ``petsc_options``, the
        database, or the problem's defaults other than ``"lu"`` and ``"cholesky"``
        (``"fieldsplit"``, say) is left alone.
        """
        assert self.A is not None
        symmetric = self.symmetric and self._plain
        if self.options.get("pc_type") in ("lu", "cholesky"):
            self.options.set_default("pc_type", "cholesky" if symmetric else "lu")
        self.A.setOption(PETSc.Mat.Option.SYMMETRIC, symmetric)

    def _configure_solver(self) -> None:
        """Operator, options and named fields (``-prefix_pc_type fieldsplit``) of the solver."""
        assert self.A is not None
        self._choose_factorization()
        self.solver.setOperators(self.A)
        self.options.apply(self.A, suffixes=["A_"])
        self.options.apply(self.solver)
        self.solver.getPC().setFieldSplitIS(*self.fields.items())
        if self._solver_setup is not None:
            self._solver_setup(self)

    # --- solve ----------------------------------------------------------------------

    def solve(self) -> None:
        """Solve the current saddle point, check the solve and scatter the solution.

        Raises:
            RuntimeError: On every rank, if the solver fails or its residual is too large.
        """
        with self.timed("solve"):
            self._solve_checked()

    def _solve_checked(self) -> None:
        assert self.A is not None and self.b is not None and self.x is not None
        self.solve_retrying(self.solver, self._configure_solver, self.b, self.x)
        if self.solver.getConvergedReason() < 0:
            raise RuntimeError(
                "the contact solve failed: " + solver_failure(self.solver, self.options.prefix)
            )
        system_checks.check_solve(
            self.A, self.b, self.x, self.residual_tolerance, self.solver, self.options.prefix
        )
        self.scatter()

    def solve_retrying(
        self, ksp: PETSc.KSP, configure: Callable[[], None], b: PETSc.Vec, x: PETSc.Vec
    ) -> None:
        """:func:`~dolfinx_contact_s2s.options.solve_retrying` under this system's options."""
        solve_retrying(ksp, configure, b, x, self.options, self.workspace_retries)

    def scatter(self) -> None:
        """Copy the solution :attr:`x` into :attr:`u` and :attr:`multipliers`."""
        assert self.x is not None
        fields = list(self.fields.values())[: len(self.u) + len(self.multipliers)]
        for f, is_ in zip(self.u + self.multipliers, fields, strict=True):
            sub = self.x.getSubVector(is_)
            f.x.array[: sub.getLocalSize()] = sub.array_r
            self.x.restoreSubVector(is_, sub)
            f.x.scatter_forward()

    def destroy(self) -> None:
        """Destroy the PETSc objects and remove the options from the database."""
        self._destroy_assembly()
        for obj in [self.solver, *self._K, *self._loads, *self.near_nullspaces]:
            obj.destroy()
        if self.kept is not None:
            self.kept.destroy()
        self.options.clear()

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

import contextlib
import logging
import time
import typing
from collections.abc import Iterator, Sequence

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s import checks
from dolfinx_contact_s2s._compat import DOLFINX_VERSION
from dolfinx_contact_s2s.assemble import CouplingOperator, assemble_coupling

# h2: the input checks and the advice on singular or tied problems live in checks/
from dolfinx_contact_s2s.checks.advice import unsupported_error, warn_tied_gaps
from dolfinx_contact_s2s.checks.inputs import (
    check_problem_arguments,
    check_solver_types,
    check_stiffness,
)
from dolfinx_contact_s2s.la import is_symmetric
from dolfinx_contact_s2s.options import (
    MUMPS_WORKSPACE_ERRORS,
    PETScOptions,
    mumps_factor,
    solver_failure,
)
from dolfinx_contact_s2s.pair import ContactPair

__all__ = ["BACKWARD_TOLERANCE", "DEFAULT_OPTIONS", "TIMINGS", "LinearContactProblem"]

logger = logging.getLogger(__name__)

#: Solver defaults; each yields to ``petsc_options`` and to the options database. The
#: default ``pc_type`` is MUMPS :math:`LDL^T` (``"cholesky"`` on an AIJ matrix: MUMPS's
#: general symmetric mode, SYM = 2, for the indefinite saddle point) when every
#: :math:`\mathbf K` is symmetric, and ``"lu"`` otherwise.
DEFAULT_OPTIONS = {
    "ksp_type": "preonly",
    "pc_type": "cholesky",
    "pc_factor_mat_solver_type": "mumps",
}

#: The stages of :attr:`LinearContactProblem.timings`.
TIMINGS = ("stiffness", "contact", "system", "solve")

#: Largest normwise backward error (:meth:`LinearContactProblem.backward_error`) that
#: trusts a solve whose relative residual is above ``residual_tolerance``: 256 machine
#: epsilons, the round-off of a backward-stable factorization (MUMPS at a Young's modulus
#: ratio of :math:`10^6`: 0.5; a Jacobi sweep taken for a solve: 0.15).
BACKWARD_TOLERANCE = 256 * float(np.finfo(np.float64).eps)


def _as_list(forms: typing.Any) -> list:
    return list(forms) if isinstance(forms, Sequence) else [forms]


def _contains(V: dolfinx.fem.FunctionSpace, bc: dolfinx.fem.DirichletBC) -> bool:
    # bc.function_space is a C++ space in some DOLFINx versions, a Python one in others.
    W = bc.function_space
    return V._cpp_object.contains(getattr(W, "_cpp_object", W))


def _dof_coordinates(Q: dolfinx.fem.FunctionSpace) -> npt.NDArray[np.floating]:
    """Coordinates of every global dof of a scalar space, on every process."""
    imap = Q.dofmap.index_map
    x = Q.tabulate_dof_coordinates()[: imap.size_local]
    out = np.zeros((imap.size_global, 3))
    for start, xs in Q.mesh.comm.allgather((imap.local_range[0], x)):
        out[start : start + xs.shape[0]] = xs
    return out


def _check_coordinates(spaces: Sequence[dolfinx.fem.FunctionSpace]) -> None:
    """Raise on every rank if a mesh has a node with NaN or infinite coordinates."""
    for i, V in enumerate(spaces):
        geometry = V.mesh.geometry
        owned = geometry.x[: geometry.index_map().size_local]
        local = int(np.count_nonzero(~np.all(np.isfinite(owned), axis=1)))
        count = V.mesh.comm.allreduce(local, op=MPI.SUM)
        if count:
            raise ValueError(
                f"the mesh of space {i} has {count} node(s) with NaN or infinite "
                "coordinates; check the mesh (mesh.geometry.x) and how it was built or moved"
            )


def _create_vector(V: dolfinx.fem.FunctionSpace) -> PETSc.Vec:
    """A ghosted PETSc vector of ``V`` (the API moved in DOLFINx 0.10)."""
    if DOLFINX_VERSION >= (0, 10):
        return dolfinx.fem.petsc.create_vector(V)
    return dolfinx.la.create_petsc_vector(V.dofmap.index_map, V.dofmap.index_map_bs)


def _owned_vec(V: dolfinx.fem.FunctionSpace, values: npt.NDArray[np.floating]) -> PETSc.Vec:
    """A PETSc vector in the owned layout of ``V`` holding a copy of ``values``."""
    n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
    return PETSc.Vec().createWithArray(np.array(values[:n]), comm=V.mesh.comm)


class LinearContactProblem:
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
            form_compiler_options: Passed to :func:`dolfinx.fem.form`.
            jit_options: Passed to :func:`dolfinx.fem.form`.

        Raises:
            ValueError: On every rank, for inconsistent input or a mesh with NaN or
                infinite coordinates.
        """
        # h2: the types of a, L, pairs and bcs (a swap of pairs and bcs) raise TypeError
        check_problem_arguments(a, L, pairs, bcs, type(self).__name__)
        a, L = _as_list(a), _as_list(L)
        if len(a) != len(L) or not a:
            raise ValueError("give one bilinear and one linear form per displacement space")
        if kind not in ("aij", "nest"):
            raise ValueError(f"kind must be 'aij' or 'nest', not {kind!r}")
        self.spaces: list[dolfinx.fem.FunctionSpace] = []
        for ai, Li in zip(a, L, strict=True):
            test, trial = (arg.ufl_function_space() for arg in ai.arguments())
            if test is not trial or Li.arguments()[0].ufl_function_space() is not test:
                raise ValueError("each a and L must share one displacement space")
            if any(test is V for V in self.spaces):
                raise ValueError("each displacement space may carry only one form a")
            self.spaces.append(test)
        self.comm: MPI.Comm = self.spaces[0].mesh.comm
        _check_coordinates(self.spaces)
        options = {"form_compiler_options": form_compiler_options, "jit_options": jit_options}
        self.a = [dolfinx.fem.form(ai, **options) for ai in a]
        self.L = [dolfinx.fem.form(Li, **options) for Li in L]
        self.pairs = list(pairs)
        self._check_pairs()
        self.bcs = list(bcs)
        self.bcs_by_space = [[bc for bc in self.bcs if _contains(V, bc)] for V in self.spaces]
        if sum(len(b) for b in self.bcs_by_space) != len(self.bcs):
            raise ValueError("a Dirichlet condition is on none of the problem's spaces")
        self.kind = kind
        self.residual_tolerance = float(residual_tolerance)
        #: Times a MUMPS workspace error is met by doubling ICNTL(14) before raising.
        self.workspace_retries = 3

        self.u = [dolfinx.fem.Function(V, name=f"u{i}") for i, V in enumerate(self.spaces)]
        self.multipliers = [
            dolfinx.fem.Function(pair.Q, name=f"lambda{j}") for j, pair in enumerate(self.pairs)
        ]
        self._K: list[PETSc.Mat] = []
        #: Whether every assembled :math:`\mathbf K` is symmetric (set by :meth:`assemble`).
        self.symmetric = True
        self._loads = [_create_vector(V) for V in self.spaces]
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

        #: Called as ``solver_setup(self)`` each time the solver is configured for a new
        #: system, e.g. :class:`dolfinx_contact_s2s.fieldsplit.SchurComplementSetup`.
        self.solver_setup: typing.Callable[[LinearContactProblem], None] | None = None
        self.options = PETScOptions(petsc_options_prefix, petsc_options, self._default_options())
        # h2: an unknown ksp, pc or snes type raises ValueError on every rank, before PETSc
        check_solver_types(self.options, self.comm)
        self.solver = PETSc.KSP().create(self.comm)
        self.options.apply(self.solver)

    @contextlib.contextmanager
    def _timed(self, stage: str) -> Iterator[None]:
        """Add the wall time of the block to :attr:`timings` ``[stage]``."""
        begin = time.perf_counter()
        try:
            yield
        finally:
            self.timings[stage] += time.perf_counter() - begin

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

    def _default_options(self) -> dict[str, typing.Any]:
        """Solver defaults of this problem; each yields to ``petsc_options`` and the database."""
        return dict(DEFAULT_OPTIONS)

    # --- set-up checks --------------------------------------------------------------

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

    def _check_pairs(self) -> None:
        seen: dict[tuple[int, int], int] = {}
        for j, pair in enumerate(self.pairs):
            for surface in (pair.contactor, *pair.targets):
                self.space_index(surface.V)
            key = (id(pair.contactor.V.mesh), pair.contactor.tag)
            if key in seen:
                raise ValueError(
                    f"pairs {seen[key]} and {j} share the contactor surface (tag "
                    f"{pair.contactor.tag}): a contactor carries one multiplier field, so give "
                    "all its targets to one pair, contact_pair(contactor, [target_a, target_b])"
                )
            seen[key] = j

    # --- assembly -------------------------------------------------------------------

    def dirichlet_mask(self, i: int) -> PETSc.Vec:
        """1 at the free dofs of space ``i``, 0 at its Dirichlet dofs (owned layout).

        The caller must ``destroy()`` it.
        """
        keep = dolfinx.fem.Function(self.spaces[i])
        keep.x.array[:] = 1.0
        for bc in self.bcs_by_space[i]:
            keep.x.array[bc.dof_indices()[0]] = 0.0
        return _owned_vec(self.spaces[i], keep.x.array)

    def dirichlet_values(self, i: int) -> PETSc.Vec:
        """The Dirichlet values of space ``i``, zero elsewhere (owned layout); destroy it."""
        values = dolfinx.fem.Function(self.spaces[i])
        for bc in self.bcs_by_space[i]:
            bc.set(values.x.array)
        return _owned_vec(self.spaces[i], values.x.array)

    @staticmethod
    def _active(op: CouplingOperator, inactive: npt.NDArray[np.int64]) -> PETSc.Vec:
        """1 for the constrained multipliers of a pair, 0 at the global dofs ``inactive``."""
        active = op.G.duplicate()
        active.set(1.0)
        start, end = active.getOwnershipRange()
        mine = inactive[(inactive >= start) & (inactive < end)]
        active.array[mine - start] = 0.0
        return active

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
                constraints (Eq. 35). Only diagnostics of singular discretizations
                (:mod:`dolfinx_contact_s2s.analysis.dense`) leave it out.

        Raises:
            ValueError: On every rank, if some :math:`\mathbf K` or :math:`\mathbf F`
                has NaN or infinite entries; with ``check``, if a body is not supported
                or constraints are redundant.
        """
        self._destroy_assembly()
        if not self._K:
            self._create_stiffness()
        with self._timed("stiffness"):
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
            self._check_finite()
        with self._timed("system"):
            self._decide_symmetry()
            self._masks = [self.dirichlet_mask(i) for i in range(len(self.spaces))]
            self._values = [self.dirichlet_values(i) for i in range(len(self.spaces))]
            self._owned.extend(self._masks + self._values)
            # h2: a body with zero (or negative) stiffness raises before any factorization
            check_stiffness(self.spaces, self._K, self._masks, self._labels)
        with self._timed("contact"):
            self.operators = [assemble_coupling(pair) for pair in self.pairs]
        for j, op in enumerate(self.operators):
            if op.uncovered.size:
                logger.info(
                    "pair %d: %d multipliers face no target and are set to zero",
                    j,
                    op.uncovered.size,
                )
        if check:
            with self._timed("system"):
                self._check_support(self._masks)
                self._check_redundancy(self._masks)
        self._build_system()

    def _check_finite(self) -> None:
        r"""Raise on every rank if some :math:`\mathbf K` or :math:`\mathbf F` is not finite.

        A NaN or infinite material value, load or coefficient of the user's forms would
        otherwise reach the factorization, which fails on some ranks only, or not at all.
        """
        for i, (K, F) in enumerate(zip(self._K, self._loads, strict=True)):
            # Norms are collective and the same on every rank.
            for name, norm, form in (
                ("stiffness matrix K", K.norm(PETSc.NormType.FROBENIUS), "a"),
                ("load vector F", F.norm(), "L"),
            ):
                if not np.isfinite(norm):
                    raise ValueError(
                        f"the {name} of space {i} has NaN or infinite entries: check the "
                        f"material parameters, coefficients and constants of the form "
                        f"{form}[{i}] (and the Dirichlet values)"
                    )

    def _decide_symmetry(self) -> None:
        r"""Set :attr:`symmetric` from the assembled :math:`\mathbf K` (collective)."""
        flags = [is_symmetric(K) for K in self._K]
        self.symmetric = all(flags)
        if not self.symmetric:
            spaces = ", ".join(str(i) for i, f in enumerate(flags) if not f)
            logger.info(
                "K of space(s) %s is not symmetric: the saddle point is factorized by "
                "LU, not LDL^T",
                spaces,
            )

    def _build_system(
        self, released: Sequence[npt.NDArray[np.int64]] | None = None, load: float = 1.0
    ) -> None:
        r"""The saddle point of Eq. (18) from the assembled blocks.

        Args:
            released: Per pair, global multipliers set to zero besides the pair's
                inactive ones (the inactive set of a unilateral contact iteration).
            load: Factor on :math:`\mathbf F` and the Dirichlet values.
        """
        with self._timed("system"):
            self._assemble_system(released, load)

    def _assemble_system(
        self, released: Sequence[npt.NDArray[np.int64]] | None, load: float
    ) -> None:
        nb, npairs = len(self.spaces), len(self.pairs)
        # K lives in the previous A only (kind="aij"): take it out before A goes, and
        # free the previous factorization first, so that K is never stored twice
        # beside a factor.
        extracted = [] if self._K else [self.stiffness_matrix(i) for i in range(nb)]
        if extracted:
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
            active = self._active(op, off)
            G = op.G.copy()
            masked = []
            for V, B in op.blocks:
                i = self.space_index(V)
                # -B U = G with U = U_free + t U_D  =>  -B U_free = G + t B U_D.
                self._add_scaled(B, self._values[i], load, G)
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
            if self.comm.allreduce(off.size):
                # Inactive multipliers: the row reads lambda_k = 0.
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

        nest = PETSc.Mat().createNest(blocks, comm=self.comm)
        nest.assemble()
        index_sets = nest.getNestISs()[0]
        names = [f"u{i}" for i in range(nb)] + [f"lambda{j}" for j in range(npairs)]
        self.fields = dict(zip(names, index_sets, strict=True))
        self._system.extend(index_sets)
        if self.kind == "nest":
            self.A = nest
            self.b = self._plain_vector(nest)
            self._system.append(nest)
        else:
            self.A = nest.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())
            # K now lives in A: no second copy (the nest, K and the extracted copies).
            nest.destroy()
            for K in extracted:
                K.destroy()
            self._release_stiffness()
            self._system.append(self.A)
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

    @staticmethod
    def _add_scaled(B: PETSc.Mat, u: PETSc.Vec, t: float, y: PETSc.Vec) -> None:
        """``y += t B u``."""
        w = B.createVecLeft()
        B.mult(u, w)
        y.axpy(t, w)
        w.destroy()

    @staticmethod
    def _plain_vector(nest: PETSc.Mat) -> PETSc.Vec:
        """An MPI vector in the row layout of a ``MatNest`` (the nest reads it by index sets)."""
        n, N = nest.getSizes()[0]
        return PETSc.Vec().createMPI((n, N), comm=nest.getComm())

    def _choose_factorization(self) -> None:
        """The default ``pc_type``: :math:`LDL^T` if :attr:`symmetric`, else LU.

        Only a default factorization is adapted: a ``pc_type`` from ``petsc_options``, the
        database, or a subclass's :meth:`_default_options` other than ``"lu"`` and
        ``"cholesky"`` (``"fieldsplit"``, say) is left alone.
        """
        assert self.A is not None
        if self.options.get("pc_type") in ("lu", "cholesky"):
            self.options.set_default("pc_type", "cholesky" if self.symmetric else "lu")
        self.A.setOption(PETSc.Mat.Option.SYMMETRIC, self.symmetric)

    def _configure_solver(self) -> None:
        """Operator, options and named fields (``-prefix_pc_type fieldsplit``) of the solver."""
        assert self.A is not None
        self._choose_factorization()
        self.solver.setOperators(self.A)
        self.options.apply(self.A, suffixes=["A_"])
        self.options.apply(self.solver)
        self.solver.getPC().setFieldSplitIS(*self.fields.items())
        if self.solver_setup is not None:
            self.solver_setup(self)

    def _check_support(self, masks: list[PETSc.Vec]) -> None:
        constraints = [[(self.space_index(V), B) for V, B in op.blocks] for op in self.operators]
        # Kept: a unilateral iteration checks its active sets against it (without K).
        self._support = checks.support_gram(
            self.spaces, self._K, masks, constraints, labels=self._labels
        )
        motions = self._support.motions([op.inactive for op in self.operators])
        if motions:
            # h2: the error names the Dirichlet condition frictionless contact cannot replace
            raise unsupported_error(motions, self._support)

    def _check_redundancy(self, masks: list[PETSc.Vec]) -> None:
        constraints = [[(self.space_index(V), B) for V, B in op.blocks] for op in self.operators]
        inactive = [op.inactive for op in self.operators]
        if not constraints:
            return

        def redundancy(which: list[int]) -> checks.Redundancy:
            return checks.joint_redundant_constraints(
                [constraints[j] for j in which], masks, [inactive[j] for j in which]
            )

        report = redundancy(list(range(len(constraints))))
        if report.redundant == 0:
            return
        # Name the culprit: a pair alone, else two pairs that share a space.
        groups = [[j] for j in range(len(constraints))] if len(constraints) > 1 else []
        groups += [
            [i, j]
            for i in range(len(constraints))
            for j in range(i + 1, len(constraints))
            if {s for s, _ in constraints[i]} & {s for s, _ in constraints[j]}
        ]
        for which in groups:
            found = redundancy(which)
            if found.redundant > 0:
                raise self._redundancy_error(which, found, constraints, masks, inactive)
        raise self._redundancy_error(
            list(range(len(constraints))), report, constraints, masks, inactive
        )

    def _redundancy_error(
        self,
        which: list[int],
        report: checks.Redundancy,
        constraints: list[list[tuple[int, PETSc.Mat]]],
        masks: list[PETSc.Vec],
        inactive: list[npt.NDArray[np.int64]],
    ) -> ValueError:
        """The error for redundant constraints of the pairs ``which`` (Eq. 35)."""
        named = ""
        if report.active <= 2000:
            rows = checks.joint_redundant_multipliers(
                [constraints[j] for j in which], masks, [inactive[j] for j in which]
            )
            x = [_dof_coordinates(self.pairs[j].Q) for j in which]
            label = (lambda k: f"pair {which[k]} ") if len(which) > 1 else (lambda k: "")
            named = (
                " Dependent multipliers, at: "
                + "; ".join(
                    ", ".join(
                        f"{label(k)}({x[k][r, 0]:.4g}, {x[k][r, 1]:.4g})" for k, r in group[:4]
                    )
                    for group in rows[:5]
                )
                + "."
            )
        pairs = " and ".join(
            f"pair {j} ({self.pairs[j].method}, contactor tag {self.pairs[j].contactor.tag})"
            for j in which
        )
        together = (
            " together, though each alone has full row rank (two passes constrain the same "
            "motion twice)"
            if len(which) > 1
            else ""
        )
        return ValueError(
            f"{pairs} {'have' if len(which) > 1 else 'has'} {report.redundant} redundant "
            f"constraint(s) of {report.active} ({report.zero} act only on Dirichlet "
            f"dofs){together}: B has no full row rank (Eq. 35), so the multipliers are not "
            f"determined.{named} Choose a stable discretization (segment-to-segment with a "
            "continuous multiplier, section 5)."
        )

    # --- solve ----------------------------------------------------------------------

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
        self._solve_system()
        # h2: a tied pair that closed open initial gaps by tension gets a UserWarning
        warn_tied_gaps(self)
        return self.u, self.multipliers

    def _solve_system(self) -> None:
        """Solve the current saddle point, check the solve and scatter the solution."""
        with self._timed("solve"):
            self._solve_checked()

    def _solve_checked(self) -> None:
        assert self.A is not None and self.b is not None and self.x is not None
        self._solve_retrying(self.solver, self._configure_solver, self.b, self.x)
        if self.solver.getConvergedReason() < 0:
            raise RuntimeError(
                "the contact solve failed: " + solver_failure(self.solver, self.options.prefix)
            )
        self._check_residual()
        self._scatter()

    def _solve_retrying(
        self, ksp: PETSc.KSP, configure: typing.Callable[[], None], b: PETSc.Vec, x: PETSc.Vec
    ) -> None:
        """``ksp.solve(b, x)``; a MUMPS workspace error is met by doubling ICNTL(14).

        Args:
            ksp: The solver, configured.
            configure: Gives the reset ``ksp`` its operator and options again.
            b: Right-hand side.
            x: Solution.
        """
        ksp.solve(b, x)
        for _ in range(self.workspace_retries):
            F = mumps_factor(ksp)
            if ksp.getConvergedReason() >= 0 or F is None:
                break
            if F.getMumpsInfog(1) not in MUMPS_WORKSPACE_ERRORS:
                break
            icntl = max(2 * F.getMumpsIcntl(14), F.getMumpsIcntl(14) + 50)
            logger.info("MUMPS workspace too small: retrying with ICNTL(14) = %d", icntl)
            self.options.set("mat_mumps_icntl_14", icntl)
            # A new factor reads the raised ICNTL(14) from the database.
            ksp.reset()
            configure()
            ksp.solve(b, x)

    def _scatter(self) -> None:
        """Copy the solution :attr:`x` into :attr:`u` and :attr:`multipliers`."""
        assert self.x is not None
        for f, is_ in zip(self.u + self.multipliers, self.fields.values(), strict=True):
            sub = self.x.getSubVector(is_)
            f.x.array[: sub.getLocalSize()] = sub.array_r
            self.x.restoreSubVector(is_, sub)
            f.x.scatter_forward()

    def residual(self) -> float:
        r"""Relative residual :math:`\|\mathbf b - \mathbf A \mathbf x\|_2 / \|\mathbf b\|_2`."""
        assert self.A is not None and self.b is not None and self.x is not None
        r = self.b.duplicate()
        self.A.mult(self.x, r)
        r.aypx(-1.0, self.b)
        rnorm, bnorm = r.norm(), self.b.norm()
        r.destroy()
        return rnorm / bnorm if bnorm > 0 else rnorm

    def backward_error(self) -> float:
        r"""Normwise backward error of the last solve (Rigal-Gaches).

        :math:`\eta = \|\mathbf b - \mathbf A\mathbf x\|_\infty / (\|\mathbf A\|_\infty
        \|\mathbf x\|_\infty + \|\mathbf b\|_\infty)`, the smallest relative normwise
        perturbation of :math:`\mathbf A` and :math:`\mathbf b` of which :attr:`x` is the
        exact solution. Collective. Needs the assembled saddle point (``kind="aij"``):
        ``inf`` for a ``"nest"`` matrix.
        """
        assert self.A is not None and self.b is not None and self.x is not None
        if self.A.getType() == PETSc.Mat.Type.NEST:
            return float("inf")
        r = self.b.duplicate()
        self.A.mult(self.x, r)
        r.aypx(-1.0, self.b)
        rnorm = r.norm(PETSc.NormType.INFINITY)
        r.destroy()
        inf = PETSc.NormType.INFINITY
        scale = self.A.norm(inf) * self.x.norm(inf) + self.b.norm(inf)
        return rnorm / scale if scale > 0 else rnorm

    def _check_residual(self) -> None:
        r"""Raise unless the solve is trusted: a small relative residual, else backward error.

        The relative residual :math:`\|\mathbf r\| / \|\mathbf b\|` alone fails a
        backward-stable direct solve whenever :math:`\|\mathbf b\| \ll \|\mathbf
        A\|\|\mathbf x\|`: with a Young's modulus ratio of :math:`10^6` between the
        README's bodies, MUMPS leaves :math:`\|\mathbf r\|/\|\mathbf b\| = 1.4 \cdot
        10^{-8}` (P2) while the normwise backward error :meth:`backward_error` is 0.5
        machine epsilons. Such a solution is the exact one of a system within round-off of
        Eq. (18), and its accuracy is the conditioning's
        (:func:`~dolfinx_contact_s2s.analysis.roundoff.round_off_bound`). A solve is therefore
        trusted when either measure is small. A wrong factorization (:math:`LDL^T` of a
        nonsymmetric matrix) or a preconditioner sweep taken for a solve leave a backward
        error many orders above :data:`BACKWARD_TOLERANCE` and still raise; singular
        models are caught before the solve (Eqs. 33 and 35). The componentwise
        (Oettli-Prager) backward error was not chosen: it reached 1000 machine epsilons
        on good solves at a contrast of :math:`10^{-6}` (rows of tiny
        :math:`|\mathbf A||\mathbf x|`), too close to a usable tolerance.
        """
        residual = self.residual()
        if residual <= self.residual_tolerance:
            return
        backward = self.backward_error()
        if backward <= BACKWARD_TOLERANCE:
            logger.info(
                "relative residual %.2e > %.0e, but backward error %.2e <= %.2e: trusted",
                residual,
                self.residual_tolerance,
                backward,
                BACKWARD_TOLERANCE,
            )
            return
        raise RuntimeError(
            f"the contact solve cannot be trusted: relative residual {residual:.2e} > "
            f"{self.residual_tolerance:.0e} and normwise backward error {backward:.2e} > "
            f"{BACKWARD_TOLERANCE:.1e}. The saddle-point matrix is (nearly) singular "
            "or too ill-conditioned for this solver (check the supports, the element "
            "quality and nu close to 1/2), or an iterative solver stopped early "
            f"({solver_failure(self.solver, self.options.prefix)})."
        )

    def contact_forces(self) -> list[dolfinx.fem.Function]:
        r"""Nodal contact force on every space, :math:`\sum_j \mathbf B_{j}^T \Lambda_j`.

        Call after :meth:`solve`. Includes the forces at Dirichlet dofs (taken by the
        supports).
        """
        forces = [
            dolfinx.fem.Function(V, name=f"contact_force{i}") for i, V in enumerate(self.spaces)
        ]
        for op, lam in zip(self.operators, self.multipliers, strict=True):
            for V, B in op.blocks:
                f = forces[self.space_index(V)]
                y = B.createVecRight()
                B.multTranspose(lam.x.petsc_vec, y)
                f.x.array[: y.getLocalSize()] += y.array_r
                y.destroy()
        for f in forces:
            f.x.scatter_forward()
        return forces

    def destroy(self) -> None:
        """Destroy the PETSc objects and remove the problem's options from the database."""
        self._destroy_assembly()
        for obj in [self.solver, *self._K, *self._loads, *self.near_nullspaces]:
            obj.destroy()
        self.options.clear()

    def __enter__(self) -> LinearContactProblem:
        """Use as a context manager: :meth:`destroy` on exit."""
        return self

    def __exit__(self, *exc: object) -> None:
        """Destroy the PETSc objects."""
        self.destroy()

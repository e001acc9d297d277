# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The inf-sup test of Eqs. (26)-(32) for large meshes: one factorization.

By default MUMPS also returns the Schur complement on the multipliers (ICNTL(19)), a
dense matrix as small as the contact line, whose generalized eigenproblem is solved
densely: the test costs one factorization. Beyond :data:`SCHUR_LIMIT` multipliers,
SLEPc finds the smallest eigenvalue with back-substitutions instead.

The dense reference, exactly as the paper states the test, is
:func:`dolfinx_contact_s2s.analysis.dense.inf_sup_dense`; both take any
:class:`~dolfinx_contact_s2s.problem.LinearContactProblem`. This module needs
petsc4py (and slepc4py for :meth:`InfSupTest.solve`).
"""

from __future__ import annotations

from petsc4py import PETSc

import numpy as np
import numpy.typing as npt
import scipy.linalg

from dolfinx_contact_s2s.analysis.dense import (
    InfSup,
    assembled,
    dirichlet_free,
    dual_norm_matrix,
    norm_matrices,
    stack_pairs,
)
from dolfinx_contact_s2s.assemble import multiplier_mass
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.mumps import schur_complement, set_schur_indices
from dolfinx_contact_s2s.options import PETScOptions
from dolfinx_contact_s2s.problem import LinearContactProblem

__all__ = ["SCHUR_LIMIT", "InfSupTest", "inf_sup"]

#: Most multipliers for which the dense Schur complement is formed by default (its
#: size grows with their square: 5,000 take 200 MB on process 0).
SCHUR_LIMIT = 5000


class _InverseSchur:
    r"""Shell operator :math:`\mathbf P (\Sigma - \tau \mathbf P)^{-1} \mathbf P`.

    Each product is one saddle-point back-substitution.
    """

    def __init__(self, test: InfSupTest):
        self.test = test
        self.solves = 0

    def mult(self, mat: PETSc.Mat, x: PETSc.Vec, y: PETSc.Vec) -> None:
        t = self.test
        t.P.mult(x, t._z)
        t._rhs.set(0.0)
        t._scatter(t._z, t._rhs, forward=True)
        t.ksp.solve(t._rhs, t._sol)
        self.solves += 1
        t._scatter(t._z, t._sol, forward=False)
        # [[S, B^T], [B, tau P]] [u; p] = [0; y]  gives  p = -(Sigma - tau P)^{-1} y.
        t.P.mult(t._z, y)
        y.scale(-1.0)


class InfSupTest:
    r"""The inf-sup test of Eqs. (26)-(32) for large meshes, with one factorization.

    The non-zero eigenvalues of Eq. (30) are those of the pencil on the multipliers

    .. math:: \Sigma \mathbf M = \lambda\, h \mathbf P \mathbf M, \qquad
        \Sigma = \mathbf B \mathbf S^{-1} \mathbf B^T,

    and :math:`(\Sigma - \tau h \mathbf P)^{-1}` is (minus) the multiplier block of the
    inverse of the shifted saddle-point matrix

    .. math:: \mathbf A_\tau = \begin{bmatrix} \mathbf S & \mathbf B^T \\
        \mathbf B & \tau h \mathbf P \end{bmatrix},

    factorized once (symmetric indefinite :math:`LDL^T`, MUMPS).

    With ``schur`` (the default up to :data:`SCHUR_LIMIT` multipliers), the
    factorization also yields the dense Schur complement :math:`\mathbf C = \tau h
    \mathbf P - \Sigma` (MUMPS's ICNTL(19)), and the pencil :math:`(\tau h \mathbf P -
    \mathbf C, h \mathbf P)` is solved densely: every eigenvalue, the pressure modes
    (those :math:`\le \tau`) included, for the cost of one factorization.

    Otherwise, since :math:`\mathbf
    S` is positive definite, Sylvester's law of inertia gives the number of negative
    pivots of :math:`\mathbf A_\tau` as the number of eigenvalues :math:`\lambda >
    \tau`, so that

    - the pressure modes, the eigenvalues :math:`\lambda \le \tau` (Eq. 32; zero unless
      :math:`\mathbf B` is rank deficient, Eq. 35), are counted exactly by the inertia;
    - if there are none, SLEPc finds the largest eigenvalue :math:`\mu` of
      :math:`h \mathbf P (\Sigma - \tau h \mathbf P)^{-1} h \mathbf P \mathbf M = \mu\,
      h \mathbf P \mathbf M` (generalized Hermitian, each product one
      back-substitution), and :math:`\beta^{*2}_h = \lambda_k = \tau + 1/\mu`.

    The multipliers are scaled by :math:`(h P_{ii})^{-1/2}` first, which leaves the
    eigenvalues alone and gives :math:`h \mathbf P` a unit diagonal, so that :math:`\tau`
    is a plain threshold on :math:`\beta^{*2}`. The methods below work on the scaled
    multipliers, where :attr:`P` stands for :math:`h \mathbf P`.
    """

    def __init__(
        self,
        problem: LinearContactProblem,
        h: float,
        *,
        norm: str = "H1",
        petsc_options_prefix: str = "infsup_",
        petsc_options: dict | None = None,
        shift: float = 1e-10,
        schur: bool | None = None,
    ):
        r"""Assemble and factorize the saddle-point matrix.

        Args:
            problem: The contact problem (its spaces, Dirichlet conditions and pairs).
            h: Element size of Eqs. (26) and (31).
            norm: ``"H1"`` (Eq. 28) or ``"energy"`` (:math:`\mathbf S = \mathbf K`).
            petsc_options_prefix: Prefix of the options of the factorization
                (``{prefix}ksp_``, ``{prefix}pc_``, ``{prefix}mat_mumps_``) and of
                the eigensolver (``{prefix}eps_``, ``{prefix}st_``).
            petsc_options: Options set under the prefix (the package's one options
                policy, :class:`~dolfinx_contact_s2s.options.PETScOptions`); the
                defaults, MUMPS :math:`LDL^T`, yield to them and to the database.
            shift: :math:`\tau`: eigenvalues :math:`\beta^{*2} \le \tau` count as
                pressure modes.
            schur: Form the dense Schur complement on the multipliers in the
                factorization (MUMPS ICNTL(19)) and solve the eigenproblem densely;
                ``None``: if there are at most :data:`SCHUR_LIMIT` multipliers.
        """
        if not h > 0:
            raise ValueError(f"the element size h must be positive, not {h}")
        if norm not in ("H1", "energy"):
            raise ValueError(f"norm must be 'H1' or 'energy', not {norm!r}")
        self.h = float(h)
        self.shift = float(shift)
        self.options = PETScOptions(
            petsc_options_prefix,
            petsc_options,
            {"ksp_type": "preonly", "pc_type": "cholesky", "pc_factor_mat_solver_type": "mumps"},
        )
        self.prefix = self.options.prefix
        comm = assembled(problem).comm
        self.comm = comm
        self._S = norm_matrices(problem, norm)
        nb, npairs = len(problem.spaces), len(problem.pairs)
        blocks: list[list[PETSc.Mat | None]] = [[None] * (nb + npairs) for _ in range(nb + npairs)]
        for i, S in enumerate(self._S):
            blocks[i][i] = S
        self._owned = []
        scalings = []
        P_blocks: list[list[PETSc.Mat | None]] = [[None] * npairs for _ in range(npairs)]
        for j, (pair, op, constraint) in enumerate(
            zip(problem.pairs, problem.operators, problem.constraints, strict=True)
        ):
            start, end = pair.Q.dofmap.index_map.local_range
            active = np.setdiff1d(np.arange(start, end, dtype=np.int64), op.inactive)
            rows = PETSc.IS().createGeneral(active.astype(PETSc.IntType), comm=comm)
            M = multiplier_mass(pair)
            P = M.createSubMatrix(rows, rows)
            d = P.getDiagonal()
            d.scale(self.h)
            d.sqrtabs()
            d.reciprocal()
            P.diagonalScale(d, d)
            P.scale(self.h)
            P_blocks[j][j] = P
            scalings.append(d)
            shifted = P.copy()
            shifted.scale(shift)
            blocks[nb + j][nb + j] = shifted
            self._owned.append(shifted)
            for i, Bi in constraint:
                c0, c1 = Bi.getOwnershipRangeColumn()
                cols = PETSc.IS().createStride(c1 - c0, first=c0, step=1, comm=comm)
                B = Bi.createSubMatrix(rows, cols)
                B.diagonalScale(d, None)
                Bt = PETSc.Mat()
                B.transpose(Bt)
                blocks[nb + j][i] = B
                blocks[i][nb + j] = Bt
                self._owned.extend([B, Bt, cols])
            self._owned.extend([M, rows, d])
        self._nest = PETSc.Mat().createNest(blocks, comm=comm)
        self._P_nest = PETSc.Mat().createNest(P_blocks, comm=comm)
        self.A = self._nest.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())
        self.A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        #: :math:`h \mathbf D \mathbf P \mathbf D` on the scaled multipliers.
        self.P = self._P_nest.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())
        self._is_saddle = list(self._nest.getNestISs()[0])[nb:]
        self._is_mult = list(self._P_nest.getNestISs()[0])
        self.constraints = self.P.getSize()[0]
        self.displacements = sum(S.getSize()[0] for S in self._S) - self._dirichlet_count(problem)
        self._rhs, self._sol = self.A.createVecRight(), self.A.createVecRight()
        self._z = self.P.createVecRight()
        #: The scaling :math:`(h P_{ii})^{-1/2}` of the multipliers.
        self._scaling = self.P.createVecRight()
        for d, is_m in zip(scalings, self._is_mult, strict=True):
            sub = self._scaling.getSubVector(is_m)
            sub.array[:] = d.array_r
            self._scaling.restoreSubVector(is_m, sub)
        # S now lives in A alone: no second copy beside the factorization.
        for obj in [self._nest, self._P_nest, *self._S, *self._owned]:
            obj.destroy()
        self._S, self._owned = [], []

        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setOperators(self.A)
        self.options.apply(self.ksp)
        pc = self.ksp.getPC()
        if pc.getType() != "cholesky" or pc.getFactorSolverType() != "mumps":
            raise ValueError("the inf-sup test counts pressure modes with MUMPS LDL^T (cholesky)")
        pc.setFactorSetUpSolverType()
        F = pc.getFactorMatrix()
        F.setMumpsIcntl(13, 1)  # inertia of the root front too (no ScaLAPACK there)
        #: Whether the eigenproblem is solved densely on MUMPS's Schur complement.
        self.schur = self.constraints <= SCHUR_LIMIT if schur is None else bool(schur)
        schur_rows, order = self._schur_rows() if self.schur else (None, None)
        if schur_rows is not None:
            set_schur_indices(F, schur_rows)
        self.ksp.setUp()
        if F.getMumpsInfog(1) < 0:
            raise RuntimeError(f"MUMPS failed to factorize (INFOG(1) = {F.getMumpsInfog(1)})")
        #: The dense Schur complement :math:`\tau \mathbf P - \Sigma` (scaled
        #: multipliers, in the order of :attr:`P`), with ``schur``.
        self.C: npt.NDArray[np.floating] | None = None
        #: Every eigenvalue of the pencil, ascending, with ``schur``.
        self.eigenvalues: npt.NDArray[np.floating] | None = None
        if schur_rows is not None:
            assert order is not None
            C = np.empty((self.constraints, self.constraints))
            C[np.ix_(order, order)] = schur_complement(F)
            self.C = C
            P = gather_dense(self.P)
            self.eigenvalues = scipy.linalg.eigh(self.shift * P - C, P, eigvals_only=True)
            schur_rows.destroy()
            #: :math:`k_{pm}`: the eigenvalues :math:`\lambda \le \tau`.
            self.pressure_modes = int(np.count_nonzero(self.eigenvalues <= self.shift))
        else:
            negative = int(F.getMumpsInfog(12))
            # k_pm: the eigenvalues lambda <= tau, from the inertia.
            self.pressure_modes = self.constraints - negative

    def _schur_rows(self) -> tuple[PETSc.IS, npt.NDArray[np.int64]]:
        """The multipliers' rows of :attr:`A`, all on process 0 (as PETSc wants them).

        Returns:
            The index set (sorted; empty except on process 0) and, for each of its
            entries, the position of the multiplier in :attr:`P`.
        """
        saddle = np.concatenate([is_.getIndices() for is_ in self._is_saddle] or [[]])
        mult = np.concatenate([is_.getIndices() for is_ in self._is_mult] or [[]])
        parts = self.comm.gather((saddle.astype(np.int64), mult.astype(np.int64)), root=0)
        rows = np.zeros(0, dtype=PETSc.IntType)
        order = np.zeros(0, dtype=np.int64)
        if self.comm.rank == 0:
            assert parts is not None
            all_saddle = np.concatenate([a for a, _ in parts])
            all_mult = np.concatenate([b for _, b in parts])
            sort = np.argsort(all_saddle)
            rows = all_saddle[sort].astype(PETSc.IntType)
            order = all_mult[sort]
        order = self.comm.bcast(order, root=0)
        return PETSc.IS().createGeneral(rows, comm=self.comm), order

    @staticmethod
    def _dirichlet_count(problem: LinearContactProblem) -> int:
        return int(np.count_nonzero(~dirichlet_free(problem)))

    def _scatter(self, x: PETSc.Vec, y: PETSc.Vec, forward: bool) -> None:
        """Copy the multipliers between ``x`` (multiplier space) and ``y`` (saddle)."""
        for is_m, is_s in zip(self._is_mult, self._is_saddle, strict=True):
            a, b = x.getSubVector(is_m), y.getSubVector(is_s)
            if forward:
                b.array[:] = a.array_r
            else:
                a.array[:] = b.array_r
            x.restoreSubVector(is_m, a)
            y.restoreSubVector(is_s, b)

    def solve(self, eigenvalues: int = 1, tol: float = 1e-10) -> InfSup:
        r"""Compute :math:`\beta^*_h` (Eq. 27) and the smallest ``eigenvalues`` of Eq. (30).

        Raises:
            RuntimeError: On every rank, if SLEPc does not converge.
        """
        if self.pressure_modes > 0:
            return InfSup(0.0, self.pressure_modes, self.constraints, self.displacements, self.h)
        if self.eigenvalues is not None:
            return self._result(tuple(float(x) for x in self.eigenvalues[:eigenvalues]), 0)
        from slepc4py import SLEPc

        context = _InverseSchur(self)
        n_local = self.P.getLocalSize()[0]
        op = PETSc.Mat().createPython([[n_local, self.constraints]] * 2, context, comm=self.comm)
        op.setUp()
        eps = SLEPc.EPS().create(self.comm)
        eps.setOperators(op, self.P)
        eps.setProblemType(SLEPc.EPS.ProblemType.GHEP)
        eps.setWhichEigenpairs(SLEPc.EPS.Which.LARGEST_REAL)
        # The smallest eigenvalues cluster (more so on finer meshes): a wide basis
        # saves restarts, hence back-substitutions.
        nev = min(eigenvalues, self.constraints)
        eps.setDimensions(nev, min(self.constraints, max(2 * nev, 48)))
        eps.setTolerances(tol, 1000)
        st = eps.getST()
        st.setType(SLEPc.ST.Type.SHIFT)
        st_ksp = st.getKSP()
        st_ksp.setType("preonly")
        st_ksp.getPC().setType("cholesky")
        st_ksp.getPC().setFactorSolverType("mumps")
        self.options.apply(eps)
        eps.solve()
        nconv = eps.getConverged()
        if nconv < 1:
            iterations = eps.getIterationNumber()
            eps.destroy()
            op.destroy()
            raise RuntimeError(
                f"the inf-sup eigensolver did not converge ({iterations} iterations)"
            )
        mu = sorted((eps.getEigenvalue(i).real for i in range(nconv)), reverse=True)
        lam = tuple(self.shift + 1.0 / m for m in mu[:eigenvalues])
        eps.destroy()
        op.destroy()
        return self._result(lam, context.solves)

    def _result(self, lam: tuple[float, ...], solves: int) -> InfSup:
        r"""From the smallest eigenvalues of Eq. (30): :math:`\beta^* = \sqrt{\lambda_1}`."""
        return InfSup(
            float(np.sqrt(lam[0])),
            0,
            self.constraints,
            self.displacements,
            self.h,
            eigenvalues=lam,
            solves=solves,
        )

    def inverse_schur(self, block: int = 64) -> npt.NDArray[np.floating]:
        r"""Dense :math:`(\Sigma - \tau \mathbf P)^{-1}`, scaled, on every process.

        One back-substitution per multiplier, ``block`` right-hand sides at a time
        (``MatMatSolve``): meant for a moderate number :math:`n` of multipliers. With
        ``schur``: :math:`-\mathbf C^{-1}`, no back-substitution.
        """
        if self.C is not None:
            Y = -np.linalg.inv(self.C)
            return 0.5 * (Y + Y.T)
        n = self.constraints
        Y = np.zeros((n, n))
        start, end = self.P.getOwnershipRange()
        # Rows of the saddle-point vector that hold the owned multipliers, in order.
        rows = np.empty(end - start, dtype=np.int64)
        r0 = self.A.getOwnershipRange()[0]
        for is_m, is_s in zip(self._is_mult, self._is_saddle, strict=True):
            rows[is_m.getIndices() - start] = is_s.getIndices() - r0
        F = self.ksp.getPC().getFactorMatrix()
        local = self.A.getLocalSize()[0]
        for first in range(0, n, block):
            cols = np.arange(first, min(first + block, n))
            E = PETSc.Mat().createDense([[local, None], [None, cols.size]], comm=self.comm)
            E.setUp()
            e = E.getDenseArray()
            e[:] = 0.0
            owned = cols[(cols >= start) & (cols < end)]
            e[rows[owned - start], owned - first] = 1.0
            E.assemble()
            X = E.duplicate()
            F.matSolve(E, X)
            Y[start:end, cols] = -X.getDenseArray()[rows, :]
            E.destroy()
            X.destroy()
        Y = self.comm.allreduce(Y)
        return 0.5 * (Y + Y.T)

    def _smallest(self, N: npt.NDArray[np.floating], count: int = 1) -> npt.NDArray:
        r"""Smallest eigenvalues of :math:`\Sigma \mathbf x = \lambda \mathbf N \mathbf x`.

        With :math:`\mathbf Y = (\Sigma - \tau \mathbf P)^{-1} = \mathbf L \mathbf
        L^T`, :math:`\mathbf x = \mathbf L \mathbf w` turns it into :math:`\mathbf L^T
        \mathbf N \mathbf L \mathbf w = \lambda^{-1} (\mathbf I + \tau \mathbf L^T
        \mathbf P \mathbf L) \mathbf w`: the wanted eigenvalues are the largest of a
        pencil whose right-hand matrix is close to the identity, so nothing
        ill-conditioned is inverted.
        """
        L = np.linalg.cholesky(self.inverse_schur())
        P = gather_dense(self.P)
        right = np.eye(L.shape[0]) + self.shift * (L.T @ P @ L)
        nu = scipy.linalg.eigh(L.T @ N @ L, right, eigvals_only=True)[::-1]
        return 1.0 / nu[:count]

    def solve_dense(self) -> InfSup:
        r""":math:`\beta^*_h` from the dense :meth:`inverse_schur`.

        Block back-substitutions instead of the Krylov eigensolver of :meth:`solve`: the
        cost grows with the number of multipliers, not with the conditioning of the
        eigenproblem.
        """
        if self.pressure_modes > 0:
            return InfSup(0.0, self.pressure_modes, self.constraints, self.displacements, self.h)
        lam = self._smallest(gather_dense(self.P), 4)
        return InfSup(
            float(np.sqrt(lam[0])),
            0,
            self.constraints,
            self.displacements,
            self.h,
            eigenvalues=tuple(float(x) for x in lam),
            solves=0 if self.C is not None else self.constraints,
        )

    def _dense_order(self, problem: LinearContactProblem) -> npt.NDArray[np.int64]:
        """Position in the scaled multiplier vector of each row of :func:`_stack_pairs`."""
        order = []
        for pair, op, is_m in zip(problem.pairs, problem.operators, self._is_mult, strict=True):
            start, end = pair.Q.dofmap.index_map.local_range
            active = np.setdiff1d(np.arange(start, end, dtype=np.int64), op.inactive)
            parts = self.comm.allgather((active, is_m.getIndices().astype(np.int64)))
            dofs = np.concatenate([a for a, _ in parts])
            positions = np.concatenate([b for _, b in parts])
            order.append(positions[np.argsort(dofs)])
        return np.concatenate(order)

    def beta_full(self, problem: LinearContactProblem) -> float:
        r""":math:`\beta_h` of Eq. (22), from :meth:`inverse_schur` and :func:`dual_norm_matrix`.

        :math:`\beta_h^2` is the smallest eigenvalue of :math:`\Sigma \mathbf M =
        \lambda \mathbf T \mathbf M`; 0 where pressure modes exist.
        """
        if self.pressure_modes > 0:
            return 0.0
        order = self._dense_order(problem)
        D = self.comm.allreduce(self._scaling_local())
        T = stack_pairs(problem, dual_norm_matrix)
        T_scaled = np.empty_like(T)
        T_scaled[np.ix_(order, order)] = T * np.outer(D[order], D[order])
        return float(np.sqrt(self._smallest(T_scaled)[0]))

    def _scaling_local(self) -> npt.NDArray[np.floating]:
        """The scaling :math:`(h P_{ii})^{-1/2}` of the owned multipliers, in place."""
        out = np.zeros(self.constraints)
        start, end = self.P.getOwnershipRange()
        out[start:end] = self._scaling.array_r
        return out

    def destroy(self) -> None:
        """Destroy the PETSc objects and remove the options from the database."""
        for obj in [
            self.ksp,
            self.A,
            self.P,
            self._rhs,
            self._sol,
            self._z,
            self._scaling,
            *self._S,
            *self._owned,
        ]:
            obj.destroy()
        self.options.clear()


def inf_sup(problem: LinearContactProblem, h: float, **options) -> InfSup:
    r""":math:`\beta^*_h` of Eq. (27) with :class:`InfSupTest` (one factorization, SLEPc).

    Args:
        problem: The contact problem.
        h: Element size.
        options: Passed to :class:`InfSupTest`.
    """
    test = InfSupTest(problem, h, **options)
    try:
        return test.solve()
    finally:
        test.destroy()

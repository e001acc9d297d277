# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Solvability and stability of a contact discretization (section 3.1).

Eq. (18) is solvable when :math:`\mathbf K` is positive definite on the kernel of
:math:`\mathbf B` (Eq. 33: a properly supported structure) and :math:`\mathbf B` has full
row rank (Eqs. 34-35): otherwise some multipliers are not determined, and a direct
solver returns arbitrary values for them. It is stable when, in addition, the inf-sup
values of Eqs. (22) and (26)-(27) stay bounded away from zero as the mesh is refined:
:func:`inf_sup_dense` evaluates them as the paper states them, :class:`InfSupTest` for
large meshes. This module needs petsc4py (and slepc4py for :meth:`InfSupTest.solve`).
"""

from __future__ import annotations

from dataclasses import dataclass

from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import scipy.linalg
import ufl

from dolfinx_contact_s2s.coupling import ContactPair
from dolfinx_contact_s2s.petsc import ContactProblem, gather_dense

__all__ = [
    "InfSup",
    "InfSupTest",
    "Solvability",
    "constraint_matrix",
    "dual_norm_matrix",
    "h1_norm_form",
    "inf_sup",
    "inf_sup_dense",
    "multiplier_mass",
    "solvability",
]


@dataclass(frozen=True)
class Solvability:
    r"""Rank of the constraint matrix (Eq. 35).

    Attributes:
        constraints: Number :math:`n` of active multipliers.
        rank: Numerical rank of :math:`\mathbf B`.
        condition: :math:`\sigma_{max} / \sigma_{min}` of :math:`\mathbf B` (infinite if
            rank deficient).
    """

    constraints: int
    rank: int
    condition: float = np.inf

    @property
    def redundant(self) -> int:
        r"""Number of redundant constraints, :math:`n - \mathrm{rank}(\mathbf B)`."""
        return self.constraints - self.rank

    @property
    def solvable(self) -> bool:
        r"""Whether :math:`\mathrm{rank}(\mathbf B) = n` (Eq. 35)."""
        return self.redundant == 0


def constraint_matrix(problem: ContactProblem) -> npt.NDArray[np.floating]:
    r"""The active rows of :math:`\mathbf B` as a dense array on every process.

    Columns are the displacement dofs of the bodies in order; Dirichlet columns are zero.
    Meant for small problems (reference computations and tests).
    """
    sizes = [V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces]
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    rows = []
    for pair, (B_c, B_t) in zip(problem.pairs, problem.constraints, strict=True):
        n = pair.Q.dofmap.index_map.size_global
        B = np.zeros((n, offsets[-1]))
        for Bi, V in ((B_c, pair.contactor.V), (B_t, pair.target.V)):
            i = next(k for k, W in enumerate(problem.spaces) if W is V)
            B[:, offsets[i] : offsets[i + 1]] += gather_dense(Bi)
        rows.append(np.delete(B, pair.inactive, axis=0))
    return np.vstack(rows)


def solvability(problem: ContactProblem) -> Solvability:
    r"""Rank of :math:`\mathbf B` by a dense SVD (Eq. 35).

    The rank counts singular values above :math:`\sigma_{max} \max(n, m)\,\epsilon`.
    """
    B = constraint_matrix(problem)
    s = scipy.linalg.svdvals(B)
    tol = (s.max(initial=0.0)) * max(B.shape) * np.finfo(float).eps
    rank = int(np.count_nonzero(s > tol))
    condition = s.max() / s.min() if rank == B.shape[0] and rank > 0 else np.inf
    return Solvability(B.shape[0], rank, float(condition))


# --- The inf-sup test (Eqs. 26-32) -------------------------------------------------

#: Methods whose multipliers are nodal values (collocation, Eqs. 37-39).
_NODAL = ("node-to-segment", "node-to-node")


def h1_norm_form(V: dolfinx.fem.FunctionSpace) -> ufl.Form:
    r"""The :math:`H^1` inner product :math:`\int \nabla u : \nabla v + u \cdot v` (Eq. 28)."""
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    return (ufl.inner(ufl.grad(u), ufl.grad(v)) + ufl.inner(u, v)) * ufl.dx


def _lumped(pair: ContactPair, M: PETSc.Mat) -> PETSc.Mat:
    """Diagonal of row sums of ``M`` (the tributary lengths of the nodes)."""
    w = M.createVecLeft()
    M.getRowSum(w)
    D = PETSc.Mat().createAIJ([M.getSizes()[0]] * 2, nnz=(1, 0), comm=M.getComm())
    if pair.weight == "unit":
        # The multiplier is the node's force w_i t_i: ||t||^2 = sum_i mu_i^2 / w_i.
        w.reciprocal()
    D.setDiagonal(w)
    D.assemble()
    w.destroy()
    return D


def multiplier_mass(pair: ContactPair) -> PETSc.Mat:
    r"""The matrix :math:`\mathbf P` of Eq. (29), over all multipliers of ``pair``.

    :math:`\mathbf M^T \mathbf P \mathbf M = \|\mu_h\|^2_{0,\Gamma}`; inactive multipliers
    are included.

    The multiplier of the segment-to-segment methods and of the intermediate surface is
    a function on its mesh: :math:`\mathbf P` is its mass matrix. Node-based methods
    (Eqs. 37-39) collocate the traction at the nodes, each standing for its tributary
    length :math:`w^i`: :math:`\mathbf P` is the lumped mass matrix, or its inverse
    when the multiplier is the nodal force (``weight="unit"``).
    """
    Q = pair.Q
    p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
    M = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(ufl.inner(p, q) * ufl.dx))
    M.assemble()
    if pair.method not in _NODAL:
        return M
    D = _lumped(pair, M)
    M.destroy()
    return D


def _traction_scale(pair: ContactPair) -> npt.NDArray[np.floating]:
    """Factors taking the multipliers of ``pair`` to traction values (all dofs, global)."""
    Q = pair.Q
    n = Q.dofmap.index_map.size_global
    if pair.method not in _NODAL or pair.weight != "unit":
        return np.ones(n)
    M = multiplier_mass(pair)  # diag(1 / w)
    d = gather_dense(M).diagonal().copy()
    M.destroy()
    return d


def dual_norm_matrix(pair: ContactPair) -> npt.NDArray[np.floating]:
    r"""Dense :math:`\mathbf T` of the dual norm of Eqs. (21)-(22), over all multipliers.

    :math:`\mathbf M^T \mathbf T \mathbf M = \|\mu_h\|^2_{-1/2,\Gamma}`.

    The supremum of Eq. (21) is taken over the continuous Lagrange functions
    :math:`W` of degree :math:`s + 2` on the multiplier's mesh (:math:`s` its degree).
    :math:`W` holds a bubble of each element for every moment of the multiplier, so the
    supremum over :math:`W` is equivalent to the one over :math:`H^{1/2}(\Gamma)` with
    constants independent of :math:`h` (a Fortin argument). :math:`\|w\|_{1/2,\Gamma}`
    is the interpolation norm :math:`[L^2, H^1]_{1/2}`: with :math:`\mathbf A \Phi =
    \mathbf M \Phi \Lambda` the :math:`H^1` and :math:`L^2` matrices of :math:`W`,
    :math:`\|w\|^2_{1/2} = \mathbf w^T \mathbf M \Phi \Lambda^{1/2} \Phi^T \mathbf M
    \mathbf w`, whose inverse is :math:`\Phi \Lambda^{-1/2} \Phi^T`, so that
    :math:`\mathbf T = \mathbf F \Phi \Lambda^{-1/2} \Phi^T \mathbf F^T` with
    :math:`F_{ij} = \int_\Gamma \mu_i w_j`. Node-based multipliers are read as the
    continuous traction field through their values. Dense: for reference computations.
    """
    mesh = pair.Q.mesh
    W = dolfinx.fem.functionspace(mesh, ("Lagrange", pair.multiplier_degree + 2))
    w, v = ufl.TrialFunction(W), ufl.TestFunction(W)
    q = ufl.TestFunction(pair.Q)
    forms = [
        (ufl.inner(ufl.grad(w), ufl.grad(v)) + ufl.inner(w, v)) * ufl.dx,
        ufl.inner(w, v) * ufl.dx,
        ufl.inner(w, q) * ufl.dx,
    ]
    A, M, F = (_dense_form(f) for f in forms)
    lam, phi = scipy.linalg.eigh(A, M)
    F *= _traction_scale(pair)[:, None]
    X = F @ phi
    return (X / np.sqrt(lam)) @ X.T


def _dense_form(form: ufl.Form) -> npt.NDArray[np.floating]:
    A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(form))
    A.assemble()
    D = gather_dense(A)
    A.destroy()
    return D


@dataclass(frozen=True)
class InfSup:
    r"""Result of the inf-sup test of Eqs. (26)-(32) (and Eq. 22).

    Attributes:
        beta: :math:`\beta^*_h` of Eq. (27): the square root of the smallest non-zero
            eigenvalue of Eq. (30), or 0 where pressure modes exist.
        pressure_modes: :math:`k_{pm}` of Eq. (32).
        constraints: :math:`n`, the number of active multipliers.
        displacements: :math:`m`, the number of free displacement unknowns.
        h: The element size of Eqs. (26) and (31).
        beta_full: :math:`\beta_h` of Eq. (22) with the :math:`H^{-1/2}` dual norm of
            the multiplier, if computed.
        eigenvalues: The smallest non-zero eigenvalues of Eq. (30) found.
        solves: Back-substitutions with the saddle-point factorization (scalable path).
    """

    beta: float
    pressure_modes: int
    constraints: int
    displacements: int
    h: float
    beta_full: float | None = None
    eigenvalues: tuple[float, ...] = ()
    solves: int = 0

    @property
    def solvable(self) -> bool:
        r"""No pressure modes: :math:`\mathbf B` has full rank (Eq. 35)."""
        return self.pressure_modes == 0


def _dirichlet_free(problem: ContactProblem) -> npt.NDArray[np.bool_]:
    """Global mask of the displacement unknowns without a Dirichlet condition."""
    comm = problem.spaces[0].mesh.comm
    masks = []
    for i in range(len(problem.spaces)):
        x_bc, keep = problem._dirichlet_vectors(i)
        masks.append(np.concatenate(comm.allgather(keep.array_r.copy())) > 0.5)
        x_bc.destroy()
        keep.destroy()
    return np.concatenate(masks)


def _norm_matrices(problem: ContactProblem, norm: str) -> list[PETSc.Mat]:
    r""":math:`\mathbf S` of Eq. (28) per body, Dirichlet rows and columns unit."""
    if norm == "energy":
        return [K.copy() for K in problem._K]
    if norm != "H1":
        raise ValueError(f"norm must be 'H1' or 'energy', not {norm!r}")
    out = []
    for V, bcs in zip(problem.spaces, problem._body_bcs, strict=True):
        S = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(h1_norm_form(V)), bcs=bcs)
        S.assemble()
        out.append(S)
    return out


def inf_sup_dense(
    problem: ContactProblem,
    h: float,
    *,
    norm: str = "H1",
    full: bool = True,
    zero_tolerance: float = 1e-10,
) -> InfSup:
    r"""The inf-sup test exactly as Eqs. (26)-(32) state it, with dense matrices.

    :math:`\mathbf G = \mathbf B^T \mathbf P^{-1} \mathbf B / h` (Eq. 31) and
    :math:`\mathbf G \phi = \lambda \mathbf S \phi` (Eq. 30) on the :math:`m` free
    displacement unknowns; an eigenvalue counts as zero below ``zero_tolerance``
    times the largest. With :math:`k - 1` zero eigenvalues, :math:`k_{pm} = k - (m - n
    + 1)` (Eq. 32); :math:`\beta^*_h = \sqrt{\lambda_k}` if :math:`k_{pm} = 0`, else 0.

    With ``full``, also :math:`\beta_h` of Eq. (22): the smallest :math:`\lambda` of
    :math:`\mathbf B \mathbf S^{-1} \mathbf B^T \mathbf M = \lambda \mathbf T \mathbf M`
    with :math:`\mathbf T` from :func:`dual_norm_matrix` (the supremum over
    :math:`\mathbf V` of Eq. 22 is :math:`\sqrt{\mathbf M^T \mathbf B \mathbf S^{-1}
    \mathbf B^T \mathbf M}`).

    Args:
        problem: The contact problem (its spaces, Dirichlet conditions and pairs).
        h: Element size.
        norm: ``"H1"`` (Eq. 28) or ``"energy"`` (:math:`\mathbf S = \mathbf K`, Eq. 23).
        full: Whether to compute :math:`\beta_h` of Eq. (22) too.
        zero_tolerance: Relative size below which an eigenvalue is zero.

    Meant for small meshes: the cost is cubic in :math:`m`.
    """
    B = constraint_matrix(problem)
    free = _dirichlet_free(problem)
    S_blocks = _norm_matrices(problem, norm)
    S = scipy.linalg.block_diag(*[gather_dense(Si) for Si in S_blocks])
    for Si in S_blocks:
        Si.destroy()
    S = S[np.ix_(free, free)]
    B = B[:, free]
    P = _stack_pairs(problem, lambda pair: _gather_matrix(multiplier_mass(pair)))
    n, m = B.shape
    G = B.T @ np.linalg.solve(P, B) / h
    lam = scipy.linalg.eigh(G, S, eigvals_only=True)
    zeros = int(np.count_nonzero(lam <= zero_tolerance * lam[-1]))
    k = zeros + 1
    k_pm = k - (m - n + 1)
    beta = float(np.sqrt(lam[zeros])) if k_pm == 0 else 0.0
    beta_full = None
    if full:
        if k_pm == 0:
            T = _stack_pairs(problem, dual_norm_matrix)
            Sigma = B @ scipy.linalg.cho_solve(scipy.linalg.cho_factor(S), B.T)
            beta_full = float(np.sqrt(scipy.linalg.eigh(Sigma, T, eigvals_only=True)[0]))
        else:
            beta_full = 0.0
    return InfSup(beta, k_pm, n, m, h, beta_full, tuple(float(x) for x in lam[zeros : zeros + 4]))


def _gather_matrix(A: PETSc.Mat) -> npt.NDArray[np.floating]:
    D = gather_dense(A)
    A.destroy()
    return D


def _stack_pairs(problem: ContactProblem, matrix) -> npt.NDArray[np.floating]:
    """Block diagonal over the pairs of a per-pair dense matrix, active rows only."""
    blocks = []
    for pair in problem.pairs:
        D = matrix(pair)
        keep = np.setdiff1d(np.arange(D.shape[0]), pair.inactive)
        blocks.append(D[np.ix_(keep, keep)])
    return scipy.linalg.block_diag(*blocks)


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

    factorized once (symmetric indefinite :math:`LDL^T`, MUMPS). Since :math:`\mathbf
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
        problem: ContactProblem,
        h: float,
        *,
        norm: str = "H1",
        petsc_options_prefix: str = "infsup_",
        shift: float = 1e-10,
    ):
        r"""Assemble and factorize the saddle-point matrix.

        Args:
            problem: The contact problem (its spaces, Dirichlet conditions and pairs).
            h: Element size of Eqs. (26) and (31).
            norm: ``"H1"`` (Eq. 28) or ``"energy"`` (:math:`\mathbf S = \mathbf K`).
            petsc_options_prefix: Prefix of the options of the factorization
                (``{prefix}ksp_``, ``{prefix}pc_``, ``{prefix}mat_mumps_``) and of
                the eigensolver (``{prefix}eps_``, ``{prefix}st_``).
            shift: :math:`\tau`: eigenvalues :math:`\beta^{*2} \le \tau` count as
                pressure modes.
        """
        if not h > 0:
            raise ValueError(f"the element size h must be positive, not {h}")
        self.h = float(h)
        self.shift = float(shift)
        self.prefix = petsc_options_prefix
        comm = problem.spaces[0].mesh.comm
        self.comm = comm
        self._S = _norm_matrices(problem, norm)
        nb, npairs = len(problem.spaces), len(problem.pairs)
        blocks: list[list[PETSc.Mat | None]] = [[None] * (nb + npairs) for _ in range(nb + npairs)]
        for i, S in enumerate(self._S):
            blocks[i][i] = S
        self._owned = []
        scalings = []
        P_blocks: list[list[PETSc.Mat | None]] = [[None] * npairs for _ in range(npairs)]
        index = {id(V): i for i, V in enumerate(problem.spaces)}
        for j, (pair, constraint) in enumerate(
            zip(problem.pairs, problem.constraints, strict=True)
        ):
            start, end = pair.Q.dofmap.index_map.local_range
            active = np.setdiff1d(np.arange(start, end, dtype=np.int64), pair.inactive)
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
            for Bi, V in zip(constraint, (pair.contactor.V, pair.target.V), strict=True):
                c0, c1 = Bi.getOwnershipRangeColumn()
                cols = PETSc.IS().createStride(c1 - c0, first=c0, step=1, comm=comm)
                B = Bi.createSubMatrix(rows, cols)
                B.diagonalScale(d, None)
                Bt = PETSc.Mat()
                B.transpose(Bt)
                i = index[id(V)]
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

        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setOperators(self.A)
        self.ksp.setOptionsPrefix(petsc_options_prefix)
        self.ksp.setType("preonly")
        pc = self.ksp.getPC()
        pc.setType("cholesky")
        pc.setFactorSolverType("mumps")
        self.ksp.setFromOptions()
        pc.setFactorSetUpSolverType()
        F = pc.getFactorMatrix()
        F.setMumpsIcntl(13, 1)  # inertia of the root front too (no ScaLAPACK there)
        self.ksp.setUp()
        if F.getMumpsInfog(1) < 0:
            raise RuntimeError(f"MUMPS failed to factorize (INFOG(1) = {F.getMumpsInfog(1)})")
        negative = int(F.getMumpsInfog(12))
        #: :math:`k_{pm}`: the eigenvalues :math:`\lambda \le \tau`, from the inertia.
        self.pressure_modes = self.constraints - negative

    @staticmethod
    def _dirichlet_count(problem: ContactProblem) -> int:
        return int(np.count_nonzero(~_dirichlet_free(problem)))

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
        from slepc4py import SLEPc

        if self.pressure_modes > 0:
            return InfSup(0.0, self.pressure_modes, self.constraints, self.displacements, self.h)
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
        eps.setOptionsPrefix(self.prefix)
        eps.setFromOptions()
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
        return InfSup(
            float(np.sqrt(lam[0])),
            0,
            self.constraints,
            self.displacements,
            self.h,
            eigenvalues=lam,
            solves=context.solves,
        )

    def inverse_schur(self, block: int = 64) -> npt.NDArray[np.floating]:
        r"""Dense :math:`(\Sigma - \tau \mathbf P)^{-1}`, scaled, on every process.

        One back-substitution per multiplier, ``block`` right-hand sides at a time
        (``MatMatSolve``): meant for a moderate number :math:`n` of multipliers.
        """
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
            solves=self.constraints,
        )

    def _dense_order(self, problem: ContactProblem) -> npt.NDArray[np.int64]:
        """Position in the scaled multiplier vector of each row of :func:`_stack_pairs`."""
        order = []
        for pair, is_m in zip(problem.pairs, self._is_mult, strict=True):
            start, end = pair.Q.dofmap.index_map.local_range
            active = np.setdiff1d(np.arange(start, end, dtype=np.int64), pair.inactive)
            parts = self.comm.allgather((active, is_m.getIndices().astype(np.int64)))
            dofs = np.concatenate([a for a, _ in parts])
            positions = np.concatenate([b for _, b in parts])
            order.append(positions[np.argsort(dofs)])
        return np.concatenate(order)

    def beta_full(self, problem: ContactProblem) -> float:
        r""":math:`\beta_h` of Eq. (22), from :meth:`inverse_schur` and :func:`dual_norm_matrix`.

        :math:`\beta_h^2` is the smallest eigenvalue of :math:`\Sigma \mathbf M =
        \lambda \mathbf T \mathbf M`; 0 where pressure modes exist.
        """
        if self.pressure_modes > 0:
            return 0.0
        order = self._dense_order(problem)
        D = self.comm.allreduce(self._scaling_local())
        T = _stack_pairs(problem, dual_norm_matrix)
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
        """Destroy the PETSc objects."""
        for obj in [
            self.ksp,
            self.A,
            self.P,
            self._nest,
            self._P_nest,
            self._rhs,
            self._sol,
            self._z,
            self._scaling,
            *self._S,
            *self._owned,
        ]:
            obj.destroy()


def inf_sup(problem: ContactProblem, h: float, **options) -> InfSup:
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

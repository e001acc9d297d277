# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""An iterative saddle-point solver for large scenes: a Schur-complement field split.

The tied system of Eq. (18) with the signs of Eq. (15),

.. math::
    \begin{bmatrix} \mathbf K & -\mathbf B^T \\ -\mathbf B & \mathbf D \end{bmatrix}
    \begin{Bmatrix} \mathbf U \\ \mathbf \Lambda \end{Bmatrix} =
    \begin{Bmatrix} \mathbf F \\ \mathbf G \end{Bmatrix},

(:math:`\mathbf D` is zero but for the unit rows of inactive multipliers) is solved by
GMRES, right-preconditioned with PETSc's ``PCFieldSplit`` of type ``schur``: two splits,
``u`` (every displacement field) and ``lambda`` (every multiplier field), and

- on ``u``: GAMG on each displacement space's :math:`\mathbf K_i`, which carries the
  rigid-body modes of each of its bodies as near-null space (a nested additive field
  split over the spaces when there are several, since GAMG needs one AIJ matrix);
- on ``lambda``: an approximation :math:`\hat{\mathbf S}` of the Schur complement
  :math:`\mathbf S = \mathbf D - \mathbf B \mathbf K^{-1} \mathbf B^T`.

Why :math:`\hat{\mathbf S}` is not the multiplier mass matrix. :math:`\mathbf B
\mathbf K^{-1} \mathbf B^T` maps a contact traction to the gap it opens: the
compliance of the bodies on the contact line. A traction of wavelength :math:`\ell`
opens a gap of order :math:`\ell / E^*` (an elastic half-plane, plane strain: :math:`2
(1 - \nu^2)/(E k)` per unit traction at wavenumber :math:`k = 2\pi/\ell`), so in terms
of the multiplier mass matrix :math:`\mathbf P` of Eq. (29), :math:`\mathbf S \approx
(h/E)\, \mathbf P` for the finest modes (:math:`\ell \sim h`) but :math:`(H/E)\,
\mathbf P` for the smoothest (:math:`\ell \sim H`, the size of the bodies): the mass
matrix is spectrally equivalent to :math:`\mathbf S` only up to :math:`H/h`, and the
iterations grow like :math:`\sqrt{H/h}` under refinement. Measured on the inf-sup model
of Fig. 2 (two clamped blocks, 14, 28, 56, 112 elements on the contactor, 1 rank): 34,
49, 59, 68 GMRES iterations with the mass matrix, 24, 28, 31, 32 with the fractional
:math:`\hat{\mathbf S}` below; on the two-block scene of ``make bench`` (P6, default
``rtol``) 63 iterations at 10,000 unknowns, 70 at 1 million and 72 at 8 million.
:math:`\mathbf S` is an operator of order :math:`-1`, the discrete
:math:`H^{-1/2}(\Gamma_C)` inner product: with :math:`\mathbf A` the Laplacian of the
multiplier space on the contact line and :math:`\mathbf A \boldsymbol\phi_k = \mu_k
\mathbf P \boldsymbol\phi_k`, :math:`\boldsymbol\Phi^T \mathbf P \boldsymbol\Phi =
\mathbf I`,

.. math:: \hat{\mathbf S}^{-1} = -c\, \boldsymbol\Phi\,
    (\boldsymbol\Lambda + \kappa^2)^{1/2} \boldsymbol\Phi^T,
    \qquad \kappa = \pi / |\Gamma_C|,

is spectrally equivalent to :math:`\mathbf S^{-1}` uniformly in :math:`h`
(``"fractional"``, the default), so the iterations stay nearly constant. :math:`c`
is the stiffness of the bodies: the half-plane's compliance :math:`2/E^*` summed over
the spaces a pair couples, with :math:`E^* \approx \operatorname{median}
\operatorname{diag} \mathbf K_i / 2` (P1/Q1), so :math:`c^{-1} = \sum_i
4/\operatorname{median} \operatorname{diag} \mathbf K_i`. A constant factor, to
which the Krylov method is not very sensitive (measured, 113 multipliers, with
:math:`\gamma/\operatorname{median}` in place of 4: :math:`\gamma` = 0.1, 0.3, 1, 3,
4, 10 take 56, 48, 37, 32, 32, 33 iterations). The contact line of a 2D scene has
:math:`O(\sqrt N)` multipliers, so :math:`\hat{\mathbf S}^{-1}` is formed densely on
every process (a generalized symmetric eigenproblem of that size, gathered): about
1,600 multipliers at 8 million unknowns. Its set-up costs :math:`O(m^3)` in the number
:math:`m` of multipliers: at 1,625, the generalized eigensolve and the product took 72
and 23 s on this machine's reference BLAS under load; on OpenBLAS the whole system
stage took 7 s at 8 million unknowns (a tridiagonal eigensolver on the lumped mass,
1.5 s there, and applying :math:`\boldsymbol\Phi` without forming the product would
remove most of it). The multiplier block is then preconditioned by
multiplying with it (``-fieldsplit_lambda_pc_type mat``). ``"mass"``, :math:`\hat{\mathbf
S} = -(\bar h / c)\, \mathbf P` (:math:`\bar h` the mean facet size, Jacobi on it), is
the sparse alternative for contact lines too long for a dense matrix. Inactive
multipliers keep their row :math:`\lambda_k = 0`: :math:`\hat S_{kk} = 1`.

Use::

    from dolfinx_contact_s2s.fieldsplit import iterative_options, use_schur_complement

    problem = LinearContactProblem(
        a, L, pairs, bcs, kind="nest", petsc_options_prefix="contact_",
        petsc_options=iterative_options(spaces=len(a)),
    )
    use_schur_complement(problem)
    problem.solve()  # checks the residual as every solve does

The options (all under the problem's prefix; every one can be changed from the command
line, ``-contact_ksp_rtol 1e-12``):

========================================== ============================================
``ksp_type gmres``, ``ksp_pc_side right``  outer Krylov method, right preconditioned:
                                           the true residual is what converges. The
                                           preconditioner is linear (``preonly``
                                           inner solves); with an inner Krylov solve
                                           use ``fgmres`` (same iterations here, but
                                           twice the Krylov vectors: 1.59 GB peak
                                           against 1.26 at 1 million unknowns)
``ksp_rtol 1e-11``, ``ksp_atol 0``         below the problem's residual check (1e-8)
``ksp_gmres_restart 100``                  no restart below 100 iterations
``pc_type fieldsplit``                     the two splits ``u`` and ``lambda``
``pc_fieldsplit_type schur``               Schur-complement factorization ...
``pc_fieldsplit_schur_fact_type lower``    ... block lower triangular (``upper`` and
                                           ``full`` take about as many iterations,
                                           ``diag`` 1.6 times as many)
``pc_fieldsplit_schur_precondition user``  :math:`\hat{\mathbf S}` above
``fieldsplit_u_ksp_type preonly``          one V-cycle per application
``fieldsplit_u_pc_type gamg``              one space (several: ``fieldsplit`` of type
                                           ``additive``, ``fieldsplit_u_fieldsplit_
                                           pc_type gamg``)
``fieldsplit_u_pc_gamg_threshold 0.01``    drop weak couplings when aggregating
``fieldsplit_lambda_ksp_type preonly``     one application of :math:`\hat{\mathbf
                                           S}^{-1}`
``fieldsplit_lambda_pc_type mat``          multiply by :math:`\hat{\mathbf S}^{-1}`
                                           (``jacobi`` with ``"mass"``)
``s2s_schur_pre fractional``               which :math:`\hat{\mathbf S}`: ``fractional``
                                           or ``mass``
========================================== ============================================

GAMG needs every :math:`\mathbf K_i` invertible on its own: each body must be held by
Dirichlet conditions (a body held by contact alone makes :math:`\mathbf K_i` singular
and the Schur complement undefined; use the direct solver there).

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import typing

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import numpy.typing as npt
import scipy.linalg
import ufl

from dolfinx_contact_s2s.assemble import multiplier_mass
from dolfinx_contact_s2s.la import gather_dense

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.problem import ContactProblemBase, LinearContactProblem
    from dolfinx_contact_s2s.system import ContactSystem

__all__ = [
    "SCHUR_PRECONDITIONERS",
    "SchurComplementSetup",
    "iterative_options",
    "schur_approximation",
    "use_schur_complement",
]

#: Approximations of the Schur complement (see the module docstring).
SCHUR_PRECONDITIONERS = ("fractional", "mass")


def iterative_options(
    spaces: int = 1,
    *,
    schur: str = "fractional",
    fact_type: str = "lower",
    rtol: float = 1e-11,
    max_it: int = 1000,
) -> dict[str, typing.Any]:
    r"""PETSc options of the Schur-complement field split (Eq. 18), for ``petsc_options``.

    Args:
        spaces: Number of displacement spaces of the problem (forms ``a``).
        schur: Approximation of the Schur complement, one of
            :data:`SCHUR_PRECONDITIONERS`.
        fact_type: ``-pc_fieldsplit_schur_fact_type``: ``lower``, ``upper``, ``full``
            or ``diag``.
        rtol: Relative tolerance of the outer GMRES on the true residual (right
            preconditioning); keep it below the problem's ``residual_tolerance``.
        max_it: Largest number of outer iterations.

    Returns:
        The options, to be set under the problem's prefix.

    Raises:
        ValueError: For an unknown ``schur`` or fewer than one space.
    """
    if schur not in SCHUR_PRECONDITIONERS:
        raise ValueError(f"schur must be one of {SCHUR_PRECONDITIONERS}, not {schur!r}")
    if spaces < 1:
        raise ValueError("a problem has at least one displacement space")
    options: dict[str, typing.Any] = {
        "ksp_type": "gmres",
        "ksp_pc_side": "right",
        "ksp_rtol": rtol,
        "ksp_atol": 0.0,
        "ksp_max_it": max_it,
        "ksp_gmres_restart": 100,
        "pc_type": "fieldsplit",
        "pc_fieldsplit_type": "schur",
        "pc_fieldsplit_schur_fact_type": fact_type,
        "pc_fieldsplit_schur_precondition": "user",
        "fieldsplit_u_ksp_type": "preonly",
        "fieldsplit_lambda_ksp_type": "preonly",
        "fieldsplit_lambda_pc_type": "mat" if schur == "fractional" else "jacobi",
        "s2s_schur_pre": schur,
    }
    gamg = {"pc_type": "gamg", "pc_gamg_threshold": 0.01}
    if spaces == 1:
        options.update({f"fieldsplit_u_{k}": v for k, v in gamg.items()})
    else:
        options.update(
            {
                "fieldsplit_u_pc_type": "fieldsplit",
                "fieldsplit_u_pc_fieldsplit_type": "additive",
                "fieldsplit_u_fieldsplit_ksp_type": "preonly",
            }
        )
        options.update({f"fieldsplit_u_fieldsplit_{k}": v for k, v in gamg.items()})
    return options


def _split_numbering(problem: LinearContactProblem | ContactSystem) -> list[npt.NDArray[np.int64]]:
    """Per pair, the index in the ``lambda`` split of each global multiplier dof."""
    comm = problem.comm
    maps = [pair.Q.dofmap.index_map for pair in problem.pairs]
    local = np.array([m.size_local for m in maps], dtype=np.int64)
    starts = np.array([m.local_range[0] for m in maps], dtype=np.int64)
    # Rows: ranks; columns: pairs.
    all_local = np.array(comm.allgather(local)).reshape(comm.size, -1)
    all_starts = np.array(comm.allgather(starts)).reshape(comm.size, -1)
    rank_offset = np.concatenate([[0], np.cumsum(all_local.sum(axis=1))])
    out = []
    for j, m in enumerate(maps):
        numbering = np.empty(m.size_global, dtype=np.int64)
        for r in range(comm.size):
            before = rank_offset[r] + all_local[r, :j].sum()
            numbering[all_starts[r, j] : all_starts[r, j] + all_local[r, j]] = before + np.arange(
                all_local[r, j]
            )
        out.append(numbering)
    return out


def _inactive(problem: LinearContactProblem | ContactSystem, j: int) -> npt.NDArray[np.bool_]:
    r"""Multipliers of pair ``j`` whose row reads :math:`\lambda_k = 0` (on every process)."""
    assert problem.A is not None
    nb = len(problem.spaces)
    n = problem.pairs[j].Q.dofmap.index_map.size_global
    D = problem.A.getNestSubMatrix(nb + j, nb + j) if problem.A.getType() == "nest" else None
    if D is None or not D.handle:
        return np.zeros(n, dtype=bool)
    d = D.getDiagonal()
    start, _ = d.getOwnershipRange()
    mine = start + np.flatnonzero(d.array_r != 0.0)
    d.destroy()
    out = np.zeros(n, dtype=bool)
    out[np.concatenate(problem.comm.allgather(mine)).astype(np.int64)] = True
    return out


def _stiffness_scale(problem: LinearContactProblem | ContactSystem, j: int) -> float:
    r"""Compliance :math:`1/c` of the contact line of pair ``j`` (see the module docstring).

    A half-plane opens a gap :math:`2/(E^* k)` under a unit traction of wavenumber
    :math:`k`, and the diagonal of a P1/Q1 plane stiffness is about :math:`2 E^*`:
    :math:`1/c = \sum_i 4/\operatorname{median} \operatorname{diag} \mathbf K_i` over
    the spaces the pair couples.
    """
    total = 0.0
    for V, _ in problem.operators[j].blocks:
        K = problem.stiffness[problem.space_index(V)]
        d = K.getDiagonal()
        values = np.concatenate(problem.comm.allgather(np.abs(d.array_r)))
        d.destroy()
        total += 4.0 / float(np.median(values))
    return total


def _laplacian(pair: typing.Any) -> PETSc.Mat:
    """Laplacian of the multiplier space on the contact line (interior jumps if discontinuous)."""
    Q = pair.Q
    p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
    form = ufl.inner(ufl.grad(p), ufl.grad(q)) * ufl.dx
    element = Q.ufl_element()
    if getattr(element, "discontinuous", False) or "Discontinuous" in str(element):
        h = ufl.CellDiameter(Q.mesh)
        form += ufl.avg(1 / h) * ufl.jump(p) * ufl.jump(q) * ufl.dS
    A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(form))
    A.assemble()
    return A


def _line_length(pair: typing.Any) -> float:
    mesh = pair.Q.mesh
    one = dolfinx.fem.form(dolfinx.fem.Constant(mesh, 1.0) * ufl.dx(domain=mesh))
    return mesh.comm.allreduce(dolfinx.fem.assemble_scalar(one), op=MPI.SUM)


def _pair_block(
    problem: LinearContactProblem | ContactSystem, j: int
) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.bool_]]:
    r"""Dense block :math:`\hat S^{-1}` (``"fractional"``) of pair ``j``, in global dofs."""
    pair = problem.pairs[j]
    inactive = _inactive(problem, j)
    active = ~inactive
    c = 1.0 / _stiffness_scale(problem, j)
    P = multiplier_mass(pair)
    Pd = gather_dense(P)
    P.destroy()
    n = Pd.shape[0]
    block = np.zeros((n, n))
    A = _laplacian(pair)
    Ad = gather_dense(A)
    A.destroy()
    if pair.nodal and pair.weight == "unit":
        # The multiplier is the nodal force: in its coefficients the traction
        # basis is scaled by 1/w, and P = diag(1/w).
        Ad = Pd @ Ad @ Pd
    Aa, Pa = Ad[np.ix_(active, active)], Pd[np.ix_(active, active)]
    mu, Phi = scipy.linalg.eigh(0.5 * (Aa + Aa.T), 0.5 * (Pa + Pa.T))
    kappa = np.pi / _line_length(pair)
    root = np.sqrt(np.maximum(mu, 0.0) + kappa**2)
    block[np.ix_(active, active)] = -c * (Phi * root) @ Phi.T
    block[inactive, inactive] = 1.0
    return block, inactive


def _insert_mass(
    problem: LinearContactProblem | ContactSystem,
    j: int,
    S: PETSc.Mat,
    split: npt.NDArray[np.int64],
) -> None:
    r"""Insert this process's rows of :math:`\hat S = -(\bar h / c) \mathbf P` of pair ``j``.

    Sparse (``"mass"``): the multiplier mass is never gathered, so that a 3D contact
    surface of many thousand multipliers costs its nonzeros only. Inactive multipliers
    get the unit row :math:`\hat S_{kk} = 1`.
    """
    pair = problem.pairs[j]
    inactive = _inactive(problem, j)
    c = 1.0 / _stiffness_scale(problem, j)
    cells = pair.Q.mesh.topology.index_map(pair.Q.mesh.topology.dim).size_global
    hbar = _line_length(pair) / cells
    P = multiplier_mass(pair)
    indptr, cols, values = P.getValuesCSR()
    first, _ = P.getOwnershipRange()
    P.destroy()
    for i in range(indptr.size - 1):
        row = first + i
        if inactive[row]:
            S.setValue(split[row], split[row], 1.0, addv=PETSc.InsertMode.INSERT_VALUES)
            continue
        k = cols[indptr[i] : indptr[i + 1]]
        keep = ~inactive[k]
        S.setValues(
            [split[row]],
            split[k[keep]].astype(PETSc.IntType),
            -(hbar / c) * values[indptr[i] : indptr[i + 1]][keep],
            addv=PETSc.InsertMode.INSERT_VALUES,
        )


def schur_approximation(
    problem: LinearContactProblem | ContactSystem, schur: str = "fractional"
) -> PETSc.Mat:
    r"""The multiplier-block preconditioner of an assembled problem, in the ``lambda`` split.

    Args:
        problem: An assembled :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`,
            or its :class:`~dolfinx_contact_s2s.system.ContactSystem`.
        schur: ``"fractional"``: :math:`\hat{\mathbf S}^{-1}` (apply by multiplication,
            ``-fieldsplit_lambda_pc_type mat``); ``"mass"``: :math:`\hat{\mathbf S}`
            (a matrix to precondition, e.g. with Jacobi).

    Returns:
        A distributed matrix in the layout of the concatenated multiplier fields (dense
        for ``"fractional"``, AIJ for ``"mass"``). The caller must ``destroy()`` it.

    Raises:
        ValueError: For an unknown ``schur``.
    """
    if schur not in SCHUR_PRECONDITIONERS:
        raise ValueError(f"schur must be one of {SCHUR_PRECONDITIONERS}, not {schur!r}")
    comm = problem.comm
    numbering = _split_numbering(problem)
    local = sum(pair.Q.dofmap.index_map.size_local for pair in problem.pairs)
    total = sum(pair.Q.dofmap.index_map.size_global for pair in problem.pairs)
    start = comm.scan(local) - local
    sizes = ((local, total), (local, total))
    if schur == "fractional":
        S = PETSc.Mat().createDense(sizes, comm=comm)
    else:
        S = PETSc.Mat().createAIJ(sizes, comm=comm)
        S.setPreallocationNNZ(
            max(pair.Q.dofmap.cell_dofs(0).size for pair in problem.pairs) * 3 if local else 1
        )
        S.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
    S.setUp()
    for j in range(len(problem.pairs)):
        if schur == "mass":
            _insert_mass(problem, j, S, numbering[j])
            continue
        block, _ = _pair_block(problem, j)
        split = numbering[j]
        mine = np.flatnonzero((split >= start) & (split < start + local))
        if mine.size == 0:
            continue
        cols = np.flatnonzero(np.any(block[mine] != 0.0, axis=0))
        S.setValues(
            split[mine].astype(PETSc.IntType),
            split[cols].astype(PETSc.IntType),
            np.ascontiguousarray(block[np.ix_(mine, cols)]),
            addv=PETSc.InsertMode.INSERT_VALUES,
        )
    S.assemble()
    return S


def _concatenate(comm: MPI.Comm, sets: list[PETSc.IS]) -> PETSc.IS:
    if len(sets) == 1:
        return sets[0]
    indices = np.concatenate([s.getIndices() for s in sets]).astype(PETSc.IntType)
    return PETSc.IS().createGeneral(indices, comm=comm)


class SchurComplementSetup:
    r"""Installs the two-split Schur preconditioner on a problem's solver.

    Installed by :func:`use_schur_complement` (``problem.set_solver_setup``). Called after the
    problem configured its solver for a new system: when the options select
    ``-pc_fieldsplit_type schur``, it replaces the problem's named fields by the two
    splits ``u`` (every ``u*`` field) and ``lambda`` (every ``lambda*`` field) and
    gives the Schur complement the matrix of :func:`schur_approximation`, as chosen by
    the option ``s2s_schur_pre``. Other options leave the solver as it is.
    """

    def __init__(self) -> None:
        """No PETSc objects until the first system."""
        self._owned: list[typing.Any] = []

    def destroy(self) -> None:
        """Destroy the matrices and index sets of the last system."""
        for obj in self._owned:
            obj.destroy()
        self._owned = []

    def __call__(self, problem: ContactSystem) -> None:
        """Configure the solver of the system ``problem`` holds (collective)."""
        pc = problem.solver.getPC()
        if (
            pc.getType() != "fieldsplit"
            or problem.options.get("pc_fieldsplit_type") != "schur"
            or problem.A is None
            or problem.A.getType() != "nest"
        ):
            return
        schur = problem.options.get("s2s_schur_pre", "fractional")
        if schur not in SCHUR_PRECONDITIONERS:
            raise ValueError(
                f"-{problem.options.prefix}s2s_schur_pre must be one of "
                f"{SCHUR_PRECONDITIONERS}, not {schur!r}"
            )
        self.destroy()
        # The problem attached one split per field; PCFieldSplit only adds splits, so
        # a new implementation drops them.
        pc.setType(PETSc.PC.Type.NONE)
        pc.setType(PETSc.PC.Type.FIELDSPLIT)
        pc.setFromOptions()
        fields = problem.fields
        u = _concatenate(problem.comm, [s for k, s in fields.items() if k.startswith("u")])
        lam = _concatenate(problem.comm, [s for k, s in fields.items() if k.startswith("lambda")])
        pc.setFieldSplitIS(("u", u), ("lambda", lam))
        S = schur_approximation(problem, schur)
        pc.setFieldSplitSchurPreType(PETSc.PC.FieldSplitSchurPreType.USER, S)
        self._owned = [S] + [s for s in (u, lam) if all(s is not f for f in fields.values())]


def use_schur_complement(problem: ContactProblemBase) -> SchurComplementSetup:
    """Solve ``problem`` with the Schur-complement field split of its options.

    The problem must have been created with ``kind="nest"``; this installs the setup
    (``problem.set_solver_setup``) and changes nothing else. Call before
    :meth:`~dolfinx_contact_s2s.problem.LinearContactProblem.solve` (or ``assemble``),
    with the options of :func:`iterative_options`. The setup's matrices are destroyed
    with the next system or by its :meth:`SchurComplementSetup.destroy`.

    Returns:
        The installed setup.

    Raises:
        ValueError: If the problem was not created with ``kind="nest"``.
    """
    if problem.kind != "nest":
        raise ValueError(
            "use_schur_complement needs a problem created with kind='nest', not "
            f"kind={problem.kind!r}"
        )
    setup = SchurComplementSetup()
    problem.set_solver_setup(setup)
    return setup

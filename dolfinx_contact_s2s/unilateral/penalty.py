# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The ``"penalty"`` and ``"augmented-lagrangian"`` algorithms.

``"penalty"``: :math:`\lambda_j = c_j \max(0, -\tilde g_j)` from the penetration, no
multiplier unknowns in the solve; the error falls like :math:`1/\varepsilon`.
``"augmented-lagrangian"``: Uzawa updates :math:`\lambda_j \leftarrow \max(0, \lambda_j
- c_j \tilde g_j)` around penalty solves, until :math:`\lambda` stops changing: the
Lagrange solution for any :math:`\varepsilon`.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import typing

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.options import solver_failure
from dolfinx_contact_s2s.unilateral.history import LoadStep
from dolfinx_contact_s2s.unilateral.iteration import ContactIteration
from dolfinx_contact_s2s.unilateral.uzawa import UzawaMonitor

__all__ = ["solve_step"]


def _relative_change(
    comm: MPI.Comm, new: npt.NDArray[np.floating], old: npt.NDArray[np.floating]
) -> float:
    r""":math:`\max|new - old| / \max|new|` over all processes (0 if both vanish)."""
    change = comm.allreduce(float(np.max(np.abs(new - old), initial=0.0)), op=MPI.MAX)
    size = comm.allreduce(float(np.max(np.abs(new), initial=0.0)), op=MPI.MAX)
    return change / size if size > 0 else change


def _check_linear(
    ksp: PETSc.KSP,
    P: PETSc.Mat,
    rhs: PETSc.Vec,
    U: PETSc.Vec,
    residual_tolerance: float,
    prefix: str,
) -> None:
    """Raise unless the KSP converged with a small relative residual."""
    if ksp.getConvergedReason() < 0:
        raise RuntimeError("the penalty solve failed: " + solver_failure(ksp, prefix))
    r = rhs.duplicate()
    P.mult(U, r)
    r.aypx(-1.0, rhs)
    rel = r.norm() / max(rhs.norm(), np.finfo(float).tiny)
    r.destroy()
    if not rel <= residual_tolerance:
        raise RuntimeError(
            f"the penalty solve cannot be trusted: relative residual {rel:.2e} > "
            f"{residual_tolerance:.0e}"
        )


def solve_step(
    run: ContactIteration,
    step: LoadStep,
    active: list[npt.NDArray[np.bool_]],
    augmented: bool = False,
) -> list[npt.NDArray[np.bool_]]:
    r"""Penalty solves, within Uzawa updates for the augmented Lagrangian.

    With :math:`\mathbf C` the masked coupling (so that :math:`\tilde g = \mathbf C
    \mathbf U + \hat{\mathbf G}`), :math:`\lambda^k` the current multiplier (zero
    for the penalty method) and :math:`\mathcal A = \{j: \lambda^k_j - c_j \tilde g_j
    > 0\}`, each solve is the Newton step of the penalized energy

    .. math:: (\mathbf K + \mathbf C^T \mathbf W_{\mathcal A} \mathbf C) \mathbf U =
        \mathbf F + \mathbf C^T (\lambda^k_{\mathcal A} - \mathbf W_{\mathcal A}
        \hat{\mathbf G}), \qquad \mathbf W = \mathrm{diag}(c),

    repeated until :math:`\mathcal A` repeats; then :math:`\lambda \leftarrow
    \max(0, \lambda^k - c \tilde g)`.

    Args:
        run: The solve's shared state.
        step: The load step; its iterations are appended.
        active: Per pair, the first active set (owned multipliers).
        augmented: Uzawa updates (the augmented Lagrangian), else one penalty solve.

    Returns:
        The last active set.

    Raises:
        ContactConvergenceError: If the iteration does not converge.
        RuntimeError: If a penalty solve fails or cannot be trusted.
    """
    system, comp = run.system, run.complementarity
    comm = system.comm
    system.build(None, load=step.load)
    assert system.A is not None and system.b is not None
    nb = len(system.spaces)
    names = list(system.fields)
    A = system.A if system.kind == "aij" else system.A.convert(PETSc.Mat.Type.AIJ, out=PETSc.Mat())
    rows = [
        PETSc.IS().createGeneral(
            np.concatenate([system.fields[n].getIndices() for n in part]).astype(np.int32),
            comm=comm,
        )
        for part in (names[:nb], names[nb:])
    ]
    K = A.createSubMatrix(rows[0], rows[0])
    minus_C = A.createSubMatrix(rows[1], rows[0])
    F = system.b.getSubVector(rows[0]).copy()
    G = system.b.getSubVector(rows[1]).copy()
    c = G.duplicate()
    c.array[:] = np.concatenate([s.array_r for s in comp.scales])
    lam = G.duplicate()
    lam.set(0.0)
    if augmented:
        lam.array[:] = np.concatenate(comp.lambdas())
    sizes = [s.getLocalSize() for s in comp.scales]
    pinned = np.concatenate([comp.pinned(j) for j in range(len(system.pairs))])
    U, rhs, g, w, work = (
        K.createVecRight(),
        F.duplicate(),
        G.duplicate(),
        G.duplicate(),
        F.duplicate(),
    )
    ksp = PETSc.KSP().create(comm)
    owned: list[typing.Any] = [K, minus_C, F, G, c, lam, U, rhs, g, w, work, ksp, *rows]
    if A is not system.A:
        owned.append(A)
    flat = np.concatenate(active)
    split = np.cumsum(sizes)[:-1]
    last = lam.array_r.copy()
    uzawa = UzawaMonitor(run.tolerance)
    try:
        for outer in range(1, run.max_iterations + 1 if augmented else 2):
            for _ in range(run.max_iterations):
                # No penalty stiffness off the active set: a body held by contact
                # alone floats there (Eq. 33 on the active rows).
                run.check_active_support(step, comp.released(np.split(flat, split)))
                # W = diag(c) on the active set; P = K + (-C)^T W (-C).
                w.array[:] = np.where(flat, c.array_r, 0.0)
                WC = minus_C.copy()
                WC.diagonalScale(w)
                P = minus_C.transposeMatMult(WC)
                P.axpy(1.0, K, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
                # rhs = F - (-C)^T (lambda_A) + (-C)^T (W G).
                w.array[:] = np.where(flat, lam.array_r, 0.0) - w.array_r * G.array_r
                minus_C.multTranspose(w, work)
                F.copy(rhs)
                rhs.axpy(-1.0, work)

                def configure(P: PETSc.Mat = P) -> None:
                    ksp.setOperators(P)
                    system.options.apply(ksp)

                configure()
                with system.timed("solve"):
                    system.solve_retrying(ksp, configure, rhs, U)
                    _check_linear(ksp, P, rhs, U, system.residual_tolerance, system.options.prefix)
                WC.destroy()
                P.destroy()
                minus_C.mult(U, g)
                g.aypx(-1.0, G)
                z = lam.array_r - c.array_r * g.array_r
                z[pinned] = -np.inf
                lam_new = np.where(np.isfinite(z), np.maximum(z, 0.0), 0.0)
                residual = _relative_change(comm, lam_new, last)
                last = lam_new
                nxt, entered, left = comp.update(np.split(flat, split), np.split(z, split))
                run.record(step, np.split(flat, split), entered, left, residual, outer)
                if entered == 0 and left == 0:
                    break
                flat = np.concatenate(nxt)
            else:
                run.fail(
                    f"the penalty iteration did not converge in {run.max_iterations} "
                    f"solves at load {step.load:g}"
                )
            change = _relative_change(comm, lam_new, lam.array_r)
            lam.array[:] = lam_new
            # The monitor records the update's rate, raises c if it is poor, decides the stop.
            if not augmented or uzawa.update(step, change, c):
                step.converged = True
                break
        else:
            run.fail(
                f"the augmented Lagrangian did not converge in {run.max_iterations} "
                f"updates at load {step.load:g}"
            )
        offset = 0
        for u in system.u:
            n = u.x.petsc_vec.getLocalSize()
            u.x.array[:n] = U.array_r[offset : offset + n]
            u.x.scatter_forward()
            offset += n
        parts = np.split(lam.array_r, np.cumsum(sizes)[:-1])
        for f, part in zip(system.multipliers, parts, strict=True):
            f.x.array[: part.size] = part
            f.x.scatter_forward()
        return np.split(flat, np.cumsum(sizes)[:-1])
    finally:
        for obj in owned:
            obj.destroy()

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Regularized (penalty) friction against the Lagrange solution on Cattaneo-Mindlin in 2D.

The scene and load path of :func:`paper.friction.cattaneo_mindlin` (two identical half
cylinders, the upper face moved down by :math:`\delta` in four frictionless steps, then
sideways in four steps with :math:`\mu = 0.2`), solved on one mesh by
:class:`~dolfinx_contact_s2s.friction.FrictionalContactProblem` and by
:class:`~dolfinx_contact_s2s.friction.RegularizedFrictionProblem` for several penalty
factors (:func:`study`): the stick half-width :math:`c`, the shear :math:`q(x) =
\lambda_t` and the pressure :math:`p(x) = \lambda_n` of each against the Lagrange ones
(and against Cattaneo and Mindlin's closed form), and the time of each solve.
"""

from __future__ import annotations

import math
import time
import typing

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s.friction import FrictionalContactProblem, RegularizedFrictionProblem
from paper.friction import (
    CM_A,
    CM_DELTA,
    CM_MU,
    CM_R,
    CM_SHIFT,
    NU,
    E,
    cattaneo_mindlin_scene,
    cattaneo_mindlin_shear,
)

__all__ = ["relative_l2", "solve_path", "study"]


def relative_l2(x: np.ndarray, values: np.ndarray, reference: typing.Callable, a: float) -> float:
    r"""Relative L2 distance over :math:`[-a, a]` of nodal ``values`` (linear) to ``reference``."""
    order = np.argsort(x)
    fine = np.linspace(-a, a, 20001)
    ref = reference(fine)
    error = np.interp(fine, x[order], values[order]) - ref
    return math.sqrt(np.trapezoid(error**2, fine) / np.trapezoid(ref**2, fine))


def solve_path(problem: typing.Any, motion: dolfinx.fem.Function) -> list[int]:
    """The load path of Cattaneo-Mindlin; the iterations of every step."""
    motion.interpolate(lambda x: np.stack([0.0 * x[0], -CM_DELTA + 0.0 * x[0]]))
    problem.solve([0.25, 0.5, 0.75, 1.0], mu=0.0)
    counts = [len(s.iterations) for s in problem.history.steps]
    for k in range(1, 5):
        shift = k * CM_SHIFT / 4
        motion.interpolate(lambda x, s=shift: np.stack([0 * x[0] + s, -CM_DELTA + 0 * x[0]]))
        problem.solve([1.0], restart=False)
        counts += [len(s.iterations) for s in problem.history.steps]
    return counts


def study(
    comm: MPI.Comm, degree: int = 2, across: int = 20, penalties: typing.Sequence[float] = ()
) -> list[dict[str, typing.Any]]:
    r"""Cattaneo-Mindlin by the Lagrange solver, then by the regularized one per penalty factor.

    Returns:
        One record per solver (``"lagrange"`` first, then ``"penalty"`` per factor
        :math:`\kappa`): ``c`` (the largest :math:`|x|` of a sticking node), ``seconds``
        (the load path's solves, largest over ranks), ``iterations`` per step (linear
        solves; the regularized solver's count its first residual too), ``unknowns``,
        the nodes' ``x``, ``q``, ``p`` (gathered, every rank); with the
        Lagrange solution's: ``c_error_elements`` (:math:`|c - c_L| / h`),
        ``q_L2_error``, ``p_L2_error`` (relative L2 distances over :math:`[-a, a]`), and
        against the closed form ``q_exact_L2_error``, ``c_exact_error_elements``.
    """
    a_form, L, bcs, pair, motion = cattaneo_mindlin_scene(comm, degree, across)
    V = pair.contactor.V
    n = pair.Q.dofmap.index_map.size_local
    x = np.concatenate(comm.allgather(pair.Q.tabulate_dof_coordinates()[:n, 0]))
    h = 2 * CM_A / across
    runs = [("lagrange", None, FrictionalContactProblem, {})]
    runs += [("penalty", k, RegularizedFrictionProblem, {"penalty": k}) for k in penalties]
    records = []
    for solver, kappa, cls, options in runs:
        with cls(
            a_form, L, [pair], bcs, mu=CM_MU, petsc_options_prefix=f"cmp_{solver}_", **options
        ) as problem:
            comm.Barrier()
            begin = time.perf_counter()
            counts = solve_path(problem, motion)
            seconds = comm.allreduce(time.perf_counter() - begin, op=MPI.MAX)
            p, q, stick = (
                np.concatenate(comm.allgather(f.x.array[:n]))
                for f in (problem.multipliers[0], problem.tangential[0], problem.stick[0])
            )

            def integral(f):
                return comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(f * ufl.dx)))

            P, Q = integral(problem.multipliers[0]), integral(problem.tangential[0])
        c = float(np.max(np.abs(x[stick > 0.5]), initial=0.0))
        records.append(
            {
                "solver": solver,
                "penalty": kappa,
                "degree": degree,
                "across": across,
                "h": h,
                "c": c,
                "P": P,
                "Q": Q,
                "seconds": seconds,
                "iterations": counts,
                "unknowns": 2 * V.dofmap.index_map.size_global
                + (2 * pair.Q.dofmap.index_map.size_global if solver == "lagrange" else 0),
                "x": x,
                "q": q,
                "p": p,
            }
        )
    ref = records[0]
    E_star = E / (2 * (1 - NU**2))
    a = 2 * math.sqrt(ref["P"] * (CM_R / 2) / (math.pi * E_star))
    p0, c_exact = 2 * ref["P"] / (math.pi * a), a * math.sqrt(1 - ref["Q"] / (CM_MU * ref["P"]))
    order = np.argsort(x)
    for rec in records:
        rec["c_error_elements"] = abs(rec["c"] - ref["c"]) / h
        for key in ("q", "p"):
            lagrange = lambda s, k=key: np.interp(s, x[order], ref[k][order])  # noqa: E731
            rec[f"{key}_L2_error"] = relative_l2(x, rec[key], lagrange, a)
        exact = lambda s: cattaneo_mindlin_shear(s, a, c_exact, p0)  # noqa: E731
        rec["q_exact_L2_error"] = relative_l2(x, rec["q"], exact, a)
        rec["c_exact_error_elements"] = abs(rec["c"] - c_exact) / h
        rec.update(a=a, c_exact=c_exact, p0=p0)
    return records

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The 3D scenes and runs of ``bench/bench_3d.py`` (P9-P11 of ``make bench``, issue 21).

The two blocks of :mod:`paper.blocks3d` (non-matching hexahedra, ``n`` and ``1.2 n``
across, ``n / 2`` layers each), the top of the upper block *held* at the displacement of
uniaxial stress, :math:`u_z = -P/E` at :math:`z = 1`, instead of loaded by the pressure
:math:`P`: the same exact solution (contact pressure :math:`P`), and every block held
by Dirichlet conditions, which the Schur field split with GAMG needs
(:mod:`dolfinx_contact_s2s.fieldsplit`). :func:`solve_level` solves it, tied or
unilateral, with that iterative solver and returns its times, iterations, memory and
errors against the exact solution.
"""

from __future__ import annotations

import time
import typing

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from paper.bench import backend_name, peak_memory, solver_description, timed
from paper.blocks3d import BOTTOM, TOP, E, P, errors, scene

__all__ = ["UNILATERAL_TOLERANCE", "held_scene", "level_for", "solve_level", "unknowns_of"]

#: Relative complementarity residual of a converged unilateral solve, here.
UNILATERAL_TOLERANCE = 1e-4


def _cells(level: int) -> tuple[tuple[int, int], int]:
    """Cells across the lower and the upper block and the layers of both, at ``level``."""
    return (level, round(1.2 * level)), max(1, level // 2)


def unknowns_of(level: int, degree: int = 1) -> int:
    """Displacements of both blocks and multipliers (Q1 or Q2 on the upper block's bottom)."""
    (lo, up), layers = _cells(level)
    nodes = [(degree * n + 1) ** 2 * (degree * layers + 1) for n in (lo, up)]
    return 3 * sum(nodes) + (degree * up + 1) ** 2


def level_for(unknowns: float, degree: int = 1) -> int:
    """The smallest level with at least ``unknowns`` unknowns."""
    level = 1
    while unknowns_of(level, degree) < unknowns:
        level += 1
    return level


def held_scene(comm: MPI.Comm, level: int, degree: int = 1, cells: str = "hex") -> tuple:
    """The blocks of ``level``, the upper top held at :math:`u_z = -P/E` (no load).

    Returns:
        ``(spaces, a, L, bcs)`` as :func:`paper.blocks3d.scene` returns them.
    """
    (lo, up), layers = _cells(level)
    spaces, a, L, bcs = scene(cells, cells, degree, cells=(lo, up), layers=layers, comm=comm, P=0.0)
    V_up, tags_up = spaces[1]
    # No load (UFL drops the zero traction's form: a zero one with its test function).
    zero = dolfinx.fem.Constant(V_up.mesh, np.zeros(3))
    L[1] = ufl.inner(zero, ufl.TestFunction(V_up)) * ufl.ds
    top = dolfinx.fem.locate_dofs_topological(V_up.sub(2), 2, tags_up.find(TOP))
    bcs.append(dolfinx.fem.dirichletbc(-P / E, top, V_up.sub(2)))
    return spaces, a, L, bcs


def solve_level(
    comm: MPI.Comm,
    level: int,
    *,
    unilateral: bool = False,
    degree: int = 1,
    log: typing.Callable[..., None] = lambda *m: None,
) -> dict[str, typing.Any]:
    """Set up and solve the held blocks with the Schur field split and GAMG (collective).

    The contactor is the upper block's bottom, the multiplier continuous of the
    displacement degree, the Schur complement approximated by the scaled multiplier mass
    (``s2s_schur_pre mass``: sparse, where the fractional one is dense).

    Args:
        comm: Communicator.
        level: Cells across the lower block (see :func:`unknowns_of`).
        unilateral: The active-set solve of the inequality constraint, not the tied one.
        degree: Displacement degree.
        log: Progress printer.

    Returns:
        Unknowns, cells, the stage times (s, slowest process), the KSP iterations of the
        last solve (and of every active-set iteration), peak memory and the largest
        errors of pressure and displacement against the exact solution.
    """
    from dolfinx_contact_s2s import contact_pair, contact_surface
    from dolfinx_contact_s2s.fieldsplit import iterative_options, use_schur_complement
    from dolfinx_contact_s2s.problem import LinearContactProblem
    from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

    times: dict[str, typing.Any] = {}
    (spaces, a, L, bcs), times["forms"] = timed(comm, lambda: held_scene(comm, level, degree))
    (V_lo, t_lo), (V_up, t_up) = spaces

    def make_pair():
        upper = contact_surface(V_up, t_up, BOTTOM)
        return contact_pair(upper, contact_surface(V_lo, t_lo, TOP))

    pair, times["pair"] = timed(comm, make_pair)
    options = iterative_options(spaces=2, schur="mass")
    iterations: list[int] = []
    kind = UnilateralContactProblem if unilateral else LinearContactProblem
    extra = {
        "monitor": lambda _: iterations.append(problem.solver.getIterationNumber()),
        # The iterative solve (rtol 1e-11) leaves pressure errors that grow with the size
        # (2e-7 at 1,420 unknowns, 1.4e-5 at 100,116, measured): the default 1e-10 of a
        # direct solve, or 1e-6, is never reached and the active set repeats its solves.
        "tolerance": UNILATERAL_TOLERANCE,
    }

    def make_problem():
        return kind(
            a,
            L,
            [pair],
            bcs,
            petsc_options_prefix="bench3d_",
            petsc_options=options,
            kind="nest",
            **(extra if unilateral else {}),
        )

    problem, times["problem"] = timed(comm, make_problem)
    use_schur_complement(problem)
    unknowns = sum(
        V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in (V_lo, V_up, pair.Q)
    )
    cells = sum(V.mesh.topology.index_map(3).size_global for V in (V_lo, V_up))
    log(f"level {level}: {unknowns} unknowns, {cells} cells; solving")
    try:
        begin = time.perf_counter()
        (us, (pressure,)), times["solve"] = timed(comm, problem.solve)
        times["stages"] = {k: comm.allreduce(v, op=MPI.MAX) for k, v in problem.timings.items()}
        if unilateral:
            times["update"] = comm.allreduce(problem.update_seconds, op=MPI.MAX)
        error_p, error_u = errors(us, pressure)
        solver = solver_description(problem.solver)
        log(
            f"  {solver['iterations']} iterations, {time.perf_counter() - begin:.1f} s; errors "
            f"pressure {error_p:.2e}, displacement {error_u:.2e}"
        )
        return {
            "level": level,
            "degree": degree,
            "unknowns": unknowns,
            "cells": cells,
            "multipliers": pair.Q.dofmap.index_map.size_global,
            "ranks": comm.size,
            "backend": backend_name(pair.contactor),
            "unilateral": unilateral,
            "times": times,
            "iterations": solver["iterations"],
            "iterations_per_solve": iterations or [solver["iterations"]],
            "solver_used": solver,
            "error_pressure": error_p,
            "error_displacement": error_u,
            "peak_memory": peak_memory(comm),
        }
    finally:
        problem.destroy()

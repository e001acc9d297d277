# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Run a study over refinement levels, assert a rate, extrapolate (Richardson)."""

from __future__ import annotations

import math
import time
import typing
from collections.abc import Callable, Mapping, Sequence

from mpi4py import MPI

import dolfinx
import numpy as np

from dolfinx_contact_s2s.convergence.table import ROUNDOFF, SECONDS, ConvergenceTable, Level

__all__ = ["assert_rate", "convergence_study", "richardson"]

#: Largest relative difference between the values ranks report for one quantity.
_RANK_TOLERANCE = 1e-12


def _default_h(solved: typing.Any) -> float:
    """Largest cell diameter over the meshes of ``solved.spaces``, over all processes."""
    spaces = getattr(solved, "spaces", None)
    if spaces is None:
        raise ValueError(
            f"cannot find the mesh size of a {type(solved).__name__} (no 'spaces'): give h="
        )
    meshes = {id(V.mesh): V.mesh for V in spaces}.values()
    h = 0.0
    for mesh in meshes:
        tdim = mesh.topology.dim
        cells = np.arange(mesh.topology.index_map(tdim).size_local, dtype=np.int32)
        local = dolfinx.cpp.mesh.h(mesh._cpp_object, tdim, cells)
        h = max(h, mesh.comm.allreduce(float(np.max(local, initial=0.0)), op=MPI.MAX))
    return h


def _default_unknowns(solved: typing.Any) -> int:
    """Global size of ``solved.A`` if assembled, else the global dofs of ``solved.spaces``."""
    A = getattr(solved, "A", None)
    if A is not None:
        return int(A.getSize()[0])
    spaces = getattr(solved, "spaces", None)
    if spaces is None:
        raise ValueError(
            f"cannot count the unknowns of a {type(solved).__name__} (no 'A' or 'spaces'): "
            "give unknowns="
        )
    return sum(V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in spaces)


def _default_cleanup(solved: typing.Any) -> None:
    destroy = getattr(solved, "destroy", None)
    if callable(destroy):
        destroy()


def _split_seconds(solved: typing.Any, total: float) -> dict[str, float]:
    """This process's wall time of one level by stage (see :attr:`Level.seconds`)."""
    timings = getattr(solved, "timings", None)
    if not isinstance(timings, Mapping):
        return {"setup": total, "contact": 0.0, "assembly": 0.0, "solve": 0.0, "total": total}
    contact = float(timings.get("contact", 0.0))
    assembly = float(timings.get("stiffness", 0.0)) + float(timings.get("system", 0.0))
    solve = float(timings.get("solve", 0.0))
    setup = max(total - contact - assembly - solve, 0.0)
    return {
        "setup": setup,
        "contact": contact,
        "assembly": assembly,
        "solve": solve,
        "total": total,
    }


def _agreed(comm: MPI.Comm, level: typing.Any, values: dict[str, float]) -> dict[str, float]:
    """Rank 0's ``values``, after checking every rank has the same, finite, non-negative ones.

    Raises:
        ValueError: On every rank, if not.
    """
    gathered = comm.allgather(values)
    problems = []
    for key in gathered[0]:
        column = [float(g[key]) for g in gathered]
        if not all(math.isfinite(v) and v >= 0 for v in column):
            shown = column[0] if comm.size == 1 else column
            problems.append(f"{key} = {shown} is not a finite non-negative number")
        elif any(abs(v - column[0]) > _RANK_TOLERANCE * abs(column[0]) for v in column):
            problems.append(
                f"{key} differs between the ranks ({column}): its function must be collective "
                "(reduce over all processes) and return the same value on every rank"
            )
    if problems:
        raise ValueError(f"level {level!r}: " + "; ".join(problems))
    return {k: float(v) for k, v in gathered[0].items()}


def _print(line: str) -> None:
    print(line, flush=True)


def _log_line(name: str, lv: Level) -> str:
    errors = " ".join(f"{k}={v:.4e}" for k, v in lv.errors.items())
    s = lv.seconds
    split = ", ".join(f"{k} {s[k]:.3g}" for k in SECONDS[:-1])
    timed = f"{s['total']:.3g} s ({split})" if s["setup"] < s["total"] else f"{s['total']:.3g} s"
    return f"{name}: level {lv.level}: h={lv.h:.4g} unknowns={lv.unknowns} {errors} {timed}"


def convergence_study(
    solve: Callable[[typing.Any], typing.Any],
    levels: Sequence[typing.Any],
    errors: Mapping[str, Callable[[typing.Any], float]],
    h: Callable[[typing.Any], float] | None = None,
    unknowns: Callable[[typing.Any], int] | None = None,
    name: str = "convergence study",
    comm: MPI.Comm = MPI.COMM_WORLD,
    log: Callable[[str], None] | None = _print,
    cleanup: Callable[[typing.Any], None] | None = None,
    *,
    roundoff: float = ROUNDOFF,
) -> ConvergenceTable:
    """Solve at every level, measure the errors and time the solves.

    Collective over ``comm``: every process calls ``solve``, the error functionals,
    ``h``, ``unknowns`` and ``cleanup`` at every level, in the same order.

    Args:
        solve: Maps a level (an element of ``levels``) to a solved object, e.g. a
            solved :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`.
        levels: The refinement levels, coarsest first: the mesh size must decrease
            strictly from one to the next.
        errors: Name to error functional of a solved object. Each must be collective
            and return the same finite, non-negative number on every process.
        h: Mesh size of a solved object; default: the largest cell diameter over the
            meshes of ``solved.spaces``.
        unknowns: Number of unknowns of a solved object; default: the global size of
            ``solved.A`` if present, else the global dofs of ``solved.spaces``.
        name: Name of the study, in the log and the table.
        comm: The processes taking part.
        log: Called on rank 0 with one line per level (h, unknowns, errors, seconds);
            ``None`` for silence. Default: print and flush.
        cleanup: Called on a solved object when it has been measured; default: its
            ``destroy()``, if it has one.
        roundoff: Errors at or below this are round-off and get no rate.

    Returns:
        The same table on every process. Its seconds are those of the slowest process
        (the largest total), so the stages add up to the total.

    Raises:
        ValueError: On every process, if ``levels`` is empty, the mesh size does not
            decrease strictly, or an error, ``h`` or ``unknowns`` is not finite, is
            negative, or differs between the processes.
    """
    if len(levels) == 0:
        raise ValueError("a convergence study needs at least one level")
    cleanup = _default_cleanup if cleanup is None else cleanup
    table = ConvergenceTable(name, [], ranks=comm.size, roundoff=float(roundoff), comm=comm)
    for level in levels:
        begin = time.perf_counter()
        solved = solve(level)
        wall = time.perf_counter() - begin
        try:
            measured = {
                "h": float(_default_h(solved) if h is None else h(solved)),
                "unknowns": float(
                    _default_unknowns(solved) if unknowns is None else unknowns(solved)
                ),
            }
            measured.update({f"error {k}": float(f(solved)) for k, f in errors.items()})
            seconds = _split_seconds(solved, wall)
        finally:
            cleanup(solved)
        agreed = _agreed(comm, level, measured)
        if agreed["unknowns"] != int(agreed["unknowns"]):
            raise ValueError(f"level {level!r}: unknowns = {agreed['unknowns']} is no integer")
        # The slowest process's split, so that the stages add up to its total.
        every = comm.allgather(seconds)
        slowest = every[int(np.argmax([s["total"] for s in every]))]
        lv = Level(
            level=level,
            h=agreed["h"],
            unknowns=int(agreed["unknowns"]),
            errors={k: agreed[f"error {k}"] for k in errors},
            seconds=dict(slowest),
        )
        if table.levels and not lv.h < table.levels[-1].h:
            raise ValueError(
                f"level {level!r}: h = {lv.h:.6g} does not decrease from level "
                f"{table.levels[-1].level!r} (h = {table.levels[-1].h:.6g}); give the levels "
                "coarsest first"
            )
        table.levels.append(lv)
        if log is not None and comm.rank == 0:
            log(_log_line(name, lv))
    return table


# --- checks and records ----------------------------------------------------------------


def assert_rate(
    table: ConvergenceTable,
    name: str,
    expected: float,
    tolerance: float = 0.1,
    last: int = 3,
    *,
    at_least: bool = False,
) -> float:
    r"""Assert that error ``name`` converges at rate ``expected``, for use in tests.

    Args:
        table: The study.
        name: The error.
        expected: The expected rate (slope of :math:`\log e` against :math:`\log h`).
        tolerance: Largest admissible difference of the fitted rate from ``expected``.
        last: Number of finest levels fitted (:meth:`ConvergenceTable.fitted_rate`).
        at_least: Only a rate below ``expected - tolerance`` fails.

    Returns:
        The fitted rate.

    Raises:
        AssertionError: With the table, if the rate is off or the errors are at
            round-off (no rate to measure).
        ValueError: For an unknown error name or too few levels.
    """
    rate = table.fitted_rate(name, last)
    if math.isnan(rate):
        raise AssertionError(
            f"{table.name}: the errors {name!r} of the last {last} levels are at round-off "
            f"(at most {table.roundoff:.1e}), not a rate: there is no rate to compare with "
            f"{expected}.\n\n{table.markdown(last=last)}"
        )
    low, high = expected - tolerance, math.inf if at_least else expected + tolerance
    if not low <= rate <= high:
        bound = f">= {low:g}" if at_least else f"{expected:g} ± {tolerance:g}"
        raise AssertionError(
            f"{table.name}: the rate of {name!r} over the last {last} levels is {rate:.3f}, "
            f"expected {bound}.\n\n{table.markdown(last=last)}"
        )
    return rate


def richardson(levels: Sequence[float], values: Sequence[float]) -> tuple[float, float]:
    r"""Limit and order :math:`(E, q)` of :math:`E_h = E + C h^q` from three levels.

    ``levels`` are :math:`h` with a constant ratio :math:`r = h_1/h_2 = h_2/h_3`.
    """
    (h1, h2, h3), (e1, e2, e3) = levels[-3:], values[-3:]
    r = h1 / h2
    if not math.isclose(r, h2 / h3, rel_tol=1e-6):
        raise ValueError("Richardson extrapolation needs a constant refinement ratio")
    d1, d2 = e1 - e2, e2 - e3
    if d1 == 0 or d2 == 0 or d1 / d2 <= 0:
        raise ValueError("the values do not converge monotonically")
    q = math.log(d1 / d2) / math.log(r)
    return e3 - d2 / (r**q - 1.0), q

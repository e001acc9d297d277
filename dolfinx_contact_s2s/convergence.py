# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Convergence studies that run in CI: errors, rates and wall time against mesh size.

A study runs a user's solve at a sequence of refinement levels, evaluates error
functionals on each solution and records the mesh size :math:`h`, the number of
unknowns, every error and the wall time, split into setup, contact, assembly and
solve. The observed rate between two levels is

.. math:: r_i = \frac{\log(e_i / e_{i+1})}{\log(h_i / h_{i+1})},

and the fitted rate is the least-squares slope of :math:`\log e` against
:math:`\log h` over the last levels. :func:`assert_rate` checks one inside a test::

    table = convergence_study(solve, [8, 16, 32, 64], errors={"L2": l2_error})
    assert_rate(table, "L2", 2.0, tolerance=0.1)

Everything is collective over ``comm``: every process calls the solve, the error
functionals, :func:`convergence_study` and the writers, and every process gets the same
table. Errors at or below :attr:`ConvergenceTable.roundoff` (a patch test passed to
round-off) have no rate: it is NaN, ``null`` in JSON, and :func:`assert_rate` says so.

This module does not need petsc4py; matplotlib is imported only by
:meth:`ConvergenceTable.plot`.
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import time
import typing
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from mpi4py import MPI

import dolfinx
import numpy as np
import numpy.typing as npt

__all__ = [
    "ROUNDOFF",
    "SECONDS",
    "ConvergenceTable",
    "Level",
    "assert_rate",
    "convergence_study",
    "json_ready",
    "on_rank0",
    "richardson",
]

#: Keys of :attr:`Level.seconds`: wall time (s) of one level, split by stage.
SECONDS = ("setup", "contact", "assembly", "solve", "total")

#: Default :attr:`ConvergenceTable.roundoff`: errors at or below it are round-off.
ROUNDOFF = 1e-10

#: Largest relative difference between the values ranks report for one quantity.
_RANK_TOLERANCE = 1e-12


@dataclass
class Level:
    """One refinement level of a study.

    Attributes:
        level: The argument the solve was called with.
        h: Mesh size (by default the largest cell diameter).
        unknowns: Number of unknowns (global).
        errors: Value of each error functional.
        seconds: Wall time (s) of the level by stage, keys :data:`SECONDS`: ``"setup"``
            (the solve's wall time outside the stages below), ``"contact"`` (search,
            segmentation, coupling), ``"assembly"`` (stiffness and saddle-point system),
            ``"solve"`` (factorization and solve) and ``"total"`` (the solve's wall time).
            Error functionals are not timed.
    """

    level: typing.Any
    h: float
    unknowns: int
    errors: dict[str, float]
    seconds: dict[str, float]


def json_ready(value: typing.Any) -> typing.Any:
    """``value`` for :func:`json.dumps`, with non-finite floats as ``None`` (JSON ``null``).

    NumPy scalars and arrays become Python numbers and lists, tuples lists.
    """
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, Mapping):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [json_ready(v) for v in value]
    return value


def _format_rate(rate: float) -> str:
    return "n/a" if math.isnan(rate) else f"{rate:.2f}"


@dataclass
class ConvergenceTable:
    """The result of :func:`convergence_study`: one :class:`Level` per refinement.

    Attributes:
        name: Name of the study.
        levels: The levels, coarsest first (:math:`h` strictly decreasing).
        ranks: Number of processes the study ran on.
        roundoff: Errors at or below this are round-off and have no rate. Scaled
            errors (relative to the solution) suit the default :data:`ROUNDOFF`.
        comm: Communicator the writers are collective over (not stored in JSON).
    """

    name: str
    levels: list[Level]
    ranks: int = 1
    roundoff: float = ROUNDOFF
    comm: MPI.Comm = field(default_factory=lambda: MPI.COMM_WORLD, repr=False, compare=False)

    @property
    def error_names(self) -> list[str]:
        """Names of the errors, in the order they were given."""
        return list(self.levels[0].errors) if self.levels else []

    def h(self) -> npt.NDArray[np.float64]:
        """Mesh size of every level."""
        return np.array([lv.h for lv in self.levels], dtype=np.float64)

    def errors(self, name: str) -> npt.NDArray[np.float64]:
        """Values of error ``name`` at every level.

        Raises:
            ValueError: If the table has no error ``name``.
        """
        if name not in self.error_names:
            raise ValueError(f"no error {name!r} in the study; it has {self.error_names}")
        return np.array([lv.errors[name] for lv in self.levels], dtype=np.float64)

    def at_roundoff(self, name: str) -> npt.NDArray[np.bool_]:
        """Whether error ``name`` is at round-off (at most :attr:`roundoff`) at each level."""
        return self.errors(name) <= self.roundoff

    def rates(self, name: str) -> list[float]:
        r"""Observed rates :math:`\log(e_i/e_{i+1}) / \log(h_i/h_{i+1})` between levels.

        Returns:
            One rate per pair of consecutive levels; NaN where either error is at
            round-off.
        """
        e, h, zero = self.errors(name), self.h(), self.at_roundoff(name)
        return [
            math.nan
            if zero[i] or zero[i + 1]
            else float(np.log(e[i] / e[i + 1]) / np.log(h[i] / h[i + 1]))
            for i in range(len(self.levels) - 1)
        ]

    def fitted_rate(self, name: str, last: int = 3) -> float:
        r"""Least-squares slope of :math:`\log e` against :math:`\log h` over the last levels.

        Args:
            name: The error.
            last: Number of finest levels fitted, at least 2.

        Returns:
            The slope; NaN if an error of these levels is at round-off.

        Raises:
            ValueError: If ``last < 2`` or the table has fewer than ``last`` levels.
        """
        if last < 2:
            raise ValueError(f"a rate needs at least 2 levels, not last={last}")
        if last > len(self.levels):
            raise ValueError(
                f"last={last} levels asked for, the study {self.name!r} has {len(self.levels)}"
            )
        e, h = self.errors(name)[-last:], self.h()[-last:]
        if np.any(self.at_roundoff(name)[-last:]):
            return math.nan
        return float(np.polyfit(np.log(h), np.log(e), 1)[0])

    def to_dict(self, last: int = 3) -> dict[str, typing.Any]:
        """The table as a JSON-ready dictionary (NaN as ``None``).

        Args:
            last: Levels of the fitted rates (fewer if the table has fewer).
        """
        fit = min(last, len(self.levels))
        out = {
            "name": self.name,
            "ranks": self.ranks,
            "roundoff": self.roundoff,
            "levels": [
                {
                    "level": lv.level,
                    "h": lv.h,
                    "unknowns": lv.unknowns,
                    "errors": lv.errors,
                    "seconds": lv.seconds,
                }
                for lv in self.levels
            ],
            "rates": {n: self.rates(n) for n in self.error_names},
            "fitted_rates": {
                n: self.fitted_rate(n, fit) if fit >= 2 else math.nan for n in self.error_names
            },
            "fitted_over": fit,
        }
        return json_ready(out)

    @classmethod
    def from_dict(cls, data: Mapping[str, typing.Any]) -> ConvergenceTable:
        """A table from :meth:`to_dict` (or its JSON); rates are recomputed."""
        levels = [
            Level(
                level=lv["level"],
                h=float(lv["h"]),
                unknowns=int(lv["unknowns"]),
                errors={k: float(v) for k, v in lv["errors"].items()},
                seconds={k: float(v) for k, v in lv["seconds"].items()},
            )
            for lv in data["levels"]
        ]
        return cls(
            name=data["name"],
            levels=levels,
            ranks=int(data.get("ranks", 1)),
            roundoff=float(data.get("roundoff", ROUNDOFF)),
        )

    def write_json(
        self, path: str | os.PathLike, *, last: int = 3, comm: MPI.Comm | None = None
    ) -> None:
        """Write :meth:`to_dict` to ``path``: rank 0 writes, every rank returns after it.

        Args:
            path: The JSON file.
            last: Levels of the fitted rates.
            comm: The processes taking part; default :attr:`comm`.
        """
        text = json.dumps(self.to_dict(last), indent=1, allow_nan=False)
        on_rank0(self.comm if comm is None else comm, lambda: _write_text(path, text))

    def markdown(self, *, last: int = 3) -> str:
        """The table in Markdown: every level's h, unknowns, errors, rates and seconds.

        Args:
            last: Levels of the fitted rates listed below the table.
        """
        names = self.error_names
        head = ["level", "h", "unknowns"]
        for n in names:
            head += [n, "rate"]
        head += [f"{k} (s)" for k in SECONDS]
        rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        rates = {n: self.rates(n) for n in names}
        for i, lv in enumerate(self.levels):
            cells = [str(lv.level), f"{lv.h:.4g}", str(lv.unknowns)]
            for n in names:
                cells += [f"{lv.errors[n]:.4e}", _format_rate(rates[n][i - 1]) if i else ""]
            cells += [f"{lv.seconds[k]:.3g}" for k in SECONDS]
            rows.append("| " + " | ".join(cells) + " |")
        fit = min(last, len(self.levels))
        if fit >= 2:
            fitted = ", ".join(f"{n} {_format_rate(self.fitted_rate(n, fit))}" for n in names)
            rows += ["", f"Fitted rate over the last {fit} levels: {fitted}."]
        if any(np.any(self.at_roundoff(n)) for n in names):
            rows += [f"n/a: an error at round-off (at most {self.roundoff:.1e}), no rate."]
        return "\n".join(rows) + "\n"

    def plot(
        self,
        path: str | os.PathLike,
        *,
        slopes: Sequence[float] | None = None,
        last: int = 3,
        title: str | None = None,
        comm: MPI.Comm | None = None,
    ) -> None:
        """Write a log-log plot of every error against h (PNG; rank 0 writes).

        Collective: every rank returns once the file is written. Errors at round-off
        are drawn at their value if positive; exact zeros are left out.

        Args:
            path: The image file.
            slopes: Reference slopes, drawn as dotted lines :math:`h^s` through half
                each error's finest value; by default each error's fitted rate rounded to
                a half.
            last: Levels of the default slopes' fit.
            title: Plot title; default: the study's name.
            comm: The processes taking part; default :attr:`comm`.
        """

        def draw() -> None:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            import matplotlib.ticker

            fig, ax = plt.subplots(figsize=(5.5, 4.2))
            h = self.h()
            fit = min(last, len(self.levels))
            for n in self.error_names:
                e = self.errors(n)
                positive = e > 0
                label = f"{n} (round-off)" if np.any(self.at_roundoff(n)) else n
                (line,) = ax.loglog(h[positive], e[positive], "o-", label=label)
                if slopes is not None:
                    chosen = list(slopes)
                elif fit >= 2 and not math.isnan(rate := self.fitted_rate(n, fit)):
                    chosen = [round(2 * rate) / 2]
                else:
                    chosen = []
                if not positive[-1]:
                    continue
                for s in chosen:
                    # Below the data by half, so that both stay visible.
                    ax.loglog(
                        h,
                        0.5 * e[-1] * (h / h[-1]) ** s,
                        ":",
                        color=line.get_color(),
                        label=f"$h^{{{s:g}}}$",
                    )
            # Ticks at the levels' h: a study often spans less than a decade.
            ax.set_xticks(h, [f"{v:.3g}" for v in h])
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_xlabel("h")
            ax.set_ylabel("error")
            ax.set_title(self.name if title is None else title)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize="small")
            fig.tight_layout()
            fig.savefig(path, dpi=120)
            plt.close(fig)

        on_rank0(self.comm if comm is None else comm, draw)


def _write_text(path: str | os.PathLike, text: str) -> None:
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text + "\n")


def on_rank0(comm: MPI.Comm, action: Callable[[], None]) -> None:
    """Run ``action`` on rank 0 of ``comm``; an exception there is raised on every rank."""
    error = None
    if comm.rank == 0:
        try:
            action()
        except Exception as e:  # raised again below, on every rank
            error = f"{type(e).__name__}: {e}"
    error = comm.bcast(error, root=0)
    if error is not None:
        raise RuntimeError(f"rank 0 failed to write: {error}")


# --- the study -------------------------------------------------------------------------


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

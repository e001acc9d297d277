# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The table of a convergence study: levels, errors, rates, Markdown, JSON and plots.

matplotlib is imported only by :meth:`ConvergenceTable.plot`.
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import typing
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from mpi4py import MPI

import numpy as np
import numpy.typing as npt

__all__ = ["ROUNDOFF", "SECONDS", "ConvergenceTable", "Level", "json_ready", "on_rank0"]

#: Keys of :attr:`Level.seconds`: wall time (s) of one level, split by stage.
SECONDS = ("setup", "contact", "assembly", "solve", "total")

#: Default :attr:`ConvergenceTable.roundoff`: errors at or below it are round-off.
ROUNDOFF = 1e-10


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

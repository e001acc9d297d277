# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The files of ``results/``: convergence records and the JSON lists the studies update.

Every study of the paper files its refinement tables in ``results/convergence.json``
through :func:`records` and :func:`update_results`; the JSON conversion is the
library's :func:`~dolfinx_contact_s2s.convergence.json_ready`.
"""

from __future__ import annotations

import fcntl
import json
import math
import os
import pathlib
import typing
from collections.abc import Mapping, Sequence
from pathlib import Path

from mpi4py import MPI

from dolfinx_contact_s2s.convergence import ConvergenceTable, json_ready, on_rank0

__all__ = ["merge_rank_records", "records", "update_results"]


#: Keys of a record of ``results/convergence.json`` given by the caller, and defaults.
_RECORD_KEYS = {
    "study": None,
    "variant": "",
    "method": None,
    "multiplier": None,
    "degree": None,
    "cell": None,
}


def records(
    table: ConvergenceTable,
    *,
    quantities: Sequence[str] | None = None,
    last: int = 3,
    **keys: typing.Any,
) -> list[dict[str, typing.Any]]:
    """Records of ``results/convergence.json``: one per error of the table.

    Each record has the ``keys`` (``study`` required; ``variant``, ``method``,
    ``multiplier``, ``degree``, ``cell`` default to ``""``/``None``; any other key is
    kept), ``quantity`` (the error's name), ``ranks``, ``levels`` (``level``, ``h``,
    ``unknowns``, ``error``, ``seconds`` = the total and ``split`` = all
    :data:`SECONDS`), ``rates`` and ``fitted_rate`` (NaN as ``None``).

    Args:
        table: The study.
        quantities: The errors to record; default: all.
        last: Levels of the fitted rate (fewer if the table has fewer).
        keys: The study, method and so on.

    Raises:
        ValueError: Without ``study``.
    """
    if not keys.get("study"):
        raise ValueError("a record needs study=")
    fit = min(last, len(table.levels))
    out = []
    for q in table.error_names if quantities is None else quantities:
        e = table.errors(q)
        record = {**_RECORD_KEYS, **keys, "quantity": q, "ranks": table.ranks}
        record["levels"] = [
            {
                "level": lv.level,
                "h": lv.h,
                "unknowns": lv.unknowns,
                "error": float(ei),
                "seconds": lv.seconds["total"],
                "split": lv.seconds,
            }
            for lv, ei in zip(table.levels, e, strict=True)
        ]
        record["rates"] = table.rates(q)
        record["fitted_rate"] = table.fitted_rate(q, fit) if fit >= 2 else math.nan
        out.append(json_ready(record))
    return out


def update_results(
    path: str | os.PathLike,
    records: Sequence[Mapping[str, typing.Any]],
    *,
    study: str,
    ranks: int,
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> None:
    """Replace the records of ``study`` on ``ranks`` processes in a JSON list of records.

    Rank 0 reads ``path`` (if it exists), drops the records with this ``study`` and
    ``ranks``, appends ``records`` and writes the file back, holding a lock on it so that
    concurrent writers do not lose each other's records. Collective over ``comm``.

    Args:
        path: The JSON file, e.g. ``results/convergence.json``.
        records: Records from :func:`records` (the function).
        study: The study they belong to.
        ranks: The number of processes they were computed on.
        comm: The processes taking part.

    Raises:
        ValueError: On every rank, if a record is of another study or rank count.
        RuntimeError: On every rank, if rank 0 cannot read or write the file.
    """
    new = [json_ready(dict(r)) for r in records]
    for r in new:
        if r.get("study") != study or r.get("ranks") != ranks:
            raise ValueError(
                f"record of study {r.get('study')!r} on {r.get('ranks')} ranks given to "
                f"update study {study!r} on {ranks} ranks"
            )

    def write() -> None:
        target = pathlib.Path(path)
        target.parent.mkdir(parents=True, exist_ok=True)
        with open(target, "a+") as f:
            fcntl.flock(f, fcntl.LOCK_EX)
            f.seek(0)
            text = f.read()
            old = json.loads(text) if text.strip() else []
            if not isinstance(old, list):
                raise ValueError(f"{target} holds no JSON list of records")
            kept = [r for r in old if not (r.get("study") == study and r.get("ranks") == ranks)]
            f.seek(0)
            f.truncate()
            f.write(json.dumps(kept + new, indent=1, allow_nan=False) + "\n")
            f.flush()
            os.fsync(f.fileno())

    on_rank0(comm, write)


def merge_rank_records(
    path: str | os.PathLike, records: Sequence[Mapping[str, typing.Any]], ranks: int
) -> list[dict[str, typing.Any]]:
    """Replace the records of ``ranks`` processes in the JSON list at ``path``; on one rank.

    The records of the other rank counts are kept, so that runs on 1 and 2 ranks sit
    side by side; the list is sorted by rank count (stably). Not collective: call it on
    rank 0.

    Returns:
        The merged list, as written.
    """
    target = Path(path)
    old = json.loads(target.read_text()) if target.exists() else []
    merged = [r for r in old if r.get("ranks") != ranks] + [dict(r) for r in records]
    merged.sort(key=lambda r: r.get("ranks", 0))
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(merged, indent=1) + "\n")
    return merged

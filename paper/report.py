# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The shared results report: each study replaces its own section of ``report.md``.

Every demo writes one section, fenced by HTML comments that Markdown does not show, so
that the demos can run in any order and any subset without erasing each other's
results.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from pathlib import Path

from mpi4py import MPI

__all__ = ["TITLE", "demo_parser", "output_folder", "rank0_print", "verdict", "write_section"]

#: The first line of a new report.
TITLE = "# dolfinx_contact_s2s: results"


def write_section(
    path: str | Path, name: str, lines: Sequence[str], *, after: str | None = None
) -> None:
    """Replace the section ``name`` of the report at ``path``, or add it.

    Call on one process only (the report is one file).

    Args:
        path: The report (created with :data:`TITLE` if absent).
        name: Key of the section, e.g. ``"hertz"``; its fences are
            ``<!-- begin NAME -->`` and ``<!-- end NAME -->``.
        lines: The section's Markdown, its own headings included.
        after: A new section goes right after this section (a subsection of it,
            e.g. ``"tradeoff"``, the speed-accuracy section) if the report has it, else
            at the end.
    """
    path = Path(path)
    begin, end = f"<!-- begin {name} -->", f"<!-- end {name} -->"
    text = path.read_text() if path.exists() else TITLE + "\n"
    body = "\n".join([begin, *lines, end])
    if begin in text and end in text[text.index(begin) :]:
        head, rest = text.split(begin, 1)
        tail = rest.split(end, 1)[1]
        text = head + body + tail
    elif after is not None and f"<!-- end {after} -->" in text:
        head, tail = text.split(f"<!-- end {after} -->", 1)
        text = head + f"<!-- end {after} -->\n\n" + body + tail
    else:
        text = text.rstrip("\n") + "\n\n" + body + "\n"
    path.write_text(text)


def verdict(demo: str, comm: MPI.Comm, smoke: bool, failed: Sequence[str]) -> str:
    """A demo section's first line: the script, its ranks, smoke or not, and its checks."""
    state = "all checks met." if not failed else "FAILED: " + "; ".join(failed)
    return f"`demos/{demo}`, {comm.size} rank(s)" + (" (smoke run)" if smoke else "") + ": " + state


def demo_parser(
    description: str, smoke: str, out: Path | None = Path("results")
) -> argparse.ArgumentParser:
    """The command line every demo has: ``--smoke`` (a reduced run) and ``--out``.

    Args:
        description: What the demo studies.
        smoke: What ``--smoke`` runs instead.
        out: The default output folder.
    """
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--smoke", action="store_true", help=smoke)
    parser.add_argument("--out", type=Path, default=out, help="output folder")
    return parser


def output_folder(path: Path, comm: MPI.Comm) -> Path:
    """Create ``path`` on rank 0 before any rank writes into it (collective)."""
    if comm.rank == 0:
        path.mkdir(parents=True, exist_ok=True)
    comm.Barrier()
    return path


def rank0_print(comm: MPI.Comm) -> Callable[..., None]:
    """A ``print`` that prints on rank 0 only, flushed (the demos' progress lines)."""

    def log(*words: object) -> None:
        if comm.rank == 0:
            print(*words, flush=True)

    return log

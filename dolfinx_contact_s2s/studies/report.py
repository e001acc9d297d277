# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The shared results report: each study replaces its own section of ``report.md``.

Every demo writes one section, fenced by HTML comments that Markdown does not show, so
that the demos can run in any order and any subset without erasing each other's
results.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

__all__ = ["TITLE", "write_section"]

#: The first line of a new report.
TITLE = "# dolfinx_contact_s2s: results"


def write_section(path: str | Path, name: str, lines: Sequence[str]) -> None:
    """Replace the section ``name`` of the report at ``path``, or append it.

    Call on one process only (the report is one file).

    Args:
        path: The report (created with :data:`TITLE` if absent).
        name: Key of the section, e.g. ``"hertz"``; its fences are
            ``<!-- begin NAME -->`` and ``<!-- end NAME -->``.
        lines: The section's Markdown, its own headings included.
    """
    path = Path(path)
    begin, end = f"<!-- begin {name} -->", f"<!-- end {name} -->"
    text = path.read_text() if path.exists() else TITLE + "\n"
    body = "\n".join([begin, *lines, end])
    if begin in text and end in text[text.index(begin) :]:
        head, rest = text.split(begin, 1)
        tail = rest.split(end, 1)[1]
        text = head + body + tail
    else:
        text = text.rstrip("\n") + "\n\n" + body + "\n"
    path.write_text(text)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The report's sections: each replaced in place, the others kept, in any order."""

from mpi4py import MPI

import pytest

from paper.report import TITLE, write_section


@pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="a file written by one process")
def test_sections_replace_only_themselves(tmp_path):
    path = tmp_path / "report.md"
    write_section(path, "a", ["## A", "first"])
    write_section(path, "b", ["## B", "", "## B, part two", "x"])
    write_section(path, "a", ["## A", "second"])
    text = path.read_text()
    assert text.startswith(TITLE)
    assert "first" not in text and "second" in text
    # Both sections once, in their first order; a section may hold several headings.
    assert text.count("## A") == 1 and text.count("## B, part two") == 1
    assert text.index("## A") < text.index("## B")
    write_section(path, "b", ["## B", "y"])
    text = path.read_text()
    assert "part two" not in text and "second" in text and text.endswith("<!-- end b -->\n")

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""``help()`` of the user-facing factories documents every argument (Google style)."""

import inspect
import re

import pytest

from dolfinx_contact_s2s import contact_pair, contact_pairs, contact_surface

SECTIONS = ("Args", "Returns", "Raises")


def sections(doc: str) -> dict[str, list[str]]:
    """The lines of each Google-style section of a cleaned docstring, by its header."""
    found, current = {}, None
    for line in doc.splitlines():
        header = re.fullmatch(r"(\w[\w ]*):", line)
        if header:
            current = found.setdefault(header.group(1), [])
        elif current is not None and (line.startswith(" ") or not line):
            current.append(line)
        else:
            current = None
    return found


def documented(args: list[str]) -> set[str]:
    """The parameter names of an ``Args`` section (entries at its first indentation)."""
    indent = min(len(a) - len(a.lstrip()) for a in args if a.strip())
    names = set()
    for line in args:
        entry = re.match(r"\*{0,2}(\w+)( \([^)]*\))?:", line[indent:])
        if line.strip() and len(line) - len(line.lstrip()) == indent and entry:
            names.add(entry.group(1))
    return names


@pytest.mark.parametrize("function", [contact_pair, contact_pairs, contact_surface])
def test_every_argument_documented(function):
    doc = inspect.getdoc(function)
    parts = sections(doc)
    for name in SECTIONS:
        assert parts.get(name), f"{function.__name__}: no {name}: section"
    params = set(inspect.signature(function).parameters)
    assert params == documented(parts["Args"]), function.__name__
    # Each entry says something (no bare names).
    for line in parts["Args"]:
        assert not re.fullmatch(r"\s*\*{0,2}\w+:\s*", line), line


def test_search_radius_and_defaults_explained():
    args = "\n".join(sections(inspect.getdoc(contact_pair))["Args"])
    entry = args[args.index("search_radius:") :]
    assert "normal distance" in entry and "Default" in entry and "largest facet" in entry
    for method in ("segment-to-segment", "node-to-segment", "node-to-node", "intermediate"):
        assert method in args
    for rule in ("composite-gauss", "composite-newton-cotes"):
        assert rule in args
    backend = "\n".join(sections(inspect.getdoc(contact_surface))["Args"])
    for name in ('"auto"', '"c"', '"numpy"'):
        assert name in backend


def test_no_control_characters_in_the_sources():
    r"""No tab or other control character in the package's sources.

    A ``"\tau"`` written into a non-raw string (or a tab pasted into a raw one) renders as
    a tab followed by ``au``: the maths of the docstring is silently lost.
    """
    import pathlib

    import dolfinx_contact_s2s

    root = pathlib.Path(dolfinx_contact_s2s.__file__).parent
    bad = [
        f"{path.relative_to(root)}:{number}"
        for path in sorted(root.rglob("*.py"))
        for number, line in enumerate(path.read_text().splitlines(), 1)
        if any(ord(c) < 32 for c in line)
    ]
    assert not bad, bad

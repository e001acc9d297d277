#!/usr/bin/env python3
# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Print the import graph of the library as layers, its circles, and its module sizes.

    python3 scripts/import_layers.py [--check] [--max-lines 600] [--max-total 20600]

Reads the source with :mod:`ast` (nothing is imported, so no DOLFINx is needed). Every
import of a library module counts: at module level, inside functions, and under
``typing.TYPE_CHECKING``. A module's layer is 0 if it imports no library module, else
one more than the highest layer it imports, so in a graph without circles every import
runs from a higher layer to a lower one. A module's import of the packages it sits in
is not counted (Python runs them first in any case). With ``--check`` the exit status is
1 if there is a circle, an import from a layer up or sideways, a module longer than
``--max-lines`` or a library longer than ``--max-total`` lines. The total is also given
in lines of code (neither blank, nor comment, nor docstring).
"""

from __future__ import annotations

import argparse
import ast
import pathlib
import sys

PACKAGE = "dolfinx_contact_s2s"


def module_name(path: pathlib.Path, root: pathlib.Path) -> str:
    """Dotted module name of a file of the package (``pkg.sub`` for ``pkg/sub/__init__.py``)."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports(path: pathlib.Path, name: str, modules: set[str]) -> set[str]:
    """The library modules that the file at ``path`` (module ``name``) imports."""
    tree = ast.parse(path.read_text(), filename=str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(tree):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            # ``from pkg import sub`` imports the submodule ``pkg.sub``; ``pkg`` itself
            # counts only for a name that is not a submodule.
            subs = [f"{base}.{alias.name}" for alias in node.names]
            targets = subs + ([] if all(t in modules for t in subs) else [base])
        for target in targets:
            while target and target not in modules:
                target = target.rpartition(".")[0]
            # A module's own packages run before it anyway: no edge to them.
            if target and not (name == target or name.startswith(target + ".")):
                found.add(target)
    return found


def code_lines(path: pathlib.Path) -> int:
    """Lines that are neither blank, nor a comment, nor part of a docstring."""
    source = path.read_text()
    docstrings: set[int] = set()
    for node in ast.walk(ast.parse(source)):
        body = getattr(node, "body", None)
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            first = body[0] if body else None
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                if isinstance(first.value.value, str):
                    docstrings.update(range(first.lineno, (first.end_lineno or 0) + 1))
    return sum(
        1
        for number, line in enumerate(source.splitlines(), 1)
        if line.strip() and not line.strip().startswith("#") and number not in docstrings
    )


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components with more than one module (the circles)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return circles


def layers(graph: dict[str, set[str]], circles: list[list[str]]) -> dict[str, int]:
    """Layer of each module; the modules of a circle share one layer."""
    group = {m: tuple(c) for c in circles for m in c}
    layer: dict[str, int] = {}

    def of(m: str) -> int:
        if m not in layer:
            members = group.get(m, (m,))
            for x in members:
                layer[x] = 0  # a circle's own edges do not lift it
            deps = {d for x in members for d in graph[x]} - set(members)
            value = 1 + max((of(d) for d in deps), default=-1)
            for x in members:
                layer[x] = value
        return layer[m]

    for m in graph:
        of(m)
    return layer


def main() -> int:
    """Print the layers, circles and sizes; with ``--check``, fail on a violation."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--root", default=pathlib.Path(__file__).resolve().parents[1], type=pathlib.Path
    )
    parser.add_argument(
        "--check", action="store_true", help="exit 1 on a circle or a size over the limits"
    )
    parser.add_argument("--max-lines", type=int, default=600, help="longest module allowed")
    parser.add_argument("--max-total", type=int, default=20600, help="longest library allowed")
    args = parser.parse_args()
    root = args.root
    files = sorted((root / PACKAGE).rglob("*.py"))
    names = {module_name(f, root): f for f in files}
    modules = set(names)
    graph = {name: imports(path, name, modules) for name, path in names.items()}
    circles = strongly_connected(graph)
    layer = layers(graph, circles)
    lines = {name: len(path.read_text().splitlines()) for name, path in names.items()}

    short = {name: name.removeprefix(PACKAGE + ".") for name in names}
    code = sum(code_lines(path) for path in names.values())
    print(
        f"{PACKAGE}: {len(names)} modules, {sum(lines.values())} lines ({code} of code), "
        f"{max(layer.values()) + 1} layers"
    )
    for level in range(max(layer.values()), -1, -1):
        members = sorted(m for m in names if layer[m] == level)
        print(f"  layer {level:2d}: " + ", ".join(f"{short[m]} ({lines[m]})" for m in members))
    print("circles: " + ("; ".join(" <-> ".join(short[m] for m in c) for c in circles) or "none"))
    upward = sorted((short[a], short[b]) for a in graph for b in graph[a] if layer[b] >= layer[a])
    print(
        "imports from a layer up or sideways: "
        + (", ".join(f"{a} -> {b}" for a, b in upward) or "none")
    )
    largest = max(lines, key=lines.get)
    print(f"largest module: {short[largest]} ({lines[largest]} lines)")
    too_long = sorted(short[m] for m in lines if lines[m] > args.max_lines)
    if too_long:
        print(f"longer than {args.max_lines} lines: " + ", ".join(too_long))
    if sum(lines.values()) > args.max_total:
        print(f"longer than {args.max_total} lines in all: {sum(lines.values())}")
    failed = bool(circles or upward or too_long or sum(lines.values()) > args.max_total)
    return int(args.check and failed)


if __name__ == "__main__":
    sys.exit(main())

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Time and peak memory of the tied two-block scene against its size, direct or iterative.

The scene is the inf-sup model of Fig. 2 at any size: a lower block :math:`[0, 1]
\times [0, 0.5]` with :math:`10m \times 5m` bilinear quadrilaterals and an upper block
with :math:`7m \times 3.5m` (non-matching on the contact line), overlapping by
:math:`-g_0 = 0.01`, the lower one clamped at its bottom and the upper one at its top
(:func:`~paper.blocks.block_forms`, ``support="clamped"``),
composite segment-to-segment with the upper block as contactor. The meshes come from
:func:`dolfinx.mesh.create_rectangle` rather than Gmsh, so that a scene of millions of
cells is built in seconds and in little memory on every rank.

Each size is solved either by the package's default MUMPS LU (``"lu"``) or by the
Schur-complement field split of :mod:`dolfinx_contact_s2s.fieldsplit` (``"iterative"``).
Peak memory is ``ru_maxrss``, which only grows: measure each size in a process of its
own (``python3 -m paper.large --unknowns 1e6 --solver lu``).
"""

from __future__ import annotations

import argparse
import json
import resource
import time
import typing
from pathlib import Path

from mpi4py import MPI

import dolfinx
import numpy as np

from paper.blocks import block_problem
from paper.scenes import BOTTOM, LEFT, RIGHT, TOP, Body, PatchTestScene

__all__ = ["SOLVERS", "large_problem", "large_scene", "level_for", "run", "unknowns_of"]

#: The solvers compared.
SOLVERS = ("lu", "iterative")

_WIDTH, _HEIGHT, _GAP = 1.0, 0.5, -0.01


def unknowns_of(m: int) -> int:
    """Unknowns of Eq. (18) at level ``m`` (P1 displacements and multipliers)."""
    lower = (10 * m + 1) * (5 * m + 1)
    upper = (7 * m + 1) * (round(3.5 * m) + 1)
    return 2 * (lower + upper) + 7 * m + 1


def level_for(unknowns: float) -> int:
    """The smallest level ``m`` with at least ``unknowns`` unknowns."""
    m = 1
    while unknowns_of(m) < unknowns:
        m += 1
    return m


def _rectangle(
    comm: MPI.Comm, name: str, y0: float, elements: tuple[int, int], contact: int
) -> Body:
    mesh = dolfinx.mesh.create_rectangle(
        comm,
        [np.array([0.0, y0]), np.array([_WIDTH, y0 + _HEIGHT])],
        list(elements),
        cell_type=dolfinx.mesh.CellType.quadrilateral,
    )
    mesh.name = name
    tdim = mesh.topology.dim
    sides = {
        BOTTOM: lambda x: np.isclose(x[1], y0),
        RIGHT: lambda x: np.isclose(x[0], _WIDTH),
        TOP: lambda x: np.isclose(x[1], y0 + _HEIGHT),
        LEFT: lambda x: np.isclose(x[0], 0.0),
    }
    facets, values = [], []
    for tag, where in sides.items():
        found = dolfinx.mesh.locate_entities_boundary(mesh, tdim - 1, where)
        facets.append(found)
        values.append(np.full(found.size, tag, dtype=np.int32))
    f = np.concatenate(facets)
    order = np.argsort(f, kind="stable")
    facet_tags = dolfinx.mesh.meshtags(mesh, tdim - 1, f[order], np.concatenate(values)[order])
    ncells = mesh.topology.index_map(tdim).size_local
    cells = np.arange(ncells, dtype=np.int32)
    cell_tags = dolfinx.mesh.meshtags(mesh, tdim, cells, np.ones(ncells, dtype=np.int32))
    tags = {"bottom": BOTTOM, "right": RIGHT, "top": TOP, "left": LEFT}
    return Body(name, mesh, cell_tags, facet_tags, tags=tags, contact=contact)


def large_scene(comm: MPI.Comm, m: int) -> PatchTestScene:
    """The two blocks at level ``m`` (:func:`unknowns_of`), distributed over ``comm``."""
    if m < 1:
        raise ValueError("the level m must be at least 1")
    lower = _rectangle(comm, "lower", 0.0, (10 * m, 5 * m), TOP)
    upper = _rectangle(comm, "upper", _HEIGHT + _GAP, (7 * m, round(3.5 * m)), BOTTOM)
    return PatchTestScene(lower, upper, _WIDTH, _HEIGHT, _GAP)


def large_problem(comm: MPI.Comm, m: int, solver: str, *, prefix: str = "large_") -> typing.Any:
    """The tied problem of :func:`large_scene` with ``solver`` set up (not assembled)."""
    from dolfinx_contact_s2s.fieldsplit import iterative_options, use_schur_complement

    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}, not {solver!r}")
    scene = large_scene(comm, m)
    options = iterative_options(spaces=2) if solver == "iterative" else None
    problem = block_problem(
        scene,
        (1, 1),
        "upper",
        support="clamped",
        petsc_options_prefix=prefix,
        petsc_options=options,
        kind="nest" if solver == "iterative" else "aij",
        search_radius=abs(_GAP) + _WIDTH / (7 * m),
    )
    if solver == "iterative":
        use_schur_complement(problem)
    return problem


def _peak_mb(comm: MPI.Comm) -> float:
    """Peak resident memory summed over the ranks (MB; ``ru_maxrss`` is in kB on Linux)."""
    return comm.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, op=MPI.SUM) / 1024


def run(
    comm: MPI.Comm, unknowns: float, solver: str, log: typing.Callable[[str], None] | None = None
) -> dict[str, typing.Any]:
    """Build, assemble and solve the scene of about ``unknowns`` unknowns; a record.

    Returns:
        ``solver``, ``ranks``, ``level``, ``unknowns``, ``multipliers``, ``iterations``
        (outer Krylov; 1 for LU), ``residual``, seconds of each stage (``build``,
        ``stiffness``, ``contact``, ``system``, ``solve``, ``total``: slowest rank)
        and ``peak_rss_mb`` (summed over ranks), and ``peak_rss_mb_build`` (after
        building the meshes and spaces).
    """

    def say(text: str) -> None:
        if log is not None and comm.rank == 0:
            log(text)

    m = level_for(unknowns)
    say(f"[{solver}] level {m}: {unknowns_of(m)} unknowns expected; building")
    comm.Barrier()
    t0 = time.perf_counter()
    problem = large_problem(comm, m, solver)
    t_build = time.perf_counter() - t0
    peak_build = _peak_mb(comm)
    say(f"[{solver}] built in {t_build:.1f} s, peak {peak_build:.0f} MB; assembling and solving")
    try:
        problem.solve()
        comm.Barrier()
        total = time.perf_counter() - t0
        assert problem.A is not None
        record = {
            "solver": solver,
            "ranks": comm.size,
            "level": m,
            "unknowns": problem.A.getSize()[0],
            "multipliers": problem.pairs[0].Q.dofmap.index_map.size_global,
            "iterations": problem.solver.getIterationNumber() if solver == "iterative" else 1,
            "residual": problem.residual(),
            "build": comm.allreduce(t_build, op=MPI.MAX),
            **{k: comm.allreduce(v, op=MPI.MAX) for k, v in problem.timings.items()},
            "total": comm.allreduce(total, op=MPI.MAX),
            "peak_rss_mb_build": peak_build,
            "peak_rss_mb": _peak_mb(comm),
        }
    finally:
        problem.destroy()
    say(f"[{solver}] {json.dumps(record)}")
    return record


def main(argv: typing.Sequence[str] | None = None) -> None:
    """Command line: one size, one solver; appends the record to a JSON list."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--unknowns", type=float, required=True)
    parser.add_argument("--solver", choices=SOLVERS, default="iterative")
    parser.add_argument("--out", type=Path, default=None, help="JSON file to append to")
    args = parser.parse_args(argv)
    comm = MPI.COMM_WORLD
    record = run(comm, args.unknowns, args.solver, log=lambda s: print(s, flush=True))
    if args.out is not None and comm.rank == 0:
        old = json.loads(args.out.read_text()) if args.out.exists() else []
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps([*old, record], indent=1))


if __name__ == "__main__":
    main()

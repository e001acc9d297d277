# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""P1: coupling throughput against DOLFINx's own stiffness assembly, on the same bodies.

Two strips (two layers of quadrilaterals each) touch along a line carrying ``n``
contactor facets (the upper strip) and ``0.7 n`` target facets (the lower one). For
P1 and P2 displacements (and geometry of the same degree), at each ``n``:

- the coupling: the wall time of :func:`dolfinx_contact_s2s.assemble.assemble_coupling`
  (search, facet geometry, composite integration of Eq. 40 and insertion into PETSc),
  per sub-segment of the composite rule, for every kernel backend present: its first
  assembly on a new pair, which finds the blocks' CSR structure, and the best of the
  later ones, which reuse it (:class:`~dolfinx_contact_s2s.assemble.CooPattern`; all of
  the geometry, search and integration is done again);
- the stiffness: the wall time of :func:`dolfinx.fem.petsc.assemble_matrix` of the
  elasticity forms of both strips into their existing matrices, per cell, and the time
  of its first assembly, which creates the matrices (sparsity and preallocation).

The figure is the coupling's throughput (sub-segments per second) over the stiffness
assembly's (cells per second), both from this run: later assemblies against assembly
into the existing matrices (the headline), and first against first beside it. Issue
24's goal is >= 2 (a sub-segment costs at most half a cell) at every size from 1e3 to
1e6 contact facets. The headline ratio is the smallest over the degrees and sizes, with
the compiled backend when there is one.

Writes ``results/bench/p1_coupling.json`` and ``p1_coupling.png``.
"""

import argparse
from pathlib import Path

from mpi4py import MPI

import dolfinx
import dolfinx.fem.petsc
import numpy as np

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from paper.bench import (
    Progress,
    backend_name,
    backends,
    make_record,
    timed,
    write_record,
)
from paper.blocks import MATERIALS, NAMES, block_spaces
from paper.scenes import patch_test

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--sizes", type=int, nargs="+", help="contactor facets n")
parser.add_argument("--degrees", type=int, nargs="+", default=[1, 2])
parser.add_argument("--out", type=Path, default=Path("results/bench"))
args = parser.parse_args()
comm = MPI.COMM_WORLD
log = Progress(comm, "P1")
sizes = args.sizes or ([20, 40] if args.smoke else [1000, 10000, 100000, 1000000])
present = backends()
log(f"backends present: {present}; sizes {sizes}; degrees {args.degrees}")


def best(f, repeat):
    """The result of the fastest of ``repeat`` calls of ``f`` and its time."""
    keep, t_keep = None, np.inf
    for _ in range(repeat):
        result, seconds = timed(comm, f)
        if seconds < t_keep:
            result, keep, t_keep = keep, result, seconds
        for obj in result if isinstance(result, list) else [result]:
            if hasattr(obj, "destroy"):
                obj.destroy()
    return keep, t_keep


def surfaces_and_pair(scene, spaces, degree, backend):
    """The contact surfaces of both strips on ``backend`` and the S2S pair (upper on lower)."""
    surfaces = {
        b: contact_surface(
            spaces[b], scene.bodies[b].facet_tags, scene.bodies[b].contact, backend=backend
        )
        for b in NAMES
    }
    return surfaces, contact_pair(
        surfaces["upper"], surfaces["lower"], multiplier=("Lagrange", degree)
    )


def measure(degree, n):
    """The stiffness assembly and the coupling (every backend) of the strips of size ``n``."""
    # Best of many for both at the smallest size: one call takes about a millisecond, and
    # the best of 3 varied by 10% between runs (cache and clock of a shared machine).
    repeat = 30 if n <= 1000 else 5 if n <= 10000 else 2
    m = max(1, round(0.7 * n))
    with log.step(f"P{degree}, n = {n}: meshing two strips ({m} and {n} facets)"):
        scene = patch_test(
            comm,
            (m, n),
            cell="quadrilateral",
            geometry_degree=degree,
            height=2.0 / n,
            layers=(2, 2),
        )
        spaces = block_spaces(scene, (degree, degree))
    cells = sum(comm.allreduce(spaces[b].mesh.topology.index_map(2).size_local) for b in NAMES)
    forms = [dolfinx.fem.form(MATERIALS[b].forms(spaces[b])[0]) for b in NAMES]

    def create():
        """DOLFINx's assembly of both strips' stiffness, the matrices created (sparsity)."""
        out = []
        for a in forms:
            K = dolfinx.fem.petsc.assemble_matrix(a)
            K.assemble()
            out.append(K)
        return out

    def assemble():
        """DOLFINx's assembly into the existing matrices (what every new assembly costs)."""
        for K, a in zip(Ks, forms, strict=True):
            K.zeroEntries()
            dolfinx.fem.petsc.assemble_matrix(K, a)
            K.assemble()

    Ks, t_create = best(create, 1)
    _, t_stiffness = best(assemble, repeat)
    for K in Ks:
        K.destroy()
    row = {
        "degree": degree,
        "n": n,
        "target_facets": m,
        "cells": cells,
        "stiffness_seconds": t_stiffness,
        "cells_per_second": cells / t_stiffness,
        "stiffness_with_creation_seconds": t_create,
        "backends": {},
    }
    log(
        f"  stiffness: {cells} cells in {t_stiffness:.3f} s ({cells / t_stiffness:.3g}/s); "
        f"{t_create:.3f} s with the matrix's creation"
    )
    for name in present:
        (surfaces, pair), t_setup = timed(
            comm, lambda name=name: surfaces_and_pair(scene, spaces, degree, name)
        )
        # The sub-segments (groups of the pair's blocks), counted outside the timing.
        segments = comm.allreduce(sum(b.rows.shape[0] for b in pair.coupling_blocks()))
        op, t_first = best(lambda pair=pair: assemble_coupling(pair), 1)
        op.destroy()
        op, t_coupling = best(lambda pair=pair: assemble_coupling(pair), repeat)
        op.destroy()
        entry = {
            "ran": backend_name(surfaces["upper"]),
            "setup_seconds": t_setup,
            "coupling_seconds": t_coupling,
            "coupling_first_seconds": t_first,
            "sub_segments": segments,
            "sub_segments_per_second": segments / t_coupling,
            "ratio": (segments / t_coupling) / (cells / t_stiffness),
            "ratio_with_creation": (segments / t_first) / (cells / t_create),
        }
        row["backends"][name] = entry
        log(
            f"  coupling [{name}]: {segments} sub-segments in {t_coupling:.3f} s "
            f"({segments / t_coupling:.3g}/s): ratio {entry['ratio']:.3f}, first assembly "
            f"{t_first:.3f} s ({entry['ratio_with_creation']:.3f} against the first stiffness) "
            f"(surfaces and pair set up in {t_setup:.2f} s)"
        )
    return row


rows = [measure(degree, n) for degree in args.degrees for n in sizes]

headline = present[-1]
ratios = [r["backends"][headline]["ratio"] for r in rows]
ratio = min(ratios)
worst = rows[int(np.argmin(ratios))]
speedups = {}
if len(present) > 1:
    speedups = {
        f"P{r['degree']} n={r['n']}": r["backends"]["numpy"]["coupling_seconds"]
        / r["backends"][headline]["coupling_seconds"]
        for r in rows
    }
record = make_record(
    "p1_coupling",
    comm,
    figure="P1",
    title="coupling throughput (sub-segments/s) over DOLFINx stiffness assembly (cells/s)",
    backend=headline,
    times={
        "coupling_seconds": worst["backends"][headline]["coupling_seconds"],
        "stiffness_seconds": worst["stiffness_seconds"],
    },
    ratio=ratio,
    smoke=args.smoke,
    ratio_definition=(
        "min over degree and n of (sub_segments / t_assemble_coupling, best of the "
        "assemblies after the first) / (cells / t_assemble_matrix into the existing "
        "matrices)"
    ),
    backends_present=present,
    worst_case={"degree": worst["degree"], "n": worst["n"]},
    rows=rows,
    backend_speedup_over_numpy=speedups,
)
write_record(args.out, record, comm)
log(f"P1 = {ratio:.3f} (goal >= 2) at P{worst['degree']}, n = {worst['n']} [{headline}]")

if comm.rank == 0:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
    for k, degree in enumerate(args.degrees):
        colour = f"C{k}"
        sel = [r for r in rows if r["degree"] == degree]
        ns = [r["n"] for r in sel]
        ax.loglog(
            ns,
            [r["cells_per_second"] for r in sel],
            "s--",
            color=colour,
            label=f"P{degree} stiffness (cells/s)",
        )
        for j, name in enumerate(present):
            style = ["o-", "^-", "v-"][j % 3]
            ax.loglog(
                ns,
                [r["backends"][name]["sub_segments_per_second"] for r in sel],
                style,
                color=colour,
                label=f"P{degree} coupling [{name}] (sub-segments/s)",
            )
            bx.semilogx(
                ns,
                [r["backends"][name]["ratio"] for r in sel],
                style,
                color=colour,
                label=f"P{degree} [{name}]",
            )
    ax.set_xlabel("contactor facets n")
    ax.set_ylabel("per second (cells or sub-segments)")
    ax.legend(fontsize=7)
    bx.axhline(2.0, color="k", lw=0.8, ls=":", label="goal")
    bx.set_xlabel("contactor facets n")
    bx.set_ylabel("coupling / stiffness throughput")
    bx.legend(fontsize=7)
    fig.suptitle(f"P1 coupling throughput, {comm.size} rank(s)")
    fig.tight_layout()
    suffix = f"_np{comm.size}" if comm.size > 1 else ""
    fig.savefig(args.out / f"p1_coupling{suffix}.png", dpi=120)

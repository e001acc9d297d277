# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""P9-P11: three-dimensional contact (issue 21): coupling throughput, share, field split.

- P9 (``p9_coupling_3d``): the blocks of :mod:`paper.blocks3d` (hexahedra below,
  tetrahedra above, non-matching, two layers each), P1 and P2. The coupling's
  throughput, overlap polygons (contactor face, target face) per second of
  :func:`~dolfinx_contact_s2s.assemble.assemble_coupling` (search, clipping,
  triangulation, pull-back, Eqs. 40-42 and insertion), over DOLFINx's assembly of both
  blocks' K into their existing matrices (cells per second), both from this run, for
  every kernel backend; the headline is the smallest over degrees with the compiled
  backend. Goal >= 0.5.
- P10 (``p10_share_3d``): the blocks held at the top (:mod:`paper.bench3d`, hexahedra
  ``n`` against ``1.2 n``) solved as *unilateral* contact by the active-set method,
  every linear solve by the Schur field split with GAMG, at about 1 million unknowns;
  the contact-specific time (the contact surfaces and pair, ``timings["contact"]``
  and the active-set updates) over the whole (pair, problem, solve). Goal <= 10%.
- P11 (``p11_fieldsplit_3d``): the same blocks *tied*, at several sizes up to at least
  2 million unknowns, each in a process of its own: GMRES iterations, times, peak memory
  and the errors of the patch test (pressure and displacement against uniaxial stress).
  The figure is the largest run's peak memory over 16 GB (goal <= 1).

Writes ``results/bench/p9_coupling_3d.json``, ``p10_share_3d.json``,
``p11_fieldsplit_3d.json`` and ``p9_p11_3d.png``.
"""

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--parts", nargs="+", default=["p9", "p10", "p11"])
parser.add_argument("--coupling-cells", type=int, nargs=2, help="P9 cells across (P1; P2 half)")
parser.add_argument("--share-unknowns", type=float, default=1e6, help="P10 size")
parser.add_argument(
    "--fieldsplit-unknowns", type=float, nargs="+", default=[1e4, 1e5, 5e5, 2e6], help="P11"
)
parser.add_argument("--out", type=Path, default=Path("results/bench"))
parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
parser.add_argument("--level", type=int, help=argparse.SUPPRESS)
parser.add_argument("--unilateral", action="store_true", help=argparse.SUPPRESS)
args = parser.parse_args()

if args.child is not None:
    # One solve in this process, so that its peak memory is its own.
    from mpi4py import MPI

    from paper.bench import Progress
    from paper.bench3d import solve_level

    comm = MPI.COMM_WORLD
    run = solve_level(
        comm, args.level, unilateral=args.unilateral, log=Progress(comm, "P10/P11 child")
    )
    if comm.rank == 0:
        args.child.write_text(json.dumps(run))
    sys.exit(0)

from mpi4py import MPI  # noqa: E402

import dolfinx  # noqa: E402
import dolfinx.fem.petsc  # noqa: E402
import numpy as np  # noqa: E402

from dolfinx_contact_s2s import contact_pair, contact_surface  # noqa: E402
from dolfinx_contact_s2s.assemble import assemble_coupling  # noqa: E402
from paper.bench import (  # noqa: E402
    Progress,
    backend_name,
    backends,
    make_record,
    timed,
    write_record,
)
from paper.bench3d import UNILATERAL_TOLERANCE, level_for, unknowns_of  # noqa: E402
from paper.blocks3d import BOTTOM, TOP, scene  # noqa: E402

comm = MPI.COMM_WORLD
log = Progress(comm, "P9-P11")
LIMIT_MB = 16 * 1024


def best(f, repeat):
    """The fastest of ``repeat`` calls of ``f`` (its result destroyed) and its time."""
    t_best = np.inf
    for _ in range(repeat):
        result, seconds = timed(comm, f)
        t_best = min(t_best, seconds)
        for obj in result if isinstance(result, list) else [result]:
            if hasattr(obj, "destroy"):
                obj.destroy()
    return t_best


def coupling_row(degree, cells, present):
    """K's assembly and the coupling (every backend) of the 3D blocks."""
    repeat = 3
    with log.step(f"P{degree}, {cells} cells across: the blocks"):
        ((V_lo, t_lo), (V_up, t_up)), a, _, _ = scene("hex", "tet", degree, seed=1, cells=cells)
    forms = [dolfinx.fem.form(f) for f in a]
    Ks = [dolfinx.fem.petsc.assemble_matrix(f) for f in forms]

    def assemble():
        for K, f in zip(Ks, forms, strict=True):
            K.zeroEntries()
            dolfinx.fem.petsc.assemble_matrix(K, f)
            K.assemble()

    t_stiffness = best(assemble, repeat)
    for K in Ks:
        K.destroy()
    n_cells = sum(V.mesh.topology.index_map(3).size_global for V in (V_lo, V_up))
    row = {
        "degree": degree,
        "cells_across": list(cells),
        "cells": n_cells,
        "stiffness_seconds": t_stiffness,
        "cells_per_second": n_cells / t_stiffness,
        "backends": {},
    }
    log(f"  K: {n_cells} cells in {t_stiffness:.3f} s ({n_cells / t_stiffness:.3g}/s)")
    for name in present:
        upper = contact_surface(V_up, t_up, BOTTOM, backend=name)
        pair = contact_pair(upper, contact_surface(V_lo, t_lo, TOP, backend=name))
        assemble_coupling(pair).destroy()  # once: the multiplier space's integrals
        t_coupling = best(lambda pair=pair: assemble_coupling(pair), repeat)
        pieces = pair.sub_segments(0)
        polygons = np.unique(np.stack([pieces.contactor, pieces.target]), axis=1).shape[1]
        polygons = comm.allreduce(polygons)
        triangles = comm.allreduce(len(pieces))
        rate = polygons / t_coupling
        row["backends"][name] = {
            "ran": backend_name(upper),
            "coupling_seconds": t_coupling,
            "polygons": polygons,
            "triangles": triangles,
            "polygons_per_second": rate,
            "ratio": rate / row["cells_per_second"],
        }
        log(
            f"  coupling [{name}]: {polygons} polygons ({triangles} triangles) in "
            f"{t_coupling:.3f} s ({rate:.3g}/s): ratio {rate / row['cells_per_second']:.3f}"
        )
    return row


def p9():
    """P9: the coupling's throughput against K's, P1 and P2."""
    present = backends()
    n = args.coupling_cells or ((3, 4) if args.smoke else (40, 54))
    rows = [coupling_row(1, tuple(n), present)]
    rows.append(coupling_row(2, tuple(max(2, k // 2) for k in n), present))
    headline = present[-1]
    ratios = [r["backends"][headline]["ratio"] for r in rows]
    worst = rows[int(np.argmin(ratios))]
    record = make_record(
        "p9_coupling_3d",
        comm,
        figure="P9",
        title="3D coupling throughput (overlap polygons/s) over DOLFINx's K assembly (cells/s)",
        backend=headline,
        times={
            "coupling_seconds": worst["backends"][headline]["coupling_seconds"],
            "stiffness_seconds": worst["stiffness_seconds"],
        },
        ratio=min(ratios),
        smoke=args.smoke,
        ratio_definition=(
            "min over P1, P2 of (overlap polygons / t_assemble_coupling) / "
            "(cells / t_assemble_matrix into the existing matrices), 3D blocks hex below, "
            "tet above"
        ),
        backends_present=present,
        worst_case={"degree": worst["degree"]},
        rows=rows,
    )
    write_record(args.out, record, comm)
    log(f"P9 = {min(ratios):.3f} (goal >= 0.5) at P{worst['degree']} [{headline}]")
    return record


def child(level, unilateral, tmp):
    """:func:`paper.bench3d.solve_level` in a process of its own; its record or None."""
    path = Path(tmp) / f"{'u' if unilateral else 't'}{level}.json"
    command = [sys.executable, __file__, "--child", str(path), "--level", str(level)]
    command += ["--unilateral"] if unilateral else []
    done = subprocess.run(command, check=False)
    if done.returncode != 0:
        log(f"  level {level} failed (exit {done.returncode})")
        return None
    return json.loads(path.read_text())


def p10(tmp):
    """P10: the contact share of the unilateral solve at about 1 million unknowns."""
    level = 8 if args.smoke else level_for(args.share_unknowns)
    log(f"P10: unilateral, level {level}, about {unknowns_of(level)} unknowns")
    run = child(level, True, tmp)
    if run is None:
        return None
    t = run["times"]
    contact = t["pair"] + t["stages"]["contact"] + t["update"]
    whole = t["pair"] + t["problem"] + t["solve"]
    share = contact / whole
    record = make_record(
        "p10_share_3d",
        comm,
        figure="P10",
        title="contact-specific time as a share of a 3D unilateral solve (field split, GAMG)",
        backend=run["backend"],
        times={"contact_seconds": contact, "whole_seconds": whole, **t},
        ratio=share,
        smoke=args.smoke,
        ratio_definition=(
            "(pair set-up + timings['contact'] + active-set updates) / (pair + problem + "
            "solve), the held 3D blocks, active set, every solve GMRES with the Schur "
            "field split and GAMG"
        ),
        peak=run["peak_memory"],
        run=run,
        complementarity_tolerance=UNILATERAL_TOLERANCE,
    )
    write_record(args.out, record, comm)
    log(f"P10 = {share:.2%} (goal <= 10%), {run['unknowns']} unknowns")
    return record


def p11(tmp):
    """P11: the tied blocks by the Schur field split at sizes up to >= 2 million unknowns."""
    levels = [4, 8] if args.smoke else [level_for(u) for u in args.fieldsplit_unknowns]
    runs = []
    for level in levels:
        log(f"P11: tied, level {level}, about {unknowns_of(level)} unknowns")
        run = child(level, False, tmp)
        if run is None:
            break
        runs.append(run)
    if not runs:
        return None
    largest = runs[-1]
    ratio = largest["peak_memory"]["max_mb"] / LIMIT_MB
    record = make_record(
        "p11_fieldsplit_3d",
        comm,
        figure="P11",
        title="tied 3D blocks by the Schur field split with GAMG: peak memory over 16 GB",
        backend=largest["backend"],
        times={
            "largest_solve_seconds": largest["times"]["solve"],
            "largest_pipeline_seconds": sum(
                largest["times"][k] for k in ("forms", "pair", "problem", "solve")
            ),
        },
        ratio=ratio,
        smoke=args.smoke,
        ratio_definition="peak resident memory of the largest run / 16 GB",
        peak=largest["peak_memory"],
        runs=runs,
        largest_unknowns=largest["unknowns"],
        sizes_met=largest["unknowns"] >= 2_000_000,
    )
    write_record(args.out, record, comm)
    for run in runs:
        log(
            f"  {run['unknowns']:>9} unknowns: {run['iterations']} iterations, "
            f"{run['times']['solve']:.1f} s, {run['peak_memory']['max_mb']:.0f} MB, errors "
            f"{run['error_pressure']:.1e} / {run['error_displacement']:.1e}"
        )
    return record


records = {}
if "p9" in args.parts:
    records["p9"] = p9()
with tempfile.TemporaryDirectory() as tmp:
    if "p10" in args.parts:
        records["p10"] = p10(tmp)
    if "p11" in args.parts:
        records["p11"] = p11(tmp)

if comm.rank == 0 and records.get("p9") and records.get("p11"):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
    rows = records["p9"]["rows"]
    for j, name in enumerate(records["p9"]["backends_present"]):
        ax.bar(
            [k + 0.35 * j for k in range(len(rows))],
            [r["backends"][name]["ratio"] for r in rows],
            width=0.35,
            label=name,
        )
    ax.axhline(0.5, color="k", ls=":", lw=0.8, label="goal")
    ax.set_xticks(range(len(rows)), [f"P{r['degree']}" for r in rows])
    ax.set_yscale("log")
    ax.set_ylabel("polygons/s over cells/s")
    ax.set_title("P9 coupling throughput")
    ax.legend(fontsize=7)
    runs = records["p11"]["runs"]
    x = [r["unknowns"] for r in runs]
    bx.semilogx(x, [r["iterations"] for r in runs], "o-", label="GMRES iterations")
    cx = bx.twinx()
    cx.semilogx(x, [r["peak_memory"]["max_mb"] / 1024 for r in runs], "s--", color="C1")
    cx.set_ylabel("peak GB", color="C1")
    bx.set_xlabel("unknowns")
    bx.set_ylabel("iterations")
    bx.set_title("P11 Schur field split, GAMG")
    fig.tight_layout()
    fig.savefig(args.out / "p9_p11_3d.png", dpi=120)

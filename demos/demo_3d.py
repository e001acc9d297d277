# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Three dimensions: the patch test and the inf-sup test on faces
#
# The paper leaves its segment-to-segment algorithm in 3D to future work. Its
# generalization here: each contactor face and each target face that faces it are drawn
# in the contactor face's plane, the overlap of their corner polygons is clipped and cut
# into triangles, and a Gauss rule of the triangle placed on each is pulled back to both
# faces (Eq. 38 along the contactor normal): the composite rule of Fig. 15(b), with
# polygons for intervals. The multiplier is continuous on the contactor's faces, of the
# displacement's degree (or lower).
#
# Two blocks meshed apart (tetrahedra and hexahedra, 3 and 4 cells across), pressed by a
# uniform pressure $p$: the exact solution is uniaxial stress and the contact pressure is
# $p$ (Eq. 36). Composite S2S must transmit it to round-off on every combination of cells,
# degrees and contactors, on structured meshes and with the nodes of the contact plane
# moved; a bilinear face that is not a parallelogram cannot be integrated exactly by any
# rule on the triangles of the overlaps, and its error is measured, not hidden. The
# inf-sup value $\beta^*_h$ of Eq. (27) (MUMPS's Schur complement on the multipliers)
# must stay away from zero as the mesh is refined.
#
# Outputs (in `--out`, default `results/`): `contact_3d.json` (records per rank count),
# `infsup_3d.png` and the `three_d` section of `report.md`. Run it as
# `python3 demos/demo_3d.py` or with `mpirun -n 2`; `--smoke` runs fewer levels.

# +
import itertools
import time

from mpi4py import MPI

import numpy as np

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.analysis.infsup import inf_sup
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.blocks3d import BOTTOM, TOP, errors, scene
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, write_section

args = demo_parser("3D contact: patch test and inf-sup test", "fewer levels").parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
records = []


def solve(cells, degree, *, contactor="upper", seed=None, warp=False, unilateral=False, **pair):
    """One patch test: errors of the pressure and of the displacement, unknowns, seconds."""
    start = time.perf_counter()
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, seed, warp=warp)
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    surfaces = (upper, lower) if contactor == "upper" else (lower, upper)
    kind = UnilateralContactProblem if unilateral else LinearContactProblem
    contact = contact_pair(*surfaces, **pair)
    with kind(a, L, [contact], bcs, petsc_options_prefix="d3_") as p:
        us, (pressure,) = p.solve()
        p_error, u_error = errors(us, pressure)
        unknowns = sum(u.function_space.dofmap.index_map.size_global * 3 for u in us)
    return {
        "study": "patch",
        "ranks": comm.size,
        "cells": "/".join(cells),
        "degree": degree,
        "contactor": contactor,
        "mesh": "warped" if warp else "moved" if seed is not None else "structured",
        "problem": "unilateral" if unilateral else "tied",
        "multiplier": pair.get("multiplier", ("Lagrange", degree))[1],
        "pressure_error": p_error,
        "displacement_error": u_error,
        "unknowns": int(unknowns),
        "rule_degree": contact.rule_degree,
        "seconds": time.perf_counter() - start,
    }


# -

# ## The patch test

# +
CELLS = [("hex", "tet"), ("tet", "hex"), ("tet", "tet"), ("hex", "hex")]
for cells, degree, contactor, seed in itertools.product(
    CELLS, (1, 2), ("upper", "lower"), (None, 1)
):
    rec = solve(cells, degree, contactor=contactor, seed=seed)
    records.append(rec)
    log(
        f"tied {rec['cells']} P{degree} contactor {contactor:5s} {rec['mesh']:10s}: "
        f"pressure {rec['pressure_error']:.1e}, displacement {rec['displacement_error']:.1e}"
    )
    if max(rec["pressure_error"], rec["displacement_error"]) > 1e-10:
        raise SystemExit(f"the 3D patch test failed: {rec}")
for cells, degree, multiplier in (
    (("hex", "tet"), 1, 1),
    (("tet", "hex"), 2, 2),
    (("hex", "tet"), 2, 1),
):
    rec = solve(cells, degree, seed=2, unilateral=True, multiplier=("Lagrange", multiplier))
    records.append(rec)
    log(
        f"unilateral {rec['cells']} P{degree}, multiplier P{multiplier}: pressure "
        f"{rec['pressure_error']:.1e}, displacement {rec['displacement_error']:.1e}"
    )
    if max(rec["pressure_error"], rec["displacement_error"]) > 1e-10:
        raise SystemExit(f"the unilateral 3D patch test failed: {rec}")
# Faces that are not parallelograms: rational inverse maps, the rule raised until exact.
for cells, degree in itertools.product((("hex", "tet"), ("tet", "hex"), ("hex", "hex")), (1, 2)):
    rec = solve(cells, degree, seed=1, warp=True)
    records.append(rec)
    log(
        f"tied {rec['cells']} P{degree}, Q{degree} faces warped (rule of degree "
        f"{rec['rule_degree']}): pressure {rec['pressure_error']:.1e}, displacement "
        f"{rec['displacement_error']:.1e}"
    )
    if max(rec["pressure_error"], rec["displacement_error"]) > 1e-10:
        raise SystemExit(f"the 3D patch test on warped faces failed: {rec}")
# -

# ## The inf-sup test
#
# Levels of $n$ (upper block, the contactor) and $n + 1$ (lower) cells across, $n/2$
# layers deep, so that the cells keep their shape.

# +
LEVELS = (2, 4) if args.smoke else (2, 4, 6, 8, 10)
CASES = [(("hex", "tet"), 1), (("tet", "hex"), 1), (("hex", "tet"), 2)]
curves = {}
for cells, degree in CASES:
    betas = []
    for n in LEVELS:
        ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(*cells, degree, None, (n + 1, n), n // 2)
        pair = contact_pair(contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP))
        with LinearContactProblem(a, L, [pair], bcs, petsc_options_prefix="d3is_") as problem:
            result = inf_sup(problem, 1.0 / n)
        betas.append(result.beta)
        records.append(
            {
                "study": "infsup",
                "ranks": comm.size,
                "cells": "/".join(cells),
                "degree": degree,
                "n": n,
                "beta": result.beta,
                "pressure_modes": result.pressure_modes,
            }
        )
        log(f"inf-sup {'/'.join(cells)} P{degree} n = {n:2d}: beta* = {result.beta:.4f}")
    fine = slice(-3, None)  # the last three levels (both of a smoke run)
    slope = np.polyfit(np.log(1.0 / np.array(LEVELS[fine])), np.log(betas[fine]), 1)[0]
    curves[f"{'/'.join(cells)} P{degree}"] = (LEVELS, betas, slope)
    log(f"inf-sup {'/'.join(cells)} P{degree}: slope {slope:.3f} over the finer levels")
# -

# ## Records, figure and report

# +
if comm.rank == 0:
    merge_rank_records(out / "contact_3d.json", records, comm.size)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3.6))
    for name, (levels, betas, slope) in curves.items():
        ax.loglog(1.0 / np.array(levels), betas, "o-", label=f"{name} (slope {slope:.2f})")
    ax.set_xlabel("h (upper block)")
    ax.set_ylabel("beta*_h (Eq. 27)")
    ax.set_title("3D composite S2S: inf-sup test")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "infsup_3d.png", dpi=120)

    patch = [r for r in records if r["study"] == "patch"]
    exact = patch
    lines = [
        "## Three dimensions",
        "",
        f"`demos/demo_3d.py`, {comm.size} rank(s). The patch test between non-matching "
        f"blocks: {len(exact)} cases (tetrahedra/hexahedra, P1/P2, either contactor, "
        "structured, with the contact plane's nodes moved, and hexahedra moved at random "
        "(warped faces), tied and unilateral), "
        "largest pressure error "
        f"{max(r['pressure_error'] for r in exact):.1e}, displacement error "
        f"{max(r['displacement_error'] for r in exact):.1e} (both against 1).",
        "",
        "| case | pressure error | displacement error | unknowns | face rule degree |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in patch:
        if r["mesh"] == "warped" or r["problem"] == "unilateral":
            lines.append(
                f"| {r['problem']} {r['cells']} P{r['degree']} (multiplier "
                f"P{r['multiplier']}), {r['mesh']} | {r['pressure_error']:.1e} | "
                f"{r['displacement_error']:.1e} | {r['unknowns']} | {r['rule_degree']} |"
            )
    lines += [
        "",
        "Warped faces (not parallelograms) have rational inverse maps: the pair raises the "
        "rule on the triangles of the overlaps until the faces' own shape-function "
        "integrals are exact to round-off (`contact_rule.face_rule`); affine faces keep "
        "the polynomial degree.",
        "",
        "| inf-sup | " + " | ".join(f"n = {n}" for n in LEVELS) + " | slope |",
        "|---|" + "---:|" * (len(LEVELS) + 1),
    ]
    for name, (_, betas, slope) in curves.items():
        lines.append(f"| {name} | " + " | ".join(f"{b:.4f}" for b in betas) + f" | {slope:.3f} |")
    lines += ["", "![inf-sup 3D](infsup_3d.png)"]
    write_section(out / "report.md", "three_d", lines)
# -

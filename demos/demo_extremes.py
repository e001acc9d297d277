# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # The patch test at numerical extremes
#
# The contact patch test (El-Abbasi & Bathe 2001, section 3.2) has an exact solution,
# a uniform stress, that every element used here represents exactly: whatever a
# discretization passing it computes beyond round-off is a defect. This demo pushes the
# README's two blocks to the extremes a user may meet, and asks at each point whether
# the answer is right *to the accuracy the conditioning allows*:
#
# - Young's modulus ratio between the bodies $10^{-6}$ to $10^{6}$, Poisson's ratio up
#   to 0.4999, element-size ratio up to 1:64 across the interface;
# - the scene scaled by $10^{\pm 6}$ and translated by $10^6$;
# - initial gaps and overlaps from $10^{-14}$ to the element size $h$, tied (the gap
#   closes, the pressure stays uniform) and unilateral (contact);
# - interface nodes $10^{-11}h$ to $10^{-13}h$ apart, with segment-to-segment and the
#   two-pass node-to-segment method;
# - surfaces that cover each other in part, and a curved (quadratic) interface under a
#   hydrostatic load ($\lambda = p$ on any interface shape).
#
# The tolerance of each point is the round-off bound of its own solve
# (`dolfinx_contact_s2s.analysis.roundoff.round_off_bound`): the Oettli-Prager backward error
# times Higham's estimate of $\| |\mathbf A^{-1}| (|\mathbf A||\mathbf x| + |\mathbf b|)
# \|_\infty$ restricted to the displacements or to the multipliers. A point passes when
# both errors, against the closed form, are within it. The scenes are built as the
# README builds its example (one Gmsh model, the user's forms);
# `paper.extremes` holds the grid.
#
# It writes `results/extremes.json` (records of every rank count side by side),
# `results/extremes.png` and the section "extremes" of `results/report.md`. Run it as
# `python3 demos/demo_extremes.py` or `mpirun -n 2 python3 demos/demo_extremes.py`;
# `--smoke` runs a few points.

# +
import time

from mpi4py import MPI

from paper.extremes import grid, record_lines, run_point
from paper.records import merge_rank_records
from paper.report import (
    demo_parser,
    output_folder,
    rank0_print,
    write_section,
)

args = demo_parser("The patch test at numerical extremes", "a few points only").parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)


# -

# ## The grid

# +
points = grid()
if args.smoke:
    wanted = ("reference", "E ratio 1e+06", "translation (1e6, 1e6) P", "near nodes S2S 1e-13")
    points = [p for p in points if any(p.name.startswith(w) for w in wanted)]
records = []
start = time.perf_counter()
for k, point in enumerate(points, 1):
    prefix = f"extremes_{k}_"
    rec = run_point(point, comm, prefix=prefix)
    records.append(rec)
    if rec["exception"] is not None:
        status = ("raises as expected: " if rec["passed"] else "FAIL, raises: ") + rec["exception"]
    else:
        lam = rec["multiplier_error"]
        status = (
            f"u {rec['displacement_error']:.1e} <= {rec['displacement_bound']:.1e}, "
            + ("lambda -" if lam is None else f"lambda {lam:.1e} <= {rec['multiplier_bound']:.1e}")
            + f", cond {rec['condition']:.1e}: {'pass' if rec['passed'] else 'FAIL'}"
        )
    log(f"[{k:2d}/{len(points)}] {point.name:44s} {status} ({time.perf_counter() - start:.0f} s)")
failed = [r["name"] for r in records if not r["passed"]]
log(f"{len(records) - len(failed)} of {len(records)} points pass on {comm.size} rank(s)")
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "extremes.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    solved = [r for r in merged if r["exception"] is None]
    for key, marker, label in (
        ("displacement", "o", "displacements"),
        ("multiplier", "s", "multipliers"),
    ):
        rs = [r for r in solved if r[f"{key}_error"] is not None]
        ax.loglog(
            [r[f"{key}_bound"] for r in rs],
            [max(r[f"{key}_error"], 1e-30) for r in rs],
            marker,
            fillstyle="none",
            label=label,
        )
    lo = min(r["displacement_bound"] for r in solved)
    hi = max(max(r["displacement_bound"], r["multiplier_bound"] or 0) for r in solved)
    ax.loglog([lo, hi], [lo, hi], "k-", lw=0.8, label="error = bound")
    ax.set_xlabel("round-off bound of the solve")
    ax.set_ylabel("measured error (closed form)")
    ax.set_title("Patch test at the extremes: every point below the diagonal")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "extremes.png", dpi=120)

    passed = sum(r["passed"] for r in merged)
    section = [
        "## The patch test at numerical extremes",
        "",
        "`demos/demo_extremes.py`: the README's two blocks (13/9 elements, E = 1/3, "
        "nu = 0.3/0.2 unless the point says otherwise) at each extreme; the errors are "
        "max |u - u_exact| and max |lambda - lambda_exact| against the closed form, the "
        "bounds those of `round_off_bound` for the same solve (Oettli-Prager backward "
        "error times Higham's 1-norm estimate), cond the equilibrated 1-norm condition "
        "number. Two-pass node-to-segment splits the force between its passes: only its "
        "displacements are compared. Curved interfaces only with P2 (P1 on quadratic "
        "cells does not hold linear fields).",
        "",
        f"{passed} of {len(merged)} records pass; ![errors against bounds](extremes.png)",
        "",
        *record_lines(merged),
    ]
    write_section(out / "report.md", "extremes", section)
# -

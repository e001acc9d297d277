# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Finite deformation and large sliding: the patch test and ironing
#
# `NonlinearContactProblem` (in `dolfinx_contact_s2s.finite`) runs Newton's method on the
# user's residual forms with the contact surfaces placed at $X + u$ in every iteration:
# the coupling of Eq. (40) and the gap rebuilt on the current configuration, and Newton's
# matrix holding the change of the contact terms with $u$.
#
# **Large-sliding patch test** (`paper.large_sliding.sliding_patch`): a neo-Hookean block
# pressed by $P = 0.2$ onto a wider one and slid over it by 8 of the lower block's
# elements (5.5 of its own contact elements), one element per step, frictionless; the
# lateral sides held in $x$, so every state is homogeneous and the contact pressure is
# $P$. Node-to-segment on the same meshes.
#
# **Ironing** (after Yang, Laursen and Meng 2005; `paper.large_sliding.ironing`): a
# neo-Hookean block 9 x 3 ($E = 1$, $\nu = 0.3$) ironed by a stiff half-ring die (outer
# radius 3, inner 2.8, $E = 1000$): pressed down by 1.4 in 14 steps, then slid by 4 in
# 160 steps, frictionless, P1 triangles of size $h = 0.6, 0.3, 0.15$ in one Gmsh model;
# composite segment-to-segment and node-to-segment on the same meshes, with the multiplier
# on the block's top (the die's arc the target) and on the die's arc. The force on the die's
# held top ends at every step; its vertical component's oscillation over the steady
# slide ($1 \le s \le 3$): the range of its deviation from a least-squares quadratic in
# $s$, over its mean (the raw range over the mean is reported too).
#
# Checked: the patch test's pressure and displacement within $10^{-9}$ at every slide
# (segment-to-segment), node-to-segment off by more than $10^{-4}$; Newton's measured
# order above 1.8 (`NewtonStep.orders`: settled iterations) on every slide step of the P1
# and P2 patch tests; every ironing step converged. And Newton's local order from starts
# at known distances (`paper.large_sliding.newton_order_probe`: the last state of each
# run perturbed by 1e-3, 1e-4, 1e-5 of its largest displacement along one fixed field,
# 1e-4 to 1e-6 on ironing's stiff die; the slope of the residual after one Newton
# iteration with the full tangent against the one before, in a settled active set)
# above 1.8 for the patch tests and every segment-to-segment ironing. The ironing
# oscillations are reported, not asserted. The exit status is non-zero if a check fails. It writes
# `results/large_sliding.json`, `results/ironing.png` and the section "large-sliding" of
# `results/report.md`. Run it as
# `python3 demos/demo_large_sliding.py` or with `mpirun -n 2`; `--smoke` runs P1 only and
# the ironing at $h = 0.6$ with 20 slide steps.

# +
import itertools

from mpi4py import MPI

import numpy as np

from paper.large_sliding import IRONING, ironing, sliding_patch
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, verdict, write_section

args = demo_parser(
    "Finite deformation: the large-sliding patch test and ironing",
    "P1 only, the ironing at h = 0.6 with 20 slide steps",
).parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
DEGREES = (1,) if args.smoke else (1, 2)
SIZES = (0.6,) if args.smoke else (0.6, 0.3, 0.15)
SLIDES = 20 if args.smoke else 160
failed: list[str] = []
records: list[dict] = []
# -

# ## The large-sliding patch test

# +
for degree in DEGREES:
    for method in ("segment-to-segment", "node-to-segment"):
        rec = sliding_patch(degree, method, comm=comm)
        rec["ranks"] = comm.size
        records.append(rec)
        worst = max(max(s["lambda_error"], s["u_error"]) for s in rec["steps"])
        u_worst = max(s["u_error"] for s in rec["steps"])
        log(
            f"patch P{degree} {method}: worst error {worst:.1e} (u {u_worst:.1e}), iterations "
            + " ".join(str(s["iterations"]) for s in rec["steps"])
            + f"; order from known distances {rec['probe']['order']:.3f}"
        )
        if method == "segment-to-segment":
            if worst > 1e-9:
                failed.append(f"patch P{degree}: error {worst:.1e} above 1e-9")
            for s in rec["steps"][1:]:
                if not max(s["orders"], default=0.0) > 1.8:
                    failed.append(f"patch P{degree}, slide {s['elements']}: no order above 1.8")
            probe = rec["probe"]
            if not (probe["order"] > 1.8 and probe["settled"]):
                failed.append(f"patch P{degree}: order {rec['probe']['order']:.2f} near the end")
        elif min(s["u_error"] for s in rec["steps"]) <= 1e-4:
            failed.append(f"node-to-segment P{degree} passes the patch test")
# -

# ## Ironing

# +
for contactor, h, method in itertools.product(
    ("block", "die"), SIZES, ("segment-to-segment", "node-to-segment")
):
    rec = ironing(comm, h, method, slide_steps=SLIDES, contactor=contactor)
    rec["ranks"] = comm.size
    fy = np.asarray(rec["fy"])
    window = (np.asarray(rec["d"]) == IRONING["press"]) & (
        np.abs(np.asarray(rec["s"]) - 2.0) <= 1.0 + 1e-12
    )
    rec["raw_oscillation"] = float(np.ptp(fy[window]) / np.mean(np.abs(fy[window])))
    records.append(rec)
    log(
        f"ironing ({contactor} contactor) h = {h:g} {method}: mean vertical force "
        f"{np.mean(fy[window]):.4f}, "
        f"oscillation {rec['oscillation']:.2e} (raw {rec['raw_oscillation']:.2e}, "
        f"horizontal {rec['horizontal_oscillation']:.2e}), "
        f"{sum(rec['iterations'])} iterations in {len(rec['s'])} steps, "
        f"order from known distances {rec['probe']['order']:.3f}, {rec['seconds']:.0f} s"
    )
    probe = rec["probe"]
    valid = probe["settled"]
    if method == "segment-to-segment" and not (probe["order"] > 1.8 and valid):
        failed.append(f"ironing {contactor} h = {h:g}: order {probe['order']:.2f} at the end")
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "large_sliding.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [r for r in records if r["scene"] == "ironing"]
    fig, axes = plt.subplots(2, 2, figsize=(12, 7), sharex=True, sharey="row")
    for r in runs:
        top, bottom = axes[:, 0 if r["contactor"] == "block" else 1]
        s = np.asarray(r["s"])
        pressed = np.asarray(r["d"]) == IRONING["press"]
        style = "-" if r["method"] == "segment-to-segment" else "--"
        label = f"{r['method']}, h = {r['h']:g}"
        top.plot(s[pressed], np.asarray(r["fy"])[pressed], style, label=label)
        bottom.plot(s[pressed], np.asarray(r["fx"])[pressed], style, label=label)
    for k, contactor in enumerate(("block's top", "die's arc")):
        axes[0, k].set_title(f"multiplier on the {contactor}")
        axes[1, k].set_xlabel("slide s")
    axes[0, 0].set_ylabel("vertical force on the die")
    axes[1, 0].set_ylabel("horizontal force on the die")
    axes[0, 1].legend(fontsize="small")
    fig.suptitle("Ironing: neo-Hookean block, stiff half-ring die, frictionless")
    fig.tight_layout()
    fig.savefig(out / "ironing.png", dpi=120)

    mine = [r for r in merged if r["ranks"] == comm.size]

    def patch_row(r):
        steps = r["steps"]
        return (
            f"| P{r['degree']} | {r['method']} | "
            f"{max(s['lambda_error'] for s in steps):.1e} | "
            f"{max(s['u_error'] for s in steps):.1e} | "
            f"{' '.join(str(s['iterations']) for s in steps)} | "
            f"{min(max(s['orders'], default=0.0) for s in steps[1:]):.2f} | "
            f"{r['probe']['order']:.3f} |"
        )

    def ironing_row(r):
        return (
            f"| {r['contactor']} | {r['h']:g} | {r['method']} | {r['unknowns']} | "
            f"{r['contact_facets']} | "
            f"{r['oscillation']:.2e} | {r['raw_oscillation']:.2e} | "
            f"{r['horizontal_oscillation']:.2e} | "
            f"{sum(r['iterations']) / len(r['iterations']):.1f} | {r['probe']['order']:.3f} | "
            f"{r['seconds']:.0f} |"
        )

    lines = [
        "## Finite deformation and large sliding",
        "",
        verdict("demo_large_sliding.py", comm, args.smoke, failed),
        "",
        "Large-sliding patch test (neo-Hookean, pressed by P = 0.2, slid by 8 lower elements "
        "one per step; errors: the largest over all steps of |λ - P|/P and of |u - u exact|; "
        "Newton iterations per step; the smallest over the slide steps of the best measured "
        "order; the order from starts at known distances of the last state, "
        "`newton_order_probe`):",
        "",
        "| P | method | λ error | u error | iterations per step | order | order (probe) |",
        "|---|---|---:|---:|---|---:|---:|",
        *[patch_row(r) for r in mine if r["scene"] == "large-sliding-patch"],
        "",
        f"Ironing (pressed by 1.4 in 14 steps, slid by 4 in {SLIDES} steps; oscillation of "
        "the vertical force over 1 <= s <= 3: the range of its deviation from a quadratic "
        "fit, and the raw range, over its mean; horizontal: the range of the horizontal "
        "force's deviation from a cubic fit over the same mean):",
        "",
        "| contactor | h | method | unknowns | contact facets | oscillation | raw | "
        "horizontal | iterations per step | order (probe) | s |",
        "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        *[ironing_row(r) for r in mine if r["scene"] == "ironing"],
        "",
        "![Ironing](ironing.png)",
    ]
    write_section(out / "report.md", "large-sliding", lines)
if failed:
    raise SystemExit("large-sliding: " + "; ".join(failed))
# -

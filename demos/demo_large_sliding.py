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
# on the block's top (the die's arc the target), on the die's arc, and on the arc of a die
# meshed twice as coarse as the block (size $2h$: a tool meshed coarser than the
# workpiece). The force on the die's held top ends at every step; its vertical
# component's oscillation over the steady slide ($1 \le s \le 3$): the range of its
# deviation from a least-squares quartic in $s$ (the trend over the window), over its
# mean (the raw range over the mean is reported too).
#
# Checked: the patch test's pressure and displacement within $10^{-9}$ at every slide
# (segment-to-segment), node-to-segment off by more than $10^{-4}$; Newton's measured
# order above 1.8 (`NewtonStep.orders`: settled iterations) on every slide step of the P1
# and P2 patch tests; every ironing step converged. And Newton's local order from starts
# at known distances (`paper.large_sliding.newton_order_probe`: a step's solution
# perturbed by 1e-3, 1e-4, 1e-5 of its largest displacement along one fixed field,
# 1e-4 to 1e-6 on ironing's stiff die; the slope of the residual after one Newton
# iteration with the full tangent against the one before) above 1.8 at every step of the
# patch tests, and at every 10th step of every segment-to-segment ironing whose active set
# the probe left alone (the count is printed). On the coarse die
# (not with `--smoke`, whose 20 steps do not resolve a ripple of one element): the
# segment-to-segment oscillation a third of node-to-segment's or less at every $h$, and
# falling with $h$ (the "smooth", and node-to-segment's "not"). The exit status is
# non-zero if a check fails. It writes
# `results/large_sliding.json`, `results/ironing.png` and the section "large-sliding" of
# `results/report.md`. Run it as
# `python3 demos/demo_large_sliding.py` or with `mpirun -n 2`; `--smoke` runs P1 only and
# the ironing at $h = 0.6$ with 20 slide steps.

# +
import itertools
import math

from mpi4py import MPI

import numpy as np

from paper.large_sliding import IRONING, ironing, sliding_patch, steady_window
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
# Newton's order probed at every 10th ironing step: each probe is three more Newton
# iterations (at every step it was measured too: the same orders, README).
PROBE_EVERY = 10
# The surface carrying the multiplier, and the die's triangles' size over the block's.
CONTACTORS = (("block", 1.0), ("die", 1.0), ("die", 2.0))
failed: list[str] = []
records: list[dict] = []


def probe_span(probes: list) -> str:
    """The probe's orders of the steps whose active set settled: their range and count."""
    probes = [p for p in probes if p is not None]
    settled = [order for order, ok in probes if ok]
    span = f"{min(settled):.3f} to {max(settled):.3f}" if settled else "none"
    return f"{span} ({len(settled)} of {len(probes)} settled)"


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
            + "; three-point orders "
            + " ".join(f"{max(s['orders'], default=math.nan):.2f}" for s in rec["steps"])
            + "; order from known distances "
            + probe_span([(s["probe"]["order"], s["probe"]["settled"]) for s in rec["steps"]])
        )
        if method == "segment-to-segment":
            if worst > 1e-9:
                failed.append(f"patch P{degree}: error {worst:.1e} above 1e-9")
            for s in rec["steps"][1:]:
                if not max(s["orders"], default=0.0) > 1.8:
                    failed.append(f"patch P{degree}, slide {s['elements']}: no order above 1.8")
            for s in rec["steps"]:
                probe = s["probe"]
                if not (probe["order"] > 1.8 and probe["settled"]):
                    failed.append(
                        f"patch P{degree}, slide {s['elements']}: order {probe['order']:.2f} "
                        f"from known distances (settled: {probe['settled']})"
                    )
        elif min(s["u_error"] for s in rec["steps"]) <= 1e-4:
            failed.append(f"node-to-segment P{degree} passes the patch test")
# -

# ## Ironing

# +
for (family, (contactor, coarsening)), h, method in itertools.product(
    enumerate(CONTACTORS), SIZES, ("segment-to-segment", "node-to-segment")
):
    rec = ironing(
        comm,
        h,
        method,
        slide_steps=SLIDES,
        contactor=contactor,
        die_h=coarsening * h,
        probe_steps=PROBE_EVERY,
    )
    rec["ranks"], rec["family"] = comm.size, family
    fy = np.asarray(rec["fy"])
    window = steady_window(rec)
    records.append(rec)
    log(
        f"ironing ({contactor} contactor, die h = {coarsening * h:g}) h = {h:g} {method}: "
        "mean vertical force "
        f"{np.mean(fy[window]):.4f}, "
        f"oscillation {rec['oscillation']:.2e} (raw {rec['raw_oscillation']:.2e}, "
        f"horizontal {rec['horizontal_oscillation']:.2e}), "
        f"{sum(rec['iterations'])} iterations in {len(rec['s'])} steps, "
        f"order from known distances {probe_span(rec['probes'])}, {rec['seconds']:.0f} s"
    )
    probed = [(x, p) for x, p in zip(rec["s"], rec["probes"], strict=True) if p is not None]
    low = [(x, o) for x, (o, ok) in probed if ok and o <= 1.8]
    if method == "segment-to-segment" and (low or not any(ok for _, (_, ok) in probed)):
        failed.append(f"ironing {contactor} h = {h:g}: orders (s, order) {low[:3]} at most 1.8")

if not args.smoke:
    coarse = {
        (r["method"], r["h"]): r["oscillation"]
        for r in records
        if r["scene"] == "ironing" and CONTACTORS[r["family"]][1] > 1.0
    }
    s2s = [coarse["segment-to-segment", h] for h in SIZES]
    for h, mortar in zip(SIZES, s2s, strict=True):
        if not mortar <= coarse["node-to-segment", h] / 3:
            failed.append(
                f"coarse die h = {h:g}: segment-to-segment oscillation {mortar:.1e} not a "
                f"third of node-to-segment's {coarse['node-to-segment', h]:.1e}"
            )
    if not all(b < a for a, b in itertools.pairwise(s2s)):
        failed.append(f"coarse die: segment-to-segment oscillations {s2s} do not fall with h")
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "large_sliding.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [r for r in records if r["scene"] == "ironing"]
    fig, axes = plt.subplots(2, 3, figsize=(16, 7), sharex=True, sharey="row")
    for r in runs:
        top, bottom = axes[:, r["family"]]
        s = np.asarray(r["s"])
        pressed = np.asarray(r["d"]) == IRONING["press"]
        style = "-" if r["method"] == "segment-to-segment" else "--"
        label = f"{r['method']}, h = {r['h']:g}"
        top.plot(s[pressed], np.asarray(r["fy"])[pressed], style, label=label)
        bottom.plot(s[pressed], np.asarray(r["fx"])[pressed], style, label=label)
    for k, (contactor, ratio) in enumerate(CONTACTORS):
        surface = "block's top" if contactor == "block" else "die's arc"
        axes[0, k].set_title(f"multiplier on the {surface}, die h = {ratio:g} h")
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
            f"{probe_span([(s['probe']['order'], s['probe']['settled']) for s in steps])} |"
        )

    def ironing_row(r):
        return (
            f"| {r['contactor']} | {r['h']:g} | {r['die_h']:g} | {r['method']} | "
            f"{r['unknowns']} | "
            f"{r['contact_facets']} | "
            f"{r['oscillation']:.2e} | {r['raw_oscillation']:.2e} | "
            f"{r['horizontal_oscillation']:.2e} | "
            f"{sum(r['iterations']) / len(r['iterations']):.1f} | {probe_span(r['probes'])} | "
            f"{r['seconds']:.0f} |"
        )

    lines = [
        "## Finite deformation and large sliding",
        "",
        verdict("demo_large_sliding.py", comm, args.smoke, failed),
        "",
        "Large-sliding patch test (neo-Hookean, pressed by P = 0.2, slid by 8 lower elements "
        "one per step; errors: the largest over all steps of |λ - P|/P and of |u - u exact|; "
        "Newton iterations per step; the smallest over the slide steps of the best "
        "three-point order of its residuals; the orders from starts at known distances of "
        "every step's solution, `newton_order_probe`, over the steps whose set settled; "
        f"in the ironing every {PROBE_EVERY}th step):",
        "",
        "| P | method | λ error | u error | iterations per step | order | orders (probe) |",
        "|---|---|---:|---:|---|---:|---:|",
        *[patch_row(r) for r in mine if r["scene"] == "large-sliding-patch"],
        "",
        f"Ironing (pressed by 1.4 in 14 steps, slid by 4 in {SLIDES} steps; oscillation of "
        "the vertical force over 1 <= s <= 3: the range of its deviation from a quartic "
        "fit, and the raw range, over its mean; horizontal: the range of the horizontal "
        "force's deviation from a quartic fit over the same mean):",
        "",
        "| contactor | h | die h | method | unknowns | contact facets | oscillation | raw | "
        "horizontal | iterations per step | orders (probe) | s |",
        "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        *[ironing_row(r) for r in mine if r["scene"] == "ironing"],
        "",
        "![Ironing](ironing.png)",
    ]
    write_section(out / "report.md", "large-sliding", lines)
if failed:
    raise SystemExit("large-sliding: " + "; ".join(failed))
# -

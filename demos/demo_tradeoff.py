# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# # Speed and accuracy: which method for which error
#
# Node-to-segment is cheap and fails the patch test on non-matching meshes; composite
# segment-to-segment (El-Abbasi & Bathe 2001, section 5) passes it and integrates on
# more points; the quadrature rule and the penalty parameter move along the same line.
# This demo measures the trade on the same meshes: every discretization of
# `contact_pairs` (node-to-segment with unit and tributary weights, at Gauss points,
# two-pass, the intermediate surface, segment-to-segment with plain and composite
# Gauss and Newton-Cotes rules of 1 to 4 points, $P_1$ and $P_2$) with the active-set
# solver, and every solver of `UnilateralContactProblem` (active set, SNES VI, the
# augmented Lagrangian, the penalty method at $\kappa = 10$ to $10^4$) with composite
# S2S and node-to-segment, on
#
# - the non-matching patch test (section 3.2), $10n/7n$ elements along the contact,
#   error $\max|\lambda - p|/p$;
# - Hertz (a half cylinder on a block, $a/R = 5\%$), $n$ elements across the contact
#   width, error: the relative $L^2$ error of the pressure over $[-a, a]$;
# - Fig. 16, its smooth variant (the inf-sup model of Fig. 2 with $g_0 = 0$, rollers,
#   a cosine top displacement; nested quadrilaterals, $10n/7n$ elements along the
#   contact), error: the relative energy norm $\|u - u_h\|_E / \|u\|_E$ against the
#   closed-form solution. It is solved tied, as Fig. 16 is (the pressure is
#   compressive everywhere, so tied is unilateral there): every discretization, no
#   unilateral solver.
#
# Wall times are the minimum over repeats (`problem.timings` per stage, and the total
# from building the pairs to the solved problem; the meshes are shared).
#
# The demo writes `results/tradeoff.json` (one record per scene, method, degree,
# solver and level), `results/tradeoff_patch.png`, `results/tradeoff_hertz.png` and
# `results/tradeoff_fig16.png` (error against time, log-log, Pareto front drawn), and
# the "Speed and accuracy"
# section of `results/report.md`. Run it as `python3 demos/demo_tradeoff.py` or with
# `mpirun -n 2`; `--smoke` runs a tiny version into another folder.

# +
from pathlib import Path

from mpi4py import MPI

from paper.records import merge_rank_records
from paper.report import (
    demo_parser,
    output_folder,
    rank0_print,
    write_section,
)
from paper.tradeoff import (
    METHODS,
    PRIMARY,
    SOLVERS,
    TIED,
    grid,
    guide,
    markdown,
    pareto,
    plot,
    run_study,
)

parser = demo_parser("speed-accuracy trade of the contact methods", "a tiny version", out=None)
parser.add_argument("--repeats", type=int, default=None, help="timed runs per case")
args = parser.parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out or Path("build/smoke/tradeoff" if args.smoke else "results"), comm)
log = rank0_print(comm)


# -

# ## The runs
#
# Every method with the active-set loop; every solver with composite S2S (3 Gauss
# points per sub-segment) and node-to-segment with tributary weights. Fig. 16: every
# method, tied, on the nested levels $n = 2, 4, 8$.

# +
if args.smoke:
    methods = ["S2S composite Gauss 2", "S2S Gauss 2", "NTS, tributary w", "two-pass NTS"]
    runs = grid(
        ["patch", "hertz"],
        [1],
        {"patch": [1], "hertz": [10]},
        methods,
        ["active-set", "penalty 1e2"],
        ["S2S composite Gauss 2"],
    ) + grid(["fig16"], [1], {"fig16": [2]}, methods, [TIED], [])
    repeats = args.repeats or 1
else:
    # P2 on Hertz stops at 20 across: at 40 one run takes seconds (x 3 repeats).
    runs = [
        *grid(
            ["patch", "hertz"],
            [1],
            {"patch": [1, 2, 4], "hertz": [10, 20, 40]},
            list(METHODS),
            list(SOLVERS),
            ["S2S composite Gauss 3", "NTS, tributary w"],
        ),
        *grid(
            ["patch", "hertz"],
            [2],
            {"patch": [1, 2, 4], "hertz": [10, 20]},
            list(METHODS),
            list(SOLVERS),
            ["S2S composite Gauss 3", "NTS, tributary w"],
        ),
        *grid(["fig16"], [1, 2], {"fig16": [2, 4, 8]}, list(METHODS), [TIED], []),
    ]
    repeats = args.repeats or 2
log(f"{len(runs)} runs, {repeats} repeat(s) each, {comm.size} rank(s)")
records = run_study(comm, runs, repeats=repeats, log=log)
pareto(records)
# -

# ## Output

# +
if comm.rank == 0:
    everything = merge_rank_records(out / "tradeoff.json", records, comm.size)
    pareto(everything)
    mine = [r for r in everything if r["ranks"] == comm.size]
    scenes = ("patch", "hertz", "fig16")
    for scene in scenes:
        plot(out / f"tradeoff_{scene}.png", mine, scene)
    targets = {
        "patch": [1e-2, 1e-6, 1e-10],
        "hertz": [5e-2, 2e-2, 1e-2],
        "fig16": [5e-2, 1e-2, 1e-3],
    }
    failed = [r for r in records if "failed" in r or "skipped" in r]
    section = [
        "## Speed and accuracy",
        "",
        f"`demos/demo_tradeoff.py`, {comm.size} rank(s), {repeats} repeat(s) per run "
        "(times are the minimum; 2 shared cores, so treat differences under ~20% as "
        "noise); P2 Hertz up to n = 20. Every discretization with the active-set loop, "
        "and every solver with "
        "composite S2S (3 Gauss points) and node-to-segment (tributary weights), on the "
        "same meshes. Patch test: non-matching, 10n/7n elements along the contact, "
        f"error `{PRIMARY['patch']}` = max |lambda - p|/p. Hertz: n elements across 2a, "
        f"error `{PRIMARY['hertz']}` = relative L2 error of the pressure over [-a, a]. "
        "Fig. 16 (smooth variant, tied, every discretization, nested quadrilaterals "
        "with 10n/7n elements along the contact, n = 2, 4, 8): error "
        f"`{PRIMARY['fig16']}` = ||u - u_h||_E / ||u||_E against the closed-form "
        "solution. "
        "`total` runs from building the pairs to the solved problem (the mesh is "
        "shared); `unknowns` counts displacements and multipliers (the penalty method "
        "solves for the displacements only). Records: `results/tradeoff.json`.",
        "",
        "![patch](tradeoff_patch.png) ![hertz](tradeoff_hertz.png) ![fig16](tradeoff_fig16.png)",
        "",
        "### The cheapest run that reaches an error",
        "",
        *guide(everything, comm.size, targets),
        "",
        "### The Pareto front",
        "",
    ]
    for scene in scenes:
        section += [f"{scene}:", "", *markdown(mine, scene, only_front=True), ""]
    section += [
        f"### Runs that failed or do not apply ({len(failed)})",
        "",
        *(
            f"- {r['scene']} P{r['degree']} n={r['level']} {r['method']}, {r['solver']}: "
            f"{r.get('failed') or r.get('skipped')}"
            for r in failed
        ),
        "",
        "### Every run",
        "",
    ]
    for scene in scenes:
        section += [f"{scene}:", "", *markdown(mine, scene), ""]
    report = out / "report.md"
    write_section(report, "tradeoff", section)
    log(f"wrote {out / 'tradeoff.json'}, {report}, {out}/tradeoff_*.png")
# -

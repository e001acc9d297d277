# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# # The contact edge on demand: adaptive refinement against uniform refinement
#
# Two elastic cylinders ($R_1 = 1$, $R_2 = 3$, $E_1 = 1$, $E_2 = 2$) pressed together in
# plane strain, meshed as a user meshes them: about 10 P1 triangles across the contact
# width $2a$ and no node at the exact edges $x = \pm a$ of Hertz's solution,
# $a = 2 \sqrt{F R / (\pi E^*)}$. The discrete contact conditions (Eq. 1 on the nodal
# weighted gaps of Eq. 17) end the zone between the last active and the first inactive
# multiplier node: the edge is known to a facet size, 20% of $a$ here.
#
# `refine_contact_zone` refines the cells around each edge (DOLFINx's `refine`, tags
# carried over), rebuilds the problem through the user's `build` and solves again,
# until the bracket is below 1% of $a$. Uniform meshes of 10, 20 and 40 elements across
# show what the same bracket costs without it.
#
# Outputs (in `--out`, default `results/`): `hertz_adaptive.json` (one record per run and
# rank count), `hertz_adaptive.png` (bracket and error of $a$ against unknowns) and the
# `adaptive_edge` section of `report.md`. Run it as `python3 demos/demo_adaptive_edge.py`
# or with `mpirun -n 2`; `--smoke` runs a reduced study.

# +
from mpi4py import MPI

from paper.hertz.adaptive import CASE, adaptive_run, uniform_run
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, write_section

args = demo_parser("Adaptive contact edge on Hertz", "a reduced study").parse_args()
comm = MPI.COMM_WORLD
out = args.out
output_folder(out, comm)
log = rank0_print(comm)
# -

# ## Adaptive refinement of the edges

# +
tolerance = 0.05 if args.smoke else 0.01
adaptive = adaptive_run(CASE, tolerance=tolerance, max_steps=6, comm=comm)
for k, step in enumerate(adaptive["steps"]):
    log(
        f"adaptive step {k}: {step['unknowns']:>6} unknowns, bracket {step['bracket_over_a']:.2%} "
        f"of a, a {step['a_error']:+.2%}, {step['seconds']:.2f} s"
    )
assert adaptive["bracket_over_a"] <= tolerance
assert abs(adaptive["a_error"]) < 0.01 or args.smoke
# -

# ## Uniform refinement

# +
uniform = [uniform_run(CASE, n, comm) for n in ([10] if args.smoke else [10, 20, 40])]
for r in uniform:
    log(
        f"uniform n={r['elements_across']:<3} {r['unknowns']:>6} unknowns, bracket "
        f"{r['bracket_over_a']:.2%} of a, a {r['a_error']:+.2%}, {r['seconds']:.2f} s"
    )
# -

# ## Records, figure and report

# +
if comm.rank == 0:
    records = [adaptive, *uniform]
    merge_rank_records(out / "hertz_adaptive.json", records, comm.size)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    steps = adaptive["steps"]
    for ax, key, label in (
        (axes[0], "bracket_over_a", "bracket / a"),
        (axes[1], "a_error", "|a / a_Hertz - 1|"),
    ):
        ax.loglog(
            [s["unknowns"] for s in steps], [abs(s[key]) for s in steps], "o-", label="adaptive"
        )
        ax.loglog(
            [r["unknowns"] for r in uniform], [abs(r[key]) for r in uniform], "s--", label="uniform"
        )
        ax.set_xlabel("unknowns")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(out / "hertz_adaptive.png", dpi=120)
    lines = [
        "## Speed-accuracy: the contact edge, adaptive against uniform refinement",
        "",
        f"Two cylinders (R1 = 1, R2 = 3), P1 triangles, a = {CASE.exact.a:g}, no node at +-a; "
        f"{comm.size} rank(s). Bracket: last active to first inactive multiplier node.",
        "",
        "| run | unknowns | bracket / a | a error | time (s) |",
        "|---|---:|---:|---:|---:|",
        *(
            f"| adaptive step {k} | {s['unknowns']} | {s['bracket_over_a']:.2%} | "
            f"{s['a_error']:+.2%} | {s['seconds']:.2f} |"
            for k, s in enumerate(steps)
        ),
        *(
            f"| uniform, {r['elements_across']} across | {r['unknowns']} | "
            f"{r['bracket_over_a']:.2%} | {r['a_error']:+.2%} | {r['seconds']:.2f} |"
            for r in uniform
        ),
        "",
        "![adaptive edge](hertz_adaptive.png)",
    ]
    write_section(out / "report.md", "adaptive_edge", lines)
# -

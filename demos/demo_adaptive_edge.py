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
# carried over), moves the nodes it adds on the arcs onto the circles (`snap=`, the
# library's `snap_boundary` with the scene's projection), rebuilds the problem through
# the user's `build` and solves again from the previous contact zone (one or two
# active-set solves instead of six to eighteen), until the bracket is below 1% of $a$.
# Uniform meshes of 10, 20 and 40 elements across show what the same accuracy costs
# without it.
#
# The second scene is an elastic half cylinder ($a/R = 2.5\%$, plane strain) on a rigid
# plane (`plane_obstacle`), P1 from 10 elements across; `pressure_tolerance=0.01` also
# refines inside the zone where the pressure's second difference is large (the P1
# multiplier oscillates at the end of the contactor on the symmetry line), so that
# $p_0$ and the $L^2$ pressure error follow Hertz too.
#
# Outputs (in `--out`, default `results/`): `hertz_adaptive.json` (one record per run and
# rank count), `hertz_adaptive.png` (error of $a$ against unknowns, both scenes) and the
# `adaptive_edge` subsection of the speed-accuracy section of `report.md`. Run it as
# `python3 demos/demo_adaptive_edge.py` or with `mpirun -n 2`; `--smoke` runs a reduced
# study.

# +
from mpi4py import MPI

import numpy as np

from paper.hertz import plane
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

# ## The rigid plane: edge and pressure

# +
PLANE = plane.PlaneCase(a_over_R=0.025)
plane_adaptive = plane.adaptive_run(
    PLANE, tolerance=tolerance, pressure_tolerance=0.05 if args.smoke else 0.01, comm=comm
)
for k, step in enumerate(plane_adaptive["steps"]):
    log(
        f"plane, adaptive step {k}: {step['unknowns']:>6} unknowns, bracket "
        f"{step['bracket_over_a']:.2%} of a, a {step['a_error']:+.2%}, {step['solves']} solves"
    )
log(
    f"plane, adaptive: a {plane_adaptive['a_error']:+.2%}, p0 {plane_adaptive['p0_error']:+.2%}, "
    f"L2(p) {plane_adaptive['l2_error']:.2%}"
)
assert args.smoke or abs(plane_adaptive["a_error"]) < 0.01
assert args.smoke or abs(plane_adaptive["p0_error"]) < 0.02
assert args.smoke or plane_adaptive["l2_error"] < 0.05
plane_uniform = [plane.uniform_run(PLANE, n, comm) for n in ([10] if args.smoke else [10, 20, 40])]
for r in plane_uniform:
    log(
        f"plane, uniform n={r['elements_across']:<3} {r['unknowns']:>6} unknowns, a "
        f"{r['a_error']:+.2%}, p0 {r['p0_error']:+.2%}, L2(p) {r['l2_error']:.2%}, "
        f"{r['seconds']:.2f} s"
    )
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

# ## Uniform refinement to the same accuracy
#
# A uniform mesh fine enough for the adaptive run's bracket would cost more than the
# demo should run (the bracket halves with $h$, the unknowns grow like $h^{-2}$). Its cost
# is extrapolated instead: least-squares lines through the uniform runs' bracket and time
# against unknowns (log-log), read at the adaptive run's bracket. The fitted exponents
# are printed and recorded; they say how far the extrapolation can be trusted.


# +
def same_accuracy(runs, bracket):
    """Unknowns and seconds of uniform refinement at ``bracket``, from a log-log fit."""
    n = np.log([r["unknowns"] for r in runs])
    k, c = np.polyfit(n, np.log([r["bracket_over_a"] for r in runs]), 1)
    m, d = np.polyfit(n, np.log([r["seconds"] for r in runs]), 1)
    unknowns = float(np.exp((np.log(bracket) - c) / k))
    return {
        "bracket_over_a": bracket,
        "unknowns": round(unknowns),
        "seconds": float(np.exp(m * np.log(unknowns) + d)),
        "bracket_exponent": float(k),
        "seconds_exponent": float(m),
    }


extrapolated = {}
if len(uniform) > 1:
    for name, run, runs in (
        ("two_cylinders", adaptive, uniform),
        ("rigid_plane", plane_adaptive, plane_uniform),
    ):
        extrapolated[name] = same_accuracy(runs, run["bracket_over_a"])
        e = extrapolated[name]
        log(
            f"{name}: uniform to a bracket of {e['bracket_over_a']:.2%} of a needs about "
            f"{e['unknowns']} unknowns and {e['seconds']:.0f} s (bracket ~ "
            f"N^{e['bracket_exponent']:.2f}, time ~ N^{e['seconds_exponent']:.2f}), against "
            f"{run['unknowns']} unknowns and "
            f"{run['seconds']:.2f} s adaptive"
        )
# -

# ## Records, figure and report

# +
if comm.rank == 0:
    adaptive["scene"] = "two_cylinders"
    for r in uniform:
        r["scene"] = "two_cylinders"
    records = [adaptive, *uniform, plane_adaptive, *plane_uniform]
    records += [{"scene": k, "extrapolated": True, **v} for k, v in extrapolated.items()]
    merge_rank_records(out / "hertz_adaptive.json", records, comm.size)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    scenes = (("two cylinders", adaptive, uniform), ("rigid plane", plane_adaptive, plane_uniform))
    for ax, (title, run, runs) in zip(axes, scenes, strict=True):
        steps = run["steps"]
        ax.loglog(
            [s["unknowns"] for s in steps],
            [max(abs(s["a_error"]), 1e-5) for s in steps],
            "o-",
            label="adaptive, |a error|",
        )
        ax.loglog(
            [s["unknowns"] for s in steps],
            [s["bracket_over_a"] for s in steps],
            ":",
            label="bracket / a",
        )
        ax.loglog(
            [r["unknowns"] for r in runs],
            [max(abs(r["a_error"]), 1e-5) for r in runs],
            "s--",
            label="uniform, |a error|",
        )
        ax.set_title(title)
        ax.set_xlabel("unknowns")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "hertz_adaptive.png", dpi=120)

    def row(name, r):
        extra = f" {r['p0_error']:+.2%} | {r['l2_error']:.2%} |" if "p0_error" in r else " | |"
        solves = r.get("solves", "")
        return (
            f"| {name} | {r['unknowns']} | {r['bracket_over_a']:.2%} | {r['a_error']:+.2%} |"
            f"{extra} {solves} | {r['seconds']:.2f} |"
        )

    def same(name, e):
        return (
            f"| {name}, uniform to the same bracket (extrapolated) | ~{e['unknowns']} | "
            f"{e['bracket_over_a']:.2%} | | | | | ~{e['seconds']:.0f} |"
        )

    lines = [
        "### The contact edge: adaptive against uniform refinement",
        "",
        f"P1 triangles from 10 elements across, no node at +-a, {comm.size} rank(s). Two "
        f"cylinders (R1 = 1, R2 = 3, a = {CASE.exact.a:g}); an elastic half cylinder on a "
        f"rigid plane (a/R = {PLANE.a_over_R:g}; pressure refined too). Bracket: last active "
        "to first inactive multiplier node; solves: active-set solves over all steps "
        "(restarted from the previous zone); time: all steps, meshing included for uniform.",
        "",
        "| run | unknowns | bracket / a | a error | p0 error | L2(p) error | solves | time (s) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
        row("two cylinders, adaptive", adaptive),
        *(row(f"two cylinders, uniform {r['elements_across']}", r) for r in uniform),
        *([same("two cylinders", extrapolated["two_cylinders"])] if extrapolated else []),
        row("rigid plane, adaptive", plane_adaptive),
        *(row(f"rigid plane, uniform {r['elements_across']}", r) for r in plane_uniform),
        *([same("rigid plane", extrapolated["rigid_plane"])] if extrapolated else []),
        "",
        "Uniform at the adaptive run's bracket: extrapolated (not run) from a least-squares "
        "line through the uniform runs, log bracket and log time against log unknowns; the "
        "fitted exponents are in the JSON records.",
        "",
        "![adaptive edge](hertz_adaptive.png)",
    ]
    write_section(out / "report.md", "adaptive_edge", lines, after="tradeoff")
# -

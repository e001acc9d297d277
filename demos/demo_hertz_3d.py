# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Hertz in 3D: a sphere on a block, two spheres, and a half-ball on a box
#
# Hertz's point contact: $1/R^* = 1/R_1 + 1/R_2$, $1/E^* = (1 - \nu_1^2)/E_1 + (1 -
# \nu_2^2)/E_2$, $a = (3FR^*/(4E^*))^{1/3}$, $p_0 = 3F/(2\pi a^2)$ and $p(r) =
# p_0\sqrt{1 - r^2/a^2}$, the solution for two half-spaces. Quarter models
# (`paper/hertz3d.py`): symmetry planes $x = 0$ and $y = 0$, the quarter carries $F/4$.
# One Gmsh model (OpenCASCADE) with two volumes meshed apart, tetrahedra with their
# second-order nodes on the spheres; the element size is $h$ within $R/10$ of the touching
# point, growing at a slope of 0.3: sizes chosen from the geometry ($h$ a fraction of $R$),
# no node placed at $r = a$. The multiplier is P1 on the contactor's faces (with P2
# displacements too: a P2 triangle's vertex functions integrate to zero).
#
# Everything is read from $\lambda$ (`paper/hertz3d_study.py`): $p_0$ at the pole node,
# $a$ where the least-squares line of $\lambda^2$ against $r^2$ through the active nodes
# reaches zero, the L2 error of $\lambda$ against Hertz over the multiplier's faces. The
# contact force of the pair ($\mathbf B^T\Lambda$) balances the load to round-off.
#
# - **Sphere on a block** ($R = 1$ on a cylindrical block of radius and depth 1, $E = 1$,
#   $\nu = 0.3$, $a/R = 5\%$): P2 and P1 at $h = R/80, R/120, R/160$; the axisymmetric
#   model of the same bodies (`Material(..., plane="axisymmetric")`) at the same $h$ and
#   at $h = R/500$ measures the model error (the finite bodies) and the 3D discretization
#   error.
# - **Two spheres** (the axisymmetric scene of `demos/demo_axisymmetric.py`: $R_1 = 1$,
#   $R_2 = 2$, $a/R_1 = 5\%$).
# - **The half-ball of another package**: $R = 8$, flat face up, on a $20^3$ box, $E =
#   200$, $\nu = 0.3$, $F = 10$ uniform on the flat face, the bottom clamped ($a = 0.817$,
#   $p_0 = 7.15$). Here $a/R \approx 0.1$ and the box is small: its model error is
#   estimated with the axisymmetric model of the finite bodies and of a large block.
#
# Outputs (in `--out`, default `results/`): `hertz_3d.json`, `hertz_3d.png` and the
# section `hertz_3d` of `report.md`. Run it as `python3 demos/demo_hertz_3d.py` or with
# `mpirun -n 2`; `--smoke` runs one coarse level of each scene ($h = R/40$) and checks
# equilibrium only.

# +
from mpi4py import MPI

import numpy as np

from paper.hertz3d_study import axisymmetric, run
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, write_section

args = demo_parser(
    "Hertz in 3D: sphere on block, two spheres, half-ball", "coarsest only"
).parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
records, curves = [], {}
#: The issue's tolerances (P2), from outside the code: a 1%, p0 2%, L2 5%.
TOLERANCE = {"a_error": 0.01, "p0_error": 0.02, "L2_error": 0.05}
#: Element sizes near the contact, as fractions of the sphere's radius.
LEVELS = (40,) if args.smoke else (80, 120, 160)
#: The axisymmetric reference and the half-ball's size near the contact (R/n).
FINE, BALL = (250, 40) if args.smoke else (500, 80)


def show(rec, label):
    """Log a record, keep it, and keep its profile for the plot."""
    r, p = rec.pop("r", None), rec.pop("pressure", None)
    rec["label"] = label
    records.append(rec)
    if r is not None:
        curves[(rec["scene"], label)] = (r / rec["a_exact"], p / rec["p0_exact"])
    log(
        f"{rec['scene']:15s} {label:24s}: a {rec['a_error']:+.2%}, p0 {rec['p0_error']:+.2%}, "
        f"L2 {rec['L2_error']:.2%}, force {rec['force_error']:.1e}; {rec['unknowns']} "
        f"unknowns, {rec['solves']} solves, {rec['seconds']:.1f} s"
    )
    if not rec["force_error"] <= 1e-10:
        raise SystemExit(f"the contact force does not balance the load: {rec}")
    return rec


# -

# ## A sphere on a block: P2 and P1, three levels

# +
block = {}
for n in LEVELS:
    for degree in (2, 1):
        rec = run(comm, "sphere-on-block", h=1.0 / n, degree=degree, keep_profile=True)
        block[(degree, n)] = show(rec, f"P{degree}, h = R/{n}")
# -

# ## The axisymmetric model of the same bodies

# +
axi = {
    n: show(axisymmetric(comm, "sphere-on-block", h=1.0 / n), f"axisym., h = R/{n}") for n in LEVELS
}
axi_fine = show(axisymmetric(comm, "sphere-on-block", h=1.0 / FINE), f"axisym., h = R/{FINE}")
# -

# ## Two spheres, and the half-ball on the box

# +
n = LEVELS[-1]
spheres = show(run(comm, "two-spheres", h=1.0 / n, keep_profile=True), f"P2, h = R1/{n}")
spheres_axi = show(axisymmetric(comm, "two-spheres", h=1.0 / FINE), f"axisym., h = R1/{FINE}")
ball = {}
for degree in (2, 1):
    rec = run(comm, "half-ball", h=8.0 / BALL, degree=degree, keep_profile=True)
    ball[degree] = show(rec, f"P{degree}, h = R/{BALL}")
ball_axi = show(axisymmetric(comm, "half-ball", h=8.0 / FINE), "axisym. box -> cylinder")
ball_far = show(
    axisymmetric(comm, "half-ball", h=8.0 / FINE, size=(80.0, 80.0)), "axisym., block 80 x 80"
)
# -

# ## Checks, records, figure and report

# +
finest = block[(2, LEVELS[-1])]
# A smoke run checks equilibrium only (above); the tolerances are the full run's.
failed = [] if args.smoke else [k for k, tol in TOLERANCE.items() if not abs(finest[k]) <= tol]
if comm.rank == 0:
    merge_rank_records(out / "hertz_3d.json", records, comm.size)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    s = np.linspace(0, 1.3, 400)
    for ax, scene in zip(axes, ("sphere-on-block", "half-ball"), strict=True):
        ax.plot(s, np.sqrt(np.clip(1 - s**2, 0, None)), "k-", label="Hertz")
        for (name, label), (r, p) in curves.items():
            if name == scene:
                ax.plot(r, p, ".", ms=3, label=label)
        ax.set_xlim(0, 1.3)
        ax.set_xlabel("r / a")
        ax.set_ylabel("lambda / p0")
        ax.set_title(scene)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "hertz_3d.png", dpi=120)

    def row(r):
        return (
            f"| {r['scene']} | {r['label']} | {r['a_over_h']:.1f} | {r['a_error']:+.2%} | "
            f"{r['p0_error']:+.2%} | {r['L2_error']:.2%} | {r['force_error']:.0e} | "
            f"{r['unknowns']} | {r['solves']} | {r['seconds']:.1f} |"
        )

    lines = [
        "## Hertz in 3D",
        "",
        f"`demos/demo_hertz_3d.py`, {comm.size} rank(s). Quarter models, tetrahedra with "
        "curved (P2) geometry, size h within R/10 of the touching point (no node at r = a), "
        "P1 multiplier; read from λ: p0 at the pole, a from the λ²-r² line through the "
        "active nodes, L2 over the contactor's faces. Tolerances (P2, finest level): a "
        f"{TOLERANCE['a_error']:.0%}, p0 {TOLERANCE['p0_error']:.0%}, L2 "
        f"{TOLERANCE['L2_error']:.0%}: " + ("met." if not failed else f"MISSED: {failed}."),
        "",
        "| scene | model | a/h | a | p0 | L2(p) | force | unknowns | solves | s |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        *[row(r) for r in records],
        "",
        f"Model error of the finite bodies (axisymmetric, h = R/{FINE}): sphere on block "
        f"a {axi_fine['a_error']:+.2%}, p0 {axi_fine['p0_error']:+.2%}; two spheres a "
        f"{spheres_axi['a_error']:+.2%}, p0 {spheres_axi['p0_error']:+.2%}; half-ball on "
        f"the box (as a cylinder of radius 10) a {ball_axi['a_error']:+.2%}, p0 "
        f"{ball_axi['p0_error']:+.2%}, on an 80 x 80 block a {ball_far['a_error']:+.2%}, "
        f"p0 {ball_far['p0_error']:+.2%}.",
        "",
        "![Hertz 3D](hertz_3d.png)",
    ]
    write_section(out / "report.md", "hertz_3d", lines)
if failed:
    raise SystemExit(f"3D Hertz, P2 at h = R/{LEVELS[-1]}: {failed} beyond {TOLERANCE}")
# -

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
# One Gmsh model (OpenCASCADE) with two volumes meshed apart, as a user meshes it:
# tetrahedra of size $R/40$ within $R/10$ of the touching point, growing at a slope of 0.3
# (no node placed at $r = a$, nothing graded with $a$). The multiplier is P1 on the
# contactor's faces (with P2 displacements too: a P2 triangle's vertex functions integrate
# to zero).
#
# The solution refines the mesh (`refine_contact_zone` with `axis=`): the contact front
# of $\lambda$ (`contact_front`: the zero crossings of $\lambda$ on the edges from an
# active to an inactive multiplier node, their mean radius bracketed by the mean radii of
# the edges' two ends) is resolved when its bracket is below `TOLERANCE_FRONT` of its
# radius; else the tetrahedra within two edge lengths of every crossing are split, the
# new nodes on the spheres projected onto them, the geometry lifted to 10-node
# tetrahedra with their midside nodes on the spheres (P2), and the next solve starts
# with the nodes inside the previous front active. The peak of $\lambda$ (the pole) is
# refined too (`peak_tolerance`), until it changes by at most 0.5% over a step: the front
# alone would leave the pole on its R/40 faces, and its change over a step would not
# measure the pole's error.
#
# Read from $\lambda$ and the weighted gaps (`paper/hertz3d_study.py`): $a$ the front's
# gap estimate (`contact_front(..., gaps=problem.gaps[0])`: the radius $e$ whose law
# $C (r - e)_+^{3/2}$ of a smooth contact edge, weighted by the multiplier's hats as in
# Eq. 17, fits the weighted gaps of the inactive nodes within three edges of the front;
# it is not Hertz's profile), inside the front's bracket; also the bracket's middle (an
# active-set $\lambda$ is zero at the inactive nodes, so its zero crossings are those
# nodes, the bracket's top: the middle is off by at most half the bracket), $p_0$ at the
# pole node, the L2 error of $\lambda$ against Hertz over the multiplier's faces;
# also $a$ of the least-squares line of $\lambda^2$ against $r^2$ (it assumes Hertz's
# profile). The contact force of the pair ($\mathbf B^T\Lambda$) balances the load to
# round-off.
#
# - **Sphere on a block** ($R = 1$ on a cylindrical block of radius and depth 1, $E = 1$,
#   $\nu = 0.3$, $a/R = 5\%$), P2 and P1; the axisymmetric model of the same bodies at
#   $h = R/500$ measures the model error (the finite bodies).
# - **Two spheres** (the axisymmetric scene of `demos/demo_axisymmetric.py`: $R_1 = 1$,
#   $R_2 = 2$, $a/R_1 = 5\%$), P2.
# - **The half-ball of another package**: $R = 8$, flat face up, on a $20^3$ box, $E =
#   200$, $\nu = 0.3$, $F = 10$ uniform on the flat face, the bottom clamped ($a = 0.817$,
#   $p_0 = 7.15$), P2 and P1; its model error from the axisymmetric model of the finite
#   bodies and of a large block.
#
# The agreement with the axisymmetric model is judged on the same bodies and the same
# discretization but the dimension: its multiplier of degree 1 as in 3D (the degree
# alone moves the axisymmetric $p_0$ by about 0.1% at $h = R/500$; the P2 multiplier's
# model is reported beside it), against a bound from the refinement itself: for $a$, half
# the last front bracket (where the discrete front lies); for $p_0$, its change since the
# step before the peak's last refinement; each plus the axisymmetric model's own distance
# to Hertz. Asserted for every P2 run:
# equilibrium, $a$ within 1%, $p_0$ within 2% and the L2 error within 5% of Hertz, the
# axisymmetric model's $a$ inside the front's bracket, and the agreement within the bound.
# The sphere on the block is also run from finer meshes of the user's (R/56, R/80).
#
# Outputs (in `--out`, default `results/`): `hertz_3d.json`, `hertz_3d.png` and the
# section `hertz_3d` of `report.md`. Run it as `python3 demos/demo_hertz_3d.py` or with
# `mpirun -n 2`; `--smoke` makes one refinement step of the sphere on the block and
# solves the half-ball once (P1 both), checking equilibrium only.

# +
from mpi4py import MPI

from paper.hertz3d_study import adaptive, axisymmetric
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, write_section

args = demo_parser(
    "Hertz in 3D: sphere on block, two spheres, half-ball", "one refinement step"
).parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
records = []
#: The issue's tolerances (P2), from outside the code: a 1%, p0 2%, L2 5%.
TOLERANCE = {"a_gap_error": 0.01, "p0_error": 0.02, "L2_error": 0.05}
#: The front's bracket, relative to its radius, at which the refinement stops: what three
#: refinements of the R/40 mesh reach (each halves it, and multiplies the unknowns by
#: about 2.4: 200,000 for the P2 sphere on the block, two minutes on this machine).
TOLERANCE_FRONT = 0.06
#: The peak of λ is refined too (its node and ``layers`` of its edges) until it changes by
#: at most this over a step: the front alone would leave the pole's R/40 faces as they are.
PEAK_TOLERANCE = 0.005
STEPS = 1 if args.smoke else 3
#: Finer meshes of the user's (R/n) for the sphere on the block: how the answers move.
BASES = (56, 80)
#: The axisymmetric reference (R/n).
FINE = 150 if args.smoke else 500


def show(recs, label):
    """Log the steps of an adaptive run, keep them, return the last."""
    for rec in recs:
        rec["label"] = label
        records.append(rec)
        lo, hi = rec["front"]
        log(
            f"{rec['scene']:15s} {label:5s} step {rec['step']}: a {rec['a_gap_error']:+.2%} "
            f"(middle {rec['a_front_error']:+.2%}) in [{lo / rec['a_exact'] - 1:+.2%}, "
            f"{hi / rec['a_exact'] - 1:+.2%}] (bracket "
            f"{rec['front_over_a']:.1%}), a(fit) {rec['a_error']:+.2%}, p0 "
            f"{rec['p0_error']:+.2%}, L2 {rec['L2_error']:.2%}; {rec['unknowns']} unknowns, "
            f"{rec['solves']} solves, {rec['seconds']:.1f} s"
        )
    last = recs[-1]
    log(f"  force balance {last['force_error']:.1e}, {last['seconds_total']:.1f} s in all")
    if not last["force_error"] <= 1e-10:
        raise SystemExit(f"the contact force does not balance the load: {last}")
    return last


def show_axi(rec, label):
    """Log and keep an axisymmetric record."""
    rec["label"] = label
    records.append(rec)
    log(
        f"{rec['scene']:15s} {label}: a {rec['a_error']:+.2%}, p0 {rec['p0_error']:+.2%}, "
        f"L2 {rec['L2_error']:.2%}; {rec['unknowns']} unknowns, {rec['solves']} solves, "
        f"{rec['seconds']:.1f} s"
    )
    return rec


def run(name, degree, steps=STEPS, n=40):
    """The adaptive run of a scene from the R/n mesh; its records."""
    return adaptive(
        comm,
        name,
        n=n,
        degree=degree,
        tolerance=TOLERANCE_FRONT,
        max_steps=steps,
        peak_tolerance=PEAK_TOLERANCE,
    )


# -

# ## A sphere on a block, P2 and P1, and the axisymmetric model of the same bodies

# +
block = {}
for degree in (1,) if args.smoke else (2, 1):
    block[degree] = run("sphere-on-block", degree)
    show(block[degree], f"P{degree}")
axi = show_axi(axisymmetric(comm, "sphere-on-block", h=1.0 / FINE), f"axisym., h = R/{FINE}")
# The same bodies and discretization but the dimension: P1 multiplier as in 3D.
axi_p1 = show_axi(
    axisymmetric(comm, "sphere-on-block", h=1.0 / FINE, multiplier=1), f"axisym. P1 mult., R/{FINE}"
)
# -

# ## The user's mesh finer: the sphere on the block from R/56 and R/80, P2

# +
finer = {}
for n in () if args.smoke else BASES:
    finer[n] = run("sphere-on-block", 2, n=n)
    show(finer[n], f"P2 R/{n}")
# -

# ## Two spheres, and the half-ball on the box

# +
spheres, ball = None, {}
if not args.smoke:
    spheres = run("two-spheres", 2)
    show(spheres, "P2")
    spheres_axi = axisymmetric(comm, "two-spheres", h=1.0 / FINE)
    show_axi(spheres_axi, f"axisym., h = R1/{FINE}")
    spheres_axi_p1 = axisymmetric(comm, "two-spheres", h=1.0 / FINE, multiplier=1)
    show_axi(spheres_axi_p1, f"axisym. P1 mult., R1/{FINE}")
for degree in (1,) if args.smoke else (2, 1):
    ball[degree] = run("half-ball", degree, 0 if args.smoke else STEPS)
    show(ball[degree], f"P{degree}")
ball_axi = show_axi(axisymmetric(comm, "half-ball", h=8.0 / FINE), "axisym. box -> cylinder")
ball_far = None
if not args.smoke:
    ball_far = axisymmetric(comm, "half-ball", h=8.0 / FINE, size=(80.0, 80.0))
    show_axi(ball_far, "axisym., block 80 x 80")
# -

# ## Checks: the tolerances (P2) and the axisymmetric model within the bound

# +


def agreement(recs, reference):
    """3D (last step) against the axisymmetric model: (key, difference, bound).

    The bound, as in the module's text: half the last front bracket for a, for p0 its
    change since the step before the peak's last refinement; plus the axisymmetric
    model's own distance to Hertz.
    """
    last = recs[-1]
    refined = [k for k in range(1, len(recs)) if not recs[k - 1]["peak_change"] <= PEAK_TOLERANCE]
    since = recs[refined[-1] - 1] if refined else last
    out = []
    for key, own in (
        ("a", 0.5 * (last["front"][1] - last["front"][0])),
        ("p0", abs(last["p0"] - since["p0"])),
    ):
        value = last["a_gap"] if key == "a" else last["p0"]
        model = abs(reference[f"{key}_error"]) * reference[f"{key}_exact"]
        out.append((key, abs(value - reference[key]), own + model))
    return out


checks, p2_multiplier = [], []
if not args.smoke:
    checks.append(("sphere on block", agreement(block[2], axi_p1)))
    checks.append(("two spheres", agreement(spheres, spheres_axi_p1)))
    # Reported: against the P2 multiplier's axisymmetric model (the degree differs too).
    p2_multiplier = [
        ("sphere on block", agreement(block[2], axi)),
        ("two spheres", agreement(spheres, spheres_axi)),
    ]
# Asserted, for every P2 run: equilibrium (in show), a, p0 and L2 within the issue's
# tolerances, the axisymmetric model's a inside the front's bracket, and the agreement
# with it within the bound.
p2 = []
if not args.smoke:
    p2 = [
        ("sphere on block R/40", block[2], axi),
        *[(f"sphere on block R/{n}", finer[n], axi) for n in BASES],
        ("two spheres", spheres, spheres_axi),
        ("half-ball", ball[2], ball_axi),
    ]
failed = []
for scene, recs, model in p2:
    last = recs[-1]
    failed += [
        f"{scene}: {key} {last[key]:+.2%} beyond {TOLERANCE[key]:.0%}"
        for key in TOLERANCE
        if not abs(last[key]) <= TOLERANCE[key]
    ]
    if not last["front"][0] <= model["a"] <= last["front"][1]:
        failed.append(f"{scene}: the axisymmetric a {model['a']:.5g} outside {last['front']}")
failed += [
    f"{scene}: {key} differs by {d:.3g} > {bound:.3g}"
    for scene, rows in checks
    for key, d, bound in rows
    if not d <= bound
]
for s, rows in checks:
    for k, d, b in rows:
        log(f"{s}: {k} differs by {d:.3g} (bound {b:.3g})")
for s, rows in [] if args.smoke else p2_multiplier:
    for k, d, b in rows:
        log(f"{s}, the axisymmetric model's P2 multiplier: {k} differs by {d:.3g} ({b:.3g})")
# -

# ## Records, figure and report

# +
if comm.rank == 0:
    merge_rank_records(out / "hertz_3d.json", records, comm.size)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    for ax, recs, title in (
        (axes[0], block[max(block)], f"sphere on block, P{max(block)}"),
        (axes[1], ball[1], "half-ball, P1"),
    ):
        n = [r["unknowns"] for r in recs]
        for key, label in (
            ("a_gap_error", "a"),
            ("a_front_error", "a (middle)"),
            ("p0_error", "p0"),
            ("L2_error", "L2"),
        ):
            ax.loglog(n, [max(abs(r[key]), 1e-5) for r in recs], "o-", label=label)
        ax.loglog(n, [r["front_over_a"] for r in recs], "k--", label="front bracket / a")
        ax.set_xlabel("unknowns")
        ax.set_ylabel("relative error")
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "hertz_3d.png", dpi=120)

    def row(r):
        lo, hi = r["front"]
        return (
            f"| {r['scene']} | {r['label']} | {r['step']} | {r['a_gap_error']:+.2%} | "
            f"{r['a_front_error']:+.2%} | "
            f"[{lo / r['a_exact'] - 1:+.1%}, {hi / r['a_exact'] - 1:+.1%}] | "
            f"{r['a_error']:+.2%} | {r['p0_error']:+.2%} | {r['L2_error']:.2%} | "
            f"{r['unknowns']} | {r['solves']} | {r['seconds']:.1f} |"
        )

    def axi_row(r):
        return (
            f"| {r['scene']} | {r['label']} | | | | | {r['a_error']:+.2%} | {r['p0_error']:+.2%} "
            f"| {r['L2_error']:.2%} | {r['unknowns']} | {r['solves']} | {r['seconds']:.1f} |"
        )

    lines = [
        "## Hertz in 3D",
        "",
        f"`demos/demo_hertz_3d.py`, {comm.size} rank(s). Quarter models, tetrahedra of size "
        "R/40 within R/10 of the touching point (no node at r = a), P1 multiplier, refined "
        "by the solution around the contact front until its bracket is below "
        f"{TOLERANCE_FRONT:.0%} of its radius, and around the peak of λ until it changes "
        f"by at most {PEAK_TOLERANCE:.1%} over a step (at most {STEPS} steps). a: the front's "
        "gap estimate (the law (r - e)^{3/2} fitted to the weighted gaps near the front), "
        "middle: the middle of the front's bracket (the zero crossings of λ are its top), "
        "a(fit): the λ²-r² line; "
        "p0 at the pole; L2 over the contactor's faces; the seconds are cumulative. "
        f"Tolerances (P2, last step): a {TOLERANCE['a_gap_error']:.0%}, p0 "
        f"{TOLERANCE['p0_error']:.0%}, L2 {TOLERANCE['L2_error']:.0%}"
        + (" (smoke run: not checked)." if args.smoke else ": ")
        + ("" if args.smoke else "all met." if not failed else f"FAILED: {failed}."),
        "",
        "| scene | model | step | a | middle | front | a(fit) | p0 | L2(p) | unknowns | solves "
        "| s |",
        "|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|",
        *[row(r) if "step" in r else axi_row(r) for r in records],
        "",
        "Against the axisymmetric model of the same bodies with the 3D models' P1 multiplier "
        "(bound: half the last bracket for a, p0's change since the step before the peak's "
        "last refinement, plus the model's own distance to Hertz): "
        + "; ".join(f"{s}: {k} {d:.3g} (bound {b:.3g})" for s, r in checks for k, d, b in r)
        + ". With the axisymmetric model's P2 multiplier instead: "
        + "; ".join(f"{s}: {k} {d:.3g} ({b:.3g})" for s, r in p2_multiplier for k, d, b in r)
        + ".",
        "",
        f"Model error of the finite bodies (axisymmetric, h = R/{FINE}): sphere on block "
        f"a {axi['a_error']:+.2%}, p0 {axi['p0_error']:+.2%}; half-ball on the box (as a "
        f"cylinder of radius 10) a {ball_axi['a_error']:+.2%}, p0 "
        f"{ball_axi['p0_error']:+.2%}"
        + (
            ""
            if ball_far is None
            else f", on an 80 x 80 block a {ball_far['a_error']:+.2%}, "
            f"p0 {ball_far['p0_error']:+.2%}"
        )
        + ".",
        "",
        "![Hertz 3D](hertz_3d.png)",
    ]
    write_section(out / "report.md", "hertz_3d", lines)
if failed:
    raise SystemExit(f"3D Hertz: {failed}")
# -

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Coulomb friction in 2D: Cattaneo-Mindlin, half disks, an inclined block, the patch tests
#
# `FrictionalContactProblem` (in `dolfinx_contact_s2s.friction`) adds to the mortar
# contact of Eq. (1) a tangential multiplier $\lambda_t$ in the same space as the
# normal one $\lambda_n$, and Coulomb's law at every multiplier node: $|\lambda_t| \le
# \mu\lambda_n$, stick (no weighted slip increment) where $|\lambda_t| < \mu\lambda_n$,
# slip against the increment where $|\lambda_t| = \mu\lambda_n$. The slip increment of
# a load step is measured from the previous step's solution, so the answer depends on
# the load path. $\lambda_n$ is the contact pressure and $\lambda_t$ the shear traction
# itself: everything below is read from them.
#
# **Cattaneo-Mindlin.** Two identical half cylinders ($R = 1$, $E = 1$, $\nu = 0.3$,
# plane strain; `paper.hertz.scene.hertz` with `lower_radius=R`, graded for $a = 0.05$
# with about $n$ elements across $2a$): the upper flat face is moved down in four
# frictionless steps (Hertz: $a = 2\sqrt{P R_e/(\pi E^*)}$, $p_0 = 2P/(\pi a)$, $R_e =
# R/2$, $E^* = E/(2(1-\nu^2))$), then sideways in four steps with $\mu = 0.2$. Identical
# bodies decouple the normal and tangential problems, and the shear for $Q < \mu P$ is
#
# $$q(x) = \frac{\mu p_0}{a}\left[\sqrt{a^2 - x^2} - \sqrt{c^2 - x^2}\right] \text{ for
# } |x| < c, \qquad \mu p(x) \text{ for } c < |x| < a, \qquad c = a\sqrt{1 -
# Q/(\mu P)},$$
#
# with $P$ and $Q$ the integrals of $\lambda_n$ and $\lambda_t$. The measured $c$ is
# the largest $|x|$ of a sticking multiplier node; the L2 errors of $q$ and $p$ are
# relative, over $[-a, a]$, of the nodal values interpolated linearly.
#
# **Cattaneo-Mindlin on a mesh refined by the solution.** The same scene meshed as a
# user meshes it (20 P1 or 10 P2 elements across $2a$, a linear geometry), solved along
# the same load path and refined by `refine_contact_zone` around the ends of the contact
# zone and of the stick zone until their brackets are 1% of $a$ (the new nodes on the
# arcs moved onto the circles, the mesh lifted to the displacement's degree;
# `paper.friction_adaptive`). Checked: $c$ (the brackets' middle) within 2% and within
# one element of the user's mesh, $q$ within 5% L2, P1 and P2.
#
# **The other package's half disks.** The friction demo of the other FEniCSx contact
# package, solved here: two identical half disks of radius $R = 8$ touching at their
# poles, $E = 200$, $\nu = 0.3$, plane strain, the lower flat face clamped; a normal
# traction $0.625$ on the upper flat face ($F = 10$ per unit thickness) in four
# frictionless steps, the axes $x = 0$ held sideways (symmetry: without friction nothing
# else holds the upper body); then a second problem continues the first
# (`solve(after=...)`) with the axes released and the top's vertical motion held, and
# $\mu = 0.2$ and a tangential traction $0.05851$ on the same face ($Q = 0.936$) in eight
# steps. Hertz with $R_e = R/2$ gives $a = 0.681$, $p_0 = 9.35$, and Cattaneo and Mindlin
# $c = a\sqrt{1 - Q/(\mu F)} = 0.729a$. The mesh is a user's: triangles of size $h$
# within 1 of the poles, graded to 1 (`paper.friction.half_disks_mesh`). The loads the
# contact tractions balance on the upper body, read from the couplings, must equal $F$
# (after the normal steps) and $Q$ (at the end) to round-off.
#
# **Inclined block.** A block pressed onto a wedge of slope $\tan\alpha = 0.1$ and
# pushed up it, all of it sliding with $\mu = 0.5$: the push's reaction over the
# vertical load is $(\mu + \tan\alpha)/(1 - \mu\tan\alpha) = 0.6316$.
#
# **Frictional patch tests.** Two non-matching blocks (7/5 elements) in a uniform
# stress: a shear $\tau = 0.2 < \mu p$ ($p = 0.75$, $\mu = 0.5$) sticks everywhere with
# $\lambda_t = \tau$; the top moved beyond the stick limit ($\mu = 0.3$) slips everywhere
# with $\lambda_t = \pm\mu p$.
#
# Checked (the issue's bounds): $c$ within one element (the middle of the brackets of the
# stick zone's ends: last sticking, first slipping node), $q$ within 5% relative L2 for
# P2, the inclined block's ratio to $10^{-8}$, the patch tests to $10^{-10}$ relative;
# the half disks' equilibrium to $10^{-10}$ relative, and in P2 $c$ within one element
# and $q$ within 10% L2; the exit status is non-zero if one fails. It writes
# `results/friction.json`, `results/friction.png`, `results/friction_refined.png`,
# `results/friction_half_disks.png` and
# the section "friction" of `results/report.md`. Run it as
# `python3 demos/demo_friction.py` or `mpirun -n 2 python3 demos/demo_friction.py`;
# `--smoke` runs Cattaneo-Mindlin at 20 elements, the refined P2 run to brackets of 4%
# of $a$ and the half disks at $h = 0.1$ only.

# +
from mpi4py import MPI

import numpy as np

from paper.friction import (
    CM_MU,
    HD_MU,
    HD_OTHER_PACKAGE,
    cattaneo_mindlin,
    cattaneo_mindlin_shear,
    half_disks,
    inclined_block,
    patch_slip,
    patch_stick,
)
from paper.friction_adaptive import cattaneo_mindlin_adaptive
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, verdict, write_section

args = demo_parser(
    "Coulomb friction in 2D: Cattaneo-Mindlin, inclined block, patch tests",
    "Cattaneo-Mindlin at 20 elements across, the refined P2 run to coarser brackets and the "
    "half disks at h = 0.1 only",
).parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
ACROSS = (20,) if args.smoke else (20, 40, 80)
SIZES = (0.1,) if args.smoke else (0.1, 0.05, 0.025)
# The refined runs (degree, elements across 2a) and their edge tolerance (of a).
REFINED, EDGE = (((2, 10),), 0.04) if args.smoke else (((1, 20), (2, 10)), 0.01)
PATCH_BOUND, INCLINE_BOUND, Q_BOUND, HD_Q_BOUND, C_BOUND = 1e-10, 1e-8, 0.05, 0.10, 0.02
records, failed = [], []
# -

# ## Cattaneo-Mindlin

# +
traction = None
for degree in (1, 2):
    for across in ACROSS:
        rec = cattaneo_mindlin(comm, degree, across, keep_traction=True)
        x, q, p = rec.pop("x"), rec.pop("q"), rec.pop("p")
        if degree == 2 and across == ACROSS[-1]:
            traction = rec, x, q, p
        rec["ranks"] = comm.size
        records.append(rec)
        log(
            f"P{degree} n = {across:3d}: c {rec['c']:.5f} exact {rec['c_exact']:.5f} "
            f"({rec['c_error_elements']:.2f} elements, {rec['c_error']:.2%}), bracket "
            f"middle {rec['c_middle']:.5f} ({rec['c_middle_error_elements']:.2f} elements, "
            f"{rec['c_middle_error']:.2%}), "
            f"L2 q {rec['q_L2_error']:.2%}, p {rec['p_L2_error']:.2%}, Q/(mu P) "
            f"{rec['Q_over_muP']:.3f}; solves per step {rec['solves_per_step']}, "
            f"{rec['unknowns']} unknowns, {rec['seconds']:.1f} s"
        )
        if rec["c_middle_error_elements"] > 1.0:
            failed.append(
                f"P{degree} n = {across}: c off by {rec['c_middle_error_elements']:.2f} h"
            )
        if degree == 2 and rec["q_L2_error"] > Q_BOUND:
            failed.append(f"P2 n = {across}: q off by {rec['q_L2_error']:.2%} (L2)")
# -

# ## Cattaneo-Mindlin refined by the solution

# +
refined = None
for degree, across in REFINED:
    rec = cattaneo_mindlin_adaptive(comm, degree, across, tolerance=EDGE, keep_traction=True)
    x, q, p = rec.pop("x"), rec.pop("q"), rec.pop("p")
    if degree == 2:
        refined = rec, x, q, p
    rec["ranks"] = comm.size
    records.append(rec)
    user_h = 2 * rec["a"] / across
    off = rec["c_middle_error"] * rec["c_exact"]
    log(
        f"refined P{degree} from n = {across}: {len(rec['steps'])} meshes, "
        f"{rec['across_contact']:g} elements across 2a at the end, c (middle) "
        f"{rec['c_middle']:.5f} exact {rec['c_exact']:.5f} ({rec['c_middle_error']:.2%}, "
        f"{off / user_h:.2f} of the user's elements, {rec['c_middle_error_elements']:.2f} "
        f"of the local ones), L2 q {rec['q_L2_error']:.2%}, p {rec['p_L2_error']:.2%}; "
        f"{rec['unknowns']} unknowns, {rec['seconds']:.1f} s"
    )
    if rec["c_middle_error"] > C_BOUND or off > user_h:
        failed.append(f"refined P{degree}: c off by {rec['c_middle_error']:.2%}")
    if rec["q_L2_error"] > Q_BOUND:
        failed.append(f"refined P{degree}: q off by {rec['q_L2_error']:.2%} (L2)")
# -

# ## The other package's half disks

# +
disks = None
for degree in (1, 2):
    for h in SIZES:
        rec = half_disks(comm, degree, h, keep_traction=True)
        x, q, p = rec.pop("x"), rec.pop("q"), rec.pop("p")
        if degree == 2 and h == SIZES[-1]:
            disks = rec, x, q, p
        rec["ranks"] = comm.size
        records.append(rec)
        balance = max(abs(rec["P_normal"] / rec["F"] - 1), abs(rec["Q_measured"] / rec["Q"] - 1))
        log(
            f"half disks P{degree} h = {h:g}: c {rec['c']:.4f} exact {rec['c_exact']:.4f} "
            f"({rec['c_error_elements']:.2f} elements), L2 q {rec['q_L2_error']:.2%}, "
            f"p {rec['p_L2_error']:.2%}, p0 {rec['p0_measured']:.3f} ({rec['p0']:.3f}), "
            f"a {rec['a_measured']:.3f} ({rec['a']:.3f}); balance {balance:.1e}, P at the "
            f"end {rec['P'] / rec['F'] - 1:+.1e}; solves per step {rec['solves_per_step']}, "
            f"{rec['unknowns']} unknowns, {rec['seconds']:.1f} s"
        )
        if balance > PATCH_BOUND:
            failed.append(f"half disks P{degree} h = {h:g}: equilibrium off by {balance:.1e}")
        if degree == 2 and rec["c_error_elements"] > 1.0:
            failed.append(f"half disks P2 h = {h:g}: c off by {rec['c_error_elements']:.2f} h")
        if degree == 2 and rec["q_L2_error"] > HD_Q_BOUND:
            failed.append(f"half disks P2 h = {h:g}: q off by {rec['q_L2_error']:.2%} (L2)")
# -

# ## The inclined block and the frictional patch tests

# +
checks = []
for degree in (1, 2):
    rec = inclined_block(comm, degree)
    checks.append(rec)
    log(f"inclined block P{degree}: ratio {rec['ratio']:.10f}, error {rec['error']:.1e}")
    if rec["error"] > INCLINE_BOUND or not rec["sliding"]:
        failed.append(f"inclined block P{degree}: {rec}")
    for case, run in (
        ("stick", lambda d: patch_stick(comm, d)),
        ("slip +", lambda d: patch_slip(comm, d, 1.0)),
        ("slip -", lambda d: patch_slip(comm, d, -1.0)),
    ):
        rec = run(degree)
        rec["scene"] = f"patch-{case.replace(' +', '').replace(' -', '-reverse')}"
        checks.append(rec)
        errors = max(rec["lambda_n_error"], rec["lambda_t_error"], rec["u_error"])
        expected_stick = rec["multipliers"] if case == "stick" else 0
        log(
            f"patch {case} P{degree}: lambda_n {rec['lambda_n_error']:.1e}, lambda_t "
            f"{rec['lambda_t_error']:.1e}, u {rec['u_error']:.1e}; active {rec['active']}/"
            f"{rec['multipliers']}, stick {rec['stick']}, {rec['solves']} solves"
        )
        sets = rec["active"] == rec["multipliers"] and rec["stick"] == expected_stick
        if errors > PATCH_BOUND or not sets or not rec["converged"]:
            failed.append(f"patch {case} P{degree}: {rec}")
for rec in checks:
    rec["ranks"] = comm.size
records += checks
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "friction.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def plot_traction(data, mu, title, name):
        """lambda_n / p0 and lambda_t / (mu p0) against Hertz and Cattaneo-Mindlin."""
        rec, x, q, p = data
        a, c, p0 = rec["a"], rec["c_exact"], rec["p0"]
        s = np.linspace(-1.3 * a, 1.3 * a, 801)
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot(s / a, np.sqrt(np.clip(1 - s**2 / a**2, 0, None)), "k--", lw=0.8, label="Hertz")
        shear = cattaneo_mindlin_shear(s, a, c, p0, mu) / (mu * p0)
        ax.plot(s / a, shear, "k-", lw=0.8, label="q(x) (Cattaneo-Mindlin)")
        keep = np.abs(x) < 1.3 * a
        ax.plot(x[keep] / a, p[keep] / p0, "s", ms=3, mfc="none", label=r"$\lambda_n / p_0$")
        ax.plot(x[keep] / a, q[keep] / (mu * p0), "o", ms=3, label=r"$\lambda_t / (\mu p_0)$")
        for side in (-1, 1):
            ax.axvline(side * c / a, color="0.6", lw=0.6)
        ax.set_xlabel("x / a")
        ax.set_ylabel("traction, scaled")
        ax.set_title(f"{title}, c/a = {c / a:.3f}")
        ax.legend(loc="lower center", fontsize="small")
        fig.tight_layout()
        fig.savefig(out / name, dpi=120)

    plot_traction(
        traction,
        CM_MU,
        f"Cattaneo-Mindlin, P2, {traction[0]['across']} elements across 2a",
        "friction.png",
    )
    plot_traction(
        refined,
        CM_MU,
        f"Cattaneo-Mindlin, P2 from n = {refined[0]['across']}, refined",
        "friction_refined.png",
    )
    plot_traction(
        disks, HD_MU, f"Half disks R = 8, P2, h = {disks[0]['h']:g}", "friction_half_disks.png"
    )

    def cm_row(r):
        return (
            f"| P{r['degree']} | {r['across']} | {r['c']:.5f} | {r['c_exact']:.5f} | "
            f"{r['c_error_elements']:.2f} | {r['c_error']:.2%} | {r['c_middle']:.5f} | "
            f"{r['c_middle_error_elements']:.2f} | {r['c_middle_error']:.2%} | "
            f"{r['q_L2_error']:.2%} | "
            f"{r['p_L2_error']:.2%} | {' '.join(map(str, r['solves_per_step']))} | "
            f"{r['unknowns']} | {r['seconds']:.1f} |"
        )

    def disks_row(r):
        return (
            f"| P{r['degree']} | {r['h']:g} | {r['c']:.4f} | {r['c_exact']:.4f} | "
            f"{r['c_error_elements']:.2f} | {r['q_L2_error']:.2%} | {r['p_L2_error']:.2%} | "
            f"{r['a_measured']:.4f} | {r['p0_measured']:.3f} | "
            f"{max(abs(r['P_normal'] / r['F'] - 1), abs(r['Q_measured'] / r['Q'] - 1)):.0e} | "
            f"{r['P'] / r['F'] - 1:+.1e} | {' '.join(map(str, r['solves_per_step']))} | "
            f"{r['unknowns']} | {r['seconds']:.1f} |"
        )

    def patch_row(r):
        return (
            f"| {r['scene']} | P{r['degree']} | {r['lambda_n_error']:.1e} | "
            f"{r['lambda_t_error']:.1e} | {r['u_error']:.1e} | {r['active']}/"
            f"{r['multipliers']} | {r['stick']} | {r['solves']} |"
        )

    mine = [r for r in merged if r["ranks"] == comm.size]

    def other_package_rows():
        other = HD_OTHER_PACKAGE
        here = min(
            (r for r in mine if r["scene"] == "half-disks" and r["degree"] == 2),
            key=lambda r: r["h"],
        )
        c, a, p0 = here["c_exact"], here["a"], here["p0"]
        return [
            f"| unknowns | {other['unknowns']:,} | {here['unknowns']:,} |",
            f"| iterations | {other['newton']} Newton, {other['linear']} Krylov | "
            f"{sum(here['solves_per_step'])} LU solves (active, stick and slip sets) |",
            f"| time | {other['seconds']:.0f} s ({other['cpu_seconds']:.0f} s CPU, shared "
            f"cores) | {here['seconds']:.1f} s |",
            f"| c (exact {c:.4f}) | {other['c']:.3f} ({other['c'] / c - 1:+.1%}) | "
            f"{here['c']:.4f} ({here['c'] / c - 1:+.1%}) |",
            f"| L2(q), L2(p) | {other['q_L2_error']:.1%}, {other['p_L2_error']:.1%} | "
            f"{here['q_L2_error']:.2%}, {here['p_L2_error']:.2%} |",
            f"| a, p0 (Hertz {a:.4f}, {p0:.3f}) | fitted {other['a']:.3f} "
            f"({other['a'] / a - 1:+.1%}), {other['p0']:.3f} ({other['p0'] / p0 - 1:+.1%}) | "
            f"outermost active node {here['a_measured']:.4f} "
            f"({here['a_measured'] / a - 1:+.1%}), largest λn "
            f"{here['p0_measured']:.3f} ({here['p0_measured'] / p0 - 1:+.1%}) |",
        ]

    lines = [
        "## Coulomb friction in 2D",
        "",
        verdict("demo_friction.py", comm, args.smoke, failed),
        "",
        "Cattaneo-Mindlin (two half cylinders R = 1, a ≈ 0.05, μ = 0.2, Q/(μP) ≈ 0.5; "
        "n elements across 2a, no node at the contact edges; c: the outermost sticking "
        "node, and the middle of the brackets of the stick zone's ends; errors relative L2 "
        "over [-a, a]; solves per load step: 4 frictionless normal steps, then 4 "
        "tangential):",
        "",
        "| P | n | c | c exact | error (h) | error | c (middle) | error (h) | error | L2(q) | "
        "L2(p) | solves per step | unknowns | s |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|",
        *[cm_row(r) for r in mine if r["scene"] == "cattaneo-mindlin"],
        "",
        "The issue's 2% for c at about 40 elements across, from the middle of the brackets "
        "of the stick zone's ends (last sticking, first slipping node; reported): "
        + (
            ", ".join(
                f"P{r['degree']} {r['c_middle_error']:.2%}"
                for r in mine
                if r["scene"] == "cattaneo-mindlin" and r["across"] == 40
            )
            or "not run (smoke run)"
        )
        + "; the outermost sticking node lies up to one node spacing inside c.",
        "",
        "![Cattaneo-Mindlin](friction.png)",
        "",
        "Cattaneo-Mindlin on a mesh refined by the solution (`refine_contact_zone` with the "
        "load path; from the user's n elements across 2a, around the ends of the contact "
        f"and stick zones until their brackets are {EDGE:.0%} of a; c the middle of the stick "
        "zone's brackets, its error in the user's elements and in the local ones; "
        "elements across 2a at the end):",
        "",
        "| P | n | meshes | across at the end | c (middle) | c exact | error | error "
        "(user's h) | error (local h) | L2(q) | L2(p) | unknowns | s |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *[
            f"| P{r['degree']} | {r['across']} | {len(r['steps'])} | {r['across_contact']:g} | "
            f"{r['c_middle']:.5f} | {r['c_exact']:.5f} | {r['c_middle_error']:.2%} | "
            f"{r['c_middle_error'] * r['c_exact'] * r['across'] / (2 * r['a']):.2f} | "
            f"{r['c_middle_error_elements']:.2f} | {r['q_L2_error']:.2%} | "
            f"{r['p_L2_error']:.2%} | {r['unknowns']} | {r['seconds']:.1f} |"
            for r in mine
            if r["scene"] == "cattaneo-mindlin-adaptive"
        ],
        "",
        "![Cattaneo-Mindlin refined by the solution](friction_refined.png)",
        "",
        "The other FEniCSx contact package's friction demo, solved here: two half disks "
        "R = 8 touching at their poles, E = 200, nu = 0.3, plane strain; F = 10 in 4 "
        "frictionless steps (axes x = 0 held sideways), then, continued by a second "
        "problem with the axes released and the top's vertical motion held, μ = 0.2 and "
        "Q = 0.936 in 8 steps (Q/(μF) = 0.468). Exact: a = 0.6808, p0 = 9.351 (Hertz, "
        "R_e = R/2), c = 0.4965 (Cattaneo-Mindlin). h: element size within 1 of the poles "
        "(a user's mesh, graded to 1); a: the outermost active node; p0: the largest λn; "
        "balance: the loads the contact tractions balance against F and Q (relative); "
        "P end: the normal load's drift in the tangential steps (top held):",
        "",
        "| P | h | c | c exact | error (h) | L2(q) | L2(p) | a | p0 | balance | P end | "
        "solves per step | unknowns | s |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|",
        *[disks_row(r) for r in mine if r["scene"] == "half-disks"],
        "",
        "![half disks](friction_half_disks.png)",
        "",
        "Side by side with the other package's own demo, both run on this machine (its "
        "numbers from `paper.friction.HD_OTHER_PACKAGE`: v0.9.0 on DOLFINx 0.9, one rank, "
        "read from its raw stresses at the contact quadrature points; here the finest P2 "
        "row above):",
        "",
        "| | the other package's demo | here |",
        "|---|---|---|",
        *other_package_rows(),
        "| contact | Nitsche, penalty 100 E (frictionless), 10 E (Coulomb), P1 | "
        "mortar multipliers (λn, λt), semismooth Newton on the active, stick and slip "
        "sets; P1 and P2 |",
        "| mesh | quadrilaterals (recombined, then split: sizes about halved), target "
        "size 0.03 within R/2 of the upper pole growing to 0.12 at R, a gap 0.01 between "
        "the poles | triangles, size h within 1 of the poles growing at 0.25 to 1, "
        "touching poles |",
        "| load path | traction ramped in 4 frictionless steps, u_x = 0 on x = 0; then "
        "the top's vertical increments held, x = 0 released, 8 tangential steps | the "
        "same, the second stage a second problem (`solve(after=...)`) |",
        "| solver | Newton (tolerance 1e-7), GAMG-preconditioned CG, then GMRES | "
        "one LU solve (MUMPS) per active-set iteration |",
        "| checks | writes the analytic traction beside its own, asserts nothing | "
        "equilibrium to 1e-10 relative, c within one element and q within 10% L2 (P2) "
        "asserted |",
        "",
        "Inclined block (tan(alpha) = 0.1, μ = 0.5, all sliding), push reaction / vertical load:",
        "",
        "| P | ratio | exact | relative error | solves |",
        "|---|---:|---:|---:|---:|",
        *[
            f"| P{r['degree']} | {r['ratio']:.10f} | {r['expected']:.10f} | "
            f"{r['error']:.1e} | {r['solves']} |"
            for r in mine
            if r["scene"] == "inclined-block"
        ],
        "",
        "Frictional patch tests (7/5 non-matching blocks; max relative errors):",
        "",
        "| case | P | λn | λt | u | active | stick | solves |",
        "|---|---|---:|---:|---:|---|---:|---:|",
        *[patch_row(r) for r in mine if r["scene"].startswith("patch")],
    ]
    write_section(out / "report.md", "friction", lines)
if failed:
    raise SystemExit("friction: " + "; ".join(failed))
# -

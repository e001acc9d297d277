# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Regularized (penalty) friction against the Lagrange multipliers: Cattaneo-Mindlin
#
# `RegularizedFrictionProblem` (in `dolfinx_contact_s2s.friction`) is the cheap
# alternative to the multipliers of `FrictionalContactProblem`: no multiplier among the
# unknowns, the tractions computed from the displacement at every multiplier node $j$,
#
# $$\lambda_{n,j} = c_j \max(0, -\tilde g_j), \qquad \lambda_{t,j} = \lambda^*_j
# \min\left(1, \frac{\mu \lambda_{n,j}}{|\lambda^*_j|}\right), \qquad \lambda^*_j =
# \lambda^{\mathrm{prev}}_{t,j} + c_j \Delta\tilde s_j,$$
#
# a normal penalty on the weighted gap and Coulomb's return mapping on the weighted slip
# increment of the load step (stick inside the disk $|\lambda_t| \le \mu\lambda_n$, slip
# on its rim), with $c_j = \kappa \bar E / \int \mu_j h$. Each load step is one nonlinear
# equilibrium, solved by Newton's method with its consistent tangent. The bodies
# penetrate by $\lambda_n / \varepsilon$ and slip elastically by $\lambda_t /
# \varepsilon$ where they should stick: the error falls like $1/\kappa$.
#
# **The scene** is `paper.friction.cattaneo_mindlin`'s (two identical half cylinders,
# $R = 1$, $E = 1$, $\nu = 0.3$, plane strain, graded for $a = 0.05$ with 20 elements
# across $2a$, P2): the upper face moved down in four frictionless steps, then sideways
# in four steps with $\mu = 0.2$ ($Q/(\mu P) \approx 0.5$), solved once by the Lagrange
# solver and once by the regularized one per $\kappa = 10, \dots, 10^4$ on the same mesh.
# Measured against the Lagrange solution: the stick half-width $c$ (the outermost
# sticking node) in elements, and the relative L2 distances over $[-a, a]$ of the shear
# $q = \lambda_t$ and the pressure $p = \lambda_n$; and the wall time of the load path.
#
# Checked: the errors fall like $1/\kappa$ (the log-log slope of $q$'s error within
# $[-1.2, -0.8]$) and $c$ is the Lagrange solution's at $\kappa \ge 100$; the exit status
# is non-zero otherwise. It writes `results/friction_penalty.json`,
# `results/friction_penalty.png` and the section "friction-penalty" of
# `results/report.md`. Run it as `python3 demos/demo_friction_penalty.py` or with
# `mpirun -n 2`; `--smoke` runs $\kappa = 10, 100, 1000$ only.

# +
from mpi4py import MPI

import numpy as np

from paper.friction_penalty import study
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, verdict, write_section

args = demo_parser(
    "Regularized (penalty) friction against the Lagrange solution on Cattaneo-Mindlin",
    "penalty factors 10, 100, 1000 only",
).parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
PENALTIES = (1e1, 1e2, 1e3) if args.smoke else (1e1, 1e2, 1e3, 1e4)
failed = []
# -

# ## Cattaneo-Mindlin, P2, 20 elements across the contact

# +
records = study(comm, degree=2, across=20, penalties=PENALTIES)
lagrange = records[0]
for rec in records:
    for key in ("x", "q", "p"):
        rec.pop(key)
    rec["ranks"] = comm.size
    name = "Lagrange" if rec["penalty"] is None else f"kappa = {rec['penalty']:.0e}"
    log(
        f"{name:>14}: c {rec['c']:.5f} ({rec['c_error_elements']:.2f} elements from the "
        f"Lagrange c), L2 q {rec['q_L2_error']:.2e}, p {rec['p_L2_error']:.2e}, q vs the "
        f"closed form {rec['q_exact_L2_error']:.2%}; {rec['seconds']:.2f} s, "
        f"{sum(rec['iterations'])} iterations {rec['iterations']}, {rec['unknowns']} unknowns"
    )
penalty = [r for r in records if r["penalty"] is not None]
kappa = np.array([r["penalty"] for r in penalty])
slopes = {
    key: float(np.polyfit(np.log(kappa), np.log([r[f"{key}_L2_error"] for r in penalty]), 1)[0])
    for key in ("q", "p")
}
log(f"log-log slopes of the L2 errors against kappa: q {slopes['q']:.3f}, p {slopes['p']:.3f}")
if not -1.2 <= slopes["q"] <= -0.8:
    failed.append(f"q's error falls with slope {slopes['q']:.2f}, not -1")
for r in penalty:
    if r["penalty"] >= 100 and r["c_error_elements"] > 0:
        failed.append(f"kappa = {r['penalty']:g}: c off by {r['c_error_elements']:.2f} elements")
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "friction_penalty.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for key, marker in (("q", "o"), ("p", "s")):
        errors = [r[f"{key}_L2_error"] for r in penalty]
        left.loglog(kappa, errors, marker + "-", label=f"{key}: L2 distance to Lagrange")
        right.semilogy([r["seconds"] for r in penalty], errors, marker, label=key)
    left.loglog(kappa, penalty[0]["q_L2_error"] * kappa[0] / kappa, "k:", lw=0.8, label="1/κ")
    right.axvline(lagrange["seconds"], color="0.5", lw=0.8, label="Lagrange solver")
    for r in penalty:
        right.annotate(f"κ={r['penalty']:.0e}", (r["seconds"], r["q_L2_error"]), fontsize=7)
    left.set_xlabel("penalty factor κ")
    left.set_ylabel("relative L2 distance over [-a, a]")
    right.set_xlabel("wall time of the load path (s)")
    right.set_xlim(0, 1.2 * max(r["seconds"] for r in records))
    left.legend(fontsize="small")
    right.legend(fontsize="small")
    fig.suptitle("Regularized friction vs Lagrange: Cattaneo-Mindlin, P2, 20 elements across 2a")
    fig.tight_layout()
    fig.savefig(out / "friction_penalty.png", dpi=120)

    def row(r):
        name = "Lagrange" if r["penalty"] is None else f"{r['penalty']:.0e}"
        return (
            f"| {name} | {r['c']:.5f} | {r['c_error_elements']:.2f} | {r['q_L2_error']:.2e} | "
            f"{r['p_L2_error']:.2e} | {r['q_exact_L2_error']:.2%} | {r['seconds']:.2f} | "
            f"{' '.join(map(str, r['iterations']))} | {r['unknowns']} |"
        )

    mine = [r for r in merged if r["ranks"] == comm.size]
    lines = [
        "## Regularized (penalty) friction against the Lagrange multipliers",
        "",
        verdict("demo_friction_penalty.py", comm, args.smoke, failed),
        "",
        "Cattaneo-Mindlin (P2, 20 elements across 2a, μ = 0.2, the load path of the friction "
        "section) by `FrictionalContactProblem` and by `RegularizedFrictionProblem` per "
        "penalty factor κ on the same mesh; c: the outermost sticking node, its distance to "
        "the Lagrange c in elements; L2: relative distances to the Lagrange λt (q) and λn (p) "
        "over [-a, a]; q exact: to Cattaneo and Mindlin's shear; time: the eight solves; "
        "iterations per load step (linear solves; the regularized solver counts its first "
        "residual too):",
        "",
        "| κ | c | c vs Lagrange (h) | L2(q) | L2(p) | q exact | s | iterations | unknowns |",
        "|---|---:|---:|---:|---:|---:|---:|---|---:|",
        *[row(r) for r in mine],
        "",
        f"Log-log slopes of the L2 distances against κ: q {slopes['q']:.3f}, "
        f"p {slopes['p']:.3f} (1/κ).",
        "",
        "![Regularized friction](friction_penalty.png)",
    ]
    write_section(out / "report.md", "friction-penalty", lines, after="friction")
if failed:
    raise SystemExit("friction-penalty: " + "; ".join(failed))
# -

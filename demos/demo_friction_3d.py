# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# # Coulomb friction in 3D: the frictional patch tests and Cattaneo-Mindlin between spheres
#
# In 3D the tangential multiplier has two components per node, along the tangents
# $\mathbf T_1 = \mathbf a \times \mathbf N / |\mathbf a \times \mathbf N|$ and
# $\mathbf T_2 = \mathbf N \times \mathbf T_1$ of one axis $\mathbf a$ per pair (by
# default the Cartesian axis least aligned with the contactor's mean normal). Coulomb's
# law is the disk $|\lambda_t| \le \mu \lambda_n$: where it slips, $\lambda_t$ points
# along the slip $\tilde s$, and each semismooth Newton step linearizes that direction
# (Hüeber, Stadler and Wohlmuth). The disk and the slip turn with the basis, so the
# answer does not depend on $\mathbf a$.
#
# **Frictional patch tests.** Two non-matching blocks (tetrahedra against hexahedra, 3
# and 4 across, also with the nodes moved at random in the contact plane) in the uniform
# stress $\sigma_{zz} = -p$, $\sigma_{xz} = \tau_x$, $\sigma_{yz} = \tau_y$: a shear
# $|\tau| < \mu p$ sticks everywhere with $\lambda_t = \tau$; the top moved along 30
# degrees beyond the stick limit slips everywhere with $\lambda_t = \mu p\, \mathbf d /
# |\mathbf d|$. Checked to $10^{-10}$ relative (the exit status is non-zero if not).
#
# **Inclined block.** A block pushed up the tilted plane $z = 0.5 + 0.1 x$ ($\mu = 0.5$,
# $u_y = 0$), all of it sliding: the push's reaction over the vertical load is
# $(\mu + \tan\alpha)/(1 - \mu\tan\alpha)$, checked to $10^{-8}$.
#
# **Cattaneo-Mindlin.** Two identical spheres ($R = 1$, $E = 1$, $\nu = 0.3$, the half
# model $y \ge 0$), the upper flat face moved down in one frictionless step (frictionless
# linear contact does not depend on the path; $a \approx 0.05$), then along $x$ in four
# steps with $\mu = 0.2$
# ($Q/(\mu P) \approx 0.45$): the stick radius $c = a (1 - Q/(\mu P))^{1/3}$ and
# Mindlin's shear against $\lambda_t$, on meshes of uniform size $h$ within $2a$ of the
# contact. Then from a user's mesh (size $R/40$ near the contact, a linear geometry)
# refined by the solution: `refine_contact_zone` with the load path, around the contact
# front and the stick front (brackets of their radii) and where $\lambda_n$ or
# $\lambda_t$ is far from the plane through its neighbours' values
# (`pressure_tolerance`), the new nodes on the spheres, the mesh lifted to P2
# (`paper.friction3d.cattaneo_mindlin_adaptive`, two refinements). There $\nu = 0$:
# Mindlin's solution takes the shear along $Q$ everywhere, exact only when Cerruti's
# kernel is isotropic ($\nu = 0$); the tangential motion in one step (monotonic: the
# same end as four steps, to 1e-4 of the peak shear).
# Checked: $c$ within one element with P2; the L2 errors of $q$ and $p$ and the 2% for
# $c$ are reported. `--fine` refines four times instead, to brackets of 1% and
# `pressure_tolerance` 1%, and checks the bounds: $c$ within 2% and one element,
# $q$ within 5% (L2). Its last mesh has about a million unknowns, whose MUMPS factors
# (about 35 GB) do not fit in this machine's 24 GB: they go out of core (ICNTL(22) = 1,
# in `$MUMPS_OOC_TMPDIR`, by default `/tmp`; about 10 GB of memory and 40 GB of disk,
# an hour and a half on one rank). It writes `results/friction3d.json`, `results/friction3d.png`
# and the section "friction-3d" of `results/report.md`. Run it as
# `python3 demos/demo_friction_3d.py` or `mpirun -n 2 python3 demos/demo_friction_3d.py`;
# `--smoke` runs the patch tests, the coarsest P1 Cattaneo-Mindlin mesh and the refined
# run's first mesh only.

# +
from mpi4py import MPI

import numpy as np

from paper.friction3d import (
    CM_MU,
    cattaneo_mindlin,
    cattaneo_mindlin_adaptive,
    inclined_block,
    patch,
)
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, verdict, write_section

parser = demo_parser(
    "Coulomb friction in 3D: patch tests, Cattaneo-Mindlin between spheres",
    "the patch tests and the coarsest P1 Cattaneo-Mindlin mesh only",
)
parser.add_argument(
    "--fine",
    action="store_true",
    help="refine Cattaneo-Mindlin four times to 1%% brackets (MUMPS out of core) and check "
    "c within 2%% and q within 5%%",
)
args = parser.parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
PATCH_BOUND, INCLINE_BOUND = 1e-10, 1e-8
C_BOUND, Q_BOUND = 0.02, 0.05  # issue [4/6]: c within 2%, q within 5% (L2), with P2
SIZES = {1: (0.02,)} if args.smoke else {1: (0.02, 0.01, 0.007), 2: (0.02, 0.014, 0.01)}
records, failed = [], []
# -

# ## The frictional patch tests

# +
for case in ("stick", "slip"):
    for cells, degree in ((("tet", "hex"), 1), (("hex", "tet"), 1), (("tet", "hex"), 2)):
        for seed in (None, 1):
            rec = patch(case, cells, degree, seed, comm=comm)
            rec["scene"] = f"patch-3d-{case}"
            rec["ranks"] = comm.size
            records.append(rec)
            worst = max(rec["lambda_n_error"], rec["lambda_t_error"], rec["u_error"])
            expected = rec["multipliers"] if case == "stick" else 0
            log(
                f"patch {case} {rec['cells']} P{degree} seed {seed}: lambda_n "
                f"{rec['lambda_n_error']:.1e}, lambda_t {rec['lambda_t_error']:.1e}, u "
                f"{rec['u_error']:.1e}; stick {rec['stick']}/{rec['multipliers']}, "
                f"{rec['solves']} solves"
            )
            if worst > PATCH_BOUND or rec["stick"] != expected or not rec["converged"]:
                failed.append(f"patch {case} {rec['cells']} P{degree} seed {seed}")
# -

# ## The inclined block

# +
for cells, degree in ((("tet", "hex"), 1), (("hex", "tet"), 1), (("tet", "hex"), 2)):
    rec = inclined_block(comm, degree, cells=cells)
    rec["cells"], rec["ranks"] = "-".join(cells), comm.size
    records.append(rec)
    log(
        f"inclined block {rec['cells']} P{degree}: ratio {rec['ratio']:.10f}, error "
        f"{rec['error']:.1e}, {rec['solves']} solves"
    )
    if rec["error"] > INCLINE_BOUND or not rec["sliding"]:
        failed.append(f"inclined block {rec['cells']} P{degree}: {rec}")
# -

# ## Cattaneo-Mindlin between two spheres

# +
traction = None
for degree, sizes in SIZES.items():
    for h in sizes:
        rec = cattaneo_mindlin(comm, degree, h)
        r, q, p = rec.pop("r"), rec.pop("q"), rec.pop("p")
        if h == sizes[-1]:  # the finest mesh of the highest degree
            traction = rec, r, q, p
        rec["ranks"] = comm.size
        records.append(rec)
        log(
            f"P{degree} h = {h}: {rec['across']:.1f} across 2a, c {rec['c']:.5f} exact "
            f"{rec['c_exact']:.5f} ({rec['c_error_elements']:.2f} elements, "
            f"{rec['c_error']:.2%}), L2 q {rec['q_L2_error']:.2%}, p {rec['p_L2_error']:.2%}, "
            f"Q/(mu P) {rec['Q_over_muP']:.3f}; solves per step {rec['solves_per_step']}, "
            f"{rec['unknowns']} unknowns, {rec['seconds']:.1f} s"
        )
        if degree == 2 and rec["c_error_elements"] > 1.0:
            failed.append(f"P2 h = {h}: c off by {rec['c_error_elements']:.2f} h")
# -

# ## Cattaneo-Mindlin between spheres, refined by the solution

# +
FINE = {"tolerance": 0.01, "pressure_tolerance": 0.01, "max_steps": 0 if args.smoke else 4}
COARSE = {"tolerance": 0.06, "pressure_tolerance": 0.05, "max_steps": 0 if args.smoke else 2}
rec = cattaneo_mindlin_adaptive(
    comm,
    2,
    40,
    nu=0.0,
    steps=1,
    petsc_options={"mat_mumps_icntl_22": 1} if args.fine else None,
    **(FINE if args.fine else COARSE),
)
for key in ("r", "q", "p"):
    rec.pop(key)
rec["ranks"] = comm.size
records.append(rec)
for k, row in enumerate(rec["steps"]):
    log(
        f"refined P2 mesh {k}: {row['unknowns']} unknowns, bracket {row['relative']:.3f} of "
        f"the radius, c (middle) {row['c_middle_error']:.2%}, L2 q {row['q_L2_error']:.2%}, "
        f"p {row['p_L2_error']:.2%}; {row['solves']} solves, {row['seconds']:.1f} s"
    )
if abs(rec["c_middle"] - rec["c_exact"]) > rec["h"]:
    failed.append(f"refined P2: c off by {abs(rec['c_middle'] - rec['c_exact']) / rec['h']:.2f} h")
if args.fine and not args.smoke and rec["c_middle_error"] > C_BOUND:
    failed.append(f"refined P2: c off by {rec['c_middle_error']:.2%}")
if args.fine and not args.smoke and rec["q_L2_error"] > Q_BOUND:
    failed.append(f"refined P2: q off by {rec['q_L2_error']:.2%} (L2)")
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "friction3d.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rec, r, q, p = traction
    a, c, p0 = rec["a"], rec["c_exact"], rec["p0"]
    s = np.linspace(0, 1.3 * a, 401)
    mindlin = np.sqrt(np.clip(a**2 - s**2, 0, None)) - np.sqrt(np.clip(c**2 - s**2, 0, None))
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(s / a, np.sqrt(np.clip(1 - s**2 / a**2, 0, None)), "k--", lw=0.8, label=r"$\mu p$")
    ax.plot(s / a, mindlin / a, "k-", lw=0.8, label="q(r) (Mindlin)")
    keep = r < 1.3 * a
    ax.plot(r[keep] / a, p[keep] / p0, "s", ms=3, mfc="none", label=r"$\lambda_n / p_0$")
    ax.plot(r[keep] / a, q[keep] / (CM_MU * p0), "o", ms=3, label=r"shear along x")
    ax.axvline(c / a, color="0.6", lw=0.6)
    ax.set_xlabel("r / a")
    ax.set_ylabel(r"traction / ($\mu p_0$), pressure / $p_0$")
    ax.set_title(
        f"Cattaneo-Mindlin, two spheres, P{rec['degree']}, h = {rec['h']}, c/a = {c / a:.3f}"
    )
    ax.legend(loc="upper right", fontsize="small")
    fig.tight_layout()
    fig.savefig(out / "friction3d.png", dpi=120)

    mine = [x for x in merged if x["ranks"] == comm.size]
    patches = [x for x in mine if x["scene"].startswith("patch-3d")]
    lines = [
        "## Coulomb friction in 3D",
        "",
        verdict("demo_friction_3d.py", comm, args.smoke, failed),
        "",
        f"Frictional patch tests ({len(patches)} cases: stick and slip; tets/hexes, P1/P2, "
        "nodes moved or not): largest relative errors "
        + ", ".join(
            f"{k} {max(x[k + '_error'] for x in patches):.1e}"
            for k in ("lambda_n", "lambda_t", "u")
        )
        + f"; solves {sorted({x['solves'] for x in patches})}.",
        "",
        "Inclined block in 3D (the contact plane z = 0.5 + 0.1 x, μ = 0.5, u_y = 0, all "
        "sliding), push reaction / vertical load against 0.6315789474: "
        + ", ".join(
            f"{x['cells']} P{x['degree']} {x['error']:.1e} ({x['solves']} solves)"
            for x in mine
            if x["scene"] == "inclined-block-3d"
        )
        + ".",
        "",
        "Cattaneo-Mindlin (two spheres R = 1, a ≈ 0.05, μ = 0.2; h: element size within 2a "
        "of the contact; c: the outermost sticking node; errors relative L2 over the "
        "contact surface; solves per load step: 1 frictionless, then 4 tangential):",
        "",
        "| P | h | 2a/h | Q/(μP) | c | c exact | error (h) | error | L2(q) | L2(p) | "
        "solves per step | unknowns | s |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|",
        *[
            f"| P{x['degree']} | {x['h']} | {x['across']:.1f} | {x['Q_over_muP']:.3f} | "
            f"{x['c']:.5f} | {x['c_exact']:.5f} | {x['c_error_elements']:.2f} | "
            f"{x['c_error']:.1%} | {x['q_L2_error']:.1%} | {x['p_L2_error']:.1%} | "
            f"{' '.join(map(str, x['solves_per_step']))} | {x['unknowns']} | "
            f"{x['seconds']:.1f} |"
            for x in mine
            if x["scene"] == "cattaneo-mindlin-3d"
        ],
        "",
        "![Cattaneo-Mindlin in 3D](friction3d.png)",
        "",
        "Refined by the solution (P2 from a user's mesh of size R/40 near the contact, "
        "around the contact and stick fronts and where λ is far from the plane through "
        "its neighbours' values; nu = 0, one tangential step; bracket: the widest "
        "front's, relative to its radius, refined while above "
        + ", ".join(f"{x['tolerance']:.0%}" for x in mine if x["scene"].endswith("adaptive"))
        + "; c: the middle of the stick front's bracket):",
        "",
        "| mesh | unknowns | bracket | c error | L2(q) | L2(p) | solves | s |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
        *[
            f"| {k} | {row['unknowns']} | {row['relative']:.3f} | "
            f"{row['c_middle_error']:.2%} | {row['q_L2_error']:.1%} | "
            f"{row['p_L2_error']:.1%} | {row['solves']} | {row['seconds']:.1f} |"
            for x in mine
            if x["scene"] == "cattaneo-mindlin-3d-adaptive"
            for k, row in enumerate(x["steps"])
        ],
    ]
    write_section(out / "report.md", "friction-3d", lines)
if failed:
    raise SystemExit("friction 3D: " + "; ".join(failed))
# -

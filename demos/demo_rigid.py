# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Rigid obstacles: a cylinder on a rigid plane, and a flat punch
#
# Most contact scenes have one body whose deformation nobody wants: a floor, a die, a
# punch. `dolfinx_contact_s2s.rigid_surface(mesh, facet_tags, tag, motion=...)` makes
# tagged facets of a mesh that carries no form a rigid target, and
# `plane_obstacle`, `circle_obstacle` or `obstacle(distance, gradient)` give analytic
# ones. The saddle point of Eq. (18) then has no target block: the coupling of Eq. (17)
# is integrated as for a deformable target, and the target's known (prescribed) motion
# $\mathbf U_T$ moves the gap, $\mathbf G + \mathbf B_T \mathbf U_T$. An analytic
# obstacle with signed distance $d$ constrains $\int \mu_k (d/|\nabla d| + \hat{\mathbf
# n} \cdot \mathbf u)\, ds \ge 0$ on the contactor segments.
#
# Two closed forms check it:
#
# - **Hertz**: an elastic cylinder (plane strain, radius $R$) pressed by $F$ per unit
#   length on a rigid plane: $1/E^* = (1 - \nu^2)/E$, $a = \sqrt{4FR/(\pi E^*)}$,
#   $p_0 = 2F/(\pi a)$, $p(x) = p_0\sqrt{1 - x^2/a^2}$. P2 from 10 elements across the
#   contact (no node at $\pm a$), the edge and the pressure refined adaptively, the edge
#   read by `contact_zones`. The same scene with the floor meshed as an
#   elastic body $10^6$ times stiffer agrees to the order of $E_1/E_2$, with more
#   unknowns.
# - **Flat punch**: an elastic layer pressed by $F$ onto a rigid flat punch of
#   half-width $a$: $p(x) = F / (\pi\sqrt{a^2 - x^2})$ on a half-plane. The interior
#   $|x| \le a/2$ is compared; the edge is singular and its nodal value is reported.
#
# It writes `results/rigid.json` (records of every rank count side by side),
# `results/rigid.png` and the section "rigid" of `results/report.md`. Run it as
# `python3 demos/demo_rigid.py` or `mpirun -n 2 python3 demos/demo_rigid.py`;
# `--smoke` runs coarser meshes.

# +
import math

from mpi4py import MPI

import numpy as np

from paper.hertz.plane import PlaneCase, adaptive_run
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, write_section
from paper.rigid import flat_punch, hertz_on_plane

args = demo_parser("Rigid obstacles: Hertz on a rigid plane, flat punch", "coarser").parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
# -

# ## Hertz: a cylinder on a rigid plane

# +
E, nu, R, a_exact = 1.0, 0.3, 1.0, 0.05
E_star = E / (1 - nu**2)
F = a_exact**2 * math.pi * E_star / (4 * R)
p0 = 2 * F / (math.pi * a_exact)
# A size that is not a divisor of a: the edge falls inside an element, as on a user's mesh.
h = a_exact / (1.83 if args.smoke else 3.65)
records, curves = [], {}
hertz = {}
for target in ("rigid", "plane", "elastic"):
    r = hertz_on_plane(comm, F=F, R=R, h=h, target=target, target_E=1e6 * E)
    hertz[target] = r
    curves[f"Hertz, {target} floor"] = (r.x / a_exact, r.pressure / p0)
    records.append(
        {
            "study": "rigid",
            "scene": f"hertz-{target}",
            "ranks": comm.size,
            "unknowns": r.unknowns,
            "seconds": r.seconds,
            "h": h,
        }
    )
    log(f"Hertz, {target:7s} floor: {r.unknowns} unknowns, {r.seconds:.2f} s")
# -

# The accuracy of $a$, $p_0$ and the pressure: P2 from 10 elements across the contact,
# the edge and the pressure refined by `refine_contact_zone` (the edge is read by
# `contact_zones`; refined with linear geometry, the refined arc nodes moved onto the
# circle, each refined mesh lifted to a curved quadratic geometry for the solve).

# +
for target in ("rigid", "plane"):
    case = PlaneCase(a_over_R=0.025, degree=2, target=target)
    run = adaptive_run(case, pressure_tolerance=0.01, max_steps=8, comm=comm)
    errors = {"a": abs(run["a_error"]), "p0": abs(run["p0_error"]), "L2": run["l2_error"]}
    records.append(
        {
            "study": "rigid",
            "scene": f"hertz-{target}-p2-adaptive",
            "ranks": comm.size,
            "unknowns": run["unknowns"],
            "seconds": run["seconds"],
            "steps": len(run["steps"]),
            "errors": errors,
        }
    )
    log(
        f"Hertz, {target:7s} floor, P2 adaptive: a {errors['a']:.2%}, p0 {errors['p0']:.2%}, "
        f"L2 {errors['L2']:.2%}; {run['unknowns']} unknowns, {len(run['steps'])} steps"
    )
    if not (errors["a"] < 0.01 and errors["p0"] < 0.02 and errors["L2"] < 0.05):
        raise SystemExit(f"Hertz on a {target} floor misses its tolerances: {errors}")
difference = np.max(np.abs(hertz["elastic"].pressure - hertz["rigid"].pressure))
difference /= np.max(hertz["rigid"].pressure)
saved = hertz["elastic"].unknowns - hertz["rigid"].unknowns
records.append(
    {
        "study": "rigid",
        "scene": "hertz-stiff-vs-rigid",
        "ranks": comm.size,
        "difference": float(difference),
        "E2_over_E1": 1e6,
        "unknowns_saved": saved,
    }
)
log(
    f"stiff elastic floor (E2/E1 = 1e6) against rigid: max |d lambda| / max lambda = "
    f"{difference:.2e}; the rigid floor saves {saved} unknowns"
)
if difference > 1e-4:
    raise SystemExit("the stiff elastic floor differs from the rigid one by more than 100 E1/E2")
# -

# ## A flat punch under an elastic layer

# +
a, force = 1.0, 1.0
n_under = 20 if args.smoke else 40
punch = {}
for depth in (20.0, 40.0):
    r = flat_punch(comm, F=force, a=a, width=20.0, depth=depth, elements_under=n_under, degree=2)
    inner = r.x <= 0.5 * a + 1e-12
    exact = force / (math.pi * np.sqrt(a**2 - r.x[inner] ** 2))
    punch[depth] = (r, inner, float(np.max(np.abs(r.pressure[inner] / exact - 1))))
(r20, in20, err20), (r40, in40, err40) = punch[20.0], punch[40.0]
change = float(
    np.max(np.abs(np.interp(r20.x[in20], r40.x[in40], r40.pressure[in40]) / r20.pressure[in20] - 1))
)
edge = np.flatnonzero(r20.pressure > 0)[-1]
curves["flat punch (x/a, p a/F)"] = (r20.x / a, r20.pressure * a / force)
records.append(
    {
        "study": "rigid",
        "scene": "flat-punch",
        "ranks": comm.size,
        "force_error": abs(r20.force / (force / 2) - 1),
        "interior_error": err20,
        "depth_doubled_change": change,
        "edge_pressure": float(r20.pressure[edge]),
        "mean_pressure": force / (2 * a),
        "unknowns": r20.unknowns,
        "elements_under": n_under,
    }
)
log(
    f"flat punch: force error {abs(r20.force / (force / 2) - 1):.1e}, interior |x| <= a/2 within "
    f"{err20:.2%} of the half-plane, depth doubled changes it by {change:.2%}; edge node "
    f"pressure {r20.pressure[edge]:.3g} (mean F/2a = {force / (2 * a):.3g}: singular)"
)
if not args.smoke and not (err20 < 0.02 and change < 0.005):
    raise SystemExit("the flat punch misses its tolerances")
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "rigid.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    s = np.linspace(0, 1, 200)
    axes[0].plot(s, np.sqrt(1 - s**2), "k-", lw=0.8, label="Hertz")
    for name, (x, p) in curves.items():
        if name.startswith("Hertz"):
            axes[0].plot(x, p, ".", label=name)
    axes[0].set_xlim(0, 1.5)
    axes[0].set_xlabel("x / a")
    axes[0].set_ylabel("p / p0")
    axes[0].legend()
    x, p = curves["flat punch (x/a, p a/F)"]
    xs = np.linspace(0, 0.99, 200)
    axes[1].plot(xs, 1 / (np.pi * np.sqrt(1 - xs**2)), "k-", lw=0.8, label="half-plane")
    axes[1].plot(x, p, ".", label="rigid punch, P2")
    axes[1].set_xlim(0, 1.2)
    axes[1].set_ylim(0, 3)
    axes[1].set_xlabel("x / a")
    axes[1].set_ylabel("p a / F")
    axes[1].legend()
    fig.tight_layout()
    fig.savefig(out / "rigid.png", dpi=120)

    by = {(r["scene"], r["ranks"]): r for r in merged}
    ranks = sorted({r["ranks"] for r in merged})
    lines = [
        "## Rigid obstacles",
        "",
        "`demos/demo_rigid.py`: ![pressures](rigid.png)",
        "",
        f"Hertz, an elastic cylinder on a floor (plane strain, P2 at h = a/{a_exact / h:.3g}, "
        "no node at +-a): the floor rigid (meshed), an analytic plane, or meshed elastic "
        "with E2/E1 = 1e6; what the rigid floor saves.",
        "",
        "| ranks | floor | unknowns | time (s) |",
        "|---:|---|---:|---:|",
    ]
    for n in ranks:
        for target in ("rigid", "plane", "elastic"):
            rec = by.get((f"hertz-{target}", n))
            if rec is None:  # a rank count run by an older version
                continue
            lines.append(f"| {n} | {target} | {rec['unknowns']} | {rec['seconds']:.3f} |")
        rec = by.get(("hertz-stiff-vs-rigid", n))
        if rec is None:  # a rank count run by an older version
            continue
        lines.append(
            f"| {n} | elastic - rigid | {rec['unknowns_saved']} saved | max abs(d lambda) / max "
            f"lambda = {rec['difference']:.2e} |"
        )
    lines += [
        "",
        "P2 from 10 elements across, the edge and the pressure refined (`refine_contact_zone`).",
        "",
        "| ranks | floor | a error | p0 error | L2(p) error | unknowns | steps | time (s) |",
        "|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for n in ranks:
        for target in ("rigid", "plane"):
            rec = by.get((f"hertz-{target}-p2-adaptive", n))
            if rec is None:  # a rank count run by an older version
                continue
            e = rec["errors"]
            lines.append(
                f"| {n} | {target} | {e['a']:.2%} | {e['p0']:.2%} | {e['L2']:.2%} | "
                f"{rec['unknowns']} | {rec['steps']} | {rec['seconds']:.2f} |"
            )
    lines += [
        "",
        "Flat punch on an elastic layer (P2), against the half-plane p = F / (pi sqrt(a^2 - "
        "x^2)) for |x| <= a/2; the edge node is singular and only reported.",
        "",
        "| ranks | under punch | force error | interior error | depth doubled | edge p / mean |",
        "|---:|---:|---:|---:|---:|---:|",
    ]
    for n in ranks:
        rec = by.get(("flat-punch", n))
        if rec is None:  # a rank count run by an older version
            continue
        lines.append(
            f"| {n} | {rec['elements_under']} | {rec['force_error']:.1e} | "
            f"{rec['interior_error']:.2%} | {rec['depth_doubled_change']:.2%} | "
            f"{rec['edge_pressure'] / rec['mean_pressure']:.1f} |"
        )
    write_section(out / "report.md", "rigid", lines)
# -

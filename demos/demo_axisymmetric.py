# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Axisymmetric Hertz: a sphere on a rigid plane, and two elastic spheres
#
# A sphere is a body of revolution: `Material(E, nu, plane="axisymmetric")` models it on
# a mesh of its half-section in the $(r, z)$ plane, with the hoop strain $u_r/r$ and the
# weight $2\pi r$ on every integral, and `contact_pair(..., axisymmetric=True)` weights
# the coupling of Eq. (17) by $2\pi r$: the multiplier is the contact pressure and the
# loads are total forces. The solid spheres need $u_r = 0$ on the axis.
#
# Hertz's point contact: $1/R = 1/R_1 + 1/R_2$, $1/E^* = (1 - \nu_1^2)/E_1 + (1 -
# \nu_2^2)/E_2$ (a rigid body adds 0), $a = (3FR/(4E^*))^{1/3}$, $p_0 = 3F/(2\pi a^2)$,
# $p(r) = p_0\sqrt{1 - r^2/a^2}$. It is the solution for two half-spaces: each body here
# is a hemisphere, its pole at the contact point and its flat face (loaded by a uniform
# pressure, total $F$, or held, $u_z = 0$) at distance $R_i$; the load gives $a = 0.05
# R_1$. The hemispheres' finite size is a model error of order $a/R$: we measure it by
# halving $a/R_1$ at the same $a/h$.
#
# The meshes are made as a user would: Gmsh, size $h$ within $R_1/10$ of the contact
# point, growing to $R/8$, no node placed at $r = a$; $h = a/9.3$, about 9 elements
# across the contact radius and deliberately not a divisor of $a$. Everything is read
# with the library's post-processing: the edge from `contact_zones` (its "gap" estimate,
# inside the bracket of the last active and first inactive node), $p_0$ at the axis node
# and the L2 error over the contact disk with the weight $2\pi r$ from
# `pressure_profile`, the force from `contact_force`.
#
# It writes `results/axisymmetric.json` (records of every rank count side by side),
# `results/axisymmetric.png` and the section "axisymmetric" of `results/report.md`. Run
# it as `python3 demos/demo_axisymmetric.py` or `mpirun -n 2 python3
# demos/demo_axisymmetric.py`; `--smoke` runs a few coarse cases only.

# +
from mpi4py import MPI

import numpy as np

from paper.hertz.axisymmetric import model_error, run
from paper.records import merge_rank_records
from paper.report import demo_parser, output_folder, rank0_print, write_section

args = demo_parser(
    "Axisymmetric Hertz: sphere on a rigid plane, two spheres", "a few coarse cases"
).parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)
SCENES = ("sphere-on-plane", "two-spheres")
records, curves = [], {}


def show(rec, label):
    """Log a record and keep its pressure for the plot."""
    r, p = rec.pop("r"), rec.pop("pressure")
    records.append(rec)
    curves[(rec["scene"], label)] = (r / rec["a_exact"], p / rec["p0_exact"])
    lo, hi = rec["bracket"]
    log(
        f"{rec['scene']:15s} {label:28s}: a {rec['a_error']:.2%}, p0 {rec['p0_error']:.2%}, "
        f"L2 {rec['L2_error']:.2%} (bracket [{lo / rec['a_exact']:.4f}, "
        f"{hi / rec['a_exact']:.4f}] a); {rec['unknowns']} unknowns, {rec['solves']} solves"
        + (f", {len(rec['steps']) - 1} refinements" if "steps" in rec else "")
    )


# -

# ## A plain mesh at about 9 elements across the contact radius
#
# One solve, curved geometry of the displacement's degree, triangles and
# quadrilaterals: what a user gets without the adaptive edge.

# +
for scene in SCENES:
    for degree in (2,) if args.smoke else (2, 1):
        for cell in ("triangle",) if args.smoke else ("triangle", "quadrilateral"):
            rec = run(comm, scene, degree=degree, cell=cell, keep_pressure=True)
            show(rec, f"P{degree} {cell} uniform")
# -

# ## The adaptive edge
#
# Triangles with linear geometry from the same size, refined by `refine_contact_zone`
# until the edge's bracket is 1% of the zone's radius, and inside the zone until the
# pressure's second difference is below a tolerance (the axis node, the peak, needs it),
# the new nodes on the contact arcs moved onto the spheres (`snap`), for P2 every
# refined mesh lifted to a curved quadratic geometry (`geometry_degree=2`), every solve
# restarted from the previous zone.

# +
PRESSURE_TOLERANCE = {1: 0.005, 2: 0.01}
for scene in SCENES:
    for degree in (1,) if args.smoke else (1, 2):
        rec = run(
            comm,
            scene,
            degree=degree,
            refine=True,
            tolerance=0.05 if args.smoke else 0.01,
            pressure_tolerance=None if args.smoke else PRESSURE_TOLERANCE[degree],
            keep_pressure=True,
        )
        show(rec, f"P{degree} triangle adaptive")
        missed = rec["a_error"] > 0.01 or rec["p0_error"] > 0.02 or rec["L2_error"] > 0.05
        if not args.smoke and missed:
            raise SystemExit(f"{scene} P{degree} adaptive misses its tolerances")
# -

# ## Quadrilaterals: the size for 1%
#
# DOLFINx refines no quadrilateral mesh: P2 on uniform curved quadrilaterals over sizes
# from $a/15$ to $a/38$, none a divisor of $a$.

# +
if not args.smoke:
    for scene in SCENES:
        for across in (15.3, 18.7, 21.4, 24.6, 28.3, 33.3, 37.7):
            rec = run(
                comm, scene, degree=2, cell="quadrilateral", h=0.05 / across, keep_pressure=True
            )
            show(rec, f"P2 quadrilateral a/h = {across}")
# -

# ## The model error of the finite bodies
#
# The same P2 scenes with $a/R_1 = 2.5\%$ instead of 5% (the load divided by 8) and $h$
# halved: the discretization error about the same, the finite-body error halved. The
# change of the relative errors of $a$ and $p_0$ bounds the model error at 5%.

# +
if not args.smoke:
    for scene in ("sphere-on-plane", "two-spheres"):
        rec = model_error(comm, scene)
        records.append(rec)
        log(
            f"{scene}: a/R1 5% -> 2.5% changes the error of a by {rec['change_a']:.2%}, "
            f"of p0 by {rec['change_p0']:.2%}"
        )
# -

# ## Results

# +
if comm.rank == 0:
    merged = merge_rank_records(out / "axisymmetric.json", records, comm.size)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    s = np.linspace(0, 1, 200)
    for ax, scene in zip(axes, ("sphere-on-plane", "two-spheres"), strict=True):
        ax.plot(s, np.sqrt(1 - s**2), "k-", lw=0.8, label="Hertz")
        for (name, label), (x, p) in curves.items():
            if name == scene and "a/h" not in label:
                ax.plot(x, p, "." if "adaptive" in label else "x", ms=3, label=label)
        ax.set_xlim(0, 1.5)
        ax.set_xlabel("r / a")
        ax.set_title(scene)
        ax.legend()
    axes[0].set_ylabel("p / p0")
    fig.tight_layout()
    fig.savefig(out / "axisymmetric.png", dpi=120)

    lines = ["## Axisymmetric Hertz", "", "`demos/demo_axisymmetric.py`:", ""]
    lines += ["![pressures](axisymmetric.png)", ""]
    for rec in merged:
        lines.append("- " + ", ".join(f"{k} {v}" for k, v in rec.items() if k != "study"))
    write_section(out / "report.md", "axisymmetric", lines)
# -

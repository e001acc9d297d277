# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # The contact patch test
#
# El-Abbasi & Bathe (2001), section 3.2: two elastic blocks are pressed together by a
# uniform pressure $p$ on the top of the upper block. The lower block rests on rollers
# at $y = 0$, both blocks on rollers at $x = 0$. Whatever the two meshes along the
# contact line, the exact solution is
#
# $$\sigma_x = \sigma_{xy} = 0, \quad \sigma_y = -p, \quad \lambda = p,$$
#
# with linear displacements, which every element used here represents exactly. A
# contact discretization *passes the patch test* when it reproduces this state, i.e.
# when its evaluation of the contact integral (Eq. 17) transmits a constant pressure
# exactly (Eq. 36). The new segment-to-segment algorithm of section 5 does so by
# integrating over sub-segments bounded by the nodes of both surfaces (Fig. 15(b)).
#
# This demo solves the patch test for linear and quadratic elements, triangles and
# quadrilaterals, non-matching meshes (10/7 and 7/10 elements along the contact),
# either body as contactor, with an initial gap or overlap, curved-geometry cells and
# bodies of different degrees. It writes
#
# - `results/patch_test.json`: one record per case and number of ranks,
# - `results/report.md`: the table, and `results/patch_test_pressure.png`: the
#   contact pressure along the interface, exact against computed,
# - `results/vtx/`: displacements, stresses and pressure of one case for ParaView.
#
# Run it as `python3 demos/demo_patch_test.py` or `mpirun -n 2 python3 demos/demo_patch_test.py`;
# records of different rank counts are kept side by side.

# +
import argparse
import json
import time
from pathlib import Path

from mpi4py import MPI

import numpy as np

from dolfinx_contact_s2s.patch_test import PatchTestCase, errors, solve_patch_test

TOLERANCE = 1e-10

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--smoke", action="store_true", help="a few cases only")
parser.add_argument("--out", type=Path, default=Path("results"), help="output folder")
args = parser.parse_args()
comm = MPI.COMM_WORLD
out: Path = args.out
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)
comm.Barrier()


def log(*msg):
    if comm.rank == 0:
        print(*msg, flush=True)


# -

# ## The cases
#
# The matrix of Fig. 6 (b) and (c), linear on linear and quadratic on quadratic, plus
# the variants: an initial gap $g_0 > 0$, an overlap $g_0 < 0$, quadratic cells with
# curved-capable geometry, and bodies of different degree (Fig. 6(d)).

# +
cases = [
    PatchTestCase(degrees=(k, k), elements=ne, cell=cell, contactor=c)
    for k in (1, 2)
    for cell in ("triangle", "quadrilateral")
    for ne in ((10, 7), (7, 10))
    for c in ("upper", "lower")
]
cases += [
    PatchTestCase(gap=0.01),
    PatchTestCase(gap=-0.01, cell="quadrilateral", contactor="lower"),
    PatchTestCase(degrees=(2, 2), geometry_degree=2, elements=(10, 7)),
    PatchTestCase(degrees=(2, 2), geometry_degree=2, cell="quadrilateral", elements=(7, 10)),
    PatchTestCase(degrees=(2, 1), elements=(10, 7), contactor="lower"),
    PatchTestCase(degrees=(1, 2), elements=(7, 10), cell="quadrilateral"),
]
if args.smoke:
    cases = [cases[0], cases[11], cases[16], cases[-1]]
# -

# ## Solve and compare with the exact solution

# +
records = []
profiles = {}
start = time.perf_counter()
for k, case in enumerate(cases, 1):
    sol = solve_patch_test(comm, case)
    err = errors(sol)
    e_p, e_s = err.pressure, err.stress
    rec = case.record()
    rec.update(
        ranks=comm.size,
        pressure_error=e_p,
        stress_error=e_s,
        passed=bool(max(e_p, e_s) <= TOLERANCE),
    )
    records.append(rec)
    log(
        f"[{k:2d}/{len(cases)}] {case.cell:13s} P{case.degrees[0]}/P{case.degrees[1]} "
        f"{case.elements[0]:2d}/{case.elements[1]:<2d} contactor={case.contactor:5s} "
        f"g0={case.gap:+.2f} geometry P{case.geometry_degree}  "
        f"pressure error {e_p:.1e}  stress error {e_s:.1e}  "
        f"{'pass' if rec['passed'] else 'FAIL'}  ({time.perf_counter() - start:.1f} s)"
    )
    # The pressure along the interface, gathered for the plot.
    Q = sol.pressure.function_space
    n = Q.dofmap.index_map.size_local
    x = Q.tabulate_dof_coordinates()[:n, 0]
    parts = comm.gather((x, sol.pressure.x.array[:n].copy()), root=0)
    if comm.rank == 0:
        xs = np.concatenate([p[0] for p in parts])
        ls = np.concatenate([p[1] for p in parts])
        order = np.argsort(xs)
        profiles[k - 1] = (xs[order], ls[order])
    if k == 1:
        from dolfinx.io import VTXWriter

        vtx = out / "vtx"
        for name, u in sol.displacement.items():
            with VTXWriter(comm, vtx / f"displacement_{name}.bp", [u], engine="BP4") as f:
                f.write(0.0)
            with VTXWriter(comm, vtx / f"stress_{name}.bp", [sol.stress[name]], engine="BP4") as f:
                f.write(0.0)
        with VTXWriter(comm, vtx / "contact_pressure.bp", [sol.pressure], engine="BP4") as f:
            f.write(0.0)
# -

# ## Results
#
# Records of other rank counts already in the JSON file are kept; the report shows
# all of them.

# +
if comm.rank == 0:
    json_path = out / "patch_test.json"
    old = json.loads(json_path.read_text()) if json_path.exists() else []
    merged = [r for r in old if r.get("ranks") != comm.size] + records
    merged.sort(key=lambda r: (r["ranks"],))
    json_path.write_text(json.dumps(merged, indent=1))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(12, 5.5))
    for k, (xs, ls) in profiles.items():
        c = cases[k]
        label = (
            f"P{c.degrees[0]}/P{c.degrees[1]} {c.cell[:4]} "
            f"{c.elements[0]}/{c.elements[1]}, {c.contactor}"
        )
        ax0.plot(xs, ls, ".-", label=label, alpha=0.7)
        ax1.semilogy(xs, np.maximum(np.abs(ls - c.pressure), 1e-17), ".", label=label, alpha=0.7)
    ax0.axhline(1.0, color="k", lw=2, ls="--", label="exact $\\lambda = p$")
    ax0.set(
        xlabel="x",
        ylabel="contact pressure $\\lambda / p$",
        ylim=(0.9, 1.1),
        title="Contact pressure along the interface",
    )
    ax1.axhline(TOLERANCE, color="r", ls="--", label="tolerance")
    ax1.set(
        xlabel="x",
        ylabel="$|\\lambda - p| / p$",
        ylim=(1e-17, 1e-8),
        title="Pointwise pressure error (floored at 1e-17)",
    )
    handles, labels = ax0.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=7)
    fig.tight_layout(rect=(0, 0.22, 1, 1))
    fig.savefig(out / "patch_test_pressure.png", dpi=120)

    lines = [
        "# dolfinx_contact_s2s: results",
        "",
        "## Contact patch test (El-Abbasi & Bathe 2001, section 3.2, Figs. 4 and 6)",
        "",
        "Segment-to-segment algorithm of section 5 (composite Gauss quadrature on the",
        "sub-segments of Fig. 15(b), continuous multiplier of the contactor's degree).",
        "Exact: constant pressure p, sigma_y = -p, sigma_x = 0.",
        f"Pass: both errors <= {TOLERANCE:g}.",
        "",
        f"{sum(r['passed'] for r in merged)} of {len(merged)} cases pass.",
        "",
        "![contact pressure](patch_test_pressure.png)",
        "",
        "| ranks | method | multiplier | degrees | cell | geometry | elements | contactor | g0 "
        "| pressure error | stress error | passed |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in merged:
        lines.append(
            f"| {r['ranks']} | {r['method']} | ${r['multiplier']}$ "
            f"| {r['degrees'][0]}/{r['degrees'][1]} "
            f"| {r['cell']} | P{r['geometry_degree']} | {r['elements'][0]}/{r['elements'][1]} "
            f"| {r['contactor']} | {r['gap']:+g} | {r['pressure_error']:.1e} "
            f"| {r['stress_error']:.1e} | {'yes' if r['passed'] else '**no**'} |"
        )
    (out / "report.md").write_text("\n".join(lines) + "\n")
    log(f"wrote {json_path}, {out / 'report.md'}, {out / 'patch_test_pressure.png'}, {out / 'vtx'}")

failed = comm.allreduce(sum(not r["passed"] for r in records))
if failed:
    raise SystemExit(f"{failed} patch test case(s) failed")
# -

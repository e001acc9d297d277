# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The performance section of the report, from the records of ``make bench``.

Reads every ``results/bench/*.json``, checks that each is complete (every key of
:data:`~paper.bench.REQUIRED_KEYS`, a finite positive ratio),
draws ``results/bench/summary.png`` (each figure's ratio against its goal) and replaces
the ``bench`` section of ``results/report.md``. Exits with an error when a record is
incomplete or a figure has no record (``--require``).
"""

import argparse
import json
import math
import sys
from pathlib import Path

from paper.bench import GOALS, record_problems
from paper.report import write_section

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", type=Path, default=Path("results/bench"), help="records folder")
parser.add_argument("--report", type=Path, help="report (default: OUT/../report.md)")
parser.add_argument("--require", nargs="*", default=[], help="record names that must exist")
args = parser.parse_args()
report = args.report or args.out.parent / "report.md"

records = {}
problems = []
for path in sorted(args.out.glob("*.json")):
    record = json.loads(path.read_text())
    records[path.stem] = record
    problems += [f"{path.name}: {p}" for p in record_problems(record)]
problems += [f"no record {name}.json" for name in args.require if name not in records]
if problems:
    print("incomplete benchmark records:\n  " + "\n  ".join(problems), file=sys.stderr)
    sys.exit(1)
if not records:
    print(f"no records in {args.out}", file=sys.stderr)
    sys.exit(1)


#: Records whose ratio is a share, shown in percent.
SHARES = ("p2_", "p10_")


def seconds(value):
    """Seconds in the table: 3 significant digits."""
    return f"{value:.3g}" if isinstance(value, int | float) else "-"


def goal_text(name, goal):
    """``<= 2`` or ``-`` (shares in percent)."""
    if not goal:
        return "-"
    value = f"{goal['value']:.0%}" if name.startswith(SHARES) else f"{goal['value']:g}"
    return f"{goal['op']} {value}"


def ratio_text(name, ratio):
    """The ratio as the issue states it (shares in percent)."""
    return f"{ratio:.2%}" if name.startswith(SHARES) else f"{ratio:.3g}"


def met_text(met):
    """The cell of ``met``: yes, **no** or -."""
    return "-" if met is None else ("yes" if met else "**no**")


def raw_times(record):
    """The raw times of the ratio: the first two scalars of ``times``."""
    scalars = [(k, v) for k, v in record["times"].items() if isinstance(v, int | float)]
    return ", ".join(f"{k.removesuffix('_seconds')} {seconds(v)} s" for k, v in scalars[:2])


first = next(iter(records.values()))
machine, versions = first["machine"], first["versions"]
smoke = any(r["smoke"] for r in records.values())
order = sorted(records, key=lambda n: (records[n]["figure"], n))
lines = [
    "## Performance (`make bench`)",
    "",
    "Every figure is a ratio of two times measured in the same run (never absolute "
    "seconds as pass or fail). "
    + ("**Smoke run: tiny sizes, the ratios mean nothing.** " if smoke else "")
    + f"Machine: {machine['cpu']}, {machine['cores']} cores, "
    f"{machine['memory_mb'] / 1024:.1f} GB. DOLFINx {versions['dolfinx']}, PETSc "
    f"{versions['petsc']}, MUMPS {versions['mumps'] or 'unknown'}, BLAS "
    f"{versions['blas_kind']} ({', '.join(versions['blas']) or 'not mapped'}).",
    "",
    "| figure | record | measures | ratio | goal | met | raw times | ranks | peak MB (max / sum) "
    "| backend |",
    "|---|---|---|---|---|---|---|---|---|---|",
]
for name in order:
    r = records[name]
    peak = r["peak_memory"]
    ranks = r["ranks"] if not isinstance(r["ranks"], list) else "/".join(map(str, r["ranks"]))
    backend = r["backend"] if isinstance(r["backend"], str) else ", ".join(r["backend"])
    lines.append(
        f"| {r['figure']} | `{name}` | {r['title']} | {ratio_text(name, r['ratio'])} | "
        f"{goal_text(name, r['goal'])} | {met_text(r['met'])} | {raw_times(r)} | {ranks} | "
        f"{peak['max_mb']:.0f} / {peak['sum_mb']:.0f} | {backend} |"
    )
loads = [r["load_average"][1] for r in records.values() if "load_average" in r]
if loads and max(loads) > 1.5 * machine["cores"]:
    lines += [
        "",
        f"**Noisy run**: the 5-minute load average reached {max(loads):.1f} on "
        f"{machine['cores']} cores (other processes competed for them); ratios whose two "
        "times were taken minutes apart, or on 1 against 2 ranks (P7), suffer most.",
    ]
lines += ["", "Definitions of the ratios:", ""]
lines += [f"- `{n}`: {records[n]['ratio_definition']}" for n in order]

if "p1_coupling" in records:
    r = records["p1_coupling"]
    lines += [
        "",
        "### P1: coupling throughput against DOLFINx's stiffness assembly",
        "",
        "| degree | n | backend | sub-segments/s | cells/s | ratio | ratio against assembly "
        "with the matrix's creation |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        for backend, b in row["backends"].items():
            lines.append(
                f"| P{row['degree']} | {row['n']} | {backend} | "
                f"{b['sub_segments_per_second']:.3g} | {row['cells_per_second']:.3g} | "
                f"{b['ratio']:.3f} | {b.get('ratio_with_creation', math.nan):.3f} |"
            )
    lines += ["", "![P1](bench/p1_coupling.png)"]
if "p2_share_hertz" in records:
    r = records["p2_share_hertz"]
    t = r["times"]
    lines += [
        "",
        f"### P2: Hertz, {r['unknowns']} unknowns, {r['iterations']} semismooth Newton iterations",
        "",
        f"Per iteration: {t['per_iteration_contact_seconds']:.3g} s contact-specific of "
        f"{t['per_iteration_whole_seconds']:.3g} s; the active-set updates took "
        f"{t['update_seconds']:.3g} s in all, the coupling {t['stages']['contact']:.3g} s "
        f"(once: the contact is linear), the largest share in one iteration "
        f"{r['max_iteration_share']:.2%}.",
    ]
if "p6_scaling" in records:
    r = records["p6_scaling"]
    lines += [
        "",
        "### P6: time and memory against unknowns (1 rank)",
        "",
        "| solver | unknowns | pipeline (s) | solve (s) | peak MB |",
        "|---|---|---|---|---|",
    ]
    for run in sorted(r["runs"], key=lambda x: (x["solver"], x["unknowns"])):
        lines.append(
            f"| {run['solver']} | {run['unknowns']} | {run['times']['pipeline']:.3g} | "
            f"{run['times']['solve']:.3g} | {run['peak_memory']['max_mb']:.0f} |"
        )
    missing = [s for s in ("default", "iterative") if s not in r["solvers"]]
    if missing:
        lines += ["", f"Not available in this run: {', '.join(missing)} solver column."]
    li = r.get("largest_iterative")
    if li is not None:
        lines += [
            "",
            f"The iterative solver's largest scene: {li['unknowns']:,} unknowns in "
            f"{li['iterations']} iterations, {li['seconds']:.0f} s, peak "
            f"{li['peak_mb'] / 1024:.1f} GB. Goal: at least 8,000,000 unknowns within 16 GB, "
            f"beyond a direct factorization here (MUMPS LU ran out of 16 GB between 4.0 and "
            f"4.8 million unknowns): **{'met' if li['met'] else 'missed'}**.",
        ]
    lines += ["", "![P6](bench/p6_scaling.png)"]
if "p7_ranks" in records:
    r = records["p7_ranks"]
    lines += [
        "",
        "### P7: stages on 1 against 2 ranks (speed-up per stage)",
        "",
        ", ".join(f"{k} {v:.2f}" for k, v in r["stage_speedups"].items()),
    ]
    every = r.get("pipeline_seconds")
    if every:
        lines += [
            "",
            "Pipeline times of every run (s), the fastest of each kept: "
            + "; ".join(
                f"{k} rank(s) " + ", ".join(f"{t:.2f}" for t in v) for k, v in every.items()
            )
            + ".",
        ]
if "p5_mpc" in records:
    r = records["p5_mpc"]
    lines += [
        "",
        "### P5: the patch test by dolfinx_mpc's contact slip condition beside composite S2S",
        "",
        "Same meshes (both blocks in one mesh, triangles, 10n/7n along the contact), same "
        "space, MUMPS LU; errors are max |sigma - sigma_exact| / p over both bodies and over "
        "the upper cells along the contact, and for S2S max |lambda - p| / p.",
        "",
        "| n | displacements | dolfinx_mpc stress | at the contact | time (s) | S2S stress "
        "| at the contact | multiplier | time (s) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        m, c = row["mpc"], row["s2s"]
        lines.append(
            f"| {row['level']} | {row['displacements']} | {m['stress_error']:.2e} | "
            f"{m['contact_stress_error']:.2e} | {m['times']['total']:.3g} | "
            f"{c['stress_error']:.2e} | {c['contact_stress_error']:.2e} | "
            f"{c['pressure_error']:.2e} | {c['times']['total']:.3g} |"
        )
    control = r.get("control")
    if control:
        lines += [
            "",
            "Control: on matching meshes (10 and 10 elements) dolfinx_mpc's stress error is "
            f"{control['stress_error']:.1e}: the constraint is set up right, and the error "
            "above is that of a node-wise slip condition on non-matching meshes.",
        ]
else:
    lines += ["", "P5 (dolfinx_mpc's slip constraint beside S2S): no record in this run."]
if "p9_coupling_3d" in records:
    r = records["p9_coupling_3d"]
    lines += [
        "",
        "### P9: 3D coupling throughput against DOLFINx's stiffness assembly",
        "",
        "| degree | cells across | backend | polygons | triangles | polygons/s | cells/s | ratio |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        for backend, b in row["backends"].items():
            lines.append(
                f"| P{row['degree']} | {row['cells_across']} | {backend} | {b['polygons']} | "
                f"{b['triangles']} | {b['polygons_per_second']:.3g} | "
                f"{row['cells_per_second']:.3g} | {b['ratio']:.3f} |"
            )
if "p10_share_3d" in records:
    r = records["p10_share_3d"]
    run, t = r["run"], r["times"]
    lines += [
        "",
        f"### P10: 3D unilateral solve, {run['unknowns']:,} unknowns",
        "",
        f"Active set, {len(run['iterations_per_solve'])} linear solve(s) of "
        f"{', '.join(map(str, run['iterations_per_solve']))} GMRES iterations (Schur field "
        f"split, GAMG); contact {t['contact_seconds']:.3g} s of {t['whole_seconds']:.3g} s "
        f"(pair {t['pair']:.3g}, coupling {t['stages']['contact']:.3g}, active-set updates "
        f"{t['update']:.3g}); peak {run['peak_memory']['max_mb'] / 1024:.1f} GB; errors "
        f"against the exact solution: pressure {run['error_pressure']:.1e}, displacement "
        f"{run['error_displacement']:.1e} (complementarity tolerance "
        f"{r['complementarity_tolerance']:g}).",
    ]
if "p11_fieldsplit_3d" in records:
    r = records["p11_fieldsplit_3d"]
    lines += [
        "",
        "### P11: tied 3D blocks, Schur field split with GAMG, by size (1 rank)",
        "",
        "| unknowns | multipliers | GMRES iterations | solve (s) | peak MB | pressure error "
        "| displacement error |",
        "|---|---|---|---|---|---|---|",
    ]
    for run in r["runs"]:
        lines.append(
            f"| {run['unknowns']:,} | {run['multipliers']:,} | {run['iterations']} | "
            f"{run['times']['solve']:.3g} | {run['peak_memory']['max_mb']:.0f} | "
            f"{run['error_pressure']:.1e} | {run['error_displacement']:.1e} |"
        )
    lines += ["", "![P9 and P11](bench/p9_p11_3d.png)"]
if "p13_dual" in records:
    r = records["p13_dual"]
    lines += [
        "",
        "### P13: tied dual multipliers condensed, CG + GAMG (1 rank)",
        "",
        "| unknowns | multipliers | condensed (s) | its | set-up T^T K T (s) | K alone (s) | its "
        "| ratio | pressure error |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        lines.append(
            f"| {row['unknowns']:,} | {row['multipliers']} | {row['condensed_seconds']:.3g} | "
            f"{row['condensed_iterations']} | {row['condensation_setup_seconds']:.3g} | "
            f"{row['k_seconds']:.3g} | {row['k_iterations']} | {row['ratio']:.2f} | "
            f"{row['pressure_error']:.1e} |"
        )
if "p12_unilateral" in records:
    r = records["p12_unilateral"]
    lines += [
        "",
        "### P12: unilateral contact from one factorization (Hertz, 1 rank)",
        "",
        "Whole `problem.solve()` each, the same scene, pair and solver; the condensed answer "
        "against the loop's (one factorization per iteration).",
        "",
        "| unknowns | multipliers | iterations | tied (s) | condensed (s) | loop (s) | "
        "condensed / tied | loop / tied | same sets | pressure diff. | displacement diff. |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        lines.append(
            f"| {row['unknowns']:,} | {row['multipliers']} | {row['iterations']} | "
            f"{row['tied_seconds']:.3g} | {row['condensed_seconds']:.3g} | "
            f"{row['loop_seconds']:.3g} | {row['ratio']:.2f} | {row['loop_ratio']:.1f} | "
            f"{row['same_active_sets']} | {row['pressure_difference']:.1e} | "
            f"{row['displacement_difference']:.1e} |"
        )


def p1_limits(r):
    """Missed P1 points: the coupling's fixed cost per call, from the two smallest n."""
    out = []
    for degree in sorted({row["degree"] for row in r["rows"]}):
        rows = sorted((row for row in r["rows"] if row["degree"] == degree), key=lambda x: x["n"])
        for backend in rows[0]["backends"]:
            missed = [row for row in rows if row["backends"][backend]["ratio"] < r["goal"]["value"]]
            if not missed or len(rows) < 2 or backend == "numpy":
                continue
            (s0, t0), (s1, t1) = [
                (
                    row["backends"][backend]["sub_segments"],
                    row["backends"][backend]["coupling_seconds"],
                )
                for row in rows[:2]
            ]
            per = (t1 - t0) / (s1 - s0)
            fixed = t0 - per * s0
            for row in missed:
                b = row["backends"][backend]
                rate = row["cells_per_second"] * per
                text = (
                    f"- P1, P{degree}, n = {row['n']} ({backend}): ratio {b['ratio']:.3g}. "
                    f"Straight line through the coupling times at n = {rows[0]['n']} and "
                    f"{rows[1]['n']}: {fixed * 1e3:.2g} ms per call whatever n (the fixed "
                    "costs of a call: Python calls and array set-up), "
                    f"{fixed / b['coupling_seconds']:.0%} of this "
                    f"point's {b['coupling_seconds'] * 1e3:.3g} ms; per sub-segment the "
                    f"coupling alone runs at {1 / rate:.3g} times DOLFINx's rate per cell."
                )
                predicted = fixed + per * b["sub_segments"]
                if b["coupling_seconds"] > 1.05 * predicted:
                    text += (
                        f" Here the call takes {b['coupling_seconds'] / predicted:.2f} times "
                        "what that line predicts, while DOLFINx's rate per cell changes by "
                        f"{row['cells_per_second'] / rows[0]['cells_per_second']:.2f}: the "
                        "coupling's cost per sub-segment grows with n (likely memory-bound "
                        "work on arrays that no longer fit in the caches; not measured per "
                        "stage)."
                    )
                out.append(text)
    return out


def p7_limits(r):
    """Missed P7: each stage's share of the 1-rank time and its speed-up."""
    one, two = r["runs"]["1"]["times"], r["runs"]["2"]["times"]
    stages = ["stiffness", "contact", "system", "solve"]
    total1 = one["pipeline"]
    goal = r["goal"]["value"]
    parts = ", ".join(
        f"{k} {one[k] / total1:.0%} of 1 rank's time, speed-up {one[k] / two[k]:.2f}"
        for k in stages
        if two.get(k)
    )
    rest2 = two["pipeline"] - two["solve"]
    budget = total1 / goal - rest2
    needed = (
        f"the solve alone would have to speed up {one['solve'] / budget:.2f} times"
        if budget > 0
        else "no speed-up of the solve alone could reach it"
    )
    return [
        f"- P7: whole pipeline {r['ratio']:.3g} on 2 ranks ({parts}). The solve (MUMPS's "
        "factorization) dominates and scales least besides the system stage (the checks "
        f"and the saddle point's conversion, serial in nature); for {goal:g} with the other "
        f"stages as measured, {needed}."
    ]


missed = [n for n in order if records[n]["met"] is False]
if missed:
    lines += ["", "### Goals missed, and what limits them", ""]
    for name in missed:
        r = records[name]
        if name == "p1_coupling":
            lines += p1_limits(r)
        elif name == "p7_ranks":
            lines += p7_limits(r)
        else:
            lines.append(
                f"- {r['figure']} (`{name}`): {ratio_text(name, r['ratio'])} against "
                f"{goal_text(name, r['goal'])}; raw times {raw_times(r)}."
            )
lines += ["", "![summary](bench/summary.png)", ""]

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(8, 4))
names = [n for n in order if GOALS.get(n.split("_np")[0]) is not None]
for k, name in enumerate(names):
    r = records[name]
    goal = r["goal"]["value"]
    # Both kinds of goal on one scale: above 1 misses it, below 1 meets it.
    height = r["ratio"] / goal if r["goal"]["op"] == "<=" else goal / r["ratio"]
    colour = "tab:green" if r["met"] else "tab:red"
    ax.bar(k, height, color=colour)
    label = f"{ratio_text(name, r['ratio'])} ({goal_text(name, r['goal'])})"
    ax.text(k, height, label, ha="center", va="bottom", fontsize=7)
ax.axhline(1.0, color="k", ls=":", lw=0.8)
ax.set_xticks(range(len(names)), [f"{records[n]['figure']}\n{n}" for n in names], fontsize=7)
ax.set_ylabel("ratio over goal, > 1: missed (green: met)")
if any(math.isfinite(records[n]["ratio"]) and records[n]["ratio"] > 0 for n in names):
    ax.set_yscale("log")
fig.tight_layout()
fig.savefig(args.out / "summary.png", dpi=120)
write_section(report, "bench", lines)
print(f"wrote {report} (bench section) and {args.out / 'summary.png'}")

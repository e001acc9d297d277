# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Solvability and the inf-sup test
#
# El-Abbasi & Bathe (2001), section 3.1. A contact discretization is *solvable* when
# its constraint matrix $\mathbf B$ has full rank (Eq. 35), and *stable* when the
# inf-sup value
#
# $$\beta^*_h = \inf_{\mathbf M} \sup_{\mathbf V}
#   \frac{\mathbf M^T \mathbf B \mathbf V}
#        {h^{1/2} \sqrt{\mathbf M^T \mathbf P \mathbf M} \sqrt{\mathbf V^T \mathbf S \mathbf V}}
#   \qquad \text{(Eq. 27)}$$
#
# stays bounded away from zero as the meshes are refined. $\mathbf S$ is the $H^1$
# norm matrix of the displacements, $\mathbf P$ the $L^2$ mass matrix of the
# multiplier; $\beta^{*2}_h$ is the smallest non-zero eigenvalue of
# $\mathbf B^T \mathbf P^{-1} \mathbf B \phi = \lambda h \mathbf S \phi$ (Eqs. 30-31),
# or 0 if there are pressure modes (Eq. 32). The stronger value $\beta_h$ of Eq. (22)
# measures the multiplier in the $H^{-1/2}$ dual norm instead.
#
# The model is Fig. 2: two blocks meshed independently, overlapping by $-g_0$, on two
# families of meshes: `10n/7n` (a fixed ratio) and `5n/(2n+1)` (Fig. 11(b)). Every
# discretization runs on both, with either surface as contactor. $\beta^*_h$ comes
# from the scalable test (one MUMPS factorization of the saddle-point matrix and a
# SLEPc eigensolver on the multipliers); on the small meshes the dense reference of
# Eqs. (30)-(32) runs too and must agree. The demo writes
#
# - `results/infsup.json`: per case and level `h`, `beta`, `beta_full`,
#   `pressure_modes`, `rank_deficiency`, the verdicts `stable` and `solvable`, and
#   Tables 1 and 2 computed beside the paper's;
# - `results/infsup.md` and the figures `results/fig8_infsup_nts.png`,
#   `results/fig11_infsup_two_pass.png` and `results/infsup_s2s.png`.
#
# Run it as `python3 demos/demo_infsup.py` or with `mpirun -n 2`; `--smoke` runs two
# levels of a few cases. It exits with an error if a computed table disagrees with the
# paper (the full run only).

# +
import json
import sys
import time

from mpi4py import MPI

from paper.infsup import (
    FAMILIES,
    LEVELS,
    STABLE_SLOPE,
    InfSupCase,
    run_case,
    study_cases,
    table,
)
from paper.report import demo_parser, output_folder, rank0_print

args = demo_parser("Solvability and inf-sup study", "two levels of a few cases").parse_args()
comm = MPI.COMM_WORLD
out = output_folder(args.out, comm)
log = rank0_print(comm)


def name(rec: dict) -> str:
    m = rec["multiplier"]
    label = rec["method"] if m is None else f"{rec['method']} {m[0]}{m[1]}"
    return f"{label} P{rec['degree']}"


# -

# ## The study

# +
cases = study_cases()
levels = LEVELS
if args.smoke:
    levels = (1, 2)
    cases = [
        InfSupCase(),
        InfSupCase(multiplier=("DG", 1), contactor="lower"),
        InfSupCase(method="two-pass node-to-segment", family="5n/(2n+1)"),
    ]
records = []
start = time.perf_counter()
for k, case in enumerate(cases, 1):
    rec = run_case(comm, case, levels)
    rec["ranks"] = comm.size
    records.append(rec)
    betas = " ".join(f"{lvl['beta']:.3g}" for lvl in rec["levels"])
    fitted = "-" if rec["slope"] is None else f"{rec['slope']:.2f}"
    log(
        f"[{k:2d}/{len(cases)}] {name(rec):40s} {rec['family']:9s} {rec['contactor']:5s} "
        f"beta* {betas:45s} slope {fitted}"
        f" {'stable' if rec['stable'] else 'unstable'}"
        f" {'solvable' if rec['solvable'] else 'UNSOLVABLE'} ({time.perf_counter() - start:.0f} s)"
    )
tables = {f"table_{k}": table(records, k) for k in (1, 2)}
# -

# ## Results
#
# Records of other rank counts already in the file are kept beside this run's.

# +
if comm.rank == 0:
    path = out / "infsup.json"
    old = json.loads(path.read_text())["records"] if path.exists() else []
    merged = [r for r in old if r.get("ranks") != comm.size] + records
    merged.sort(key=lambda r: r["ranks"])
    path.write_text(
        json.dumps(
            {
                "families": {f: [FAMILIES[f](n) for n in levels] for f in FAMILIES},
                "stable_slope": STABLE_SLOPE,
                "records": merged,
                **tables,
            },
            indent=1,
        )
    )

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def plot(ax, selected, label):
        for r in selected:
            h = [lvl["h"] for lvl in r["levels"] if lvl["beta"] > 0]
            b = [lvl["beta"] for lvl in r["levels"] if lvl["beta"] > 0]
            ax.loglog(h, b, "o-", label=label(r))
        ax.set_xlabel("h (lower surface)")
        ax.set_ylabel("beta*")
        ax.invert_xaxis()
        ax.grid(True, which="both", alpha=0.3)
        if selected:  # a smoke run may leave a panel without its method
            ax.legend(fontsize=7)

    figures = {
        "fig8_infsup_nts.png": (
            "Fig. 8: single-pass node-to-segment, linear elements",
            [lambda r: r["method"] == "node-to-segment"],
            lambda r: f"{r['family']}, {r['contactor']} contactor",
        ),
        "fig11_infsup_two_pass.png": (
            "Fig. 11: single- and two-pass node-to-segment, linear elements",
            [
                lambda r, f=f: (
                    r["method"] in ("node-to-segment", "two-pass node-to-segment")
                    and r["family"] == f
                    and r["contactor"] == "upper"
                )
                for f in FAMILIES
            ],
            lambda r: r["method"],
        ),
        "infsup_s2s.png": (
            "S2S: multiplier spaces, upper and lower contactor",
            [
                lambda r, k=k, c=c: (
                    r["method"] == "segment-to-segment"
                    and r["degree"] == k
                    and r["family"] == "5n/(2n+1)"
                    and r["contactor"] == c
                )
                for k in (1, 2)
                for c in ("upper", "lower")
            ],
            lambda r: f"{r['multiplier'][0]}{r['multiplier'][1]} on P{r['degree']}",
        ),
    }
    for filename, (title, panels, label) in figures.items():
        fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4), squeeze=False)
        for ax, keep in zip(axes[0], panels, strict=True):
            selected = [r for r in records if keep(r)]
            plot(ax, selected, label)
            if len(panels) > 1 and selected:
                first = selected[0]
                ax.set_title(f"{first['family']}, {first['contactor']} contactor", fontsize=9)
        fig.suptitle(title)
        fig.tight_layout()
        fig.savefig(out / filename, dpi=110)
        plt.close(fig)

    lines = [
        "# Solvability and inf-sup study (section 3.1, Fig. 2 model)",
        "",
        f"Ranks: {comm.size}. Levels n = {', '.join(map(str, levels))}. Stable: fitted slope of "
        f"log beta* against log h (levels n >= 3) below {STABLE_SLOPE}; solvable: full-rank B "
        "on every level.",
        "",
    ]
    for key, title in (("table_1", "Table 1 (linear)"), ("table_2", "Table 2 (quadratic)")):
        lines += [
            f"## {title}",
            "",
            "| multiplier | stable (computed / paper) | solvable (computed / paper) | agrees |",
            "|---|---|---|---|",
        ]
        for row in tables[key]:
            m = row["multiplier"]
            lines.append(
                f"| {m[0]}{m[1]} | {row['stable']} / {row['paper_stable']} | "
                f"{row['solvable']} / {row['paper_solvable']} | {row['agrees']} |"
            )
        lines.append("")
    lines += [
        "## Every case",
        "",
        "| discretization | family | contactor | beta* per level | beta (Eq. 22), finest |"
        " pressure modes | slope | stable | solvable |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in records:
        finest = r["levels"][-1]
        full = finest["beta_full"]
        fitted = "-" if r["slope"] is None else f"{r['slope']:.2f}"
        lines.append(
            f"| {name(r)} | {r['family']} | {r['contactor']} | "
            + " ".join(f"{lvl['beta']:.3g}" for lvl in r["levels"])
            + f" | {'-' if full is None else f'{full:.3g}'} | "
            + " ".join(str(lvl["pressure_modes"]) for lvl in r["levels"])
            + f" | {fitted} | {r['stable']} |"
            f" {r['solvable']} |"
        )
    (out / "infsup.md").write_text("\n".join(lines) + "\n")
    log(f"wrote {path}, {out / 'infsup.md'} and the figures")

disagree = [row for rows in tables.values() for row in rows if not row["agrees"]]
for row in disagree:
    log(f"DISAGREES with the paper: {row}")
if disagree and not args.smoke:
    sys.exit(1)
# -

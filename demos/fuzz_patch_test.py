# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Randomized patch tests
#
# The patch test of section 3.2 (Figs. 4 and 6) holds for composite segment-to-segment
# whatever the two meshes along the contact line: a uniform pressure $p$ on the upper
# block is transmitted exactly, $\lambda = p$, and the displacements are the linear
# field of $\sigma_y = -p$, $\sigma_x = \sigma_{xy} = 0$ (Eq. 36). This script draws
# thousands of two-block models with Hypothesis
# (`paper.fuzz.cases`): one Gmsh model with both blocks in one
# mesh, or a model per block; each block's cell type and displacement degree; contact
# edges of several Gmsh curves with random break points, element counts and geometric
# grading; Young's moduli over six decades, Poisson's ratios up to 0.49; the
# contactor; a small gap or overlap. Each is built as the README builds its model,
# solved, and compared with the exact solution within the round-off bound of its
# solve (`dolfinx_contact_s2s.analysis.roundoff`). A case above its bound, or raising, is a
# failure.
#
# The cases are drawn in chunks, each a Hypothesis run with its own seed (base seed +
# chunk number), the same on every rank; nothing is shrunk (Hypothesis shrinks against
# a wall clock that the ranks would not share). Every failure is written with its
# parameters and a command that reruns it:
#
#     python3 demos/fuzz_patch_test.py --case '<the case JSON>'
#
# Run it as `python3 demos/fuzz_patch_test.py --cases 1500` or on 2 ranks under
# `mpirun -n 2 python3 -m mpi4py`; `make fuzz` does both. It writes `results/fuzz.json`
# (one record per rank count) and the section "fuzz" of `results/report.md`.

# +
import json
import platform
import sys
import time

from mpi4py import MPI

import dolfinx

from paper.fuzz import (
    BOUND_CEILING,
    FuzzCase,
    campaign_parser,
    cases,
    check_case,
    guarded,
    rerun_command,
    run_campaign,
)
from paper.report import rank0_print, write_section

comm = MPI.COMM_WORLD
parser = campaign_parser("Randomized patch tests of composite S2S", 200)
parser.add_argument("--max-elements", type=int, default=8, help="most elements per curve")
parser.add_argument("--max-segments", type=int, default=3, help="most curves per edge")
parser.add_argument("--max-layers", type=int, default=4, help="most elements across a block")
args = parser.parse_args()


log = rank0_print(comm)


def reproduce(case) -> str:
    return rerun_command("demos/fuzz_patch_test.py", case, comm)


def run_case(case: FuzzCase) -> tuple[dict, str | None]:
    """Check one case; a failure's message, the same on every rank (or None)."""

    def check() -> tuple[dict, str | None]:
        result = check_case(case, comm, prefix="fuzz_demo_")
        record = {
            "ratio": result.ratio,
            "pressure_error": result.pressure_error,
            "pressure_bound": result.pressure_bound,
            "displacement_error": result.displacement_error,
            "displacement_bound": result.displacement_bound,
            "condition": result.condition,
            "backward_error": result.backward_error,
            "unknowns": result.unknowns,
        }
        return record, None if result.passed else f"error above its round-off bound: {record}"

    return guarded(comm, check)


# -

# ## One case

if args.case is not None:
    case = FuzzCase.from_json(args.case)
    log(case.describe())
    record, failure = run_case(case)
    log(json.dumps(record, indent=1))
    log("FAIL: " + failure if failure else "pass")
    sys.exit(1 if failure else 0)

# ## The campaign

# +
strategy = cases(args.max_elements, args.max_segments, args.max_layers)
state = {
    "cases": 0,
    "failures": [],
    "worst": None,
    "condition": 0.0,
    "unknowns": 0,
    "pressure_bound": 0.0,
    "backward_error": 0.0,
    "loose": 0,
}
mix: dict[str, int] = {}


def count(key: str) -> None:
    mix[key] = mix.get(key, 0) + 1


def visit(case: FuzzCase, chunk_seed: int) -> float | None:
    record, failure = run_case(case)
    state["cases"] += 1
    count("one mesh" if case.one_mesh else "two meshes")
    for block in (case.lower, case.upper):
        count(f"{block.cell} P{block.degree}")
    count(f"contactor {case.contactor}")
    count("graded" if any(s.progression != 1.0 for s in case.lower.contact) else "uniform")
    if failure is not None:
        state["failures"].append(
            {"seed": chunk_seed, "case": json.loads(case.to_json()), "message": failure}
        )
        state["failures"][-1]["command"] = reproduce(case)
        log(f"FAILURE (chunk seed {chunk_seed}): {failure}\n  {reproduce(case)}")
        return None
    ratio = record["ratio"]
    state["condition"] = max(state["condition"], record["condition"])
    state["unknowns"] = max(state["unknowns"], record["unknowns"])
    state["backward_error"] = max(state["backward_error"], record["backward_error"])
    state["pressure_bound"] = max(state["pressure_bound"], record["pressure_bound"])
    state["loose"] += record["pressure_bound"] > 1e-5
    if state["worst"] is None or ratio > state["worst"]["ratio"]:
        state["worst"] = {"ratio": ratio, "seed": chunk_seed, "case": json.loads(case.to_json())}
        state["worst"]["result"] = record
    # Steer the search towards large ratios (Hypothesis's targeted phase).
    return ratio


start = time.perf_counter()


def progress(drawn: int) -> None:
    worst = state["worst"]["ratio"] if state["worst"] else float("nan")
    log(
        f"fuzz [{comm.size} rank(s)] {drawn}/{args.cases} cases, "
        f"{len(state['failures'])} failure(s), worst error/bound {worst:.3g}, "
        f"largest condition {state['condition']:.2g}, {time.perf_counter() - start:.0f} s"
    )


_, last_seed = run_campaign(comm, strategy, visit, args.cases, args.chunk, args.seed, progress)
seconds = time.perf_counter() - start
# -

# ## Results

# +
record = {
    "ranks": comm.size,
    "cases": state["cases"],
    "failures": state["failures"],
    "worst": state["worst"],
    "largest_condition": state["condition"],
    "largest_unknowns": state["unknowns"],
    "largest_backward_error": state["backward_error"],
    "largest_pressure_bound": state["pressure_bound"],
    "pressure_bound_above_1e-5": state["loose"],
    "mix": dict(sorted(mix.items())),
    "seeds": [args.seed, last_seed],
    "chunk": args.chunk,
    "limits": {
        "max_elements": args.max_elements,
        "max_segments": args.max_segments,
        "max_layers": args.max_layers,
    },
    "seconds": seconds,
    "dolfinx": dolfinx.__version__,
    "python": platform.python_version(),
}
if comm.rank == 0:
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "fuzz.json"
    merged = json.loads(path.read_text()) if path.exists() else {}
    # One record per rank count and DOLFINx version (make fuzz SUITE=sid adds its own).
    merged[f"np{comm.size}-dolfinx{dolfinx.__version__}"] = record
    path.write_text(json.dumps(merged, indent=1))
    lines = [
        "## Randomized patch tests (`make fuzz`)",
        "",
        "Composite segment-to-segment on random non-matching two-block models (one mesh",
        "or two; triangles or quadrilaterals and P1 or P2 per block; graded contact edges",
        "of several Gmsh curves; E over six decades, nu up to 0.49; either contactor;",
        "gap or overlap up to 0.01). Pass: max |lambda - p| and max |u - u_exact| within",
        "the round-off bound of the solve (`round_off_bound`), the pressure's bound",
        f"below {BOUND_CEILING:g} p (else the check could not tell a wrong pressure).",
        "",
        "| ranks | cases | failures | worst error / bound | largest condition"
        " | largest backward error | largest pressure bound (cases > 1e-5)"
        " | largest system | DOLFINx | seconds |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for key in sorted(merged):
        r = merged[key]
        worst = r["worst"]["ratio"] if r["worst"] else float("nan")
        lines.append(
            f"| {r['ranks']} | {r['cases']} | {len(r['failures'])} | {worst:.3g} | "
            f"{r['largest_condition']:.2g} | {r['largest_backward_error']:.2g} | "
            f"{r['largest_pressure_bound']:.2g} ({r['pressure_bound_above_1e-5']}) | "
            f"{r['largest_unknowns']} | {r['dolfinx']} | "
            f"{r['seconds']:.0f} |"
        )
    failures = [f for r in merged.values() for f in r["failures"]]
    lines += ["", f"Failures: {len(failures)}."]
    lines += [f"- `{f['command']}`: {f['message']}" for f in failures[:20]]
    lines += ["", "Cases drawn (per block for cell and degree):", ""]
    for key in sorted(merged):
        r = merged[key]
        lines.append(
            f"- {r['ranks']} rank(s), DOLFINx {r['dolfinx']}: "
            + ", ".join(f"{k} {v}" for k, v in r["mix"].items())
        )
    write_section(args.out / "report.md", "fuzz", lines)
log(
    f"fuzz [{comm.size} rank(s)]: {state['cases']} cases, {len(state['failures'])} failure(s), "
    f"worst error/bound {record['worst']['ratio'] if record['worst'] else float('nan'):.3g}; "
    f"wrote {args.out / 'fuzz.json'} and {args.out / 'report.md'}"
)
sys.exit(1 if state["failures"] else 0)
# -

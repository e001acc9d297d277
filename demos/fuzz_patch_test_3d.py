# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: light
# ---

# # Randomized patch tests in 3D
#
# The patch test of section 3.2 holds for composite segment-to-segment on faces: two
# blocks meshed apart and pressed by a uniform pressure $P$ transmit it exactly,
# $\lambda = P$, and deform by uniaxial stress, $u = (\nu P x / E, \nu P y / E, -P z / E)$
# (Eq. 36). This script draws hundreds of such scenes with Hypothesis
# (`paper.fuzz3d.cases`, on the scene of `paper.blocks3d`): tetrahedra or hexahedra per
# block, P1/Q1 or P2/Q2, 2 to 6 cells across each block (different counts), 1 to 3
# layers, structured meshes or nodes moved in the contact plane (hexahedra by a graded map
# that keeps their faces parallelograms, or at random: warped faces, on which the pair
# raises its rule until it is exact), either contactor, tied or
# unilateral contact, a multiplier of degree 1 or of the displacement's degree (P1 for
# unilateral contact on P2 tetrahedral faces, which refuse P2 by design), and $E$ and
# $P$ over four decades. Each is solved and compared with the exact solution to
# $10^{-10}$ relative (the tolerance of `tests/test_contact_3d.py`); a case above it, or
# raising, is a failure.
#
# As in the 2D campaign (`demos/fuzz_patch_test.py`): the cases are drawn in chunks, each
# a Hypothesis run with its own seed (base seed + chunk number), drawn on rank 0 and
# checked on every rank; nothing is shrunk. Every failure is written with its parameters
# and a command that reruns it:
#
#     python3 demos/fuzz_patch_test_3d.py --case '<the case JSON>'
#
# Run it as `python3 demos/fuzz_patch_test_3d.py --cases 500` or on 2 ranks under
# `mpirun -n 2 python3 -m mpi4py`; `make fuzz` does both. It writes
# `results/fuzz_3d.json` (one record per rank count and DOLFINx version) and the section
# "fuzz_3d" of `results/report.md`.

# +
import json
import platform
import sys
import time

from mpi4py import MPI

import dolfinx

from paper.fuzz import campaign_parser, guarded, rerun_command, run_campaign
from paper.fuzz3d import TOLERANCE, FuzzCase3D, cases, check_case
from paper.report import rank0_print, write_section

comm = MPI.COMM_WORLD
parser = campaign_parser("Randomized 3D patch tests of composite S2S", 100)
parser.add_argument("--max-cells", type=int, default=6, help="most cells across a block")
parser.add_argument("--max-layers", type=int, default=3, help="most cells across a height")
args = parser.parse_args()


log = rank0_print(comm)


def reproduce(case) -> str:
    return rerun_command("demos/fuzz_patch_test_3d.py", case, comm)


def run_case(case: FuzzCase3D) -> tuple[dict, str | None]:
    """Check one case; a failure's message, the same on every rank (or None)."""

    def check() -> tuple[dict, str | None]:
        result = check_case(case, comm, prefix="fuzz3d_demo_")
        record = {
            "ratio": result.ratio,
            "pressure_error": result.pressure_error,
            "displacement_error": result.displacement_error,
            "relative_pressure_error": result.pressure_error / case.P,
            "relative_displacement_error": result.displacement_error * case.E / case.P,
            "unknowns": result.unknowns,
        }
        return record, None if result.passed else f"error above its tolerance: {record}"

    return guarded(comm, check)


# -

# ## One case

if args.case is not None:
    case = FuzzCase3D.from_json(args.case)
    log(case.describe())
    record, failure = run_case(case)
    log(json.dumps(record, indent=1))
    log("FAIL: " + failure if failure else "pass")
    sys.exit(1 if failure else 0)

# ## The campaign

# +
strategy = cases(args.max_cells, args.max_layers)
state = {"cases": 0, "failures": [], "worst": None, "pressure": 0.0, "displacement": 0.0}
state["unknowns"] = 0
mix: dict[str, int] = {}


def count(key: str) -> None:
    mix[key] = mix.get(key, 0) + 1


def visit(case: FuzzCase3D, chunk_seed: int) -> float | None:
    record, failure = run_case(case)
    state["cases"] += 1
    count(f"{case.lower}/{case.upper} P{case.degree}")
    count(f"{case.problem} P{case.multiplier} multiplier")
    count(f"contactor {case.contactor}")
    count("structured" if case.seed is None else "warped" if case.warp else "moved nodes")
    if failure is not None:
        entry = {"seed": chunk_seed, "case": json.loads(case.to_json()), "message": failure}
        entry["command"] = reproduce(case)
        state["failures"].append(entry)
        log(f"FAILURE (chunk seed {chunk_seed}): {failure}\n  {reproduce(case)}")
        return None
    state["pressure"] = max(state["pressure"], record["relative_pressure_error"])
    state["displacement"] = max(state["displacement"], record["relative_displacement_error"])
    state["unknowns"] = max(state["unknowns"], record["unknowns"])
    if state["worst"] is None or record["ratio"] > state["worst"]["ratio"]:
        state["worst"] = {"ratio": record["ratio"], "seed": chunk_seed}
        state["worst"]["case"] = json.loads(case.to_json())
        state["worst"]["result"] = record
    # Steer the search towards large errors (Hypothesis's targeted phase).
    return record["ratio"]


start = time.perf_counter()


def progress(drawn: int) -> None:
    worst = state["worst"]["ratio"] if state["worst"] else float("nan")
    log(
        f"fuzz 3D [{comm.size} rank(s)] {drawn}/{args.cases} cases, "
        f"{len(state['failures'])} failure(s), worst error/tolerance {worst:.3g}, "
        f"{time.perf_counter() - start:.0f} s"
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
    "tolerance": TOLERANCE,
    "largest_relative_pressure_error": state["pressure"],
    "largest_relative_displacement_error": state["displacement"],
    "largest_unknowns": state["unknowns"],
    "mix": dict(sorted(mix.items())),
    "seeds": [args.seed, last_seed],
    "chunk": args.chunk,
    "limits": {"max_cells": args.max_cells, "max_layers": args.max_layers},
    "seconds": seconds,
    "dolfinx": dolfinx.__version__,
    "python": platform.python_version(),
}
if comm.rank == 0:
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "fuzz_3d.json"
    merged = json.loads(path.read_text()) if path.exists() else {}
    merged[f"np{comm.size}-dolfinx{dolfinx.__version__}"] = record
    path.write_text(json.dumps(merged, indent=1))
    lines = [
        "## Randomized 3D patch tests (`make fuzz`)",
        "",
        "Composite segment-to-segment on faces between two random non-matching blocks",
        "(tetrahedra or hexahedra per block, P1/Q1 or P2/Q2, 2-6 cells across each,",
        "1-3 layers, structured or with the contact plane's nodes moved, hexahedra by",
        "a map that keeps their faces parallelograms or at random (warped faces, the rule",
        "raised until exact: `contact_rule.face_rule`); either contactor; tied or",
        "unilateral; multiplier P1 or of the displacement's degree; E and P over four",
        "decades). Pass: max abs(lambda - P) and max abs(u - u_exact) (Eq. 36) within the",
        f"round-off bound of the solve (`round_off_bound`, as in 2D), or {TOLERANCE:g} P and",
        f"{TOLERANCE:g} P / E where those are larger.",
        "",
        "| ranks | cases | failures | largest abs(lambda - P) / P | largest abs(u - u_exact) E / P"
        " | largest system | DOLFINx | seconds |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for key in sorted(merged):
        r = merged[key]
        lines.append(
            f"| {r['ranks']} | {r['cases']} | {len(r['failures'])} | "
            f"{r['largest_relative_pressure_error']:.2g} | "
            f"{r['largest_relative_displacement_error']:.2g} | {r['largest_unknowns']} | "
            f"{r['dolfinx']} | {r['seconds']:.0f} |"
        )
    failures = [f for r in merged.values() for f in r["failures"]]
    lines += ["", f"Failures: {len(failures)}."]
    lines += [f"- `{f['command']}`: {f['message']}" for f in failures[:20]]
    lines += ["", "Cases drawn:", ""]
    for key in sorted(merged):
        r = merged[key]
        lines.append(
            f"- {r['ranks']} rank(s), DOLFINx {r['dolfinx']}: "
            + ", ".join(f"{k} {v}" for k, v in r["mix"].items())
        )
    write_section(args.out / "report.md", "fuzz_3d", lines, after="fuzz")
log(
    f"fuzz 3D [{comm.size} rank(s)]: {state['cases']} cases, {len(state['failures'])} "
    f"failure(s), largest relative errors: pressure {state['pressure']:.2g}, displacement "
    f"{state['displacement']:.2g}; wrote {args.out / 'fuzz_3d.json'} and "
    f"{args.out / 'report.md'}"
)
sys.exit(1 if state["failures"] else 0)
# -

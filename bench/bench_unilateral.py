# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""P12 (issue 24): unilateral contact at the cost of one solve.

The Hertz scene of P2 (:mod:`paper.hertz.study`: a half cylinder pressed on a block,
unknown contact area, Eq. 1) at two sizes, about 100,000 and 1,000,000 unknowns, solved
three ways with the same solver (MUMPS :math:`LDL^T`) on the same pair:

- tied (:class:`~dolfinx_contact_s2s.problem.LinearContactProblem`): one assembly, one
  factorization, one solve: the least any solve of the scene costs;
- ``"condensed-active-set"``: the active-set iterations from one factorization;
- ``"active-set"``: one factorization per iteration, the reference of the answer.

Each time is the whole ``problem.solve()`` (assembly of K and the coupling, the checks,
the factorizations and solves). The figure: condensed / tied at the largest size, goal
<= 1.5. Recorded per size: the times, the solve stage alone, the iterations, and the
condensed answer against the loop's (the same active sets, the largest differences of
the pressure and the displacement relative to their largest values).

Writes ``results/bench/p12_unilateral.json``.
"""

import argparse
from pathlib import Path

from mpi4py import MPI

import numpy as np

from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.bench import Progress, backend_name, make_record, solver_description, timed, write_record
from paper.hertz.study import HertzCase, hertz_model

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--out", type=Path, default=Path("results/bench"))
args = parser.parse_args()
comm = MPI.COMM_WORLD
log = Progress(comm, "P12 unilateral")

# (elements across the contact, element size far away): about 1e5 and 1e6 unknowns.
SIZES = [(8, 0.2), (16, 0.1)] if args.smoke else [(90, 0.0115), (280, 0.0036)]


def largest(values):
    """The largest absolute value over all processes."""
    return comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def solve(model, kind):
    """Solve the scene one way: the whole solve's time and what to compare."""
    pair = model.pair()
    if kind == "tied":
        problem = LinearContactProblem(
            model.a, model.L, [pair], model.bcs, petsc_options_prefix="p12_tied_"
        )
    else:
        problem = UnilateralContactProblem(
            model.a,
            model.L,
            [pair],
            model.bcs,
            petsc_options_prefix=f"p12_{kind.replace('-', '_')}_",
            algorithm=kind,
            max_iterations=300,
        )
    with problem:
        _, seconds = timed(comm, problem.solve)
        n = pair.Q.dofmap.index_map.size_local
        nu = model.V.dofmap.index_map.size_local * model.V.dofmap.index_map_bs
        history = getattr(problem, "history", None)
        return {
            "seconds": seconds,
            "solve_stage_seconds": comm.allreduce(problem.timings["solve"], op=MPI.MAX),
            "iterations": history.iterations if history is not None else 1,
            "sets": None
            if history is None
            else [
                [tuple(tuple(s.tolist()) for s in it.active_sets) for it in step.iterations]
                for step in history.steps
            ],
            "u": problem.u[0].x.array[:nu].copy(),
            "lam": problem.multipliers[0].x.array[:n].copy(),
            "multipliers": pair.Q.dofmap.index_map.size_global,
            "backend": backend_name(pair.contactor),
            "solver": solver_description(problem.solver),
        }


rows = []
for elements_across, far_size in SIZES:
    case = HertzCase(elements_across=elements_across, far_size=far_size)
    with log.step(f"Hertz scene, {elements_across} elements across, far size {far_size} (Gmsh)"):
        model = hertz_model(case, comm)
    unknowns = None
    runs = {}
    for kind in ("tied", "condensed-active-set", "active-set"):
        with log.step(f"  {kind}"):
            runs[kind] = solve(model, kind)
        log(f"    {runs[kind]['seconds']:.2f} s, {runs[kind]['iterations']} iteration(s)")
    tied, condensed, loop = runs["tied"], runs["condensed-active-set"], runs["active-set"]
    unknowns = model.V.dofmap.index_map.size_global * 2 + condensed["multipliers"]
    same_sets = comm.allreduce(int(condensed["sets"] != loop["sets"])) == 0
    row = {
        "elements_across": elements_across,
        "far_size": far_size,
        "unknowns": unknowns,
        "multipliers": condensed["multipliers"],
        "iterations": condensed["iterations"],
        "loop_iterations": loop["iterations"],
        "tied_seconds": tied["seconds"],
        "condensed_seconds": condensed["seconds"],
        "loop_seconds": loop["seconds"],
        "tied_solve_stage_seconds": tied["solve_stage_seconds"],
        "condensed_solve_stage_seconds": condensed["solve_stage_seconds"],
        "loop_solve_stage_seconds": loop["solve_stage_seconds"],
        "ratio": condensed["seconds"] / tied["seconds"],
        "loop_ratio": loop["seconds"] / tied["seconds"],
        "same_active_sets": same_sets,
        "pressure_difference": largest(condensed["lam"] - loop["lam"]) / largest(loop["lam"]),
        "displacement_difference": largest(condensed["u"] - loop["u"]) / largest(loop["u"]),
    }
    rows.append(row)
    log(
        f"  {unknowns} unknowns, {row['multipliers']} multipliers: condensed / tied = "
        f"{row['ratio']:.2f}, loop / tied = {row['loop_ratio']:.2f}; same sets {same_sets}, "
        f"pressure {row['pressure_difference']:.1e}, displacement "
        f"{row['displacement_difference']:.1e}"
    )
    del model

top = rows[-1]
record = make_record(
    "p12_unilateral",
    comm,
    figure="P12",
    title="unilateral contact (condensed active set) against one tied solve, Hertz",
    backend=condensed["backend"],
    times={
        "tied_seconds": top["tied_seconds"],
        "condensed_seconds": top["condensed_seconds"],
        "loop_seconds": top["loop_seconds"],
    },
    ratio=top["ratio"],
    smoke=args.smoke,
    ratio_definition=(
        "t(condensed-active-set solve) / t(tied solve), whole problem.solve() each (assembly, "
        "checks, factorization, solves), same scene, pair and solver, largest size"
    ),
    unknowns=top["unknowns"],
    rows=rows,
    answer_matches=all(r["same_active_sets"] and r["pressure_difference"] <= 1e-10 for r in rows),
    solver_used=condensed["solver"],
)
write_record(args.out, record, comm)
log(
    f"P12 = {top['ratio']:.2f} (goal <= 1.5) at {top['unknowns']} unknowns; "
    f"{rows[0]['ratio']:.2f} at {rows[0]['unknowns']}"
)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""P2 (Hertz): the share of contact in the semismooth Newton solve of a Hertz contact.

The scene of the Hertz study (:mod:`paper.hertz.study`: a half
cylinder pressed on a block, unknown contact area, Eq. 1) refined to about 500,000
unknowns, solved by the primal-dual active-set method (semismooth Newton), every
iteration one saddle-point solve. The contact-specific time is the contact surfaces and
the pair (with its multiplier space), the search, segmentation and coupling
(``timings["contact"]``) and the active-set update of every iteration (weighted gaps,
complementarity function, new active set, released multipliers), the problem's
``update_seconds``; the whole is the set-up (without Gmsh) and the solve. Both are also
reported per iteration, read by the problem's ``monitor``. Goal: <= 5%.

Writes ``results/bench/p2_share_hertz.json``.
"""

import argparse
from pathlib import Path

from mpi4py import MPI

from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.bench import (
    Progress,
    backend_name,
    make_record,
    solver_description,
    timed,
    write_record,
)
from paper.hertz.study import HertzCase, hertz_model

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--elements-across", type=int, default=200)
parser.add_argument("--far-size", type=float, default=0.0051, help="element size far away")
parser.add_argument("--out", type=Path, default=Path("results/bench"))
args = parser.parse_args()
comm = MPI.COMM_WORLD
log = Progress(comm, "P2 Hertz")
case = (
    HertzCase(elements_across=10)
    if args.smoke
    else HertzCase(elements_across=args.elements_across, far_size=args.far_size)
)

with log.step(f"Hertz scene, {case.elements_across} elements across the contact (Gmsh)"):
    model, t_model = timed(comm, lambda: hertz_model(case, comm))
pair, t_pair = timed(comm, model.pair)
per_iteration: list[dict] = []


def snapshot(iteration):
    """After each solve: the cumulative stage times, to difference per iteration."""
    per_iteration.append({"update": problem.update_seconds, **problem.timings})
    log(
        f"  iteration {len(per_iteration)}: active {iteration.active}, +{iteration.entered} "
        f"-{iteration.left}, residual {iteration.residual:.1e}"
    )


problem, t_problem = timed(
    comm,
    lambda: UnilateralContactProblem(
        model.a,
        model.L,
        [pair],
        model.bcs,
        petsc_options_prefix="bench_hertz_",
        algorithm="active-set",
        max_iterations=200,
        monitor=snapshot,
    ),
)
unknowns = model.V.dofmap.index_map.size_global * 2 + pair.Q.dofmap.index_map.size_global
log(f"  {unknowns} unknowns, backend {backend_name(pair.contactor)}")

with log.step("active-set (semismooth Newton) solve"):
    _, t_solve = timed(comm, problem.solve)
iterations = problem.history.iterations
stages = {k: comm.allreduce(v, op=MPI.MAX) for k, v in problem.timings.items()}
t_update = comm.allreduce(problem.update_seconds, op=MPI.MAX)
rows, previous = [], {"update": 0.0, **dict.fromkeys(stages, 0.0)}
for snap in per_iteration:
    delta = {k: snap[k] - previous[k] for k in snap}
    previous = snap
    rows.append(delta)
rows = [{k: comm.allreduce(v, op=MPI.MAX) for k, v in r.items()} for r in rows]
for r in rows:
    total = sum(r.values())
    r["contact_share"] = (r["update"] + r["contact"]) / total if total > 0 else 0.0
log(f"  {iterations} solves; stages (s): " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items()))
log(f"  active-set updates: {t_update:.3f} s")
contact = t_pair + stages["contact"] + t_update
whole = t_pair + t_problem + t_solve
share = contact / whole
record = make_record(
    "p2_share_hertz",
    comm,
    figure="P2",
    title="contact-specific time as a share of the semismooth Newton solve, Hertz",
    backend=backend_name(pair.contactor),
    times={
        "contact_seconds": contact,
        "whole_seconds": whole,
        "per_iteration_contact_seconds": contact / max(iterations, 1),
        "per_iteration_whole_seconds": whole / max(iterations, 1),
        "pair_seconds": t_pair,
        "problem_seconds": t_problem,
        "solve_seconds": t_solve,
        "update_seconds": t_update,
        "model_seconds_with_gmsh": t_model,
        "stages": stages,
        "iterations": rows,
    },
    ratio=share,
    smoke=args.smoke,
    ratio_definition=(
        "(pair set-up + timings['contact'] + active-set updates) / (pair + problem + solve), "
        "equal to the same quotient per semismooth Newton iteration; Gmsh excluded"
    ),
    unknowns=unknowns,
    iterations=iterations,
    elements_across=case.elements_across,
    far_size=case.far_size,
    max_iteration_share=max((r["contact_share"] for r in rows), default=0.0),
    solver_used=solver_description(problem.solver),
)
write_record(args.out, record, comm)
log(
    f"P2 (Hertz) = {share:.2%} of the solve (goal <= 5%), {iterations} iterations, "
    f"{contact / max(iterations, 1):.3f} s of {whole / max(iterations, 1):.3f} s per iteration"
)
problem.destroy()

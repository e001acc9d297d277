# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""P2 (two blocks) and P3: the share of contact in a solve, the saddle point against K alone.

The scene is the inf-sup model of Fig. 2 (two blocks meshed independently, 10n/7n
quadrilaterals, clamped), S2S with the continuous multiplier of the displacement degree
(P2 by default), about 500,000 unknowns. From one run:

- P2: the contact-specific time (the contact surfaces and the pair with its multiplier
  space, then search, segmentation and coupling, ``problem.timings["contact"]``) over
  the whole set-up and solve (spaces and forms, pairs, the problem, assembly, the
  saddle point and its solve); goal <= 5%.
- P3: the solve of the saddle point of Eq. (18) (``timings["solve"]``: factorization and
  solve, with the problem's default solver) over the solve of K alone, the same blocks
  with the contact replaced by Dirichlet conditions on both contact surfaces (the same
  displacement unknowns, the same solver options); goal <= 1.3.

Writes ``results/bench/p2_share_blocks.json`` and ``p3_saddle.json``.
"""

import argparse
from pathlib import Path

from mpi4py import MPI

from paper.bench import (
    Progress,
    make_record,
    solver_description,
    timed,
    two_blocks,
    two_blocks_level,
    write_record,
)

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--unknowns", type=float, default=5e5, help="about this many unknowns")
parser.add_argument("--degree", type=int, default=2)
parser.add_argument("--solver", default="default", help="see studies.bench.solver_options")
parser.add_argument("--out", type=Path, default=Path("results/bench"))
args = parser.parse_args()
comm = MPI.COMM_WORLD
log = Progress(comm, "P2/P3")
level = 1 if args.smoke else two_blocks_level(args.unknowns, args.degree)

with log.step(f"two blocks, level {level} (P{args.degree}): mesh, spaces, forms, pair"):
    model = two_blocks(comm, level, degree=args.degree, solver=args.solver)
problem = model.problem
log(f"  {model.unknowns} unknowns, elements {model.elements}, backend {model.backend}")
with log.step("assemble and solve Eq. (18)"):
    _, t_solve_all = timed(comm, problem.solve)
stages = {k: comm.allreduce(v, op=MPI.MAX) for k, v in problem.timings.items()}
log("  stages (s): " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items()))
contact = model.times["pairs"] + stages["contact"]
whole = model.times["forms"] + model.times["pairs"] + model.times["problem"] + t_solve_all
share = contact / whole
record = make_record(
    "p2_share_blocks",
    comm,
    figure="P2",
    title="contact-specific time as a share of the whole solve, two blocks",
    backend=model.backend,
    times={
        "contact_seconds": contact,
        "whole_seconds": whole,
        "set_up": model.times,
        "assemble_and_solve": t_solve_all,
        "stages": stages,
    },
    ratio=share,
    smoke=args.smoke,
    ratio_definition=(
        "(pairs set-up + timings['contact']) / (forms + pairs + problem + assemble + solve); "
        "Gmsh meshing excluded"
    ),
    unknowns=model.unknowns,
    level=level,
    degree=args.degree,
    elements=list(model.elements),
    solver=args.solver,
    solver_used=solver_description(problem.solver),
)
write_record(args.out, record, comm)
log(f"P2 (two blocks) = {share:.2%} of the whole solve (goal <= 5%)")

saddle_solver = solver_description(problem.solver)
problem.destroy()  # its factorization: both in memory would double the peak
with log.step("K alone: contact replaced by Dirichlet conditions on the contact surfaces"):
    dirichlet = model.dirichlet_problem(args.solver)
    dirichlet.solve()
    k_stages = {k: comm.allreduce(v, op=MPI.MAX) for k, v in dirichlet.timings.items()}
    k_unknowns = dirichlet.A.getSize()[0]
    k_solver = solver_description(dirichlet.solver)
    dirichlet.destroy()
log("  stages (s): " + ", ".join(f"{k} {v:.3f}" for k, v in k_stages.items()))
ratio = stages["solve"] / k_stages["solve"]
record = make_record(
    "p3_saddle",
    comm,
    figure="P3",
    title="saddle-point solve over the solve of K alone (contact -> Dirichlet)",
    backend=model.backend,
    times={
        "saddle_solve_seconds": stages["solve"],
        "k_solve_seconds": k_stages["solve"],
        "saddle_stages": stages,
        "k_stages": k_stages,
    },
    ratio=ratio,
    smoke=args.smoke,
    ratio_definition="timings['solve'] of Eq. (18) / timings['solve'] of K with Dirichlet",
    unknowns=model.unknowns,
    k_unknowns=k_unknowns,
    level=level,
    degree=args.degree,
    solver=args.solver,
    solver_used=saddle_solver,
    k_solver_used=k_solver,
)
write_record(args.out, record, comm)
log(f"P3 = {ratio:.3f} (goal <= 1.3): {stages['solve']:.2f} s against {k_stages['solve']:.2f} s")

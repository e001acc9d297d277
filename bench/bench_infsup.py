# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Cost of the scalable inf-sup test against one saddle-point solve of the same scene.

The scene is the inf-sup model of Fig. 2 with quadratic quadrilaterals, S2S with the
quadratic continuous multiplier, large enough to be far beyond the dense test (about
240,000 displacement unknowns by default). Both timings come from the same run, so
the ratio is meaningful on a noisy machine even when the seconds are not:

- one solve: factorizing and solving Eq. (18) of the assembled ``LinearContactProblem``;
- the inf-sup test: assembling S and P, factorizing the shifted saddle-point matrix (its
  inertia counts the pressure modes) and the SLEPc eigensolve (``InfSupTest``).

Writes ``results/bench_infsup.json`` (and prints progress).
"""

import argparse
import json
import resource
import time
from pathlib import Path

from mpi4py import MPI
from petsc4py import PETSc

from dolfinx_contact_s2s.infsup import InfSupTest
from dolfinx_contact_s2s.studies.infsup import FAMILIES, InfSupCase, inf_sup_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--level", type=int, default=20, help="level n of the 10n/7n family")
parser.add_argument("--degree", type=int, default=2)
parser.add_argument("--repeat", type=int, default=2, help="timed repetitions (best kept)")
parser.add_argument("--out", type=Path, default=Path("results"))
args = parser.parse_args()
comm = MPI.COMM_WORLD


def log(*msg):
    """Print on rank 0."""
    if comm.rank == 0:
        print(*msg, flush=True)


def timed(f):
    """``f()`` and its wall time, the slowest rank's."""
    comm.Barrier()
    t0 = time.perf_counter()
    result = f()
    comm.Barrier()
    return result, comm.allreduce(time.perf_counter() - t0, op=MPI.MAX)


case = InfSupCase(degree=args.degree, family="10n/7n")
log(f"building the scene, level {args.level}: elements {FAMILIES[case.family](args.level)}")
(problem, h), t_build = timed(lambda: inf_sup_problem(comm, case, args.level))
problem.assemble()
unknowns = problem.A.getSize()[0]
log(f"  {unknowns} unknowns in Eq. (18) ({t_build:.1f} s)")


def one_solve(problem):
    """Factorize and solve Eq. (18) from scratch, as ``LinearContactProblem.solve`` does."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(problem.A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    x = problem.A.createVecRight()
    ksp.solve(problem.b, x)
    assert ksp.getConvergedReason() > 0
    x.destroy()
    ksp.destroy()


solve_times, infsup_times, block_times, results = [], [], [], []
for k in range(args.repeat):
    _, t_solve = timed(lambda: one_solve(problem))
    solve_times.append(t_solve)
    log(f"  [{k + 1}/{args.repeat}] one saddle-point solve: {t_solve:.2f} s")

    def infsup():
        """The scalable test: factorization, inertia, SLEPc."""
        test = InfSupTest(problem, h)
        try:
            return test, test.solve()
        finally:
            test.destroy()

    (test, result), t_infsup = timed(infsup)

    def infsup_block():
        """The same factorization, then block back-substitutions for dense Sigma^-1."""
        test = InfSupTest(problem, h)
        try:
            return test.solve_dense()
        finally:
            test.destroy()

    block, t_block = timed(infsup_block)
    block_times.append(t_block)
    log(
        f"  [{k + 1}/{args.repeat}] inf-sup by block back-substitution: {t_block:.2f} s, "
        f"beta* = {block.beta:.15f}"
    )
    infsup_times.append(t_infsup)
    results.append(result)
    log(
        f"  [{k + 1}/{args.repeat}] inf-sup test: {t_infsup:.2f} s, beta* = {result.beta:.15f}, "
        f"{result.solves} back-substitutions"
    )

peak = comm.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, op=MPI.SUM) / 1024
record = {
    "ranks": comm.size,
    "level": args.level,
    "degree": args.degree,
    "elements": list(FAMILIES[case.family](args.level)),
    "displacements": results[0].displacements,
    "constraints": results[0].constraints,
    "unknowns": unknowns,
    "beta": results[0].beta,
    "back_substitutions": results[0].solves,
    "solve_seconds": min(solve_times),
    "infsup_seconds": min(infsup_times),
    "ratio": min(infsup_times) / min(solve_times),
    "block_seconds": min(block_times),
    "block_ratio": min(block_times) / min(solve_times),
    "peak_rss_mb": peak,
}
log(
    f"inf-sup test / one solve = {record['ratio']:.2f} (goal <= 3), "
    f"with block back-substitutions {record['block_ratio']:.2f}; "
    f"{record['displacements']} displacements, peak RSS {peak:.0f} MB over all ranks"
)
if comm.rank == 0:
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "bench_infsup.json"
    old = json.loads(path.read_text()) if path.exists() else []
    key = (comm.size, args.level, args.degree)
    old = [r for r in old if (r["ranks"], r["level"], r["degree"]) != key]
    path.write_text(json.dumps(sorted(old + [record], key=lambda r: r["ranks"]), indent=1))
problem.destroy()

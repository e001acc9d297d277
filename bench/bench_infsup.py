# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Cost of the scalable inf-sup test against one saddle-point solve of the same scene.

The scene is the inf-sup model of Fig. 2 with quadratic quadrilaterals, S2S with the
quadratic continuous multiplier, large enough to be far beyond the dense test (about
240,000 displacement unknowns by default). Both timings come from the same run, so
the ratio is meaningful on a noisy machine even when the seconds are not:

- one solve: factorizing and solving Eq. (18) of the assembled ``LinearContactProblem``;
- the inf-sup test: assembling S and P, factorizing the shifted saddle-point matrix (its
  inertia counts the pressure modes) and the SLEPc eigensolve (``InfSupTest``).

P4 of ``make bench``: goal <= 2. The saddle-point solve uses the problem's own solver
(its defaults and options). The block back-substitution variant (dense
:math:`\Sigma^{-1}` from blocks of right-hand sides, :meth:`InfSupTest.solve_dense`) is
timed beside it. Writes ``results/bench/p4_infsup.json`` (``p4_infsup_np2.json`` on two
ranks) and prints progress.
"""

import argparse
from pathlib import Path

from mpi4py import MPI
from petsc4py import PETSc

from dolfinx_contact_s2s.analysis.infsup import InfSupTest
from paper.bench import (
    Progress,
    backend_name,
    make_record,
    solver_description,
    timed,
    write_record,
)
from paper.infsup import FAMILIES, InfSupCase, inf_sup_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--level", type=int, default=20, help="level n of the 10n/7n family")
parser.add_argument("--degree", type=int, default=2)
parser.add_argument("--repeat", type=int, default=1, help="timed repetitions (best kept)")
parser.add_argument("--no-block", action="store_true", help="skip the block variant")
parser.add_argument("--out", type=Path, default=Path("results/bench"))
args = parser.parse_args()
comm = MPI.COMM_WORLD
log = Progress(comm, "P4")
if args.smoke:
    args.level, args.repeat = 1, 1


def timed_(f):
    """``f()`` and its wall time, the slowest rank's."""
    return timed(comm, f)


case = InfSupCase(degree=args.degree, family="10n/7n")
log(f"building the scene, level {args.level}: elements {FAMILIES[case.family](args.level)}")
(problem, h), t_build = timed_(lambda: inf_sup_problem(comm, case, args.level))
problem.assemble()
unknowns = problem.A.getSize()[0]
log(f"  {unknowns} unknowns in Eq. (18) ({t_build:.1f} s)")


def one_solve(problem):
    """Factorize and solve Eq. (18) from scratch, with the problem's own solver options."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(problem.A)
    problem.options.apply(ksp)
    x = problem.A.createVecRight()
    ksp.solve(problem.b, x)
    if ksp.getConvergedReason() <= 0:
        raise RuntimeError(f"the solve failed: reason {ksp.getConvergedReason()}")
    used = solver_description(ksp)
    x.destroy()
    ksp.destroy()
    return used


solve_times, infsup_times, block_times, results = [], [], [], []
for k in range(args.repeat):
    used, t_solve = timed_(lambda: one_solve(problem))
    solve_times.append(t_solve)
    log(f"  [{k + 1}/{args.repeat}] one saddle-point solve: {t_solve:.2f} s")

    def infsup():
        """The scalable test: factorization, inertia, SLEPc."""
        test = InfSupTest(problem, h)
        try:
            return test, test.solve()
        finally:
            test.destroy()

    (test, result), t_infsup = timed_(infsup)

    def infsup_block():
        """The same factorization, then block back-substitutions for dense Sigma^-1."""
        test = InfSupTest(problem, h)
        try:
            return test.solve_dense()
        finally:
            test.destroy()

    if not args.no_block:
        block, t_block = timed_(infsup_block)
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

t_solve, t_infsup = min(solve_times), min(infsup_times)
record = make_record(
    "p4_infsup",
    comm,
    figure="P4",
    title="the scalable inf-sup test over one saddle-point solve",
    backend=backend_name(problem.pairs[0].contactor),
    times={
        "solve_seconds": t_solve,
        "infsup_seconds": t_infsup,
        "block_seconds": min(block_times) if block_times else None,
        "build_seconds": t_build,
        "all_solve_seconds": solve_times,
        "all_infsup_seconds": infsup_times,
    },
    ratio=t_infsup / t_solve,
    smoke=args.smoke,
    ratio_definition="t(InfSupTest(problem, h).solve()) / t(one factorization and solve)",
    level=args.level,
    degree=args.degree,
    elements=list(FAMILIES[case.family](args.level)),
    displacements=results[0].displacements,
    constraints=results[0].constraints,
    unknowns=unknowns,
    beta=results[0].beta,
    back_substitutions=results[0].solves,
    block_ratio=min(block_times) / t_solve if block_times else None,
    solver_used=used,
)
write_record(args.out, record, comm)
log(
    f"P4 = inf-sup test / one solve = {record['ratio']:.2f} (goal <= 2)"
    + (f", with block back-substitutions {record['block_ratio']:.2f}" if block_times else "")
    + f"; {record['displacements']} displacements, peak RSS "
    f"{record['peak_memory']['sum_mb']:.0f} MB over all ranks"
)
problem.destroy()

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""P13 (issue 24): tied contact with dual multipliers, condensed, by CG + GAMG.

Two non-matching blocks (:func:`paper.scenes.patch_test`, quadrilaterals, ``0.7 n``
lower and ``n`` upper elements along the contact line; the largest default, 2,320,
about 8 million unknowns) tied with dual multipliers
(``multiplier=("Dual", 1)``), under a uniform pressure, the upper block held by rollers
on its left (contact holds it vertically). At each size:

- the condensed solve (:class:`~dolfinx_contact_s2s.condensation.DualCondensation`):
  CG + GAMG on :math:`\mathbf T^T \mathbf K \mathbf T`, rtol 1e-12, its iterations,
  its solve time and the condensation's set-up (the product :math:`\mathbf T^T \mathbf K
  \mathbf T`);
- the reference: CG + GAMG on :math:`\mathbf K` alone of the same meshes with both
  blocks clamped (what an SPD solve of these bodies costs at least), with the
  condensation's solver options (:data:`~dolfinx_contact_s2s.condensation.DEFAULT_OPTIONS`,
  GAMG's threshold included) and the same rtol.

The figure: condensed solve / K solve at the largest size, goal <= 1.3; the iterations
should not grow with the size. The patch test's pressure error of the condensed answer
is recorded at every size.

Writes ``results/bench/p13_dual.json``.
"""

import argparse
from pathlib import Path

from mpi4py import MPI
from petsc4py import PETSc

import numpy as np

from dolfinx_contact_s2s.condensation import DEFAULT_OPTIONS, DualCondensation
from dolfinx_contact_s2s.options import PETScOptions
from paper import scenes
from paper.bench import Progress, make_record, timed, write_record
from paper.blocks import block_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--sizes", type=int, nargs="+", default=[100, 200, 400, 800, 2320])
parser.add_argument("--out", type=Path, default=Path("results/bench"))
args = parser.parse_args()
comm = MPI.COMM_WORLD
log = Progress(comm, "P13 dual")
sizes = [8, 16] if args.smoke else args.sizes
RTOL, P = 1e-12, 0.75


def solve_k_alone(scene):
    """CG + GAMG on K of both blocks, clamped, the same rtol: its time and iterations."""
    problem = block_problem(
        scene,
        (1, 1),
        "upper",
        support="clamped",
        petsc_options_prefix="p13_k_",
        multiplier=("Dual", 1),
    )
    with problem:
        problem.assemble()
        system = problem.system
        fields = list(system.fields.values())[: len(system.spaces)]
        indices = np.concatenate([f.getIndices() for f in fields]).astype(PETSc.IntType)
        u_is = PETSc.IS().createGeneral(indices, comm=comm)
        K = system.A.createSubMatrix(u_is, u_is)
        modes = []
        offset = 0
        for field, ns in zip(fields, system.near_nullspaces, strict=True):
            for v in ns.getVecs():
                w = K.createVecRight()
                w.array[offset : offset + field.getLocalSize()] = v.array_r
                modes.append(w)
            offset += field.getLocalSize()
        K.setNearNullSpace(PETSc.NullSpace().create(vectors=modes, comm=comm))
        # The condensation's own solver options (CG, GAMG and its threshold), the same rtol.
        ksp = PETSc.KSP().create(comm)
        ksp.setOperators(K)
        options = PETScOptions("p13_k_ksp_", DEFAULT_OPTIONS | {"ksp_rtol": RTOL})
        options.apply(ksp)
        b, x = K.createVecs()
        b.set(1.0)
        _, seconds = timed(comm, lambda: ksp.solve(b, x))
        its = ksp.getIterationNumber()
        for obj in [ksp, K, b, x, u_is, *modes]:
            obj.destroy()
        options.clear()
    return seconds, its


rows = []
for n in sizes:
    m = max(2, round(0.7 * n))
    with log.step(f"n = {n}: two blocks ({m} and {n} elements along the contact, Gmsh)"):
        scene = scenes.patch_test(comm, (m, n), cell="quadrilateral")
    problem = block_problem(
        scene,
        (1, 1),
        "upper",
        support="rollers",
        pressure=P,
        petsc_options_prefix="p13_",
        multiplier=("Dual", 1),
    )
    with problem:
        condensation, t_setup = timed(
            comm,
            lambda problem=problem: DualCondensation(
                problem, petsc_options_prefix="p13_cg_", petsc_options={"ksp_rtol": RTOL}
            ),
        )
        _, t_solve = timed(comm, condensation.solve)
        its = condensation.iterations
        lam = problem.multipliers[0]
        owned = lam.function_space.dofmap.index_map.size_local
        error = comm.allreduce(
            float(np.max(np.abs(lam.x.array[:owned] - P), initial=0.0)), op=MPI.MAX
        )
        unknowns = sum(V.dofmap.index_map.size_global * 2 for V in problem.spaces)
        multipliers = problem.pairs[0].Q.dofmap.index_map.size_global
        condensation.destroy()
    t_k, its_k = solve_k_alone(scene)
    row = {
        "n": n,
        "unknowns": unknowns,
        "multipliers": multipliers,
        "condensed_seconds": t_solve,
        "condensation_setup_seconds": t_setup,
        "condensed_iterations": its,
        "k_seconds": t_k,
        "k_iterations": its_k,
        "ratio": t_solve / t_k,
        "pressure_error": error / P,
    }
    rows.append(row)
    log(
        f"  {unknowns} unknowns: condensed {t_solve:.2f} s ({its} CG iterations; set-up "
        f"{t_setup:.2f} s), K alone {t_k:.2f} s ({its_k}): ratio {row['ratio']:.2f}; "
        f"pressure error {row['pressure_error']:.1e}"
    )

top = rows[-1]
record = make_record(
    "p13_dual",
    comm,
    figure="P13",
    title="tied dual multipliers condensed, CG + GAMG, over CG + GAMG on K alone",
    backend="n/a",
    times={"condensed_seconds": top["condensed_seconds"], "k_seconds": top["k_seconds"]},
    ratio=top["ratio"],
    smoke=args.smoke,
    ratio_definition=(
        "t(CG + GAMG solve of T^T K T, rtol 1e-12) / t(CG + GAMG solve of K alone, both "
        "blocks clamped, same meshes and rtol), largest size; the condensation's set-up "
        "(the product) recorded beside it"
    ),
    unknowns=top["unknowns"],
    rows=rows,
    iterations=[r["condensed_iterations"] for r in rows],
)
write_record(args.out, record, comm)
log(
    f"P13 = {top['ratio']:.2f} (goal <= 1.3) at {top['unknowns']} unknowns; iterations "
    f"{[r['condensed_iterations'] for r in rows]} (K alone {[r['k_iterations'] for r in rows]})"
)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""P8: the saddle-point factorization before and after the solver work of issue 11.

The two-block scene of P2/P3 (:func:`paper.bench.pipeline`, S2S P2,
about 505,000 unknowns) solved twice, each in a process of its own: as before issue 11,
MUMPS LU on the reference BLAS (the loader finds Debian's reference ``libblas.so.3``
and ``liblapack.so.3`` first through ``LD_LIBRARY_PATH``), and with the problem's
default now, MUMPS :math:`LDL^T` of the symmetric saddle point on OpenBLAS. Each child
records the BLAS it actually mapped (``/proc/self/maps``), so a run in which the
reference BLAS could not be put in place fails instead of measuring the same thing
twice.

The figure (a ratio of this run) is the speed-up of the solve stage (factorization and
back-substitution; the factorization is above 90% of it): ``t(LU, reference BLAS) /
t(default)``; the goal is 2.

Writes ``results/bench/p8_factorization.json``.
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="a tiny scene (seconds)")
parser.add_argument("--unknowns", type=float, default=5e5, help="about this many unknowns")
parser.add_argument("--out", type=Path, default=Path("results/bench"))
parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
parser.add_argument("--solver", default="default", help=argparse.SUPPRESS)
args = parser.parse_args()

if args.child is not None:
    from paper.bench import pipeline_child

    level = 1 if args.smoke else None
    pipeline_child(args.child, args.unknowns, name="P8", degree=2, solver=args.solver, level=level)
    sys.exit(0)


def say(*message):
    """Progress on the terminal."""
    print("[P8]", *message, flush=True)


def reference_blas_environment() -> dict[str, str]:
    """The environment in which the loader picks Debian's reference BLAS and LAPACK."""
    folders = []
    for library in ("blas/libblas.so.3", "lapack/liblapack.so.3"):
        found = sorted(glob.glob(f"/usr/lib/*/{library}"))
        if not found:
            raise SystemExit(f"P8: no reference {library} on this system (Debian's libblas3)")
        folders.append(os.path.dirname(found[0]))
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = ":".join([*folders, env.get("LD_LIBRARY_PATH", "")]).rstrip(":")
    return env


runs = {}
with tempfile.TemporaryDirectory() as tmp:
    for label, solver, env in (
        ("before", "lu", reference_blas_environment()),
        ("now", "default", dict(os.environ)),
    ):
        path = Path(tmp) / f"{label}.json"
        command = [sys.executable, __file__, "--child", str(path), "--solver", solver]
        command += ["--unknowns", str(args.unknowns)] + (["--smoke"] if args.smoke else [])
        say(f"{label}: solver {solver!r} ...")
        done = subprocess.run(command, env=env, check=False)
        if done.returncode != 0:
            raise SystemExit(f"P8: the {label!r} solve failed (exit {done.returncode})")
        run = json.loads(path.read_text())
        run["blas_kind"] = run["versions"]["blas_kind"]
        runs[label] = run
        say(
            f"  {run['unknowns']} unknowns, {run['solver_used']['pc']}, BLAS {run['blas_kind']}: "
            f"solve {run['times']['solve']:.2f} s, peak {run['peak_memory']['max_mb']:.0f} MB"
        )
if runs["before"]["blas_kind"] != "reference":
    raise SystemExit(f"P8: the reference BLAS was not loaded ({runs['before']['blas_kind']})")

from mpi4py import MPI  # noqa: E402 (after the children: this process stays light)

from paper.bench import make_record, write_record  # noqa: E402

comm = MPI.COMM_WORLD
before, now = runs["before"], runs["now"]
ratio = before["times"]["solve"] / now["times"]["solve"]
record = make_record(
    "p8_factorization",
    comm,
    figure="P8",
    title="saddle-point solve: MUMPS LU on the reference BLAS over the default solver",
    backend=sorted({before["backend"], now["backend"]}),
    times={"lu_reference_blas": before["times"]["solve"], "default": now["times"]["solve"]},
    ratio=ratio,
    smoke=args.smoke,
    ratio_definition="timings['solve'] with MUMPS LU on the reference BLAS / timings['solve'] "
    "with the default solver (MUMPS LDL^T) on the installed BLAS, same scene",
    ranks=1,
    peak={
        "max_mb": max(r["peak_memory"]["max_mb"] for r in runs.values()),
        "sum_mb": max(r["peak_memory"]["sum_mb"] for r in runs.values()),
    },
    unknowns=now["unknowns"],
    runs=[before, now],
)
write_record(args.out, record, comm)
say(
    f"P8 = {ratio:.2f} (goal >= 2): LU on the reference BLAS {before['times']['solve']:.2f} s, "
    f"default ({now['solver_used']['pc']}, {now['blas_kind']}) {now['times']['solve']:.2f} s"
)

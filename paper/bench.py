# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Shared pieces of the benchmarks of ``make bench`` (``bench/*.py``).

Every benchmark figure is a *ratio* of two times measured in the same run, so that it
means something on a noisy machine even when the seconds do not. Each script writes one
JSON record per figure with :func:`write_record`; every record holds the keys of
:data:`REQUIRED_KEYS`:

- ``figure``, ``title``: the figure's label (``"P1"`` ... ``"P7"``) and what it measures;
- ``machine``: CPU model, cores and memory (:func:`machine`);
- ``versions``: DOLFINx, PETSc, MUMPS, the BLAS library in use, ... (:func:`versions`);
- ``ranks``, ``backend``: the MPI processes and the coupling kernel backend that ran;
- ``peak_memory``: ``ru_maxrss`` of the processes, largest and summed (:func:`peak_memory`);
- ``times``: the raw times (s) the ratio is made of, and ``ratio`` itself;
- ``goal``, ``met``: the issue's goal (``{"op": "<=", "value": 2.0}`` or ``None``) and
  whether the ratio meets it (``None`` without a goal);
- ``smoke``: whether the sizes were the tiny ones of the test run.

Seams for work in progress elsewhere: :func:`backends` lists the coupling kernel
backends present (a compiled one when it exists), :func:`backend_name` reads which one
a surface uses, and :func:`solver_options` maps a solver name to PETSc options (the
iterative saddle-point solver, when :mod:`dolfinx_contact_s2s.fieldsplit` provides it).
"""

from __future__ import annotations

import contextlib
import datetime
import importlib
import importlib.metadata
import json
import math
import os
import platform
import re
import resource
import time
import typing
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from mpi4py import MPI

import numpy as np

from dolfinx_contact_s2s.convergence import json_ready

__all__ = [
    "GOALS",
    "REQUIRED_KEYS",
    "Progress",
    "TwoBlocks",
    "backend_name",
    "backends",
    "configure_solver",
    "goal_met",
    "machine",
    "make_record",
    "peak_memory",
    "pipeline",
    "pipeline_child",
    "record_problems",
    "solver_description",
    "solver_kind",
    "solver_options",
    "timed",
    "two_blocks",
    "two_blocks_level",
    "versions",
    "write_record",
]

#: Keys of every benchmark record.
REQUIRED_KEYS = (
    "backend",
    "figure",
    "goal",
    "machine",
    "met",
    "peak_memory",
    "ranks",
    "ratio",
    "smoke",
    "times",
    "title",
    "versions",
)

#: The goals of issue 11 ("Done when"), by record name; ``None``: no goal.
GOALS: dict[str, dict[str, typing.Any] | None] = {
    # Issue 24 doubled issue 11's goal of 1.
    "p1_coupling": {"op": ">=", "value": 2.0},
    "p2_share_blocks": {"op": "<=", "value": 0.05},
    "p2_share_hertz": {"op": "<=", "value": 0.05},
    "p3_saddle": {"op": "<=", "value": 1.3},
    "p4_infsup": {"op": "<=", "value": 2.0},
    "p5_mpc": None,
    "p6_scaling": None,
    "p7_ranks": {"op": ">=", "value": 1.6},
    "p8_factorization": {"op": ">=", "value": 2.0},
    # Issue 21, three-dimensional contact (bench/bench_3d.py).
    "p9_coupling_3d": {"op": ">=", "value": 0.5},
    "p10_share_3d": {"op": "<=", "value": 0.10},
    "p11_fieldsplit_3d": {"op": "<=", "value": 1.0},
    # Issue 24: unilateral contact at the cost of one solve (bench/bench_unilateral.py).
    "p12_unilateral": {"op": "<=", "value": 1.5},
    "p13_dual": {"op": "<=", "value": 1.3},
}


def _meminfo_mb() -> float:
    """Total memory of the machine (MB), from ``/proc/meminfo``."""
    with contextlib.suppress(OSError, ValueError, IndexError):
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return int(line.split()[1]) / 1024
    return math.nan


def machine() -> dict[str, typing.Any]:
    """CPU model, logical cores, physical cores and total memory of this machine."""
    model, physical = platform.processor() or "unknown", set()
    with contextlib.suppress(OSError):
        core = phys = None
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = (s.strip() for s in line.partition(":"))
            if key == "model name":
                model = value
            elif key == "physical id":
                phys = value
            elif key == "core id":
                core = value
                physical.add((phys, core))
    return {
        "cpu": model,
        "cores": os.cpu_count(),
        "physical_cores": len(physical) or None,
        "memory_mb": round(_meminfo_mb(), 1),
        "system": platform.system(),
        "machine": platform.machine(),
    }


def _mapped_libraries(*patterns: str) -> list[str]:
    """Real paths of the shared libraries of this process whose name holds a pattern."""
    found: list[str] = []
    with contextlib.suppress(OSError):
        for line in Path("/proc/self/maps").read_text().splitlines():
            parts = line.split()
            if len(parts) < 6 or not parts[5].startswith("/"):
                continue
            name = os.path.basename(parts[5])
            if any(p in name for p in patterns):
                path = os.path.realpath(parts[5])
                if path not in found:
                    found.append(path)
    return found


def _module_version(name: str) -> str | None:
    """A module's ``__version__``, else its distribution's version; None if absent."""
    try:
        module = importlib.import_module(name)
    except ImportError:
        return None
    version = getattr(module, "__version__", None)
    if version is None:
        with contextlib.suppress(importlib.metadata.PackageNotFoundError):
            version = importlib.metadata.version(name)
    return str(version) if version is not None else "unknown"


def versions() -> dict[str, typing.Any]:
    """Versions of the software that ran: Python, NumPy, DOLFINx, PETSc, MUMPS, BLAS.

    MUMPS and the BLAS are read from the shared libraries mapped into this process
    (``/proc/self/maps``): their resolved paths name the implementation (reference
    BLAS, OpenBLAS, ...) and, for MUMPS, the version of the library file.
    """
    from petsc4py import PETSc

    import dolfinx_contact_s2s

    petsc = PETSc.Sys.getVersion()
    mumps = _mapped_libraries("libdmumps", "libmumps_common")
    mumps_version = None
    for path in mumps:
        found = re.search(r"(\d+(?:\.\d+)+)", os.path.basename(path))
        if found:
            mumps_version = found.group(1)
            break
    blas = _mapped_libraries("libblas", "libopenblas", "libblis", "libmkl")
    lapack = _mapped_libraries("liblapack")
    out = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "dolfinx": _module_version("dolfinx"),
        "basix": _module_version("basix"),
        "ffcx": _module_version("ffcx"),
        "petsc": ".".join(str(v) for v in petsc),
        "petsc4py": _module_version("petsc4py"),
        "slepc4py": _module_version("slepc4py"),
        "mpi": MPI.Get_library_version().splitlines()[0].strip(),
        "mumps": mumps_version,
        "mumps_libraries": mumps,
        "blas": blas,
        "blas_kind": _blas_kind(blas),
        "lapack": lapack,
        "dolfinx_contact_s2s": dolfinx_contact_s2s.__version__,
        "dolfinx_mpc": _module_version("dolfinx_mpc"),
    }
    return out


def _blas_kind(paths: list[str]) -> str:
    """``"openblas"``, ``"blis"``, ``"mkl"``, ``"reference"`` or ``"unknown"``."""
    text = " ".join(paths).lower()
    for kind in ("openblas", "blis", "mkl"):
        if kind in text:
            return kind
    return "reference" if "libblas" in text else "unknown"


def peak_memory(comm: MPI.Comm) -> dict[str, float]:
    """Peak resident memory (``ru_maxrss``, MB) of the processes: largest and summed."""
    mine = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return {
        "max_mb": comm.allreduce(mine, op=MPI.MAX),
        "sum_mb": comm.allreduce(mine, op=MPI.SUM),
    }


def timed(comm: MPI.Comm, f: Callable[[], typing.Any]) -> tuple[typing.Any, float]:
    """``f()`` and its wall time, the slowest process's (between barriers)."""
    comm.Barrier()
    begin = time.perf_counter()
    result = f()
    seconds = time.perf_counter() - begin
    comm.Barrier()
    return result, comm.allreduce(seconds, op=MPI.MAX)


class Progress:
    """Progress lines on the terminal (rank 0), with the time since the start."""

    def __init__(self, comm: MPI.Comm, name: str):
        """Start the clock of the benchmark ``name``."""
        self.comm, self.name, self.begin = comm, name, time.perf_counter()

    def __call__(self, *message: typing.Any) -> None:
        """Print ``message`` on rank 0."""
        if self.comm.rank == 0:
            elapsed = time.perf_counter() - self.begin
            print(f"[{self.name} {elapsed:7.1f}s]", *message, flush=True)

    @contextlib.contextmanager
    def step(self, message: str) -> Iterator[None]:
        """Announce a long step and report its duration."""
        self(message, "...")
        begin = time.perf_counter()
        yield
        self(f"  done in {time.perf_counter() - begin:.1f} s")


def backends() -> list[str]:
    """The coupling kernel backends present, the reference ``"numpy"`` first.

    ``"auto"`` is not a backend of its own (it resolves to one of these) and is left out.
    """
    from dolfinx_contact_s2s import kernels

    names = [b for b in getattr(kernels, "BACKENDS", ("numpy",)) if b != "auto"]
    present = []
    for name in names:
        try:
            kernels.get_backend(name)
        except (ImportError, OSError, RuntimeError, ValueError):
            continue
        present.append(name)
    present.sort(key=lambda b: b != "numpy")
    return present


def backend_name(surface: typing.Any) -> str:
    """Name of the kernel backend a contact surface runs on (e.g. ``"numpy"``, ``"c"``)."""
    backend = getattr(surface, "backend", None)
    name = getattr(backend, "NAME", None) or getattr(backend, "name", None)
    if isinstance(name, str):
        return name
    module = getattr(backend, "__name__", "unknown")
    return module.rsplit(".", 1)[-1].removesuffix("_backend")


def solver_options(name: str, spaces: int = 2) -> dict[str, typing.Any] | None:
    """PETSc options of the saddle-point solver called ``name``, or None if absent.

    - ``"default"``: the problem's own defaults (an empty dictionary);
    - ``"lu"``: MUMPS LU; ``"ldlt"``: MUMPS :math:`LDL^T` (symmetric indefinite);
    - ``"iterative"``: the Schur-complement field split of
      :mod:`dolfinx_contact_s2s.fieldsplit` (``iterative_options``), None until it exists;
      :func:`configure_solver` completes its set-up on the problem.

    Args:
        name: The solver.
        spaces: Number of displacement spaces of the problem.
    """
    if name == "default":
        return {}
    if name == "lu":
        return {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}
    if name == "ldlt":
        return {
            "ksp_type": "preonly",
            "pc_type": "cholesky",
            "pc_factor_mat_solver_type": "mumps",
            "mat_mumps_sym": 2,
        }
    if name == "iterative":
        try:
            solvers = importlib.import_module("dolfinx_contact_s2s.fieldsplit")
        except ImportError:
            return None
        make = getattr(solvers, "iterative_options", None)
        return dict(make(spaces=spaces)) if callable(make) else None
    raise ValueError(f"unknown solver {name!r}: 'default', 'lu', 'ldlt' or 'iterative'")


def solver_kind(name: str) -> str:
    """The problem's ``kind`` for the solver called ``name``: ``"nest"`` for the iterative one."""
    return "nest" if name == "iterative" else "aij"


def configure_solver(problem: typing.Any, name: str) -> None:
    """What a solver needs on the problem besides its options (before it is assembled).

    The iterative solver installs its Schur-complement set-up
    (``dolfinx_contact_s2s.fieldsplit.use_schur_complement``, on a problem created with
    ``kind=solver_kind(name)``); the direct ones need nothing.
    """
    if name != "iterative":
        return
    solvers = importlib.import_module("dolfinx_contact_s2s.fieldsplit")
    setup = getattr(solvers, "use_schur_complement", None)
    if callable(setup):
        setup(problem)


def solver_description(ksp: typing.Any) -> dict[str, typing.Any]:
    """The solver a KSP ran: its type, the preconditioner and the factorization package."""
    pc = ksp.getPC()
    out = {"ksp": ksp.getType(), "pc": pc.getType(), "factor": None, "iterations": None}
    with contextlib.suppress(Exception):
        out["factor"] = pc.getFactorSolverType()
    with contextlib.suppress(Exception):
        out["iterations"] = ksp.getIterationNumber()
    return out


def goal_met(goal: dict[str, typing.Any] | None, ratio: float) -> bool | None:
    """Whether ``ratio`` meets ``goal`` (``{"op": "<=" or ">=", "value": x}``); None: no goal."""
    if goal is None:
        return None
    if goal["op"] == "<=":
        return bool(ratio <= goal["value"])
    if goal["op"] == ">=":
        return bool(ratio >= goal["value"])
    raise ValueError(f"unknown goal operator {goal['op']!r}")


def make_record(
    name: str,
    comm: MPI.Comm,
    *,
    figure: str,
    title: str,
    backend: str | list[str],
    times: dict[str, typing.Any],
    ratio: float,
    smoke: bool,
    ratio_definition: str,
    ranks: typing.Any = None,
    peak: dict[str, float] | None = None,
    **extra: typing.Any,
) -> dict[str, typing.Any]:
    """A benchmark record with every key of :data:`REQUIRED_KEYS` (collective).

    Args:
        name: Record name (a key of :data:`GOALS`), also the JSON file's stem.
        comm: Communicator of the run (ranks and peak memory).
        figure: ``"P1"`` ... ``"P7"``.
        title: What the figure measures.
        backend: The coupling kernel backend(s) that ran.
        times: The raw times (s) of the ratio, and any others.
        ratio: The figure.
        smoke: Whether the sizes were the tiny ones of the test run.
        ratio_definition: The ratio in words, e.g. ``"t_infsup / t_solve"``.
        ranks: The processes of the figure when they are not ``comm``'s (runs launched
            as subprocesses); default ``comm.size``.
        peak: Peak memory when it is not this run's (see :func:`peak_memory`).
        extra: More keys (sizes, counts, per-size tables, ...).
    """
    goal = GOALS.get(name)
    record = {
        "name": name,
        "figure": figure,
        "title": title,
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "machine": machine(),
        "versions": versions(),
        "ranks": comm.size if ranks is None else ranks,
        "backend": backend,
        "peak_memory": peak_memory(comm) if peak is None else peak,
        "times": times,
        "ratio": float(ratio),
        "ratio_definition": ratio_definition,
        "goal": goal,
        "met": goal_met(goal, ratio) if math.isfinite(ratio) else False,
        "smoke": bool(smoke),
        # Other processes competing for the cores make the times noisy: 1, 5 and 15 min.
        "load_average": list(os.getloadavg()),
    }
    record.update(extra)
    return record


def write_record(out: str | Path, record: dict[str, typing.Any], comm: MPI.Comm) -> Path:
    """Write ``record`` to ``out/<name>.json`` on rank 0 (``<name>_np<ranks>`` on several).

    Returns:
        The path of the file (on every process).
    """
    out = Path(out)
    ranks = record["ranks"]
    suffix = f"_np{ranks}" if isinstance(ranks, int) and ranks > 1 else ""
    path = out / f"{record['name']}{suffix}.json"
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(json_ready(record), indent=1) + "\n")
    comm.Barrier()
    return path


def record_problems(record: dict[str, typing.Any]) -> list[str]:
    """What a record lacks: missing keys, a non-finite or non-positive ratio.

    Returns:
        Descriptions of the problems; empty for a complete record.
    """
    problems = [f"missing key {k!r}" for k in REQUIRED_KEYS if k not in record]
    ratio = record.get("ratio")
    if not isinstance(ratio, int | float) or not math.isfinite(ratio) or ratio <= 0:
        problems.append(f"ratio {ratio!r} is not finite and positive")
    return problems


@dataclass
class TwoBlocks:
    """The two-block scene of the benchmarks, set up as a tied contact problem (Eq. 18).

    Attributes:
        level: Level ``n`` of the 10n/7n family of the inf-sup model (Fig. 2).
        degree: Displacement (and multiplier) degree.
        elements: Elements along the contact line of the lower and the upper block.
        scene: Meshes and tags.
        problem: The :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`.
        forms: ``(a, L, bcs)`` of the two blocks (for a problem without contact).
        times: Wall times (s, slowest process) of ``"mesh"`` (Gmsh and distribution),
            ``"forms"`` (spaces, forms and supports), ``"pairs"`` (contact surfaces and
            the pair with its multiplier space) and ``"problem"`` (its constructor).
        backend: The coupling kernel backend of the contactor surface.
    """

    level: int
    degree: int
    elements: tuple[int, int]
    scene: typing.Any
    problem: typing.Any
    forms: tuple[list, list, list]
    times: dict[str, float] = field(default_factory=dict)
    backend: str = "numpy"

    @property
    def unknowns(self) -> int:
        """Unknowns of Eq. (18): displacements of both blocks and multipliers."""
        spaces = [*self.problem.spaces, *(p.Q for p in self.problem.pairs)]
        return sum(V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in spaces)

    def dirichlet_problem(self, solver: str = "default") -> typing.Any:
        """K alone: the same blocks with the contact replaced by u = 0 on both contact surfaces.

        The unknowns are the displacements of the contact problem; the solver has the same
        options. The caller must ``destroy()`` it.
        """
        import dolfinx

        from dolfinx_contact_s2s.problem import LinearContactProblem

        a, L, bcs = self.forms
        extra = []
        for name, V in zip(("lower", "upper"), self.problem.spaces, strict=True):
            body = self.scene.bodies[name]
            fdim = body.mesh.topology.dim - 1
            dofs = dolfinx.fem.locate_dofs_topological(V, fdim, body.facet_tags.find(body.contact))
            zero = np.zeros(body.mesh.geometry.dim, dtype=dolfinx.default_scalar_type)
            extra.append(dolfinx.fem.dirichletbc(zero, dofs, V))
        problem = LinearContactProblem(
            a,
            L,
            [],
            [*bcs, *extra],
            petsc_options_prefix="bench_dirichlet_",
            petsc_options=solver_options(solver, spaces=2),
            kind=solver_kind(solver),
        )
        configure_solver(problem, solver)
        return problem


def two_blocks_level(unknowns: float, degree: int = 2) -> int:
    r"""The level of the 10n/7n family whose problem has about ``unknowns`` unknowns.

    Quadrilaterals of degree ``degree`` on the :math:`1 \times 0.5` blocks: about
    :math:`2 (10 k n + 1)(5 k n + 1) + 2 (7 k n + 1)(3.5 k n + 1)` displacements.
    """
    per_level = 2 * degree**2 * (10 * 5 + 7 * 3.5)
    return max(1, round(math.sqrt(unknowns / per_level)))


def two_blocks(
    comm: MPI.Comm, level: int, *, degree: int = 2, solver: str = "default", prefix: str = "bench_"
) -> TwoBlocks:
    """The inf-sup model of Fig. 2 (10n/7n, quadrilaterals, clamped), S2S P``degree``.

    Each stage is timed (see :class:`TwoBlocks`); nothing is assembled yet.

    Args:
        comm: Communicator of the meshes.
        level: Level ``n``: ``10 n`` and ``7 n`` elements along the contact line.
        degree: Displacement degree; the multiplier is continuous of the same degree.
        solver: A name of :func:`solver_options`.
        prefix: PETSc options prefix of the problem.
    """
    from dolfinx_contact_s2s.problem import LinearContactProblem
    from paper.blocks import block_forms, block_pairs, block_spaces
    from paper.scenes import inf_sup_model

    options = solver_options(solver, spaces=2)
    if options is None:
        raise ValueError(f"the solver {solver!r} is not available in this installation")
    elements = (10 * level, 7 * level)
    times: dict[str, float] = {}
    scene, times["mesh"] = timed(comm, lambda: inf_sup_model(comm, elements))
    (spaces, forms), times["forms"] = timed(
        comm,
        lambda: (
            sp := block_spaces(scene, (degree, degree)),
            block_forms(scene, sp, support="clamped"),
        ),
    )
    pairs, times["pairs"] = timed(
        comm,
        lambda: block_pairs(
            scene,
            spaces,
            "upper",
            multiplier=("Lagrange", degree),
            search_radius=abs(scene.gap) + scene.width / min(elements),
        ),
    )
    problem, times["problem"] = timed(
        comm,
        lambda: LinearContactProblem(
            forms[0],
            forms[1],
            pairs,
            forms[2],
            petsc_options_prefix=prefix,
            petsc_options=options,
            kind=solver_kind(solver),
        ),
    )
    configure_solver(problem, solver)
    return TwoBlocks(
        level, degree, elements, scene, problem, forms, times, backend_name(pairs[0].contactor)
    )


def pipeline(
    comm: MPI.Comm,
    unknowns: float,
    *,
    degree: int = 2,
    solver: str = "default",
    level: int | None = None,
    log: Callable[..., None] | None = None,
) -> dict[str, typing.Any]:
    """The whole pipeline on the two-block scene: set up, assemble and solve (collective).

    Args:
        comm: Communicator.
        unknowns: About this many unknowns (see :func:`two_blocks_level`).
        degree: Displacement degree.
        solver: A name of :func:`solver_options`.
        level: The level itself, instead of ``unknowns``.
        log: Progress printer (e.g. a :class:`Progress`), called on every process.

    Returns:
        ``unknowns``, ``level``, ``backend``, ``solver_used``, ``times`` (s, slowest
        process: ``mesh`` (Gmsh), ``forms``, ``pairs``, ``problem``, ``assemble_and_solve``,
        the stages of ``problem.timings`` and ``pipeline``, all but Gmsh) and
        ``peak_memory`` (:func:`peak_memory`).
    """
    level = two_blocks_level(unknowns, degree) if level is None else level
    say = log or (lambda *message: None)
    say(f"level {level}, P{degree}, solver {solver!r}: meshing and setting up")
    model = two_blocks(comm, level, degree=degree, solver=solver, prefix="bench_pipeline_")
    problem = model.problem
    try:
        say(f"{model.unknowns} unknowns: assembling and solving")
        _, t = timed(comm, problem.solve)
        stages = {k: comm.allreduce(v, op=MPI.MAX) for k, v in problem.timings.items()}
        times = dict(model.times)
        times["assemble_and_solve"] = t
        times.update(stages)
        times["pipeline"] = times["forms"] + times["pairs"] + times["problem"] + t
        return {
            "unknowns": model.unknowns,
            "level": level,
            "degree": degree,
            "backend": model.backend,
            "solver": solver,
            "solver_used": solver_description(problem.solver),
            "times": times,
            "ranks": comm.size,
            "peak_memory": peak_memory(comm),
        }
    finally:
        problem.destroy()


def pipeline_child(
    path: Path | str,
    unknowns: float,
    *,
    name: str,
    degree: int = 2,
    solver: str = "default",
    level: int | None = None,
) -> None:
    """:func:`pipeline` in a process of its own (so that its peak memory is its own).

    Writes the record, with the :func:`versions` this process mapped (its BLAS), to
    ``path`` on rank 0.

    Args:
        path: The JSON file the parent reads.
        unknowns: About this many unknowns.
        name: The figure, for the progress lines.
        degree: Displacement degree.
        solver: A name of :func:`solver_options`.
        level: The level itself, instead of ``unknowns``.
    """
    comm = MPI.COMM_WORLD
    progress = Progress(comm, f"{name}, {comm.size} rank(s)")
    run = pipeline(comm, unknowns, degree=degree, solver=solver, level=level, log=progress)
    run["versions"] = versions()
    if comm.rank == 0:
        Path(path).write_text(json.dumps(run))

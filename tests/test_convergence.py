# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The convergence-study API: known rates, round-off errors, MPI, JSON, plots, bad input."""

import json
import math
import pathlib

from mpi4py import MPI

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s.compat import DOLFINX_VERSION
from dolfinx_contact_s2s.convergence import (
    SECONDS,
    ConvergenceTable,
    assert_rate,
    convergence_study,
)
from paper import scenes
from paper.blocks import block_problem
from paper.records import records, update_results

# --- a problem with known rates: P1 Poisson, smooth manufactured solution ---------------


def exact(x):
    return ufl.sin(ufl.pi * x[0]) * ufl.sin(2 * ufl.pi * x[1]) * ufl.exp(x[0])


class PoissonSolution:
    """A solved -Δu = f on the unit square, u = 0 on the boundary, shaped like a problem."""

    def __init__(self, comm, n):
        mesh = dolfinx.mesh.create_unit_square(comm, n, n)
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
        self.spaces = [V]
        x = ufl.SpatialCoordinate(mesh)
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        f = -ufl.div(ufl.grad(exact(x)))
        a = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx
        L = f * v * ufl.dx(metadata={"quadrature_degree": 6})
        fdim = mesh.topology.dim - 1
        mesh.topology.create_connectivity(fdim, mesh.topology.dim)
        facets = dolfinx.mesh.exterior_facet_indices(mesh.topology)
        dofs = dolfinx.fem.locate_dofs_topological(V, fdim, facets)
        bc = dolfinx.fem.dirichletbc(dolfinx.default_scalar_type(0.0), dofs, V)
        options = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}
        extra = {"petsc_options_prefix": f"conv_poisson_{n}_"} if DOLFINX_VERSION >= (0, 10) else {}
        self._problem = dolfinx.fem.petsc.LinearProblem(
            a, L, bcs=[bc], petsc_options=options, **extra
        )
        out = self._problem.solve()
        self.u = out[0] if isinstance(out, tuple) else out
        self.A = self._problem.A
        self.x = x

    def error(self, kind):
        e = self.u - exact(self.x)
        integrand = ufl.inner(ufl.grad(e), ufl.grad(e)) if kind == "H1" else e * e
        form = dolfinx.fem.form(integrand * ufl.dx(metadata={"quadrature_degree": 6}))
        comm = self.u.function_space.mesh.comm
        return math.sqrt(comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM))

    def destroy(self):
        for obj in (self._problem.solver, self._problem.A, self._problem.b):
            obj.destroy()
        self.A = None


POISSON_LEVELS = [8, 16, 32, 64]


def poisson_study(comm, log=None):
    return convergence_study(
        lambda n: PoissonSolution(comm, n),
        POISSON_LEVELS,
        errors={"H1": lambda s: s.error("H1"), "L2": lambda s: s.error("L2")},
        name="Poisson P1",
        comm=comm,
        log=log,
    )


@pytest.fixture(scope="module")
def poisson_world():
    lines = []
    table = poisson_study(MPI.COMM_WORLD, log=lines.append)
    return table, lines


def test_known_rates(poisson_world):
    table, lines = poisson_world
    assert_rate(table, "H1", 1.0, tolerance=0.1)
    assert_rate(table, "L2", 2.0, tolerance=0.1)
    assert assert_rate(table, "L2", 1.8, at_least=True) > 1.9
    with pytest.raises(AssertionError, match=r"expected 3 ± 0\.1"):
        assert_rate(table, "L2", 3.0)
    assert len(table.rates("H1")) == len(POISSON_LEVELS) - 1
    # Default h: the largest cell diameter, sqrt(2)/n on the unit square.
    assert np.allclose(table.h(), np.sqrt(2) / np.array(POISSON_LEVELS), rtol=1e-14)
    # Default unknowns: the global size of A (Dirichlet rows included).
    assert [lv.unknowns for lv in table.levels] == [(n + 1) ** 2 for n in POISSON_LEVELS]
    assert table.ranks == MPI.COMM_WORLD.size
    # Progress: one line per level, on rank 0 only.
    if MPI.COMM_WORLD.rank == 0:
        assert len(lines) == len(POISSON_LEVELS)
        assert all(
            f"level {n}:" in line and "H1=" in line
            for n, line in zip(POISSON_LEVELS, lines, strict=True)
        )
    else:
        assert lines == []
    for lv in table.levels:
        assert set(lv.seconds) == set(SECONDS)
        # No timings on the object: everything is setup.
        assert lv.seconds["setup"] == lv.seconds["total"] > 0


def test_serial_equals_parallel(poisson_world):
    comm = MPI.COMM_WORLD
    if comm.size == 1:
        pytest.skip("compares a distributed study with a serial one")
    world, _ = poisson_world
    serial = poisson_study(MPI.COMM_SELF)
    assert serial.ranks == 1 and world.ranks == comm.size
    assert [lv.level for lv in serial.levels] == [lv.level for lv in world.levels]
    assert [lv.unknowns for lv in serial.levels] == [lv.unknowns for lv in world.levels]
    assert np.array_equal(serial.h(), world.h())
    # The two LU solves differ by eps * cond(A) * |u|, cond(A) ~ n^2 and |u| ~ 1; so do
    # the errors (a relative 2e-12 for L2 at n = 64: more than 1e-12, far below this).
    bound = np.finfo(np.float64).eps * np.array(POISSON_LEVELS, dtype=np.float64) ** 2
    for name in ("H1", "L2"):
        assert np.all(np.abs(serial.errors(name) - world.errors(name)) <= bound)
    # Every rank holds the same table.
    tables = comm.allgather(world.to_dict())
    for t in tables:
        assert t["levels"] == tables[0]["levels"] and t["rates"] == tables[0]["rates"]


# --- round-off errors: the tied patch test ----------------------------------------------


def solve_patch(n):
    scene = scenes.patch_test(MPI.COMM_WORLD, (n, 2 * n - 1), cell="quadrilateral")
    problem = block_problem(
        scene, (1, 1), "upper", support="rollers", pressure=1.0, petsc_options_prefix="conv_patch_"
    )
    problem.solve()
    return problem


def pressure_error(problem):
    lam = problem.multipliers[0]
    owned = lam.function_space.dofmap.index_map.size_local
    local = np.max(np.abs(lam.x.array[:owned] - 1.0), initial=0.0)
    return problem.comm.allreduce(local, op=MPI.MAX)


def test_patch_test_roundoff():
    table = convergence_study(
        solve_patch, [3, 6, 12], errors={"pressure": pressure_error}, name="patch", log=None
    )
    assert np.all(table.errors("pressure") < 1e-10)
    assert np.all(np.isnan(table.rates("pressure")))
    assert math.isnan(table.fitted_rate("pressure"))
    data = table.to_dict()
    assert data["rates"]["pressure"] == [None, None]
    assert data["fitted_rates"]["pressure"] is None
    json.dumps(data, allow_nan=False)
    with pytest.raises(AssertionError, match="round-off"):
        assert_rate(table, "pressure", 1.0)
    assert "n/a" in table.markdown()
    for lv in table.levels:
        s = lv.seconds
        assert set(s) == set(SECONDS)
        assert min(s.values()) >= 0 and s["contact"] > 0 and s["solve"] > 0
        parts = s["contact"] + s["assembly"] + s["solve"]
        assert s["total"] >= parts
        assert s["setup"] + parts == pytest.approx(s["total"], rel=1e-12)
    # Unknowns: the saddle point's size, displacements and multipliers.
    assert np.all(np.diff([lv.unknowns for lv in table.levels]) > 0)


# --- output: JSON, records, Markdown, plot -----------------------------------------------


def shared_dir(tmp_path):
    """One directory for every rank (pytest gives each process its own tmp_path)."""
    return pathlib.Path(MPI.COMM_WORLD.bcast(str(tmp_path), root=0))


def synthetic_study(**kwargs):
    """Exact rates without a mesh: e = h^2, a zero error, unknowns n^2."""
    return convergence_study(
        lambda n: n,
        [2, 4, 8, 16],
        errors={"e": lambda n: float(n) ** -2, "zero": lambda n: 0.0},
        h=lambda n: 1.0 / n,
        unknowns=lambda n: n * n,
        name="synthetic",
        log=None,
        **kwargs,
    )


def test_output(tmp_path, poisson_world):
    comm = MPI.COMM_WORLD
    directory = shared_dir(tmp_path)
    table = synthetic_study()
    assert np.allclose(table.rates("e"), 2.0, rtol=1e-14)
    assert table.fitted_rate("e", last=4) == pytest.approx(2.0, rel=1e-12)
    assert assert_rate(table, "e", 2.0, tolerance=1e-12, last=4) == pytest.approx(2.0)
    with pytest.raises(AssertionError, match="round-off"):
        assert_rate(table, "zero", 0.0)
    with pytest.raises(ValueError, match="last=5"):
        table.fitted_rate("e", last=5)
    with pytest.raises(ValueError, match="no error"):
        table.rates("missing")

    # JSON round trip, through the file.
    path = directory / "table.json"
    table.write_json(path)
    again = ConvergenceTable.from_dict(json.loads(path.read_text()))
    assert again == table
    assert again.to_dict() == table.to_dict()

    world, _ = poisson_world
    again = ConvergenceTable.from_dict(json.loads(json.dumps(world.to_dict())))
    assert again.levels == world.levels
    assert again.rates("L2") == world.rates("L2")

    text = world.markdown()
    assert sum(line.startswith("| ") for line in text.splitlines()) == 1 + len(POISSON_LEVELS)
    for lv in world.levels:
        assert f"| {lv.level} | {lv.h:.4g} | {lv.unknowns} |" in text
    assert "Fitted rate over the last 3 levels" in text

    png = directory / "poisson.png"
    world.plot(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    table.plot(directory / "synthetic.png")

    # Records of results/convergence.json: replace own study and rank count, keep the rest.
    results = directory / "convergence.json"
    ranks = comm.size
    mine = records(world, study="poisson", method="P1", degree=1, cell="triangle")
    assert [r["quantity"] for r in mine] == ["H1", "L2"]
    assert mine[0]["levels"][0]["seconds"] == world.levels[0].seconds["total"]
    other = records(table, study="other", variant="synthetic")
    assert other[1]["rates"] == [None] * 3 and other[1]["fitted_rate"] is None
    update_results(results, other, study="other", ranks=ranks)
    update_results(results, mine, study="poisson", ranks=ranks)
    update_results(results, mine[:1], study="poisson", ranks=ranks)
    stored = json.loads(results.read_text())
    assert [(r["study"], r["quantity"]) for r in stored] == [
        ("other", "e"),
        ("other", "zero"),
        ("poisson", "H1"),
    ]
    assert stored[2] == mine[0]
    with pytest.raises(ValueError, match="study 'poisson'"):
        update_results(results, mine, study="other", ranks=ranks)
    with pytest.raises(ValueError, match="study="):
        records(table)


# --- bad input: ValueError on every rank -------------------------------------------------


@pytest.mark.parametrize(
    "levels, match", [([4, 4], "does not decrease"), ([8, 4], "does not decrease"), ([], "one")]
)
def test_levels_not_refining(levels, match):
    with pytest.raises(ValueError, match=match):
        convergence_study(
            lambda n: n, levels, {"e": lambda n: 1.0 / n}, h=lambda n: 1.0 / n, unknowns=int
        )


@pytest.mark.parametrize("value", [math.nan, math.inf, -1.0])
def test_bad_error_value(value):
    with pytest.raises(ValueError, match="not a finite non-negative"):
        convergence_study(
            lambda n: n, [2, 4], {"e": lambda n: value}, h=lambda n: 1.0 / n, unknowns=int
        )


def test_values_differ_between_ranks():
    comm = MPI.COMM_WORLD
    if comm.size == 1:
        pytest.skip("needs two ranks")
    rank = float(comm.rank)
    with pytest.raises(ValueError, match="e differs between the ranks"):
        convergence_study(
            lambda n: n, [2, 4], {"e": lambda n: rank}, h=lambda n: 1.0 / n, unknowns=int
        )
    with pytest.raises(ValueError, match="h differs between the ranks"):
        convergence_study(
            lambda n: n, [2, 4], {"e": lambda n: 1.0}, h=lambda n: 1.0 / (n + rank), unknowns=int
        )


def test_default_h_needs_spaces():
    with pytest.raises(ValueError, match="give h="):
        convergence_study(lambda n: n, [2], {"e": lambda n: 1.0}, log=None)

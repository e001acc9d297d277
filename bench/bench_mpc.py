# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""P5: the patch test by dolfinx_mpc's contact slip constraint beside composite S2S.

The nearest thing DOLFINx users have today to tied frictionless contact between
non-matching meshes is dolfinx_mpc's slip condition between two facet sets
(``MultiPointConstraint.create_contact_slip_condition``: every slave node's normal
displacement equals that of the master surface at the node, eliminated from the system),
solved by ``dolfinx_mpc.LinearProblem``. Both methods solve the same patch test (section
3.2, Figs. 4 and 6) on the same meshes: two blocks in one mesh
(:func:`~paper.scenes_multi.two_blocks_one_mesh`, triangles, 10k and 7k
elements along the contact line, different materials), rollers, a pressure :math:`p` on
top. The exact solution is :math:`\sigma_{yy} = -p`, :math:`\sigma_{xx} =
\sigma_{xy} = 0` and a contact pressure :math:`p`.

Measured at each size, both methods on the same mesh and space:

- the stress error :math:`\max |\sigma - \sigma_{exact}| / p` over both bodies, and
  over the cells along the contact surface of the upper body (the contact pressure
  :math:`-\sigma_{yy}` there), for both; for S2S also the multiplier's
  :math:`\max |\lambda - p| / p`;
- the time of each: constraint or contact pair set-up, assembly and solve (MUMPS LU),
  after a warm-up of both on a tiny mesh (Numba and form compilation excluded).

A control checks the set-up of the constraint: on matching meshes (10 and 10 elements)
dolfinx_mpc must pass the patch test to round-off (``control`` in the record).

The figure is the time of dolfinx_mpc over that of S2S at the largest size.
Writes ``results/bench/p5_mpc.json`` (nothing, with a notice, without dolfinx_mpc).
"""

import argparse
import importlib.util
import sys
from pathlib import Path

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--smoke", action="store_true", help="tiny sizes (seconds)")
parser.add_argument("--levels", type=int, nargs="+", default=[4, 16, 48])
parser.add_argument("--degree", type=int, default=1)
parser.add_argument("--out", type=Path, default=Path("results/bench"))
args = parser.parse_args()
if importlib.util.find_spec("dolfinx_mpc") is None:
    print("[P5] dolfinx_mpc is not installed: no P5 record", flush=True)
    sys.exit(0)

from mpi4py import MPI  # noqa: E402

import dolfinx  # noqa: E402
import dolfinx_mpc  # noqa: E402
import dolfinx_mpc.utils  # noqa: E402
import numpy as np  # noqa: E402
import ufl  # noqa: E402

from dolfinx_contact_s2s import contact_pair, contact_surface  # noqa: E402
from dolfinx_contact_s2s.problem import LinearContactProblem  # noqa: E402
from paper.bench import (  # noqa: E402
    Progress,
    backend_name,
    make_record,
    timed,
    write_record,
)
from paper.blocks import MATERIALS  # noqa: E402
from paper.patch_test import contact_pressure  # noqa: E402
from paper.scenes_multi import two_blocks_one_mesh  # noqa: E402

comm = MPI.COMM_WORLD
log = Progress(comm, "P5")
PRESSURE = 0.75
#: Cell tags of two_blocks_one_mesh and the materials of the patch test.
CELL_MATERIALS = {1: MATERIALS["lower"], 2: MATERIALS["upper"]}
LU = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}


class Model:
    """The patch problem on the one mesh of both blocks: space, forms, supports."""

    def __init__(self, level: int, degree: int, elements: tuple[int, int] | None = None):
        """Mesh the blocks (10 level and 7 level elements along the contact line)."""
        elements = elements or (10 * level, 7 * level)
        self.scene = two_blocks_one_mesh(comm, elements, cell="triangle")
        part = self.scene.parts["blocks"]
        self.mesh, self.facet_tags = part.mesh, part.facet_tags
        self.V = dolfinx.fem.functionspace(self.mesh, ("Lagrange", degree, (2,)))
        Q0 = dolfinx.fem.functionspace(self.mesh, ("Discontinuous Lagrange", 0))
        self.mu, self.lmbda = dolfinx.fem.Function(Q0), dolfinx.fem.Function(Q0)
        for tag, material in CELL_MATERIALS.items():
            dofs = Q0.dofmap.list[part.cell_tags.find(tag)].ravel()
            self.mu.x.array[dofs], self.lmbda.x.array[dofs] = material.lame
        u, v = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        ds = ufl.Measure("ds", domain=self.mesh, subdomain_data=self.facet_tags)
        self.a = ufl.inner(self.sigma(u), ufl.sym(ufl.grad(v))) * ufl.dx
        self.L = -PRESSURE * v[1] * ds(self.scene.tag("upper", "top"))
        self.bcs = []
        for component, sides in enumerate((self.scene.fixed_x, self.scene.fixed_y)):
            for block, side in sides:
                facets = self.facet_tags.find(self.scene.tag(block, side))
                dofs = dolfinx.fem.locate_dofs_topological(self.V.sub(component), 1, facets)
                zero = dolfinx.default_scalar_type(0)
                self.bcs.append(dolfinx.fem.dirichletbc(zero, dofs, self.V.sub(component)))
        self.slave = self.scene.tag("upper", "bottom")
        self.master = self.scene.tag("lower", "top")

    def sigma(self, u):
        """Plane-strain stress of ``u`` with the materials of the cells."""
        eps = ufl.sym(ufl.grad(u))
        return 2 * self.mu * eps + self.lmbda * ufl.tr(eps) * ufl.Identity(2)

    def stress_errors(self, u: dolfinx.fem.Function) -> tuple[float, float]:
        """Relative stress errors: everywhere, and in the upper cells along the contact."""
        W = dolfinx.fem.functionspace(self.mesh, ("Discontinuous Lagrange", 1, (2, 2)))
        points = W.element.interpolation_points
        s = dolfinx.fem.Function(W)
        s.interpolate(
            dolfinx.fem.Expression(self.sigma(u), points() if callable(points) else points)
        )
        cells = self.mesh.topology.index_map(2).size_local
        values = s.x.array.reshape(-1, 4)
        dofs = W.dofmap.list[:cells]
        exact = np.array([0.0, 0.0, 0.0, -PRESSURE])
        everywhere = np.max(np.abs(values[dofs.ravel()] - exact), initial=0.0) / PRESSURE
        self.mesh.topology.create_connectivity(1, 2)
        f2c = self.mesh.topology.connectivity(1, 2)
        near = np.unique(
            np.concatenate(
                [f2c.links(f) for f in self.facet_tags.find(self.slave)] or [np.zeros(0, int)]
            )
        )
        near = near[near < cells].astype(np.int32)
        pressure = -values[dofs[near].ravel(), 3]
        contact = np.max(np.abs(pressure - PRESSURE), initial=0.0) / PRESSURE
        return (
            comm.allreduce(float(everywhere), op=MPI.MAX),
            comm.allreduce(float(contact), op=MPI.MAX),
        )


def solve_mpc(model: Model) -> tuple[dolfinx.fem.Function, dict]:
    """The patch test by dolfinx_mpc's contact slip condition; the stages' times."""
    times = {}

    def constraint():
        normal = dolfinx_mpc.utils.create_normal_approximation(
            model.V, model.facet_tags, model.slave
        )
        mpc = dolfinx_mpc.MultiPointConstraint(model.V)
        mpc.create_contact_slip_condition(model.facet_tags, model.slave, model.master, normal)
        mpc.finalize()
        return mpc

    mpc, times["constraint"] = timed(comm, constraint)
    problem, times["problem"] = timed(
        comm,
        lambda: dolfinx_mpc.LinearProblem(
            model.a, model.L, mpc, bcs=model.bcs, petsc_options=dict(LU)
        ),
    )
    u, times["assemble_and_solve"] = timed(comm, problem.solve)
    times["total"] = sum(times.values())
    return u, times


def solve_s2s(model: Model) -> tuple[dolfinx.fem.Function, float, str, dict]:
    """The patch test by composite S2S; the multiplier's error and the stages' times."""
    times = {}
    pair, times["pair"] = timed(
        comm,
        lambda: contact_pair(
            contact_surface(model.V, model.facet_tags, model.slave),
            contact_surface(model.V, model.facet_tags, model.master),
        ),
    )
    problem, times["problem"] = timed(
        comm,
        lambda: LinearContactProblem(
            model.a, model.L, [pair], model.bcs, petsc_options_prefix="bench_p5_", petsc_options=LU
        ),
    )
    ((u,), (lam,)), times["assemble_and_solve"] = timed(comm, problem.solve)
    values = contact_pressure(pair, lam, problem.operators[0].inactive)
    error = np.max(np.abs(values - PRESSURE), initial=0.0) / PRESSURE
    problem.destroy()
    times["total"] = sum(times.values())
    return u, comm.allreduce(float(error), op=MPI.MAX), backend_name(pair.contactor), times


with log.step("warm-up of both on a tiny mesh (Numba and form compilation)"):
    tiny = Model(1, args.degree)
    (_, warm_mpc), t_warm = timed(comm, lambda: solve_mpc(tiny))
    solve_s2s(tiny)

with log.step("control: dolfinx_mpc on matching meshes (10 and 10 elements)"):
    matching = Model(1, args.degree, elements=(10, 10))
    u_matching, _ = solve_mpc(matching)
    e_all, e_contact = matching.stress_errors(u_matching)
    control = {"stress_error": e_all, "contact_stress_error": e_contact}
log(f"  dolfinx_mpc on matching meshes: stress error {control['stress_error']:.1e}")

rows = []
for level in [1, 2] if args.smoke else args.levels:
    with log.step(f"level {level}: elements {10 * level} and {7 * level} along the contact"):
        model = Model(level, args.degree)
    dofs = model.V.dofmap.index_map.size_global * 2
    u_mpc, t_mpc = solve_mpc(model)
    e_mpc, c_mpc = model.stress_errors(u_mpc)
    u_s2s, lam_err, backend, t_s2s = solve_s2s(model)
    e_s2s, c_s2s = model.stress_errors(u_s2s)
    rows.append(
        {
            "level": level,
            "elements": [10 * level, 7 * level],
            "displacements": dofs,
            "mpc": {"stress_error": e_mpc, "contact_stress_error": c_mpc, "times": t_mpc},
            "s2s": {
                "stress_error": e_s2s,
                "contact_stress_error": c_s2s,
                "pressure_error": lam_err,
                "times": t_s2s,
            },
        }
    )
    log(
        f"  {dofs} displacements: dolfinx_mpc stress error {e_mpc:.2e} (at the contact "
        f"{c_mpc:.2e}) in {t_mpc['total']:.2f} s; S2S {e_s2s:.2e} (at the contact {c_s2s:.2e}, "
        f"multiplier {lam_err:.2e}) in {t_s2s['total']:.2f} s"
    )

last = rows[-1]
ratio = last["mpc"]["times"]["total"] / last["s2s"]["times"]["total"]
record = make_record(
    "p5_mpc",
    comm,
    figure="P5",
    title="patch test: dolfinx_mpc contact slip constraint over composite S2S (time)",
    backend=backend,
    times={
        "mpc_seconds": last["mpc"]["times"]["total"],
        "s2s_seconds": last["s2s"]["times"]["total"],
        "mpc_warm_up_seconds": t_warm,
    },
    ratio=ratio,
    smoke=args.smoke,
    ratio_definition="t(dolfinx_mpc: constraint + problem + assemble + solve) / "
    "t(S2S: pair + problem + assemble + solve), largest size, both with MUMPS LU",
    errors={
        "mpc_stress": last["mpc"]["stress_error"],
        "mpc_contact_stress": last["mpc"]["contact_stress_error"],
        "s2s_stress": last["s2s"]["stress_error"],
        "s2s_contact_stress": last["s2s"]["contact_stress_error"],
        "s2s_pressure": last["s2s"]["pressure_error"],
    },
    degree=args.degree,
    control=control,
    rows=rows,
)
write_record(args.out, record, comm)
log(
    f"P5: dolfinx_mpc / S2S time = {ratio:.2f}; stress errors {last['mpc']['stress_error']:.1e} "
    f"(dolfinx_mpc) against {last['s2s']['stress_error']:.1e} (S2S)"
)

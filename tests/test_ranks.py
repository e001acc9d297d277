# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Parallel consistency: every kind of scene gives the same answer on any number of ranks.

Each case is solved twice in one run: on ``COMM_WORLD`` (1, 2 or 3 ranks) and on
``COMM_SELF`` (every rank alone: the serial reference). The two are compared in a
numbering that does not depend on the partition: every displacement dof by its body
(connected component), component and coordinates, every multiplier by its coordinates.
Compared: the coupling :math:`\mathbf B` of every pair (Eq. 40), the displacements, the
multipliers (the contact pressures), the multipliers set to zero (uncovered, two-pass
duplicates) and, for unilateral contact (Eq. 1), the active sets, which must agree
exactly.

Bounds, from outside the code:

- :math:`\mathbf B`: every entry is a sum of a few sub-segment contributions, each
  computed from the same facet geometry whatever the partition (the facet coefficients
  are relative to the cell's first node, the targets are gathered in full); the
  partition changes only the order of the sum (the gathered facets' order, the entries
  sent to their owners). Two orders of a sum of :math:`m` terms :math:`t` differ by at
  most :math:`(m - 1)\,\epsilon \sum |t|` (recursive summation, unit round-off
  :math:`\epsilon / 2` each); here :math:`m \le 6` (a multiplier spans 2 contactor
  facets, each cut into at most 3 sub-segments in these scenes), and :data:`B_FACTOR`
  :math:`= 16` allows :math:`\sum |t|` up to about :math:`3 \max |\mathbf B|` (P2
  basis functions change sign, so the terms may cancel): :data:`B_FACTOR`
  :math:`\epsilon \max |\mathbf B|`.
- The solution :math:`\mathbf x = (\mathbf U, \Lambda)`: two backward-stable solves of the
  same system (up to the round-off of :math:`\mathbf B`), each with a backward error
  :math:`\omega` (measured, and asserted below :data:`OMEGA_FACTOR` :math:`\epsilon`),
  differ by at most :math:`2 \kappa_\infty(\mathbf A)\, \omega\, \|\mathbf x\|_\infty`
  to first order: the bound :data:`X_FACTOR` :math:`\epsilon\, \kappa_\infty(\mathbf A)
  \|\mathbf x\|_\infty` on every component, with :math:`\kappa_\infty` estimated on the
  serial saddle point (Hager's 1-norm estimator; the matrix is symmetric).

Partitions: forced through a cell partitioner on the Gmsh reader (:func:`partitioner`)
for every case: every cell with a contact facet on rank 0 (the other ranks own no
contact facet), and the contact line cut in slabs with the contactor's slabs on other
ranks than the target's (each pair split across ranks); for a few cases also DOLFINx's
graph partitioner and the bodies on either side of the contact on different ranks (on 3
ranks, rank 1 then owns no cell of a two-mesh scene). Each forced partition is checked
to be what it claims. On one rank every case runs once. Set ``S2S_RANKS_JSON=path`` to
write the largest disagreements seen, the backward errors and the facets each rank owns.
"""

from __future__ import annotations

import functools
import json
import os
import typing
from dataclasses import dataclass

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import numpy as np
import pytest
import ufl
from partition_keys import dof_perm as _dof_perm
from partition_keys import gather as _gather
from partition_keys import keys as _keys
from partition_keys import match, matrix_difference, matrix_entries
from readme_model import readme_mesh

from dolfinx_contact_s2s import Material, contact_surface
from dolfinx_contact_s2s.checks import connected_components
from dolfinx_contact_s2s.pair import contact_pairs
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem
from paper.blocks import block_problem
from paper.hertz.study import HertzCase, hertz_model
from paper.scenes import BOTTOM, TOP, inf_sup_model, patch_test
from paper.scenes_multi import overhang, three_blocks, two_on_one

EPS = np.finfo(np.float64).eps

#: Bound on |B_world - B_self| in units of eps max|B| (a reordered sum of <= 8 terms).
B_FACTOR = 16.0
#: Largest backward error of a solve, in units of eps. With two steps of iterative
#: refinement on every number of processes (``options.refine_distributed``) the largest
#: measured over these cases is 0.5 (condition up to 1e9); without them on several
#: processes, 30 on the intermediate surface's saddle point and up to 115 on the P1
#: patch test (3 processes).
OMEGA_FACTOR = 100.0
#: Bound on |x_world - x_self| in units of eps kappa_inf(A) ||x||_inf: 2 omega.
X_FACTOR = 2 * OMEGA_FACTOR

PARTITIONS = ("default", "contact on rank 0", "crossed", "bodies apart")
#: The partitions every case runs on (a few cases run on all).
FORCED = ("contact on rank 0", "crossed")

#: Largest disagreement seen per quantity: absolute and relative to its bound.
SUMMARY: dict[str, dict] = {}
#: Per case and partition: the contactor and target facets each rank owns (per pair).
PARTITION_COUNTS: dict[str, list] = {}
#: Largest backward error (units of eps) and condition estimate seen.
SOLVES: dict[str, typing.Any] = {"omega_over_eps": 0.0, "kappa": 0.0}


# ---------------------------------------------------------------------------------------
# Partitions forced on the Gmsh reader


def partitioner(rule: str, contact_tags: tuple[int, ...] | dict[str, tuple[int, ...]], y0: float):
    """A cell partitioner for :func:`~dolfinx_contact_s2s.meshing.model_to_mesh`.

    The process holding the Gmsh model decides from the model's nodes: a cell is a
    contact cell when two of its vertices lie on a curve of ``contact_tags`` (it then
    has a contact facet; a dict gives the tags of each Gmsh model by name); ``y0``
    separates the bodies below (targets or contactors) from those above.

    - ``"contact on rank 0"``: every contact cell on rank 0, the other cells on ranks
      1, 2, ... in vertical slabs: those ranks own no contact facet.
    - ``"bodies apart"``: the bodies below ``y0`` on the last rank, those above on rank
      0: every contactor facet faces targets of another rank only, and a mesh of
      bodies on one side has no cell on the other ranks (on 3 ranks, rank 1 owns none).
    - ``"crossed"``: vertical slabs of the contact line's extent, the slab ``k`` of the
      bodies below ``y0`` on rank ``k``, of those above on rank ``n - 1 - k``: each pair
      is split across ranks, most facets facing facets of another rank.
    """

    def partition(comm, nparts, cell_types, cells):
        nv = dolfinx.cpp.mesh.cell_num_vertices(cell_types[0])
        topology = np.asarray(cells[0], dtype=np.int64).reshape(-1, nv)
        dest = np.zeros(topology.shape[0], dtype=np.int32)
        if topology.shape[0] and nparts > 1:
            import gmsh

            tags, xyz, _ = gmsh.model.mesh.getNodes()
            x = np.zeros((int(tags.max()), 3))
            x[tags.astype(np.int64) - 1] = np.reshape(xyz, (-1, 3))
            on = np.zeros(x.shape[0], dtype=bool)
            curves = contact_tags
            if isinstance(curves, dict):
                curves = curves[gmsh.model.getCurrent()]
            for tag in curves:
                nodes, _ = gmsh.model.mesh.getNodesForPhysicalGroup(1, tag)
                on[np.asarray(nodes, dtype=np.int64) - 1] = True
            mid = x[topology].mean(axis=1)
            contact = np.count_nonzero(on[topology], axis=1) >= 2
            if rule == "contact on rank 0":
                lo, width = x[:, 0].min(), np.ptp(x[:, 0])
                slab = np.floor((nparts - 1) * (mid[:, 0] - lo) / width).astype(np.int64)
                dest = np.where(contact, 0, 1 + np.clip(slab, 0, nparts - 2))
            elif rule == "bodies apart":
                dest = np.where(mid[:, 1] < y0, nparts - 1, 0)
            elif rule == "crossed":
                lo, width = x[on, 0].min(), np.ptp(x[on, 0])
                slab = np.floor(nparts * (mid[:, 0] - lo) / width).astype(np.int64)
                slab = np.clip(slab, 0, nparts - 1)
                dest = np.where(mid[:, 1] < y0, slab, nparts - 1 - slab)
            else:
                raise ValueError(f"unknown partition rule {rule!r}")
        adj = dolfinx.graph.adjacencylist(dest.astype(np.int32))
        return getattr(adj, "_cpp_object", adj)  # a Python wrapper from DOLFINx 0.10

    return partition


def _partitioner(partition: str, contact_tags, y0: float):
    return None if partition == "default" else partitioner(partition, contact_tags, y0)


# ---------------------------------------------------------------------------------------
# Scenes (collective: every rank builds them in the same order)


@functools.cache
def readme_scene(comm_name: str, partition: str):
    """The README's two blocks in one mesh (lower top 10, upper bottom 20), as a user builds it."""
    comm = MPI.COMM_WORLD if comm_name == "world" else MPI.COMM_SELF
    return readme_mesh(comm, partitioner=_partitioner(partition, (10, 20), 0.5))


#: The scenes of :mod:`~paper.scenes_multi` in one mesh: constructor, (E, nu)
#: by cell tag (each block its own; blocks side by side under one block of the same
#: vertical compliance), pairs as (contactor block, [target blocks]) of bottoms on tops,
#: and the tags of their contact lines.
MULTI = {
    "three blocks": (
        three_blocks,
        {1: (1.0, 0.3), 2: ((1 - 0.2**2) / (1 - 0.3**2), 0.2), 3: (3.0, 0.25)},
        [("upper", ["lower_left", "lower_right"])],
        (13, 23, 30),
    ),
    "overhang": (overhang, {1: (1.0, 0.3), 2: (3.0, 0.2)}, [("upper", ["lower"])], (10, 20)),
    "two on one": (
        two_on_one,
        {1: (1.0, 0.3), 2: (3.0, 0.2), 3: (3.0, 0.2)},
        [("upper_left", ["lower"]), ("upper_right", ["lower"])],
        (13, 20, 30),
    ),
}


@functools.cache
def multi_scene(name: str, comm_name: str, partition: str):
    """A scene of several blocks in ONE mesh (one displacement space for all bodies)."""
    build, _, _, tags = MULTI[name]
    return build(
        _comm(comm_name), arrangement="one mesh", partitioner=_partitioner(partition, tags, 0.5)
    )


@functools.cache
def two_meshes(comm_name: str, partition: str, inf_sup: bool):
    """The studies' two blocks, a mesh each: the patch test, or the overlapping inf-sup model.

    The contact lines: the lower mesh's top (3), the upper mesh's bottom (1).
    """
    tags = {"lower": (TOP,), "upper": (BOTTOM,)}
    split = _partitioner(partition, tags, 0.5)
    if inf_sup:
        return inf_sup_model(
            _comm(comm_name), (10, 7), cell="quadrilateral", geometry_degree=2, partitioner=split
        )
    return patch_test(_comm(comm_name), (10, 7), partitioner=split)


def _comm(comm_name: str) -> MPI.Comm:
    return MPI.COMM_WORLD if comm_name == "world" else MPI.COMM_SELF


# ---------------------------------------------------------------------------------------
# Problems


@dataclass(frozen=True)
class Case:
    """One scene and discretization.

    Attributes:
        scene: ``"readme"``, one of :data:`MULTI`, ``"patch test"``, ``"inf-sup model"``
            or ``"hertz"``.
        degree: Displacement degree.
        method: ``contact_pairs``'s method.
        contactor: ``"upper"`` or ``"lower"`` body as the contactor.
        cell: Hertz only: the cell type.
        multiplier: ``contact_pair``'s multiplier space (None: its default).
    """

    scene: str
    degree: int
    method: str = "segment-to-segment"
    contactor: str = "upper"
    cell: str = "triangle"
    multiplier: tuple[str, int] | None = None

    @property
    def id(self) -> str:
        space = "" if self.multiplier is None else f"-{self.multiplier[0]}{self.multiplier[1]}"
        return f"{self.scene}-P{self.degree}-{self.method}{space}-{self.contactor}-{self.cell}"


CASES = [
    Case("readme", 1),
    Case("readme", 1, contactor="lower"),
    Case("readme", 2),
    Case("readme", 2, contactor="lower"),
    Case("readme", 1, "node-to-segment"),
    Case("readme", 1, "two-pass node-to-segment"),
    Case("readme", 1, "intermediate-surface"),
    Case("readme", 1, multiplier=("DG", 0)),
    # Several bodies in one mesh: a contactor facing two targets, uncovered multipliers
    # (the upper block overhangs), two contactors on one target.
    Case("three blocks", 1),
    Case("overhang", 1),
    Case("two on one", 1),
    # Two meshes and spaces (the studies' scenes); the inf-sup model overlaps (G != 0).
    Case("patch test", 1, contactor="lower"),
    Case("inf-sup model", 2, cell="quadrilateral"),
    # Unilateral contact, active sets; curved (P2 geometry) arcs of two cylinders.
    Case("hertz", 1),
    Case("hertz", 2, cell="quadrilateral"),
]


#: The cases that also run on DOLFINx's own partition and with the bodies apart.
ALL_PARTITIONS = {
    Case("readme", 1),
    Case("readme", 2, contactor="lower"),
    Case("patch test", 1, contactor="lower"),
    Case("inf-sup model", 2, cell="quadrilateral"),
    Case("hertz", 1),
    Case("hertz", 2, cell="quadrilateral"),
}
assert ALL_PARTITIONS <= set(CASES)


def _hertz_case(case: Case) -> HertzCase:
    # A small level: about 6 (P1) or 4 (P2) elements across the contact width 2a.
    return HertzCase(
        degree=case.degree,
        cell=case.cell,
        elements_across=6 if case.degree == 1 else 4,
        a=0.1,
        R2=2.0 if case.degree == 2 else float("inf"),
        far_size=0.5,
    )


def _readme_problem(case: Case, comm_name: str, partition: str, prefix: str):
    mesh, facets = readme_scene(comm_name, partition)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", case.degree, (2,)))
    a, _, v = Material(E=1.0, nu=0.3).forms(V)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.array([0.0, -1.0])), v) * ds(23)
    left = np.concatenate([facets.find(4), facets.find(24)])
    bcs = [
        dolfinx.fem.dirichletbc(
            0.0, dolfinx.fem.locate_dofs_topological(V.sub(0), 1, left), V.sub(0)
        ),
        dolfinx.fem.dirichletbc(
            0.0, dolfinx.fem.locate_dofs_topological(V.sub(1), 1, facets.find(1)), V.sub(1)
        ),
    ]
    surfaces = {"upper": contact_surface(V, facets, 20), "lower": contact_surface(V, facets, 10)}
    target = "lower" if case.contactor == "upper" else "upper"
    options = {"weight": "tributary"} if case.method == "node-to-segment" else {}
    if case.multiplier is not None:
        options["multiplier"] = case.multiplier
    pairs = contact_pairs(surfaces[case.contactor], surfaces[target], method=case.method, **options)
    return LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix=prefix)


def _multi_problem(case: Case, comm_name: str, partition: str, prefix: str):
    scene = multi_scene(case.scene, comm_name, partition)
    _, materials, pairs_spec, _ = MULTI[case.scene]
    part = scene.parts["blocks"]
    mesh, ft = part.mesh, part.facet_tags
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", case.degree, (2,)))
    Q0 = dolfinx.fem.functionspace(mesh, ("Discontinuous Lagrange", 0))
    mu, lmbda = dolfinx.fem.Function(Q0), dolfinx.fem.Function(Q0)
    for tag, (E, nu) in materials.items():
        m, lm = Material(E, nu).lame
        dofs = Q0.dofmap.list[part.cell_tags.find(tag)].ravel()
        mu.x.array[dofs], lmbda.x.array[dofs] = m, lm
    mu.x.scatter_forward()
    lmbda.x.scatter_forward()
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)

    def sigma(w):
        e = ufl.sym(ufl.grad(w))
        return 2 * mu * e + lmbda * ufl.tr(e) * ufl.Identity(2)

    a = ufl.inner(sigma(u), ufl.sym(ufl.grad(v))) * ufl.dx
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft)
    L = sum(-0.75 * v[1] * ds(scene.tag(block, side)) for block, side in scene.loaded)
    bcs = []
    for component, sides in enumerate((scene.fixed_x, scene.fixed_y)):
        for block, side in sides:
            dofs = dolfinx.fem.locate_dofs_topological(
                V.sub(component), 1, ft.find(scene.tag(block, side))
            )
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(component)))
    pairs = []
    for contactor, targets in pairs_spec:
        pairs += contact_pairs(
            contact_surface(V, ft, scene.tag(contactor, "bottom")),
            [contact_surface(V, ft, scene.tag(t, "top")) for t in targets],
            method=case.method,
        )
    return LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix=prefix)


def _two_meshes_problem(case: Case, comm_name: str, partition: str, prefix: str):
    inf_sup = case.scene == "inf-sup model"
    return block_problem(
        two_meshes(comm_name, partition, inf_sup),
        (case.degree, case.degree),
        case.contactor,
        support="clamped" if inf_sup else "rollers",
        pressure=0.0 if inf_sup else 1.0,
        petsc_options_prefix=prefix,
        method=case.method,
    )


@functools.cache
def _hertz_model(case: Case, comm_name: str, partition: str):
    return hertz_model(
        _hertz_case(case), _comm(comm_name), partitioner=_partitioner(partition, (10, 20), 0.0)
    )


def _hertz_problem(case: Case, comm_name: str, partition: str, prefix: str):
    model = _hertz_model(case, comm_name, partition)
    return UnilateralContactProblem(
        model.a,
        model.L,
        [model.pair()],
        model.bcs,
        petsc_options_prefix=prefix,
        algorithm="active-set",
        max_iterations=50,
    )


def problem(case: Case, comm_name: str, partition: str) -> LinearContactProblem:
    build = {"readme": _readme_problem, "hertz": _hertz_problem}
    build |= dict.fromkeys(MULTI, _multi_problem)
    build |= dict.fromkeys(("patch test", "inf-sup model"), _two_meshes_problem)
    return build[case.scene](case, comm_name, partition, f"ranks_{comm_name}_")


# ---------------------------------------------------------------------------------------
# Records in a partition-independent numbering


def _owned(f: dolfinx.fem.Function) -> np.ndarray:
    V = f.function_space
    return _gather(V.mesh.comm, f.x.array[: V.dofmap.index_map.size_local * V.dofmap.index_map_bs])


def _backward_error(A: PETSc.Mat, b: PETSc.Vec, x: PETSc.Vec) -> float:
    r"""Normwise backward error of a solve, in the infinity norm.

    :math:`\omega = \|b - Ax\| / (\|A\| \|x\| + \|b\|)`.
    """
    r = b.duplicate()
    A.mult(x, r)
    r.aypx(-1.0, b)
    inf = PETSc.NormType.INFINITY
    omega = r.norm(inf) / (A.norm(inf) * x.norm(inf) + b.norm(inf))
    r.destroy()
    return omega


def _condition(problem: LinearContactProblem) -> float:
    r""":math:`\kappa_\infty(\mathbf A)`: Hager's estimate of :math:`\|\mathbf A^{-1}\|_1`
    (:math:`= \|\mathbf A^{-1}\|_\infty`, the matrix is symmetric) from the factorization."""
    A, ksp = problem.A, problem.solver
    assert A.getComm().size == 1
    x, y = A.createVecs()
    n = x.getSize()
    v = np.full(n, 1.0 / n)
    estimate = 0.0
    for _ in range(5):
        x.array[:] = v
        ksp.solve(x, y)
        norm = float(np.abs(y.array_r).sum())
        if norm <= estimate:
            break
        estimate = norm
        x.array[:] = np.where(y.array_r >= 0.0, 1.0, -1.0)
        ksp.solveTranspose(x, y)
        z = y.array_r.copy()
        j = int(np.argmax(np.abs(z)))
        if abs(z[j]) <= z @ v:
            break
        v = np.zeros(n)
        v[j] = 1.0
    x.destroy()
    y.destroy()
    return estimate * A.norm(PETSc.NormType.INFINITY)


def _contact_facets(problem: LinearContactProblem) -> list[dict]:
    """Per pair: owned contactor and target facets of this process, with their x ranges."""
    out = []
    for pair in problem.pairs:
        c = pair.contactor
        T = [(t, t.data) for t in pair.targets]
        out.append(
            {
                "contactor": len(c.data),
                "targets": sum(len(d) for _, d in T),
                "contactor_x": c.data.coords[:, :, 0].mean(axis=1),
                "target_ranges": [
                    np.column_stack([d.coords[:, :, 0].min(axis=1), d.coords[:, :, 0].max(axis=1)])
                    for _, d in T
                ],
            }
        )
    return out


def record(case: Case, comm_name: str, partition: str) -> dict:
    """Solve one case; return everything in global arrays, the same on every process."""
    with problem(case, comm_name, partition) as p:
        p.solve()
        comm = p.comm
        labels = [connected_components(V.mesh)[0] for V in p.spaces]
        rec: dict = {
            "spaces": [
                {"keys": _keys(V, lab), "bs": V.dofmap.index_map_bs, "u": _owned(u)}
                for V, lab, u in zip(p.spaces, labels, p.u, strict=True)
            ],
            "pairs": [],
            "omega": _backward_error(p.A, p.b, p.x),
            "x_norm": p.x.norm(PETSc.NormType.INFINITY),
            "facets": _contact_facets(p),
        }
        if comm.size == 1:
            rec["kappa"] = _condition(p)
        for j, (pair, op, lam) in enumerate(zip(p.pairs, p.operators, p.multipliers, strict=True)):
            entry = {
                "keys": _keys(pair.Q, None),
                "lambda": _owned(lam),
                "inactive": op.inactive.copy(),
                "blocks": [],
            }
            if isinstance(p, UnilateralContactProblem):
                entry["active"] = _owned(p.active[j])
            for V, B in op.blocks:
                entry["blocks"].append((p.space_index(V), *matrix_entries(B)))
            rec["pairs"].append(entry)
    return rec


# ---------------------------------------------------------------------------------------
# Comparison


def _note(quantity: str, case: Case, partition: str, diff: float, bound: float) -> None:
    ratio = diff / bound if bound > 0 else (0.0 if diff == 0 else np.inf)
    largest = SUMMARY.setdefault("largest absolute", {})
    largest[quantity] = max(largest.get(quantity, 0.0), float(diff))
    best = SUMMARY.get(quantity)
    if best is None or ratio > best["ratio"]:
        SUMMARY[quantity] = {
            "case": case.id,
            "partition": partition,
            "difference": diff,
            "bound": bound,
            "ratio": ratio,
        }


def compare(case: Case, partition: str, world: dict, serial: dict) -> dict[str, tuple]:
    """The largest disagreements and their bounds (quantity: (difference, bound))."""
    out: dict[str, tuple] = {}
    x_bound = X_FACTOR * EPS * serial["kappa"] * serial["x_norm"]
    perms = []
    for w, s in zip(world["spaces"], serial["spaces"], strict=True):
        perm = match(w["keys"], s["keys"])
        perms.append(_dof_perm(perm, s["bs"]))
        du = np.max(np.abs(s["u"][perms[-1]] - w["u"]), initial=0.0)
        out[f"u{len(perms) - 1}"] = (du, x_bound)
    for j, (w, s) in enumerate(zip(world["pairs"], serial["pairs"], strict=True)):
        q = match(w["keys"], s["keys"])
        out[f"lambda{j}"] = (np.max(np.abs(s["lambda"][q] - w["lambda"]), initial=0.0), x_bound)
        # Multipliers set to zero (uncovered, duplicates) and active sets: exactly.
        inactive_w = np.sort(q[w["inactive"]])
        out[f"inactive{j}"] = (float(not np.array_equal(inactive_w, s["inactive"])), 0.0)
        if "active" in s:
            out[f"active{j}"] = (float(np.count_nonzero(s["active"][q] != w["active"])), 0.0)
        scale = max(np.max(np.abs(b[3]), initial=0.0) for b in s["blocks"])
        assert [b[0] for b in w["blocks"]] == [b[0] for b in s["blocks"]]
        for (i, *bw), (_, *bs) in zip(w["blocks"], s["blocks"], strict=True):
            dB = matrix_difference(tuple(bw), tuple(bs), q, perms[i])
            out[f"B{j}_{i}"] = (float(dB.max()) if dB.nnz else 0.0, B_FACTOR * EPS * scale)
    for name, (diff, bound) in out.items():
        quantity = "".join(c for c in name if not c.isdigit() and c != "_")
        _note(quantity, case, partition, diff, bound)
    return out


# ---------------------------------------------------------------------------------------
# Tests


@functools.cache
def serial_record(case: Case) -> dict:
    # The serial reference, on every process alone (partitions do not apply).
    return record(case, "self", "default")


def _check_partition(partition: str, facets: list[dict]) -> list:
    """The forced partitions do what they claim (asserted on every rank alike).

    Returns:
        Per pair, the ``(contactor, target)`` facets each rank owns.
    """
    comm = MPI.COMM_WORLD
    everywhere = [comm.allgather((f["contactor"], f["targets"])) for f in facets]
    if comm.size == 1 or partition == "default":
        return everywhere
    counts = np.array(everywhere)  # (pairs, ranks, 2)
    if partition == "contact on rank 0":
        assert counts[:, 1:].sum() == 0 and counts[:, 0].min() > 0, counts
        return everywhere
    if partition == "bodies apart":
        # Per pair: the ranks owning contactor facets own no target facet.
        for pair in counts:
            assert not np.any((pair[:, 0] > 0) & (pair[:, 1] > 0)), counts
        return everywhere
    # Crossed: the contact facets on several ranks, and in every pair contactor facets
    # facing a target facet of another rank.
    assert np.count_nonzero(counts.sum(axis=(0, 2))) >= 2, counts
    for f in facets:
        ranges = comm.allgather(np.concatenate(f["target_ranges"]))
        x = f["contactor_x"]
        facing = np.array(
            [((x[:, None] > r[:, 0]) & (x[:, None] < r[:, 1])).any(axis=1) for r in ranges]
        ).reshape(comm.size, x.size)
        others = np.delete(facing, comm.rank, axis=0).any(axis=0)
        split = comm.allreduce(int(np.count_nonzero(others)))
        assert split > 0, "no contactor facet faces a target facet of another rank"
    return everywhere


@pytest.fixture(scope="module", autouse=True)
def summary():
    yield
    path = os.environ.get("S2S_RANKS_JSON")
    if path and MPI.COMM_WORLD.rank == 0:
        with open(path, "w") as f:
            out = {"ranks": MPI.COMM_WORLD.size, "largest": SUMMARY, "solves": SOLVES}
            json.dump(out | {"owned_contact_facets": PARTITION_COUNTS}, f, indent=1)


def _runs() -> list:
    """Every case on :data:`FORCED`, a few on every partition; on one rank, once."""
    if MPI.COMM_WORLD.size == 1:
        return [pytest.param(c, "default", id=f"{c.id}-default") for c in CASES]
    return [
        pytest.param(c, partition, id=f"{c.id}-{partition}")
        for c in CASES
        for partition in (PARTITIONS if c in ALL_PARTITIONS else FORCED)
    ]


@pytest.mark.parametrize(("case", "partition"), _runs())
def test_same_on_any_number_of_ranks(case, partition):
    world = record(case, "world", partition)
    serial = serial_record(case)
    PARTITION_COUNTS[f"{case.id} {partition}"] = _check_partition(partition, world["facets"])
    if case.scene == "hertz":
        # The contact zone |x| <= a is a part of the contactor |x| <= 4a: the active set
        # is neither empty nor everything.
        active = serial["pairs"][0]["active"]
        assert 0 < np.count_nonzero(active) < active.size / 2, np.count_nonzero(active)
    omega = max(world["omega"], serial["omega"])
    if omega / EPS > SOLVES["omega_over_eps"]:
        SOLVES.update(omega_over_eps=omega / EPS, omega_case=f"{case.id} {partition}")
    SOLVES["kappa"] = max(SOLVES["kappa"], serial["kappa"])
    # Both solves backward stable (the premise of the bound on x).
    assert omega <= OMEGA_FACTOR * EPS, (world["omega"], serial["omega"])
    result = compare(case, partition, world, serial)
    # Decide on every rank alike.
    worst = MPI.COMM_WORLD.allreduce(
        max((d - b for d, b in result.values()), default=0.0), op=MPI.MAX
    )
    assert worst <= 0.0, {k: v for k, v in result.items() if v[0] > v[1]}

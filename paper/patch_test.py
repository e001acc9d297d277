# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The contact patch test of section 3.2 (Figs. 4 and 6).

A lower block rests on rollers (:math:`u_y = 0` at :math:`y = 0`), both blocks are
held by rollers on :math:`x = 0` (:math:`u_x = 0`), and a uniform pressure :math:`p`
acts on the top of the upper block. The exact solution is a uniform stress
:math:`\sigma_x = \sigma_{xy} = 0`, :math:`\sigma_y = -p` in both bodies and a
constant contact pressure :math:`\lambda = p`, whatever the materials; the
displacements are linear. A discretization passes when it reproduces these.
"""

from __future__ import annotations

import typing
from dataclasses import asdict, dataclass

from mpi4py import MPI

import dolfinx
import numpy as np
import numpy.typing as npt
import scipy.linalg
import ufl

from dolfinx_contact_s2s.elasticity import Material, stress_function
from dolfinx_contact_s2s.pair import ContactPair
from paper.blocks import (
    MATERIALS,
    NAMES,
    block_pairs,
    block_problem,
    block_spaces,
)
from paper.scenes import Body, PatchTestScene, patch_test

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.analysis.dense import Solvability

__all__ = [
    "PatchTestCase",
    "PatchTestErrors",
    "PatchTestSolution",
    "contact_pressure",
    "errors",
    "exact_displacement",
    "force_transfer",
    "nodal_pressure",
    "solve_patch_test",
    "stress_component_errors",
]


@dataclass(frozen=True)
class PatchTestCase:
    """One configuration of the patch test.

    Attributes:
        degrees: Displacement degree of the lower and the upper body.
        elements: Elements along the contact line on the lower and the upper body.
        cell: ``"triangle"`` or ``"quadrilateral"``.
        contactor: ``"upper"`` or ``"lower"``: the body carrying the multiplier.
        geometry_degree: Degree of the cells' geometry.
        gap: Initial gap :math:`g_0`.
        pressure: Applied pressure :math:`p`.
        method, multiplier, quadrature, quadrature_points, weight: The discretization,
            as for :func:`~dolfinx_contact_s2s.contact_pairs`.
    """

    degrees: tuple[int, int] = (1, 1)
    elements: tuple[int, int] = (10, 7)
    cell: str = "triangle"
    contactor: str = "upper"
    geometry_degree: int = 1
    gap: float = 0.0
    pressure: float = 1.0
    method: str = "segment-to-segment"
    multiplier: tuple[str, int] | None = None
    quadrature: str | None = None
    quadrature_points: int | None = None
    weight: str = "unit"

    def pair_options(self) -> dict:
        """Keyword arguments of :func:`~dolfinx_contact_s2s.contact_pair`."""
        return {
            "method": self.method,
            "multiplier": self.multiplier,
            "quadrature": self.quadrature,
            "quadrature_points": self.quadrature_points,
            "weight": self.weight,
        }

    def record(self) -> dict:
        """The case as a JSON-ready dictionary."""
        return asdict(self)


@dataclass
class PatchTestSolution:
    """Solution of a patch test case.

    Attributes:
        case: The configuration.
        scene: Meshes and tags.
        pairs: The contact pairs (two for a two-pass method).
        solvability: Rank of the constraints (Eq. 35); unsolvable cases are not solved.
        displacement: Displacement of each body (``None`` if unsolvable).
        stress: Stress of each body (discontinuous Lagrange tensor).
        pressures: Multiplier of each pair.
        nodal_pressure: Contact force over consistent load at each contact node.
        inactive: Multipliers of each pair that carry no constraint (global dofs).
    """

    case: PatchTestCase
    scene: PatchTestScene
    pairs: list[ContactPair]
    solvability: Solvability
    displacement: dict[str, dolfinx.fem.Function] | None = None
    stress: dict[str, dolfinx.fem.Function] | None = None
    pressures: list[dolfinx.fem.Function] | None = None
    nodal_pressure: dict[str, npt.NDArray[np.floating]] | None = None
    inactive: list[npt.NDArray[np.int64]] | None = None

    @property
    def pair(self) -> ContactPair:
        """The (first) contact pair."""
        return self.pairs[0]

    @property
    def pressure(self) -> dolfinx.fem.Function:
        """The multiplier of the (first) pair."""
        assert self.pressures is not None
        return self.pressures[0]


def exact_displacement(case: PatchTestCase, height: float, body: str):
    """Exact displacement of ``body`` (plane strain), as a callable for interpolation."""
    p, g0 = case.pressure, case.gap

    def strains(m: Material) -> tuple[float, float]:
        mu, lmbda = m.lame
        # Uniaxial sigma_y = -p, sigma_x = 0 in the 2D model.
        eyy = -p * (lmbda + 2 * mu) / (4 * mu * (lmbda + mu))
        exx = p * lmbda / (4 * mu * (lmbda + mu))
        return exx, eyy

    _, eyy_l = strains(MATERIALS["lower"])
    exx, eyy = strains(MATERIALS[body])

    def u(x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        if body == "lower":
            return np.vstack([exx * x[0], eyy * x[1]])
        return np.vstack([exx * x[0], eyy_l * height - g0 + eyy * (x[1] - height - g0)])

    return u


def solve_patch_test(
    comm: MPI.Comm,
    case: PatchTestCase,
    *,
    petsc_options_prefix: str = "patch_",
    petsc_options: dict | None = None,
) -> PatchTestSolution:
    """Build the scene of ``case`` and solve the contact problem (Eq. 18).

    A case whose constraints are rank deficient (dense SVD, Eq. 35) is reported, not
    solved.
    """
    from dolfinx_contact_s2s.analysis.dense import solvability

    scene = patch_test(
        comm, case.elements, cell=case.cell, geometry_degree=case.geometry_degree, gap=case.gap
    )
    problem = block_problem(
        scene,
        case.degrees,
        case.contactor,
        support="rollers",
        pressure=case.pressure,
        petsc_options_prefix=petsc_options_prefix,
        petsc_options=petsc_options,
        **case.pair_options(),
    )
    with problem:
        problem.assemble(check=False)
        check = solvability(problem)
        inactive = [op.inactive.copy() for op in problem.operators]
        if not check.solvable:
            return PatchTestSolution(case, scene, problem.pairs, check, inactive=inactive)
        u, lam = problem.solve()
        forces = dict(zip(NAMES, problem.contact_forces(), strict=True))
    nodal = {n: nodal_pressure(scene.bodies[n], forces[n]) for n in NAMES}
    displacement = dict(zip(NAMES, u, strict=True))
    for name, f in displacement.items():
        f.name = f"u_{name}"
    stress = {n: stress_function(displacement[n], MATERIALS[n]) for n in NAMES}
    for f in lam:
        f.name = "contact_pressure"
    return PatchTestSolution(
        case, scene, problem.pairs, check, displacement, stress, lam, nodal, inactive
    )


def nodal_pressure(body: Body, force: dolfinx.fem.Function) -> npt.NDArray[np.floating]:
    r"""Pressure carried by each contact node: its contact force over its consistent load.

    The consistent load of a unit pressure is :math:`\int_{\Gamma} \phi_j \, (-\mathbf n)`;
    a node transmitting the exact pressure :math:`p` carries :math:`p` times it (Fig. 9(a)).
    """
    V = force.function_space
    v = ufl.TestFunction(V)
    n = ufl.FacetNormal(V.mesh)
    ds = ufl.Measure("ds", domain=V.mesh, subdomain_data=body.facet_tags)
    load = dolfinx.fem.assemble_vector(dolfinx.fem.form(ufl.inner(-n, v) * ds(body.contact)))
    load.scatter_reverse(dolfinx.la.InsertMode.add)
    owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
    c = load.array[:owned].reshape(-1, 2)[:, 1]
    f = force.x.array[:owned].reshape(-1, 2)[:, 1]
    on = np.abs(c) > 1e-12 * np.max(np.abs(c), initial=1.0)
    return f[on] / c[on]


def contact_pressure(
    pair: ContactPair, multiplier: dolfinx.fem.Function, inactive: npt.NDArray[np.int64]
) -> npt.NDArray:
    r"""Owned, active pressure values of a multiplier; nodal forces become pressures.

    With :math:`w^i = 1` in Eq. (39) the multiplier is the nodal force; dividing by the
    node's tributary length :math:`\int_{\Gamma_C} \mu_i` gives the pressure.
    """
    imap = multiplier.function_space.dofmap.index_map
    n = imap.size_local
    values = multiplier.x.array[:n]
    active = ~np.isin(np.arange(*imap.local_range), inactive)
    if pair.nodal and pair.weight == "unit":
        Q = multiplier.function_space
        length = dolfinx.fem.assemble_vector(
            dolfinx.fem.form(ufl.TestFunction(Q) * ufl.dx(domain=Q.mesh))
        )
        length.scatter_reverse(dolfinx.la.InsertMode.add)
        values = values / length.array[:n]
    return values[active]


@dataclass(frozen=True)
class PatchTestErrors:
    r"""Errors of a patch test solution relative to :math:`p` (maximum over all processes).

    Attributes:
        pressure: :math:`\max |\lambda - p| / p` over the active multipliers (nodal
            forces over tributary lengths for unit weights); for two-pass methods,
            whose multipliers split the force between the passes, the nodal-force
            pressure below.
        stress: :math:`\max |\sigma - \sigma_{exact}| / p` over both bodies.
        force: :math:`\max |f_j / c_j - p| / p` over the contact nodes of both bodies,
            with :math:`f_j` the transmitted nodal force and :math:`c_j` the consistent
            nodal load of a unit pressure (Fig. 9).
    """

    pressure: float
    stress: float
    force: float


def errors(solution: PatchTestSolution) -> PatchTestErrors:
    """Compare a solution with the exact one."""
    p = solution.case.pressure
    if solution.pressures is None or solution.stress is None or solution.nodal_pressure is None:
        raise ValueError("the case is not solvable: it has no errors")
    comm = solution.pair.Q.mesh.comm

    def worst(values: npt.NDArray, exact: float | npt.NDArray = p) -> float:
        local = float(np.max(np.abs(values - exact), initial=0.0)) / p
        return comm.allreduce(local, op=MPI.MAX)

    e_f = max(worst(v) for v in solution.nodal_pressure.values())
    assert solution.inactive is not None
    e_p = max(
        worst(contact_pressure(pair, lam, inactive))
        for pair, lam, inactive in zip(
            solution.pairs, solution.pressures, solution.inactive, strict=True
        )
    )
    if len(solution.pairs) > 1:
        e_p = e_f
    exact = np.array([0.0, 0.0, 0.0, -p])
    e_s = max(worst(s.x.array.reshape(-1, 4), exact) for s in solution.stress.values())
    return PatchTestErrors(e_p, e_s, e_f)


def _gather_owned(comm: MPI.Comm, start: int, values: npt.NDArray, size: int) -> npt.NDArray:
    """A distributed array (owned blocks at ``start``) whole on every process."""
    out = np.zeros((size, *values.shape[1:]))
    for s, v in comm.allgather((start, values)):
        out[s : s + v.shape[0]] = v
    return out


def force_transfer(case: PatchTestCase) -> dict[str, npt.NDArray]:
    r"""Nodal forces transmitted to the target by the exact contactor forces (Fig. 9).

    The contactor receives its consistent nodal forces :math:`\mathbf f_C = p \int \phi
    \mathbf N = -p \int \phi \mathbf n_C`; the multipliers reproducing them solve
    :math:`\mathbf B_C^T \Lambda = \mathbf f_C` (least squares), and the target then
    receives :math:`\mathbf B_T^T \Lambda`, against its consistent forces
    :math:`-p \int \phi \mathbf n_T`.

    Returns:
        ``x`` of the target's contact nodes, their ``consistent`` and ``transmitted``
        vertical forces.
    """
    from dolfinx_contact_s2s.assemble import assemble_coupling
    from dolfinx_contact_s2s.la import gather_dense

    comm = MPI.COMM_WORLD
    scene = patch_test(comm, case.elements, cell=case.cell)
    target_name = "lower" if case.contactor == "upper" else "upper"
    spaces = block_spaces(scene, case.degrees)
    (pair,) = block_pairs(scene, spaces, case.contactor, **case.pair_options())
    op = assemble_coupling(pair)
    Bc = gather_dense(op.block(spaces[case.contactor]))
    Bt = gather_dense(op.block(spaces[target_name]))
    op.destroy()

    def consistent(name: str) -> tuple[npt.NDArray, npt.NDArray]:
        """Consistent nodal force -p int phi n and the dof coordinates, whole."""
        V, body = spaces[name], scene.bodies[name]
        v, n = ufl.TestFunction(V), ufl.FacetNormal(V.mesh)
        ds = ufl.Measure("ds", domain=V.mesh, subdomain_data=body.facet_tags)
        f = dolfinx.fem.assemble_vector(
            dolfinx.fem.form(-case.pressure * ufl.inner(n, v) * ds(body.contact))
        )
        f.scatter_reverse(dolfinx.la.InsertMode.add)
        imap, bs = V.dofmap.index_map, V.dofmap.index_map_bs
        owned = imap.size_local
        start = imap.local_range[0]
        forces = _gather_owned(comm, start, f.array[: owned * bs].reshape(-1, bs), imap.size_global)
        x = _gather_owned(comm, start, V.tabulate_dof_coordinates()[:owned], imap.size_global)
        return forces.reshape(-1), x

    f_c, _ = consistent(case.contactor)
    f_t, x_t = consistent(target_name)
    # B_C^T Lambda is the contact force on the contactor, p int phi N = -p int phi n_C.
    lam = scipy.linalg.lstsq(Bc.T, f_c)[0]
    transmitted = Bt.T @ lam
    on = np.flatnonzero(np.abs(f_t[1::2]) > 0)
    order = on[np.argsort(x_t[on, 0])]
    return {
        "x": x_t[order, 0],
        "consistent": f_t[1::2][order],
        "transmitted": transmitted[1::2][order],
    }


def stress_component_errors(solution: PatchTestSolution) -> tuple[float, float]:
    r"""Fig. 10's measures: :math:`\max |\sigma_x| / p` and :math:`\max |\sigma_y + p| / p`."""
    if solution.stress is None:
        raise ValueError("the case is not solvable: it has no stresses")
    p = solution.case.pressure
    ex = ey = 0.0
    for s in solution.stress.values():
        sig = s.x.array.reshape(-1, 4)
        ex = max(ex, float(np.max(np.abs(sig[:, 0]), initial=0.0)) / p)
        ey = max(ey, float(np.max(np.abs(sig[:, 3] + p), initial=0.0)) / p)
    comm = solution.pair.Q.mesh.comm
    return comm.allreduce(ex, op=MPI.MAX), comm.allreduce(ey, op=MPI.MAX)

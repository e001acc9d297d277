# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Fig. 16: convergence on the inf-sup model of Fig. 2 under a top displacement.

Section 5.3 of the paper: "applying a linearly varying displacement field to the top
surface of the inf-sup problem of Fig. 2. Using linear elements results in linear
convergence in the energy norm [...] for both the new algorithm (with
:math:`\mathcal M^1_{h,1}`) as well as the classical node-to-segment algorithm. [With]
quadratic elements [...] the new algorithm (with :math:`\mathcal M^1_{h,2}`) maintains
quadratic convergence, while the node-to-segment algorithm results into only linear
convergence." Fig. 16 plots :math:`|E - E_h|/E`, :math:`E` the strain energy.

The blocks are those of :func:`~paper.scenes.inf_sup_model` with
:math:`g_0 = 0`, tied in the normal direction (:class:`LinearContactProblem`, Eq. 18).
The paper's negative gap serves the inf-sup test, which looks at :math:`\mathbf B`
alone; here the load is the top displacement alone, the contact surface is known
(:math:`y = H`) and the pressure is compressive everywhere, so the tied solution is
also the solution of the unilateral problem (Eq. 1). Two variants:

- ``"paper"``: as stated. Lower block clamped at its bottom, upper block's top
  displaced by :math:`\mathbf u = (0, -\delta(\tfrac12 + x/W))`, sides free. Where a
  clamped edge meets a free one the solution is singular, which caps every method's
  rate on uniform meshes. No closed form: the reference is the S2S
  :math:`P_2`/:math:`\mathcal M^1_{h,2}` solution on a nested finer mesh of the same
  family, and :math:`E` its Richardson extrapolation.
- ``"smooth"``: rollers (:math:`u_x = 0`, no shear) on all four vertical sides,
  :math:`u_y = 0` and no shear on the bottom, :math:`u_y = -\delta(1 - \tfrac{4}{\pi^2}
  \cos \pi x/W)` and no shear on the top: the mean and the first cosine term of the
  paper's ramp. The exact solution is analytic (:class:`SmoothSolution`), so only the
  contact discretization can spoil the rate. The ramp itself with rollers is not
  smooth: reflected across a roller side it has a kink, an :math:`r \log r` corner
  singularity. With free sides and a roller bottom instead, the ramp gives a quadratic
  exact solution (:math:`\sigma_{yy} = -(p_0 + p_1 x)`, :math:`\sigma_{xx} =
  \sigma_{xy} = 0`) that lies in the :math:`P_2` space: a higher-order patch test, not
  a convergence study.

The meshes of a family are nested: uniform structured quadrilateral blocks with
:math:`10n \times 5n` and :math:`7n \times 3.5n` cells, :math:`n` even, so that a
coarse solution is represented exactly in a finer space of the same family.
"""

from __future__ import annotations

import math
import typing
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass

from mpi4py import MPI

import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.convergence import richardson
from dolfinx_contact_s2s.elasticity import epsilon
from paper.blocks import MATERIALS, NAMES, block_pairs, block_spaces
from paper.scenes import BOTTOM, LEFT, RIGHT, TOP, PatchTestScene, inf_sup_model

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.convergence import ConvergenceTable
    from dolfinx_contact_s2s.problem import LinearContactProblem

__all__ = [
    "CASES",
    "DELTA",
    "LEVELS",
    "QUANTITIES",
    "REFERENCE_LEVEL",
    "VARIANTS",
    "Fig16Case",
    "Fig16Model",
    "Reference",
    "SmoothSolution",
    "energy_norm_error",
    "fig16_model",
    "fig16_problem",
    "fig16_scene",
    "run_case",
    "strain_energy",
]

#: The variants of the study.
VARIANTS = ("paper", "smooth")

#: The errors of every study: :math:`|E - E_h|/E` and the relative energy norm.
QUANTITIES = ("strain_energy", "energy_norm")

#: Mean top displacement (the problem is linear: errors are relative).
DELTA = 0.01

#: Levels :math:`n` (even: the meshes are nested) of the full study.
LEVELS = (2, 4, 8, 16)

#: Level of the reference solution of the ``"paper"`` variant (a multiple of the others).
REFERENCE_LEVEL = 32


@dataclass(frozen=True)
class Fig16Case:
    r"""A discretization of Fig. 16.

    Attributes:
        method: ``"segment-to-segment"`` or ``"node-to-segment"`` (single pass).
        degree: Displacement degree of both blocks.
        multiplier: Multiplier space of S2S; ``None``: :math:`\mathcal M^1_{h,k}`,
            ``("Lagrange", degree)``.
        contactor: ``"upper"`` or ``"lower"``.
        cell: ``"quadrilateral"`` (nested structured meshes) or ``"triangle"``.
    """

    method: str = "segment-to-segment"
    degree: int = 2
    multiplier: tuple[str, int] | None = None
    contactor: str = "upper"
    cell: str = "quadrilateral"

    @property
    def label(self) -> str:
        """Short name, e.g. ``"S2S P2"``."""
        short = {"segment-to-segment": "S2S", "node-to-segment": "NTS"}.get(
            self.method, self.method
        )
        return f"{short} P{self.degree}"

    @property
    def pair_multiplier(self) -> tuple[str, int] | None:
        """The multiplier passed to the pair (``None`` for node-to-segment)."""
        if self.method != "segment-to-segment":
            return None
        return self.multiplier or ("Lagrange", self.degree)

    def pair_options(self) -> dict[str, typing.Any]:
        """Keyword arguments of :func:`~dolfinx_contact_s2s.contact_pairs`."""
        options: dict[str, typing.Any] = {"method": self.method}
        if self.pair_multiplier is not None:
            options["multiplier"] = self.pair_multiplier
        return options

    def record(self) -> dict:
        """The case as a JSON-ready dict."""
        rec = asdict(self)
        rec["multiplier"] = list(self.pair_multiplier) if self.pair_multiplier else None
        return rec


#: S2S with :math:`\mathcal M^1_{h,k}` and single-pass node-to-segment, linear and quadratic.
CASES = (
    Fig16Case("segment-to-segment", 1),
    Fig16Case("node-to-segment", 1),
    Fig16Case("segment-to-segment", 2),
    Fig16Case("node-to-segment", 2),
)


def fig16_scene(comm: MPI.Comm, n: int, cell: str = "quadrilateral") -> PatchTestScene:
    """The inf-sup model at level ``n``: :math:`10n` and :math:`7n` elements, :math:`g_0 = 0`."""
    if n < 2 or n % 2:
        raise ValueError(f"the level must be even and at least 2 (nested meshes), not {n}")
    return inf_sup_model(comm, (10 * n, 7 * n), cell=cell, gap=0.0)


# --- the exact solutions -------------------------------------------------------------


def _lame(name: str) -> tuple[float, float]:
    r""":math:`(\mu, \lambda)` of a block."""
    return MATERIALS[name].lame


class SmoothSolution:
    r"""Exact solution of the ``"smooth"`` variant (plane strain, no body force).

    In each block, with :math:`y'` the height above the block's bottom and
    :math:`k = \pi/W`,

    .. math::
        u_x = A(y') \sin kx, \qquad u_y = B(y') \cos kx + c\,y' + d,

    :math:`A = (a_1 + a_2 y')e^{ky'} + (a_3 + a_4 y')e^{-ky'}` and :math:`B` the matching
    combination that satisfies Navier's equations. The rollers on the sides hold by
    construction; the eight constants of the cosine mode solve the conditions on the
    bottom, the top and the frictionless tied interface (continuous :math:`u_y` and
    :math:`\sigma_{yy}`, no shear on either side), the uniform part :math:`(c, d)` the
    same for a uniform compression.
    """

    def __init__(
        self,
        delta: float = DELTA,
        width: float = 1.0,
        height: float = 0.5,
        amplitude: float = 4.0 / math.pi**2,
    ):
        r"""Solve for the constants.

        Args:
            delta: Mean top displacement (downwards).
            width: Block width :math:`W`.
            height: Block height :math:`H`.
            amplitude: Top displacement :math:`u_y = -\delta(1 - \text{amplitude}\cos kx)`.
        """
        self.delta, self.width, self.height = delta, width, height
        self.amplitude = amplitude
        self.k = math.pi / width
        H = height
        rows = {name: (self._rows(name, 0.0), self._rows(name, H)) for name in NAMES}
        # Unknowns: the four constants of the lower block, then the upper block's.
        M = np.zeros((8, 8))
        rhs = np.zeros(8)
        (L0, LH), (U0, UH) = rows["lower"], rows["upper"]
        zero = np.zeros(4)
        # rows[..] = (A, A', B, B', sigma_yy, sigma_xy) as linear maps of the constants
        M[0] = np.r_[L0[2], zero]  # lower bottom: u_y = 0
        M[1] = np.r_[L0[5], zero]  # lower bottom: no shear
        M[2] = np.r_[zero, UH[2]]  # upper top: u_y prescribed
        rhs[2] = delta * amplitude
        M[3] = np.r_[zero, UH[5]]  # upper top: no shear
        M[4] = np.r_[LH[2], -U0[2]]  # interface: continuous u_y
        M[5] = np.r_[LH[4], -U0[4]]  # interface: continuous sigma_yy
        M[6] = np.r_[LH[5], zero]  # interface: no shear below
        M[7] = np.r_[zero, U0[5]]  # interface: no shear above
        z = np.linalg.solve(M, rhs)
        self.constants = {"lower": z[:4], "upper": z[4:]}
        # Uniform compression: sigma_yy = m c equal in both blocks, u_y(0) = 0 below,
        # continuous at y = H, -delta on top.
        mL, mU = (sum(_lame(name)) + _lame(name)[0] for name in NAMES)
        cL = -delta / (H * (1.0 + mL / mU))
        self.uniform = {"lower": (cL, 0.0), "upper": (cL * mL / mU, cL * H)}
        self.origin = {"lower": 0.0, "upper": H}

    def _rows(self, name: str, yl: float) -> npt.NDArray[np.float64]:
        """Rows (A, A', B, B', sigma_yy, sigma_xy amplitudes) at height ``yl`` in block ``name``."""
        k = self.k
        mu, lmbda = _lame(name)
        kappa = (lmbda + 3 * mu) / (lmbda + mu)
        ep, em = math.exp(k * yl), math.exp(-k * yl)
        A = np.array([ep, yl * ep, em, yl * em])
        dA = np.array([k * ep, (1 + k * yl) * ep, -k * em, (1 - k * yl) * em])
        B = np.array([-ep, (kappa / k - yl) * ep, em, (kappa / k + yl) * em])
        dB = np.array([-k * ep, (kappa - 1 - k * yl) * ep, -k * em, (1 - kappa - k * yl) * em])
        syy = lmbda * (k * A + dB) + 2 * mu * dB
        sxy = mu * (dA - k * B)
        return np.array([A, dA, B, dB, syy, sxy])

    def _profiles(self, name: str, yl: typing.Any, exp: Callable) -> tuple:
        """:math:`A(y')` and :math:`B(y')` of block ``name`` (``exp``: NumPy's or UFL's)."""
        a1, a2, a3, a4 = (float(c) for c in self.constants[name])
        mu, lmbda = _lame(name)
        q = (lmbda + 3 * mu) / (lmbda + mu) / self.k
        ep, em = exp(self.k * yl), exp(-self.k * yl)
        A = (a1 + a2 * yl) * ep + (a3 + a4 * yl) * em
        B = (-a1 + a2 * (q - yl)) * ep + (a3 + a4 * (q + yl)) * em
        return A, B

    def ufl(self, name: str, mesh: dolfinx.mesh.Mesh) -> ufl.core.expr.Expr:
        """The displacement of block ``name`` as a UFL expression on ``mesh``."""
        x = ufl.SpatialCoordinate(mesh)
        yl = x[1] - self.origin[name]
        A, B = self._profiles(name, yl, ufl.exp)
        c, d = self.uniform[name]
        return ufl.as_vector([A * ufl.sin(self.k * x[0]), B * ufl.cos(self.k * x[0]) + c * yl + d])

    def __call__(self, name: str, x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        """The displacement of block ``name`` at points ``x`` (shape ``(3, m)``), ``(2, m)``."""
        yl = x[1] - self.origin[name]
        A, B = self._profiles(name, yl, np.exp)
        c, d = self.uniform[name]
        return np.vstack([A * np.sin(self.k * x[0]), B * np.cos(self.k * x[0]) + c * yl + d])

    def top(self, x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        """The prescribed top displacement :math:`u_y(x)`."""
        return -self.delta * (1.0 - self.amplitude * np.cos(self.k * x[0]))

    def pressure(self, x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        r"""Contact pressure :math:`p = -\sigma_{yy}` on the interface."""
        mL = sum(_lame("lower")) + _lame("lower")[0]
        syy = self._rows("lower", self.height)[4] @ self.constants["lower"]
        return -(mL * self.uniform["lower"][0] + syy * np.cos(self.k * np.asarray(x)))

    @property
    def energy(self) -> float:
        r"""Strain energy :math:`E`: half the work of the top traction (the only work)."""
        mU = sum(_lame("upper")) + _lame("upper")[0]
        s0 = mU * self.uniform["upper"][0]
        s1 = self._rows("upper", self.height)[4] @ self.constants["upper"]
        d0, d1 = -self.delta, self.delta * self.amplitude
        return 0.5 * self.width * (s0 * d0 + 0.5 * s1 * d1)


# --- problems and measures ------------------------------------------------------------


def _dirichlet(
    V: dolfinx.fem.FunctionSpace,
    facets: npt.NDArray[np.int32],
    component: int | None,
    values: Callable | None,
) -> dolfinx.fem.DirichletBC:
    """``values(x)`` (``None``: zero) on ``facets``, on one component or all of ``V``."""
    fdim = V.mesh.topology.dim - 1
    W = V if component is None else V.sub(component)
    if values is None:
        if component is None:
            zero = np.zeros(V.mesh.geometry.dim, dtype=dolfinx.default_scalar_type)
            dofs = dolfinx.fem.locate_dofs_topological(V, fdim, facets)
            return dolfinx.fem.dirichletbc(zero, dofs, V)
        dofs = dolfinx.fem.locate_dofs_topological(W, fdim, facets)
        return dolfinx.fem.dirichletbc(dolfinx.default_scalar_type(0.0), dofs, W)
    if component is None:
        g = dolfinx.fem.Function(V)
        g.interpolate(values)
        dofs = dolfinx.fem.locate_dofs_topological(V, fdim, facets)
        return dolfinx.fem.dirichletbc(g, dofs)
    Wc, _ = W.collapse()
    g = dolfinx.fem.Function(Wc)
    g.interpolate(values)
    dofs = dolfinx.fem.locate_dofs_topological((W, Wc), fdim, facets)
    return dolfinx.fem.dirichletbc(g, dofs, W)


def _bcs(
    scene: PatchTestScene,
    spaces: dict[str, dolfinx.fem.FunctionSpace],
    variant: str,
    delta: float,
    smooth: SmoothSolution | None,
) -> list[dolfinx.fem.DirichletBC]:
    lower, upper = scene.bodies["lower"], scene.bodies["upper"]
    Vl, Vu = spaces["lower"], spaces["upper"]
    W = scene.width
    if variant == "paper":

        def ramp(x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
            return np.vstack([np.zeros_like(x[0]), -delta * (0.5 + x[0] / W)])

        return [
            _dirichlet(Vl, lower.facet_tags.find(BOTTOM), None, None),
            _dirichlet(Vu, upper.facet_tags.find(TOP), None, ramp),
        ]
    assert smooth is not None
    bcs = [
        _dirichlet(Vl, lower.facet_tags.find(BOTTOM), 1, None),
        _dirichlet(Vu, upper.facet_tags.find(TOP), 1, smooth.top),
    ]
    for body, V in ((lower, Vl), (upper, Vu)):
        sides = np.union1d(body.facet_tags.find(LEFT), body.facet_tags.find(RIGHT))
        bcs.append(_dirichlet(V, sides.astype(np.int32), 0, None))
    return bcs


@dataclass
class Fig16Model:
    """A Fig. 16 scene at one level, without its contact pairs.

    Attributes:
        scene: The two blocks.
        spaces: Displacement space of each block.
        a: Bilinear form of each block (lower, upper).
        L: Linear form of each block (zero: the top displacement is the load).
        bcs: The Dirichlet conditions of the variant.
        exact: The exact solution of the smooth variant (``None`` for ``"paper"``).
    """

    scene: PatchTestScene
    spaces: dict[str, dolfinx.fem.FunctionSpace]
    a: list[ufl.Form]
    L: list[ufl.Form]
    bcs: list[dolfinx.fem.DirichletBC]
    exact: SmoothSolution | None


def fig16_model(
    comm: MPI.Comm, degree: int, cell: str, variant: str, n: int, *, delta: float = DELTA
) -> Fig16Model:
    """The scene, spaces, forms and conditions of ``variant`` at level ``n``."""
    if variant not in VARIANTS:
        raise ValueError(f"variant must be one of {VARIANTS}, not {variant!r}")
    scene = fig16_scene(comm, n, cell)
    spaces = block_spaces(scene, (degree, degree))
    exact = SmoothSolution(delta, scene.width, scene.height) if variant == "smooth" else None
    a = [MATERIALS[name].forms(spaces[name])[0] for name in NAMES]
    L = []
    for name in NAMES:
        v = ufl.TestFunction(spaces[name])
        zero = dolfinx.fem.Constant(scene.bodies[name].mesh, np.zeros(2))
        L.append(ufl.inner(zero, v) * ufl.dx)
    bcs = _bcs(scene, spaces, variant, delta, exact)
    return Fig16Model(scene, spaces, a, L, bcs, exact)


def fig16_problem(
    comm: MPI.Comm,
    case: Fig16Case,
    variant: str,
    n: int,
    *,
    delta: float = DELTA,
    petsc_options_prefix: str = "fig16_",
    petsc_options: dict | None = None,
) -> LinearContactProblem:
    """The tied problem of ``case`` and ``variant`` at level ``n``, not yet solved."""
    from dolfinx_contact_s2s.problem import LinearContactProblem

    model = fig16_model(comm, case.degree, case.cell, variant, n, delta=delta)
    pairs = block_pairs(model.scene, model.spaces, case.contactor, **case.pair_options())
    problem = LinearContactProblem(
        model.a,
        model.L,
        pairs,
        model.bcs,
        petsc_options_prefix=petsc_options_prefix,
        petsc_options=petsc_options,
    )
    return problem


def _integral(form: ufl.Form, comm: MPI.Comm) -> float:
    return comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(form)), op=MPI.SUM)


def _energy_density(name: str, w: typing.Any) -> typing.Any:
    return ufl.inner(MATERIALS[name].sigma(w), epsilon(w))


def strain_energy(problem: LinearContactProblem) -> float:
    r"""Strain energy :math:`E_h = \tfrac12 \sum a(\mathbf u_h, \mathbf u_h)` of both blocks."""
    return 0.5 * sum(
        _integral(_energy_density(name, u) * ufl.dx, problem.comm)
        for name, u in zip(NAMES, problem.u, strict=True)
    )


def energy_norm_error(problem: LinearContactProblem, exact: SmoothSolution) -> float:
    r""":math:`\|\mathbf u - \mathbf u_h\|_E = (\sum a(e, e))^{1/2}` against the exact solution.

    Integrated with a rule of degree :math:`2k + 6` (the exact solution is not a
    polynomial).
    """
    total = 0.0
    for name, u in zip(NAMES, problem.u, strict=True):
        mesh = u.function_space.mesh
        degree = u.function_space.ufl_element().degree
        dx = ufl.dx(domain=mesh, metadata={"quadrature_degree": 2 * degree + 6})
        total += _integral(_energy_density(name, u - exact.ufl(name, mesh)) * dx, problem.comm)
    return math.sqrt(max(total, 0.0))


class Reference:
    r"""The reference of the ``"paper"`` variant: S2S :math:`P_2`/:math:`\mathcal M^1_{h,2}`.

    Solved at ``level``; :math:`E` is the Richardson extrapolation of the strain
    energies at ``level``/4, ``level``/2 and ``level`` (:func:`richardson`). Coarse
    solutions of the same family are interpolated into the reference's spaces
    (non-matching interpolation; the meshes are nested, so it is exact) and the energy
    norm of the difference is integrated on the fine mesh.

    Attributes:
        problem: The solved reference problem.
        energy: Its strain energy :math:`E_{ref}`.
        extrapolated: :math:`E` extrapolated; ``order``: the observed order of
            :math:`E_h - E`.
    """

    def __init__(self, comm: MPI.Comm, level: int = REFERENCE_LEVEL, *, delta: float = DELTA):
        """Solve the reference and the two coarser levels of the extrapolation."""
        if level % 8:
            raise ValueError(f"the reference level must be a multiple of 8, not {level}")
        case = Fig16Case("segment-to-segment", 2)
        energies, hs = [], []
        for n in (level // 4, level // 2, level):
            problem = fig16_problem(
                comm, case, "paper", n, delta=delta, petsc_options_prefix="fig16_ref_"
            )
            problem.solve()
            energies.append(strain_energy(problem))
            hs.append(1.0 / n)
            if n != level:
                problem.destroy()
        self.problem = problem
        self.level = level
        self.energy = energies[-1]
        self.energies = energies
        try:
            self.extrapolated, self.order = richardson(hs, energies)
        except ValueError:
            self.extrapolated, self.order = self.energy, math.nan

    def interpolate(self, problem: LinearContactProblem) -> list[dolfinx.fem.Function]:
        """The displacements of a solved coarse ``problem`` in the reference's spaces."""
        out = []
        for uc, V in zip(problem.u, self.problem.spaces, strict=True):
            imap = V.mesh.topology.index_map(V.mesh.topology.dim)
            cells = np.arange(imap.size_local + imap.num_ghosts, dtype=np.int32)
            data = dolfinx.fem.create_interpolation_data(V, uc.function_space, cells, 1e-10)
            f = dolfinx.fem.Function(V)
            f.interpolate_nonmatching(uc, cells, data)
            f.x.scatter_forward()
            out.append(f)
        return out

    def error(self, problem: LinearContactProblem) -> float:
        r""":math:`\|\mathbf u_{ref} - I\mathbf u_h\|_E` of a solved coarse ``problem``."""
        total = 0.0
        fine = self.interpolate(problem)
        for name, f, uf in zip(NAMES, fine, self.problem.u, strict=True):
            total += _integral(_energy_density(name, f - uf) * ufl.dx, problem.comm)
        return math.sqrt(max(total, 0.0))

    def destroy(self) -> None:
        """Destroy the reference problem."""
        self.problem.destroy()


def run_case(
    comm: MPI.Comm,
    case: Fig16Case,
    variant: str,
    levels: Sequence[int] = LEVELS,
    *,
    reference: Reference | None = None,
    delta: float = DELTA,
    log: Callable[[str], None] | None = None,
) -> ConvergenceTable:
    r"""The convergence study of ``case`` on ``variant``: a table of both :data:`QUANTITIES`.

    ``"strain_energy"`` is :math:`|E - E_h|/E` (Fig. 16), ``"energy_norm"`` is
    :math:`\|\mathbf u - \mathbf u_h\|_E / \|\mathbf u\|_E` with
    :math:`\|\mathbf v\|_E^2 = \sum a(\mathbf v, \mathbf v)` over both blocks. For
    ``"smooth"`` both are against :class:`SmoothSolution`; for ``"paper"`` against
    ``reference`` (its extrapolated :math:`E`; its solution for the norm), whose level
    every level must divide.
    """
    from dolfinx_contact_s2s.convergence import convergence_study

    errors: dict[str, Callable[[typing.Any], float]]
    if variant == "smooth":
        exact = SmoothSolution(delta)
        E, norm = exact.energy, math.sqrt(2 * exact.energy)
        errors = {
            "strain_energy": lambda p: abs(E - strain_energy(p)) / E,
            "energy_norm": lambda p: energy_norm_error(p, exact) / norm,
        }
    elif variant == "paper":
        if reference is None:
            raise ValueError("the paper variant needs a Reference")
        if any(reference.level % n for n in levels):
            raise ValueError(f"every level must divide the reference level {reference.level}")
        ref = reference
        errors = {
            "strain_energy": lambda p: abs(ref.extrapolated - strain_energy(p)) / ref.extrapolated,
            "energy_norm": lambda p: ref.error(p) / math.sqrt(2 * ref.energy),
        }
    else:
        raise ValueError(f"variant must be one of {VARIANTS}, not {variant!r}")

    def solve(n: int) -> LinearContactProblem:
        problem = fig16_problem(comm, case, variant, n, delta=delta)
        problem.solve()
        return problem

    return convergence_study(
        solve, list(levels), errors, name=f"Fig. 16 {variant}, {case.label}", comm=comm, log=log
    )

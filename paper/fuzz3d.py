# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Randomized 3D patch tests: two non-matching blocks of tetrahedra or hexahedra, drawn at random.

A :class:`FuzzCase3D` is the 3D patch test of section 3.2 on the scene of
:mod:`paper.blocks3d` with its choices left free: each block's cell type (tetrahedra or
hexahedra), the displacement degree (P1/Q1 or P2/Q2, the same for both blocks), the
cells across each block (two different counts, so the contact faces never match), the
layers, the motion of the nodes in the plane of the contact (random for tetrahedra; for
hexahedra the graded map of :func:`paper.blocks3d.block`, which keeps the faces
parallelograms, or random too, which does not: a bilinear face that is not a
parallelogram has a rational inverse map, and the pair raises its rule until it is
exact, :func:`~dolfinx_contact_s2s.contact_rule.face_rule`),
the contactor, tied (:class:`~dolfinx_contact_s2s.problem.LinearContactProblem`)
or unilateral (:class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem`) contact,
the multiplier's degree, Young's modulus and the pressure over a few decades.
:func:`check_case` solves it with composite segment-to-segment and compares it with the
exact solution: the contact pressure :math:`\lambda = P` and the linear displacements of
uniaxial stress (Eq. 36), within the round-off bound of its solve
(:func:`~dolfinx_contact_s2s.analysis.roundoff.round_off_bound`, as the 2D cases of
``paper.fuzz``), or :data:`TOLERANCE` relative where that is larger (the tolerance of
``tests/test_contact_3d.py``).

Not drawn: P2 multipliers on a tetrahedral contactor with unilateral contact:
:class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem` refuses them by
design (vertex functions of zero integral), and the P1 multiplier it names is drawn
instead.

:func:`cases` is the Hypothesis strategy (Hypothesis is imported when it is called);
``tests/reproductions/test_fuzz_3d.py`` runs a few and ``demos/fuzz_patch_test_3d.py``
hundreds.
"""

from __future__ import annotations

import json
import typing
from dataclasses import asdict, dataclass

from mpi4py import MPI

from dolfinx_contact_s2s import contact_pair, contact_surface
from paper.blocks3d import BOTTOM, TOP, errors, scene

__all__ = ["TOLERANCE", "CaseResult3D", "FuzzCase3D", "cases", "check_case"]

#: An error relative to the exact solution's scale (P for the pressure, P / E for the
#: displacements) that passes whatever the round-off bound: the tolerance of
#: ``tests/test_contact_3d.py``.
TOLERANCE = 1e-10

#: Cell types of a block.
CELLS = ("tet", "hex")


@dataclass(frozen=True)
class FuzzCase3D:
    """A randomized 3D patch test on the scene of :func:`paper.blocks3d.scene`.

    Attributes:
        lower: Cells of the lower block, ``"tet"`` or ``"hex"``.
        upper: Cells of the upper block.
        degree: Displacement degree of both blocks, 1 or 2.
        cells: Cells across the lower and the upper block.
        layers: Cells across the height of each block.
        seed: Motion of the nodes in the plane of the contact (None: a structured mesh).
        contactor: ``"upper"`` or ``"lower"``: the block whose face carries the multiplier.
        problem: ``"tied"`` or ``"unilateral"``.
        multiplier: Degree of the continuous Lagrange multiplier (1 or ``degree``).
        E: Young's modulus of both blocks.
        P: The pressure on the top.
        warp: Move the nodes of hexahedra at random too (faces not parallelograms).
    """

    lower: str
    upper: str
    degree: int
    cells: tuple[int, int]
    layers: int
    seed: int | None
    contactor: str
    problem: str
    multiplier: int
    E: float
    P: float
    warp: bool = False

    def to_json(self) -> str:
        """The case as one line of JSON (:meth:`from_json` reads it back exactly)."""
        return json.dumps(asdict(self), separators=(",", ":"))

    @classmethod
    def from_json(cls, text: str) -> FuzzCase3D:
        """Read a case written by :meth:`to_json`."""
        d = json.loads(text)
        return cls(**{**d, "cells": tuple(d["cells"])})

    def describe(self) -> str:
        """A short human-readable summary."""
        seed = "structured" if self.seed is None else f"seed {self.seed}"
        return (
            f"{self.lower}/{self.upper} P{self.degree} n={self.cells[0]}/{self.cells[1]} "
            f"layers {self.layers} {seed}{' warped' if self.warp else ''}, contactor "
            f"{self.contactor}, {self.problem}, multiplier P{self.multiplier}, "
            f"E={self.E:.3g}, P={self.P:.3g}"
        )


@dataclass(frozen=True)
class CaseResult3D:
    r"""The outcome of one case (the same on every process).

    Attributes:
        pressure_error: :math:`\max |\lambda - P|`.
        displacement_error: :math:`\max |u - u_{exact}|` over both blocks.
        pressure_tolerance: The round-off bound of the solve on the multipliers
            (:func:`~dolfinx_contact_s2s.analysis.roundoff.round_off_bound`), or
            :data:`TOLERANCE` :math:`P` if larger.
        displacement_tolerance: The bound on the displacements, or :data:`TOLERANCE`
            :math:`P / E` if larger.
        unknowns: Size of the saddle point.
    """

    pressure_error: float
    displacement_error: float
    pressure_tolerance: float
    displacement_tolerance: float
    unknowns: int

    @property
    def ratio(self) -> float:
        """The larger error over its tolerance (at most 1 for a pass)."""
        return max(
            self.pressure_error / self.pressure_tolerance,
            self.displacement_error / self.displacement_tolerance,
        )

    @property
    def passed(self) -> bool:
        """Both errors within their tolerances."""
        return self.ratio <= 1.0


def check_case(case: FuzzCase3D, comm: MPI.Comm, prefix: str = "fuzz3d_") -> CaseResult3D:
    """Build and solve ``case`` as ``tests/test_contact_3d.py`` does; its errors (collective).

    Args:
        case: The case.
        comm: Communicator of the meshes.
        prefix: The problem's ``petsc_options_prefix``.

    Raises:
        ValueError: On every rank, if the case differs between the ranks.
    """
    from dolfinx_contact_s2s.analysis.roundoff import round_off_bound
    from dolfinx_contact_s2s.problem import LinearContactProblem
    from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

    texts = comm.allgather(case.to_json())
    if any(t != texts[0] for t in texts):
        ranks = [r for r, t in enumerate(texts) if t != texts[0]]
        raise ValueError(f"the case differs between the ranks: ranks {ranks} differ from rank 0")
    ((V_lo, t_lo), (V_up, t_up)), a, L, bcs = scene(
        case.lower,
        case.upper,
        case.degree,
        case.seed,
        case.cells,
        case.layers,
        case.warp,
        comm,
        E=case.E,
        P=case.P,
    )
    upper, lower = contact_surface(V_up, t_up, BOTTOM), contact_surface(V_lo, t_lo, TOP)
    contactor, target = (upper, lower) if case.contactor == "upper" else (lower, upper)
    pair = contact_pair(contactor, target, multiplier=("Lagrange", case.multiplier))
    kind = LinearContactProblem if case.problem == "tied" else UnilateralContactProblem
    with kind(a, L, [pair], bcs, petsc_options_prefix=prefix) as problem:
        us, (pressure,) = problem.solve()
        worst_p, worst_u = errors(us, pressure, case.E, case.P)
        unknowns = problem.A.getSize()[0]
        # The round-off bound of the (last) solve, as the 2D cases are judged.
        bound = round_off_bound(problem)
    return CaseResult3D(
        worst_p,
        worst_u,
        max(TOLERANCE * case.P, float(bound.multiplier[0])),
        max(TOLERANCE * case.P / case.E, max(float(b) for b in bound.displacement)),
        int(unknowns),
    )


def cases(max_cells: int = 6, max_layers: int = 3, decades: float = 2.0) -> typing.Any:
    r"""The Hypothesis strategy of :class:`FuzzCase3D`.

    Args:
        max_cells: Most cells across a block (at least 3: the two counts differ).
        max_layers: Most cells across a block's height.
        decades: E and P range over :math:`10^{\pm \text{decades}}`.
    """
    from hypothesis import strategies as st

    @st.composite
    def case(draw) -> FuzzCase3D:
        lower, upper = draw(st.sampled_from(CELLS)), draw(st.sampled_from(CELLS))
        degree = draw(st.sampled_from([1, 2]))
        n_lower = draw(st.integers(2, max_cells))
        n_upper = draw(st.integers(2, max_cells).filter(lambda n: n != n_lower))
        contactor = draw(st.sampled_from(["upper", "lower"]))
        problem = draw(st.sampled_from(["tied", "unilateral"]))
        tet_contactor = (upper if contactor == "upper" else lower) == "tet"
        # P2 multipliers on triangular faces have vertex functions of zero integral: the
        # unilateral problem refuses them by design and takes P1 (its message's remedy).
        refused = problem == "unilateral" and degree == 2 and tet_contactor
        multiplier = 1 if refused else draw(st.sampled_from(sorted({1, degree})))
        # Seeds 0..5: the graded map of hexahedra stays one-to-one (its x amplitude
        # 0.1 (1 + 0.3 seed) is below 1 / pi).
        seed = draw(st.none() | st.integers(0, 5))
        warp = seed is not None and "hex" in (lower, upper) and draw(st.booleans())
        return FuzzCase3D(
            lower=lower,
            upper=upper,
            degree=degree,
            cells=(n_lower, n_upper),
            layers=draw(st.integers(1, max_layers)),
            seed=seed,
            contactor=contactor,
            problem=problem,
            multiplier=multiplier,
            E=10.0 ** draw(st.floats(-decades, decades)),
            P=10.0 ** draw(st.floats(-decades, decades)),
            warp=warp,
        )

    return case()

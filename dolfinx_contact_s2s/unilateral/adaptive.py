# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Accuracy on demand at the contact edge: refine the mesh around it until it is resolved.

The discrete contact conditions (Eq. 1 on the nodal weighted gaps of Eq. 17) end the
contact zone between two multiplier nodes: the last active one and the first inactive
one (:class:`~dolfinx_contact_s2s.postprocess.ContactEdge`). Its bracket is the
contactor's facet size there, whatever the rest of the mesh. :func:`refine_contact_zone`
solves, splits the edges of the cells within a few facet sizes of every edge whose
bracket is too wide (:func:`dolfinx.mesh.refine`, tags carried over by
:func:`dolfinx.mesh.transfer_meshtag`), rebuilds the user's problem on the new mesh
through their own ``build`` callable, and solves again, until every bracket is below
the tolerance.

This module needs petsc4py and must be imported explicitly.
"""

from __future__ import annotations

import logging
import time
import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import blocked_sub_element, refine_marked
from dolfinx_contact_s2s.postprocess import ContactZone, contact_zones
from dolfinx_contact_s2s.unilateral.problem import UnilateralContactProblem

__all__ = ["AdaptiveResult", "AdaptiveStep", "RefinementError", "refine_contact_zone"]

logger = logging.getLogger("dolfinx_contact_s2s.unilateral")


@dataclass(frozen=True)
class AdaptiveStep:
    """One solve of :func:`refine_contact_zone`.

    Attributes:
        unknowns: Displacement and multiplier unknowns of the solve (global).
        bracket: Widest bracket of all edges (length).
        relative: Widest bracket relative to its reference length (the zone's length,
            or the ``length`` given).
        zones: The contact zones of every pair.
        seconds: Wall time of the step (build, solve and post-processing; rank 0's).
    """

    unknowns: int
    bracket: float
    relative: float
    zones: list[list[ContactZone]]
    seconds: float

    @property
    def lengths(self) -> list[list[float]]:
        """Estimated length of every zone of every pair."""
        return [[z.length for z in zones] for zones in self.zones]


@dataclass
class AdaptiveResult:
    """What :func:`refine_contact_zone` returns.

    Attributes:
        problem: The last problem, solved (the caller destroys it).
        meshes: Its mesh(es), cell tags and facet tags, as given to ``build``.
        history: One :class:`AdaptiveStep` per solve.
    """

    problem: UnilateralContactProblem
    meshes: tuple
    history: list[AdaptiveStep] = field(default_factory=list)


class RefinementError(RuntimeError):
    """The tolerance was not reached in the allowed steps (raised on every rank).

    Attributes:
        history: The steps made.
        problem: The last problem, solved (the caller destroys it).
    """

    def __init__(self, message: str, history: list[AdaptiveStep], problem: typing.Any):
        """Keep the history and the last problem."""
        super().__init__(message)
        self.history = history
        self.problem = problem


def _unknowns(problem: UnilateralContactProblem) -> int:
    count = sum(V.dofmap.index_map.size_global * V.dofmap.index_map_bs for V in problem.spaces)
    return count + sum(
        lam.function_space.dofmap.index_map.size_global for lam in problem.multipliers
    )


def _zones(problem: UnilateralContactProblem, estimate: str) -> list[list[ContactZone]]:
    return [
        contact_zones(pair, lam, act, gap, estimate=estimate)
        for pair, lam, act, gap in zip(
            problem.pairs, problem.multipliers, problem.active, problem.gaps, strict=True
        )
    ]


def _mark(mesh: dolfinx.mesh.Mesh, balls: npt.NDArray[np.floating]) -> npt.NDArray[np.int32]:
    """Local edges of the cells whose midpoint lies in a ball ``(centre..., radius)``."""
    tdim, gdim = mesh.topology.dim, mesh.geometry.dim
    num = mesh.topology.index_map(tdim).size_local
    cells = np.arange(num, dtype=np.int32)
    mid = dolfinx.mesh.compute_midpoints(mesh, tdim, cells)[:, :gdim]
    near = np.zeros(num, dtype=bool)
    for ball in balls:
        near |= np.linalg.norm(mid - ball[:gdim], axis=1) <= ball[gdim]
    mesh.topology.create_entities(1)
    mesh.topology.create_connectivity(tdim, 1)
    return dolfinx.mesh.compute_incident_entities(mesh.topology, cells[near], tdim, 1)


def refine_contact_zone(
    build: Callable[..., UnilateralContactProblem],
    mesh: dolfinx.mesh.Mesh | Sequence[dolfinx.mesh.Mesh],
    cell_tags: dolfinx.mesh.MeshTags | Sequence[dolfinx.mesh.MeshTags],
    facet_tags: dolfinx.mesh.MeshTags | Sequence[dolfinx.mesh.MeshTags],
    *,
    tolerance: float = 0.01,
    max_steps: int = 5,
    length: float | None = None,
    layers: float = 2.0,
    estimate: str = "gap",
    load_factors: Sequence[float] = (1.0,),
) -> AdaptiveResult:
    r"""Solve, refine around the contact edges and solve again, until they are resolved.

    Every step calls ``build(mesh, cell_tags, facet_tags)`` (with the arguments in the
    shape given here: one mesh or a list) for a new
    :class:`~dolfinx_contact_s2s.unilateral.UnilateralContactProblem`, solves it at
    ``load_factors`` and reads its contact zones
    (:func:`~dolfinx_contact_s2s.postprocess.contact_zones`). An edge is resolved when
    its bracket (the distance from the last active to the first inactive multiplier
    node) is at most ``tolerance`` times the zone's length (or ``length``). Around every
    other edge, the cells of every mesh whose midpoint lies within ``layers`` brackets
    of its two nodes have all their edges split, and the tags are carried to the new
    mesh. Nodes added on a curved boundary lie on the chords of the old facets: a
    ``build`` that knows the exact geometry may move them onto it before making its
    surfaces.

    Args:
        build: Makes the problem of a mesh: forms, Dirichlet conditions, contact
            surfaces and pairs, e.g. from the tags of the user's Gmsh model.
        mesh: The mesh, or a list of meshes (simplices, linear geometry).
        cell_tags: Their cell tags (as many).
        facet_tags: Their facet tags (as many).
        tolerance: Largest relative bracket of a resolved edge.
        max_steps: Largest number of refinements (``max_steps + 1`` solves).
        length: Reference length of the brackets (default: each zone's length).
        layers: Radius of the refined region, in brackets.
        estimate: The edge estimate of the zones, one of
            :data:`~dolfinx_contact_s2s.postprocess.ESTIMATES`.
        load_factors: Given to every ``solve``.

    Returns:
        The last problem (solved; the caller destroys it), its meshes and tags, and the
        history of the steps.

    Raises:
        NotImplementedError: On every rank, for a mesh that is not made of simplices
            with a linear coordinate element (DOLFINx refines those only).
        ValueError: On every rank, for a bad argument or a problem without contact.
        RefinementError: On every rank, if an edge is still too wide after
            ``max_steps`` refinements; it names the widest bracket reached.
    """
    single = isinstance(mesh, dolfinx.mesh.Mesh)
    meshes = [mesh] if single else list(mesh)
    ctags = [cell_tags] if single else list(cell_tags)  # type: ignore[list-item]
    ftags = [facet_tags] if single else list(facet_tags)  # type: ignore[list-item]
    if not (len(meshes) == len(ctags) == len(ftags)) or not meshes:
        raise ValueError("give as many cell tags and facet tags as meshes")
    if not (0.0 < tolerance < 1.0):
        raise ValueError(f"tolerance must lie in (0, 1), not {tolerance!r}")
    if int(max_steps) != max_steps or max_steps < 0:
        raise ValueError(f"max_steps must be an integer >= 0, not {max_steps!r}")
    if length is not None and not (length > 0.0 and np.isfinite(length)):
        raise ValueError(f"length must be positive and finite, not {length!r}")
    if not layers > 0.0:
        raise ValueError(f"layers must be positive, not {layers!r}")
    for m in meshes:
        simplex = m.topology.cell_name() in ("interval", "triangle", "tetrahedron")
        degree = blocked_sub_element(m.ufl_domain().ufl_coordinate_element()).degree
        if not simplex or degree != 1:
            raise NotImplementedError(
                f"refine_contact_zone needs simplices with a linear geometry: DOLFINx "
                f"refines no {m.topology.cell_name()} mesh of geometry degree "
                f"{degree}; mesh the scene with triangles and linear geometry"
            )

    history: list[AdaptiveStep] = []
    problem: UnilateralContactProblem | None = None
    for step in range(int(max_steps) + 1):
        begin = time.perf_counter()
        if problem is not None:
            problem.destroy()
        args = (meshes[0], ctags[0], ftags[0]) if single else (meshes, ctags, ftags)
        problem = build(*args)
        if not isinstance(problem, UnilateralContactProblem):
            raise ValueError("build must return a UnilateralContactProblem")
        problem.solve(load_factors)
        zones = _zones(problem, estimate)
        if not any(zones):
            raise ValueError("the solve has no contact zone with an edge to refine")
        wide: list[npt.NDArray[np.floating]] = []
        widest, relative = 0.0, 0.0
        for z in (z for pair_zones in zones for z in pair_zones):
            reference = length if length is not None else max(z.length, 1e-300)
            for edge in (z.start, z.end):
                widest = max(widest, edge.bracket)
                relative = max(relative, edge.bracket / reference)
                if edge.bracket > tolerance * reference:
                    radius = layers * edge.bracket
                    wide += [np.append(p, radius) for p in edge.bracket_points]
        seconds = problem.comm.bcast(time.perf_counter() - begin, root=0)
        history.append(AdaptiveStep(_unknowns(problem), widest, relative, zones, seconds))
        logger.info(
            "contact edge, step %d: %d unknowns, widest bracket %.3g (%.3g of the reference), "
            "%.2f s",
            step,
            history[-1].unknowns,
            widest,
            relative,
            seconds,
        )
        if not wide:
            return AdaptiveResult(problem, args, history)
        if step == max_steps:
            break
        balls = np.array(wide)
        for k, m in enumerate(meshes):
            edges = _mark(m, balls)
            meshes[k], (ctags[k], ftags[k]) = refine_marked(m, edges, (ctags[k], ftags[k]))
    raise RefinementError(
        f"the contact edges were not resolved to {tolerance:g} in {max_steps} refinements: "
        f"the widest bracket is {history[-1].bracket:.3g}, {history[-1].relative:.3g} of its "
        f"reference length (steps: "
        + ", ".join(f"{s.relative:.3g}" for s in history)
        + "); allow more steps or a larger tolerance",
        history,
        problem,
    )

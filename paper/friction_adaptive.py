# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Cattaneo-Mindlin on a mesh refined by the solution (issue [4/6]).

:func:`cattaneo_mindlin_adaptive`: the 2D scene of :func:`paper.friction.cattaneo_mindlin`,
meshed as a user meshes it (about ``across`` elements across :math:`2a`, no node at the
contact or stick edges, a linear geometry), solved along its load path and refined by
:func:`~dolfinx_contact_s2s.unilateral.adaptive.refine_contact_zone` around the edges of
the contact zone and of the stick zone until their brackets are ``tolerance`` of
:math:`a`; the new nodes on the arcs are moved onto the circles
(:func:`paper.hertz.adaptive.arcs`) and the mesh lifted to the displacement's degree.
:func:`refined_load_path` runs a scene's model and load path that way (2D and 3D).
"""

from __future__ import annotations

import logging
import time
import typing

from mpi4py import MPI

from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.unilateral.adaptive import RefinementError, refine_contact_zone
from paper.friction import (
    CM_A,
    CM_MU,
    CM_R,
    cattaneo_mindlin_measure,
    cattaneo_mindlin_model,
    cattaneo_mindlin_path,
)
from paper.hertz.adaptive import arcs
from paper.hertz.scene import hertz
from paper.hertz.study import HertzCase

__all__ = ["cattaneo_mindlin_adaptive", "refined_load_path"]

logger = logging.getLogger("paper.friction_adaptive")


def refined_load_path(
    model: typing.Callable,
    path: typing.Callable,
    measure: typing.Callable,
    keys: tuple[str, ...],
    mesh: tuple,
    *,
    mu: float,
    prefix: str,
    petsc_options: dict[str, typing.Any] | None = None,
    **refine: typing.Any,
) -> dict[str, typing.Any]:
    """Refine a frictional scene by its solution; the record on the last mesh.

    Args:
        model: ``model(mesh, facet_tags) -> (a, L, bcs, pair, motion)``.
        path: The load path, ``path(problem, motion, first) -> solves per step``.
        measure: ``measure(problem) -> record`` (collective).
        keys: The entries of the record kept for every mesh.
        mesh: The user's ``(mesh, cell_tags, facet_tags)``.
        mu: The friction coefficient.
        prefix: The problems' PETSc options prefix.
        petsc_options: Options of the problems' linear solves (e.g. MUMPS out of core,
            ``{"mat_mumps_icntl_22": 1}``, for meshes whose factors do not fit in memory).
        refine: The arguments of :func:`refine_contact_zone`.

    Returns:
        ``measure``'s record of the last mesh, with ``steps`` (``keys``, the widest
        relative bracket, solves and seconds of every mesh), ``solves_per_step`` of the
        last and ``resolved`` (False: still too wide after ``max_steps`` refinements,
        measured all the same).
    """
    motion: list = []
    solves: list[list[int]] = []
    steps: list[dict[str, typing.Any]] = []

    def build(domain, cell_tags, facet_tags):
        a_form, L, bcs, pair, m = model(domain, facet_tags)
        motion[:] = [m]
        return FrictionalContactProblem(
            a_form, L, [pair], bcs, mu=mu, petsc_options_prefix=prefix, petsc_options=petsc_options
        )

    def solve(problem, first):
        solves.append(path(problem, motion[0], first))

    def on_step(step, problem):
        rec = measure(problem)
        steps.append({k: rec[k] for k in keys})
        logger.info("%s mesh %d: %s", prefix, step, steps[-1])

    try:
        result = refine_contact_zone(build, *mesh, solve=solve, on_step=on_step, **refine)
        problem, history, resolved = result.problem, result.history, True
    except RefinementError as error:
        problem, history, resolved = error.problem, error.history, False
    with problem:
        record = measure(problem)
    for row, s, n in zip(steps, history, solves, strict=True):
        row.update(relative=s.relative, solves=sum(n), seconds=s.seconds)
    record.update(resolved=resolved, steps=steps, solves_per_step=solves[-1])
    return record


def cattaneo_mindlin_adaptive(
    comm: MPI.Comm,
    degree: int,
    across: int = 10,
    *,
    tolerance: float = 0.01,
    max_steps: int = 6,
    keep_traction: bool = False,
    **options: typing.Any,
) -> dict[str, typing.Any]:
    """Cattaneo-Mindlin from ``across`` elements across, refined until the edges are resolved.

    ``options`` go to :func:`refine_contact_zone` (e.g. ``pressure_tolerance``).

    Returns:
        The record of :func:`~paper.friction.cattaneo_mindlin_measure` on the last mesh
        (``h`` the element size at the stick zone's ends), with ``steps`` (unknowns,
        elements across the contact, errors, widest relative bracket, solves and seconds
        of every solve), ``solves_per_step`` of the last one, ``resolved`` and
        ``seconds`` in all.
    """
    begin = time.perf_counter()
    scene = hertz(comm, R=CM_R, a=CM_A, elements_across=across, lower_radius=CM_R, edge_nodes=False)
    case = HertzCase(a=CM_A, elements_across=across, R1=CM_R, R2=CM_R, edge_nodes=False)
    record = refined_load_path(
        lambda mesh, tags: cattaneo_mindlin_model(mesh, tags, degree),
        cattaneo_mindlin_path,
        cattaneo_mindlin_measure,
        ("unknowns", "across_contact", "c_middle_error", "q_L2_error"),
        (scene.mesh, scene.cell_tags, scene.facet_tags),
        mu=CM_MU,
        prefix=f"cma{degree}_",
        tolerance=tolerance,
        max_steps=max_steps,
        length=CM_A,
        snap=arcs(case),
        geometry_degree=degree,
        **options,
    )
    record.update(
        scene="cattaneo-mindlin-adaptive",
        degree=degree,
        across=across,
        tolerance=tolerance,
        seconds=comm.allreduce(time.perf_counter() - begin, op=MPI.MAX),
    )
    if not keep_traction:
        for key in ("x", "q", "p"):
            record.pop(key)
    return record

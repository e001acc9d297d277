# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Cattaneo-Mindlin in 2D on a mesh refined by the solution (issue [4/6]).

The scene of :func:`paper.friction.cattaneo_mindlin`, meshed as a user meshes it (about
``across`` elements across :math:`2a`, no node at the contact or stick edges, a linear
geometry), solved along its load path and refined by
:func:`~dolfinx_contact_s2s.unilateral.adaptive.refine_contact_zone` around the edges of
the contact zone and of the stick zone until their brackets are ``tolerance`` of
:math:`a`; the new nodes on the arcs are moved onto the circles
(:func:`paper.hertz.adaptive.arcs`) and the mesh lifted to the displacement's degree.
"""

from __future__ import annotations

import time
import typing

from mpi4py import MPI

from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.unilateral.adaptive import refine_contact_zone
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

__all__ = ["cattaneo_mindlin_adaptive"]


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
        widest relative bracket, elements across the contact, solves and seconds of
        every solve), ``solves_per_step`` of the last one and ``seconds`` in all.
    """
    begin = time.perf_counter()
    scene = hertz(comm, R=CM_R, a=CM_A, elements_across=across, lower_radius=CM_R, edge_nodes=False)
    case = HertzCase(a=CM_A, elements_across=across, R1=CM_R, R2=CM_R, edge_nodes=False)
    motion: list = []
    solves: list[list[int]] = []
    steps: list[dict[str, typing.Any]] = []

    def build(mesh, cell_tags, facet_tags):
        a_form, L, bcs, pair, m = cattaneo_mindlin_model(mesh, facet_tags, degree)
        motion[:] = [m]
        return FrictionalContactProblem(
            a_form, L, [pair], bcs, mu=CM_MU, petsc_options_prefix=f"cma{degree}_"
        )

    def path(problem, first):
        solves.append(cattaneo_mindlin_path(problem, motion[0], first))

    def on_step(step, problem):
        rec = cattaneo_mindlin_measure(problem)
        steps.append(
            {k: rec[k] for k in ("unknowns", "across_contact", "c_middle_error", "q_L2_error")}
        )

    result = refine_contact_zone(
        build,
        scene.mesh,
        scene.cell_tags,
        scene.facet_tags,
        tolerance=tolerance,
        max_steps=max_steps,
        length=CM_A,
        snap=arcs(case),
        geometry_degree=degree,
        solve=path,
        on_step=on_step,
        **options,
    )
    with result.problem as problem:
        record = cattaneo_mindlin_measure(problem)
    for row, s, n in zip(steps, result.history, solves, strict=True):
        row.update(relative=s.relative, solves=sum(n), seconds=s.seconds)
    record.update(
        scene="cattaneo-mindlin-adaptive",
        degree=degree,
        across=across,
        tolerance=tolerance,
        steps=steps,
        solves_per_step=solves[-1],
        seconds=comm.allreduce(time.perf_counter() - begin, op=MPI.MAX),
    )
    if not keep_traction:
        for key in ("x", "q", "p"):
            record.pop(key)
    return record

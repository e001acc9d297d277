# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""What to tell a user whose model is singular, or whose tied solve pulls the surfaces.

* :func:`unsupported_error`: the rigid motions that no Dirichlet condition, no contact
  row and no stiffness holds (Eq. 33 with every multiplier active). A body that contact
  touches yet leaves free moves tangentially to every contact surface: frictionless
  contact, which pushes only along the normals, can never hold it, whatever the contact
  area, so the advice for contact that opened (``start="tied"``, smaller load steps)
  cannot help: the message names the Dirichlet condition it misses instead.
* :func:`warn_tied_gaps`: a tied problem (Eq. 18) closes the initial gaps :math:`g_0`
  of its pairs; where they are not zero it pulls the surfaces together and returns
  negative pressures (tension), which :class:`~dolfinx_contact_s2s.unilateral.
  UnilateralContactProblem` (:math:`g \ge 0`) would not.
"""

from __future__ import annotations

import typing
import warnings
from collections.abc import Sequence

from mpi4py import MPI

import numpy as np

from dolfinx_contact_s2s.checks.support import RigidMotion, SupportGram, UnsupportedMotion

__all__ = [
    "GAP_TOLERANCE",
    "TENSION_TOLERANCE",
    "contact_bodies",
    "unsupported_error",
    "warn_tied_gaps",
]


def contact_bodies(support: SupportGram) -> set[tuple[int, int]]:
    """The bodies, ``(space, component)``, that some contact row acts on (collective)."""
    owners = [
        (s, c) for s, b in enumerate(support.bodies) for c in range(b.count) for _ in range(b.modes)
    ]
    local: set[int] = set()
    for rows in support.rows:
        if rows is not None and rows.nnz:
            local.update(np.unique(rows.tocoo().col).tolist())
    columns = set().union(*support.comm.allgather(local))
    return {owners[j] for j in columns}


def _missing_condition(motion: RigidMotion) -> str:
    """The Dirichlet condition that holds ``motion``, in words."""
    t, w = np.asarray(motion.translation), np.asarray(motion.rotation)
    size = float(np.max(motion.bounding_box[1] - motion.bounding_box[0], initial=0.0))
    if np.linalg.norm(w) * max(size, 1e-300) <= 1e-8 * np.linalg.norm(t):
        axis = int(np.argmax(np.abs(t)))
        if abs(t[axis]) >= (1 - 1e-8) * np.linalg.norm(t):
            name = "xyz"[axis]
            return (
                f"a Dirichlet condition on its {name} component (V.sub({axis}), u_{name} = 0 "
                "or a prescribed value) somewhere on that body"
            )
        return "a Dirichlet condition on the components along that direction"
    return (
        "a Dirichlet condition on the tangential component at a second point of that "
        "body (or on both components of one edge)"
    )


def unsupported_error(motions: Sequence[UnsupportedMotion], support: SupportGram) -> ValueError:
    """The error for motions free with every contact row active (Eq. 33; collective).

    Args:
        motions: The unsupported motions (every multiplier active).
        support: The Gram matrix they were found with.

    Returns:
        The :class:`ValueError` to raise, the same on every rank.
    """
    lines = "\n".join(f"  - {m.describe()}" for m in motions)
    touched = contact_bodies(support)
    advice = []
    for m in motions:
        first = m.motions[0]
        if any((b.space, b.component) in touched for b in m.motions):
            advice.append(
                f"Frictionless contact cannot hold {first.body()}: contact pushes only "
                f"along the normals of the surfaces, and its {first.description} is "
                "tangential to every one of them even with every multiplier active, so no "
                "contact area, start or load step holds it. Add "
                f"{_missing_condition(first)}."
            )
    if len(advice) < len(motions):
        advice.append("Add a Dirichlet condition (or a contact pair) that holds each of them.")
    return ValueError(
        "the problem is singular: these rigid motions meet no Dirichlet condition, "
        f"no contact constraint and no stiffness (Eq. 33):\n{lines}\n" + "\n".join(advice)
    )


#: Largest initial gap, relative to the size of the contactor, of a pair whose gaps count
#: as closed (:func:`warn_tied_gaps`): far above the round-off of a matching mesh's
#: :math:`g_0` (:math:`10^{-16}`), far below a gap a user draws.
GAP_TOLERANCE = 1e-8
#: Most negative pressure, relative to the largest one, that counts as zero.
TENSION_TOLERANCE = 1e-8


def warn_tied_gaps(problem: typing.Any) -> None:
    r"""Warn (``UserWarning``, the same on every rank) if a tied solve closed open gaps.

    For each pair, the weighted initial gaps :math:`\int \mu_j g_0` divided by
    :math:`\int \mu_j` (a length per multiplier; in axisymmetry times :math:`2\pi r_j`
    at the multiplier's node, as :math:`g_0` carries :math:`2\pi r`) are compared with
    :data:`GAP_TOLERANCE` times the contactor's size, and the multipliers with
    :data:`TENSION_TOLERANCE` times the largest: open initial gaps and a negative
    pressure mean the tied problem pulled the surfaces together. Collective.

    Args:
        problem: A solved :class:`~dolfinx_contact_s2s.problem.LinearContactProblem`.
    """
    comm = problem.comm
    for j, (op, lam, pair) in enumerate(
        zip(problem.operators, problem.multipliers, problem.pairs, strict=True)
    ):
        n = op.G.getLocalSize()
        start = op.G.getOwnershipRange()[0]
        keep = np.ones(n, dtype=bool)
        inactive = op.inactive[(op.inactive >= start) & (op.inactive < start + n)] - start
        keep[inactive] = False
        lengths = pair.multiplier_integrals()[:n]
        if pair.axisymmetric:
            # G carries 2 pi r (Eq. 17 in axisymmetry): so does the length, at mu_j's node.
            lengths = lengths * 2 * np.pi * pair.Q.tabulate_dof_coordinates()[:n, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            gaps = np.where(lengths > 0, op.G.array_r / lengths, 0.0)[keep]
        values = lam.x.array[:n][keep]
        x = pair.Q.mesh.geometry.x
        lower = comm.allgather(np.min(x, axis=0, initial=np.inf))
        upper = comm.allgather(np.max(x, axis=0, initial=-np.inf))
        size = float(np.max(np.max(upper, axis=0) - np.min(lower, axis=0)))
        largest_gap = comm.allreduce(float(np.max(np.abs(gaps), initial=0.0)), op=MPI.MAX)
        lowest = comm.allreduce(float(np.min(values, initial=np.inf)), op=MPI.MIN)
        largest = comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)
        if largest_gap <= GAP_TOLERANCE * size or not lowest < -TENSION_TOLERANCE * largest:
            continue
        warnings.warn(
            f"pair {j} (contactor tag {pair.contactor.tag}) has initial gaps (up to "
            f"{largest_gap:.3g}): the tied problem closes them and pulls the surfaces "
            f"together (tension: the smallest pressure is {lowest:.3g}, negative). Contact "
            "that may open is UnilateralContactProblem, which imposes g >= 0 "
            "(dolfinx_contact_s2s.unilateral).",
            UserWarning,
            stacklevel=3,
        )

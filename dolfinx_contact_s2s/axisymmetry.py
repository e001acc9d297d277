# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Axisymmetric bodies and contact: the ring weight :math:`2\pi r` and the checks of the axis.

An axisymmetric mesh lies in the half-plane :math:`r = x_0 \ge 0` of the :math:`(r, z)`
plane. Its integrals carry the weight :math:`2\pi r`: the elasticity forms
(:meth:`~dolfinx_contact_s2s.elasticity.Material.forms` with ``plane="axisymmetric"``) and
the contact integral of Eq. (17) of a pair made with ``axisymmetric=True``, where
:math:`r` is that of the contactor point. A contact surface may touch the axis (an end
node at :math:`r = 0`) but neither cross it nor lie on it; the checks here raise
:class:`ValueError` on every rank otherwise.
"""

from __future__ import annotations

import math

from mpi4py import MPI

import dolfinx
import numpy as np
import numpy.typing as npt

__all__ = [
    "AXIS_TOLERANCE",
    "check_axis_surface",
    "check_axisymmetric_mesh",
    "ring_weights",
]

#: A node lies on the axis when :math:`|r|` is at most this fraction of its mesh's size
#: (the diameter of its bounding box, over all processes); below :math:`-` that, at
#: :math:`r < 0`.
AXIS_TOLERANCE = 1e-10


def _size(mesh: dolfinx.mesh.Mesh) -> float:
    """Diameter of the mesh's bounding box over all processes (collective)."""
    x = mesh.geometry.x[:, : mesh.geometry.dim]
    boxes = mesh.comm.allgather(
        (np.min(x, axis=0, initial=np.inf), np.max(x, axis=0, initial=-np.inf))
    )
    lower = np.min([lo for lo, _ in boxes], axis=0)
    upper = np.max([hi for _, hi in boxes], axis=0)
    return float(np.linalg.norm(upper - lower))


def check_axisymmetric_mesh(mesh: dolfinx.mesh.Mesh, tolerance: float = AXIS_TOLERANCE) -> None:
    """Raise :class:`ValueError` on every rank if a node of ``mesh`` lies at :math:`r < 0`.

    Collective. :math:`r = x_0`; the test is :math:`r < -` ``tolerance`` times the mesh's
    size.
    """
    if mesh.geometry.dim != 2:
        raise ValueError(
            f"an axisymmetric mesh lies in the (r, z) plane: gdim must be 2, not "
            f"{mesh.geometry.dim}"
        )
    owned = mesh.geometry.x[: mesh.geometry.index_map().size_local, 0]
    size = _size(mesh)
    count = mesh.comm.allreduce(int(np.count_nonzero(owned < -tolerance * size)), op=MPI.SUM)
    if count:
        lowest = mesh.comm.allreduce(float(np.min(owned, initial=np.inf)), op=MPI.MIN)
        raise ValueError(
            f"the axisymmetric mesh {mesh.name!r} has {count} node(s) at r = x[0] < 0 (down "
            f"to r = {lowest:.4g}): an axisymmetric body lies in the half-plane r >= 0 "
            "with its axis at r = 0; mesh half the section, or move it to r >= 0"
        )


def check_axis_surface(surface, tolerance: float = AXIS_TOLERANCE, samples: int = 5) -> None:
    r"""Raise :class:`ValueError` on every rank if a contact surface crosses or lies on the axis.

    Collective. A surface of an axisymmetric pair must lie in :math:`r \ge 0`; it may touch
    the axis at an end node (:math:`r = 0`, e.g. the flat face of a solid cylinder), but a
    facet with :math:`r < 0` (the surface crosses the axis, or lies behind it) or one
    lying on the axis (:math:`r = 0` all along: no area) is refused. The facets are
    sampled at ``samples`` points each.

    Args:
        surface: A :class:`~dolfinx_contact_s2s.surface.ContactSurface`.
        tolerance: Relative to the size of the surface's mesh (see :data:`AXIS_TOLERANCE`).
        samples: Points per facet.
    """
    mesh, comm = surface.V.mesh, surface.comm
    if mesh.topology.dim != 2:
        raise ValueError(
            f"contact surface {surface.tag} is on a {mesh.topology.dim}D mesh: an "
            "axisymmetric model is a 2D mesh of the (r, z) half plane, with r the axis' distance"
        )
    data = surface.data
    n = len(data)
    xi = np.linspace(0.0, 1.0, samples)
    rows = np.repeat(np.arange(n, dtype=np.int32), samples)
    _, x, _ = surface.evaluate(data, rows, np.tile(xi, n))
    r = x[:, 0].reshape(n, samples)
    eps = tolerance * _size(mesh)
    behind = comm.allreduce(int(np.count_nonzero(np.any(r < -eps, axis=1))), op=MPI.SUM)
    ahead = comm.allreduce(int(np.count_nonzero(np.any(r > eps, axis=1))), op=MPI.SUM)
    on_axis = comm.allreduce(int(np.count_nonzero(np.all(np.abs(r) <= eps, axis=1))), op=MPI.SUM)
    if behind:
        where = "crosses the axis r = 0" if ahead else "lies at r < 0"
        raise ValueError(
            f"the axisymmetric contact surface {surface.tag} {where} ({behind} facet(s) "
            "with points at r = x[0] < 0): an axisymmetric surface lies in r >= 0 and may "
            "only touch the axis at an end node; mesh half the section"
        )
    if on_axis:
        raise ValueError(
            f"the axisymmetric contact surface {surface.tag} has {on_axis} facet(s) on the "
            "axis r = 0: they have no area (weight 2 pi r = 0); leave the axis out of the "
            "contact tag"
        )


def ring_weights(
    weights: npt.NDArray[np.floating], r: npt.NDArray[np.floating]
) -> npt.NDArray[np.floating]:
    r"""Point weights times the ring length :math:`2\pi r` (``r`` of the same shape)."""
    return weights * (2 * math.pi) * r

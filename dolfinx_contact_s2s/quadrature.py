# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Quadrature rules for contact integrals (Fig. 15): the unit interval, and the triangle.

Gauss rules come from Basix; closed Newton-Cotes rules (Fig. 15(c): the two-point
one is the trapezoidal rule) have equally spaced points including both ends.
"""

from __future__ import annotations

import basix
import numpy as np
import numpy.typing as npt

__all__ = ["RULES", "interval_rule", "split_face_rule", "triangle_rule"]

#: Rule names: ``composite-`` rules are applied on every sub-segment (Fig. 15(b)-(c)),
#: the others on every contactor segment (Fig. 15(a)).
RULES = ("composite-gauss", "composite-newton-cotes", "gauss", "newton-cotes")


def interval_rule(
    kind: str, points: int
) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    """Points and weights of a rule on :math:`[0, 1]`.

    Args:
        kind: ``"gauss"`` (Gauss-Legendre, exact to degree :math:`2n - 1`) or
            ``"newton-cotes"`` (closed, exact to degree :math:`n - 1`, or :math:`n` for
            odd :math:`n`); a ``composite-`` prefix is ignored here.
        points: Number of points :math:`n`.
    """
    kind = kind.removeprefix("composite-")
    if kind == "gauss":
        if points < 1:
            raise ValueError("a Gauss rule needs at least one point")
        x, w = basix.make_quadrature(
            basix.CellType.interval, 2 * points - 1, rule=basix.QuadratureType.gauss_jacobi
        )
        return x[:, 0], w
    if kind == "newton-cotes":
        if points < 2:
            raise ValueError("a closed Newton-Cotes rule needs at least two points")
        x = np.linspace(0.0, 1.0, points)
        # Weights integrating 1, x, ..., x^(n-1) exactly.
        moments = 1.0 / np.arange(1, points + 1)
        w = np.linalg.solve(np.vander(x, increasing=True).T, moments)
        return x, w
    raise ValueError(f"unknown quadrature rule {kind!r}; choose from {RULES}")


def triangle_rule(degree: int) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    """Basix's Gauss-Jacobi rule on the reference triangle, for the pieces of faces.

    The composite rule in 3D (Fig. 15(b) on faces) places it on every sub-triangle of
    the overlap of a contactor face and a target face.

    Args:
        degree: Maximum polynomial degree that will be integrated exactly.

    Returns:
        ``(points, weights)``, of shapes ``(Q, 2)`` and ``(Q,)``; the weights sum to 1/2.
    """
    x, w = basix.make_quadrature(
        basix.CellType.triangle, max(int(degree), 0), rule=basix.QuadratureType.gauss_jacobi
    )
    return x, w


def split_face_rule(
    cell: str, degree: int, pieces: int
) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    """Basix's Gauss rule on each of the ``pieces**2`` pieces of a reference face.

    For integrands with a kink inside a face, such as :math:`(r - e)_+^{3/2}` at a
    contact front: the kink then costs accuracy on a few pieces only.

    Args:
        cell: ``"triangle"`` (cut into upright and inverted triangles) or
            ``"quadrilateral"``.
        degree: Maximum polynomial degree that will be integrated exactly on each piece.
        pieces: Pieces along each edge.

    Returns:
        ``(points, weights)`` on the whole reference face.
    """
    s, w = basix.make_quadrature(basix.CellType[cell], int(degree))
    k = int(pieces)
    if cell == "quadrilateral":
        shifts = [((i, j), 1.0) for i in range(k) for j in range(k)]
    else:
        shifts = [((i, j), 1.0) for i in range(k) for j in range(k - i)]
        shifts += [((i + 1, j + 1), -1.0) for i in range(k) for j in range(k - i - 1)]
    points = np.concatenate([(np.array(c) + sign * s) / k for c, sign in shifts])
    return points, np.tile(w / k**2, len(shifts))

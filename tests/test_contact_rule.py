# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The rule on the pieces of faces: exact on affine faces, measured on the others.

A flat quadrilateral that is not a parallelogram has a rational inverse map, so the
integrals of its shape functions over straight-sided triangles of its plane (the pieces
of Fig. 15(b) in 3D) are not polynomials in the rule's points: the rule is raised until
they are exact to round-off. The numbers checked are closed forms.
"""

import itertools

from mpi4py import MPI

import numpy as np
import pytest

from dolfinx_contact_s2s.contact_rule import (
    RULE_TOLERANCE,
    face_rule,
    non_affine,
    piece_integrals,
    rule_error,
)
from dolfinx_contact_s2s.quadrature import triangle_rule

#: The trapezoid (0, 0), (2, 0), (0, 1), (1, 1) in Basix's vertex order, tilted out of
#: the coordinate planes: x(xi, eta) = (xi (2 - eta), eta), area element 2 - eta, so
#: int N_j dA = 5/12, 5/12, 1/3, 1/3 (N_0 = (1 - xi)(1 - eta), ...; sum 3/2, the area).
_TRAPEZOID = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
_TRAPEZOID_INTEGRALS = np.array([5 / 12, 5 / 12, 1 / 3, 1 / 3])


def _tilted(points_2d: np.ndarray) -> np.ndarray:
    """Plane points mapped into 3D by a rotation and a shift, ``(1, K, 3)``."""
    q, _ = np.linalg.qr(np.array([[0.3, -0.8, 0.5], [0.9, 0.2, -0.4], [0.1, 0.6, 0.7]]))
    x = np.column_stack([points_2d, np.zeros(len(points_2d))]) @ q.T + [0.5, -1.0, 2.0]
    return x[None]


def test_a_trapezoid_needs_a_higher_rule():
    """Closed-form integrals: missed at the polynomial degree, met once the rule is raised."""
    face = _tilted(_TRAPEZOID)
    assert non_affine(face)[0].tolist() == [True]
    base = piece_integrals(face, triangle_rule(4))
    assert np.abs(base - _TRAPEZOID_INTEGRALS).max() > 1e-8
    errors = [rule_error(face, triangle_rule(q))[0] for q in (4, 8, 12, 16)]
    assert all(b < a / 10 for a, b in itertools.pairwise(errors)), errors
    rule, degree, error = face_rule([_Surface(face)], 4, MPI.COMM_SELF)
    assert degree > 4 and error <= RULE_TOLERANCE
    np.testing.assert_allclose(piece_integrals(face, rule)[0], _TRAPEZOID_INTEGRALS, atol=1e-13)


@pytest.mark.parametrize(
    "nodes, cost",
    [
        ([[0, 0], [2, 0], [0.5, 1], [2.5, 1]], False),  # A parallelogram: affine.
        ([[0, 0], [2, 0], [0, 1]], False),  # A triangle: affine.
        # A P2 triangle whose midside nodes slide along straight edges: flat, not affine.
        ([[0, 0], [2, 0], [0, 1], [1.2, 0.4], [0, 0.6], [0.8, 0]], True),
    ],
)
def test_only_non_affine_faces_raise_the_rule(nodes, cost):
    """Affine faces keep the polynomial degree (exact: closed-form area), others pay."""
    face = _tilted(np.array(nodes, dtype=float))
    flat, curved = non_affine(face)
    assert flat.tolist() == [cost] and curved.tolist() == [False]
    _, degree, error = face_rule([_Surface(face)], 4, MPI.COMM_SELF)
    assert (degree > 4) == cost and error <= RULE_TOLERANCE
    area = 0.5 * np.linalg.norm(np.cross(face[0, 1] - face[0, 0], face[0, 2] - face[0, 0]))
    area *= 2 if len(nodes) == 4 else 1
    assert piece_integrals(face, triangle_rule(degree)).sum() == pytest.approx(area, rel=1e-14)


def test_curved_faces_are_not_measured():
    """A bent face's pieces miss its curved boundary whatever the rule: not measured."""
    face = _tilted(np.array([[0, 0], [2, 0], [0, 1], [1.0, 0.7], [0, 0.5], [1.0, 0.0]]))
    face[0, 3] += 0.05 * np.cross(face[0, 1] - face[0, 0], face[0, 2] - face[0, 0])
    flat, curved = non_affine(face)
    assert curved.tolist() == [True] and flat.tolist() == [False]
    assert face_rule([_Surface(face)], 6, MPI.COMM_SELF)[1:] == (6, 0.0)


class _Surface:
    """The part of a contact surface :func:`face_rule` reads: its face nodes."""

    def __init__(self, nodes: np.ndarray):
        self.data = type("Data", (), {"coefficients": nodes, "__len__": lambda s: len(nodes)})()

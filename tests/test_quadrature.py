# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The split face rule against closed-form integrals on the reference faces."""

import math

import numpy as np
import pytest

from dolfinx_contact_s2s.quadrature import split_face_rule


def _monomial(cell: str, a: int, b: int) -> float:
    """:math:`\\int x^a y^b` on the reference triangle or square."""
    if cell == "triangle":
        return math.factorial(a) * math.factorial(b) / math.factorial(a + b + 2)
    return 1.0 / ((a + 1) * (b + 1))


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
@pytest.mark.parametrize("pieces", [1, 3, 4])
def test_exact_to_its_degree(cell, pieces):
    x, w = split_face_rule(cell, 8, pieces)
    inside = x.sum(axis=1) <= 1 + 1e-14 if cell == "triangle" else np.all(x <= 1 + 1e-14, axis=1)
    assert np.all(inside) and np.all(x >= -1e-14)
    for a in range(9):
        for b in range(9 - a):
            exact = _monomial(cell, a, b)
            assert w @ (x[:, 0] ** a * x[:, 1] ** b) == pytest.approx(exact, rel=1e-13, abs=1e-15)


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral"])
def test_a_kink_costs_a_few_pieces(cell):
    """:math:`\\int (x - e)_+^{3/2}`: the error of a Gauss rule across the kink falls as the
    width of the pieces it cuts to the power 5/2, so 4 pieces per edge take it down by
    about :math:`4^{5/2} = 32` (measured: 17 on the triangle, 39 on the square)."""
    e = 0.3
    if cell == "triangle":
        # int_e^1 (x - e)^{3/2} (1 - x) dx
        exact = (1 - e) ** 3.5 / 2.5 / 3.5
    else:
        exact = (1 - e) ** 2.5 / 2.5
    errors = []
    for pieces in (1, 4):
        x, w = split_face_rule(cell, 8, pieces)
        errors.append(abs(w @ np.maximum(x[:, 0] - e, 0.0) ** 1.5 - exact))
    assert errors[1] < errors[0] / 10, errors

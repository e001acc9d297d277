# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Edges, the facets of 2D cells: their bases as polynomials in the edge's parameter, checks.

The counterpart of :mod:`dolfinx_contact_s2s.faces` for the facets of 2D cells.
"""

from __future__ import annotations

from mpi4py import MPI

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s import faces
from dolfinx_contact_s2s.compat import tabulate
from dolfinx_contact_s2s.kernels.numpy_backend import DEGENERATE_TOLERANCE

__all__ = ["check_edges", "facet_monomials"]


def facet_monomials(
    element, ref_a: npt.NDArray[np.floating], ref_b: npt.NDArray[np.floating]
) -> npt.NDArray[np.floating]:
    r"""Monomial coefficients in :math:`\xi` of a scalar element's basis along reference facets.

    On the straight reference facet :math:`X(\xi) = X_a + \xi (X_b - X_a)` a degree-:math:`k`
    Lagrange basis function is a polynomial of degree :math:`k` in :math:`\xi`: Basix
    tabulates it at :math:`k + 1` equispaced points, a Vandermonde solve gives the
    coefficients (the input of the backends' ``facet_basis`` and ``facet_coefficients``).

    Args:
        element: Scalar Basix-UFL element.
        ref_a: First vertex of each reference facet, ``(L, tdim)``.
        ref_b: Second vertex of each reference facet, ``(L, tdim)``.

    Returns:
        ``table[l, m, k]``, shape ``(L, degree + 1, num_dofs)``.
    """
    p = element.degree
    xi = np.linspace(0.0, 1.0, p + 1)
    vandermonde = np.vander(xi, p + 1, increasing=True)
    out = []
    for a, b in zip(ref_a, ref_b, strict=True):
        tab = tabulate(element, 0, a[None, :] + xi[:, None] * (b - a)[None, :])[0]
        # A Lagrange function at equispaced facet points is 0 or of order 0.1 (degree <= 2);
        # Basix's round-off (1e-17) on the functions of the dofs off the facet would couple
        # those dofs: times the far side of a soft body (displacements 1e3 times the
        # contact line's) that broke the patch test by 3e-9 at a contrast of 3e4.
        tab[np.abs(tab) < 1e-12] = 0.0
        out.append(np.linalg.solve(vandermonde, tab))
    return np.ascontiguousarray(np.stack(out))


def check_edges(
    comm: MPI.Comm,
    tag: int,
    coords: npt.NDArray[np.floating],
    coefficients: npt.NDArray[np.floating],
    normals: npt.NDArray[np.floating],
) -> None:
    """Raise on every rank for NaN or infinite nodes, or zero-length facets (collective).

    One reduction of two counts; the location of a degenerate facet is gathered only
    when there is one, so that every rank raises the same message.
    """
    finite = np.all(np.isfinite(coords), axis=(1, 2))
    extent = np.max(np.abs(coords - coords[:, :1, :]), axis=(1, 2), initial=0.0)
    chord = np.linalg.norm(np.sum(coefficients[:, 1:, :], axis=1), axis=1)
    flat = finite & (
        ~(chord > DEGENERATE_TOLERANCE * extent) | ~np.all(np.isfinite(normals), axis=1)
    )
    faces.raise_degenerate(
        comm,
        tag,
        finite,
        flat,
        coefficients[:, 0, :],
        "facet",
        "zero length (two nodes coincide)",
        "remove the duplicate nodes from the mesh",
    )

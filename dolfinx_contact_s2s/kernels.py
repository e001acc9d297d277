# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Batched element kernels of the contact coupling block.

Every kernel works on whole arrays of sub-segments at once, so that a compiled
implementation can replace it with the same signature.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = ["segment_to_segment"]


def segment_to_segment(
    mu: npt.NDArray[np.floating],
    phi_c: npt.NDArray[np.floating],
    phi_t: npt.NDArray[np.floating],
    normals: npt.NDArray[np.floating],
    weights: npt.NDArray[np.floating],
    gaps: npt.NDArray[np.floating],
) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating], npt.NDArray[np.floating]]:
    r"""Local coupling blocks of Eqs. (40)-(42) on a batch of sub-segments.

    For sub-segment :math:`s` with integration points :math:`i`, multiplier basis
    :math:`H^{ik}_C` (Eq. 42), contactor basis :math:`h^{ij}_C` (Eq. 41), target basis
    :math:`h^{ij}_T` at the target points :math:`x^{i*}_T` (Eq. 38), normal
    :math:`N^i` and weight :math:`w^i`:

    .. math::
        B_C[s, k, j c] = \sum_i w^i H^{ik}_C h^{ij}_C N^i_c, \quad
        B_T[s, k, j c] = -\sum_i w^i H^{ik}_C h^{ij}_T N^i_c, \quad
        G[s, k] = \sum_i w^i H^{ik}_C g_0^{i}.

    Args:
        mu: Multiplier basis, shape ``(S, Q, nk)``.
        phi_c: Contactor displacement basis (scalar), shape ``(S, Q, nc)``.
        phi_t: Target displacement basis (scalar), shape ``(S, Q, nt)``.
        normals: Contact normals :math:`N`, shape ``(S, Q, gdim)``.
        weights: Quadrature weights including the facet Jacobian, shape ``(S, Q)``.
        gaps: Initial gap :math:`g_0` at the points, shape ``(S, Q)``.

    Returns:
        ``(B_C, B_T, G)`` of shapes ``(S, nk, nc * gdim)``, ``(S, nk, nt * gdim)`` and
        ``(S, nk)``; displacement columns are blocked as ``j * gdim + c``, the
        interleaved layout of DOLFINx vector spaces.
    """
    S, _, nk = mu.shape
    gdim = normals.shape[2]
    wmu = mu * weights[:, :, None]
    b_c = np.einsum("sqk,sqj,sqc->skjc", wmu, phi_c, normals).reshape(S, nk, phi_c.shape[2] * gdim)
    b_t = -np.einsum("sqk,sqj,sqc->skjc", wmu, phi_t, normals).reshape(S, nk, phi_t.shape[2] * gdim)
    g = np.einsum("sqk,sq->sk", wmu, gaps)
    return b_c, b_t, g

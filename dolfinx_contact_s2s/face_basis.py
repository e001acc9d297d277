# SPDX-License-Identifier: MIT
r"""The displacement basis on faces of 3D cells: the face's dofs only, no Basix per point.

On a face only its dofs' functions are nonzero, polynomials in :math:`Q_p` of the face
coordinates :math:`\xi` (:func:`~dolfinx_contact_s2s.faces.reference_vertices`): their
monomial coefficients are fitted once per local face from Basix's tabulation.
"""

from __future__ import annotations

import weakref

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s import faces
from dolfinx_contact_s2s.compat import tabulate

# Values below this are Basix's round-off, as ContactSurface.facet_basis drops them.
ROUNDOFF = 1e-12
_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


class FaceBasis:
    """Monomial coefficients ``coef[f]`` of the nonzero functions ``cols[f]`` on face ``f``."""

    def __init__(self, element, cell) -> None:
        """Fit ``element``'s functions on each face of ``cell`` (exact: checked)."""
        p = element.degree
        self.powers = np.array([(i, j) for j in range(p + 1) for i in range(p + 1)])
        s = np.linspace(0.0, 1.0, p + 2)
        grid = np.stack(np.meshgrid(s, s, indexing="ij"), axis=-1).reshape(-1, 2)
        V = self.monomials(grid)
        coef, cols = [], []
        for v in faces.reference_vertices(cell):
            X = v[0] + grid[:, :1] * (v[1] - v[0]) + grid[:, 1:] * (v[2] - v[0])
            table = tabulate(element, 0, X)[0]
            c = np.linalg.lstsq(V, table, rcond=None)[0]
            c[np.abs(c) < ROUNDOFF] = 0.0
            if not np.allclose(V @ c, table, rtol=0.0, atol=1e-13):
                raise ValueError("the basis on a face is not in Q_p of its coordinates")
            keep = np.flatnonzero(np.any(c != 0.0, axis=0))
            coef.append(c[:, keep])
            cols.append(keep)
        if len({k.size for k in cols}) != 1:
            raise ValueError("faces with different numbers of dofs")
        self.coef = np.stack(coef)
        self.cols = np.stack(cols).astype(np.int64)

    def monomials(self, xi: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        r""":math:`\xi_1^i \xi_2^j` at points ``xi``, ``(n, (p + 1)^2)``."""
        return xi[:, :1] ** self.powers[:, 0] * xi[:, 1:2] ** self.powers[:, 1]

    def values(
        self, local_facet: npt.NDArray[np.int32], xi: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        """The functions ``cols[local_facet]`` at face coordinates ``xi``, ``(n, nf)``."""
        M = self.monomials(xi)
        out = np.empty((xi.shape[0], self.cols.shape[1]))
        for f in range(self.coef.shape[0]):
            on = np.flatnonzero(local_facet == f)
            if on.size:
                out[on] = M[on] @ self.coef[f]
        out[np.abs(out) < ROUNDOFF] = 0.0
        return out


def face_basis(surface, data, groups, nq, xi):
    """The scalar basis at the points of ``groups`` (``nq`` each) and their unrolled dofs.

    Returns ``(phi, dofs)``: ``(len(groups) * nq, nf)`` and ``(len(groups), nf * bs)``, the
    face's dofs only on faces; on edges, every dof of the cell (``facet_basis``).
    """
    rows = np.repeat(groups, nq)
    if surface.facet_dim != 2:
        return surface.facet_basis(data, rows, xi), data.dofs[groups]
    basis = _CACHE.get(surface)
    if basis is None:
        basis = _CACHE[surface] = FaceBasis(surface.element, surface.cell_type)
    lf = data.local_facet[groups]
    bs = surface.V.dofmap.index_map_bs
    # Explicit sizes: a rank may have no groups.
    nf = basis.cols.shape[1] * bs
    cols = (basis.cols[lf][:, :, None] * bs + np.arange(bs)).reshape(len(groups), nf)
    phi = basis.values(np.repeat(lf, nq), np.ascontiguousarray(xi, dtype=np.float64))
    return phi, np.take_along_axis(data.dofs[groups], cols, axis=1)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The multiplier space of Eq. (16) on the contactor facets, and its basis at points.

The multiplier of the segment-to-segment algorithm (section 5) is continuous on the
contactor surface, of the displacement's degree (:math:`M^1_{h,1}`, :math:`M^1_{h,2}`):
a DOLFINx Lagrange space on a submesh of the contactor's tagged facets
(:func:`facet_space`). Its cells have their own vertex order: on an edge the cell may run
against the facet parameter (:attr:`MultiplierSpace.flip`); on a face its vertices are a
permutation of the face's (:attr:`MultiplierSpace.corners`). :meth:`MultiplierSpace.basis`
evaluates :math:`H^k` of Eq. (42) at facet parameters either way.
"""

from __future__ import annotations

import functools
import typing
from dataclasses import dataclass

import basix
import basix.ufl
import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.compat import geometry_dofmap, submesh_parent_entities, tabulate
from dolfinx_contact_s2s.edges import facet_monomials
from dolfinx_contact_s2s.face_basis import fit_monomials
from dolfinx_contact_s2s.kernels import KernelBackend
from dolfinx_contact_s2s.surface import ContactSurface, SurfaceData

__all__ = ["MultiplierSpace", "cell_rows", "facet_space"]


@dataclass(frozen=True)
class MultiplierSpace:
    r"""The multiplier space of a pair and its place on the contactor facets.

    Attributes:
        Q: The multiplier function space.
        element: Its scalar Basix-UFL element.
        cells: Cell of ``Q``'s mesh on each contactor facet row (empty for a space that
            does not live on the contactor facets).
        flip: Whether the cell runs against the contactor facet parameter
            (:math:`s = 1 - \xi`), per contactor facet row (edges).
        corners: On faces, the reference coordinates in ``Q``'s cell of the contactor
            face's corners 0, 1 and 2, ``(F, 3, 2)``: the cell's reference point of face
            coordinates :math:`\xi` is :math:`X_0 + \xi_1 (X_1 - X_0) + \xi_2 (X_2 - X_0)`
            (a symmetry of the reference triangle or square). ``None`` on edges.
        dual: Whether :meth:`basis` is the dual (biorthogonal) basis of the Lagrange
            basis :math:`\mu_k` on affine facets (Wohlmuth): on each facet
            :math:`\psi_i = \sum_j A_{ij} \mu_j` (:attr:`dual_coefficients`), so that
            :math:`\int_e \psi_i \mu_j = \delta_{ij} \int_e \mu_j` and
            :math:`\sum_i \psi_i = 1`; P1 edges: :math:`\psi_i = 2 \mu_i - \mu_j`.
    """

    Q: dolfinx.fem.FunctionSpace
    element: typing.Any
    cells: npt.NDArray[np.int32]
    flip: npt.NDArray[np.bool_]
    corners: npt.NDArray[np.floating] | None = None
    dual: bool = False

    @functools.cached_property
    def integrals(self) -> npt.NDArray[np.floating]:
        r"""The integrals :math:`|\int \mu_k|` of the owned basis functions (read-only).

        Computed once, collective the first time: ``Q`` lives on a mesh of its own,
        made with the pair, whose nodes nothing moves.
        """
        form = dolfinx.fem.form(ufl.TestFunction(self.Q) * ufl.dx(domain=self.Q.mesh))
        vector = dolfinx.fem.assemble_vector(form)
        vector.scatter_reverse(dolfinx.la.InsertMode.add)
        return _owned(np.abs(vector.array), self.Q)

    @functools.cached_property
    def squares(self) -> npt.NDArray[np.floating]:
        r"""The integrals :math:`\int \mu_k^2` of the owned basis functions (read-only).

        The diagonal of the multiplier mass; positive where :attr:`integrals` may vanish
        (the vertex functions of a P2 triangle). Collective the first time.
        """
        mu, nu = ufl.TrialFunction(self.Q), ufl.TestFunction(self.Q)
        mass = dolfinx.fem.assemble_matrix(dolfinx.fem.form(mu * nu * ufl.dx))
        mass.scatter_reverse()
        return _owned(mass.to_scipy().diagonal(), self.Q)

    @functools.cached_property
    def edge_table(self) -> npt.NDArray[np.floating]:
        """The basis on an edge cell as polynomials in its parameter :math:`s` (monomials)."""
        return facet_monomials(self.element, np.zeros((1, 1)), np.ones((1, 1)))

    @functools.cached_property
    def face_coefficients(self) -> npt.NDArray[np.floating]:
        r"""On faces, the basis on each contactor face as monomials of its coordinates.

        :func:`~dolfinx_contact_s2s.face_basis.fit_monomials` through :attr:`corners`,
        ``(F, (s + 1)^2, num_dofs)``: :meth:`basis` at :math:`\xi` is
        :math:`\sum_{ij} \xi_1^i \xi_2^j` times row :math:`j (s + 1) + i`.
        """
        coefficients = fit_monomials(self.element, self.element.degree, self.corners)
        return coefficients @ self.dual_coefficients.T if self.dual else coefficients

    @functools.cached_property
    def dual_coefficients(self) -> npt.NDArray[np.floating]:
        r"""The dual basis on a facet, :math:`\mathbf A = \mathbf D \mathbf M^{-1}` (cell dofs).

        :math:`\mathbf M` is the mass on the reference cell and :math:`\mathbf D` its row
        sums (:math:`\int_e \mu_j`): on an affine facet the Jacobian cancels.
        Biorthogonality is :math:`\mathbf A \mathbf M = \mathbf D`; the columns of
        :math:`\mathbf A` sum to 1. The quadratic edge's :math:`\int_e \mu_j` (1/6, 1/6,
        2/3) are positive, as are Q1's and Q2's: no modified basis is needed (the
        quadratic triangle's vanish: refused, :meth:`check_dual`).
        """
        return np.linalg.solve(self._reference_mass, np.diag(self._reference_mass.sum(axis=1))).T

    @functools.cached_property
    def dual_mass(self) -> npt.NDArray[np.floating]:
        r""":math:`\int_e \psi_i \psi_j = \mathbf D \mathbf M^{-1} \mathbf D`, reference cell."""
        return self.dual_coefficients @ np.diag(self._reference_mass.sum(axis=1))

    @functools.cached_property
    def _reference_mass(self) -> npt.NDArray[np.floating]:
        points, weights = basix.make_quadrature(self.element.cell_type, 2 * self.element.degree)
        mu = tabulate(self.element, 0, points)[0]
        return mu.T @ (weights[:, None] * mu)

    def basis(
        self, rows: npt.NDArray[np.int32], xi: npt.NDArray[np.floating], backend: KernelBackend
    ) -> npt.NDArray[np.floating]:
        r"""The multiplier basis :math:`H^k` of Eq. (42) at contactor facet parameters.

        Args:
            rows: Contactor facet row of each point, ``(n,)``.
            xi: Facet parameter of each point: ``(n,)`` on edges, ``(n, 2)`` on faces.
            backend: The contactor's kernels (edges: the basis from :attr:`edge_table`).

        Returns:
            The basis of each point's cell, ``(n, num_dofs)``, in the order of ``Q``'s
            cell dofs.
        """
        if self.corners is None:
            s = np.where(self.flip[rows], 1.0 - xi, xi)
            mu = backend.facet_basis(self.edge_table, np.zeros(s.size, np.int32), s)
            return mu @ self.dual_coefficients.T if self.dual else mu
        X0, X1, X2 = (self.corners[rows, i] for i in range(3))
        X = X0 + xi[:, :1] * (X1 - X0) + xi[:, 1:2] * (X2 - X0)
        mu = tabulate(self.element, 0, X)[0]
        return mu @ self.dual_coefficients.T if self.dual else mu

    def check_dual(self) -> None:
        """Raise ``ValueError`` where the dual basis is not defined (collective).

        A basis function of zero integral (the quadratic triangle's vertices) has no dual
        partner; on a quadrilateral that is not a parallelogram the Jacobian is not
        constant, so the combination :attr:`dual_coefficients` is not biorthogonal.
        """
        integrals = self._reference_mass.sum(axis=1)
        problem = ""
        if np.min(integrals) <= 1e-12 * np.max(integrals):
            problem = f"P{self.element.degree} on a {self.element.cell_type.name} has basis "
            problem += "functions of zero integral"
        mesh = self.Q.mesh
        cells = mesh.topology.index_map(mesh.topology.dim).size_local
        if self.element.cell_type == basix.CellType.quadrilateral and cells:
            x = mesh.geometry.x[geometry_dofmap(mesh)[:cells, :4]]
            skew = np.linalg.norm(x[:, 0] + x[:, 3] - x[:, 1] - x[:, 2], axis=1)
            if np.any(skew > 1e-10 * np.linalg.norm(x[:, 1] - x[:, 0], axis=1)):
                problem = "a contactor face is not a parallelogram"
        problems = [p for p in mesh.comm.allgather(problem) if p]
        if problems:
            raise ValueError(
                f"dual multipliers need a positive integral of every basis function and "
                f"affine facets: {problems[0]} (use a Lagrange multiplier)"
            )


def facet_space(
    contactor: ContactSurface,
    degree: int,
    discontinuous: bool,
    variant: basix.LagrangeVariant,
    dual: bool = False,
) -> MultiplierSpace:
    """A Lagrange space of Eq. (16) on a submesh of the contactor's tagged facets.

    With ``dual``, its coefficients are those of the dual basis (:class:`MultiplierSpace`).
    """
    mesh = contactor.V.mesh
    fdim = mesh.topology.dim - 1
    imap = mesh.topology.index_map(fdim)
    num_facets = imap.size_local + imap.num_ghosts
    submesh, entity_map, _, _ = dolfinx.mesh.create_submesh(mesh, fdim, contactor.tagged_facets)
    sub_map = submesh.topology.index_map(fdim)
    num_sub = sub_map.size_local + sub_map.num_ghosts
    parent = submesh_parent_entities(entity_map, num_sub)
    parent_to_sub = np.full(num_facets, -1, dtype=np.int32)
    parent_to_sub[parent] = np.arange(num_sub, dtype=np.int32)
    element = basix.ufl.element(
        "Lagrange",
        submesh.basix_cell(),
        degree,
        lagrange_variant=variant,
        discontinuous=discontinuous,
    )
    Q = dolfinx.fem.functionspace(submesh, element)
    # The submesh has the mesh's nodes: match it with the surface there, not displaced.
    data = contactor.reference
    cells = parent_to_sub[data.facets]
    if fdim == 2:
        return MultiplierSpace(
            Q, element, cells, np.zeros(len(data), bool), _face_corners(data, submesh, cells), dual
        )
    # The submesh cell may run against the facet parametrisation: s = xi or 1 - xi.
    rows = np.arange(len(data), dtype=np.int32)
    _, x0, _ = contactor.evaluate(data, rows, np.zeros(rows.size))
    sub_x = submesh.geometry.x[geometry_dofmap(submesh)[cells, 0], : x0.shape[1]]
    flip = np.linalg.norm(sub_x - x0, axis=1) > 1e-8 * (1.0 + np.linalg.norm(x0, axis=1))
    return MultiplierSpace(Q, element, cells, flip, dual=dual)


def _face_corners(
    data: SurfaceData, submesh: dolfinx.mesh.Mesh, cells: npt.NDArray[np.int32]
) -> npt.NDArray[np.floating]:
    """Reference coordinates in each submesh cell of its contactor face's corners 0, 1, 2.

    The submesh cell of a face has the face's vertices in an order of its own; matching
    their coordinates gives the vertex permutation, a symmetry of the reference cell.
    """
    reference = basix.geometry(submesh.basix_cell())
    nv = reference.shape[0]
    corners = data.coefficients[:, :nv]
    sub_x = submesh.geometry.x[geometry_dofmap(submesh)[cells, :nv]]
    distance = np.linalg.norm(corners[:, :, None, :] - sub_x[:, None, :, :], axis=-1)
    match = np.argmin(distance, axis=2)
    size = np.linalg.norm(np.ptp(corners, axis=1), axis=1)
    found = np.take_along_axis(distance, match[:, :, None], axis=2)[:, :, 0]
    if len(data) and (
        np.any(found > 1e-10 * size[:, None]) or np.any(np.sort(match, axis=1) != np.arange(nv))
    ):
        raise RuntimeError("the multiplier mesh's cells do not match the contact faces")
    return np.ascontiguousarray(reference[match[:, :3]])


def cell_rows(space: MultiplierSpace, c_rows: npt.NDArray[np.int32]) -> npt.NDArray[np.int64]:
    """Global multiplier dofs of the cells on contactor facet rows ``c_rows``, ``(S, nk)``."""
    qmap = space.Q.dofmap
    local = qmap.list[space.cells[c_rows]]
    rows = qmap.index_map.local_to_global(local.reshape(-1)).reshape(local.shape)
    return rows.astype(np.int64)


def _owned(values: npt.NDArray[np.floating], Q: dolfinx.fem.FunctionSpace) -> npt.NDArray:
    """A read-only copy of the owned entries of ``values``."""
    owned = np.array(values[: Q.dofmap.index_map.size_local])
    owned.setflags(write=False)
    return owned

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Contact surfaces: tagged boundary facets of a body and their geometry.

A :class:`ContactSurface` holds, for every *owned* facet carrying a tag, the cell it
belongs to, its local facet number, the cell's geometry nodes and the global
indices of the displacement degrees of freedom of that cell. It evaluates points,
tangents and outward normals on the facets in batches, which is all the coupling
assembly of :mod:`dolfinx_contact_s2s.coupling` needs.

Facets are parametrised by :math:`\xi \in [0, 1]` along the straight reference
facet, :math:`X(\xi) = X_a + \xi (X_b - X_a)`, where :math:`X_a, X_b` are the
reference vertices of the facet in Basix numbering; the physical facet is the
image of that segment under the cell's coordinate map, so quadratic (curved)
geometry is handled exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

from mpi4py import MPI

import basix
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s._compat import blocked_sub_element, geometry_dofmap

__all__ = ["ContactSurface", "SurfaceData", "contact_surface", "tabulate"]


def tabulate(element, derivatives: int, X: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    """Tabulate a scalar Basix-UFL element, also at zero points.

    Returns:
        Array ``(num_derivatives, num_points, num_dofs)``.
    """
    X = np.ascontiguousarray(X, dtype=np.float64)
    if X.shape[0] == 0:
        tdim = X.shape[1]
        count = (derivatives + 1) if tdim == 1 else (derivatives + 1) * (derivatives + 2) // 2
        return np.zeros((count, 0, element.dim))
    return element.tabulate(derivatives, X)


@dataclass(frozen=True)
class SurfaceData:
    """Per-facet arrays of a contact surface (one row per facet).

    Attributes:
        coords: Geometry nodes of the facet's cell, shape ``(num_facets, num_nodes, gdim)``.
        local_facet: Local index of the facet in its cell.
        dofs: Global (unrolled) displacement dofs of the facet's cell,
            shape ``(num_facets, num_cell_dofs * bs)``.
        facets: Process-local facet index in the body's mesh (``-1`` for rows
            gathered from another process).
    """

    coords: npt.NDArray[np.floating]
    local_facet: npt.NDArray[np.int32]
    dofs: npt.NDArray[np.int64]
    facets: npt.NDArray[np.int32]

    def __len__(self) -> int:
        """Number of facets."""
        return self.local_facet.shape[0]


class ContactSurface:
    """The tagged, owned boundary facets of one body and their displacement space."""

    def __init__(self, V: dolfinx.fem.FunctionSpace, facet_tags: dolfinx.mesh.MeshTags, tag: int):
        """Collect the facets of ``facet_tags`` marked ``tag`` on the mesh of ``V``.

        Args:
            V: Vector-valued Lagrange displacement space of the body.
            facet_tags: Facet markers of the body's mesh.
            tag: Marker of the contact surface.

        Raises:
            ValueError: On every rank, if no process holds a facet with ``tag``, or if
                ``V`` is not a vector Lagrange space on a 2D triangle or quadrilateral mesh.
        """
        mesh = V.mesh
        comm = mesh.comm
        tdim = mesh.topology.dim
        fdim = tdim - 1
        if facet_tags.dim != fdim:
            raise ValueError(
                f"facet_tags must mark facets (dimension {fdim}), not {facet_tags.dim}"
            )
        cell_name = mesh.topology.cell_name()
        if tdim != 2 or cell_name not in ("triangle", "quadrilateral"):
            raise ValueError(
                f"contact surfaces are implemented for 2D triangle and quadrilateral meshes, "
                f"not {cell_name} (tdim {tdim})"
            )
        element = V.ufl_element()
        if element.block_size != mesh.geometry.dim:
            raise ValueError("V must be a vector-valued space with one component per dimension")
        scalar = blocked_sub_element(element)
        if scalar.degree not in (1, 2) or scalar.discontinuous:
            raise ValueError("V must be a continuous Lagrange space of degree 1 or 2")

        num_owned = mesh.topology.index_map(fdim).size_local
        marked = facet_tags.indices[facet_tags.values == tag]
        facets = np.sort(marked[marked < num_owned]).astype(np.int32)
        if comm.allreduce(facets.size, op=MPI.SUM) == 0:
            raise ValueError(f"no facet of the mesh carries contact tag {tag}")

        mesh.topology.create_connectivity(fdim, tdim)
        mesh.topology.create_connectivity(tdim, fdim)
        f_to_c = mesh.topology.connectivity(fdim, tdim)
        c_to_f = mesh.topology.connectivity(tdim, fdim)
        num_links = f_to_c.offsets[facets + 1] - f_to_c.offsets[facets]
        interior = comm.allreduce(int(np.count_nonzero(num_links != 1)), op=MPI.SUM)
        if interior:
            raise ValueError(f"contact facets must be on the boundary (tag {tag})")
        cells = f_to_c.array[f_to_c.offsets[facets]].astype(np.int32)
        facets_per_cell = len(basix.topology(basix.CellType[cell_name])[fdim])
        cell_facets = c_to_f.array.reshape(-1, facets_per_cell)[cells]
        local_facet = np.argmax(cell_facets == facets[:, None], axis=1).astype(np.int32)

        gdim = mesh.geometry.dim
        x_dofs = geometry_dofmap(mesh)[cells]
        coords = mesh.geometry.x[x_dofs][:, :, :gdim]

        bs = V.dofmap.index_map_bs
        blocks = V.dofmap.list[cells]
        global_blocks = V.dofmap.index_map.local_to_global(blocks.reshape(-1)).reshape(blocks.shape)
        dofs = (global_blocks[:, :, None] * bs + np.arange(bs)[None, None, :]).reshape(
            cells.size, blocks.shape[1] * bs
        )

        self.V = V
        self.tag = tag
        self.tagged_facets = np.unique(marked).astype(np.int32)
        self.cells = cells
        self.data = SurfaceData(coords, local_facet, dofs.astype(np.int64), facets)
        self.cell_type = basix.CellType[cell_name]
        self.element = scalar
        # Scalar Basix element of the coordinate map (tabulates derivatives).
        self.cmap = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element())
        ref_x = basix.geometry(self.cell_type)
        facet_vertices = np.array(basix.topology(self.cell_type)[fdim])
        self._ref_a = ref_x[facet_vertices[:, 0]]
        self._ref_b = ref_x[facet_vertices[:, 1]]
        self._ref_normals = np.asarray(basix.cell.facet_outward_normals(self.cell_type))

    @property
    def comm(self) -> MPI.Comm:
        """Communicator of the body's mesh."""
        return self.V.mesh.comm

    def gather(self) -> SurfaceData:
        """All facets of the surface, from every process, on every process."""
        parts = self.comm.allgather(self.data)
        return SurfaceData(
            np.concatenate([p.coords for p in parts]),
            np.concatenate([p.local_facet for p in parts]),
            np.concatenate([p.dofs for p in parts]),
            np.full(sum(len(p) for p in parts), -1, dtype=np.int32),
        )

    # Batched evaluation. ``rows`` selects facets of ``data``, one per point.

    def reference_points(
        self, data: SurfaceData, rows: npt.NDArray[np.int32], xi: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        r"""Reference-cell coordinates :math:`X(\xi)` of points on facets ``rows``."""
        lf = data.local_facet[rows]
        a, b = self._ref_a[lf], self._ref_b[lf]
        return a + xi[:, None] * (b - a)

    def evaluate(
        self,
        data: SurfaceData,
        rows: npt.NDArray[np.int32],
        xi: npt.NDArray[np.floating],
        derivatives: int = 1,
    ) -> tuple[npt.NDArray[np.floating], ...]:
        r"""Points and derivatives along the facets.

        Args:
            data: Facet arrays (local or gathered).
            rows: Facet row of each point.
            xi: Facet parameter of each point.
            derivatives: 1 for :math:`x, x'`; 2 adds :math:`x''`.

        Returns:
            ``(X, x, dx)`` or ``(X, x, dx, ddx)``: reference points, physical points and
            their derivatives with respect to :math:`\xi`, each of shape ``(n, gdim)``.
        """
        X = self.reference_points(data, rows, xi)
        lf = data.local_facet[rows]
        d = self._ref_b[lf] - self._ref_a[lf]
        tab, coords, x, J = self._map(data, rows, X, derivatives)
        dx = np.einsum("pgd,pd->pg", J, d)
        if derivatives == 1:
            return X, x, dx
        # Second derivatives along d: phi_xx d0^2 + 2 phi_xy d0 d1 + phi_yy d1^2.
        d2 = (
            tab[3] * d[:, 0:1] ** 2 + 2 * tab[4] * (d[:, 0:1] * d[:, 1:2]) + tab[5] * d[:, 1:2] ** 2
        )
        ddx = np.einsum("pk,pkg->pg", d2, coords)
        return X, x, dx, ddx

    def _map(
        self,
        data: SurfaceData,
        rows: npt.NDArray[np.int32],
        X: npt.NDArray[np.floating],
        derivatives: int,
    ) -> tuple[npt.NDArray[np.floating], ...]:
        """Coordinate-map tables, cell nodes, points and Jacobians at reference points."""
        tab = tabulate(self.cmap, derivatives, X)
        coords = data.coords[rows]
        x = np.einsum("pk,pkg->pg", tab[0], coords)
        J = np.einsum("pkg,dpk->pgd", coords, tab[1:3])
        return tab, coords, x, J

    def outward_normals(
        self, data: SurfaceData, rows: npt.NDArray[np.int32], X: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        r"""Unit outward normals :math:`J^{-T} \hat n / |J^{-T} \hat n|` at reference points."""
        J = self._map(data, rows, X, 1)[3]
        n_ref = self._ref_normals[data.local_facet[rows], :, None]
        n = np.linalg.solve(np.swapaxes(J, 1, 2), n_ref)[:, :, 0]
        return n / np.linalg.norm(n, axis=1)[:, None]

    def basis(self, X: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        """Scalar displacement basis functions at reference points, shape ``(n, num_dofs)``."""
        return tabulate(self.element, 0, X)[0]

    def project(
        self,
        data: SurfaceData,
        rows: npt.NDArray[np.int32],
        points: npt.NDArray[np.floating],
        iterations: int = 8,
    ) -> npt.NDArray[np.floating]:
        r"""Closest-point parameters :math:`\xi` of ``points`` on the (extended) facets.

        Solves :math:`(x(\xi) - p) \cdot x'(\xi) = 0` by Newton's method: the point of the
        facet whose normal passes through ``p`` (Fig. 15(b): target nodes projected onto
        the contactor). One step is exact on straight facets.
        """
        xi = np.full(rows.size, 0.5)
        for _ in range(iterations):
            _, x, dx, ddx = self.evaluate(data, rows, xi, derivatives=2)
            r = x - points
            f = np.einsum("pg,pg->p", r, dx)
            df = np.einsum("pg,pg->p", dx, dx) + np.einsum("pg,pg->p", r, ddx)
            step = f / df
            xi = xi - step
            if np.all(np.abs(step) < 1e-15):
                break
        return xi

    def intersect(
        self,
        data: SurfaceData,
        rows: npt.NDArray[np.int32],
        origins: npt.NDArray[np.floating],
        directions: npt.NDArray[np.floating],
        iterations: int = 8,
    ) -> npt.NDArray[np.floating]:
        r"""Parameters :math:`\eta` where the lines ``origins + t * directions`` cross the facets.

        Solves :math:`(x(\eta) - o) \times N = 0` by Newton's method: the target point
        :math:`x_T^{i*}` of a contactor integration point along the normal (Eq. 38, Fig. 7(b)).
        """
        perp = np.stack([-directions[:, 1], directions[:, 0]], axis=1)
        eta = np.full(rows.size, 0.5)
        for _ in range(iterations):
            _, x, dx = self.evaluate(data, rows, eta)
            f = np.einsum("pg,pg->p", x - origins, perp)
            df = np.einsum("pg,pg->p", dx, perp)
            step = f / df
            eta = eta - step
            if np.all(np.abs(step) < 1e-15):
                break
        return eta

    def bounding_boxes(self, data: SurfaceData, samples: int = 5) -> npt.NDArray[np.floating]:
        """Axis-aligned boxes ``(num_facets, 2, gdim)`` of the facets, from sample points.

        The boxes are padded by a quarter of each facet's size, which covers the
        deviation of a quadratic facet from its sample points.
        """
        n = len(data)
        rows = np.repeat(np.arange(n, dtype=np.int32), samples)
        xi = np.tile(np.linspace(0.0, 1.0, samples), n)
        _, x, _ = self.evaluate(data, rows, xi)
        x = x.reshape(n, samples, x.shape[1])
        lo, hi = x.min(axis=1), x.max(axis=1)
        pad = 0.25 * np.linalg.norm(hi - lo, axis=1)[:, None]
        return np.stack([lo - pad, hi + pad], axis=1)

    def sizes(self, data: SurfaceData) -> npt.NDArray[np.floating]:
        """Chord length of each facet."""
        n = len(data)
        rows = np.arange(n, dtype=np.int32)
        _, x0, _ = self.evaluate(data, rows, np.zeros(n))
        _, x1, _ = self.evaluate(data, rows, np.ones(n))
        return np.linalg.norm(x1 - x0, axis=1)


def contact_surface(
    V: dolfinx.fem.FunctionSpace, facet_tags: dolfinx.mesh.MeshTags, tag: int
) -> ContactSurface:
    """Create the :class:`ContactSurface` of facets marked ``tag`` on the mesh of ``V``."""
    return ContactSurface(V, facet_tags, tag)

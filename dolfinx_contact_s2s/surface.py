# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Contact surfaces: tagged boundary facets of a body and their geometry.

A :class:`ContactSurface` holds, for every *owned* facet carrying a tag, the cell it
belongs to, its local facet number, the cell's geometry nodes and the global
indices of the displacement degrees of freedom of that cell. It evaluates points,
tangents and outward normals on the facets in batches, which is all the coupling
assembly of :mod:`dolfinx_contact_s2s.pair` needs. The batched geometry runs in a
kernel backend (:func:`dolfinx_contact_s2s.kernels.get_backend`); Basix tabulates.

Facets are parametrised by :math:`\xi \in [0, 1]` along the straight reference
facet, :math:`X(\xi) = X_a + \xi (X_b - X_a)`, where :math:`X_a, X_b` are the
reference vertices of the facet in Basix numbering; the physical facet is the
image of that segment under the cell's coordinate map, so quadratic (curved)
geometry is handled exactly. Faces of 3D cells (tetrahedra, hexahedra) are parametrised
by the reference coordinates :math:`(\xi_1, \xi_2)` of Basix's Lagrange element on the
face, and their geometry is their nodes in that element's order
(:mod:`dolfinx_contact_s2s.faces`).
"""

from __future__ import annotations

from dataclasses import dataclass

from mpi4py import MPI

import basix
import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s import faces
from dolfinx_contact_s2s.compat import blocked_sub_element, geometry_dofmap, tabulate
from dolfinx_contact_s2s.edges import check_edges, facet_monomials
from dolfinx_contact_s2s.kernels import get_backend

__all__ = ["ContactSurface", "SurfaceData", "contact_surface", "facet_monomials", "tabulate"]


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
        coefficients: Monomial coefficients of the facet's geometry in its parameter,
            shape ``(num_facets, p + 1, gdim)`` (see
            :func:`~dolfinx_contact_s2s.kernels.numpy_backend.facet_coefficients`).
        orientation: ``+1`` or ``-1``: the sign that turns the facet's tangent into its
            outward normal.
    """

    coords: npt.NDArray[np.floating]
    local_facet: npt.NDArray[np.int32]
    dofs: npt.NDArray[np.int64]
    facets: npt.NDArray[np.int32]
    coefficients: npt.NDArray[np.floating]
    orientation: npt.NDArray[np.floating]

    def __len__(self) -> int:
        """Number of facets."""
        return self.local_facet.shape[0]


class ContactSurface:
    """The tagged, owned boundary facets of one body and their displacement space."""

    #: Whether the surface is rigid (no unknowns: :mod:`dolfinx_contact_s2s.obstacles`).
    rigid = False

    def __init__(
        self,
        V: dolfinx.fem.FunctionSpace,
        facet_tags: dolfinx.mesh.MeshTags,
        tag: int,
        *,
        backend: str = "auto",
    ):
        """Collect the facets of ``facet_tags`` marked ``tag`` on the mesh of ``V``.

        Args:
            V: Vector-valued Lagrange displacement space of the body.
            facet_tags: Facet markers of the body's mesh.
            tag: Marker of the contact surface.
            backend: Kernel backend of the facet geometry and the coupling: ``"numpy"``,
                ``"c"`` or ``"auto"`` (``$S2S_KERNEL_BACKEND``, else C when it compiles),
                see :func:`dolfinx_contact_s2s.kernels.get_backend` (collective).

        Raises:
            ValueError: On every rank, if no process holds a facet with ``tag``, if a
                tagged facet is not on the mesh boundary, if ``facet_tags`` belong to
                another mesh, if ``V`` is not a vector Lagrange space on a 2D triangle or
                quadrilateral mesh in the plane or a 3D tetrahedron or hexahedron mesh,
                or if a tagged facet has a node with NaN or infinite coordinates or zero
                length or area (no normal, Eq. 38).
        """
        mesh = V.mesh
        comm = mesh.comm
        tdim = mesh.topology.dim
        fdim = tdim - 1
        if facet_tags.dim != fdim:
            raise ValueError(
                f"facet_tags must mark facets (dimension {fdim}), not {facet_tags.dim}"
            )
        if _cpp(facet_tags.topology) is not _cpp(mesh.topology):
            raise ValueError(
                "facet_tags belong to another mesh than V's: pass the facet tags of the "
                "mesh V is built on"
            )
        cell_name = mesh.topology.cell_name()
        cells_of = {2: ("triangle", "quadrilateral"), 3: ("tetrahedron", "hexahedron")}
        if mesh.geometry.dim != tdim or cell_name not in cells_of.get(tdim, ()):
            raise ValueError(
                f"contact surfaces are implemented for 2D triangle and quadrilateral meshes "
                f"in the plane and 3D tetrahedron and hexahedron meshes, not {cell_name} "
                f"(tdim {tdim}, gdim {mesh.geometry.dim}); create a 2D mesh with gdim=2"
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
        # Counting local cells is not enough: without ghost cells an interior facet on a
        # partition boundary has one local cell. DOLFINx's exterior facets exclude those.
        exterior = dolfinx.mesh.exterior_facet_indices(mesh.topology)
        outside = np.count_nonzero(~np.isin(facets, exterior, assume_unique=True))
        interior = comm.allreduce(int(outside), op=MPI.SUM)
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
        self.cell_type = basix.CellType[cell_name]
        self.element = scalar
        self.backend = get_backend(backend, comm, facet_dim=fdim)
        # Scalar Basix element of the coordinate map (tabulates derivatives).
        self.cmap = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element())
        with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
            # NaN or infinite nodes raise inside, on every rank; no warnings on the way.
            if fdim == 2:
                coefficients, orientation = self._face_geometry(coords, local_facet)
            else:
                coefficients, orientation = self._edge_geometry(coords, local_facet)
        self.data = SurfaceData(
            coords, local_facet, dofs.astype(np.int64), facets, coefficients, orientation
        )
        #: The geometry at the mesh's nodes :math:`X` (:attr:`data` until
        #: :meth:`set_displacement` places the surface elsewhere).
        self.reference = self.data
        #: V's scalar basis at the coordinate element's nodes (rows): u there.
        self.node_weights = tabulate(scalar, 0, self.cmap.basix_element.points)[0]
        self._blocks = blocks
        #: The values of the displacement :attr:`data` is placed at (None: at :math:`X`).
        self.placement: npt.NDArray[np.floating] | None = None
        # The geometry dofs of the facets' cells, to notice a mesh moved after this point.
        self._x_nodes = np.unique(x_dofs)
        self._x_start = self.V.mesh.geometry.x[self._x_nodes, :gdim].copy()
        # Caches of :meth:`gather`, :meth:`gather_near` and :meth:`bounding_boxes`, each
        # with the :attr:`data` it was made from: stale once :attr:`data` is replaced.
        self._gathered: tuple[SurfaceData, SurfaceData] | None = None
        self._near: tuple[SurfaceData | None, dict[bytes, SurfaceData]] = (None, {})
        self._gathered_boxes: dict[int, tuple[SurfaceData, int, npt.NDArray[np.floating]]] = {}

    def _edge_geometry(
        self, coords: npt.NDArray[np.floating], local_facet: npt.NDArray[np.int32]
    ) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
        """Monomial coefficients and orientation signs of edges (facets of 2D cells)."""
        ref_x = basix.geometry(self.cell_type)
        facet_vertices = np.array(basix.topology(self.cell_type)[1])
        self._ref_a = ref_x[facet_vertices[:, 0]]
        self._ref_b = ref_x[facet_vertices[:, 1]]
        self._ref_normals = np.asarray(basix.cell.facet_outward_normals(self.cell_type))
        self._facet_basis = facet_monomials(self.cmap, self._ref_a, self._ref_b)
        self._basis_table = facet_monomials(self.element, self._ref_a, self._ref_b)
        # Relative to each cell's first node, so that the chord and curvature terms carry
        # no round-off of the scene's position (a scene far from the origin); the basis is
        # a partition of unity, so the origin adds to the constant term only.
        origin = coords[:, :1, :]
        coefficients = self.backend.facet_coefficients(
            self._facet_basis, local_facet, np.ascontiguousarray(coords - origin)
        )
        coefficients[:, 0, :] += origin[:, 0, :]
        # The sign turning tangents into outward normals, from J^-T n_ref once per facet.
        rows = np.arange(local_facet.size, dtype=np.int32)
        half = np.full(local_facet.size, 0.5)
        X = self._ref_a[local_facet] + 0.5 * (self._ref_b[local_facet] - self._ref_a[local_facet])
        tab = tabulate(self.cmap, 1, X)
        n = self.backend.cell_normals(tab[1:3], coords, self._ref_normals[local_facet])
        _, dx = self.backend.evaluate(coefficients, rows, half)
        turn = n[:, 0] * dx[:, 1] - n[:, 1] * dx[:, 0]
        check_edges(self.comm, self.tag, coords, coefficients, n)
        return coefficients, np.where(turn < 0.0, -1.0, 1.0)

    def _face_geometry(
        self, coords: npt.NDArray[np.floating], local_facet: npt.NDArray[np.int32]
    ) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
        """Face nodes in the face element's order and orientation signs (faces of 3D cells)."""
        self._ref_vertices = faces.reference_vertices(self.cell_type)
        nodes = self.backend.facet_coefficients(
            faces.face_node_order(self.cmap), local_facet, coords
        )
        orientation, oriented = faces.face_orientation(self.cmap, coords, local_facet, nodes)
        faces.check_faces(self.comm, self.tag, coords, nodes, oriented)
        return nodes, orientation

    def set_displacement(self, u: dolfinx.fem.Function | None) -> None:
        r"""Place the surface at :math:`x = X + u`, the current configuration (collective).

        The facet geometry, normals, search and gap of every later coupling are those of
        :math:`X + u`; the mesh, :attr:`V` and the multiplier space stay on :math:`X`.
        ``u`` is read now. The coupling is then linearized at :math:`u` in the total
        displacement: :func:`~dolfinx_contact_s2s.assemble.assemble_coupling` gives the
        gap :math:`\mathbf G(u) - \mathbf B(u)\, \mathbf u`, so that the gap of
        :math:`\mathbf U` is :math:`\mathbf G(u) + \mathbf B(u) (\mathbf U - \mathbf
        u)`. Every surface of a pair on one space must be placed at the same :math:`u`.

        Args:
            u: A displacement in :attr:`V` (ghosts updated here), interpolated exactly at
                the geometry's nodes; ``None`` returns the surface to :math:`X`.

        Raises:
            ValueError: On every rank: ``u`` is not a function in :attr:`V`; :attr:`V`'s
                degree is above the geometry's (the current facets would be curved, the
                mesh's cannot be: give the mesh geometry of the displacement's degree);
                NaN or infinite values; a cell at the surface inverted by ``u`` (named).
        """
        if u is None:
            self.data, self.placement = self.reference, None
            return
        if getattr(u, "function_space", None) is None or not (
            u.function_space == self.V or u.function_space.dofmap is self.V.dofmap
        ):
            raise ValueError("the displacement must be a dolfinx.fem.Function in the surface's V")
        if self.element.degree > self.cmap.degree:
            raise ValueError(
                f"a displacement of degree {self.element.degree} curves facets that the "
                f"mesh's geometry of degree {self.cmap.degree} cannot follow: give the mesh "
                "geometry of the displacement's degree (e.g. Gmsh's setOrder)"
            )
        u.x.scatter_forward()
        ref = self.reference
        values = u.x.array.reshape(-1, self.V.dofmap.index_map_bs)[self._blocks]
        data = self.geometry(ref.coords + self.nodal(values))
        # A facet turned against its cell's outward normal: the cell is inverted.
        flipped = np.flatnonzero(data.orientation != ref.orientation)
        cells = self.comm.allgather(self.cells[flipped][:3].tolist())
        if any(cells):
            raise ValueError(
                f"the displacement inverts cells at contact surface {self.tag} (det F <= 0): "
                + "; ".join(f"process {r}: local cells {c}" for r, c in enumerate(cells) if c)
                + "; take a smaller load step"
            )
        self.data = data
        self.placement = u.x.array.copy()

    def nodal(self, values: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        """Displacements ``(cells, V nodes, bs)`` of the facets' cells at their geometry nodes."""
        gdim = self.reference.coords.shape[2]
        return np.einsum("xv,cvg->cxg", self.node_weights, values[:, :, :gdim])

    def geometry(self, coords: npt.NDArray[np.floating]) -> SurfaceData:
        """The surface's facets with their cells' nodes at ``coords`` (collective: checks)."""
        ref = self.reference
        with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
            if self.facet_dim == 2:
                coefficients, orientation = self._face_geometry(coords, ref.local_facet)
            else:
                coefficients, orientation = self._edge_geometry(coords, ref.local_facet)
        return SurfaceData(coords, ref.local_facet, ref.dofs, ref.facets, coefficients, orientation)

    def moved(self) -> bool:
        """Whether the mesh's nodes on this surface changed since its creation (collective).

        The facet geometry, the search radius and the multiplier space are built from the
        nodes at creation; a mesh moved afterwards (``mesh.geometry.x += ...``) would
        otherwise be coupled with its old contact geometry.
        """
        now = self.V.mesh.geometry.x[self._x_nodes, : self._x_start.shape[1]]
        return self.comm.allreduce(not np.array_equal(now, self._x_start), op=MPI.LOR)

    @property
    def facet_dim(self) -> int:
        """Topological dimension of the facets (1: edges of 2D cells).

        The key of the facet's segmentation
        (:data:`~dolfinx_contact_s2s.segmentation.SEGMENTATIONS`) and kernels.
        """
        return self.V.mesh.topology.dim - 1

    @property
    def comm(self) -> MPI.Comm:
        """Communicator of the body's mesh."""
        return self.V.mesh.comm

    def gather(self) -> SurfaceData:
        """All facets of the surface, from every process, on every process (collective).

        The gathered arrays are kept (read-only) until :attr:`data` is replaced on some
        process: every assembly of a pair reuses them without communication.
        """
        cached = self._gathered
        fresh = cached is not None and cached[0] is self.data
        if self.comm.size > 1:
            fresh = self.comm.allreduce(fresh, op=MPI.LAND)
        if fresh and cached is not None:
            return cached[1]
        gathered = _concatenate(self.comm.allgather(self.data))
        for array in vars(gathered).values():
            array.setflags(write=False)
        self._gathered = (self.data, gathered)
        return gathered

    def gather_near(self, region: npt.NDArray[np.floating] | None) -> SurfaceData:
        """The facets of the surface, from every process, whose boxes meet ``region``.

        Collective. Each process names the axis-aligned box ``(2, gdim)`` it needs (or
        ``None``); each process then sends every other only its own facets that meet
        that box, in one all-to-all: a process boxes and segments against the part of a
        target it can reach instead of the whole gathered surface. Rows keep the order
        of :meth:`gather`. On one process this is :meth:`gather`. The results of the
        last :data:`NEAR_REGIONS` regions are kept until :attr:`data` is replaced.
        """
        if self.comm.size == 1:
            return self.gather()
        key = b"" if region is None else np.asarray(region, dtype=np.float64).tobytes()
        data, cache = self._near
        if data is not self.data:
            cache = {}
        # Pairs that share this target ask for their own regions in turn: a few are kept.
        # Every process makes the same calls, so the caches agree; all must hit.
        if self.comm.allreduce(key in cache, op=MPI.LAND):
            cache[key] = cache.pop(key)  # most recently used last
            return cache[key]
        regions = self.comm.allgather(region if region is None else np.asarray(region))
        boxes = self.backend.bounding_boxes(self.data.coefficients, 5, 0.25)
        parts: list[SurfaceData | None] = []
        for r in regions:
            rows = np.empty(0, dtype=np.int64)
            if r is not None:
                meets = np.all((boxes[:, 0] <= r[1]) & (r[0] <= boxes[:, 1]), axis=1)
                rows = np.flatnonzero(meets)
            parts.append(_subset(self.data, rows))
        # This process's own part stays here: only the other parts are pickled.
        own, parts[self.comm.rank] = parts[self.comm.rank], None
        received = self.comm.alltoall(parts)
        received[self.comm.rank] = own
        near = _concatenate(received)
        for array in vars(near).values():
            array.setflags(write=False)
        cache.pop(key, None)
        cache[key] = near
        while len(cache) > NEAR_REGIONS:
            cache.pop(next(iter(cache)))
        self._near = (self.data, cache)
        return near

    # Batched evaluation. ``rows`` selects facets of ``data``, one per point.

    def reference_points(
        self, data: SurfaceData, rows: npt.NDArray[np.int32], xi: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        r"""Reference-cell coordinates :math:`X(\xi)` of points on facets ``rows``."""
        lf = data.local_facet[rows]
        if self.facet_dim == 2:
            v = self._ref_vertices[lf]
            return v[:, 0] + xi[:, :1] * (v[:, 1] - v[:, 0]) + xi[:, 1:2] * (v[:, 2] - v[:, 0])
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
        xi = np.ascontiguousarray(xi, dtype=np.float64)
        X = self.reference_points(data, rows, xi)
        return (X, *self.backend.evaluate(data.coefficients, rows, xi, derivatives))

    def outward_normals(
        self, data: SurfaceData, rows: npt.NDArray[np.int32], xi: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        r"""Unit outward normals :math:`J^{-T} \hat n / |J^{-T} \hat n|` at facet parameters."""
        xi = np.ascontiguousarray(xi, dtype=np.float64)
        return self.backend.outward_normals(data.coefficients, data.orientation, rows, xi)

    def basis(self, X: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        """Scalar displacement basis functions at reference points, shape ``(n, num_dofs)``."""
        return tabulate(self.element, 0, X)[0]

    def facet_basis(
        self, data: SurfaceData, rows: npt.NDArray[np.int32], xi: npt.NDArray[np.floating]
    ) -> npt.NDArray[np.floating]:
        r"""Scalar displacement basis functions at facet parameters, ``(n, num_dofs)``.

        The same values as :meth:`basis` at :meth:`reference_points`, from the basis'
        monomial coefficients along each reference facet (no tabulation).
        """
        xi = np.ascontiguousarray(xi, dtype=np.float64)
        if self.facet_dim == 2:
            # As facet_monomials does on edges: Basix's round-off on the functions of the
            # dofs off the face would couple those dofs.
            table = tabulate(self.element, 0, self.reference_points(data, rows, xi))[0]
            table[np.abs(table) < 1e-12] = 0.0
            return table
        return self.backend.facet_basis(self._basis_table, data.local_facet[rows], xi)

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
        return self.backend.project(data.coefficients, rows, points, iterations)

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
        return self.backend.intersect(data.coefficients, rows, origins, directions, iterations)

    def bounding_boxes(self, data: SurfaceData, samples: int = 5) -> npt.NDArray[np.floating]:
        """Axis-aligned boxes ``(num_facets, 2, gdim)`` of the facets, from sample points.

        The boxes of curved facets are padded by a quarter of each facet's size, which
        covers the deviation of a quadratic facet from its sample points; those of
        straight facets are exact. The boxes of :attr:`data` and of the gathered facets
        are cached (read-only).
        """
        gathered = None if self._gathered is None else self._gathered[1]
        near = [self.data, *self._near[1].values()]
        if data is gathered or any(data is n for n in near):
            # These facets change only with :attr:`data` (and the region of
            # :meth:`gather_near`): box them once.
            cache = self._gathered_boxes
            boxes = cache.get(id(data))
            if boxes is None or boxes[0] is not data or boxes[1] != samples:
                boxes = (
                    data,
                    samples,
                    self.backend.bounding_boxes(data.coefficients, samples, 0.25),
                )
                boxes[2].setflags(write=False)
                # Only the current facets, gathered and near facets are kept.
                cache = {
                    k: v
                    for k, v in cache.items()
                    if v[0] is gathered or any(v[0] is n for n in near)
                }
                cache[id(data)] = boxes
                self._gathered_boxes = cache
            return boxes[2]
        return self.backend.bounding_boxes(data.coefficients, samples, 0.25)

    def sizes(self, data: SurfaceData) -> npt.NDArray[np.floating]:
        """Chord length of each facet (of a face: the longest distance between its nodes)."""
        if self.facet_dim == 2:
            c = data.coefficients
            return np.max(np.linalg.norm(c[:, :, None] - c[:, None, :], axis=-1), axis=(1, 2))
        n = len(data)
        rows = np.arange(n, dtype=np.int32)
        _, x0, _ = self.evaluate(data, rows, np.zeros(n))
        _, x1, _ = self.evaluate(data, rows, np.ones(n))
        return np.linalg.norm(x1 - x0, axis=1)


def _concatenate(parts: list[SurfaceData]) -> SurfaceData:
    """The rows of ``parts`` (from other processes) in order; ``facets`` is -1."""
    return SurfaceData(
        np.concatenate([p.coords for p in parts]),
        np.concatenate([p.local_facet for p in parts]),
        np.concatenate([p.dofs for p in parts]),
        np.full(sum(len(p) for p in parts), -1, dtype=np.int32),
        np.concatenate([p.coefficients for p in parts]),
        np.concatenate([p.orientation for p in parts]),
    )


def _subset(data: SurfaceData, rows: npt.NDArray[np.int64]) -> SurfaceData:
    """The rows ``rows`` of ``data``."""
    return SurfaceData(*(a.take(rows, axis=0) for a in vars(data).values()))


def _cpp(obj):
    """The C++ object behind a DOLFINx wrapper (the wrappers differ between versions)."""
    return getattr(obj, "_cpp_object", obj)


#: Regions of :meth:`ContactSurface.gather_near` kept per surface (one per pair that
#: shares the surface as a target, in the scenes of this package).
NEAR_REGIONS = 4


def contact_surface(
    V: dolfinx.fem.FunctionSpace,
    facet_tags: dolfinx.mesh.MeshTags,
    tag: int,
    *,
    backend: str = "auto",
) -> ContactSurface:
    """The contact surface of the facets marked ``tag`` on the mesh of ``V`` (collective).

    A surface is one side of one body: the boundary facets of a Gmsh physical group,
    say. Pass it to :func:`~dolfinx_contact_s2s.pair.contact_pair` as a contactor or a
    target. Create it after the mesh has its final coordinates: a pair raises if the
    mesh moved afterwards.

    Args:
        V: The body's displacement space: a vector-valued continuous Lagrange space of
            degree 1 or 2, ``("Lagrange", k, (2,))``, on a 2D triangle or
            quadrilateral mesh with ``gdim=2`` (affine or quadratic geometry). It must be
            the space of the problem's form ``a`` (the same object).
        facet_tags: Facet markers (a :class:`dolfinx.mesh.MeshTags` of dimension 1) of
            the mesh of ``V``, e.g. those of the Gmsh reader.
        tag: The marker of the contact facets; they must lie on the boundary of the
            mesh. Facets owned by other processes are found by them.
        backend: The kernel backend of the facet geometry and the coupling:
            ``"auto"`` (the default: ``$S2S_KERNEL_BACKEND`` if set, else the compiled
            C kernels when CFFI and a C compiler work, else NumPy with a one-line
            notice), ``"c"`` or ``"numpy"``; see
            :func:`~dolfinx_contact_s2s.kernels.get_backend`.

    Returns:
        The :class:`ContactSurface` of this process's owned tagged facets.

    Raises:
        ValueError: On every rank: no process holds a facet marked ``tag``; a tagged
            facet is not on the boundary; ``facet_tags`` are not facet tags or belong
            to another mesh; ``V`` is not a vector Lagrange space of degree 1 or 2 on a
            2D triangle or quadrilateral mesh in the plane or a 3D tetrahedron or
            hexahedron mesh; a tagged facet has a node with NaN or infinite coordinates,
            or zero length or area; an unknown ``backend`` (faces: ``"c"`` too, they
            have NumPy kernels only).
        RuntimeError: On every rank, if ``backend="c"`` cannot be compiled.
    """
    return ContactSurface(V, facet_tags, tag, backend=backend)

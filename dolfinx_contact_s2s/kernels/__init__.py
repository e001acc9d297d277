# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Batched array kernels of the contact assembly, behind a backend seam.

A backend is a module exposing the same functions with array-only signatures (no
DOLFINx objects): facet geometry (:func:`facet_coefficients`, :func:`evaluate`,
:func:`outward_normals`, :func:`project`, :func:`intersect`), the facet bases
(:func:`facet_basis`), the sub-segment clipping of Fig. 15(b) (:func:`clip_segments`)
and the coupling kernel of Eqs. (40)-(42) (:func:`segment_to_segment`). Arrays are
C-contiguous ``float64`` (``int32`` for indices). :class:`KernelBackend` is that
interface; the modules below satisfy it. Each backend declares the topological
dimension of the facets it handles (``FACET_DIM``: 1, the edges of 2D cells, whose
parameter is :math:`\xi \in [0, 1]`; 2, the faces of 3D cells, whose parameter is a pair
of reference coordinates), chosen by :func:`get_backend`'s ``facet_dim``. Backends:

- ``"numpy"``: the reference (:mod:`~dolfinx_contact_s2s.kernels.numpy_backend`; on
  faces :mod:`~dolfinx_contact_s2s.kernels.face_backend`);
- ``"c"``: compiled C through CFFI (:mod:`~dolfinx_contact_s2s.kernels.c_backend`; on
  faces :mod:`~dolfinx_contact_s2s.kernels.face_c_backend`), built once on rank 0 and
  cached;
- ``"auto"``: ``$S2S_KERNEL_BACKEND`` if set, else ``"c"`` when CFFI and a C compiler
  work, else ``"numpy"`` with a one-line notice naming the optional extra that brings
  CFFI, ``pip install dolfinx-contact-s2s[c]``.

::

    backend = get_backend("auto", mesh.comm)
    x, dx = backend.evaluate(coefficients, rows, xi)
"""

from __future__ import annotations

import logging
import os
import typing

from mpi4py import MPI

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels import face_backend, numpy_backend

__all__ = ["BACKENDS", "ENV_BACKEND", "FACET_DIMS", "KernelBackend", "get_backend"]

#: Names of the available backends (``"auto"`` picks one of them).
BACKENDS = ("numpy", "c")

#: Environment variable naming the backend that ``"auto"`` picks.
ENV_BACKEND = "S2S_KERNEL_BACKEND"

#: Topological dimensions of the facets that have kernels (1: edges of 2D cells, 2: faces
#: of 3D cells: :mod:`~dolfinx_contact_s2s.kernels.face_backend` and its compiled twin
#: :mod:`~dolfinx_contact_s2s.kernels.face_c_backend`).
FACET_DIMS = (numpy_backend.FACET_DIM, face_backend.FACET_DIM)

_logger = logging.getLogger(__name__)
_noticed = False

_Array = npt.NDArray[np.float64]
_Rows = npt.NDArray[np.int32]


@typing.runtime_checkable
class KernelBackend(typing.Protocol):
    """The array kernels of one facet dimension (a module such as ``numpy_backend``).

    The signatures and meanings are those of
    :mod:`~dolfinx_contact_s2s.kernels.numpy_backend`, the reference.

    Attributes:
        FACET_DIM: Topological dimension of the facets the kernels handle.
    """

    FACET_DIM: int

    def facet_coefficients(self, basis: _Array, local_facet: _Rows, coords: _Array) -> _Array:
        """Monomial coefficients of the facets' geometry in their parameter."""
        ...

    def evaluate(
        self, coefficients: _Array, rows: _Rows, xi: _Array, derivatives: int = 1
    ) -> tuple[_Array, ...]:
        """Points and derivatives along the facets."""
        ...

    def facet_basis(self, table: _Array, local_facet: _Rows, xi: _Array) -> _Array:
        """A scalar basis at facet parameters, from its monomial table."""
        ...

    def cell_normals(self, tables: _Array, coords: _Array, reference_normals: _Array) -> _Array:
        r"""Unit normals :math:`J^{-T} \hat n` from the coordinate map's derivatives."""
        ...

    def outward_normals(
        self, coefficients: _Array, orientation: _Array, rows: _Rows, xi: _Array
    ) -> _Array:
        """Unit outward normals at facet parameters."""
        ...

    def project(
        self,
        coefficients: _Array,
        rows: _Rows,
        points: _Array,
        iterations: int = 8,
        tol: float = ...,
    ) -> _Array:
        """Closest-point facet parameters of points (Fig. 15(b))."""
        ...

    def intersect(
        self,
        coefficients: _Array,
        rows: _Rows,
        origins: _Array,
        directions: _Array,
        iterations: int = 8,
        tol: float = ...,
    ) -> _Array:
        """Facet parameters where lines cross the facets (Eq. 38)."""
        ...

    def segment_to_segment(
        self,
        mu: _Array,
        phi_c: _Array,
        phi_t: _Array,
        normals: _Array,
        weights: _Array,
        gaps: _Array,
    ) -> tuple[_Array, _Array, _Array]:
        """The local coupling blocks of Eqs. (40)-(42)."""
        ...

    def clip_segments(
        self,
        c_coefficients: _Array,
        c_orientation: _Array,
        t_coefficients: _Array,
        t_orientation: _Array,
        ic: _Rows,
        it: _Rows,
        radius: float,
        min_length: float,
        round_off: float = ...,
        iterations: int = 8,
        tol: float = ...,
    ) -> tuple[_Array, _Array, npt.NDArray[np.bool_]]:
        """The piece of each candidate pair of facets (Fig. 15(b))."""
        ...

    def bounding_boxes(self, coefficients: _Array, samples: int, pad: float) -> _Array:
        """Axis-aligned boxes of the facets."""
        ...

    def shift(self, coefficients: _Array, offset: _Array) -> _Array:
        """The facets' geometry moved by one offset per facet."""
        ...

    def box_overlaps(
        self,
        a: _Array,
        b: _Array,
        order: npt.NDArray[np.int64],
        start: npt.NDArray[np.int64],
        stop: npt.NDArray[np.int64],
    ) -> tuple[_Rows, _Rows]:
        """The overlapping pairs among a sweep's candidates (``search.box_pairs``)."""
        ...

    def coo_to_csr(
        self,
        num_rows: int,
        rows: npt.NDArray[np.int64],
        cols: npt.NDArray[np.int64],
        values: _Array,
    ) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], _Array]:
        """CSR arrays of COO entries, duplicates summed."""
        ...

    def csr_slots(
        self,
        indptr: npt.NDArray[np.int64],
        indices: npt.NDArray[np.int64],
        rows: npt.NDArray[np.int64],
        cols: npt.NDArray[np.int64],
    ) -> npt.NDArray[np.int64]:
        """Position in ``indices`` of each entry of a CSR structure (sorted columns)."""
        ...


def get_backend(
    name: str = "auto", comm: MPI.Comm = MPI.COMM_WORLD, facet_dim: int = 1
) -> KernelBackend:
    """The kernel backend called ``name`` (collective on ``comm`` unless ``"numpy"``).

    Args:
        name: One of :data:`BACKENDS` or ``"auto"``: the backend named by
            ``$S2S_KERNEL_BACKEND`` if set, else ``"c"`` if it compiles, else
            ``"numpy"`` (with a logged notice).
        comm: Communicator on which the C kernels are compiled (by its rank 0) and
            loaded; every rank of it must call this function.
        facet_dim: Topological dimension of the facets, one of :data:`FACET_DIMS`.

    Returns:
        A module satisfying :class:`KernelBackend`.

    Raises:
        ValueError: For an unknown backend (also one named by the environment).
        NotImplementedError: For a facet dimension without kernels.
        RuntimeError: On every rank, when ``"c"`` is asked for and cannot be compiled.
    """
    if facet_dim not in FACET_DIMS:
        raise NotImplementedError(
            f"no contact kernels for facets of dimension {facet_dim}; implemented: "
            f"{FACET_DIMS} (the edges of 2D cells, the faces of 3D cells)"
        )
    chosen = name
    if name == "auto":
        chosen = os.environ.get(ENV_BACKEND, "").strip().lower() or "auto"
        if chosen not in (*BACKENDS, "auto"):
            raise ValueError(
                f"unknown kernel backend {chosen!r} in ${ENV_BACKEND}; choose from {BACKENDS}"
            )
    faces = facet_dim == face_backend.FACET_DIM
    reference = face_backend if faces else numpy_backend
    if chosen == "numpy":
        return typing.cast(KernelBackend, reference)
    if chosen not in ("c", "auto"):
        raise ValueError(f"unknown kernel backend {name!r}; choose from {BACKENDS} or 'auto'")
    from dolfinx_contact_s2s.kernels import c_backend

    def compiled() -> KernelBackend:
        loaded = c_backend.load(comm)
        if faces:
            from dolfinx_contact_s2s.kernels import face_c_backend

            return typing.cast(KernelBackend, face_c_backend)
        return typing.cast(KernelBackend, loaded)

    if chosen == "c":
        return compiled()
    try:
        return compiled()
    except (ImportError, RuntimeError) as error:
        global _noticed
        if comm.rank == 0 and not _noticed:
            _logger.warning(
                "dolfinx_contact_s2s: using the NumPy contact kernels, 4-5x slower than the "
                "compiled ones, which need CFFI and a C compiler: pip install "
                "dolfinx-contact-s2s[c] (from a checkout: pip install .[c]) (%s)",
                error,
            )
            _noticed = True
        return typing.cast(KernelBackend, reference)

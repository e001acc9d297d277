# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Compiled (C, through CFFI) backend of the contact kernels.

The functions have the signatures of :mod:`dolfinx_contact_s2s.kernels.numpy_backend`
and return new arrays. Straight facets (degree-1 coefficients, or higher coefficients
exactly zero) are projected and intersected in closed form; Newton's method, with the
relative stopping test of the NumPy backend, runs only on curved facets. The C sources
(``_kernels.c``; ``_faces.c``, the face kernels of
:mod:`~dolfinx_contact_s2s.kernels.face_c_backend`) are compiled once, on rank 0 of a
communicator, into a cache directory keyed by a hash of the sources and of the CFFI and
Python versions (:func:`load`); the other ranks load it after a collective status check, as
:func:`dolfinx.jit.mpi_jit_decorator` does for forms.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
import tempfile
import types
import typing
from pathlib import Path

from mpi4py import MPI

import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.kernels.numpy_backend import FACET_DIM, NEWTON_TOL, ROUND_OFF, shift

__all__ = [
    "FACET_DIM",
    "MAX_POLYGON_VERTICES",
    "NEWTON_TOL",
    "ROUND_OFF",
    "bounding_boxes",
    "box_overlaps",
    "cache_dir",
    "cell_normals",
    "clip_polygons",
    "clip_segments",
    "compiled",
    "coo_to_csr",
    "csr_slots",
    "edge_coupling",
    "evaluate",
    "facet_basis",
    "facet_coefficients",
    "intersect",
    "load",
    "outward_normals",
    "project",
    "segment_to_segment",
    "shift",
    "triangulate_polygons",
]

_Array = npt.NDArray[np.float64]

#: The declarations CFFI binds (what Python may call).
_CDEF = Path(__file__).with_name("_kernels.h").read_text()

#: Vertices of the polygons of :func:`clip_polygons`, both together, at most (the C
#: kernel's fixed working arrays: no allocation per pair).
MAX_POLYGON_VERTICES = 32

#: Compiler flags; no contraction into fused multiply-adds, so the results round
#: like the NumPy backend's.
_COMPILE_ARGS = ["-O2", "-g0", "-ffp-contract=off"]

#: The C sources, compiled into one module.
_SOURCES = tuple(Path(__file__).with_name(f) for f in ("_kernels.c", "_faces.c"))

#: The loaded compiled module (``ffi``, ``lib``), once :func:`load` succeeded.
_module: types.ModuleType | None = None
#: Why compiling failed on this process, if it did (root only).
_failure: str | None = None


def cache_dir() -> Path:
    """Directory of the compiled kernels.

    ``$S2S_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/dolfinx_contact_s2s`` (by default
    ``~/.cache/dolfinx_contact_s2s``), the place DOLFINx's JIT cache uses.
    """
    if "S2S_CACHE_DIR" in os.environ:
        return Path(os.environ["S2S_CACHE_DIR"]).expanduser()
    base = os.environ.get("XDG_CACHE_HOME", str(Path.home() / ".cache"))
    return Path(base).expanduser() / "dolfinx_contact_s2s"


def _module_name() -> str:
    """Module name keyed by the C source, the flags and the CFFI and Python versions."""
    import cffi

    key = hashlib.sha256()
    for part in (_source().encode(), _CDEF.encode(), " ".join(_COMPILE_ARGS).encode()):
        key.update(part)
    key.update(f"{cffi.__version__} {sys.version} {sys.platform}".encode())
    return f"_s2s_kernels_{key.hexdigest()[:16]}"


def _source() -> str:
    # The declarations first: a definition that drifts from what CFFI binds is then a
    # compile error ("conflicting types"), not a call with the wrong arguments.
    return "\n".join(["#include <stdint.h>", _CDEF, *(path.read_text() for path in _SOURCES)])


def _library_path(name: str) -> Path:
    import sysconfig

    return cache_dir() / (name + sysconfig.get_config_var("EXT_SUFFIX"))


def _compile(name: str) -> None:
    """Build module ``name`` in a private directory and rename it into the cache."""
    import cffi

    target = _library_path(name)
    if target.exists():
        return
    target.parent.mkdir(parents=True, exist_ok=True)
    ffi = cffi.FFI()
    ffi.cdef(_CDEF)
    ffi.set_source(name, _source(), extra_compile_args=_COMPILE_ARGS)
    with tempfile.TemporaryDirectory(dir=target.parent, prefix=".build-") as tmp:
        built = ffi.compile(tmpdir=tmp, verbose=False)
        # Atomic on one file system: a reader sees no library or a complete one.
        os.replace(built, target)


def _import(name: str) -> types.ModuleType:
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, _library_path(name))
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load the compiled kernels from {_library_path(name)}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[name] = module
    return module


def load(comm: MPI.Comm = MPI.COMM_WORLD) -> types.ModuleType:
    """Compile (on rank 0 of ``comm``, once per cache) and load the C kernels (collective).

    Rank 0 compiles the source into :func:`cache_dir` unless the library is there;
    a reduction of its status then lets every rank load the library, or raise the same
    error on every rank, as :func:`dolfinx.jit.mpi_jit_decorator` does.

    Args:
        comm: Communicator whose ranks all call this function.

    Returns:
        This module, ready to use.

    Raises:
        RuntimeError: On every rank of ``comm``, when CFFI or the C compiler fails.
    """
    global _module, _failure
    status, message = 0, ""
    name = ""
    if comm.rank == 0:
        try:
            if _failure is not None:
                raise RuntimeError(_failure)
            name = _module_name()
            if _module is None:
                _compile(name)
        except Exception as error:  # reported on every rank below
            status, message = 1, f"{type(error).__name__}: {error}"
            _failure = message
    if comm.size > 1:
        status, message, name = comm.bcast((status, message, name), root=0)
    if status:
        raise RuntimeError(f"compiling the C contact kernels failed: {message}")
    if _module is None:
        _module = _import(name)
    return sys.modules[__name__]


def compiled() -> tuple[typing.Any, typing.Any]:
    """The loaded module's ``(ffi, lib)``, for the wrappers of other kernel modules.

    Raises:
        RuntimeError: If :func:`load` has not succeeded on this process.
    """
    return _lib()


def _lib():
    if _module is None:
        raise RuntimeError("the C kernels are not loaded: call c_backend.load(comm) first")
    return _module.ffi, _module.lib


def _f64(a) -> _Array:
    return np.ascontiguousarray(a, dtype=np.float64)


def _i32(a) -> npt.NDArray[np.int32]:
    return np.ascontiguousarray(a, dtype=np.int32)


def _ptr(ffi, a: np.ndarray, ctype: str = "double *"):
    return ffi.cast(ctype, ffi.from_buffer(a)) if a.size else ffi.NULL


def _geometry(coefficients) -> tuple[_Array, int]:
    c = _f64(coefficients)
    if c.ndim != 3 or c.shape[2] != 2:
        raise ValueError(f"the C kernels take 2D facet coefficients (F, p + 1, 2), not {c.shape}")
    return c, c.shape[1]


def facet_coefficients(basis: _Array, local_facet: npt.NDArray[np.int32], coords: _Array) -> _Array:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.facet_coefficients`."""
    ffi, lib = _lib()
    basis, local_facet, coords = _f64(basis), _i32(local_facet), _f64(coords)
    L, M, K = basis.shape
    F, _, gdim = coords.shape
    if local_facet.size and (local_facet.min() < 0 or local_facet.max() >= L):
        raise ValueError("local facet index out of range")
    out = np.empty((F, M, gdim))
    lib.s2s_facet_coefficients(
        _ptr(ffi, basis), M, K, _ptr(ffi, local_facet, "int32_t *"), F,
        _ptr(ffi, coords), gdim, _ptr(ffi, out),
    )  # fmt: skip
    return out


def evaluate(
    coefficients: _Array, rows: npt.NDArray[np.int32], xi: _Array, derivatives: int = 1
) -> tuple[_Array, ...]:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.evaluate`."""
    ffi, lib = _lib()
    c, M = _geometry(coefficients)
    rows, xi = _i32(rows), _f64(xi)
    P = rows.size
    x, dx = np.empty((P, 2)), np.empty((P, 2))
    ddx = np.empty((P, 2)) if derivatives == 2 else None
    lib.s2s_evaluate(
        _ptr(ffi, c), M, _ptr(ffi, rows, "int32_t *"), _ptr(ffi, xi), P,
        _ptr(ffi, x), _ptr(ffi, dx), ffi.NULL if ddx is None else _ptr(ffi, ddx),
    )  # fmt: skip
    return (x, dx) if ddx is None else (x, dx, ddx)


def facet_basis(table: _Array, local_facet: npt.NDArray[np.int32], xi: _Array) -> _Array:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.facet_basis`."""
    ffi, lib = _lib()
    table, local_facet, xi = _f64(table), _i32(local_facet), _f64(xi)
    _, M, K = table.shape
    out = np.empty((xi.size, K))
    lib.s2s_facet_basis(
        _ptr(ffi, table), M, K, _ptr(ffi, local_facet, "int32_t *"), _ptr(ffi, xi), xi.size,
        _ptr(ffi, out),
    )  # fmt: skip
    return out


def cell_normals(tables: _Array, coords: _Array, reference_normals: _Array) -> _Array:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.cell_normals` (2D cells)."""
    ffi, lib = _lib()
    tables, coords, reference_normals = _f64(tables), _f64(coords), _f64(reference_normals)
    P, K, gdim = coords.shape
    if gdim != 2 or tables.shape[0] != 2:
        raise ValueError("the C kernels compute normals of 2D cells only")
    out = np.empty((P, 2))
    lib.s2s_cell_normals(
        _ptr(ffi, tables), _ptr(ffi, coords), P, K, _ptr(ffi, reference_normals), _ptr(ffi, out)
    )
    return out


def outward_normals(
    coefficients: _Array,
    orientation: _Array,
    rows: npt.NDArray[np.int32],
    xi: _Array,
) -> _Array:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.outward_normals`."""
    ffi, lib = _lib()
    c, M = _geometry(coefficients)
    orientation, rows, xi = _f64(orientation), _i32(rows), _f64(xi)
    out = np.empty((rows.size, 2))
    lib.s2s_outward_normals(
        _ptr(ffi, c), M, _ptr(ffi, orientation), _ptr(ffi, rows, "int32_t *"), _ptr(ffi, xi),
        rows.size, _ptr(ffi, out),
    )  # fmt: skip
    return out


def project(
    coefficients: _Array,
    rows: npt.NDArray[np.int32],
    points: _Array,
    iterations: int = 8,
    tol: float = NEWTON_TOL,
) -> _Array:
    r"""See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.project`.

    On a straight facet :math:`x = c_0 + \xi c_1`,
    :math:`\xi = (p - c_0) \cdot c_1 / |c_1|^2` in closed form.
    """
    ffi, lib = _lib()
    c, M = _geometry(coefficients)
    rows, points = _i32(rows), _f64(points)
    out = np.empty(rows.size)
    lib.s2s_project(
        _ptr(ffi, c), M, _ptr(ffi, rows, "int32_t *"), _ptr(ffi, points), rows.size,
        int(iterations), float(tol), _ptr(ffi, out),
    )  # fmt: skip
    return out


def intersect(
    coefficients: _Array,
    rows: npt.NDArray[np.int32],
    origins: _Array,
    directions: _Array,
    iterations: int = 8,
    tol: float = NEWTON_TOL,
) -> _Array:
    r"""See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.intersect`.

    On a straight facet, with :math:`d^\perp = (-d_1, d_0)`,
    :math:`\eta = (o - c_0) \cdot d^\perp / (c_1 \cdot d^\perp)` in closed form (Eq. 38).
    """
    ffi, lib = _lib()
    c, M = _geometry(coefficients)
    rows, origins, directions = _i32(rows), _f64(origins), _f64(directions)
    out = np.empty(rows.size)
    lib.s2s_intersect(
        _ptr(ffi, c), M, _ptr(ffi, rows, "int32_t *"), _ptr(ffi, origins),
        _ptr(ffi, directions), rows.size, int(iterations), float(tol), _ptr(ffi, out),
    )  # fmt: skip
    return out


def segment_to_segment(
    mu: _Array,
    phi_c: _Array,
    phi_t: _Array,
    normals: _Array,
    weights: _Array,
    gaps: _Array,
) -> tuple[_Array, _Array, _Array]:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.segment_to_segment` (Eqs. 40-42)."""
    ffi, lib = _lib()
    mu, phi_c, phi_t = _f64(mu), _f64(phi_c), _f64(phi_t)
    normals, weights, gaps = _f64(normals), _f64(weights), _f64(gaps)
    S, Q, nk = mu.shape
    nc, nt, gdim = phi_c.shape[2], phi_t.shape[2], normals.shape[2]
    b_c = np.empty((S, nk, nc * gdim))
    b_t = np.empty((S, nk, nt * gdim))
    g = np.empty((S, nk))
    lib.s2s_segment_to_segment(
        _ptr(ffi, mu), _ptr(ffi, phi_c), _ptr(ffi, phi_t), _ptr(ffi, normals),
        _ptr(ffi, weights), _ptr(ffi, gaps), S, Q, nk, nc, nt, gdim,
        _ptr(ffi, b_c), _ptr(ffi, b_t), _ptr(ffi, g),
    )  # fmt: skip
    return b_c, b_t, g


def edge_coupling(
    contactor: tuple[_Array, _Array],
    target: _Array,
    groups: tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]],
    xi: _Array,
    weights: _Array,
    tables: tuple,
    square: bool,
    tangent: bool,
    iterations: int = 8,
    tol: float = NEWTON_TOL,
) -> tuple[_Array, ...]:
    r"""The local blocks of Eqs. (40)-(42) on edges in one pass over the points (C only).

    What ``pair._integrate`` composes from :func:`outward_normals`, :func:`intersect`,
    :func:`evaluate`, :func:`facet_basis` and :func:`segment_to_segment`, the NumPy
    reference, with the same operations (the dual multiplier's table combined first).

    Args:
        contactor: The contactor facets' coefficients ``(F, M, 2)`` and orientations.
        target: The target facets' coefficients.
        groups: Contactor and target facet of each group ``(S,)``.
        xi: Contactor facet parameters ``(S, Q)``.
        weights: The weights of Eq. (40) ``(S, Q)``.
        tables: ``((mu_table, flip), (c_table, c_local_facet), (t_table, t_local_facet))``:
            the multiplier's monomial table ``(M, nk)`` and the facets where it is read
            at :math:`1 - \xi`; each basis' tables ``(L, M, n)`` of the facet's own
            functions and the local facet of every facet.
        square: Coverage of :math:`\mu_k^2` instead of :math:`\mu_k`.
        tangent: :math:`T = (N_1, -N_0)` in place of :math:`N`, and no gap.
        iterations: Newton steps of :func:`intersect` on curved facets, at most.
        tol: Its relative stopping test.

    Returns:
        ``(b_c, b_t, gap, signed, coverage)``: ``(S, nk, 2 nc)``, ``(S, nk, 2 nt)`` and
        ``(S, nk)`` each.
    """
    ffi, lib = _lib()
    (cc, Mc), (tc, Mt) = _geometry(contactor[0]), _geometry(target)
    (mu_table, flip), (c_table, lf_c), (t_table, lf_t) = tables
    mu_table, c_table, t_table = _f64(mu_table), _f64(c_table), _f64(t_table)
    gc, gt, xi, weights = _i32(groups[0]), _i32(groups[1]), _f64(xi), _f64(weights)
    # Named: a pointer does not keep a converted temporary alive.
    orientation, flip = _f64(contactor[1]), np.ascontiguousarray(flip, dtype=np.int8)
    lf_c, lf_t = _i32(lf_c), _i32(lf_t)
    (S, Q), nk, nc, nt = xi.shape, mu_table.shape[1], c_table.shape[2], t_table.shape[2]
    if max(Mc, Mt) > 8 or max(nk, nc, nt) > 16:
        raise ValueError("edge_coupling takes facets of degree <= 7 and <= 16 functions")
    out = [np.empty((S, nk, 2 * nc)), np.empty((S, nk, 2 * nt))]
    out += [np.empty((S, nk)) for _ in range(3)]
    p = [_ptr(ffi, a) for a in out]
    lib.s2s_edge_coupling(
        _ptr(ffi, cc), Mc, _ptr(ffi, orientation), _ptr(ffi, tc), Mt,
        _ptr(ffi, gc, "int32_t *"), _ptr(ffi, gt, "int32_t *"), S, Q, _ptr(ffi, xi),
        _ptr(ffi, weights), _ptr(ffi, mu_table), mu_table.shape[0], nk,
        _ptr(ffi, flip, "int8_t *"),
        _ptr(ffi, c_table), c_table.shape[1], nc, _ptr(ffi, lf_c, "int32_t *"),
        _ptr(ffi, t_table), t_table.shape[1], nt, _ptr(ffi, lf_t, "int32_t *"),
        int(tangent), int(square), int(iterations), float(tol), *p,
    )  # fmt: skip
    return tuple(out)


def clip_segments(
    c_coefficients: _Array,
    c_orientation: _Array,
    t_coefficients: _Array,
    t_orientation: _Array,
    ic: npt.NDArray[np.int32],
    it: npt.NDArray[np.int32],
    radius: float,
    min_length: float,
    round_off: float = ROUND_OFF,
    iterations: int = 8,
    tol: float = NEWTON_TOL,
) -> tuple[_Array, _Array, npt.NDArray[np.bool_]]:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.clip_segments` (Fig. 15(b))."""
    ffi, lib = _lib()
    cc, Mc = _geometry(c_coefficients)
    tc, Mt = _geometry(t_coefficients)
    c_orientation, t_orientation = _f64(c_orientation), _f64(t_orientation)
    ic, it = _i32(ic), _i32(it)
    N = ic.size
    lo, hi, keep = np.empty(N), np.empty(N), np.empty(N, dtype=np.int8)
    lib.s2s_clip_segments(
        _ptr(ffi, cc), Mc, _ptr(ffi, c_orientation), _ptr(ffi, tc), Mt,
        _ptr(ffi, t_orientation), _ptr(ffi, ic, "int32_t *"), _ptr(ffi, it, "int32_t *"), N,
        float(radius), float(min_length), float(round_off), int(iterations), float(tol),
        _ptr(ffi, lo), _ptr(ffi, hi), _ptr(ffi, keep, "int8_t *"),
    )  # fmt: skip
    return lo, hi, keep.astype(bool)


def bounding_boxes(coefficients: _Array, samples: int, pad: float) -> _Array:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.bounding_boxes`."""
    ffi, lib = _lib()
    c, M = _geometry(coefficients)
    F = c.shape[0]
    out = np.empty((F, 2, 2))
    lib.s2s_bounding_boxes(_ptr(ffi, c), M, F, int(samples), float(pad), _ptr(ffi, out))
    return out


def box_overlaps(
    a: _Array,
    b: _Array,
    order: npt.NDArray[np.int64],
    start: npt.NDArray[np.int64],
    stop: npt.NDArray[np.int64],
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.box_overlaps`."""
    ffi, lib = _lib()
    a, b = _f64(a), _f64(b)
    order, start, stop = (np.ascontiguousarray(v, dtype=np.int64) for v in (order, start, stop))
    stop = np.maximum(stop, start)
    size = int(np.sum(stop - start))
    ia, ib = np.empty(size, dtype=np.int32), np.empty(size, dtype=np.int32)
    n = lib.s2s_box_overlaps(
        _ptr(ffi, a), a.shape[0], _ptr(ffi, b), a.shape[2], _ptr(ffi, order, "int64_t *"),
        _ptr(ffi, start, "int64_t *"), _ptr(ffi, stop, "int64_t *"),
        _ptr(ffi, ia, "int32_t *"), _ptr(ffi, ib, "int32_t *"),
    )  # fmt: skip
    return ia[:n].copy(), ib[:n].copy()


def coo_to_csr(
    num_rows: int, rows: npt.NDArray[np.int64], cols: npt.NDArray[np.int64], values: _Array
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], _Array]:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.coo_to_csr`."""
    ffi, lib = _lib()
    rows = np.ascontiguousarray(rows, dtype=np.int64)
    cols = np.ascontiguousarray(cols, dtype=np.int64)
    values = _f64(values)
    n = rows.size
    if cols.size != n or values.size != n:
        raise ValueError("rows, cols and values must have the same length")
    indptr = np.empty(num_rows + 1, dtype=np.int64)
    indices = np.empty(n, dtype=np.int64)
    data = np.empty(n)
    nnz = lib.s2s_coo_to_csr(
        num_rows, n, _ptr(ffi, rows, "int64_t *"), _ptr(ffi, cols, "int64_t *"),
        _ptr(ffi, values), _ptr(ffi, indptr, "int64_t *"), _ptr(ffi, indices, "int64_t *"),
        _ptr(ffi, data),
    )  # fmt: skip
    if nnz < 0:
        raise ValueError("row index out of range")
    return indptr, indices[:nnz].copy(), data[:nnz].copy()


def csr_slots(
    indptr: npt.NDArray[np.int64],
    indices: npt.NDArray[np.int64],
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
) -> npt.NDArray[np.int64]:
    """See :func:`~dolfinx_contact_s2s.kernels.numpy_backend.csr_slots`."""
    ffi, lib = _lib()
    arrays = [np.ascontiguousarray(a, dtype=np.int64) for a in (indptr, indices, rows, cols)]
    if rows.size and (arrays[2].min() < 0 or arrays[2].max() >= arrays[0].size - 1):
        raise ValueError("row index out of range")
    slots = np.empty(rows.size, dtype=np.int64)
    p = [_ptr(ffi, a, "int64_t *") for a in (*arrays, slots)]
    if lib.s2s_csr_slots(p[0], p[1], rows.size, p[2], p[3], p[4]) < 0:
        raise ValueError("an entry is not in the CSR structure")
    return slots


def _polygons(polygons, counts, name: str) -> tuple[_Array, npt.NDArray[np.int32]]:
    """Padded polygons ``(P, m, 2)`` and their vertex counts (all ``m`` if None), checked."""
    v = _f64(polygons)
    if v.ndim != 3 or v.shape[2] != 2:
        raise ValueError(f"{name} must be padded polygons (P, m, 2), not {v.shape}")
    n = np.full(v.shape[0], v.shape[1], dtype=np.int32) if counts is None else _i32(counts)
    if n.shape != v.shape[:1] or (n.size and (n.min() < 0 or n.max() > v.shape[1])):
        raise ValueError(f"{name} counts must be ({v.shape[0]},) in [0, {v.shape[1]}]")
    return v, n


def clip_polygons(
    subject: _Array,
    clip: _Array,
    subject_counts: npt.NDArray[np.int32] | None = None,
    clip_counts: npt.NDArray[np.int32] | None = None,
    round_off: float = ROUND_OFF,
) -> tuple[_Array, npt.NDArray[np.int32]]:
    """See :func:`~dolfinx_contact_s2s.kernels.clipping.clip_polygons` (Fig. 15(b)).

    The C kernel repeats :func:`~dolfinx_contact_s2s.kernels.clipping.clip_convex`
    operation by operation (its sums in NumPy's order), so the vertices agree to the
    last bit. At most :data:`MAX_POLYGON_VERTICES` vertices in ``m_s + m_c``.
    """
    ffi, lib = _lib()
    subject, ns = _polygons(subject, subject_counts, "subject")
    clip, nc = _polygons(clip, clip_counts, "clip")
    P, ms, mc = subject.shape[0], subject.shape[1], clip.shape[1]
    if clip.shape[0] != P:
        raise ValueError(f"{P} subject polygons but {clip.shape[0]} clip polygons")
    if ms + mc > MAX_POLYGON_VERTICES:
        raise ValueError(f"at most {MAX_POLYGON_VERTICES} vertices in both polygons, not {ms + mc}")
    out = np.empty((P, ms + mc, 2))
    counts = np.empty(P, dtype=np.int32)
    failed = lib.s2s_clip_polygons(
        _ptr(ffi, subject), ms, _ptr(ffi, ns, "int32_t *"), _ptr(ffi, clip), mc,
        _ptr(ffi, nc, "int32_t *"), P, float(round_off), ms + mc, _ptr(ffi, out),
        _ptr(ffi, counts, "int32_t *"),
    )  # fmt: skip
    if failed:
        raise ValueError(
            f"pair {np.flatnonzero(counts < 0)[0]}: the overlap has more than {ms + mc} "
            f"vertices ({failed} pairs): the polygons are not convex"
        )
    return out, counts


def triangulate_polygons(
    polygons: _Array, counts: npt.NDArray[np.int32] | None = None, round_off: float = ROUND_OFF
) -> tuple[_Array, npt.NDArray[np.int32]]:
    """See :func:`~dolfinx_contact_s2s.kernels.clipping.triangulate_polygons`."""
    ffi, lib = _lib()
    polygons, n = _polygons(polygons, counts, "polygon")
    P, m = polygons.shape[:2]
    if m > 2 * MAX_POLYGON_VERTICES:
        raise ValueError(f"at most {2 * MAX_POLYGON_VERTICES} vertices a polygon, not {m}")
    triangles = np.empty((P * m, 3, 2))
    owner = np.empty(P * m, dtype=np.int32)
    T = lib.s2s_triangulate_polygons(
        _ptr(ffi, polygons), m, _ptr(ffi, n, "int32_t *"), P, float(round_off),
        _ptr(ffi, triangles), _ptr(ffi, owner, "int32_t *"),
    )  # fmt: skip
    return triangles[:T].copy(), owner[:T].copy()

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

_CDEF = """
void s2s_facet_coefficients(const double *basis, int M, int K, const int32_t *local_facet,
                            int F, const double *coords, int gdim, double *out);
void s2s_evaluate(const double *c, int M, const int32_t *rows, const double *xi, int P,
                  double *x, double *dx, double *ddx);
void s2s_facet_basis(const double *table, int M, int K, const int32_t *local_facet,
                     const double *xi, int P, double *out);
void s2s_cell_normals(const double *tables, const double *coords, int P, int K,
                      const double *reference_normals, double *out);
void s2s_outward_normals(const double *c, int M, const double *orientation,
                         const int32_t *rows, const double *xi, int P, double *out);
void s2s_project(const double *c, int M, const int32_t *rows, const double *points, int P,
                 int iterations, double tol, double *xi);
void s2s_intersect(const double *c, int M, const int32_t *rows, const double *origins,
                   const double *directions, int P, int iterations, double tol, double *eta);
void s2s_segment_to_segment(const double *mu, const double *phi_c, const double *phi_t,
                            const double *normals, const double *weights, const double *gaps,
                            int S, int Q, int nk, int nc, int nt, int gdim, double *b_c,
                            double *b_t, double *g);
void s2s_clip_segments(const double *cc, int Mc, const double *c_orientation,
                       const double *tc, int Mt, const double *t_orientation,
                       const int32_t *ic, const int32_t *it, int N, double radius,
                       double min_length, double round_off, int iterations, double tol,
                       double *lo, double *hi, int8_t *keep);
void s2s_bounding_boxes(const double *c, int M, int F, int samples, double pad, double *out);
int64_t s2s_box_overlaps(const double *a, int64_t na, const double *b, int gdim,
                         const int64_t *order, const int64_t *start, const int64_t *stop,
                         int32_t *ia, int32_t *ib);
int64_t s2s_coo_to_csr(int64_t nrows, int64_t n, const int64_t *rows, const int64_t *cols,
                       const double *values, int64_t *indptr, int64_t *indices, double *data);
int64_t s2s_csr_slots(const int64_t *indptr, const int64_t *indices, int64_t n,
                      const int64_t *rows, const int64_t *cols, int64_t *slots);
int s2s_clip_polygons(const double *subject, int ms, const int32_t *subject_counts,
                      const double *clip, int mc, const int32_t *clip_counts, int P,
                      double round_off, int width, double *out, int32_t *counts);
int64_t s2s_triangulate_polygons(const double *polygons, int m, const int32_t *counts, int P,
                                 double round_off, double *triangles, int32_t *owner);
void s2s_face_evaluate(const double *nodes, int K, const int32_t *rows, const double *xi, int P,
                       double *x, double *dx);
void s2s_face_intersect(const double *nodes, int K, const int32_t *rows, const double *origins,
                        const double *directions, int P, int iterations, double tol,
                        double round_off, double *xi, double *t, int8_t *ok);
void s2s_face_coupling(const double *c_nodes, int Kc, const double *c_orientation,
                       const double *t_nodes, int Kt, const int32_t *rows_c,
                       const int32_t *rows_t, const double *xi, const double *weights, int S,
                       int Q, const double *mu_coef, int Mm, int nk, const int32_t *mu_index,
                       const double *c_coef, int Mc, int nc, const int32_t *c_index,
                       const double *t_coef, int Mt, int nt, const int32_t *t_index,
                       int square, int iterations, double tol, double round_off,
                       double zero_below, const double *axis, int which, double *b_c,
                       double *b_t, double *g, double *coverage, int8_t *ok);
void s2s_face_piece_gaps(const double *c_nodes, int Kc, const double *c_orientation,
                         const double *t_nodes, int Kt, const int32_t *rows_c,
                         const int32_t *rows_t, const double *triangles, const double *origin,
                         const double *frame, int S, int iterations, double tol,
                         double round_off, double *gap, int8_t *ok_c, int8_t *ok_t);
void s2s_face_piece_points(const double *nodes, int K, const int32_t *rows,
                           const double *triangles, const double *origin, const double *frame,
                           int S, const double *X, const double *W, int Q, int iterations,
                           double tol, double round_off, double *xi, double *weights,
                           int8_t *ok);
void s2s_face_project(const double *c_nodes, int Kc, const double *c_orientation,
                      const double *t_nodes, int Kt, const double *t_orientation,
                      const int32_t *ic, const int32_t *it, int N, double round_off,
                      double *origin, double *frame, double *c_poly, double *t_poly,
                      int8_t *facing, int8_t *ok_c, int8_t *ok_t);
"""

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
    return "\n".join(path.read_text() for path in _SOURCES)


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

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Batched array kernels of the contact assembly, behind a backend seam.

A backend is a module exposing the same functions with array-only signatures (no
DOLFINx objects): facet geometry (:func:`facet_coefficients`, :func:`evaluate`,
:func:`outward_normals`, :func:`project`, :func:`intersect`), the facet bases
(:func:`facet_basis`), the sub-segment clipping of Fig. 15(b) (:func:`clip_segments`)
and the coupling kernel of Eqs. (40)-(42) (:func:`segment_to_segment`). Arrays are
C-contiguous ``float64`` (``int32`` for indices). Backends:

- ``"numpy"``: the reference (:mod:`~dolfinx_contact_s2s.kernels.numpy_backend`);
- ``"c"``: compiled C through CFFI (:mod:`~dolfinx_contact_s2s.kernels.c_backend`),
  built once on rank 0 and cached;
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
import types

from mpi4py import MPI

from dolfinx_contact_s2s.kernels import numpy_backend

__all__ = ["BACKENDS", "ENV_BACKEND", "get_backend"]

#: Names of the available backends (``"auto"`` picks one of them).
BACKENDS = ("numpy", "c")

#: Environment variable naming the backend that ``"auto"`` picks.
ENV_BACKEND = "S2S_KERNEL_BACKEND"

_logger = logging.getLogger(__name__)
_noticed = False


def get_backend(name: str = "auto", comm: MPI.Comm = MPI.COMM_WORLD) -> types.ModuleType:
    """The kernel backend called ``name`` (collective on ``comm`` unless ``"numpy"``).

    Args:
        name: One of :data:`BACKENDS` or ``"auto"``: the backend named by
            ``$S2S_KERNEL_BACKEND`` if set, else ``"c"`` if it compiles, else
            ``"numpy"`` (with a logged notice).
        comm: Communicator on which the C kernels are compiled (by its rank 0) and
            loaded; every rank of it must call this function.

    Returns:
        A module with the functions of :mod:`dolfinx_contact_s2s.kernels.numpy_backend`.

    Raises:
        ValueError: For an unknown backend (also one named by the environment).
        RuntimeError: On every rank, when ``"c"`` is asked for and cannot be compiled.
    """
    chosen = name
    if name == "auto":
        chosen = os.environ.get(ENV_BACKEND, "").strip().lower() or "auto"
        if chosen not in (*BACKENDS, "auto"):
            raise ValueError(
                f"unknown kernel backend {chosen!r} in ${ENV_BACKEND}; choose from {BACKENDS}"
            )
    if chosen == "numpy":
        return numpy_backend
    if chosen not in ("c", "auto"):
        raise ValueError(f"unknown kernel backend {name!r}; choose from {BACKENDS} or 'auto'")
    from dolfinx_contact_s2s.kernels import c_backend

    if chosen == "c":
        return c_backend.load(comm)
    try:
        return c_backend.load(comm)
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
        return numpy_backend

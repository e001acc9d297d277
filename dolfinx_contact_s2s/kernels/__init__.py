# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Batched array kernels of the contact assembly, behind a backend seam.

A backend is a module exposing the same functions with array-only signatures (no
DOLFINx objects): facet geometry (:func:`facet_coefficients`, :func:`evaluate`,
:func:`outward_normals`, :func:`project`, :func:`intersect`) and the coupling kernel
of Eqs. (40)-(42) (:func:`segment_to_segment`). Arrays are C-contiguous ``float64``
(``int32`` for indices), so a compiled backend can take them as they are. NumPy is
the reference backend::

    backend = get_backend("numpy")
    x, dx = backend.evaluate(coefficients, rows, xi)
"""

from __future__ import annotations

import types

from dolfinx_contact_s2s.kernels import numpy_backend

__all__ = ["BACKENDS", "get_backend"]

#: Names of the available backends.
BACKENDS = ("numpy",)


def get_backend(name: str = "numpy") -> types.ModuleType:
    """The kernel backend called ``name``.

    Args:
        name: One of :data:`BACKENDS`.

    Returns:
        A module with the functions of :mod:`dolfinx_contact_s2s.kernels.numpy_backend`.

    Raises:
        ValueError: For an unknown backend.
    """
    if name == "numpy":
        return numpy_backend
    raise ValueError(f"unknown kernel backend {name!r}; choose from {BACKENDS}")

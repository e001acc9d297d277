# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Hertz contact of two cylinders: the Gmsh scene, the exact solution, the study.

- :mod:`~paper.hertz.scene`: a half cylinder on a block or on a second cylinder;
- :mod:`~paper.hertz.exact`: the plane-strain Hertz solution and the measures read from
  the multiplier (half-width, peak pressure, L2 pressure error);
- :mod:`~paper.hertz.study`: the runs of ``demos/demo_hertz.py`` and their refinement.
"""

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The paper's studies, built on the package's public API.

- :mod:`~dolfinx_contact_s2s.studies.blocks`: the two-block setup they share;
- :mod:`~dolfinx_contact_s2s.studies.patch_test` and
  :mod:`~dolfinx_contact_s2s.studies.patch_matrix`: the contact patch test (section 3.2)
  and the paper's matrix of verdicts (sections 4-5, Figs. 9-10);
- :mod:`~dolfinx_contact_s2s.studies.infsup`: solvability and the inf-sup test on the
  model of Fig. 2 (section 3.1, Tables 1-2, Figs. 8 and 11).

They need petsc4py and are imported explicitly.
"""

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""What a contact discretization can be trusted with, measured on an assembled problem.

- :mod:`~dolfinx_contact_s2s.analysis.dense`: solvability (the rank of :math:`\mathbf B`,
  Eq. 35) and the inf-sup test as the paper states it, dense (Eqs. 22, 26-32);
- :mod:`~dolfinx_contact_s2s.analysis.infsup`: the scalable inf-sup test (one
  :math:`LDL^T` factorization, MUMPS's Schur complement; SLEPc for many multipliers);
- :mod:`~dolfinx_contact_s2s.analysis.roundoff`: the round-off bound of a solve.

They need petsc4py (and slepc4py for the eigensolver) and are imported explicitly.
"""

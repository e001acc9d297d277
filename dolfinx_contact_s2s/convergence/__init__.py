# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Convergence studies that run in CI: errors, rates and wall time against mesh size.

A study runs a user's solve at a sequence of refinement levels, evaluates error
functionals on each solution and records the mesh size :math:`h`, the number of
unknowns, every error and the wall time, split into setup, contact, assembly and
solve. The observed rate between two levels is

.. math:: r_i = \frac{\log(e_i / e_{i+1})}{\log(h_i / h_{i+1})},

and the fitted rate is the least-squares slope of :math:`\log e` against
:math:`\log h` over the last levels. :func:`assert_rate` checks one inside a test::

    table = convergence_study(solve, [8, 16, 32, 64], errors={"L2": l2_error})
    assert_rate(table, "L2", 2.0, tolerance=0.1)

Everything is collective over ``comm``: every process calls the solve, the error
functionals, :func:`convergence_study` and the writers, and every process gets the same
table. Errors at or below :attr:`ConvergenceTable.roundoff` (a patch test passed to
round-off) have no rate: it is NaN, ``null`` in JSON, and :func:`assert_rate` says so.

This module does not need petsc4py; matplotlib is imported only by
:meth:`ConvergenceTable.plot`.
"""

from dolfinx_contact_s2s.convergence.study import assert_rate, convergence_study, richardson
from dolfinx_contact_s2s.convergence.table import (
    ROUNDOFF,
    SECONDS,
    ConvergenceTable,
    Level,
    json_ready,
    on_rank0,
)

__all__ = [
    "ROUNDOFF",
    "SECONDS",
    "ConvergenceTable",
    "Level",
    "assert_rate",
    "convergence_study",
    "json_ready",
    "on_rank0",
    "richardson",
]

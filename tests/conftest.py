# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
import gc

from mpi4py import MPI

import pytest


def pytest_runtest_setup(item):
    if item.get_closest_marker("skip_in_parallel") and MPI.COMM_WORLD.size > 1:
        pytest.skip("runs on one rank only")


@pytest.fixture(autouse=True)
def collective_cleanup():
    """PETSc destructors may be collective: collect garbage on every rank together."""
    yield
    gc.collect()
    MPI.COMM_WORLD.Barrier()

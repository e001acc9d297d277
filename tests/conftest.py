# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
import gc

from mpi4py import MPI

import pytest

from dolfinx_contact_s2s.kernels import get_backend


def pytest_runtest_setup(item):
    if item.get_closest_marker("skip_in_parallel") and MPI.COMM_WORLD.size > 1:
        pytest.skip("runs on one rank only")


@pytest.fixture(autouse=True)
def collective_cleanup():
    """PETSc destructors may be collective: collect garbage on every rank together."""
    yield
    gc.collect()
    MPI.COMM_WORLD.Barrier()


@pytest.fixture
def kernel_backend(request):
    """The kernel backend named by the (indirect) parameter, e.g.
    ``@pytest.mark.parametrize("kernel_backend", BACKENDS, indirect=True)``."""
    return get_backend(request.param)

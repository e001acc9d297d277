# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""``pip install .[c]`` brings CFFI; without it the notice names that extra."""

import logging
import pathlib
import sys

from mpi4py import MPI

import pytest

from dolfinx_contact_s2s import kernels
from dolfinx_contact_s2s.kernels import c_backend, get_backend, numpy_backend

ROOT = pathlib.Path(__file__).parents[1]


def test_pyproject_has_c_extra():
    tomllib = pytest.importorskip("tomllib")
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    extra = project["optional-dependencies"]["c"]
    assert [e.split(">")[0].split("=")[0].strip().lower() for e in extra] == ["cffi"]
    assert project["name"] == "dolfinx-contact-s2s"


def test_readme_installs_the_extra():
    readme = (ROOT / "README.md").read_text()
    assert 'pip install ".[c]"' in readme
    assert 'pip install "dolfinx-contact-s2s[c]"' in readme


@pytest.mark.parametrize("missing", ["cffi", "compiler"])
def test_notice_names_the_extra(missing, monkeypatch, tmp_path, caplog):
    """The C kernels fail as on a user's machine; ``"auto"`` falls back and says how to fix."""
    monkeypatch.delenv(kernels.ENV_BACKEND, raising=False)
    # A fresh process: nothing compiled or loaded yet, no earlier failure, no notice yet.
    monkeypatch.setattr(c_backend, "_module", None)
    monkeypatch.setattr(c_backend, "_failure", None)
    monkeypatch.setattr(kernels, "_noticed", False)
    monkeypatch.setenv("S2S_CACHE_DIR", str(tmp_path))  # nothing cached: compile
    if missing == "cffi":
        monkeypatch.setitem(sys.modules, "cffi", None)  # import cffi raises ImportError
    else:
        pytest.importorskip("cffi")
        monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    with caplog.at_level(logging.WARNING, logger=kernels.__name__):
        assert get_backend("auto") is numpy_backend
    # Every rank meets the collective calls before any rank asserts alone.
    with pytest.raises(RuntimeError, match="compiling the C contact kernels failed"):
        get_backend("c")
    notices = [r.getMessage() for r in caplog.records if r.name == kernels.__name__]
    if MPI.COMM_WORLD.rank != 0:
        assert notices == []  # rank 0 speaks for all
        return
    (notice,) = notices
    assert "\n" not in notice
    assert "using the NumPy contact kernels" in notice
    assert "pip install dolfinx-contact-s2s[c]" in notice
    assert "pip install .[c]" in notice
    assert "C compiler" in notice
    # The cause, from the failure itself.
    cause = notice.split("failed: ", 1)[1]
    assert ("cffi" if missing == "cffi" else "no-such-cc") in cause

"""The environment script takes its Debian archive from the machine's own apt sources.

``scripts/env-run``'s ``host_mirror`` (apt's own index targets) is run here, inside the
Debian root, and compared with the archives this system's sources list names, read
independently; ``S2S_MIRROR`` overrides it. No archive address is written in the
repository's scripts.
"""

import re
import subprocess
from pathlib import Path

from mpi4py import MPI

import pytest

ROOT = Path(__file__).parents[1]


def _sources() -> set[str]:
    """The archive URIs of the apt sources (one-line and deb822 formats)."""
    uris = set()
    files = [Path("/etc/apt/sources.list"), *Path("/etc/apt/sources.list.d").glob("*")]
    for path in files:
        if not path.is_file():
            continue
        text = path.read_text()
        uris |= set(re.findall(r"^\s*deb\s+(?:\[[^\]]*\]\s+)?(\S+)", text, flags=re.M))
        for line in re.findall(r"^URIs:\s*(.+)$", text, flags=re.M):
            uris |= set(line.split())
    return {u.rstrip("/") for u in uris}


@pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="a property of the machine")
def test_mirror_comes_from_the_apt_sources():
    script = (ROOT / "scripts" / "env-run").read_text()
    function = re.search(r"^host_mirror\(\) \{.*?^\}", script, flags=re.S | re.M)
    assert function is not None
    found = subprocess.run(
        ["bash", "-c", function.group(0) + "\nhost_mirror"], capture_output=True, text=True
    ).stdout.strip()
    sources = _sources()
    if not sources:
        pytest.skip("this system has no apt sources")
    assert found in sources
    # The caller's override wins; otherwise the host's archive.
    assert "${S2S_MIRROR:-$(host_mirror)}" in script


def test_no_archive_address_in_the_scripts():
    for path in [ROOT / "Makefile", *sorted((ROOT / "scripts").iterdir()), ROOT / ".ci" / "run"]:
        if path.is_file():
            assert not re.search(r"(https?|ftp)://", path.read_text()), path

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


def _sources(codename: str) -> set[str]:
    """The archive URIs the apt sources give for the suite ``codename`` (both formats)."""
    uris = set()
    files = [Path("/etc/apt/sources.list"), *Path("/etc/apt/sources.list.d").glob("*")]
    for path in files:
        if not path.is_file():
            continue
        text = path.read_text()
        for uri, suite in re.findall(
            r"^\s*deb\s+(?:\[[^\]]*\]\s+)?(\S+)\s+(\S+)", text, flags=re.M
        ):
            if suite == codename:
                uris.add(uri)
        for stanza in re.split(r"\n\s*\n", text):
            found = re.search(r"^URIs:\s*(.+)$", stanza, flags=re.M)
            suites = re.search(r"^Suites:\s*(.+)$", stanza, flags=re.M)
            if found and suites and codename in suites.group(1).split():
                uris |= set(found.group(1).split())
    return {u.rstrip("/") for u in uris}


def _codename() -> str:
    text = Path("/etc/os-release").read_text()
    found = re.search(r"^VERSION_CODENAME=\"?([^\"\n]*)", text, flags=re.M)
    return found.group(1) if found else ""


@pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="a property of the machine")
def test_mirror_comes_from_the_apt_sources():
    script = (ROOT / "scripts" / "env-run").read_text()
    function = re.search(r"^host_mirror\(\) \{.*?^\}", script, flags=re.S | re.M)
    assert function is not None
    found = subprocess.run(
        ["bash", "-c", function.group(0) + "\nhost_mirror"], capture_output=True, text=True
    ).stdout.strip()
    sources = _sources(_codename())
    # The archive of this system's release, or nothing when its sources name none (a
    # Debian root of sid, whose release has no codename of its own): no address printed.
    assert (found in sources) if sources else found == "", "host_mirror disagrees with apt"
    # The caller's override wins; otherwise the host's archive.
    assert "${S2S_MIRROR:-$(host_mirror)}" in script


def test_no_archive_address_in_the_scripts():
    for path in [ROOT / "Makefile", *sorted((ROOT / "scripts").iterdir()), ROOT / ".ci" / "run"]:
        if path.is_file():
            assert not re.search(r"(https?|ftp)://", path.read_text()), path

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The README's examples run as written (each asserts the patch test itself)."""

import re
from pathlib import Path


def test_readme_example():
    readme = (Path(__file__).parents[1] / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    assert blocks, "the README has no Python example"
    # The self-contained examples (the others are fragments of the first).
    for block in (b for b in blocks if "import" in b):
        exec(compile(block, "README.md", "exec"), {})

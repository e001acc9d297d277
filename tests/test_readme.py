# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The README's examples run as written (each asserts the patch test itself)."""

import re
from pathlib import Path

import numpy as np


def test_readme_example():
    readme = (Path(__file__).parents[1] / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    assert blocks, "the README has no Python example"
    # The self-contained examples (the others are fragments of the first).
    for block in (b for b in blocks if "import" in b):
        scope = {}
        exec(compile(block, "README.md", "exec"), scope)
        if "facets" in scope and "mesh" in scope:
            # The model the text describes: 13 and 9 elements along the contact.
            comm = scope["mesh"].comm
            owned = scope["mesh"].topology.index_map(1).size_local
            counts = [
                comm.allreduce(int(np.count_nonzero(scope["facets"].find(tag) < owned)))
                for tag in (10, 20)
            ]
            assert counts == [13, 9]

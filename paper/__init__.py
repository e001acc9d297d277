# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The paper's studies beside the library: scenes, reproductions, reports, benchmarks.

Not installed: ``demos/``, ``bench/`` and ``tests/`` import it from the repository
(``scripts/env-run`` puts the checkout on ``PYTHONPATH``). It uses the library's public
API only.

- :mod:`~paper.scenes`, :mod:`~paper.scenes_multi`: the Gmsh scenes of the studies (two
  blocks; several blocks in one mesh or several);
- :mod:`~paper.blocks`: the two-block setup the studies share;
- :mod:`~paper.patch_test`, :mod:`~paper.patch_matrix`: the contact patch test (section
  3.2) and the paper's matrix of verdicts (sections 4-5, Figs. 9-10);
- :mod:`~paper.infsup`: solvability and the inf-sup test on the model of Fig. 2 (section
  3.1, Tables 1-2, Figs. 8 and 11);
- :mod:`~paper.hertz`: Hertz contact; :mod:`~paper.fig16`: Fig. 16;
- :mod:`~paper.tradeoff`: speed against accuracy; :mod:`~paper.extremes`: numerical
  extremes; :mod:`~paper.fuzz`: random patch tests; :mod:`~paper.large`: large scenes;
- :mod:`~paper.bench`: benchmark records; :mod:`~paper.records`,
  :mod:`~paper.report`: the files of ``results/``.
"""

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Unloading: a shear that must stay locked in stays, one that must vanish vanishes.

The frictional patch test's two blocks (:func:`paper.friction.patch_scene`: width 1,
two heights 0.5 stacked, so that the top is at :math:`H = 1` above the bottom) in the
uniform state of a pressure :math:`p` and a shear :math:`\tau` with the upper block
slipped by :math:`c` on the lower one (plane strain):

.. math:: u_x = \varepsilon_{xx} x + \gamma y + c, \quad u_y = \varepsilon_{yy} y, \quad
    \gamma = \tau / G, \quad G = E / (2 (1 + \nu)),

:math:`c = 0` in the lower block. The top's :math:`u_x` is prescribed, and its shift
:math:`w = u_x(x, H) - \varepsilon_{xx} x = \tau H / G + c` drives the path; the
tractions on the sides and bottom are those of the uniform state each step must reach
(as in the patch tests, :func:`paper.friction.patch_path`). Coulomb's law on this state:
:math:`c` changes from one step to the next only if :math:`|\tau| = \mu p`, in the
direction of :math:`\tau`; else (:math:`|\tau| < \mu p`) it sticks and :math:`c` stays.
With :math:`p = 0.75`, :math:`\mu = 0.3` (:math:`\mu p = 0.225`), :math:`E = 1`,
:math:`\nu = 0.3`, pressed first with :math:`w = 0`:

- **Stick both ways.** :math:`w = \tau_1 H / G` with :math:`\tau_1 = \mu p / 2`: it
  sticks, :math:`c = 0`, :math:`\lambda_t = \tau_1`; then :math:`w = 0`: :math:`\tau =
  0`, :math:`\lambda_t = 0` everywhere (elastic, reversible).
- **Slip, re-stick, slip back.** :math:`w_1 = \mu p H / G + d`, :math:`d = 0.2`: beyond
  the stick limit :math:`\mu p H / G`, all slips, :math:`c = d`, :math:`\lambda_t = \mu
  p`. The top moved back to where it started, :math:`w = 0`: the elastic shear change
  :math:`G w_1 / H = \mu p + G d / H = 0.302` is less than :math:`2 \mu p = 0.45`, so
  the interface sticks, :math:`c = d` stays, and the shear left is :math:`\mu p - G w_1 /
  H = -G d / H = -0.0769` (an elastic, reversible answer would give 0). Then :math:`w =
  -w_1`: the change from the re-stuck state, :math:`G w_1 / H = 0.302`, exceeds
  :math:`\mu p - G d / H` = 0.148 (the room to :math:`-\mu p`), so all slips the other
  way: :math:`\tau = -\mu p`, :math:`c = w + \mu p H / G = -d`.

**Released.** Slipped by :math:`d` as above (:math:`\tau = \mu p`), then a second
problem without the top's condition continues it (``solve(after=...)``), the top loaded
by the shear traction :math:`\mu p / 2` instead: it sticks, and the slip stays,
:math:`c = d`, :math:`\lambda_t = \mu p / 2` (from rest, :math:`c` would be 0).

Every step is checked, to the patch tests' bound :math:`\min(10^{-10}, 100 \epsilon n)`
(:math:`n` unknowns) relative to :math:`p` (for :math:`\lambda`) and the largest
displacement; the sets: all active, all or none sticking.
"""

from mpi4py import MPI

import numpy as np
import pytest

from dolfinx_contact_s2s.friction import FrictionalContactProblem
from paper.friction import (
    MATERIAL,
    G,
    patch_bcs,
    patch_exact,
    patch_loads,
    patch_pair,
    patch_path,
    patch_reference,
    patch_scene,
)

EPS = np.finfo(np.float64).eps
P, MU, D, H = 0.75, 0.3, 0.2, 1.0
LIMIT = MU * P * H / G  # the top's shift at the stick limit

#: Per path, the steps: the top's shift w, and the state it must reach (tau, c, sticks).
PATHS = {
    "stick both ways": [
        (0.0, 0.0, 0.0, True),
        (MU * P / 2 * H / G, MU * P / 2, 0.0, True),
        (0.0, 0.0, 0.0, True),
    ],
    "slip, re-stick, slip back": [
        (0.0, 0.0, 0.0, True),
        (LIMIT + D, MU * P, D, False),
        (0.0, -G * D / H, D, True),
        (-(LIMIT + D), -MU * P, -D, False),
    ],
}


def _owned_max(values):
    return MPI.COMM_WORLD.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def _check(problem, pair, V, part, u, lam_n, lam_t, tau, c, sticks):
    total = pair.Q.dofmap.index_map.size_global
    tol = min(1e-10, 100 * EPS * (V.dofmap.index_map.size_global * 2 + 2 * total))
    step = problem.history.steps[-1]
    assert step.converged
    last = step.iterations[-1]
    assert last.active == (total,) and last.stick == ((total,) if sticks else (0,))
    m = pair.Q.dofmap.index_map.size_local
    assert _owned_max(lam_n.x.array[:m] - P) <= tol * P
    assert _owned_max(lam_t.x.array[:m] - tau) <= tol * P
    reference = patch_reference(part, V, patch_exact(P, tau), c)
    scale = _owned_max(reference.x.array)
    assert _owned_max(u.x.array - reference.x.array) <= tol * scale


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("degree", [1, 2])
def test_unloading(degree, path):
    """Every step of the path reaches its uniform state, continued with restart=False."""
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    L, bcs, state = patch_path(part, V, v)
    pair = patch_pair(part, V, degree)
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=MU, petsc_options_prefix="fr_unload_"
    ) as problem:
        for k, (w, tau, c, sticks) in enumerate(PATHS[path]):
            assert abs(w - (tau * H / G + c)) <= 4 * EPS  # the state's own top shift
            state(P, tau, c)
            (u,), (lam_n,), (lam_t,) = problem.solve([1.0], restart=k == 0)
            _check(problem, pair, V, part, u, lam_n, lam_t, tau, c, sticks)


@pytest.mark.parametrize("degree", [1, 2])
def test_unloading_released(degree):
    """Slipped with the top held, then continued by a problem without that condition."""
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    L, bcs, state = patch_path(part, V, v)
    pair = patch_pair(part, V, degree)
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=MU, petsc_options_prefix="fr_held_"
    ) as held:
        state(P, MU * P, D)
        (u,), (lam_n,), (lam_t,) = held.solve()
        _check(held, pair, V, part, u, lam_n, lam_t, MU * P, D, False)
        L_free = patch_loads(part, v, P, MU * P / 2)
        with FrictionalContactProblem(
            a, L_free, [pair], patch_bcs(part, V), mu=MU, petsc_options_prefix="fr_free_"
        ) as free:
            (u,), (lam_n,), (lam_t,) = free.solve(after=held)
            _check(free, pair, V, part, u, lam_n, lam_t, MU * P / 2, D, True)

        # Another pair object on the same surfaces, or a problem not solved yet: refused.
        def problem(pairs, prefix):
            return FrictionalContactProblem(
                a, L_free, pairs, patch_bcs(part, V), mu=MU, petsc_options_prefix=prefix
            )

        other = patch_pair(part, V, degree)
        with problem([other], "fr_other_") as bad, pytest.raises(ValueError, match="same spaces"):
            bad.solve(after=held)
        with (
            problem([pair], "fr_unsolved_") as unsolved,
            problem([pair], "fr_bad_") as bad,
            pytest.raises(ValueError, match="same spaces and pairs"),
        ):
            bad.solve(after=unsolved)

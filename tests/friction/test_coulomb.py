# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Coulomb friction in 2D (issue [4/6], first increment): patch tests, limits, ranks.

Every scene has an answer known without the code. The frictional patch tests load two
non-matching blocks (one mesh, :func:`paper.scenes_multi.two_blocks_one_mesh`, width 1,
heights :math:`H = 0.5`) into a uniform stress :math:`\sigma_{xx} = 0`,
:math:`\sigma_{yy} = -p`, :math:`\sigma_{xy} = \tau` with boundary conditions consistent
with it (the shear :math:`\pm\tau` on the sides, :math:`-\tau` on the bottom, rollers
there and one pinned corner), so that in plane strain

.. math:: u_x = \varepsilon_{xx} x + \gamma y + c, \quad u_y = \varepsilon_{yy} y, \quad
    \varepsilon_{xx} = \nu (1 + \nu) p / E, \quad
    \varepsilon_{yy} = -(1 - \nu^2) p / E, \quad \gamma = \tau / G,

with :math:`c = 0` in the lower block. Stick: a shear :math:`\tau < \mu p` on the top
gives :math:`c = 0` in both, :math:`\lambda_n = p`, :math:`\lambda_t = \tau`. Slip: the
top moved by :math:`d` beyond the stick limit gives :math:`c = d` in the upper block,
:math:`\tau = \mu p\, \mathrm{sign}(d)`, and :math:`\lambda_t = \mu p\, \mathrm{sign}(d)`
(:math:`\lambda_t` is the shear the contactor, the upper block, exerts on the lower one
along its tangent :math:`\mathbf T = (1, 0)`).
"""

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import ufl
from partition_keys import gather, keys, match

from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.unilateral import ContactConvergenceError, UnilateralContactProblem
from paper.friction import (
    MATERIAL,
    patch_bcs,
    patch_exact,
    patch_loads,
    patch_pair,
    patch_path,
    patch_reference,
    patch_scene,
)

EPS = np.finfo(np.float64).eps
BOUND = 1e-10


def _owned_max(values):
    return MPI.COMM_WORLD.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def _tolerance(V, pair):
    n = V.dofmap.index_map.size_global * 2 + 2 * pair.Q.dofmap.index_map.size_global
    return min(BOUND, 100 * EPS * n)


def _check_uniform(problem, pair, V, u, lam_n, lam_t, p, tau_t, reference):
    tol = _tolerance(V, pair)
    n = pair.Q.dofmap.index_map.size_local
    step = problem.history.steps[-1]
    assert step.converged
    assert _owned_max(lam_n.x.array[:n] - p) <= tol * p
    assert _owned_max(lam_t.x.array[:n] - tau_t) <= tol * abs(tau_t)
    assert _owned_max(u.x.array - reference.x.array) <= tol * _owned_max(reference.x.array)
    return step.iterations[-1], pair.Q.dofmap.index_map.size_global


#: Coulomb (mu = 0.5 for stick, 0.3 for slip) or Tresca (the slip bound g = 0.25 and 0.3).
LAWS = {"coulomb": {}, "tresca": {"slip_bound": 0.25}}


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("degree", [1, 2])
def test_patch_stick(degree, law):
    """tau < mu p (< g): every multiplier sticks, lambda_t = tau, the uniform state."""
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    p, tau, mu = 0.75, 0.2, 0.5
    pair = patch_pair(part, V, degree)
    L = patch_loads(part, v, p, tau)
    with FrictionalContactProblem(
        a, L, [pair], patch_bcs(part, V), mu=mu, petsc_options_prefix="fr_st_", **LAWS[law]
    ) as problem:
        (u,), (lam_n,), (lam_t,) = problem.solve()
        reference = patch_reference(part, V, patch_exact(p, tau), 0.0)
        last, total = _check_uniform(problem, pair, V, u, lam_n, lam_t, p, tau, reference)
        assert last.active == (total,) and last.stick == (total,)


@pytest.mark.parametrize("law", [("coulomb", {}), ("tresca", {"slip_bound": 0.3})])
@pytest.mark.parametrize("direction", [1.0, -1.0])
@pytest.mark.parametrize("degree", [1, 2])
def test_patch_slip(degree, direction, law):
    """The top moved by d beyond the stick limit: all slip, lambda_t = mu p (g) sign(d)."""
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    p, mu, d = 0.75, 0.3, 0.2 * direction
    tau = law[1].get("slip_bound", mu * p) * direction
    exact = patch_exact(p, tau)
    top = lambda x: exact(x)[0] + d  # noqa: E731
    pair = patch_pair(part, V, degree)
    L = patch_loads(part, v, p, tau, top_shear=False)
    with FrictionalContactProblem(
        a, L, [pair], patch_bcs(part, V, top), mu=mu, petsc_options_prefix="fr_sl_", **law[1]
    ) as problem:
        (u,), (lam_n,), (lam_t,) = problem.solve()
        last, total = _check_uniform(
            problem, pair, V, u, lam_n, lam_t, p, tau, patch_reference(part, V, exact, d)
        )
        assert last.active == (total,) and last.stick == (0,)


def _uneven(part, v, p0=0.2, tau0=0.15):
    """A pressure and a shear that vary along the top."""
    x = ufl.SpatialCoordinate(part.mesh)
    ds = ufl.Measure("ds", domain=part.mesh, subdomain_data=part.facet_tags)
    return (-(p0 + x[0]) * v[1] + tau0 * (1.5 - x[0]) * v[0]) * ds(23)


def test_mu_zero_is_frictionless():
    """mu = 0: the frictionless answer of UnilateralContactProblem, lambda_t = 0."""
    part, V = patch_scene(2)
    a, _, v = MATERIAL.forms(V)
    top = lambda x: 0.05 * x[0]  # noqa: E731
    bcs = patch_bcs(part, V, top)
    L = _uneven(part, v)
    with UnilateralContactProblem(
        a, L, [patch_pair(part, V, 2)], bcs, petsc_options_prefix="fr_0u_"
    ) as ref:
        (u_ref,), (lam_ref,) = ref.solve()
        u_ref, lam_ref = u_ref.x.array.copy(), lam_ref.x.array.copy()
    pair = patch_pair(part, V, 2)
    with FrictionalContactProblem(a, L, [pair], bcs, mu=0.0, petsc_options_prefix="fr_0_") as pb:
        (u,), (lam_n,), (lam_t,) = pb.solve()
        tol = _tolerance(V, pair)
        assert _owned_max(lam_t.x.array) == 0.0
        assert _owned_max(lam_n.x.array - lam_ref) <= tol * _owned_max(lam_ref)
        assert _owned_max(u.x.array - u_ref) <= tol * _owned_max(u_ref)


@pytest.mark.parametrize("degree", [1, 2])
def test_large_mu_is_tied(degree):
    """mu = 1e6: all stick, the answer of the glued saddle point solved densely.

    The reference: :math:`K U + B_t^T \\lambda_t - B_n^T \\lambda_n = F`,
    :math:`B_n U = -G`, :math:`B_t U = 0`, from the assembled blocks, Dirichlet columns
    removed, gathered and solved with NumPy.
    """
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    bcs, L = patch_bcs(part, V), _uneven(part, v, 1.0, 0.1)
    pair = patch_pair(part, V, degree)
    with FrictionalContactProblem(a, L, [pair], bcs, mu=1e6, petsc_options_prefix="fr_big_") as pb:
        (u,), (lam_n,), (lam_t,) = pb.solve()
        total = pair.Q.dofmap.index_map.size_global
        assert pb.history.steps[-1].iterations[-1].stick == (total,)
        got = [
            np.concatenate(MPI.COMM_WORLD.allgather(f.x.petsc_vec.array_r))
            for f in (u, lam_n, lam_t)
        ]
    K = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(a), bcs=bcs)
    K.assemble()
    F = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(L))
    F.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    dolfinx.fem.petsc.set_bc(F, bcs)  # zero Dirichlet values: no lifting
    ops = [assemble_coupling(pair), assemble_coupling(pair, tangential=True)]
    Kd, (Bn, Bt) = gather_dense(K), (gather_dense(op.blocks[0][1]) for op in ops)
    f, Gn = (np.concatenate(MPI.COMM_WORLD.allgather(w.array_r)) for w in (F, ops[0].G))
    for obj in (K, F, *ops):
        obj.destroy()
    mask = np.ones(Kd.shape[0])
    for bc in bcs:
        marked = dolfinx.fem.Function(V)
        marked.x.array[bc.dof_indices()[0]] = 1.0
        mask -= np.concatenate(MPI.COMM_WORLD.allgather(marked.x.petsc_vec.array_r))
    Bn, Bt = Bn * mask, Bt * mask
    n, m = Kd.shape[0], Bn.shape[0]
    A = np.block(
        [[Kd, -Bn.T, Bt.T], [-Bn, np.zeros((m, m)), np.zeros((m, m))], [Bt, np.zeros((m, 2 * m))]]
    )
    x = np.linalg.solve(A, np.concatenate([f, -Gn, np.zeros(m)]))
    tol = _tolerance(V, pair) * 10
    for value, ref in zip(got, (x[:n], x[n : n + m], x[n + m :]), strict=True):
        assert np.max(np.abs(value - ref)) <= tol * np.max(np.abs(ref))


def _solve_uneven(comm, degree, mu, tau0, loads, prefix):
    """The blocks (13 and 9 elements along the contact) under the uneven load."""
    part, V = patch_scene(degree, comm, (13, 9))
    a, _, v = MATERIAL.forms(V)
    pair = patch_pair(part, V, degree)
    L = _uneven(part, v, 1.0, tau0)
    with FrictionalContactProblem(
        a, L, [pair], patch_bcs(part, V), mu=mu, petsc_options_prefix=prefix
    ) as problem:
        (u,), (lam_n,), (lam_t,) = problem.solve(loads)
        n = pair.Q.dofmap.index_map.size_local
        values = [f.x.array[:n].copy() for f in (lam_n, lam_t, problem.stick[0], problem.active[0])]
        sets = [[(it.active, it.stick) for it in s.iterations] for s in problem.history.steps]
        return part, V, pair, u, values, sets


@pytest.mark.parametrize("degree", [1, 2])
def test_coulomb_law(degree):
    """Partial slip: the converged multipliers obey Coulomb's law node by node.

    The weighted slip :math:`\\tilde s = B_t U` (one load step from rest) recomputed
    from the tangential coupling: :math:`|\\lambda_t| \\le \\mu \\lambda_n`,
    :math:`\\tilde s = 0` where a node sticks, :math:`\\lambda_t = \\mu \\lambda_n
    \\mathrm{sign}(\\tilde s)` where it slips, :math:`\\lambda = 0` off contact.
    """
    mu = 0.3
    _, V, pair, u, (lam_n, lam_t, stick, active), sets = _solve_uneven(
        MPI.COMM_WORLD, degree, mu, 0.4, [1.0], "fr_law_"
    )
    total = MPI.COMM_WORLD.allreduce(stick.size)
    assert 0 < sets[-1][-1][1][0] < sets[-1][-1][0][0] < total  # some stick, slip and open
    op = assemble_coupling(pair, tangential=True)
    s = op.G.duplicate()
    op.blocks[0][1].mult(u.x.petsc_vec, s)
    slip, tol = s.array_r.copy(), _tolerance(V, pair)
    for obj in (s, op):
        obj.destroy()
    scale = _owned_max(lam_n)
    stick, active = stick > 0.5, active > 0.5
    assert _owned_max(np.maximum(np.abs(lam_t) - mu * lam_n, 0.0)) <= tol * scale
    assert _owned_max(slip[stick]) <= tol * _owned_max(slip)
    sliding = active & ~stick
    assert np.all(np.abs(slip[sliding]) > 1e-6 * _owned_max(slip))
    expected = mu * lam_n[sliding] * np.sign(slip[sliding])
    assert _owned_max(lam_t[sliding] - expected) <= tol * scale
    assert _owned_max(lam_n[~active]) == 0.0 and _owned_max(lam_t[~active]) == 0.0


def test_ranks_agree():
    """Two load steps on all ranks and on each rank alone: the same sets and values."""
    world = _solve_uneven(MPI.COMM_WORLD, 2, 0.3, 0.4, [0.5, 1.0], "fr_world_")
    alone = _solve_uneven(MPI.COMM_SELF, 2, 0.3, 0.4, [0.5, 1.0], "fr_self_")
    assert world[5] == alone[5]
    Q_world, Q_alone = world[2].Q, alone[2].Q
    perm = match(keys(Q_world, None), keys(Q_alone, None))
    for w, s in zip(world[4], alone[4], strict=True):
        w = gather(MPI.COMM_WORLD, w)
        assert np.max(np.abs(w - s[perm])) <= BOUND * max(np.max(np.abs(s)), 1.0)


@pytest.mark.parametrize("key", ["mu", "slip_bound"])
@pytest.mark.parametrize("value", [-0.1, np.nan, np.inf, "0.3"])
def test_bad_mu(key, value):
    """A friction coefficient or slip bound negative, NaN, infinite or no number: ValueError."""
    part, V = patch_scene(1)
    a, _, v = MATERIAL.forms(V)
    given = {"mu": value} if key == "mu" else {"mu": 0.3, "slip_bound": value}
    with pytest.raises(ValueError, match=r"friction coefficient mu|slip bound"):
        FrictionalContactProblem(
            a,
            patch_loads(part, v, 0.75, 0.2),
            [patch_pair(part, V, 1)],
            patch_bcs(part, V),
            **given,
            petsc_options_prefix="fr_bad_",
        )


def test_not_converged_raises_with_sets():
    """Shear above mu times the normal load: no equilibrium; the body named, the sets kept."""
    with pytest.raises(ContactConvergenceError, match="nothing else holds it") as error:
        _solve_uneven(MPI.COMM_WORLD, 1, 0.2, 0.4, [1.0], "fr_fail_")
    assert not error.value.history.steps[-1].converged


@pytest.mark.parametrize("tau", [0.2, 0.25])
@pytest.mark.parametrize("degree", [1, 2])
def test_friction_cannot_hold(degree, tau):
    r"""A body held tangentially by friction alone: it sticks, or the error names it.

    The patch test's blocks with no tangential condition on the upper one, pressed by
    :math:`p = 0.75` and sheared by :math:`\tau` on its top (and the uniform state's
    shear on the sides), :math:`\mu = 0.3`, :math:`\mu p = 0.225`. Below the limit,
    friction holds it: every multiplier sticks, :math:`\lambda_t = \tau`, the uniform
    state. Above it nothing can: no equilibrium exists, and the solve names the upper
    block (body 1, the contactor) on every rank instead of running to ``max_iterations``.
    """
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    p, mu = 0.75, 0.3
    pair = patch_pair(part, V, degree)
    L = patch_loads(part, v, p, tau)
    with FrictionalContactProblem(
        a, L, [pair], patch_bcs(part, V), mu=mu, petsc_options_prefix="fr_hold_"
    ) as problem:
        if tau > mu * p:
            message = (
                r"body 1 of space 0 \(nodes in \[0, 1\] x \[0.5, 1\]\) \(the contactor of "
                r"pair 0\) slips on every active multiplier and nothing else holds it "
                r"tangentially \(translation along \(1, 0\) is free\): the tangential load on "
                r"it exceeds mu = 0.3 times its normal load"
            )
            with pytest.raises(ContactConvergenceError, match=message):
                problem.solve()
            return
        (u,), (lam_n,), (lam_t,) = problem.solve()
        reference = patch_reference(part, V, patch_exact(p, tau), 0.0)
        last, total = _check_uniform(problem, pair, V, u, lam_n, lam_t, p, tau, reference)
        assert last.active == (total,) and last.stick == (total,)


def test_first_active_set_is_a_guess():
    """``solve(active=...)`` from rest: a first guess only, the same answer; checked input."""
    part, V = patch_scene(1)
    a, _, v = MATERIAL.forms(V)
    pair = patch_pair(part, V, 1)
    L = patch_loads(part, v, 0.75, 0.2)
    with FrictionalContactProblem(
        a, L, [pair], patch_bcs(part, V), mu=0.5, petsc_options_prefix="fr_first_"
    ) as problem:
        problem.solve()
        lam = [f.x.array.copy() for f in (*problem.multipliers, *problem.tangential)]
        problem.solve(active=[lambda x: x[0] < 0.5])
        assert len(problem.history.steps[0].iterations) > 1  # the guess was wrong
        new = [f.x.array for f in (*problem.multipliers, *problem.tangential)]
        error = max(np.max(np.abs(n - o), initial=0.0) for n, o in zip(new, lam, strict=True))
        scale = max(np.max(np.abs(o), initial=0.0) for o in lam)
        error, scale = (MPI.COMM_WORLD.allreduce(v, op=MPI.MAX) for v in (error, scale))
        assert error <= 1e-12 * scale
        for bad, match in (
            ({"active": [None, None]}, "one entry per pair"),
            ({"active": [np.ones(10**6, dtype=bool)]}, "owned dofs"),
            ({"active": [None], "restart": False}, "from rest"),
        ):
            with pytest.raises(ValueError, match=match):
                problem.solve(**bad)


@pytest.mark.parametrize("degree", [1, 2])
def test_contact_opens_and_frees_a_body(degree):
    """The upper block pulled off (a tension on its top), held by contact alone.

    Without the check the next solve is singular: a direct solver returns arbitrary
    displacements and the sets cycle until ``max_iterations``. The error names the
    upper block's three free rigid motions at the first solve, on every rank, like the
    frictionless problem's.
    """
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    pair = patch_pair(part, V, degree)
    L = patch_loads(part, v, -0.75, 0.0)
    with FrictionalContactProblem(
        a, L, [pair], patch_bcs(part, V), mu=0.5, petsc_options_prefix="fr_open_"
    ) as problem:
        with pytest.raises(ContactConvergenceError, match="contact open") as error:
            problem.solve()
    text = str(error.value)
    assert text.startswith("solve 1 at load 1")
    for motion in ("translation along (1, 0)", "translation along (0, 1)", "rotation about"):
        assert f"body 1 of space 0 (nodes in [0, 1] x [0.5, 1]) can move freely: {motion}" in text


@pytest.mark.parametrize("degree", [1, 2])
def test_load_order(degree):
    """Press then slide, or slide lightly pressed then press: two answers, each exact.

    Pressed by p, then the top moved by d beyond the stick limit: the slip patch test,
    lambda_t = mu p. Moved by d under a light pressure p1 (sliding, lambda_t = mu p1),
    then pressed to p with the top held: nothing slips, the shear mu p1 stays locked in
    (the uniform state of pressure p and shear mu p1), lambda_t = mu p1.
    """
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    p, p1, mu, d = 0.75, 0.2, 0.3, 0.2
    L, bcs, state = patch_path(part, V, v)
    pair = patch_pair(part, V, degree)

    for order, path, tau_end in (
        ("press, slide", [(p, 0.0, 0.0), (p, mu * p, d)], mu * p),
        ("slide, press", [(p1, mu * p1, d), (p, mu * p1, d)], mu * p1),
    ):
        with FrictionalContactProblem(
            a, L, [pair], bcs, mu=mu, petsc_options_prefix="fr_order_"
        ) as problem:
            for k, (p_, tau, c) in enumerate(path):
                state(p_, tau, c)
                (u,), (lam_n,), (lam_t,) = problem.solve([1.0], restart=k == 0)
            reference = patch_reference(part, V, patch_exact(p, tau_end), d)
            last, total = _check_uniform(problem, pair, V, u, lam_n, lam_t, p, tau_end, reference)
            assert last.stick == ((0,) if order == "press, slide" else (total,)), order

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Regularized (penalty) Coulomb friction: exact patch tests, its error, input, ranks.

The frictional patch tests of ``tests/friction/test_coulomb.py`` (two non-matching
blocks in the uniform state :math:`\sigma_{yy} = -p`, :math:`\sigma_{xy} = \tau`): the
penalty of a uniform penetration and slip on a uniform mesh is uniform, so the tractions
are the exact ones node by node, :math:`\lambda_n = p` and :math:`\lambda_t = \tau`
(stick) or :math:`\lambda_t = \mu \lambda_n = \mu p` (slip: the return mapping is exact),
and the displacement is the uniform state's with the upper block moved rigidly (by the
penetration :math:`p/\varepsilon` and in stick the elastic slip). On a partial-slip
scene the error against :class:`~dolfinx_contact_s2s.friction.FrictionalContactProblem`
falls like :math:`1/\kappa`: the slope is measured, not a tolerance.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl
from partition_keys import gather, keys, match

import paper.friction3d
from dolfinx_contact_s2s.friction import FrictionalContactProblem, RegularizedFrictionProblem
from paper.friction import (
    MATERIAL,
    patch_bcs,
    patch_exact,
    patch_loads,
    patch_pair,
    patch_reference,
    patch_scene,
)

COMM = MPI.COMM_WORLD
#: Relative bound of the exact cases (the patch tests' conditioning bound, issue 12).
BOUND = 1e-10


def _max(values, comm=COMM):
    return comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)


def _rigid_offset(part, V, u, reference):
    """Largest u - reference on the lower block, largest change of it on the upper one."""
    diff = (u.x.array - reference.x.array).reshape(-1, 2)
    lower, upper = (
        np.concatenate(COMM.allgather(diff[np.unique(V.dofmap.list[part.cell_tags.find(tag)])]))
        for tag in (1, 2)
    )
    return (np.max(np.abs(lower)), np.max(np.ptp(upper, axis=0))), _max(reference.x.array)


@pytest.mark.parametrize("degree", [1, 2])
def test_patch_stick(degree):
    """tau < mu p: every node sticks, lambda_n = p and lambda_t = tau node by node."""
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    p, tau, mu = 0.75, 0.2, 0.5
    pair = patch_pair(part, V, degree)
    L, bcs = patch_loads(part, v, p, tau), patch_bcs(part, V)
    with RegularizedFrictionProblem(a, L, [pair], bcs, mu=mu, petsc_options_prefix="rf_st_") as pb:
        (u,), (lam_n,), (lam_t,) = pb.solve()
        n, total = pair.Q.dofmap.index_map.size_local, pair.Q.dofmap.index_map.size_global
        assert _max(lam_n.x.array[:n] - p) <= BOUND * p
        assert _max(lam_t.x.array[:n] - tau) <= BOUND * tau
        last = pb.history.steps[-1].iterations[-1]
        assert last.active == (total,) and last.stick == (total,)
        (lower, upper), size = _rigid_offset(
            part, V, u, patch_reference(part, V, patch_exact(p, tau), 0.0)
        )
        assert max(lower, upper) <= BOUND * size


@pytest.mark.parametrize("direction", [1.0, -1.0])
@pytest.mark.parametrize("degree", [1, 2])
def test_patch_slip(degree, direction):
    """The top moved beyond the stick limit: all slip, lambda_t = mu lambda_n = mu p sign(d)."""
    part, V = patch_scene(degree)
    a, _, v = MATERIAL.forms(V)
    p, mu, d = 0.75, 0.3, 0.2 * direction
    exact = patch_exact(p, mu * p * direction)
    pair = patch_pair(part, V, degree)
    bcs = patch_bcs(part, V, lambda x: exact(x)[0] + d)
    L = patch_loads(part, v, p, mu * p * direction, top_shear=False)
    with RegularizedFrictionProblem(a, L, [pair], bcs, mu=mu, petsc_options_prefix="rf_sl_") as pb:
        (u,), (lam_n,), (lam_t,) = pb.solve()
        n, total = pair.Q.dofmap.index_map.size_local, pair.Q.dofmap.index_map.size_global
        ln, lt = lam_n.x.array[:n], lam_t.x.array[:n]
        assert _max(lt - mu * direction * ln) <= 1e-14 * mu * p  # the return mapping
        assert _max(ln - p) <= BOUND * p
        assert _max(lt - mu * p * direction) <= BOUND * mu * p
        last = pb.history.steps[-1].iterations[-1]
        assert last.active == (total,) and last.stick == (0,)
        (lower, upper), size = _rigid_offset(part, V, u, patch_reference(part, V, exact, d))
        assert max(lower, upper) <= BOUND * size


@pytest.mark.parametrize("case", ["stick", "slip"])
def test_patch_3d(case, monkeypatch):
    """3D (tetrahedra on hexahedra, P1): the patch tests' tractions, on Coulomb's disk.

    :func:`paper.friction3d.patch` with this solver in place of the Lagrange one; its
    displacement error measures the rigid motion of the upper block, not checked.
    """
    monkeypatch.setattr(paper.friction3d, "FrictionalContactProblem", RegularizedFrictionProblem)
    record = paper.friction3d.patch(case, ("tet", "hex"), 1)
    assert record["converged"] and record["active"] == record["multipliers"]
    assert record["stick"] == (record["multipliers"] if case == "stick" else 0)
    assert max(record["lambda_n_error"], record["lambda_t_error"]) <= BOUND


def _uneven(comm, degree):
    """Partial slip: the blocks (13/9 elements) under a pressure and shear growing along x."""
    part, V = patch_scene(degree, comm, (13, 9))
    a, _, v = MATERIAL.forms(V)
    x = ufl.SpatialCoordinate(part.mesh)
    ds = ufl.Measure("ds", domain=part.mesh, subdomain_data=part.facet_tags)
    L = (-(1.0 + x[0]) * v[1] + 0.4 * (1.5 - x[0]) * v[0]) * ds(23)
    return (a, L, [patch_pair(part, V, degree)], patch_bcs(part, V))


def _solve(scene, cls, prefix, **options):
    """The scene's solution in two load steps: u, (lambda_n, lambda_t, stick, active), sets."""
    pair = scene[2][0]
    with cls(*scene, mu=0.3, petsc_options_prefix=prefix, **options) as pb:
        (u,), (lam_n,), (lam_t,) = pb.solve([0.5, 1.0])
        n = pair.Q.dofmap.index_map.size_local
        values = [f.x.array[:n].copy() for f in (lam_n, lam_t, pb.stick[0], pb.active[0])]
        last = pb.history.steps[-1].iterations[-1]
        return u.x.array.copy(), values, (last.active, last.stick)


@pytest.mark.parametrize("degree", [1, 2])
def test_error_falls_like_one_over_penalty(degree):
    """Against the Lagrange solution (two load steps): u, lambda_n, lambda_t errors ~ 1/kappa.

    The slope of the log-log fit over kappa = 1e2, 1e3, 1e4 is within [-1.2, -0.8] for each,
    and the regularized sets are the Lagrange ones (partial slip: some stick, some slip,
    some open).
    """
    scene = _uneven(COMM, degree)
    u_ref, ref, sets = _solve(scene, FrictionalContactProblem, "rf_lag_")
    total = scene[2][0].Q.dofmap.index_map.size_global
    assert 0 < sets[1][0] < sets[0][0] < total
    penalties, errors = [1e2, 1e3, 1e4], []
    for kappa in penalties:
        u, values, pen_sets = _solve(scene, RegularizedFrictionProblem, "rf_pen_", penalty=kappa)
        assert pen_sets == sets
        pairs = [(u, u_ref), (values[0], ref[0]), (values[1], ref[1])]
        errors.append([_max(got - want) / _max(want) for got, want in pairs])
    slopes = np.polyfit(np.log(penalties), np.log(np.array(errors)), 1)[0]
    assert np.all((-1.2 <= slopes) & (slopes <= -0.8)), slopes


def test_load_path():
    """Pressed by p1, slid to mu p1, then pressed to p with the top held: the shear locks.

    The regularized history: the shear mu p1 stays (the nodes stick again), lambda_t = mu
    p1 exactly; slid after the pressure p instead, lambda_t = mu p (as the Lagrange solver).
    """
    part, V = patch_scene(1)
    a, _, v = MATERIAL.forms(V)
    p, p1, mu, d = 0.75, 0.2, 0.3, 0.2
    pressure, shear = (dolfinx.fem.Constant(part.mesh, 0.0) for _ in range(2))
    ds = ufl.Measure("ds", domain=part.mesh, subdomain_data=part.facet_tags)
    L = -pressure * v[1] * ds(23) - shear * v[0] * ds(1)
    L += shear * v[1] * (ds(2) + ds(22)) - shear * v[1] * (ds(4) + ds(24))
    Vx, _ = V.sub(0).collapse()
    top = dolfinx.fem.Function(Vx)
    dofs = dolfinx.fem.locate_dofs_topological((V.sub(0), Vx), 1, part.facet_tags.find(23))
    bcs = [*patch_bcs(part, V), dolfinx.fem.dirichletbc(top, dofs, V.sub(0))]
    pair = patch_pair(part, V, 1)
    n = pair.Q.dofmap.index_map.size_local
    for path, expected in (
        ([(p, 0.0, 0.0), (p, mu * p, d)], mu * p),
        ([(p1, mu * p1, d), (p, mu * p1, d)], mu * p1),
    ):
        with RegularizedFrictionProblem(
            a, L, [pair], bcs, mu=mu, petsc_options_prefix="rf_path_"
        ) as problem:
            for k, (pk, tau, c) in enumerate(path):
                pressure.value, shear.value = pk, tau
                top.interpolate(lambda x, pk=pk, tau=tau, c=c: patch_exact(pk, tau)(x)[0] + c)
                _, (lam_n,), (lam_t,) = problem.solve([1.0], restart=k == 0)
            assert _max(lam_n.x.array[:n] - p) <= BOUND * p
            assert _max(lam_t.x.array[:n] - expected) <= BOUND * expected


@pytest.mark.parametrize(
    "given",
    [{"penalty": -1.0}, {"penalty": 0.0}, {"penalty": np.nan}, {"penalty": np.inf},
     {"penalty": "100"}, {"mu": -0.1}, {"mu": np.nan}, {"mu": np.inf}],
)  # fmt: skip
def test_bad_input(given):
    """A penalty factor or friction coefficient negative, NaN, infinite or no number."""
    part, V = patch_scene(1)
    a, _, v = MATERIAL.forms(V)
    options = {"mu": 0.3, **given}
    with pytest.raises(ValueError, match=r"penalty|friction coefficient mu"):
        RegularizedFrictionProblem(
            a,
            patch_loads(part, v, 0.75, 0.2),
            [patch_pair(part, V, 1)],
            patch_bcs(part, V),
            petsc_options_prefix="rf_bad_",
            **options,
        )
    with RegularizedFrictionProblem(
        a,
        patch_loads(part, v, 0.75, 0.2),
        [patch_pair(part, V, 1)],
        patch_bcs(part, V),
        mu=0.3,
        petsc_options_prefix="rf_bad_",
    ) as problem:
        with pytest.raises(ValueError, match="friction coefficient mu"):
            problem.solve(mu=np.nan)


def test_ranks_agree():
    """On all ranks and on each rank alone: the same sets and tractions (P2, kappa = 1e3)."""
    scenes = [_uneven(comm, 2) for comm in (COMM, MPI.COMM_SELF)]
    world, alone = (
        _solve(scene, RegularizedFrictionProblem, f"rf_rank{k}_", penalty=1e3)
        for k, scene in enumerate(scenes)
    )
    assert world[2] == alone[2]
    perm = match(*(keys(scene[2][0].Q, None) for scene in scenes))
    for w, s in zip(world[1], alone[1], strict=True):
        assert np.max(np.abs(gather(COMM, w) - s[perm])) <= BOUND * max(np.max(np.abs(s)), 1.0)

# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The friction scenes of issue [4/6] in 3D, shared by ``tests/friction`` and the demo.

The frictional patch test in 3D: the blocks of :mod:`paper.blocks3d` (:math:`[0, 1]^2
\times [0, 1/2]` and :math:`[0, 1]^2 \times [1/2, 1]`, meshed independently, tetrahedra or
hexahedra, optionally with the nodes moved at random in the plane of the contact) in the
uniform stress :math:`\sigma_{zz} = -p`, :math:`\sigma_{xz} = \tau_x`,
:math:`\sigma_{yz} = \tau_y` (the others zero), loaded by :math:`\sigma \mathbf n` on
every face but the contact, with

.. math:: u_x = \frac{\nu p}{E} x + \frac{\tau_x}{G} z + c_x, \quad
    u_y = \frac{\nu p}{E} y + \frac{\tau_y}{G} z + c_y, \quad u_z = -\frac{p}{E} z,

:math:`\mathbf c = 0` in the lower block, which is held by :math:`u_z = 0` on its bottom,
:math:`u_x = u_y = 0` at the origin and :math:`u_y = 0` at :math:`(1, 0, 0)` (all three
true of the state). Nothing but friction holds the upper block tangentially. Stick: the
shear :math:`|\tau| < \mu p` on the top: :math:`\mathbf c = 0`, :math:`\lambda_n = p` and
the shear the upper block (the contactor) exerts on the lower one is
:math:`(\tau_x, \tau_y)`. Slip: the top's tangential motion prescribed as the state's
plus :math:`\mathbf d` beyond the stick limit: :math:`\mathbf c = \mathbf d` and
:math:`\tau = \mu p\, \mathbf d / |\mathbf d|`.
"""

from __future__ import annotations

import typing

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface
from dolfinx_contact_s2s.friction import FrictionalContactProblem
from dolfinx_contact_s2s.kernels.face_backend import tangents
from paper.blocks3d import BOTTOM, TOP, block

__all__ = ["NU", "E", "patch"]

E, NU = 1.0, 0.3
G = E / (2 * (1 + NU))


def _exact(p: float, tau: tuple[float, float], c: tuple[float, float]) -> typing.Callable:
    return lambda x: np.stack(
        [
            NU * p / E * x[0] + tau[0] / G * x[2] + c[0],
            NU * p / E * x[1] + tau[1] / G * x[2] + c[1],
            -p / E * x[2],
        ]
    )


def _vertex_dofs(V: dolfinx.fem.FunctionSpace, point: tuple[float, ...], component: int):
    mesh = V.mesh
    found = dolfinx.mesh.locate_entities_boundary(
        mesh, 0, lambda x: np.all(np.isclose(x, np.reshape(point, (3, 1))), axis=0)
    )
    return dolfinx.fem.locate_dofs_topological(V.sub(component), 0, found)


def patch(
    case: str,
    cells: tuple[str, str] = ("tet", "hex"),
    degree: int = 1,
    seed: int | None = None,
    n: tuple[int, int] = (3, 4),
    axis: typing.Sequence[float] | None = None,
    contactor: str = "upper",
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> dict[str, typing.Any]:
    r"""Solve the 3D frictional patch test ``case`` ("stick" or "slip") against its exact state.

    Stick: :math:`p = 1`, :math:`\tau = (0.2, 0.1)`, :math:`\mu = 0.5`. Slip:
    :math:`\mu = 0.3`, the top moved by :math:`\mathbf d = 0.2 (\cos 30^\circ,
    \sin 30^\circ)`, :math:`\tau = \mu p\, \mathbf d / |\mathbf d|`.

    Returns:
        A record: the largest errors of :math:`\lambda_n` (against :math:`p`),
        :math:`\lambda_t` (against the components of :math:`\pm\tau` along
        :math:`\mathbf T_1, \mathbf T_2` of the pair's tangent axis) relative to
        :math:`|\tau|`, of the displacement relative to its largest value, the sets of the
        last iteration, the solves and the unknowns.
    """
    p = 1.0
    if case == "stick":
        mu, tau, d = 0.5, (0.2, 0.1), (0.0, 0.0)
    else:
        mu, d = 0.3, (0.2 * np.cos(np.pi / 6), 0.2 * np.sin(np.pi / 6))
        tau = (mu * p * np.cos(np.pi / 6), mu * p * np.sin(np.pi / 6))
    sigma = ufl.as_matrix([[0.0, 0.0, tau[0]], [0.0, 0.0, tau[1]], [tau[0], tau[1], -p]])
    spaces, a, L, bcs = [], [], [], []
    for z0, cells_across, cell, upper in (
        (0.0, n[0], cells[0], False),
        (0.5, n[1], cells[1], True),
    ):
        mesh, tags = block(z0, cells_across, cell, seed, comm=comm)
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
        form, _, v = Material(E=E, nu=NU).forms(V)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
        traction = ufl.dot(sigma, ufl.FacetNormal(mesh))
        contact = BOTTOM if upper else TOP
        a.append(form)
        L.append(ufl.inner(traction, v) * ds - ufl.inner(traction, v) * ds(contact))
        if not upper:
            bottom = dolfinx.fem.locate_dofs_topological(V.sub(2), 2, tags.find(BOTTOM))
            pins = [(bottom, 2), (_vertex_dofs(V, (0, 0, 0), 0), 0)]
            pins += [(_vertex_dofs(V, (0, 0, 0), 1), 1), (_vertex_dofs(V, (1, 0, 0), 1), 1)]
            bcs += [dolfinx.fem.dirichletbc(0.0, dofs, V.sub(k)) for dofs, k in pins]
        elif case == "slip":
            for k in (0, 1):
                Vk, _ = V.sub(k).collapse()
                g = dolfinx.fem.Function(Vk)
                g.interpolate(lambda x, k=k: _exact(p, tau, d)(x)[k])
                dofs = dolfinx.fem.locate_dofs_topological((V.sub(k), Vk), 2, tags.find(TOP))
                bcs.append(dolfinx.fem.dirichletbc(g, dofs, V.sub(k)))
        spaces.append((V, tags, contact))
    surfaces = [contact_surface(V, tags, tag) for V, tags, tag in spaces]
    first, second = (surfaces[1], surfaces[0]) if contactor == "upper" else surfaces
    pair = contact_pair(first, second, multiplier=("Lagrange", degree))
    with FrictionalContactProblem(
        a, L, [pair], bcs, mu=mu, tangent_axis=axis, petsc_options_prefix="fr3_"
    ) as problem:
        us, (lam_n,), lam_t = problem.solve()
        normal = np.array([[0.0, 0.0, 1.0 if contactor == "upper" else -1.0]])
        axis_used = problem.tangent_axes[0]
        # The shear the contactor exerts on the target: tau from the upper block.
        shear = np.array([tau[0], tau[1], 0.0]) * (1.0 if contactor == "upper" else -1.0)
        expected = [float(shear @ tangents(normal, axis_used, k)[0]) for k in (1, 2)]
        owned = pair.Q.dofmap.index_map.size_local

        def worst(values):
            return comm.allreduce(float(np.max(np.abs(values), initial=0.0)), op=MPI.MAX)

        u_error, u_size = 0.0, 0.0
        for (V, _, _), u, c in zip(spaces, us, ((0.0, 0.0), d), strict=True):
            reference = dolfinx.fem.Function(V)
            reference.interpolate(_exact(p, tau, c))
            u_error = max(u_error, worst(u.x.array - reference.x.array))
            u_size = max(u_size, worst(reference.x.array))
        last = problem.history.steps[-1].iterations[-1]
        return {
            "case": case,
            "cells": "-".join(cells),
            "degree": degree,
            "seed": seed,
            "contactor": contactor,
            "axis": [float(t) for t in axis_used],
            "lambda_n_error": worst(lam_n.x.array[:owned] - p) / p,
            "lambda_t_error": max(
                worst(f.x.array[:owned] - e) for f, e in zip(lam_t, expected, strict=True)
            )
            / float(np.hypot(*tau)),
            "u_error": u_error / u_size,
            "converged": bool(problem.history.steps[-1].converged),
            "multipliers": pair.Q.dofmap.index_map.size_global,
            "active": int(last.active[0]),
            "stick": int(last.stick[0]),
            "solves": problem.history.iterations,
            "unknowns": sum(V.dofmap.index_map.size_global * 3 for V, _, _ in spaces)
            + 3 * pair.Q.dofmap.index_map.size_global,
        }

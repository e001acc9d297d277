# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Scenes of the defects users met, built as a user builds them (shared by several tests)."""

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface


def _tags(mesh, marks):
    fdim = mesh.topology.dim - 1
    locate = dolfinx.mesh.locate_entities_boundary
    found = [(locate(mesh, fdim, where), tag) for tag, where in marks]
    facets = np.concatenate([f for f, _ in found]).astype(np.int32)
    values = np.concatenate([np.full(f.size, t, dtype=np.int32) for f, t in found])
    order = np.argsort(facets)
    return dolfinx.mesh.meshtags(mesh, fdim, facets[order], values[order])


def quad_tri_patch(comm=MPI.COMM_WORLD, lower=13, upper=9, sides=4, E=1.0, nu=0.3):
    """The user's patch test: quadrilateral lower block, triangular upper block, P1.

    Lower block [0, 1] x [0, 0.5] (``lower`` quadrilaterals along the contact), upper
    block [0, 1] x [0.5, 1] (``upper`` triangles along it), pressure 1 on top, both left
    sides held horizontally, the lower block's bottom vertically. Returns ``a, L, pairs,
    bcs`` (two spaces, one pair: the upper block's bottom is the contactor). ``E`` may be
    a pair, one value per block, in the forms as a user writes them.
    """
    bodies = []
    for y0, n, cell in (
        (0.0, lower, dolfinx.mesh.CellType.quadrilateral),
        (0.5, upper, dolfinx.mesh.CellType.triangle),
    ):
        mesh = dolfinx.mesh.create_rectangle(comm, [[0.0, y0], [1.0, y0 + 0.5]], [n, sides], cell)
        tags = _tags(
            mesh,
            [
                (1, lambda x, y0=y0: np.isclose(x[1], y0)),
                (3, lambda x, y0=y0: np.isclose(x[1], y0 + 0.5)),
                (4, lambda x: np.isclose(x[0], 0.0)),
            ],
        )
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
        bodies.append((mesh, tags, V))
    a, L, bcs = [], [], []
    for k, (mesh, tags, V) in enumerate(bodies):
        # E per body (a pair of values) enters the user's own form.
        Ek = dolfinx.fem.Constant(mesh, float(E[k] if np.ndim(E) else E))
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        mu, lmbda = Ek / (2 * (1 + nu)), Ek * nu / ((1 + nu) * (1 - 2 * nu))
        eps = ufl.sym(ufl.grad(u))
        sigma = 2 * mu * eps + lmbda * ufl.tr(eps) * ufl.Identity(2)
        ak = ufl.inner(sigma, ufl.sym(ufl.grad(v))) * ufl.dx
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
        load = dolfinx.fem.Constant(mesh, np.array([0.0, -1.0 if k == 1 else 0.0]))
        a.append(ak)
        L.append(ufl.inner(load, v) * ds(3))
        left = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, tags.find(4))
        bcs.append(dolfinx.fem.dirichletbc(0.0, left, V.sub(0)))
        if k == 0:
            bottom = dolfinx.fem.locate_dofs_topological(V.sub(1), 1, tags.find(1))
            bcs.append(dolfinx.fem.dirichletbc(0.0, bottom, V.sub(1)))
    (_, lower_tags, V0), (_, upper_tags, V1) = bodies
    pair = contact_pair(contact_surface(V1, upper_tags, 1), contact_surface(V0, lower_tags, 3))
    return a, L, [pair], bcs

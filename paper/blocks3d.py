# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Two non-matching blocks in 3D: the contact patch test of section 3.2, and its levels.

Blocks [0, 1]^2 x [0, 1/2] and [0, 1]^2 x [1/2, 1], meshed independently (tetrahedra or
hexahedra, ``cells`` across each), a uniform pressure P on the top, symmetry conditions on
the planes x = 0 and y = 0 and u_z = 0 at the bottom. The exact solution is uniaxial
stress, u = (nu P x / E, nu P y / E, -P z / E), with the contact pressure P (Eq. 36).
Used by ``tests/test_contact_3d.py`` and ``demos/demo_3d.py``.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import Material

COMM = MPI.COMM_WORLD
E, NU, P = 1.0, 0.3, 1.0
CELLS = {"tet": dolfinx.mesh.CellType.tetrahedron, "hex": dolfinx.mesh.CellType.hexahedron}
#: Tags: the bottom and top of each block, its side x = 0 and its side y = 0.
BOTTOM, TOP, SIDE_X, SIDE_Y = 1, 2, 3, 4


def block(
    z0: float,
    n: int,
    cell: str,
    seed: int | None,
    layers: int = 2,
    warp: bool = False,
    comm: MPI.Comm = COMM,
):
    """A block [0, 1]^2 x [z0, z0 + 1/2] of ``n`` x ``n`` x ``layers`` cells, tagged.

    With ``seed``, the nodes move in the plane of the contact and the faces stay flat:
    tetrahedra at random (inside the square, by up to a fifth of a cell), hexahedra by a
    graded map of x and of y, so that their faces stay parallelograms; with ``warp`` the
    hexahedra move at random too. A bilinear face that is not a parallelogram has a
    rational inverse map, which no Gauss rule on the pieces integrates exactly (README,
    3D: the patch test then holds to the rule's error).
    """
    mesh = dolfinx.mesh.create_box(
        comm, [[0, 0, z0], [1, 1, z0 + 0.5]], [n, n, layers], CELLS[cell]
    )
    if seed is not None:
        x = mesh.geometry.x
        X, Y = x[:, 0].copy(), x[:, 1].copy()
        if cell == "hex" and not warp:
            x[:, 0] += 0.1 * np.sin(np.pi * X) * (1 + 0.3 * seed)
            x[:, 1] += 0.07 * np.sin(2 * np.pi * Y) / (1 + seed)
        else:
            inside = (np.minimum(X, Y) > 1e-12) & (np.maximum(X, Y) < 1 - 1e-12)
            # The same motion of a node on every rank that holds it: a function of position.
            x[inside, 0] += 0.2 / n * np.sin(1e3 * (X + 2 * Y) + seed)[inside]
            x[inside, 1] += 0.2 / n * np.sin(3e2 * Y - 5e2 * X + seed)[inside]
    mesh.topology.create_connectivity(2, 3)
    markers = (
        (BOTTOM, lambda x: np.isclose(x[2], z0)),
        (TOP, lambda x: np.isclose(x[2], z0 + 0.5)),
        (SIDE_X, lambda x: np.isclose(x[0], 0.0)),
        (SIDE_Y, lambda x: np.isclose(x[1], 0.0)),
    )
    found = [(dolfinx.mesh.locate_entities_boundary(mesh, 2, f), tag) for tag, f in markers]
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([np.full(f.size, tag, dtype=np.int32) for f, tag in found])
    order = np.argsort(facets, kind="stable")
    return mesh, dolfinx.mesh.meshtags(mesh, 2, facets[order], values[order])


def scene(
    lower: str,
    upper: str,
    degree: int,
    seed: int | None = None,
    cells: tuple[int, int] = (3, 4),
    layers: int = 2,
    warp: bool = False,
    comm: MPI.Comm = COMM,
    tilt: float = 0.0,
    E: float = E,
    P: float = P,
):
    r"""Spaces, forms and boundary conditions of the two blocks (the user's own forms).

    ``cells`` across the lower and the upper block; ``seed``, ``layers`` and ``warp`` as
    :func:`block` takes them. With ``tilt`` the pressure on the top is
    :math:`P (1 - \text{tilt}\, x)`: no closed form, the contact opens where it pulls.
    ``E`` (Young's modulus of both blocks) and ``P`` default to the module's constants.
    """
    spaces, a, L, bcs = [], [], [], []
    for z0, n, cell, loaded in ((0.0, cells[0], lower, False), (0.5, cells[1], upper, True)):
        mesh, tags = block(z0, n, cell, seed, layers, warp, comm)
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
        form, _, v = Material(E=E, nu=NU).forms(V)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
        x = ufl.SpatialCoordinate(mesh)
        traction = (
            ufl.as_vector([0.0, 0.0, -P * (1 - tilt * x[0])])
            if loaded
            else dolfinx.fem.Constant(mesh, np.zeros(3))
        )
        a.append(form)
        L.append(ufl.inner(traction, v) * ds(TOP))
        fixed = [(0, SIDE_X), (1, SIDE_Y)] + ([] if loaded else [(2, BOTTOM)])
        for component, tag in fixed:
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 2, tags.find(tag))
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(component)))
        spaces.append((V, tags))
    return spaces, a, L, bcs


def exact(x, E: float = E, P: float = P):
    """Uniaxial stress under the pressure P: the displacement."""
    return np.stack([NU * P / E * x[0], NU * P / E * x[1], -P / E * x[2]])


def errors(us, pressure, E: float = E, P: float = P) -> tuple[float, float]:
    """Largest errors of the multipliers (against P) and displacements (uniaxial stress).

    ``E`` and ``P`` as :func:`scene` took them. Collective: the maxima over the ranks of
    the meshes.
    """
    worst_p = np.max(np.abs(pressure.x.array - P), initial=0.0)
    worst_u = 0.0
    for u in us:
        expected = dolfinx.fem.Function(u.function_space)
        expected.interpolate(lambda x: exact(x, E, P))
        worst_u = max(worst_u, float(np.max(np.abs(u.x.array - expected.x.array), initial=0.0)))
    comm = pressure.function_space.mesh.comm
    return comm.allreduce(float(worst_p), op=MPI.MAX), comm.allreduce(worst_u, op=MPI.MAX)

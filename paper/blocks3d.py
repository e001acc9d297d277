# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Two non-matching blocks in 3D: the contact patch test of section 3.2, and its levels.

Blocks [0, 1]^2 x [0, 1/2] and [0, 1]^2 x [1/2, 1], meshed independently (tetrahedra or
hexahedra, ``cells`` across each), a uniform pressure P on the top, symmetry conditions on
the planes x = 0 and y = 0 and u_z = 0 at the bottom. The exact solution is uniaxial
stress, u = (nu P x / E, nu P y / E, -P z / E), with the contact pressure P (Eq. 36).

With ``sizes`` one block is wider than the other, [0, a] x [0, b]: it hangs over the
other's edges x = 1 or y = 1. The part of its contact face that faces nothing carries
the pressure P as a load (tag :data:`EXPOSED` of the forms' facet tags,
:func:`exposed_tags`; the contact surfaces keep the whole face), the support
the other block gives elsewhere, so the exact solution is still uniaxial stress
everywhere; the contact carries P on the common square only. Used by
``tests/test_contact_3d.py``, ``tests/test_contact_3d_overhang.py`` and
``demos/demo_3d.py``.
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
#: Tag of the part of a contact face beyond the other block (:func:`exposed_tags`).
EXPOSED = 5


def block(
    z0: float,
    n: int | tuple[int, int],
    cell: str,
    seed: int | None,
    layers: int = 2,
    warp: bool = False,
    comm: MPI.Comm = COMM,
    size: tuple[float, float] = (1.0, 1.0),
):
    """A block [0, a] x [0, b] x [z0, z0 + 1/2] of ``n`` x ``n`` x ``layers`` cells, tagged.

    ``size`` is (a, b); ``n`` an int or a pair (cells along x and along y). With
    ``seed``, the nodes move in the plane of the contact and the faces stay flat:
    tetrahedra at random (inside the square, by up to a fifth of a cell), hexahedra by a
    graded map of x and of y, so that their faces stay parallelograms; with ``warp`` the
    hexahedra move at random too. A bilinear face that is not a parallelogram has a
    rational inverse map, which no Gauss rule on the pieces integrates exactly (README,
    3D: the patch test then holds to the rule's error).

    Raises:
        ValueError: For ``seed`` with a ``size`` other than (1, 1): moved nodes would
            leave the edge of the other block between nodes.
    """
    nx, ny = (n, n) if isinstance(n, int) else n
    if seed is not None and tuple(size) != (1.0, 1.0):
        raise ValueError("moved nodes (seed) are for blocks of size (1, 1)")
    mesh = dolfinx.mesh.create_box(
        comm, [[0, 0, z0], [size[0], size[1], z0 + 0.5]], [nx, ny, layers], CELLS[cell]
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


def exposed_tags(
    mesh: dolfinx.mesh.Mesh, tags: dolfinx.mesh.MeshTags, z: float, other: tuple[float, float]
):
    """``tags`` with the faces in the plane ``z`` beyond ``[0, a] x [0, b]`` as :data:`EXPOSED`.

    ``other`` is (a, b), the size of the other block: the faces of this block's contact
    face that face nothing (all their vertices at x >= a or at y >= b). For the forms:
    a form takes one set of facet tags, and the contact surface keeps the whole face.
    """
    tol = 1e-12
    facets = dolfinx.mesh.locate_entities_boundary(
        mesh,
        2,
        lambda x: np.isclose(x[2], z) & ((x[0] >= other[0] - tol) | (x[1] >= other[1] - tol)),
    )
    values = tags.values.copy()
    values[np.isin(tags.indices, facets)] = EXPOSED
    return dolfinx.mesh.meshtags(mesh, 2, tags.indices, values)


def scene(
    lower: str,
    upper: str,
    degree: int,
    seed: int | None = None,
    cells: tuple[int | tuple[int, int], int | tuple[int, int]] = (3, 4),
    layers: int = 2,
    warp: bool = False,
    comm: MPI.Comm = COMM,
    tilt: float = 0.0,
    E: float = E,
    P: float = P,
    sizes: tuple[tuple[float, float], tuple[float, float]] = ((1.0, 1.0), (1.0, 1.0)),
):
    r"""Spaces, forms and boundary conditions of the two blocks (the user's own forms).

    ``cells`` across the lower and the upper block; ``seed``, ``layers`` and ``warp`` as
    :func:`block` takes them. With ``tilt`` the pressure on the top is
    :math:`P (1 - \text{tilt}\, x)`: no closed form, the contact opens where it pulls.
    ``E`` (Young's modulus of both blocks) and ``P`` default to the module's constants.
    ``sizes`` of the lower and the upper block (see :func:`block`): where one hangs over
    the other, its exposed contact faces carry the pressure P (:func:`exposed_tags`);
    the other block's edge x = a (y = b) must be a line of its nodes.
    """
    spaces, a, L, bcs = [], [], [], []
    blocks = ((0.0, cells[0], lower, False, 0), (0.5, cells[1], upper, True, 1))
    for z0, n, cell, loaded, i in blocks:
        mesh, tags = block(z0, n, cell, seed, layers, warp, comm, sizes[i])
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
        form, _, v = Material(E=E, nu=NU).forms(V)
        exposed = np.any(np.asarray(sizes[i]) > np.asarray(sizes[1 - i]))
        # Where this block hangs over the other: the support it does not give, P.
        form_tags = exposed_tags(mesh, tags, 0.5, sizes[1 - i]) if exposed else tags
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=form_tags)
        x = ufl.SpatialCoordinate(mesh)
        traction = (
            ufl.as_vector([0.0, 0.0, -P * (1 - tilt * x[0])])
            if loaded
            else dolfinx.fem.Constant(mesh, np.zeros(3))
        )
        a.append(form)
        L.append(ufl.inner(traction, v) * ds(TOP))
        if exposed:
            L[-1] += ufl.inner(-P * ufl.FacetNormal(mesh), v) * ds(EXPOSED)
        fixed = [(0, SIDE_X), (1, SIDE_Y)] + ([] if loaded else [(2, BOTTOM)])
        for component, tag in fixed:
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 2, tags.find(tag))
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(component)))
        spaces.append((V, tags))
    return spaces, a, L, bcs


def exact(x, E: float = E, P: float = P):
    """Uniaxial stress under the pressure P: the displacement."""
    return np.stack([NU * P / E * x[0], NU * P / E * x[1], -P / E * x[2]])


def errors(us, pressure, E: float = E, P: float = P, skip=None) -> tuple[float, float]:
    """Largest errors of the multipliers (against P) and displacements (uniaxial stress).

    ``E`` and ``P`` as :func:`scene` took them; ``skip``: global multiplier dofs left
    out (those that face nothing). Collective: the maxima over the ranks of the meshes.
    """
    values = pressure.x.array
    if skip is not None:
        imap = pressure.function_space.dofmap.index_map
        dofs = imap.local_to_global(np.arange(values.size, dtype=np.int32))
        values = values[~np.isin(dofs, skip)]
    worst_p = np.max(np.abs(values - P), initial=0.0)
    worst_u = 0.0
    for u in us:
        expected = dolfinx.fem.Function(u.function_space)
        expected.interpolate(lambda x: exact(x, E, P))
        worst_u = max(worst_u, float(np.max(np.abs(u.x.array - expected.x.array), initial=0.0)))
    comm = pressure.function_space.mesh.comm
    return comm.allreduce(float(worst_p), op=MPI.MAX), comm.allreduce(worst_u, op=MPI.MAX)

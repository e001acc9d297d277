"""Contact surfaces in the current configuration X + u (ContactSurface.set_displacement).

Finite deformation couples the bodies where they are: the coupling of surfaces displaced
by ``u`` must be the coupling of the same bodies meshed where they now are. The
independent path moves a second copy of the mesh (its nodes to ``X + f(X)``) and builds
everything on it; ``u`` is the interpolant of ``f`` (exact: ``f`` is a polynomial of the
displacement's degree), so the two couplings agree to round-off. A rigid motion of both
bodies rotates each node's coupling vector and leaves the gap: a closed form.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
from readme_model import LOWER, UPPER, readme_mesh

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.assemble import assemble_coupling
from dolfinx_contact_s2s.compat import geometry_dofmap
from dolfinx_contact_s2s.la import gather_dense
from dolfinx_contact_s2s.meshing import curved_mesh
from paper.blocks3d import BOTTOM, TOP, block

comm = MPI.COMM_WORLD


def _coupling(pair) -> tuple[list[np.ndarray], np.ndarray]:
    op = assemble_coupling(pair)
    blocks = [gather_dense(B) for _, B in op.blocks]
    gap = np.concatenate(comm.allgather(op.G.array_r.copy()))
    op.destroy()
    return blocks, gap


def _owned(V) -> int:
    return V.dofmap.index_map.size_local * V.dofmap.index_map_bs


def _upper_cells(mesh) -> np.ndarray:
    num = mesh.topology.index_map(2).size_local + mesh.topology.index_map(2).num_ghosts
    mid = dolfinx.mesh.compute_midpoints(mesh, 2, np.arange(num, dtype=np.int32))
    return np.flatnonzero(mid[:, 1] > 0.5).astype(np.int32)


def _motion_2d(degree: int):
    """Per body a polynomial motion of the displacement's degree: the upper body slides."""

    def lower(x):
        return np.stack(
            [0.01 * x[0] - 0.02 * x[1], -0.03 * x[1] + 0.01 * x[0] * x[1] * (degree - 1)]
        )

    def upper(x):
        c, s = np.cos(0.1), np.sin(0.1)
        dx, dy = x[0] - 0.5, x[1] - 0.5
        quadratic = 0.02 * (degree - 1) * dx**2
        return np.stack([(c - 1) * dx - s * dy + 0.23, s * dx + (c - 1) * dy + 0.01 + quadratic])

    return lower, upper


def _scene_2d(degree: int):
    mesh, facets = readme_mesh(lower=7, upper=5)
    if degree == 2:
        cell_tags = dolfinx.mesh.meshtags(
            mesh,
            2,
            np.arange(mesh.topology.index_map(2).size_local, dtype=np.int32),
            np.ones(mesh.topology.index_map(2).size_local, dtype=np.int32),
        )
        mesh, _, facets = curved_mesh(mesh, cell_tags, facets)
    return mesh, facets


def _displace(mesh, motions, cells_of):
    """The mesh's nodes moved: node by node, with the motion of its body's cells."""
    dofmap = geometry_dofmap(mesh)
    x = mesh.geometry.x
    for f, cells in zip(motions, cells_of, strict=True):
        nodes = np.unique(dofmap[cells])
        x[nodes, :2] += f(x[nodes, :2].T).T


def _interpolate(V, motions, cells_of) -> dolfinx.fem.Function:
    u = dolfinx.fem.Function(V)
    points = V.tabulate_dof_coordinates()
    values = u.x.array.reshape(-1, 2)
    for f, cells in zip(motions, cells_of, strict=True):
        blocks = np.unique(V.dofmap.list[cells])
        values[blocks] = f(points[blocks, :2].T).T
    return u


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("method", ["segment-to-segment", "node-to-segment"])
def test_displaced_surfaces_couple_as_the_moved_mesh(degree, method):
    motions = _motion_2d(degree)
    couplings = []
    for moved in (False, True):
        mesh, facets = _scene_2d(degree)
        upper = _upper_cells(mesh)
        imap = mesh.topology.index_map(2)
        lower = np.setdiff1d(np.arange(imap.size_local + imap.num_ghosts), upper)
        cells_of = (lower.astype(np.int32), upper)
        if moved:
            _displace(mesh, motions, cells_of)
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
        surfaces = [contact_surface(V, facets, t) for t in (LOWER["top"], UPPER["bottom"])]
        if not moved:
            u = _interpolate(V, motions, cells_of)
            reference = _coupling(contact_pair(surfaces[1], surfaces[0], method=method))
            for s in surfaces:
                s.set_displacement(u)
        couplings.append(_coupling(contact_pair(surfaces[1], surfaces[0], method=method)))
    (displaced, gap), (expected, expected_gap) = couplings
    for B, R in zip(displaced, expected, strict=True):
        assert np.max(np.abs(B - R)) <= 1e-12 * np.max(np.abs(R))
    # The gap is linearized at u in the total displacement: G(u) - B(u) u.
    values = np.concatenate(comm.allgather(u.x.array[: _owned(V)]))
    linear = gap + displaced[0] @ values
    assert np.max(np.abs(linear - expected_gap)) <= 1e-12 * np.max(np.abs(expected_gap))
    # Not the reference coupling: the motion changed it.
    assert np.max(np.abs(reference[0][0] - expected[0])) > 1e-3 * np.max(np.abs(expected[0]))


def _rotation_3d(angles):
    a, b, c = angles
    Rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    Ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    Rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def _rigid(V, R, centre, shift) -> dolfinx.fem.Function:
    gdim = R.shape[0]
    u = dolfinx.fem.Function(V)
    X = V.tabulate_dof_coordinates()[:, :gdim]
    u.x.array[:] = ((X - centre) @ (R - np.eye(gdim)).T + shift).reshape(-1)
    return u


def _rotated_blocks(B: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Each node's coupling vector (the row's entries on its components) rotated by R."""
    gdim = R.shape[0]
    rows, cols = B.shape
    return np.einsum("ij,rnj->rni", R, B.reshape(rows, cols // gdim, gdim)).reshape(rows, cols)


@pytest.mark.parametrize("degree", [1, 2])
def test_rigid_motion_rotates_the_coupling_2d(degree):
    mesh, facets = _scene_2d(degree)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    surfaces = [contact_surface(V, facets, t) for t in (LOWER["top"], UPPER["bottom"])]
    pair = contact_pair(surfaces[1], surfaces[0])
    (B,), G = _coupling(pair)
    t = 1.3
    R = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    u = _rigid(V, R, np.array([0.3, 0.7]), np.array([2.0, -1.0]))
    for s in surfaces:
        s.set_displacement(u)
    (B_rot,), G_rot = _coupling(pair)
    assert np.max(np.abs(B_rot - _rotated_blocks(B, R))) <= 1e-12 * np.max(np.abs(B))
    assert np.max(np.abs(G_rot - G)) <= 1e-12 * max(np.max(np.abs(G)), np.max(np.abs(B)))
    # Back to X: the reference coupling.
    for s in surfaces:
        s.set_displacement(None)
    (B_back,), _ = _coupling(pair)
    assert np.array_equal(B_back, B)


@pytest.mark.parametrize("cell", ["tet", "hex"])
def test_rigid_motion_rotates_the_coupling_3d(cell):
    bodies = [
        block(z0, n, cell, seed=1 if cell == "tet" else None) for z0, n in ((0.0, 3), (0.5, 4))
    ]
    spaces = [dolfinx.fem.functionspace(m, ("Lagrange", 1, (3,))) for m, _ in bodies]
    surfaces = [
        contact_surface(spaces[0], bodies[0][1], TOP),
        contact_surface(spaces[1], bodies[1][1], BOTTOM),
    ]
    pair = contact_pair(surfaces[1], surfaces[0])
    blocks, G = _coupling(pair)
    R = _rotation_3d((0.4, -1.1, 2.0))
    centre, shift = np.array([0.2, 0.1, 0.5]), np.array([1.0, -2.0, 0.5])
    for V, s in zip(spaces, surfaces, strict=True):
        s.set_displacement(_rigid(V, R, centre, shift))
    rotated, G_rot = _coupling(pair)
    for B, B_rot in zip(blocks, rotated, strict=True):
        assert np.max(np.abs(B_rot - _rotated_blocks(B, R))) <= 1e-12 * np.max(np.abs(B))
    assert np.max(np.abs(G_rot - G)) <= 1e-12 * max(np.max(np.abs(G)), 1.0)


def test_bad_displacements_raise_on_every_rank():
    mesh, facets = readme_mesh(lower=7, upper=5)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    surface = contact_surface(V, facets, LOWER["top"])
    W = dolfinx.fem.functionspace(mesh, ("Lagrange", 2, (2,)))
    with pytest.raises(ValueError, match="Function in the surface's V"):
        surface.set_displacement(dolfinx.fem.Function(W))
    with pytest.raises(ValueError, match="geometry of the displacement's degree"):
        contact_surface(W, facets, LOWER["top"]).set_displacement(dolfinx.fem.Function(W))
    u = dolfinx.fem.Function(V)
    u.x.array[:] = np.nan
    with pytest.raises(ValueError, match="NaN or infinite"):
        surface.set_displacement(u)
    # A mirror image of the lower block: every cell at its top inverted.
    X = V.tabulate_dof_coordinates()[:, :2]
    u.x.array[:] = np.stack([-2 * X[:, 0], 0 * X[:, 1]], axis=1).reshape(-1)
    with pytest.raises(ValueError, match=r"inverts cells at contact surface 10 \(det F <= 0\)"):
        surface.set_displacement(u)
    assert surface.data is surface.reference


#: The sliding patch test: lower block [-1, 2] x [0, 1/2] of 39 x 4 cells (h = 1/13),
#: upper block [0, 1] x [1/2, 1] of 9 x 4 cells, pressed by P on its top.
P, MATERIAL_E, MATERIAL_NU = 0.7, 1.0, 0.3
EXPOSED, TOP_TAG, BOTTOM_TAG, LEFT_TAG = 5, 2, 1, 4


def _sliding_body(lower: bool, degree: int, shift: float):
    box = [[-1.0, 0.0], [2.0, 0.5]] if lower else [[0.0, 0.5], [1.0, 1.0]]
    mesh = dolfinx.mesh.create_rectangle(comm, box, [39, 4] if lower else [9, 4])
    (x0, y0), (_, y1) = box
    mesh.topology.create_connectivity(1, 2)

    def exposed(x):  # the lower top the upper block does not cover (whole facets)
        return np.isclose(x[1], y1) & ((x[0] <= shift + 1e-12) | (x[0] >= 1 + shift - 1e-12))

    markers = [
        (TOP_TAG, lambda x: np.isclose(x[1], y1)),
        (BOTTOM_TAG, lambda x: np.isclose(x[1], y0)),
        (LEFT_TAG, lambda x: np.isclose(x[0], x0)),
    ]
    found = [(dolfinx.mesh.locate_entities_boundary(mesh, 1, f), t) for t, f in markers]
    if lower:
        open_top = dolfinx.mesh.locate_entities_boundary(mesh, 1, exposed)
        found = [(np.setdiff1d(f, open_top) if t == TOP_TAG else f, t) for f, t in found]
        found.append((open_top, EXPOSED))
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([np.full(f.size, t, dtype=np.int32) for f, t in found])
    order = np.argsort(facets, kind="stable")
    tags = dolfinx.mesh.meshtags(mesh, 1, facets[order], values[order])
    if degree == 2:
        imap = mesh.topology.index_map(2)
        cells = dolfinx.mesh.meshtags(
            mesh,
            2,
            np.arange(imap.size_local, dtype=np.int32),
            np.ones(imap.size_local, dtype=np.int32),
        )
        mesh, _, tags = curved_mesh(mesh, cells, tags)
    return mesh, tags


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("elements", [0, 2, 5])
def test_sliding_patch_test(degree, elements):
    """The upper block slid rigidly by whole lower elements: lambda = P exactly.

    Frictionless tied contact (normal only): each block in uniaxial stress about its own
    symmetry side, so the blocks' lateral expansions slide against each other. The lower
    top the upper block leaves open carries P as a load (its edges on lower nodes, so the
    load is exact). The upper surface is placed at the slide (``set_displacement``) and
    the solve is for the total displacement (the slide is a rigid motion: no stress).
    """
    import ufl

    from dolfinx_contact_s2s import Material
    from dolfinx_contact_s2s.problem import LinearContactProblem

    shift = elements / 13
    a, L, bcs, spaces, tags_of = [], [], [], [], []
    for lower in (True, False):
        mesh, tags = _sliding_body(lower, degree, shift)
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
        form, _, v = Material(E=MATERIAL_E, nu=MATERIAL_NU).forms(V)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
        n = ufl.FacetNormal(mesh)
        a.append(form)
        L.append(ufl.inner(-P * n, v) * ds(EXPOSED if lower else TOP_TAG))
        # The upper block's symmetry side moved with it: U is the total displacement.
        fixed = [(0, LEFT_TAG, 0.0 if lower else shift)] + ([(1, BOTTOM_TAG, 0.0)] if lower else [])
        for component, tag, value in fixed:
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 1, tags.find(tag))
            bcs.append(dolfinx.fem.dirichletbc(value, dofs, V.sub(component)))
        spaces.append(V)
        tags_of.append(tags)
    target = contact_surface(spaces[0], tags_of[0], TOP_TAG)
    contactor = contact_surface(spaces[1], tags_of[1], BOTTOM_TAG)
    slide = dolfinx.fem.Function(spaces[1])
    slide.x.array.reshape(-1, 2)[:, 0] = shift
    contactor.set_displacement(slide)
    problem = LinearContactProblem(
        a, L, [contact_pair(contactor, target)], bcs, petsc_options_prefix="sliding_"
    )
    with problem:
        (_, u), (lam,) = problem.solve()
        owned = lam.function_space.dofmap.index_map.size_local
        error = np.max(np.abs(lam.x.array[:owned] - P), initial=0.0)
        # The exact upper block: slid, then in uniaxial stress (plane strain).
        strain = -P / MATERIAL_E * (1 - MATERIAL_NU**2)
        lateral = P / MATERIAL_E * MATERIAL_NU * (1 + MATERIAL_NU)
        X = spaces[1].tabulate_dof_coordinates()[:, :2]
        exact = np.stack([shift + lateral * X[:, 0], strain * (X[:, 1] - 0.5)], axis=1)
        n = _owned(spaces[1]) // 2
        # The upper block rests on the lower, compressed by the same strain.
        exact[:, 1] += strain * 0.5
        u_error = np.max(np.abs(u.x.array[: 2 * n].reshape(-1, 2) - exact[:n]), initial=0.0)
    assert comm.allreduce(float(error), op=MPI.MAX) <= 1e-10 * P
    assert comm.allreduce(float(u_error), op=MPI.MAX) <= 1e-10

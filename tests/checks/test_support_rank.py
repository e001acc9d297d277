# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Floating bodies (Eq. 33) and redundant constraints (Eqs. 34-35).

The numbers asserted come from outside the code under test: the rectangles of the Gmsh
model, the kernel dimension of the dense stiffness matrix, the motions a boundary
condition leaves free by construction, the dependencies built into hand-made constraint
matrices (a cycle's incidence rows sum to zero) and the SVD rank of the gathered matrix.
They do not depend on the number of processes.
"""

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import scipy.linalg
import ufl

from dolfinx_contact_s2s.checks import (
    REDUNDANT_TOL,
    Redundancy,
    connected_components,
    joint_redundant_constraints,
    joint_redundant_multipliers,
    near_nullspace,
    redundant_constraints,
    redundant_multipliers,
    rigid_body_modes,
    unsupported_motions,
)
from dolfinx_contact_s2s.compat import gmsh_model_to_mesh

comm = MPI.COMM_WORLD
eps = np.finfo(np.float64).eps

# (lower-left corner, size) of disjoint rectangles, meshed in this order.
RECTANGLES = [((0.0, 0.0), (1.0, 0.5)), ((1.5, 0.0), (1.0, 1.0)), ((0.0, 1.5), (2.0, 0.5))]


def rectangles_mesh(rectangles, h: float, quadrilateral: bool = False) -> dolfinx.mesh.Mesh:
    """One mesh, one Gmsh model, several plane surfaces that share no node."""
    import gmsh

    started = not gmsh.isInitialized()
    if started:
        gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("rectangles")
    if comm.rank == 0:
        surfaces = [
            gmsh.model.occ.addRectangle(x0, y0, 0.0, w, hh) for (x0, y0), (w, hh) in rectangles
        ]
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(2, surfaces, 1)
        gmsh.option.setNumber("Mesh.CharacteristicLengthMax", h)
        if quadrilateral:
            gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.model.mesh.generate(2)
    mesh, _, _ = gmsh_model_to_mesh(gmsh.model, comm, 0, gdim=2)
    gmsh.model.remove()
    if started:
        gmsh.finalize()
    return mesh


def inside(rectangles, x: np.ndarray) -> np.ndarray:
    """Index of the rectangle containing each point."""
    index = np.full(x.shape[0], -1)
    for k, ((x0, y0), (w, h)) in enumerate(rectangles):
        hit = (x[:, 0] > x0) & (x[:, 0] < x0 + w) & (x[:, 1] > y0) & (x[:, 1] < y0 + h)
        index[hit] = k
    return index


def vector_space(mesh: dolfinx.mesh.Mesh) -> dolfinx.fem.FunctionSpace:
    return dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (mesh.geometry.dim,)))


def elasticity(V, spring: float = 0.0) -> dolfinx.fem.Form:
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    mu, lmbda = 0.5 / 1.3, 0.3 / (1.3 * 0.4)

    def eps_(w):
        return ufl.sym(ufl.grad(w))

    a = (2 * mu * ufl.inner(eps_(u), eps_(v)) + lmbda * ufl.div(u) * ufl.div(v)) * ufl.dx
    if spring:
        a += spring * ufl.inner(u, v) * ufl.ds
    return dolfinx.fem.form(a)


def stiffness(V, bcs=(), spring: float = 0.0) -> PETSc.Mat:
    K = dolfinx.fem.petsc.assemble_matrix(elasticity(V, spring), bcs=list(bcs))
    K.assemble()
    return K


def mask(V, bcs=()) -> PETSc.Vec:
    """1 at free dofs, 0 at Dirichlet dofs."""
    bs = V.dofmap.index_map_bs
    m = PETSc.Vec().createMPI((V.dofmap.index_map.size_local * bs, PETSc.DETERMINE), comm=comm)
    m.set(1.0)
    for bc in bcs:
        dofs = bc.dof_indices()[0]
        m.array[dofs[dofs < m.getLocalSize()]] = 0.0
    return m


def gather_vector(v: PETSc.Vec) -> np.ndarray:
    return np.concatenate(comm.allgather(v.array_r.copy()))


def gather_matrix(A: PETSc.Mat) -> np.ndarray:
    start, _ = A.getOwnershipRange()
    indptr, indices, data = A.getValuesCSR()
    D = np.zeros(A.getSize())
    for first, ip, ind, val in comm.allgather((start, indptr, indices, data)):
        D[first + np.repeat(np.arange(ip.size - 1), np.diff(ip)), ind] += val
    return D


def global_dof(V, point, component: int) -> int:
    """Global (PETSc) index of ``component`` of the node at ``point``."""
    imap, bs = V.dofmap.index_map, V.dofmap.index_map_bs
    x = V.tabulate_dof_coordinates()[: imap.size_local, :2]
    best = (np.inf, -1)
    if x.shape[0] > 0:
        i = int(np.argmin(np.linalg.norm(x - np.asarray(point), axis=1)))
        best = (float(np.linalg.norm(x[i] - point)), (imap.local_range[0] + i) * bs + component)
    distance, dof = min(comm.allgather(best))
    assert distance < 1e-12, f"no node at {point}"
    return dof


def constraint_block(rows: int, columns, entries) -> PETSc.Mat:
    """AIJ matrix ``rows x columns`` from ``(row, column, value)``, inserted on rank 0.

    ``columns`` is a space (its PETSc layout) or a global number of columns.
    """
    if isinstance(columns, int):
        col_sizes = (PETSc.DECIDE, columns)
    else:
        col_sizes = (columns.dofmap.index_map.size_local * columns.dofmap.index_map_bs, None)
    B = PETSc.Mat().createAIJ(((PETSc.DECIDE, rows), col_sizes), comm=comm)
    B.setUp()
    B.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
    if comm.rank == 0:
        for r, c, v in entries:
            B.setValue(r, c, v, addv=PETSc.InsertMode.ADD_VALUES)
    B.assemble()
    return B


def edge(V, x: float):
    mesh = V.mesh
    facets = dolfinx.mesh.locate_entities_boundary(
        mesh, mesh.topology.dim - 1, lambda p: np.isclose(p[0], x)
    )
    return facets


def clamp(V, x: float = 0.0, sub: int | None = None) -> dolfinx.fem.DirichletBC:
    """u = 0 (or u[sub] = 0) on the boundary facets at abscissa ``x``."""
    fdim = V.mesh.topology.dim - 1
    facets = edge(V, x)
    if sub is None:
        dofs = dolfinx.fem.locate_dofs_topological(V, fdim, facets)
        zero = np.zeros(V.mesh.geometry.dim, dtype=PETSc.ScalarType)
        return dolfinx.fem.dirichletbc(zero, dofs, V)
    dofs = dolfinx.fem.locate_dofs_topological(V.sub(sub), fdim, facets)
    return dolfinx.fem.dirichletbc(PETSc.ScalarType(0.0), dofs, V.sub(sub))


def pin(V, point) -> dolfinx.fem.DirichletBC:
    dofs = dolfinx.fem.locate_dofs_geometrical(
        V, lambda x: np.isclose(x[0], point[0]) & np.isclose(x[1], point[1])
    )
    zero = np.zeros(V.mesh.geometry.dim, dtype=PETSc.ScalarType)
    return dolfinx.fem.dirichletbc(zero, dofs, V)


def check(spaces, Ks, masks, constraints=(), inactive=()):
    motions = unsupported_motions(spaces, Ks, masks, list(constraints), list(inactive))
    for obj in [*Ks, *masks] + [B for pair in constraints for _, B in pair]:
        obj.destroy()
    return motions


# ----------------------------------------------------------------------------------------
# Connected components
# ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("quadrilateral", [False, True])
@pytest.mark.parametrize("count", [2, 3])
def test_components_of_gmsh_rectangles(count, quadrilateral):
    rectangles = RECTANGLES[:count]
    mesh = rectangles_mesh(rectangles, 0.2, quadrilateral)
    labels, num = connected_components(mesh)
    assert num == count
    cell_map = mesh.topology.index_map(2)
    cells = np.arange(cell_map.size_local + cell_map.num_ghosts, dtype=np.int32)
    assert labels.shape == cells.shape and labels.dtype == np.int32
    midpoints = dolfinx.mesh.compute_midpoints(mesh, 2, cells)
    # Numbered as meshed in Gmsh: the same labels on any number of processes.
    assert np.array_equal(labels, inside(rectangles, midpoints))


@pytest.mark.parametrize(
    "ghost_mode", [dolfinx.mesh.GhostMode.none, dolfinx.mesh.GhostMode.shared_facet]
)
def test_components_of_one_body(ghost_mode):
    mesh = dolfinx.mesh.create_rectangle(
        comm, [[0.0, 0.0], [3.0, 1.0]], [30, 4], ghost_mode=ghost_mode
    )
    labels, num = connected_components(mesh)
    assert num == 1
    assert np.all(labels == 0)


# ----------------------------------------------------------------------------------------
# Rigid body modes
# ----------------------------------------------------------------------------------------


def kernel_check(V, modes_per_body: int, bodies: int):
    K = stiffness(V)
    modes = rigid_body_modes(V)
    assert len(modes) == modes_per_body * bodies
    y = K.createVecLeft()
    norm_K = K.norm(PETSc.NormType.FROBENIUS)
    for r in modes:
        K.mult(r, y)
        # Round-off of the element sums: eps times ||K|| ||r||, with a margin for the sum.
        assert y.norm() <= 100 * eps * norm_K * r.norm()
    # The modes span the kernel of the dense stiffness matrix.
    Kd = gather_matrix(K)
    w, Z = scipy.linalg.eigh(Kd)
    null = w < 1e-8 * w[-1]
    assert np.count_nonzero(null) == modes_per_body * bodies
    R = np.stack([gather_vector(r) for r in modes], axis=1)
    assert np.linalg.matrix_rank(np.hstack([Z[:, null], R]), tol=1e-8) == null.sum()
    ns = near_nullspace(V)
    vecs = ns.getVecs()
    assert len(vecs) == len(modes)
    Q = np.stack([gather_vector(v) for v in vecs], axis=1)
    assert np.allclose(Q.T @ Q, np.eye(len(vecs)), atol=1e-12)
    assert np.linalg.matrix_rank(np.hstack([Q, R]), tol=1e-8) == len(modes)
    ns.destroy()
    for r in modes:
        r.destroy()
    y.destroy()
    K.destroy()


@pytest.mark.parametrize("count", [1, 2, 3])
def test_rigid_modes_span_kernel_2d(count):
    kernel_check(vector_space(rectangles_mesh(RECTANGLES[:count], 0.35)), 3, count)


def test_rigid_modes_span_kernel_3d():
    mesh = dolfinx.mesh.create_box(comm, [[0.0, 0.0, 0.0], [2.0, 1.0, 1.0]], [3, 2, 2])
    kernel_check(vector_space(mesh), 6, 1)


def test_rigid_modes_unit_rms():
    V = vector_space(rectangles_mesh(RECTANGLES[:2], 0.3))
    modes = rigid_body_modes(V)
    nodes = V.dofmap.index_map.size_global
    for r in modes:
        # Unit RMS displacement per node of its body: |r|^2 = nodes of the body.
        values = gather_vector(r).reshape(-1, 2)
        moving = np.linalg.norm(values, axis=1) > 0
        assert 0 < moving.sum() < nodes
        assert np.isclose(np.sum(values**2), moving.sum(), rtol=1e-12)
        r.destroy()


# ----------------------------------------------------------------------------------------
# Unsupported motions (Eq. 33)
# ----------------------------------------------------------------------------------------


def block():
    return dolfinx.mesh.create_rectangle(comm, [[0.0, 0.0], [2.0, 1.0]], [8, 4])


def test_clamped_block_is_supported():
    V = vector_space(block())
    bcs = [clamp(V)]
    assert check([V], [stiffness(V, bcs)], [mask(V, bcs)]) == []


def test_roller_leaves_vertical_translation():
    V = vector_space(block())
    bcs = [clamp(V, sub=0)]
    motions = check([V], [stiffness(V, bcs)], [mask(V, bcs)])
    assert len(motions) == 1
    (m,) = motions
    assert (m.space, m.component) == (0, 0)
    assert m.description == "translation along (0, 1)"
    u = m.displacement(np.array([[0.0, 0.0], [2.0, 1.0], [1.3, 0.2]]))
    assert np.allclose(u[:, 0], 0.0, atol=1e-12) and np.allclose(u[:, 1], u[0, 1])
    assert "body 0 of space 0 (nodes in [0, 2] x [0, 1])" in m.describe()


@pytest.mark.parametrize("point", [(0.0, 0.0), (1.5, 0.75), (2.0, 1.0)])
def test_pin_leaves_rotation_about_pin(point):
    V = vector_space(block())
    bcs = [pin(V, point)]
    motions = check([V], [stiffness(V, bcs)], [mask(V, bcs)])
    assert len(motions) == 1
    (m,) = motions
    assert m.description.startswith("rotation about")
    far = np.array([[0.0, 1.0], [2.0, 0.0], [0.3, 0.4]])
    u = m.displacement(np.vstack([point, far]))
    scale = np.linalg.norm(u, axis=1).max()
    assert scale > 0
    assert np.linalg.norm(u[0]) <= 1e-10 * scale
    # A rotation about the pin: the displacement is orthogonal to x - pin.
    assert np.allclose(np.sum(u[1:] * (far - point), axis=1), 0.0, atol=1e-10 * scale)


def test_spring_supports_everything():
    V = vector_space(block())
    assert check([V], [stiffness(V, spring=1.0)], [mask(V)]) == []


def test_free_box_3d():
    mesh = dolfinx.mesh.create_box(comm, [[0.0, 0.0, 0.0], [2.0, 1.0, 1.0]], [4, 2, 2])
    V = vector_space(mesh)
    motions = check([V], [stiffness(V)], [mask(V)])
    assert [m.description for m in motions] == [
        "translation along (1, 0, 0)",
        "translation along (0, 1, 0)",
        "translation along (0, 0, 1)",
        "rotation about the axis (1, 0, 0) through (1, 0.5, 0.5)",
        "rotation about the axis (0, 1, 0) through (1, 0.5, 0.5)",
        "rotation about the axis (0, 0, 1) through (1, 0.5, 0.5)",
    ]
    bcs = [clamp(V)]
    assert check([V], [stiffness(V, bcs)], [mask(V, bcs)]) == []


def two_bodies():
    """Body 0: [0, 1] x [0, 0.5]; body 1: [1.5, 2.5] x [0, 1]."""
    return vector_space(rectangles_mesh(RECTANGLES[:2], 0.25))


def test_free_body_next_to_clamped_body():
    V = two_bodies()
    bcs = [clamp(V)]
    motions = check([V], [stiffness(V, bcs)], [mask(V, bcs)])
    assert len(motions) == 3
    assert all((m.space, m.component) == (0, 1) for m in motions)
    assert [m.description for m in motions[:2]] == [
        "translation along (1, 0)",
        "translation along (0, 1)",
    ]
    # About the centroid of the body's nodes, near its centre on an unstructured mesh.
    assert motions[2].description.startswith("rotation about (")
    u = motions[2].displacement(np.array([[2.0, 0.5], [2.5, 1.0]]))
    assert np.linalg.norm(u[0]) < 0.05 * np.linalg.norm(u[1])
    assert all("nodes in [1.5, 2.5] x [0, 1]" in m.describe() for m in motions)


def test_contact_rows_remove_translation_and_rotation():
    """Normal rows at two nodes of the free body's left edge leave its vertical motion."""
    V = two_bodies()
    bcs = [clamp(V)]
    rows = []
    for r, y in enumerate([0.0, 0.5]):
        rows += [(r, global_dof(V, (1.0, y), 0), 1.0), (r, global_dof(V, (1.5, y), 0), -1.0)]
    B = constraint_block(2, V, rows)
    motions = check([V], [stiffness(V, bcs)], [mask(V, bcs)], [[(0, B)]], [None])
    assert [(m.component, m.description) for m in motions] == [(1, "translation along (0, 1)")]


def test_inactive_rows_are_ignored():
    V = two_bodies()
    bcs = [clamp(V)]
    rows = []
    for r, y in enumerate([0.0, 0.5]):
        rows += [(r, global_dof(V, (1.0, y), 0), 1.0), (r, global_dof(V, (1.5, y), 0), -1.0)]
    B = constraint_block(2, V, rows)
    inactive = np.array([0, 1], dtype=np.int64) if comm.rank == 0 else np.zeros(0, np.int64)
    motions = check([V], [stiffness(V, bcs)], [mask(V, bcs)], [[(0, B)]], [inactive])
    assert len(motions) == 3 and all(m.component == 1 for m in motions)


def test_tie_across_spaces_leaves_rotation_about_tie():
    """Two spaces: a clamped block, and a free one tied to it at one node."""
    V0 = vector_space(dolfinx.mesh.create_rectangle(comm, [[0.0, 0.0], [1.0, 1.0]], [4, 4]))
    V1 = vector_space(dolfinx.mesh.create_rectangle(comm, [[1.0, 0.0], [2.0, 1.0]], [3, 5]))
    bcs = [clamp(V0)]
    tie = (1.0, 0.6)
    B0 = constraint_block(2, V0, [(k, global_dof(V0, (1.0, 0.5), k), -1.0) for k in range(2)])
    B1 = constraint_block(2, V1, [(k, global_dof(V1, tie, k), 1.0) for k in range(2)])
    motions = check(
        [V0, V1],
        [stiffness(V0, bcs), stiffness(V1)],
        [mask(V0, bcs), mask(V1)],
        [[(0, B0), (1, B1)]],
        [None],
    )
    assert len(motions) == 1
    (m,) = motions
    assert (m.space, m.component, len(m.motions)) == (1, 0, 1)
    assert m.description == "rotation about (1, 0.6)"
    u = m.displacement(np.array([tie, (2.0, 1.0)]))
    assert np.linalg.norm(u[0]) <= 1e-10 * np.linalg.norm(u[1])


def test_bodies_tied_together_float_together():
    """Two free bodies tied at two node pairs move together: 3 motions of both."""
    V = two_bodies()
    rows = []
    for r, (y, k) in enumerate([(0.0, 0), (0.0, 1), (0.5, 0)]):
        rows += [(r, global_dof(V, (1.0, y), k), 1.0), (r, global_dof(V, (1.5, y), k), -1.0)]
    B = constraint_block(3, V, rows)
    motions = check([V], [stiffness(V)], [mask(V)], [[(0, B)]], [None])
    assert len(motions) == 3
    for m in motions:
        assert sorted(p.component for p in m.motions) == [0, 1]
        assert "together with" in m.describe()
        # The tied displacements agree.
        body = {p.component: p for p in m.motions}
        for y, k in [(0.0, 0), (0.0, 1), (0.5, 0)]:
            u0 = body[0].displacement(np.array([[1.0, y]]))[0, k]
            u1 = body[1].displacement(np.array([[1.5, y]]))[0, k]
            assert abs(u0 - u1) <= 1e-10


# ----------------------------------------------------------------------------------------
# Redundant constraints (Eqs. 34-35)
# ----------------------------------------------------------------------------------------


def svd_redundancy(B: np.ndarray, free: np.ndarray, active: np.ndarray) -> tuple[int, int]:
    """(zero rows, dependent rows) of the active rows of B D, by dense SVD."""
    Bt = B[active] * free[None, :]
    norms = np.linalg.norm(Bt, axis=1)
    zero = norms <= np.sqrt(REDUNDANT_TOL) * np.linalg.norm(B[active], axis=1)
    rows = Bt[~zero] / norms[~zero, None]
    sigma = scipy.linalg.svdvals(rows)
    rank = int(np.count_nonzero(sigma > np.sqrt(REDUNDANT_TOL)))
    return int(zero.sum()), rows.shape[0] - rank


def random_constraints():
    """15 rows in 30 columns: 2 zero after elimination (rows 12, 13), 3 dependent."""
    rng = np.random.default_rng(7)
    B = np.zeros((15, 30))
    B[:10] = rng.standard_normal((10, 30)) * (rng.random((10, 30)) < 0.4)
    B[:10, rng.integers(3, 30, 10)] += 1.0  # no row supported on Dirichlet columns only
    B[10] = B[0]
    B[11] = 2 * B[1] - 3 * B[2]
    B[13, :3] = [1.0, -2.0, 0.5]  # Dirichlet columns only
    B[14] = 1e-3 * B[3]
    free = np.ones(30)
    free[:3] = 0.0
    return B, free


def split_blocks(B: np.ndarray, free: np.ndarray, at: int):
    blocks, masks = [], []
    for cols in (slice(0, at), slice(at, B.shape[1])):
        part = B[:, cols]
        entries = [(r, c, part[r, c]) for r, c in zip(*np.nonzero(part), strict=True)]
        blocks.append(constraint_block(B.shape[0], part.shape[1], entries))
        m = blocks[-1].createVecRight()
        start, end = m.getOwnershipRange()
        m.array[:] = free[cols][start:end]
        masks.append(m)
    return blocks, masks


@pytest.mark.parametrize("inactive", [[], [10], [10, 12, 14]])
def test_redundant_rows_of_random_matrix(inactive):
    B, free = random_constraints()
    active = np.ones(15, dtype=bool)
    active[inactive] = False
    zero, dependent = svd_redundancy(B, free, active)
    expected_zero = 2 - int(12 in inactive)
    expected_dependent = 3 - sum(r in inactive for r in (10, 14))
    assert (zero, dependent) == (expected_zero, expected_dependent)
    blocks, masks = split_blocks(B, free, 17)
    mine = np.array(inactive if comm.rank == comm.size - 1 else [], dtype=np.int64)
    count = redundant_constraints(blocks, masks, mine)
    assert count == Redundancy(int(active.sum()), zero, dependent)
    named = redundant_multipliers(blocks, masks, mine)
    assert len(named) == count.redundant
    sets = [set(n.tolist()) for n in named]
    expected = [{0, 10}, {1, 2, 11}, {3, 14}, {12}, {13}]
    for s in expected:
        if not s & set(inactive):
            assert s in sets
    for obj in blocks + masks:
        obj.destroy()


@pytest.mark.parametrize("second", [(0, 1), (1,)])
def test_redundant_rows_of_stacked_pairs(second):
    """Two pairs, each of full row rank or nearly, dependent together (the stacked rows'
    dense SVD is the reference); the second pair on both spaces or on space 1 only."""
    B, free = random_constraints()
    top, bottom = B[:10].copy(), B[10:].copy()
    if second == (1,):
        bottom[:, :17] = 0.0
    stacked = np.vstack([top, bottom])
    zero, dependent = svd_redundancy(stacked, free, np.ones(15, dtype=bool))
    # Rows 10 and 11 depend on rows 0-2 on both spaces, not on space 1 alone.
    assert dependent == (3 if second == (0, 1) else 0)
    top_blocks, masks = split_blocks(top, free, 17)
    bottom_blocks, bottom_masks = split_blocks(bottom, free, 17)
    constraints = [list(enumerate(top_blocks)), [(s, bottom_blocks[s]) for s in second]]
    count = joint_redundant_constraints(constraints, masks)
    assert count == Redundancy(15, zero, dependent)
    for part, blocks in [(top, top_blocks), (bottom, bottom_blocks)]:
        alone = svd_redundancy(part, free, np.ones(part.shape[0], dtype=bool))
        assert redundant_constraints(blocks, masks) == Redundancy(part.shape[0], *alone)
    # Every named group is a dependency of the stacked, eliminated rows.
    named = joint_redundant_multipliers(constraints, masks)
    assert len(named) == count.redundant
    eliminated = stacked * free[None, :]
    for group in named:
        rows = eliminated[group[:, 0] * 10 + group[:, 1]]
        assert np.linalg.matrix_rank(rows, tol=1e-6 * np.abs(rows).max(initial=1.0)) < len(group)
    for obj in top_blocks + bottom_blocks + masks + bottom_masks:
        obj.destroy()


def cycles(count: int, length: int, path: bool = False) -> np.ndarray:
    """Incidence rows e_i - e_(i+1) of ``count`` disjoint cycles (or paths) of ``length``."""
    rows = []
    for c in range(count):
        first = c * length
        for i in range(length - int(path)):
            rows.append((first + i, first + (i + 1) % length))
    B = np.zeros((len(rows), count * length))
    for r, (i, j) in enumerate(rows):
        B[r, i], B[r, j] = 1.0, -1.0
    return B


@pytest.mark.parametrize(
    ("path", "pinned", "expected"), [(False, False, 3), (False, True, 3), (True, True, 0)]
)
def test_redundant_rows_of_cycles(path, pinned, expected):
    """A cycle's incidence rows sum to zero: one dependent row per cycle, none on a path."""
    B = cycles(3, 150, path)
    free = np.ones(B.shape[1])
    if pinned:
        free[::150] = 0.0
    active = np.ones(B.shape[0], dtype=bool)
    assert svd_redundancy(B, free, active) == (0, expected)
    blocks, masks = split_blocks(B, free, 200)
    count = redundant_constraints(blocks, masks if pinned else None)
    assert count == Redundancy(B.shape[0], 0, expected)
    assert count.rank == B.shape[0] - expected
    for obj in blocks + masks:
        obj.destroy()


def test_cycle_dependencies_named():
    B = cycles(2, 5)
    blocks, masks = split_blocks(B, np.ones(10), 4)
    named = redundant_multipliers(blocks)
    assert sorted(sorted(n.tolist()) for n in named) == [[0, 1, 2, 3, 4], [5, 6, 7, 8, 9]]
    for obj in blocks + masks:
        obj.destroy()


def test_all_rows_inactive():
    B = cycles(1, 6)
    blocks, masks = split_blocks(B, np.ones(6), 3)
    assert redundant_constraints(blocks, masks, np.arange(6)) == Redundancy(0, 0, 0)
    for obj in blocks + masks:
        obj.destroy()

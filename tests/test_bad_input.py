# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Bad input as a DOLFINx user meets it: a clear exception, the same on every rank.

Every case starts from the README's model (one Gmsh model, both blocks in one mesh and
one space, the user's own forms) with one thing wrong. On two ranks the bad entity often
sits on one partition only; every rank must raise the same exception with the same
message, never hang, abort in PETSc or return a plausible wrong answer. Cases that
:mod:`tests.test_surface_and_pair_input` and :mod:`tests.test_system_checks` already
cover (missing, empty and interior tags, cell tags, a scalar space, a floating lower
block, redundant node-to-segment-gauss and two-pass constraints) are not repeated.
"""

import functools
import re

from mpi4py import MPI

import basix.ufl
import dolfinx
import numpy as np
import pytest
import readme_model
import ufl
from readme_model import LOWER, UPPER

from dolfinx_contact_s2s import Material, contact_pair, contact_pairs, contact_surface
from dolfinx_contact_s2s.problem import LinearContactProblem
from dolfinx_contact_s2s.unilateral import (
    ALGORITHMS,
    ContactConvergenceError,
    UnilateralContactProblem,
)

comm = MPI.COMM_WORLD

#: The README model as these tests build it: 7 and 5 elements along the contact lines.
readme_mesh = functools.partial(readme_model.readme_mesh, lower=7, upper=5, sides=3)


def solve_once(problem):
    """Solve ``problem`` and destroy it, also when the solve raises (its options leave the
    database: options a failed solve never read would be reported unused at exit)."""
    with problem:
        return problem.solve()


def readme_problem(
    mesh,
    facets,
    *,
    degree=1,
    E=1.0,
    load=(0.0, -1.0),
    directions=(0, 1),
    problem=LinearContactProblem,
    prefix="bad_",
    **pair_options,
):
    """The README problem on ``mesh``; ``E`` and ``load`` enter the user's forms.

    ``directions`` lists the Dirichlet conditions kept: 0 holds both left sides
    horizontally, 1 the lower block's bottom vertically.
    """
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    E = dolfinx.fem.Constant(mesh, float(E))
    nu = 0.3
    mu, lmbda = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))

    def sigma(w):
        eps = ufl.sym(ufl.grad(w))
        return 2 * mu * eps + lmbda * ufl.tr(eps) * ufl.Identity(2)

    a = ufl.inner(sigma(u), ufl.sym(ufl.grad(v))) * ufl.dx
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets)
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.array(load, dtype=float)), v) * ds(UPPER["top"])
    bcs = []
    if 0 in directions:
        left = np.concatenate([facets.find(LOWER["left"]), facets.find(UPPER["left"])])
        dofs = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, left)
        bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(0)))
    if 1 in directions:
        dofs = dolfinx.fem.locate_dofs_topological(V.sub(1), 1, facets.find(LOWER["bottom"]))
        bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(1)))
    contactor = contact_surface(V, facets, UPPER["bottom"])
    target = contact_surface(V, facets, LOWER["top"])
    pairs = contact_pairs(contactor, target, **pair_options)
    return problem(a, L, pairs, bcs, petsc_options_prefix=prefix)


def raises_everywhere(exception, pattern, call, *args, **kwargs):
    """``call`` raises ``exception`` matching ``pattern``, with one message on every rank.

    The comparison follows a collective (allgather) that every rank reaches, raised or
    not, so a rank that does not raise fails the test instead of hanging the others.
    """
    message = None
    try:
        call(*args, **kwargs)
    except exception as e:
        message = str(e)
    messages = comm.allgather(message)
    assert all(m is not None for m in messages), f"not raised on every rank: {messages}"
    assert len(set(messages)) == 1, f"the ranks disagree: {messages}"
    assert re.search(pattern, messages[0]), messages[0]
    return messages[0]


def first_rank_with(mask):
    """The lowest rank where ``mask`` has a True entry (the same on every rank), else -1."""
    found = comm.allreduce(comm.rank if np.any(mask) else comm.size, op=MPI.MIN)
    return found if found < comm.size else -1


def contact_nodes(mesh, facets, tag):
    """Geometry nodes of the owned facets marked ``tag`` (process-local indices)."""
    fdim = mesh.topology.dim - 1
    owned = mesh.topology.index_map(fdim).size_local
    marked = facets.find(tag)
    marked = marked[marked < owned]
    if marked.size == 0:  # DOLFINx 0.9's entities_to_geometry divides by zero on none
        return np.empty(0, dtype=np.int32)
    return np.unique(dolfinx.mesh.entities_to_geometry(mesh, fdim, marked, False))


@pytest.fixture(scope="module")
def model():
    return readme_mesh()


# --- the material ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("E", "nu", "cause"),
    [
        (0.0, 0.3, "Young's modulus"),
        (-1.0, 0.3, "Young's modulus"),
        (np.nan, 0.3, "Young's modulus"),
        (np.inf, 0.3, "Young's modulus"),
        (1.0, 0.5, "Poisson's ratio"),
        (1.0, -1.0, "Poisson's ratio"),
        (1.0, 0.7, "Poisson's ratio"),
        (1.0, np.nan, "Poisson's ratio"),
    ],
)
def test_material_out_of_range(E, nu, cause):
    raises_everywhere(ValueError, cause, Material, E=E, nu=nu)


@pytest.mark.parametrize("E", [np.nan, np.inf])
def test_non_finite_material_in_the_users_form(model, E):
    """E = nan or inf in the user's own form (not the package's Material)."""
    mesh, facets = model
    raises_everywhere(
        ValueError,
        r"stiffness matrix K of space 0 has NaN or infinite entries.*form a\[0\]",
        lambda: solve_once(readme_problem(mesh, facets, E=E, prefix="nan_e_")),
    )


def test_non_finite_load(model):
    mesh, facets = model
    raises_everywhere(
        ValueError,
        r"load vector F of space 0 has NaN",
        lambda: solve_once(readme_problem(mesh, facets, load=(0.0, np.nan), prefix="nan_f_")),
    )


# --- coordinates ----------------------------------------------------------------------


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_contact_node_on_one_partition(value):
    """NaN in a contactor node, set on one rank only: every rank raises at contact_surface."""
    mesh, facets = readme_mesh()
    nodes = contact_nodes(mesh, facets, UPPER["bottom"])
    rank = first_rank_with(nodes.size > 0)
    if comm.rank == rank:
        mesh.geometry.x[nodes[0], 1] = value
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    contact_surface(V, facets, LOWER["top"])  # the other surface is fine
    raises_everywhere(
        ValueError,
        r"contact surface 20: the cells of 1 facet\(s\) have a node with NaN or infinite",
        contact_surface,
        V,
        facets,
        UPPER["bottom"],
    )


def test_non_finite_node_away_from_contact():
    """NaN at the top of the upper block, on one rank only: the problem refuses the mesh."""
    mesh, facets = readme_mesh()
    x = mesh.geometry.x
    owned = mesh.geometry.index_map().size_local
    top = np.flatnonzero(np.isclose(x[:owned, 1], 1.0))
    rank = first_rank_with(top.size > 0)
    if comm.rank == rank:
        x[top[0], 0] = np.nan
    raises_everywhere(
        ValueError,
        r"the mesh of space 0 has 1 node\(s\) with NaN or infinite coordinates",
        readme_problem,
        mesh,
        facets,
        prefix="nan_x_",
    )


def test_zero_length_contact_facet():
    """Two contactor nodes made to coincide (on every rank that holds them)."""
    mesh, facets = readme_mesh()
    x = mesh.geometry.x
    # The contactor nodes at x = 0.4 and 0.6 (5 elements on [0, 1]) meet at 0.5.
    for x0 in (0.4, 0.6):
        x[np.isclose(x[:, 0], x0) & np.isclose(x[:, 1], 0.5) & (x[:, 2] == 0), 0] = 0.5
    # Both blocks have nodes on y = 0.5; the lower's at 0, 1/7, ..., none at 0.4 or 0.6.
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    raises_everywhere(
        ValueError,
        r"contact surface 20: 1 facet\(s\) have zero length .* at \(0\.5, 0\.5\)",
        contact_surface,
        V,
        facets,
        UPPER["bottom"],
    )


@pytest.mark.parametrize("quads", [False, True])
def test_inverted_cells_pass_the_patch_test(quads):
    """Every cell inverted (the mesh mirrored, x -> 1 - x: clockwise cells, det J < 0).

    DOLFINx integrates with |det J|, and the outward normal J^-T n_ref points out of the
    cell whatever the sign of det J: a valid input, which must give the patch test's
    constant pressure p = 1 (not an error, and not a silently flipped normal).
    """
    mesh, facets = readme_mesh(quads=quads)
    mesh.geometry.x[:, 0] = 1.0 - mesh.geometry.x[:, 0]
    with readme_problem(mesh, facets, prefix="mirror_") as problem:
        (_,), (pressure,) = problem.solve()
        owned = pressure.function_space.dofmap.index_map.size_local
        error = float(np.max(np.abs(pressure.x.array[:owned] - 1.0), initial=0.0))
        assert comm.allreduce(error, op=MPI.MAX) < 1e-10


# --- tags -----------------------------------------------------------------------------


def test_tags_of_another_mesh(model):
    mesh, _ = model
    _, other_facets = readme_mesh()
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    raises_everywhere(
        ValueError, "facet_tags belong to another mesh", contact_surface, V, other_facets, 20
    )


def test_vertex_tags_are_not_facet_tags(model):
    mesh, _ = model
    owned = mesh.topology.index_map(0).size_local
    vertices = np.arange(min(owned, 3), dtype=np.int32)
    tags = dolfinx.mesh.meshtags(mesh, 0, vertices, np.full(vertices.size, 20, dtype=np.int32))
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    raises_everywhere(ValueError, r"must mark facets \(dimension 1\)", contact_surface, V, tags, 20)


# --- spaces and cells -----------------------------------------------------------------


@pytest.mark.parametrize(
    ("create", "pattern"),
    [
        (
            lambda: dolfinx.mesh.create_unit_cube(comm, 1, 1, 1),
            r"no facet of the mesh carries contact tag 1",
        ),
        (
            lambda: dolfinx.mesh.create_unit_cube(comm, 1, 1, 1, dolfinx.mesh.CellType.hexahedron),
            r"no facet of the mesh carries contact tag 1",
        ),
        (
            lambda: dolfinx.mesh.create_unit_cube(comm, 1, 1, 1, dolfinx.mesh.CellType.prism),
            r"3D tetrahedron and hexahedron meshes, not prism \(tdim 3",
        ),
    ],
    ids=["tetrahedron", "hexahedron", "prism"],
)
def test_three_dimensional_cells(create, pattern):
    """Tetrahedra and hexahedra are contact bodies (here without the tag); prisms are not."""
    mesh = create()
    mesh.topology.create_entities(2)
    # The cell type is refused before the tags are read: no tagged facet is needed (and
    # DOLFINx 0.11 finds the exterior facets of a prism mesh per facet type only).
    none = np.empty(0, dtype=np.int32)
    tags = dolfinx.mesh.meshtags(mesh, mesh.topology.dim - 1, none, none)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    raises_everywhere(ValueError, pattern, contact_surface, V, tags, 1)


def test_surface_mesh_in_space():
    """Triangles in 3D (gdim 3, a shell): not a plane problem."""
    if comm.rank == 0:
        x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1]], dtype=float)
        cells = np.array([[0, 1, 2], [1, 3, 2]], dtype=np.int64)
    else:
        x, cells = np.empty((0, 3)), np.empty((0, 3), dtype=np.int64)
    element = basix.ufl.element("Lagrange", "triangle", 1, shape=(3,))
    mesh = dolfinx.mesh.create_mesh(comm, cells=cells, x=x, e=element)
    mesh.topology.create_connectivity(1, 2)
    boundary = dolfinx.mesh.exterior_facet_indices(mesh.topology)
    tags = dolfinx.mesh.meshtags(mesh, 1, boundary, np.full(boundary.size, 1, dtype=np.int32))
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    raises_everywhere(
        ValueError, r"in the plane .* not triangle \(tdim 2, gdim 3\)", contact_surface, V, tags, 1
    )


def test_mixed_cell_types():
    """Triangles in one block, quadrilaterals in the other: DOLFINx 0.9's Gmsh reader
    aborts MPI on such a model; the package's reader raises on every rank first."""
    raises_everywhere(
        ValueError,
        r"the Gmsh model mixes 'Quadrilateral 4' and 'Triangle 3' cells",
        readme_mesh,
        quads="upper",
    )


@pytest.mark.parametrize(
    ("element", "pattern"),
    [
        (("Lagrange", 3, (2,)), "degree 1 or 2"),
        (("Discontinuous Lagrange", 1, (2,)), "continuous Lagrange"),
        (("Lagrange", 1, (2, 2)), "one component per dimension"),
        (("Lagrange", 1, (3,)), "one component per dimension"),
    ],
    ids=["P3", "DG1", "tensor", "three-components"],
)
def test_unsupported_space(model, element, pattern):
    mesh, facets = model
    V = dolfinx.fem.functionspace(mesh, element)
    raises_everywhere(ValueError, pattern, contact_surface, V, facets, UPPER["bottom"])


# --- multipliers and methods ----------------------------------------------------------


@pytest.fixture(scope="module")
def surfaces(model):
    mesh, facets = model
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    return contact_surface(V, facets, UPPER["bottom"]), contact_surface(V, facets, LOWER["top"])


@pytest.mark.parametrize(
    ("options", "pattern"),
    [
        ({"multiplier": ("N1curl", 1)}, "multiplier family must be 'Lagrange' or 'DG'"),
        ({"multiplier": ("Lagrange", 0)}, "continuous multiplier needs degree 1"),
        ({"multiplier": ("DG", -1)}, "integer >= 0"),
        ({"multiplier": ("DG", 1.5)}, "integer >= 0"),
        (
            {"method": "node-to-segment", "multiplier": ("DG", 0)},
            "one multiplier on every contactor node",
        ),
        (
            {"method": "node-to-segment", "multiplier": ("Lagrange", 2)},
            "one multiplier on every contactor node",
        ),
        (
            {"method": "intermediate-surface", "multiplier": ("DG", 0)},
            "defines its own multiplier space",
        ),
        (
            {"method": "node-to-segment-gauss", "quadrature": "composite-gauss"},
            "constrains the contactor's Gauss points",
        ),
        (
            {"method": "intermediate-surface", "quadrature": "gauss"},
            "integrates its own segments exactly",
        ),
        ({"method": "mortar"}, "unknown contact method 'mortar'"),
        ({"quadrature": "simpson"}, "unknown quadrature 'simpson'"),
        ({"quadrature_points": 0}, "a Gauss rule needs at least one point"),
        ({"search_radius": np.nan}, "search_radius must be positive and finite"),
        ({"search_radius": -0.1}, "search_radius must be positive and finite"),
    ],
)
def test_unusable_choices(surfaces, options, pattern):
    raises_everywhere(ValueError, pattern, contact_pair, *surfaces, **options)


def test_intermediate_surface_on_quadratic_elements(model):
    mesh, facets = model
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2, (2,)))
    up, low = contact_surface(V, facets, UPPER["bottom"]), contact_surface(V, facets, LOWER["top"])
    raises_everywhere(
        ValueError, "linear 2D surfaces", contact_pair, up, low, method="intermediate-surface"
    )


def test_node_to_node_on_non_coincident_nodes(surfaces):
    """The README mesh: 5 contactor and 7 target elements, no shared node positions."""
    raises_everywhere(
        ValueError, "needs coincident nodes", contact_pair, *surfaces, method="node-to-node"
    )


# --- singular saddle points -----------------------------------------------------------


@pytest.mark.parametrize(
    ("directions", "motions"),
    [
        ((), ["space 0", "translation"]),  # nothing holds either block
        ((1,), ["space 0", "translation"]),  # no horizontal condition: both slide
    ],
    ids=["no-dirichlet", "no-horizontal"],
)
def test_missing_dirichlet_conditions(model, directions, motions):
    mesh, facets = model
    message = raises_everywhere(
        ValueError,
        r"the problem is singular: these rigid motions",
        lambda: solve_once(readme_problem(mesh, facets, directions=directions, prefix="free_")),
    )
    for word in motions:
        assert word in message


def test_redundant_pairs_both_ways(model):
    """Each block a contactor of the other: two multiplier fields for one constraint."""
    mesh, facets = model
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    up, low = contact_surface(V, facets, UPPER["bottom"]), contact_surface(V, facets, LOWER["top"])
    a = Material().forms(V)[0]
    L = ufl.inner(dolfinx.fem.Constant(mesh, np.zeros(2)), ufl.TestFunction(V)) * ufl.dx
    bottom = dolfinx.fem.locate_dofs_topological(V, 1, facets.find(LOWER["bottom"]))
    left = dolfinx.fem.locate_dofs_topological(V.sub(0), 1, facets.find(UPPER["left"]))
    bcs = [
        dolfinx.fem.dirichletbc(np.zeros(2), bottom, V),
        dolfinx.fem.dirichletbc(0.0, left, V.sub(0)),
    ]
    pairs = contact_pairs(up, low) + contact_pairs(low, up)

    def solve():
        with LinearContactProblem(a, L, pairs, bcs, petsc_options_prefix="twice_") as problem:
            problem.solve()

    message = raises_everywhere(ValueError, r"redundant constraint", solve)
    assert "pair 0" in message and "pair 1" in message


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_body_held_only_by_contact_that_opens(model, algorithm):
    """Unilateral contact, the upper block pulled up: the contact opens and it floats.

    The assembly's support check passes (every contact row is active there); once the
    active set (for the penalty methods, the penalized rows; for SNES's VI solver, the
    complementarity test's set) releases every row, the upper block is free to translate
    vertically: each algorithm raises, naming the body and the motion, instead of
    solving a singular system or iterating to its limit.
    """
    mesh, facets = model

    def solve():
        with readme_problem(
            mesh,
            facets,
            load=(0.0, 1.0),
            problem=functools.partial(UnilateralContactProblem, algorithm=algorithm),
            prefix=f"open_{algorithm.replace('-', '_')}_",
            **({"multiplier": ("Dual", 1)} if algorithm == "dual-active-set" else {}),
        ) as problem:
            problem.solve()

    message = raises_everywhere(
        ContactConvergenceError,
        r"solve \d+ at load 1: the active set leaves these rigid motions free",
        solve,
    )
    assert "body 1 of space 0 (nodes in [0, 1] x [0.5, 1])" in message
    assert "translation along (0, 1)" in message

"""Finite deformation in 3D: the large-sliding patch test with neo-Hookean blocks.

Issue [5/6], large-sliding patch test, also in 3D. A compressible neo-Hookean block
[0, 1] x [0, 1] x [1/2, 1] (E = 2, nu = 0.25) pressed by a uniform pressure P onto a
longer one [-1, 2] x [0, 1] x [0, 1/2] (E = 1, nu = 0.3), meshed independently
(non-matching in x and in y), frictionless and unilateral, then slid along x by more than
five of its contact elements in several steps. Every lateral face is held in its normal
direction (the upper block's x-faces at the slide), the lower bottom in z, so every state
on the way is homogeneous uniaxial strain: F = diag(1, 1, beta) in each block, with the
nominal stress

    P_zz(beta) = mu (beta - 1 / beta) + lambda ln(beta) / beta = -P

of psi = mu / 2 (tr C - 3) - mu ln J + lambda / 2 (ln J)^2 (``paper.large_sliding``'s
energy and root find, as in 2D). The pressure on the top is a dead load: no lateral
stretch and a horizontal top, so the nominal load is the Cauchy one, and the Cauchy
stress sigma_zz = P_zz. The part of the lower top the upper block leaves open carries P
too (whole lower facets: slides are whole lower elements). The contact pressure, the
Cauchy traction on the current contactor (the upper bottom), is P at every step.

P1 on hexahedra (6 x 2 x 1 upper against 21 x 3 x 1 lower cells). P2 on tetrahedra with a
quadratic geometry (``curved_mesh``: the surfaces follow X + u only with the geometry of
the displacement's degree) and a P1 multiplier (P2 multipliers on triangular faces have
vertex functions of zero integral, which unilateral contact refuses).
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.finite import NonlinearContactProblem
from dolfinx_contact_s2s.meshing import curved_mesh
from paper.large_sliding import neo_hookean, newton_order_probe, stretch

comm = MPI.COMM_WORLD

#: The pressure and the materials (E, nu) of the lower and the upper block.
P = 0.2
MATERIALS = ((1.0, 0.3), (2.0, 0.25))
#: The blocks ((x0, y0, z0), (x1, y1, z1)) and their cells across (x, y, z), per cell type.
BOXES = (((-1.0, 0.0, 0.0), (2.0, 1.0, 0.5)), ((0.0, 0.0, 0.5), (1.0, 1.0, 1.0)))
CELLS = {
    "hexahedron": ((21, 3, 1), (6, 2, 1)),
    "tetrahedron": ((21, 2, 1), (6, 1, 1)),
}
#: Facet tags: bottom, top, the x-faces and the y-faces.
BOTTOM, TOP, LEFT, RIGHT, FRONT, BACK = 1, 2, 3, 4, 5, 6


def block(k: int, cell: str, degree: int):
    """Block ``k`` (0 lower, 1 upper), its faces tagged; P2 gets a quadratic geometry."""
    (x0, y0, z0), (x1, y1, z1) = BOXES[k]
    mesh = dolfinx.mesh.create_box(
        comm,
        [np.array(BOXES[k][0]), np.array(BOXES[k][1])],
        list(CELLS[cell][k]),
        getattr(dolfinx.mesh.CellType, cell),
    )
    markers = [
        (BOTTOM, lambda x: np.isclose(x[2], z0)),
        (TOP, lambda x: np.isclose(x[2], z1)),
        (LEFT, lambda x: np.isclose(x[0], x0)),
        (RIGHT, lambda x: np.isclose(x[0], x1)),
        (FRONT, lambda x: np.isclose(x[1], y0)),
        (BACK, lambda x: np.isclose(x[1], y1)),
    ]
    found = [(dolfinx.mesh.locate_entities_boundary(mesh, 2, f), t) for t, f in markers]
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([np.full(f.size, t, dtype=np.int32) for f, t in found])
    order = np.argsort(facets, kind="stable")
    tags = dolfinx.mesh.meshtags(mesh, 2, facets[order], values[order])
    if degree == 2:
        cells = np.arange(mesh.topology.index_map(3).size_local, dtype=np.int32)
        mesh, _, tags = curved_mesh(
            mesh, dolfinx.mesh.meshtags(mesh, 3, cells, np.ones_like(cells)), tags
        )
    return mesh, tags


class SlidingScene3D:
    """The two blocks: residuals, loads and conditions (collective).

    The lower top the upper block leaves open carries P (a DG0 factor on the cells at
    the lower top, updated with the slide).
    """

    def __init__(self, cell: str, degree: int):
        """Build both blocks."""
        self.F, self.u, self.bcs, self.spaces, self.tags = [], [], [], [], []
        for k in (0, 1):
            mesh, tags = block(k, cell, degree)
            V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
            u = dolfinx.fem.Function(V, name=f"u{k}")
            v = ufl.TestFunction(V)
            ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
            load = dolfinx.fem.Function(dolfinx.fem.functionspace(mesh, ("DG", 0)))
            load.x.array[:] = P if k == 1 else 0.0
            energy = neo_hookean(u, *MATERIALS[k]) * ufl.dx
            self.F.append(ufl.derivative(energy, u, v) + load * v[2] * ds(TOP))
            held = [(1, FRONT, 0.0), (1, BACK, 0.0)]
            if k == 0:
                self.load, self.lower_top = load, self._top_cells(mesh, tags)
                held += [(0, LEFT, 0.0), (0, RIGHT, 0.0), (2, BOTTOM, 0.0)]
            else:
                self.slide = dolfinx.fem.Constant(mesh, 0.0)
                held += [(0, LEFT, self.slide), (0, RIGHT, self.slide)]
            for component, tag, value in held:
                dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 2, tags.find(tag))
                self.bcs.append(dolfinx.fem.dirichletbc(value, dofs, V.sub(component)))
            self.u.append(u)
            self.spaces.append(V)
            self.tags.append(tags)
        self.multiplier = ("Lagrange", 1) if degree == 2 and cell == "tetrahedron" else None

    @staticmethod
    def _top_cells(mesh: dolfinx.mesh.Mesh, tags: dolfinx.mesh.MeshTags) -> tuple:
        """The cells of the top's facets and the facets' midpoints' x."""
        mesh.topology.create_connectivity(2, 3)
        f_to_c = mesh.topology.connectivity(2, 3)
        facets = tags.find(TOP)
        cells = np.array([f_to_c.links(f)[0] for f in facets], dtype=np.int32)
        return cells, dolfinx.mesh.compute_midpoints(mesh, 2, facets)[:, 0]

    def set_slide(self, shift: float) -> None:
        """Move the upper block's x-faces to ``shift`` and load the open lower top."""
        self.slide.value = shift
        cells, x = self.lower_top
        self.load.x.array[cells] = np.where((x < shift) | (x > 1 + shift), P, 0.0)
        self.load.x.scatter_forward()

    def pair(self):
        """The upper bottom (contactor) on the lower top."""
        target = contact_surface(self.spaces[0], self.tags[0], TOP)
        contactor = contact_surface(self.spaces[1], self.tags[1], BOTTOM)
        return contact_pair(contactor, target, multiplier=self.multiplier)

    def errors(self, lam: dolfinx.fem.Function, shift: float) -> tuple[float, float]:
        """The largest |lambda - P| / P, and |u - u_exact| over the largest |u_exact|."""
        n = lam.function_space.dofmap.index_map.size_local
        lam_error = np.max(np.abs(lam.x.array[:n] - P), initial=0.0) / P
        beta = [stretch(*m, P) for m in MATERIALS]
        error, scale = 0.0, 0.0
        for k, (V, u) in enumerate(zip(self.spaces, self.u, strict=True)):
            X = V.tabulate_dof_coordinates()
            exact = np.zeros_like(X)
            if k == 0:
                exact[:, 2] = (beta[0] - 1) * X[:, 2]
            else:
                exact[:, 0] = shift
                exact[:, 2] = (beta[0] - 1) * 0.5 + (beta[1] - 1) * (X[:, 2] - 0.5)
            m = V.dofmap.index_map.size_local
            found = u.x.array[: 3 * m].reshape(-1, 3)
            error = max(error, float(np.max(np.abs(found - exact[:m]), initial=0.0)))
            scale = max(scale, float(np.max(np.abs(exact[:m]), initial=0.0)))
        lam_error, error, scale = (
            comm.allreduce(float(x), op=MPI.MAX) for x in (lam_error, error, scale)
        )
        return lam_error, error / scale


@pytest.mark.parametrize(
    "cell, degree",
    [("hexahedron", 1), pytest.param("tetrahedron", 2, marks=pytest.mark.slow)],
)
def test_large_sliding_patch_test_3d(cell, degree):
    """Pressed, then slid by 6 lower elements (36/7 upper contact elements): lambda = P.

    Slides of two lower elements (1/7) at a time: the open part of the lower top is
    whole facets.
    """
    scene = SlidingScene3D(cell, degree)
    h = (BOXES[0][1][0] - BOXES[0][0][0]) / CELLS[cell][0][0]
    with NonlinearContactProblem(
        scene.F,
        scene.u,
        [scene.pair()],
        scene.bcs,
        max_iterations=60,
        petsc_options_prefix=f"sliding3d_{degree}_",
    ) as problem:
        for k in (0, 2, 4, 6):
            shift = k * h
            scene.set_slide(shift)
            _, (lam,) = problem.solve()
            lam_error, u_error = scene.errors(lam, shift)
            assert lam_error <= 1e-9
            assert u_error <= 1e-9
            if k == 0:
                continue
            # Newton with the coupling's change in its matrix: quadratic on each slide
            # (without it, linear convergence takes over 20 iterations here).
            assert len(problem.step.iterations) <= 7
            assert max(problem.step.orders, default=0.0) > 1.8
        # And from starts at known distances of the last slide's solution (one C).
        probe = newton_order_probe(problem)
        assert probe["settled"]
        assert probe["order"] > 1.8

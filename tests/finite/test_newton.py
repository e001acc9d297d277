"""Finite deformation: Newton on neo-Hookean blocks in contact on the current configuration.

The large-sliding patch test of issue [5/6]: a neo-Hookean upper block pressed by a
uniform pressure P and slid over a wider lower block, frictionless and unilateral; the
lateral sides held in x (uniaxial strain, so every state on the way is homogeneous:
F = diag(1, beta) in each block, with P_yy(beta) = -P). The contact pressure (the Cauchy
traction on the current contact surface) equals P at every step.
"""

from mpi4py import MPI

import dolfinx
import numpy as np
import pytest
import scipy.optimize
import ufl

from dolfinx_contact_s2s import contact_pair, contact_surface
from dolfinx_contact_s2s.finite import NonlinearContactProblem, NonlinearConvergenceError
from dolfinx_contact_s2s.meshing import curved_mesh

comm = MPI.COMM_WORLD

P = 0.2
MATERIALS = ((1.0, 0.3), (2.0, 0.25))  # (E, nu) of the lower and the upper block
EXPOSED, TOP, BOTTOM, LEFT, RIGHT = 5, 2, 1, 4, 3


def lame(E: float, nu: float) -> tuple[float, float]:
    return E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))


def neo_hookean(u: dolfinx.fem.Function, E: float, nu: float) -> ufl.Form:
    """Residual of a compressible neo-Hookean solid in plane strain (a user's own form)."""
    mu, lmbda = lame(E, nu)
    v = ufl.TestFunction(u.function_space)
    F = ufl.Identity(2) + ufl.grad(u)
    J = ufl.det(F)
    C = F.T * F
    energy = mu / 2 * (ufl.tr(C) + 1 - 3) - mu * ufl.ln(J) + lmbda / 2 * ufl.ln(J) ** 2
    return ufl.derivative(energy * ufl.dx, u, v)


def stretch(E: float, nu: float, p: float) -> float:
    """beta of uniaxial strain F = diag(1, beta) with P_yy = -p (the exact state)."""
    mu, lmbda = lame(E, nu)
    return scipy.optimize.brentq(lambda b: mu * (b - 1 / b) + lmbda * np.log(b) / b + p, 0.2, 1.0)


def block(lower: bool, degree: int):
    """A block, tagged; P2 gets a quadratic geometry (the current facets follow u)."""
    box = [[-1.0, 0.0], [2.0, 0.5]] if lower else [[0.0, 0.5], [1.0, 1.0]]
    mesh = dolfinx.mesh.create_rectangle(comm, box, [39, 4] if lower else [9, 4])
    (x0, y0), (x1, y1) = box
    markers = [
        (TOP, lambda x: np.isclose(x[1], y1)),
        (BOTTOM, lambda x: np.isclose(x[1], y0)),
        (LEFT, lambda x: np.isclose(x[0], x0)),
        (RIGHT, lambda x: np.isclose(x[0], x1)),
    ]
    found = [(dolfinx.mesh.locate_entities_boundary(mesh, 1, f), t) for t, f in markers]
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([np.full(f.size, t, dtype=np.int32) for f, t in found])
    order = np.argsort(facets, kind="stable")
    tags = dolfinx.mesh.meshtags(mesh, 1, facets[order], values[order])
    if degree == 2:
        imap = mesh.topology.index_map(2)
        cells = np.arange(imap.size_local, dtype=np.int32)
        ctags = dolfinx.mesh.meshtags(mesh, 2, cells, np.ones_like(cells))
        mesh, _, tags = curved_mesh(mesh, ctags, tags)
    return mesh, tags


class SlidingScene:
    """The two blocks, their neo-Hookean residuals, loads and conditions.

    The lower top the upper block leaves open carries P (a DG0 factor on the cells at
    the top, updated with the slide: slides are whole lower elements, 1/13, so the open
    part is whole facets).
    """

    def __init__(self, degree: int):
        self.F, self.u, self.bcs, self.spaces, self.tags = [], [], [], [], []
        for k, lower in enumerate((True, False)):
            mesh, tags = block(lower, degree)
            V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
            u = dolfinx.fem.Function(V, name=f"u{k}")
            v = ufl.TestFunction(V)
            ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
            load = dolfinx.fem.Function(dolfinx.fem.functionspace(mesh, ("DG", 0)))
            load.x.array[:] = 0.0 if lower else P
            # P_nominal = P: no lateral stretch, the top stays horizontal.
            self.F.append(neo_hookean(u, *MATERIALS[k]) + load * v[1] * ds(TOP))
            if lower:
                self.load, self.lower_top = load, self._top_cells(mesh, tags)
                fixed = [(0, LEFT, 0.0), (0, RIGHT, 0.0), (1, BOTTOM, 0.0)]
            else:
                self.slide = dolfinx.fem.Constant(mesh, 0.0)
                fixed = [(0, LEFT, self.slide), (0, RIGHT, self.slide)]
            for component, tag, value in fixed:
                dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 1, tags.find(tag))
                self.bcs.append(dolfinx.fem.dirichletbc(value, dofs, V.sub(component)))
            self.u.append(u)
            self.spaces.append(V)
            self.tags.append(tags)

    @staticmethod
    def _top_cells(mesh, tags):
        """The cells on the lower top and their facet midpoints' x."""
        mesh.topology.create_connectivity(1, 2)
        f_to_c = mesh.topology.connectivity(1, 2)
        facets = tags.find(TOP)
        cells = np.array([f_to_c.links(f)[0] for f in facets], dtype=np.int32)
        x = dolfinx.mesh.compute_midpoints(mesh, 1, facets)[:, 0]
        return cells, x

    def set_slide(self, shift: float) -> None:
        self.slide.value = shift
        cells, x = self.lower_top
        self.load.x.array[cells] = np.where((x < shift) | (x > 1 + shift), P, 0.0)
        self.load.x.scatter_forward()

    def pair(self, method: str = "segment-to-segment"):
        target = contact_surface(self.spaces[0], self.tags[0], TOP)
        contactor = contact_surface(self.spaces[1], self.tags[1], BOTTOM)
        return contact_pair(contactor, target, method=method)

    def errors(self, lam, shift):
        """max |lambda - P| / P and max |u - u_exact| (the homogeneous state)."""
        n = lam.function_space.dofmap.index_map.size_local
        lam_error = np.max(np.abs(lam.x.array[:n] - P), initial=0.0) / P
        beta = [stretch(*m, P) for m in MATERIALS]
        u_error = 0.0
        for k, (V, u) in enumerate(zip(self.spaces, self.u, strict=True)):
            X = V.tabulate_dof_coordinates()[:, :2]
            if k == 0:
                exact = np.stack([0 * X[:, 0], (beta[0] - 1) * X[:, 1]], axis=1)
            else:
                y = (beta[0] - 1) * 0.5 + (beta[1] - 1) * (X[:, 1] - 0.5)
                exact = np.stack([shift + 0 * X[:, 0], y], axis=1)
            m = V.dofmap.index_map.size_local
            u_error = max(u_error, np.max(np.abs(u.x.array[: 2 * m].reshape(-1, 2) - exact[:m])))
        return (
            comm.allreduce(float(lam_error), op=MPI.MAX),
            comm.allreduce(float(u_error), op=MPI.MAX),
        )


@pytest.mark.parametrize("degree", [1, 2])
def test_large_sliding_patch_test(degree):
    """Pressed, then slid by 8 lower elements (5.5 upper contact elements): lambda = P."""
    scene = SlidingScene(degree)
    with NonlinearContactProblem(
        scene.F,
        scene.u,
        [scene.pair()],
        scene.bcs,
        max_iterations=60,
        petsc_options_prefix="sliding_nl_",
    ) as problem:
        for k in (0, 2, 4, 6, 8):
            shift = k / 13
            scene.set_slide(shift)
            _, (lam,) = problem.solve()
            lam_error, u_error = scene.errors(lam, shift)
            assert lam_error <= 1e-9
            assert u_error <= 1e-9
            # Newton with the coupling's change in its matrix: quadratic once the step's
            # first iteration has moved to the new slide.
            assert len(problem.step.iterations) <= 7
            assert max(problem.step.orders) > 1.8


def test_large_sliding_node_to_segment_fails_the_patch_test():
    """Node-to-segment on the same meshes and slides: the patch test fails (section 4.2)."""
    scene = SlidingScene(1)
    with NonlinearContactProblem(
        scene.F,
        scene.u,
        [scene.pair("node-to-segment")],
        scene.bcs,
        max_iterations=60,
        linearization="frozen",
        petsc_options_prefix="sliding_nts_",
    ) as problem:
        for k in (0, 8):
            scene.set_slide(k / 13)
            problem.solve()
            _, u_error = scene.errors(problem.multipliers[0], k / 13)
            assert u_error > 1e-4


def pressed_blocks(angle: float, delta: float = 0.04):
    """Two neo-Hookean blocks, the lower bottom clamped, the upper top moved down by delta.

    The whole scene (meshes and motions) turned by ``angle`` about the origin.
    """
    R = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    F, u, bcs, spaces, tags_of, motions = [], [], [], [], [], []
    for k, (box, n) in enumerate(
        ((((0.0, 0.0), (1.0, 0.5)), (7, 4)), (((0.2, 0.5), (0.8, 1.0)), (5, 4)))
    ):
        mesh = dolfinx.mesh.create_rectangle(comm, [np.array(box[0]), np.array(box[1])], list(n))
        y0, y1 = box[0][1], box[1][1]
        markers = [(TOP, y1), (BOTTOM, y0)]
        found = [
            (dolfinx.mesh.locate_entities_boundary(mesh, 1, lambda x, y=y: np.isclose(x[1], y)), t)
            for t, y in markers
        ]
        facets = np.concatenate([f for f, _ in found])
        values = np.concatenate([np.full(f.size, t, dtype=np.int32) for f, t in found])
        order = np.argsort(facets, kind="stable")
        tags = dolfinx.mesh.meshtags(mesh, 1, facets[order], values[order])
        mesh.geometry.x[:, :2] = mesh.geometry.x[:, :2] @ R.T
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
        uk = dolfinx.fem.Function(V)
        motion = dolfinx.fem.Function(V)
        held = R @ np.array([0.0, -delta * k])
        motion.interpolate(lambda x, held=held: np.outer(held, np.ones(x.shape[1])))
        dofs = dolfinx.fem.locate_dofs_topological(V, 1, tags.find(BOTTOM if k == 0 else TOP))
        bcs.append(dolfinx.fem.dirichletbc(motion, dofs))
        F.append(neo_hookean(uk, *MATERIALS[k]))
        u.append(uk)
        spaces.append(V)
        tags_of.append(tags)
        motions.append(motion)
    target = contact_surface(spaces[0], tags_of[0], TOP)
    contactor = contact_surface(spaces[1], tags_of[1], BOTTOM)
    return F, u, bcs, contact_pair(contactor, target), motions, R


def _owned_values(f):
    n = f.function_space.dofmap.index_map.size_local * f.function_space.dofmap.index_map_bs
    return f.x.array[:n].copy()


@pytest.mark.parametrize("angle", [np.pi / 2, 0.7])
def test_objectivity(angle):
    """The scene turned rigidly gives the same pressures, and so does the solved scene
    turned by a superposed rigid rotation (the motions of both bodies' held faces rotated
    in steps): the contact lives on the current configuration."""
    results = {}
    for name, turn in (("reference", 0.0), ("turned", angle)):
        F, u, bcs, pair, _, _ = pressed_blocks(turn)
        with NonlinearContactProblem(F, u, [pair], bcs, petsc_options_prefix=f"obj_{name}_") as p:
            p.solve()
            results[name] = _owned_values(p.multipliers[0])
    F, u, bcs, pair, motions, _ = pressed_blocks(0.0)
    with NonlinearContactProblem(
        F, u, [pair], bcs, max_iterations=60, petsc_options_prefix="obj_superposed_"
    ) as problem:
        problem.solve()
        steps = int(np.ceil(abs(angle) / (np.pi / 12)))
        for s in range(1, steps + 1):
            t = angle * s / steps
            Q = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
            for k, motion in enumerate(motions):
                X = motion.function_space.tabulate_dof_coordinates()[:, :2]
                held = np.array([0.0, -0.04 * k])
                motion.x.array[:] = ((X + held) @ Q.T - X).reshape(-1)
            problem.solve()
        results["superposed"] = _owned_values(problem.multipliers[0])
    scale = comm.allreduce(float(np.max(np.abs(results["reference"]), initial=0.0)), op=MPI.MAX)
    assert scale > 0.01
    for name in ("turned", "superposed"):
        error = np.max(np.abs(results[name] - results["reference"]), initial=0.0)
        assert comm.allreduce(float(error), op=MPI.MAX) <= 1e-10 * scale, name


def test_inverted_cells_and_slow_steps_raise():
    """A step that inverts cells names them; one that does not converge shows its history."""
    F, u, bcs, pair, _, _ = pressed_blocks(0.0, delta=1.2)
    with NonlinearContactProblem(F, u, [pair], bcs, petsc_options_prefix="bad_nl_") as problem:
        with pytest.raises(ValueError, match=r"inverts cells \(det F <= 0\).*smaller load step"):
            problem.solve()
    F, u, bcs, pair, _, _ = pressed_blocks(0.0)
    with NonlinearContactProblem(
        F, u, [pair], bcs, max_iterations=2, petsc_options_prefix="slow_nl_"
    ) as problem:
        with pytest.raises(NonlinearConvergenceError, match=r"in 2 iterations(.|\n)*  1: residual"):
            problem.solve()
    with pytest.raises(ValueError, match="contact must be"):
        NonlinearContactProblem(F, u, [pair], bcs, contact="sliding", petsc_options_prefix="x_")


def test_tangent_against_moving_one_dof():
    """H and D (every cell of a surface moved at once, group by group) against moving
    one displacement dof at a time and assembling the whole coupling again."""
    from dolfinx_contact_s2s.assemble import assemble_coupling
    from dolfinx_contact_s2s.finite.tangent import ContactTangent
    from dolfinx_contact_s2s.la import gather_dense

    F, u, bcs, pair, _, _ = pressed_blocks(0.3)
    with NonlinearContactProblem(F, u, [pair], bcs, petsc_options_prefix="tangent_") as problem:
        problem.solve()
        problem.place()
        tangent = ContactTangent(problem.problem.system)
        tangent.update(u)
        (lam,) = problem.multipliers
        system = problem.problem.system

        def evaluate():
            """The contact force on each space and the gap at the surfaces' placement."""
            op = assemble_coupling(pair)
            out = {}
            g = op.G.copy()
            for V, B in op.blocks:
                i = system.space_index(V)
                y = B.createVecRight()
                B.multTranspose(lam.x.petsc_vec, y)
                out[("u", i)] = np.concatenate(comm.allgather(y.array_r.copy()))
                B.multAdd(u[i].x.petsc_vec, g, g)
                y.destroy()
            out[("lambda", 0)] = np.concatenate(comm.allgather(g.array_r.copy()))
            g.destroy()
            op.destroy()
            return out

        dense = {key: gather_dense(M) for key, M in tangent.blocks.items()}
        h = 1e-6
        checked = 0
        for j, V in enumerate(system.spaces):
            # The dofs of the contact surfaces (a column of D has entries).
            D = dense[(("lambda", 0), j)]
            for m in np.flatnonzero(np.abs(D).max(axis=0) > 0)[::3]:
                columns = []
                for sign in (1.0, -1.0):
                    local = V.dofmap.index_map.local_range[0] * V.dofmap.index_map_bs
                    n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
                    if local <= m < local + n:
                        u[j].x.array[m - local] += sign * h
                    problem.place()
                    columns.append(evaluate())
                    if local <= m < local + n:
                        u[j].x.array[m - local] -= sign * h
                problem.place()
                for key, expected in dense.items():
                    if key[1] != j:
                        continue
                    fd = (columns[0][key[0]] - columns[1][key[0]]) / (2 * h)
                    scale = max(np.max(np.abs(M)) for k, M in dense.items() if k[0] == key[0])
                    assert np.max(np.abs(fd - expected[:, m])) <= 1e-8 * scale, (key, m)
                checked += 1
        tangent.destroy()
    assert checked >= 4

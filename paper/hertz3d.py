# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Hertz in 3D: quarter models of a sphere on a block, two spheres, and a half-ball on a box.

One Gmsh model (OpenCASCADE), two volumes that touch at one point and are meshed apart
(tetrahedra, geometry of degree 1 or 2), as a user builds it; the symmetry planes
:math:`x = 0` and :math:`y = 0` carry :math:`u_x = 0` and :math:`u_y = 0`, so the quarter
carries :math:`F/4`. The element size is :math:`h` within ``reach`` of the touching point
(the origin), growing linearly (slope :data:`GRADING`) to ``far``: sizes chosen from the
geometry (fractions of :math:`R`), never from the contact radius.

Scenes (:data:`SCENES`):

- ``"sphere-on-block"``: a hemisphere (:math:`R = 1`, pole down at the origin, its flat
  face :math:`z = R` loaded by the uniform pressure :math:`F/(\pi R^2)`) on a cylindrical
  block :math:`r \le W`, :math:`-D \le z \le 0` (its bottom held, :math:`u_z = 0`), both
  :math:`E = 1`, :math:`\nu = 0.3`. A cylinder, not a box, so that the axisymmetric model
  (:func:`axisymmetric`) solves the same scene.
- ``"two-spheres"``: the scene of :mod:`paper.hertz.axisymmetric`: sphere 1
  (:math:`R_1 = 1`, :math:`E_1 = 1`, :math:`\nu_1 = 0.3`, below, flat face held) and
  sphere 2 (:math:`R_2 = 2`, :math:`E_2 = 2`, :math:`\nu_2 = 0.25`, above, loaded).
- ``"half-ball"``: the 3D Hertz problem of another contact package: a half-ball
  :math:`R = 8`, flat face up, on the box :math:`20 \times 20 \times 20` (a quarter:
  :math:`[0, 10]^2 \times [-20, 0]`), :math:`E = 200`, :math:`\nu = 0.3` for both,
  :math:`F = 10` as a uniform traction on the flat face, the box's bottom clamped.

The multiplier lives on the upper body's sphere, or on sphere 1 (the lower one) for two
spheres, as in the axisymmetric scenes. Hertz (1882): :math:`1/R^* = 1/R_1 + 1/R_2`,
:math:`1/E^* = (1 - \nu_1^2)/E_1 + (1 - \nu_2^2)/E_2`,
:math:`a = (3 F R^* / (4 E^*))^{1/3}`, :math:`p_0 = 3F / (2\pi a^2)`,
:math:`p = p_0 \sqrt{1 - r^2/a^2}`.
"""

from __future__ import annotations

import math
import typing
from dataclasses import dataclass

from mpi4py import MPI

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s import Material, contact_pair, contact_surface, gmsh_session
from dolfinx_contact_s2s import model_to_mesh as _model_to_mesh
from dolfinx_contact_s2s.meshing import Projection
from dolfinx_contact_s2s.unilateral import UnilateralContactProblem

__all__ = [
    "GRADING",
    "SCENES",
    "TAGS",
    "Scene",
    "build",
    "exact",
    "mesh",
    "projection",
]

#: Facet tags: the upper body's contact cap and flat face, the lower body's contact face
#: (a square of its flat top, or a cap of its sphere), its far face (bottom or flat face),
#: the free faces of both, and the symmetry planes of both bodies.
TAGS = {
    "upper_sphere": 11,
    "upper_flat": 12,
    "upper_free": 13,
    "lower_top": 21,
    "lower_far": 22,
    "free": 23,
    "lower_free": 24,
}
SYM_X, SYM_Y = 31, 32
#: Cell tags.
UPPER, LOWER = 1, 2
#: Growth of the element size with the distance from the touching point.
GRADING = 0.3


@dataclass(frozen=True)
class Scene:
    r"""The bodies and load of a scene.

    Attributes:
        R1: Radius of the upper sphere (sphere 2 of two spheres: the loaded one).
        R2: Radius of the lower sphere (``math.inf``: the block).
        width: Half-width of the lower block: radius of the cylinder, or of the box.
        depth: Depth of the lower block.
        box: Whether the lower block is a box (else a cylinder).
        materials: Upper and lower body.
        F: Default total force (of the whole model, not the quarter).
        clamped: Whether the lower body's far face is clamped (else :math:`u_z = 0`).
    """

    R1: float
    R2: float
    width: float
    depth: float
    box: bool
    materials: tuple[Material, Material]
    F: float
    clamped: bool

    @property
    def R(self) -> float:
        """Relative radius :math:`R^*`."""
        return 1.0 / (1.0 / self.R1 + 1.0 / self.R2)

    @property
    def E_star(self) -> float:
        """Contact modulus :math:`E^*`."""
        return 1.0 / sum((1 - m.nu**2) / m.E for m in self.materials)


#: The scenes; the default force of the first two gives :math:`a = 0.05` (:math:`a/R_1` =
#: 5% and 5% of the smaller sphere).
SCENES: dict[str, Scene] = {
    "sphere-on-block": Scene(1.0, math.inf, 1.0, 1.0, False, (Material(1, 0.3),) * 2, 0.0, False),
    "two-spheres": Scene(
        2.0, 1.0, 1.0, 1.0, False, (Material(2.0, 0.25), Material(1.0, 0.3)), 0.0, False
    ),
    "half-ball": Scene(8.0, math.inf, 10.0, 20.0, True, (Material(200, 0.3),) * 2, 10.0, True),
}
for _name in ("sphere-on-block", "two-spheres"):
    _s = SCENES[_name]
    SCENES[_name] = Scene(**{**_s.__dict__, "F": 4 * _s.E_star * 0.05**3 / (3 * _s.R)})


def exact(scene: Scene, F: float | None = None) -> tuple[float, float]:
    """Hertz's contact radius and peak pressure :math:`(a, p_0)` of the whole model."""
    F = scene.F if F is None else F
    a = (3 * F * scene.R / (4 * scene.E_star)) ** (1 / 3)
    return a, 3 * F / (2 * math.pi * a**2)


#: Half-angle of the spherical caps that are contact surfaces (as the axisymmetric arcs),
#: and the half-width of the block's target square, relative to the upper sphere's radius.
CAP, TARGET = 0.4, 0.5


def _split(gmsh: typing.Any, volume: int, cutter: int) -> list[int]:
    """The pieces of ``volume`` cut by the box ``cutter`` (conforming; the rest removed)."""
    occ = gmsh.model.occ
    _, pieces = occ.fragment([(3, volume)], [(3, cutter)])
    keep = {t for _, t in pieces[0]}
    occ.remove([(3, t) for _, t in pieces[1] if t not in keep], recursive=True)
    return sorted(keep)


def _classify(
    gmsh: typing.Any, volumes: list[int], upper: bool, scene: Scene, half: bool = False
) -> dict[int, list[int]]:
    r"""The physical tag of every boundary face of a body, from its centre of mass and type.

    ``half``: the model :math:`y \ge 0`, whose faces are centred on :math:`x = 0`.
    """
    tags: dict[int, list[int]] = {}
    cap = scene.R1 * math.sin(CAP) if upper else scene.R2 * math.sin(CAP)
    square = TARGET * scene.R1
    boundary = gmsh.model.getBoundary([(3, v) for v in volumes], combined=True, oriented=False)
    for _, face in boundary:
        x, y, z = gmsh.model.occ.getCenterOfMass(2, face)
        kind, r = gmsh.model.getType(2, face), math.hypot(x, y)
        if abs(x) < 1e-9 * scene.R1 and not half:
            tag = SYM_X
        elif abs(y) < 1e-9 * scene.R1:
            tag = SYM_Y
        elif kind == "Sphere":
            near = r < cap
            far_tag = TAGS["upper_free" if upper else "lower_free"]
            tag = TAGS["upper_sphere" if upper else "lower_top"] if near else far_tag
        elif upper:
            tag = TAGS["upper_flat"]
        elif abs(z) < 1e-9 * scene.R1:
            tag = TAGS["lower_top"] if max(abs(x), y) < square else TAGS["free"]
        elif z < -0.5 * scene.depth or not math.isinf(scene.R2):
            tag = TAGS["lower_far"]
        else:
            tag = TAGS["lower_free"] if kind == "Cylinder" else TAGS["free"]
        tags.setdefault(tag, []).append(face)
    return tags


def mesh(
    comm: MPI.Comm,
    scene: Scene,
    *,
    h: float,
    reach: float,
    far: float | None = None,
    geometry_degree: int = 2,
    rank: int = 0,
    half: bool = False,
) -> tuple[dolfinx.mesh.Mesh, dolfinx.mesh.MeshTags, dolfinx.mesh.MeshTags]:
    r"""The quarter model of ``scene``: tetrahedra of size ``h`` within ``reach`` of the origin.

    Args:
        comm: Communicator the mesh is distributed over.
        scene: One of :data:`SCENES`.
        h: Element size within ``reach`` of the touching point.
        reach: Radius of the fine zone.
        far: Largest element size (default: the smaller radius over 4).
        geometry_degree: 1, or 2 for second-order nodes on the spheres.
        rank: Rank that builds the Gmsh model.
        half: The half model :math:`y \ge 0` instead (symmetry :data:`SYM_Y` only), for
            loads along :math:`x`.

    Returns:
        ``(mesh, cell_tags, facet_tags)``: cells :data:`UPPER` and :data:`LOWER`, facets
        :data:`TAGS`, :data:`SYM_X` and :data:`SYM_Y`.

    Raises:
        ValueError: On every rank, for a bad size or degree.
    """
    far = min(scene.R1, scene.R2, scene.width) / 4 if far is None else far
    if not (0 < h <= far and reach > 0):
        raise ValueError(f"need 0 < h <= far and reach > 0, not h={h}, far={far}, reach={reach}")
    if geometry_degree not in (1, 2):
        raise ValueError(f"geometry_degree must be 1 or 2, not {geometry_degree!r}")
    if half and scene.box:
        raise ValueError("the half model is built for spheres and cylinders, not boxes")
    with gmsh_session() as gmsh:
        gmsh.model.add("hertz3d")
        if comm.rank == rank:
            occ = gmsh.model.occ
            quarter = math.pi * (1 + half) / 2
            R1, x0 = scene.R1, -1.0 if half else 0.0  # x0: where the cutting boxes start
            upper = occ.addSphere(0, 0, R1, R1, -1, -math.pi / 2, 0.0, quarter)
            cut = R1 * (1 - math.cos(CAP))
            uppers = _split(gmsh, upper, occ.addBox(x0 * R1, 0, 0, (1 - x0) * R1, R1, cut))
            if math.isinf(scene.R2):
                W, D = scene.width, scene.depth
                if scene.box:
                    lower = occ.addBox(0, 0, -D, W, W, D)
                else:
                    lower = occ.addCylinder(0, 0, -D, 0, 0, D, W, -1, quarter)
                side = TARGET * R1
                lowers = _split(
                    gmsh, lower, occ.addBox(x0 * side, 0, -side, (1 - x0) * side, side, side)
                )
            else:
                R2 = scene.R2
                lower = occ.addSphere(0, 0, -R2, R2, -1, 0.0, math.pi / 2, quarter)
                cut = R2 * (1 - math.cos(CAP))
                lowers = _split(gmsh, lower, occ.addBox(x0 * R2, 0, -cut, (1 - x0) * R2, R2, cut))
            occ.synchronize()
            gmsh.model.addPhysicalGroup(3, uppers, UPPER)
            gmsh.model.addPhysicalGroup(3, lowers, LOWER)
            faces: dict[int, list[int]] = {}
            for volumes, is_upper in ((uppers, True), (lowers, False)):
                for tag, f in _classify(gmsh, volumes, is_upper, scene, half).items():
                    faces.setdefault(tag, []).extend(f)
            for tag, f in sorted(faces.items()):
                gmsh.model.addPhysicalGroup(2, f, tag)
            field = gmsh.model.mesh.field
            size = field.add("MathEval")
            field.setString(
                size,
                "F",
                f"Min({far}, {h} + {GRADING} * Max(0, Sqrt(x*x + y*y + z*z) - {reach}))",
            )
            field.setAsBackgroundMesh(size)
            for option in ("ExtendFromBoundary", "FromPoints", "FromCurvature"):
                gmsh.option.setNumber(f"Mesh.MeshSize{option}", 0)
            gmsh.model.mesh.generate(3)
            gmsh.model.mesh.setOrder(geometry_degree)
        return _model_to_mesh(gmsh.model, comm, rank, gdim=3)


def projection(scene: Scene) -> Projection:
    """Moves points of the curved faces onto their spheres and cylinder.

    The ``snap`` of the refinement and the ``project`` of
    :func:`~dolfinx_contact_s2s.meshing.curved_mesh`: every curved face, the contact caps
    and the free rest of the spheres and the block's cylindrical side alike (a free face
    left on its chords dents the body: 0.9% of R on the R/4 faces far from the contact,
    enough to move p0 by 0.4%).
    """
    upper = (np.array([0.0, 0.0, scene.R1]), scene.R1)
    spheres = {TAGS["upper_sphere"]: upper, TAGS["upper_free"]: upper}
    if not math.isinf(scene.R2):
        lower = (np.array([0.0, 0.0, -scene.R2]), scene.R2)
        spheres |= {TAGS["lower_top"]: lower, TAGS["lower_free"]: lower}

    def project(tag: int, points: np.ndarray) -> np.ndarray | None:
        if tag == TAGS["lower_free"] and math.isinf(scene.R2):  # the cylinder's side
            r = np.maximum(np.hypot(points[:, 0], points[:, 1]), 1e-300)
            return np.column_stack([points[:, :2] * (scene.width / r)[:, None], points[:, 2]])
        if tag not in spheres:
            return None
        centre, radius = spheres[tag]
        d = points - centre
        return centre + radius * d / np.maximum(np.linalg.norm(d, axis=1), 1e-300)[:, None]

    return project


def build(
    scene: Scene,
    *,
    degree: int = 2,
    F: float | None = None,
    prefix: str = "hertz3d_",
    start: str = "nearest",
) -> typing.Callable[..., UnilateralContactProblem]:
    r"""``build(mesh, cell_tags, facet_tags)`` of the quarter model of ``scene``.

    P``degree`` displacements; the multiplier P1 (a P2 triangle's vertex functions
    integrate to zero: the unilateral problem needs P1 on P2 faces). The flat face of
    the upper body carries :math:`F/(\pi R_1^2)` (:math:`F/4` on the quarter); the lower
    body's far face is clamped or holds :math:`u_z = 0`; symmetry on :math:`x = 0` and
    :math:`y = 0`.
    """
    F = scene.F if F is None else F

    def make(domain, cell_tags, facet_tags) -> UnilateralContactProblem:
        V = dolfinx.fem.functionspace(domain, ("Lagrange", degree, (3,)))
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        dx = ufl.Measure("dx", domain=domain, subdomain_data=cell_tags)
        ds = ufl.Measure("ds", domain=domain, subdomain_data=facet_tags)
        a = sum(
            ufl.inner(m.sigma(u), m.strain(v)) * dx(tag)
            for m, tag in zip(scene.materials, (UPPER, LOWER), strict=True)
        )
        q = dolfinx.fem.Constant(domain, -F / (math.pi * scene.R1**2))
        L = q * v[2] * ds(TAGS["upper_flat"])
        domain.topology.create_connectivity(2, 3)
        bcs = []
        held = [(0, SYM_X), (1, SYM_Y)] + [(i, TAGS["lower_far"]) for i in (0, 1) if scene.clamped]
        for component, tag in [*held, (2, TAGS["lower_far"])]:
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(component), 2, facet_tags.find(tag))
            bcs.append(dolfinx.fem.dirichletbc(0.0, dofs, V.sub(component)))
        sphere, other = (
            contact_surface(V, facet_tags, TAGS["upper_sphere"]),
            contact_surface(V, facet_tags, TAGS["lower_top"]),
        )
        # Two spheres: sphere 1 (the lower one) is the contactor, as in the axisymmetric scene.
        surfaces = (other, sphere) if not math.isinf(scene.R2) else (sphere, other)
        pair = contact_pair(*surfaces, multiplier=("Lagrange", 1))
        return UnilateralContactProblem(
            [a], [L], [pair], bcs, petsc_options_prefix=prefix, start=start
        )

    return make

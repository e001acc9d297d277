# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The Hertz scene: a half cylinder pressed onto a block, or onto a second half cylinder.

Plane strain. The upper body is the lower half of a disk of radius :math:`R_1` centred
at :math:`(0, R_1)`: its arc touches :math:`y = 0` at the origin and its flat face is
:math:`y = R_1`. The lower body is the block :math:`[-W, W] \times [-D, 0]`, or the
upper half of a disk of radius :math:`R_2` centred at :math:`(0, -R_2)` (the arc
touches the origin, the flat face is :math:`y = -R_2`). Both bodies are surfaces of ONE
Gmsh model, hence one DOLFINx mesh of two connected components that share no node,
and each has a mesh node at the contact point :math:`(0, 0)`; the upper arc also has
nodes at the exact contact edges :math:`x = \pm a` of the design load (unless
``edge_nodes=False``).

The mesh is graded toward the contact point with a Gmsh ``Distance`` field of the two
contact points and a ``Threshold`` field: size :math:`h = 2a / n` within
:math:`1.5 a` of the origin (about :math:`n` elements across the contact width
:math:`2a`), growing linearly to :math:`\min(R_1, R_2, W, D) / 8` (the block's
:math:`R_2 = \infty`; or ``far_size``) at a slope of :data:`GRADING`. Quadrilaterals come from
recombination (Blossom, of quadrilaterals of quality 0.3 or better, on a mesh of twice
the size) followed by the split of every cell into quadrilaterals; geometry degree 2
puts the second-order nodes on the arcs.

Cell tags: upper body 1, lower body 2. Facet tags: see :data:`TAGS`.
"""

from __future__ import annotations

import contextlib
import math
import typing
from collections.abc import Iterator
from dataclasses import dataclass

from mpi4py import MPI

import dolfinx

from dolfinx_contact_s2s.meshing import gmsh_session, model_to_mesh

__all__ = ["GRADING", "TAGS", "HertzScene", "hertz"]

#: Facet tags of the Hertz scene by name:
#:
#: - ``"contactor"``: the part :math:`|x| \le 4a` of the upper arc,
#: - ``"upper_top"``: the flat top face of the upper body (loaded),
#: - ``"upper_rest"``: the rest of the upper arc,
#: - ``"target"``: the part :math:`|x| \le 5a` of the lower body's top (line or arc),
#: - ``"lower_top_rest"``: the rest of the lower body's top,
#: - ``"lower_bottom"``: the bottom face of the lower body (clamped),
#: - ``"lower_sides"``: the block's sides :math:`x = \pm W` (no facet for a lower cylinder).
TAGS: dict[str, int] = {
    "contactor": 10,
    "upper_top": 11,
    "upper_rest": 12,
    "target": 20,
    "lower_top_rest": 21,
    "lower_bottom": 22,
    "lower_sides": 23,
}

#: Growth of the element size with the distance from the contact point (size per length).
GRADING = 0.25

#: Cell tags of the two bodies.
_UPPER, _LOWER = 1, 2


@dataclass
class HertzScene:
    r"""A Hertz scene: one mesh holding the upper half cylinder and the lower body.

    Attributes:
        mesh: The mesh of both bodies.
        cell_tags: Cell markers: upper body 1, lower body 2.
        facet_tags: Facet markers, values in :attr:`tags`.
        R1: Radius :math:`R_1` of the upper cylinder.
        R2: Radius :math:`R_2` of the lower cylinder; ``math.inf`` for the block.
        a: Design half-width :math:`a` of the contact the mesh is graded for.
        h: Element size at the contact point, :math:`2a / n`.
        width: Half-width :math:`W` of the block (:math:`R_2` for a lower cylinder).
        depth: Depth :math:`D` of the block (:math:`R_2` for a lower cylinder).
        cell: ``"triangle"`` or ``"quadrilateral"``.
        geometry_degree: Degree of the coordinate element, 1 or 2.
        tags: Facet tag of each named boundary part (see :data:`TAGS`).
    """

    mesh: dolfinx.mesh.Mesh
    cell_tags: dolfinx.mesh.MeshTags
    facet_tags: dolfinx.mesh.MeshTags
    R1: float
    R2: float
    a: float
    h: float
    width: float
    depth: float
    cell: str
    geometry_degree: int
    tags: dict[str, int]


@contextlib.contextmanager
def _options(gmsh: typing.Any, values: dict[str, float]) -> Iterator[None]:
    """Set Gmsh number options for the duration of the block, then restore them."""
    old = {name: gmsh.option.getNumber(name) for name in values}
    try:
        for name, value in values.items():
            gmsh.option.setNumber(name, value)
        yield
    finally:
        for name, value in old.items():
            gmsh.option.setNumber(name, value)


def _arc_point(
    geo: typing.Any, x: float, centre: tuple[float, float], radius: float, up: bool
) -> int:
    """A point of the circle about ``centre`` at abscissa ``x`` (its upper or lower half)."""
    dy = math.sqrt(radius**2 - x**2)
    return geo.addPoint(x, centre[1] + (dy if up else -dy), 0.0)


def _upper_body(
    gmsh: typing.Any, R: float, a: float, edge_nodes: bool
) -> tuple[int, dict[str, list[int]], int]:
    r"""The lower half of the disk of radius ``R`` about ``(0, R)``: surface, curves, origin.

    With ``edge_nodes``, the points of the arc at :math:`x = \pm a` are geometry points,
    hence mesh nodes.
    """
    geo = gmsh.model.geo
    centre = geo.addPoint(0.0, R, 0.0)
    left, right = geo.addPoint(-R, R, 0.0), geo.addPoint(R, R, 0.0)
    q_left = _arc_point(geo, -4.0 * a, (0.0, R), R, up=False)
    q_right = _arc_point(geo, 4.0 * a, (0.0, R), R, up=False)
    origin = geo.addPoint(0.0, 0.0, 0.0)
    # Counterclockwise: along the arc from the origin to the right, the top leftwards, down.
    if edge_nodes:
        e_left = _arc_point(geo, -a, (0.0, R), R, up=False)
        e_right = _arc_point(geo, a, (0.0, R), R, up=False)
        right_arc = [
            geo.addCircleArc(origin, centre, e_right),
            geo.addCircleArc(e_right, centre, q_right),
        ]
    else:
        right_arc = [geo.addCircleArc(origin, centre, q_right)]
    curves = [
        *right_arc,
        geo.addCircleArc(q_right, centre, right),
        geo.addLine(right, left),
        geo.addCircleArc(left, centre, q_left),
    ]
    if edge_nodes:
        left_arc = [
            geo.addCircleArc(q_left, centre, e_left),
            geo.addCircleArc(e_left, centre, origin),
        ]
    else:
        left_arc = [geo.addCircleArc(q_left, centre, origin)]
    curves += left_arc
    surface = geo.addPlaneSurface([geo.addCurveLoop(curves)])
    k = len(right_arc)
    parts = {
        # With edge nodes: the arcs from the contact point to the edges come first.
        "contactor": [right_arc[0], left_arc[-1], *right_arc[1:], *left_arc[:-1]],
        "upper_top": [curves[k + 1]],
        "upper_rest": [curves[k], curves[k + 2]],
    }
    return surface, parts, origin


def _lower_block(
    gmsh: typing.Any, W: float, D: float, a: float
) -> tuple[int, dict[str, list[int]], int]:
    """The block ``[-W, W] x [-D, 0]``: surface, curves, origin."""
    geo = gmsh.model.geo
    b_left, b_right = geo.addPoint(-W, -D, 0.0), geo.addPoint(W, -D, 0.0)
    t_right, t_left = geo.addPoint(W, 0.0, 0.0), geo.addPoint(-W, 0.0, 0.0)
    q_right, q_left = geo.addPoint(5.0 * a, 0.0, 0.0), geo.addPoint(-5.0 * a, 0.0, 0.0)
    origin = geo.addPoint(0.0, 0.0, 0.0)
    curves = [
        geo.addLine(b_left, b_right),
        geo.addLine(b_right, t_right),
        geo.addLine(t_right, q_right),
        geo.addLine(q_right, origin),
        geo.addLine(origin, q_left),
        geo.addLine(q_left, t_left),
        geo.addLine(t_left, b_left),
    ]
    surface = geo.addPlaneSurface([geo.addCurveLoop(curves)])
    parts = {
        "target": [curves[3], curves[4]],
        "lower_top_rest": [curves[2], curves[5]],
        "lower_bottom": [curves[0]],
        "lower_sides": [curves[1], curves[6]],
    }
    return surface, parts, origin


def _lower_cylinder(gmsh: typing.Any, R: float, a: float) -> tuple[int, dict[str, list[int]], int]:
    """The upper half of the disk of radius ``R`` about ``(0, -R)``: surface, curves, origin."""
    geo = gmsh.model.geo
    centre = geo.addPoint(0.0, -R, 0.0)
    left, right = geo.addPoint(-R, -R, 0.0), geo.addPoint(R, -R, 0.0)
    q_right = _arc_point(geo, 5.0 * a, (0.0, -R), R, up=True)
    q_left = _arc_point(geo, -5.0 * a, (0.0, -R), R, up=True)
    origin = geo.addPoint(0.0, 0.0, 0.0)
    curves = [
        geo.addLine(left, right),
        geo.addCircleArc(right, centre, q_right),
        geo.addCircleArc(q_right, centre, origin),
        geo.addCircleArc(origin, centre, q_left),
        geo.addCircleArc(q_left, centre, left),
    ]
    surface = geo.addPlaneSurface([geo.addCurveLoop(curves)])
    parts = {
        "target": [curves[2], curves[3]],
        "lower_top_rest": [curves[1], curves[4]],
        "lower_bottom": [curves[0]],
        "lower_sides": [],
    }
    return surface, parts, origin


def _model(
    gmsh: typing.Any,
    R1: float,
    R2: float,
    a: float,
    h: float,
    W: float,
    D: float,
    cell: str,
    geometry_degree: int,
    edge_nodes: bool,
    far_size: float | None,
) -> None:
    """Build and mesh the Hertz scene in the current Gmsh model."""
    upper, upper_parts, o_upper = _upper_body(gmsh, R1, a, edge_nodes)
    if math.isinf(R2):
        lower, lower_parts, o_lower = _lower_block(gmsh, W, D, a)
        far = min(R1, W, D)
    else:
        lower, lower_parts, o_lower = _lower_cylinder(gmsh, R2, a)
        far = min(R1, R2)
    gmsh.model.geo.synchronize()
    # Quadrilaterals: mesh at twice the size, recombine, split every cell (in 4 or 3).
    scale = 2.0 if cell == "quadrilateral" else 1.0
    if edge_nodes:
        # Uniform cells between the contact point and each edge, n/2 (after the split).
        segments = max(1, math.floor(a / (scale * h) + 0.5))
        for curve in upper_parts["contactor"][:2]:
            gmsh.model.mesh.setTransfiniteCurve(curve, segments + 1)

    gmsh.model.addPhysicalGroup(2, [upper], _UPPER, name="upper")
    gmsh.model.addPhysicalGroup(2, [lower], _LOWER, name="lower")
    for name, curves in (upper_parts | lower_parts).items():
        if curves:
            gmsh.model.addPhysicalGroup(1, curves, TAGS[name], name=name)

    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", [o_upper, o_lower])
    threshold = field.add("Threshold")
    size_max = max(h, far / 8.0 if far_size is None else far_size)
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", scale * h)
    field.setNumber(threshold, "SizeMax", scale * size_max)
    field.setNumber(threshold, "DistMin", 1.5 * a)
    field.setNumber(threshold, "DistMax", 1.5 * a + (size_max - h) / GRADING)
    field.setAsBackgroundMesh(threshold)
    if cell == "quadrilateral":
        gmsh.model.mesh.setRecombine(2, upper)
        gmsh.model.mesh.setRecombine(2, lower)
    gmsh.model.mesh.generate(2)
    gmsh.model.mesh.setOrder(geometry_degree)


def hertz(
    comm: MPI.Comm,
    *,
    R: float = 1.0,
    a: float = 0.05,
    elements_across: int = 20,
    cell: str = "triangle",
    geometry_degree: int = 1,
    size: tuple[float, float] = (1.0, 1.0),
    lower_radius: float = math.inf,
    edge_nodes: bool = True,
    far_size: float | None = None,
    rank: int = 0,
    partitioner: typing.Callable | None = None,
) -> HertzScene:
    r"""The Hertz scene: a half cylinder on a block, or on a second half cylinder.

    Args:
        comm: Communicator the mesh is distributed over.
        R: Radius :math:`R_1` of the upper cylinder.
        a: Half-width :math:`a` of the contact zone the mesh is graded for; below
            :math:`R_1 / 4`, so that the contactor :math:`|x| \le 4a` is part of the arc.
        elements_across: About how many elements span the contact width :math:`2a`:
            the element size at the contact point is :math:`h = 2a / n`.
        cell: ``"triangle"`` or ``"quadrilateral"`` (recombined).
        geometry_degree: 1, or 2 for curved arcs (second-order nodes on the circles).
        size: Half-width :math:`W` and depth :math:`D` of the block; :math:`W > 5a`.
            Ignored for a lower cylinder.
        lower_radius: Radius :math:`R_2` of the lower cylinder, above :math:`5a`;
            ``math.inf`` (the default) for the block.
        edge_nodes: Put mesh nodes on the upper arc at :math:`x = \pm a`, the exact
            contact edges at the design load. The discrete contact conditions act on
            nodal weighted gaps, so the computed edge is always at a node; an exact
            edge inside an element adds an error that depends on where in the element
            it falls, which changes from mesh to mesh (``False`` measures it).
        far_size: Element size far from the contact (default: the smallest of
            :math:`R_1, R_2, W, D` over 8). A convergence study of global quantities
            (the strain energy) refines it with ``h``.
        rank: Rank that builds the Gmsh model.
        partitioner: Cell partitioner of the mesh (see
            :func:`dolfinx_contact_s2s.meshing.model_to_mesh`); None: DOLFINx's.

    Returns:
        The scene; facet tags in :data:`TAGS` (``"lower_sides"`` marks no facet for a
        lower cylinder), cell tags upper 1 and lower 2.

    Raises:
        ValueError: On every rank, for an invalid argument.
    """
    if cell not in ("triangle", "quadrilateral"):
        raise ValueError(f"cell must be 'triangle' or 'quadrilateral', not {cell!r}")
    if geometry_degree not in (1, 2):
        raise ValueError(f"geometry_degree must be 1 or 2, not {geometry_degree!r}")
    if not (R > 0.0 and math.isfinite(R)):
        raise ValueError(f"the radius R must be positive and finite, not {R!r}")
    if not a > 0.0:
        raise ValueError(f"the half-width a must be positive, not {a!r}")
    if a >= R / 4.0:
        raise ValueError(f"the half-width a = {a} must be below R/4 = {R / 4.0}")
    if isinstance(elements_across, bool) or int(elements_across) != elements_across:
        raise ValueError(f"elements_across must be an integer, not {elements_across!r}")
    if elements_across < 1:
        raise ValueError(f"elements_across must be 1 or more, not {elements_across}")
    if far_size is not None and not (far_size > 0.0 and math.isfinite(far_size)):
        raise ValueError(f"far_size must be positive and finite, not {far_size!r}")
    if not 0 <= rank < comm.size:
        raise ValueError(f"rank {rank} is not a rank of the communicator (size {comm.size})")
    R2 = float(lower_radius)
    if math.isinf(R2):
        if R2 < 0.0:
            raise ValueError("lower_radius must be positive (math.inf for the block)")
        W, D = (float(s) for s in size)
        if not W > 5.0 * a:
            raise ValueError(f"the block half-width W = {W} must exceed 5a = {5.0 * a}")
        if not (D > 0.0 and math.isfinite(D)):
            raise ValueError(f"the block depth D must be positive and finite, not {D!r}")
    else:
        if not R2 > 5.0 * a:
            raise ValueError(f"lower_radius = {R2} must exceed 5a = {5.0 * a}")
        W = D = R2
    h = 2.0 * a / int(elements_across)

    quads = cell == "quadrilateral"
    options = {
        "Mesh.MeshSizeExtendFromBoundary": 0,
        "Mesh.MeshSizeFromPoints": 0,
        "Mesh.MeshSizeFromCurvature": 0,
        # Frontal-Delaunay for quads makes right-angled triangles that recombine well.
        "Mesh.Algorithm": 8 if quads else 6,
        # Blossom recombination of good quads only, then every cell split into quads: all
        # quads, none with two edges on one arc (which curved geometry would invert).
        "Mesh.RecombinationAlgorithm": 1,
        "Mesh.RecombineMinimumQuality": 0.3,
        "Mesh.SubdivisionAlgorithm": 1 if quads else 0,
    }
    with gmsh_session() as gmsh, _options(gmsh, options):
        gmsh.model.add("hertz")
        if comm.rank == rank:
            _model(
                gmsh, float(R), R2, float(a), h, W, D, cell, geometry_degree, edge_nodes, far_size
            )
        mesh, cell_tags, facet_tags = model_to_mesh(
            gmsh.model, comm, rank, gdim=2, partitioner=partitioner
        )
        gmsh.model.remove()
    mesh.name = "hertz"
    return HertzScene(
        mesh,
        cell_tags,
        facet_tags,
        float(R),
        R2,
        float(a),
        h,
        W,
        D,
        cell,
        geometry_degree,
        dict(TAGS),
    )

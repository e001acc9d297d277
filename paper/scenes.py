# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Two-body geometries (scenes) generated with Gmsh.

Gmsh builds every body on one rank; DOLFINx's Gmsh reader distributes it. Each
body is a mesh of its own, so bodies may carry different element types, degrees,
materials and partitions; the contact coupling only ever touches their surfaces.
Scenes of several blocks, in one mesh or several, are in
:mod:`paper.scenes_multi`.
"""

from __future__ import annotations

import typing
from dataclasses import dataclass, field
from pathlib import Path

from mpi4py import MPI

import dolfinx

from dolfinx_contact_s2s.meshing import gmsh_session, model_to_mesh

__all__ = [
    "Body",
    "PatchTestScene",
    "inf_sup_model",
    "patch_test",
    "size_field",
]


#: Facet tags of a rectangular block.
BOTTOM, RIGHT, TOP, LEFT = 1, 2, 3, 4


@dataclass
class Body:
    """A body of a scene: its mesh and markers.

    Attributes:
        name: Name of the body.
        mesh: The body's mesh.
        cell_tags: Cell markers (the body's cells carry tag 1).
        facet_tags: Boundary facet markers.
        tags: Names of the facet markers, e.g. ``{"bottom": 1, ...}``.
        contact: Tag of the body's contact surface.
    """

    name: str
    mesh: dolfinx.mesh.Mesh
    cell_tags: dolfinx.mesh.MeshTags
    facet_tags: dolfinx.mesh.MeshTags
    tags: dict[str, int] = field(default_factory=dict)
    contact: int = 0


@dataclass
class PatchTestScene:
    r"""The contact patch test of Figs. 4 and 6: a lower and an upper block on :math:`y = H`.

    Attributes:
        lower: Block :math:`[0, W] \times [0, H]`, contact surface on top.
        upper: Block :math:`[0, W] \times [H + g_0, 2H + g_0]`, contact surface below.
        width: :math:`W`.
        height: :math:`H`.
        gap: Initial gap :math:`g_0` (negative: overlap).
    """

    lower: Body
    upper: Body
    width: float
    height: float
    gap: float

    @property
    def bodies(self) -> dict[str, Body]:
        """The bodies by name."""
        return {"lower": self.lower, "upper": self.upper}


def _block(
    gmsh: typing.Any,
    comm: MPI.Comm,
    name: str,
    origin: tuple[float, float],
    size: tuple[float, float],
    divisions: tuple[int, int],
    cell: str,
    degree: int,
    msh_dir: Path | None,
    partitioner: typing.Callable | None = None,
) -> tuple[dolfinx.mesh.Mesh, dolfinx.mesh.MeshTags, dolfinx.mesh.MeshTags]:
    """Mesh the rectangle ``origin + [0, w] x [0, h]`` with ``divisions`` along x and y."""
    gmsh.model.add(name)
    if comm.rank == 0:
        (x0, y0), (w, h), (nx, ny) = origin, size, divisions
        geo = gmsh.model.geo
        lc = w / nx
        p = [
            geo.addPoint(x0, y0, 0, lc),
            geo.addPoint(x0 + w, y0, 0, lc),
            geo.addPoint(x0 + w, y0 + h, 0, lc),
            geo.addPoint(x0, y0 + h, 0, lc),
        ]
        # Horizontal edges both run left to right (and vertical ones upwards), so that
        # blocks with the same divisions get bit-identical nodes on a shared line.
        lines = [
            geo.addLine(p[0], p[1]),  # bottom
            geo.addLine(p[1], p[2]),  # right
            geo.addLine(p[3], p[2]),  # top
            geo.addLine(p[0], p[3]),  # left
        ]
        loop = geo.addCurveLoop([lines[0], lines[1], -lines[2], -lines[3]])
        surface = geo.addPlaneSurface([loop])
        geo.synchronize()
        for line, n in zip(lines, (nx, ny, nx, ny), strict=True):
            gmsh.model.mesh.setTransfiniteCurve(line, n + 1)
        if cell == "quadrilateral":
            gmsh.model.mesh.setTransfiniteSurface(surface)
            gmsh.model.mesh.setRecombine(2, surface)
        gmsh.model.addPhysicalGroup(2, [surface], 1, name=name)
        for line, tag, label in zip(
            lines, (BOTTOM, RIGHT, TOP, LEFT), ("bottom", "right", "top", "left"), strict=True
        ):
            gmsh.model.addPhysicalGroup(1, [line], tag, name=label)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(degree)
        if msh_dir is not None:
            msh_dir.mkdir(parents=True, exist_ok=True)
            gmsh.write(str(msh_dir / f"{name}.msh"))
    mesh, cell_tags, facet_tags = model_to_mesh(gmsh.model, comm, 0, 2, partitioner=partitioner)
    gmsh.model.remove()
    mesh.name = name
    return mesh, cell_tags, facet_tags


def patch_test(
    comm: MPI.Comm,
    elements: tuple[int, int] = (10, 7),
    *,
    cell: str = "triangle",
    geometry_degree: int = 1,
    gap: float = 0.0,
    width: float = 1.0,
    height: float = 0.5,
    layers: tuple[int, int] | None = None,
    msh_dir: str | Path | None = None,
    partitioner: typing.Callable | None = None,
) -> PatchTestScene:
    """Two blocks pressed together along :math:`y = H` (Figs. 4 and 6 of the paper).

    Args:
        comm: Communicator the meshes are distributed over.
        elements: Number of elements along the contact line of the lower and the
            upper block; different numbers give non-matching meshes.
        cell: ``"triangle"`` (unstructured inside) or ``"quadrilateral"`` (structured).
        geometry_degree: 1 or 2 (straight-sided quadratic cells).
        gap: Initial gap :math:`g_0` between the blocks; negative for an overlap.
        width: Width :math:`W` of both blocks.
        height: Height :math:`H` of each block.
        layers: Number of elements across each block's height; by default about
            as many as keep the cells square.
        msh_dir: If given, rank 0 writes the Gmsh models there as ``lower.msh``
            and ``upper.msh``.
        partitioner: Cell partitioner of both meshes (see :func:`model_to_mesh`); None:
            DOLFINx's.

    Returns:
        The scene. Facet tags: bottom 1, right 2, top 3, left 4.
    """
    if cell not in ("triangle", "quadrilateral"):
        raise ValueError(f"cell must be 'triangle' or 'quadrilateral', not {cell!r}")
    if geometry_degree not in (1, 2):
        raise ValueError("geometry_degree must be 1 or 2")
    if min(elements) < 1:
        raise ValueError("each block needs at least one element along the contact line")
    if layers is None:
        layers = tuple(max(2, round(n * height / width)) for n in elements)  # type: ignore[assignment]
    tags = {"bottom": BOTTOM, "right": RIGHT, "top": TOP, "left": LEFT}
    out = Path(msh_dir) if msh_dir is not None else None
    with gmsh_session() as gmsh:
        lower = _block(
            gmsh,
            comm,
            "lower",
            (0.0, 0.0),
            (width, height),
            (elements[0], layers[0]),
            cell,
            geometry_degree,
            out,
            partitioner,
        )
        upper = _block(
            gmsh,
            comm,
            "upper",
            (0.0, height + gap),
            (width, height),
            (elements[1], layers[1]),
            cell,
            geometry_degree,
            out,
            partitioner,
        )
    return PatchTestScene(
        Body("lower", *lower, tags=dict(tags), contact=TOP),
        Body("upper", *upper, tags=dict(tags), contact=BOTTOM),
        width,
        height,
        gap,
    )


def inf_sup_model(
    comm: MPI.Comm,
    elements: tuple[int, int] = (10, 7),
    *,
    cell: str = "quadrilateral",
    geometry_degree: int = 1,
    gap: float = -0.01,
    width: float = 1.0,
    height: float = 0.5,
    msh_dir: str | Path | None = None,
    partitioner: typing.Callable | None = None,
) -> PatchTestScene:
    """The inf-sup model of Fig. 2: two blocks meshed independently, overlapping by ``-gap``.

    The meshes refine uniformly with ``elements`` (about square cells), so that a family
    of element counts is a family of meshes with decreasing :math:`h`. The paper
    evaluates solvability and the inf-sup tests on this model (section 3.1) with a
    negative initial gap :math:`g_0`.

    Args:
        comm: Communicator the meshes are distributed over.
        elements: Elements along the contact line of the lower and the upper block.
        cell: ``"triangle"`` or ``"quadrilateral"``.
        geometry_degree: 1 or 2.
        gap: Initial gap :math:`g_0`; negative (an overlap) as in the paper.
        width: Width of both blocks.
        height: Height of each block.
        msh_dir: If given, rank 0 writes the Gmsh models there.
        partitioner: Cell partitioner of both meshes (see :func:`model_to_mesh`).
    """
    return patch_test(
        comm,
        elements,
        cell=cell,
        geometry_degree=geometry_degree,
        gap=gap,
        width=width,
        height=height,
        msh_dir=msh_dir,
        partitioner=partitioner,
    )


def size_field(gmsh: typing.Any, point: int, near: float, far: float, reach: float) -> None:
    """Gmsh background field: size ``near`` within ``reach`` of ``point``, growing to ``far``.

    The size grows linearly (slope 0.3) beyond ``reach``; sizes from points, boundaries
    and curvature are switched off, so the field alone sizes the mesh.
    """
    f = gmsh.model.mesh.field
    distance = f.add("Distance")
    f.setNumbers(distance, "PointsList", [point])
    threshold = f.add("Threshold")
    f.setNumber(threshold, "InField", distance)
    f.setNumber(threshold, "SizeMin", near)
    f.setNumber(threshold, "SizeMax", far)
    f.setNumber(threshold, "DistMin", reach)
    f.setNumber(threshold, "DistMax", reach + (far - near) / 0.3)
    f.setAsBackgroundMesh(threshold)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)

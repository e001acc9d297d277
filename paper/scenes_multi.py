# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Scenes of several rectangular blocks, meshed the way users mesh them.

Each scene is a set of axis-parallel blocks pressed together by a uniform pressure
:math:`p` on their top faces. Gmsh builds the blocks on one rank and DOLFINx's Gmsh
reader distributes them. Blocks never share nodes (each block has its own points and
curves), so a mesh holding several blocks has several connected components; where
the blocks go is chosen by ``arrangement``:

- ``"one mesh"``: every block in one mesh (one displacement space for all bodies),
- ``"mixed"``: the blocks on one side of the contact line in one mesh, the others in
  another,
- ``"separate"``: one mesh per block.

Tags: block :math:`b` (numbered from 1 in the order given) carries cell tag :math:`b`
and facet tags :math:`10b` (bottom), :math:`10b + 2` (right), :math:`10b + 3` (top)
and :math:`10b + 4` (left), the same whichever mesh holds it, so that a tag names one
side of one block in every arrangement. The only exception is the lower block of the
two-block scenes, which keeps the tags of :func:`paper.scenes.patch_test`
for bottom 1, right 2 and left 4, and has top 10.

Every scene solves the patch problem exactly: :math:`\sigma_{yy} = -p`,
:math:`\sigma_{xx} = \sigma_{xy} = 0` in every block and a contact pressure
:math:`\lambda = p` wherever the blocks touch, whatever the materials (frictionless
contact lets blocks of different Poisson ratios slide along each other), as long as
blocks standing side by side under one block keep their tops level: they need the same
vertical compliance, :math:`(1 - \nu^2)/E` in plane strain. The supports
that give this solution are part of the scene: :attr:`BlocksScene.fixed_x` (sides with
:math:`u_x = 0`, one vertical side per block), :attr:`BlocksScene.fixed_y` (the bottom
of the lowest blocks) and :attr:`BlocksScene.loaded` (the top of the highest blocks).
"""

from __future__ import annotations

import typing
from dataclasses import dataclass

from mpi4py import MPI

import dolfinx
import numpy as np

from dolfinx_contact_s2s.compat import gmsh_model_to_mesh
from dolfinx_contact_s2s.meshing import gmsh_session

__all__ = [
    "ARRANGEMENTS",
    "SIDES",
    "Block",
    "BlocksScene",
    "MeshPart",
    "overhang",
    "three_blocks",
    "two_blocks_one_mesh",
    "two_on_one",
]

#: Where the blocks of a scene go (see the module docstring).
ARRANGEMENTS = ("one mesh", "mixed", "separate")

#: Sides of a block, in the order of the facet tag offsets 0, 2, 3 and 4.
SIDES = ("bottom", "right", "top", "left")

_OFFSETS = {"bottom": 0, "right": 2, "top": 3, "left": 4}

#: Facet tags of the lower block of the two-block scenes (the issue's numbering).
_TWO_BLOCKS_LOWER = {"bottom": 1, "right": 2, "top": 10, "left": 4}


@dataclass(frozen=True)
class Block:
    r"""A rectangular block :math:`[x_0, x_0 + w] \times [y_0, y_0 + h]` of a scene.

    Attributes:
        name: Name of the block, e.g. ``"lower"``.
        origin: Lower left corner :math:`(x_0, y_0)`.
        size: Width and height :math:`(w, h)`.
        elements: Elements along the horizontal and the vertical sides.
        cell_tag: Tag of the block's cells.
        tags: Facet tag of each side, e.g. ``{"bottom": 20, "right": 22, ...}``.
        mesh: Name of the :class:`MeshPart` that holds the block.
    """

    name: str
    origin: tuple[float, float]
    size: tuple[float, float]
    elements: tuple[int, int]
    cell_tag: int
    tags: dict[str, int]
    mesh: str

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` of the block."""
        (x0, y0), (w, h) = self.origin, self.size
        return x0, x0 + w, y0, y0 + h


@dataclass
class MeshPart:
    """One DOLFINx mesh of a scene, holding one or more blocks.

    Attributes:
        name: Name of the mesh.
        mesh: The mesh.
        cell_tags: Cell markers (each block's :attr:`Block.cell_tag`).
        facet_tags: Facet markers of the sides of its blocks.
        blocks: Names of the blocks in the mesh.
    """

    name: str
    mesh: dolfinx.mesh.Mesh
    cell_tags: dolfinx.mesh.MeshTags
    facet_tags: dolfinx.mesh.MeshTags
    blocks: tuple[str, ...]


@dataclass
class BlocksScene:
    """Blocks in one or more meshes, with the supports and load of the patch problem.

    Attributes:
        name: Name of the scene.
        blocks: The blocks by name.
        parts: The meshes by name.
        fixed_x: ``(block, side)`` of the sides where :math:`u_x = 0`.
        fixed_y: ``(block, side)`` of the sides where :math:`u_y = 0`.
        loaded: ``(block, side)`` of the sides under the pressure :math:`p`.
    """

    name: str
    blocks: dict[str, Block]
    parts: dict[str, MeshPart]
    fixed_x: tuple[tuple[str, str], ...]
    fixed_y: tuple[tuple[str, str], ...]
    loaded: tuple[tuple[str, str], ...]

    @property
    def tags(self) -> dict[str, int]:
        """Every facet tag by name ``"<block>_<side>"``, e.g. ``{"upper_bottom": 20, ...}``."""
        return {f"{b.name}_{s}": t for b in self.blocks.values() for s, t in b.tags.items()}

    def part(self, block: str) -> MeshPart:
        """The mesh that holds ``block``."""
        return self.parts[self.blocks[block].mesh]

    def tag(self, block: str, side: str) -> int:
        """Facet tag of a side of a block."""
        return self.blocks[block].tags[side]


def _check(cell: str, geometry_degree: int, arrangement: str) -> None:
    if cell not in ("triangle", "quadrilateral"):
        raise ValueError(f"cell must be 'triangle' or 'quadrilateral', not {cell!r}")
    if geometry_degree not in (1, 2):
        raise ValueError("geometry_degree must be 1 or 2")
    if arrangement not in ARRANGEMENTS:
        raise ValueError(f"arrangement must be one of {ARRANGEMENTS}, not {arrangement!r}")


def _block(
    name: str,
    number: int,
    origin: tuple[float, float],
    size: tuple[float, float],
    elements: int,
    layers: int | None,
    mesh: str,
    tags: dict[str, int] | None = None,
) -> Block:
    """A block numbered ``number`` with about square cells unless ``layers`` is given."""
    if elements < 1:
        raise ValueError(f"block {name!r} needs at least one element along its width")
    if layers is None:
        layers = max(2, round(elements * size[1] / size[0]))
    if tags is None:
        tags = {side: 10 * number + offset for side, offset in _OFFSETS.items()}
    return Block(name, origin, size, (elements, layers), number, dict(tags), mesh)


def _add_rectangle(gmsh: typing.Any, block: Block) -> tuple[int, dict[str, int]]:
    """Add ``block``'s own points, curves and surface to the current Gmsh model.

    Returns:
        The surface and the curve of each side (not yet synchronized).
    """
    geo = gmsh.model.geo
    (x0, y0), (w, h), (nx, _) = block.origin, block.size, block.elements
    lc = w / nx
    p = [
        geo.addPoint(x0, y0, 0, lc),
        geo.addPoint(x0 + w, y0, 0, lc),
        geo.addPoint(x0 + w, y0 + h, 0, lc),
        geo.addPoint(x0, y0 + h, 0, lc),
    ]
    # Horizontal curves run left to right, vertical ones upwards.
    lines = {
        "bottom": geo.addLine(p[0], p[1]),
        "right": geo.addLine(p[1], p[2]),
        "top": geo.addLine(p[3], p[2]),
        "left": geo.addLine(p[0], p[3]),
    }
    loop = geo.addCurveLoop([lines["bottom"], lines["right"], -lines["top"], -lines["left"]])
    return geo.addPlaneSurface([loop]), lines


def _model_blocks(gmsh: typing.Any, blocks: list[Block], cell: str, geometry_degree: int) -> None:
    """Mesh ``blocks`` in the current Gmsh model, with a physical group per block and side."""
    entities = [_add_rectangle(gmsh, block) for block in blocks]
    # One synchronization: a later one would reset the mesh constraints set below.
    gmsh.model.geo.synchronize()
    for block, (surface, lines) in zip(blocks, entities, strict=True):
        nx, ny = block.elements
        for side, line in lines.items():
            gmsh.model.mesh.setTransfiniteCurve(line, (nx if side in ("bottom", "top") else ny) + 1)
        if cell == "quadrilateral":
            gmsh.model.mesh.setTransfiniteSurface(surface)
            gmsh.model.mesh.setRecombine(2, surface)
        gmsh.model.addPhysicalGroup(2, [surface], block.cell_tag, name=block.name)
        for side, line in lines.items():
            gmsh.model.addPhysicalGroup(1, [line], block.tags[side], name=f"{block.name}_{side}")
    gmsh.model.mesh.generate(2)
    gmsh.model.mesh.setOrder(geometry_degree)
    for block, (_, lines) in zip(blocks, entities, strict=True):
        _snap(gmsh, block, lines, geometry_degree)


def _snap(gmsh: typing.Any, block: Block, lines: dict[str, int], geometry_degree: int) -> None:
    """Put the nodes inside the sides of ``block`` at their exact, uniform positions.

    Gmsh places the nodes of a transfinite curve up to about :math:`10^{-12}` off
    (:math:`1/3 + 6/9` lands at :math:`1 - 10^{-12}`), which would leave slivers
    where a node is meant to meet the end of another body's side.
    """
    (x0, y0), (w, h), (nx, ny) = block.origin, block.size, block.elements
    for side, line in lines.items():
        tags, coords, params = gmsh.model.mesh.getNodes(1, line, returnParametricCoord=True)
        coords = np.asarray(coords).reshape(-1, 3)
        axis, start, length, n = (0, x0, w, nx) if side in ("bottom", "top") else (1, y0, h, ny)
        n *= geometry_degree
        if len(tags) != n - 1:
            raise RuntimeError(f"side {side!r} of block {block.name!r} has no uniform nodes")
        order = np.argsort(coords[:, axis])
        coords[order, axis] = start + length * np.arange(1, n) / n
        for tag, x, t in zip(tags, coords, params, strict=True):
            gmsh.model.mesh.setNode(tag, x, [t])


def _mesh_blocks(
    comm: MPI.Comm,
    blocks: list[Block],
    cell: str,
    geometry_degree: int,
    partitioner: typing.Callable | None = None,
) -> dict[str, MeshPart]:
    """Mesh the blocks on rank 0, one Gmsh model per mesh name, and distribute them."""
    names = list(dict.fromkeys(b.mesh for b in blocks))
    parts = {}
    with gmsh_session() as gmsh:
        for name in names:
            mine = [b for b in blocks if b.mesh == name]
            gmsh.model.add(name)
            if comm.rank == 0:
                _model_blocks(gmsh, mine, cell, geometry_degree)
            mesh, cell_tags, facet_tags = gmsh_model_to_mesh(gmsh.model, comm, 0, 2, partitioner)
            gmsh.model.remove()
            mesh.name = name
            parts[name] = MeshPart(name, mesh, cell_tags, facet_tags, tuple(b.name for b in mine))
    return parts


def _two_blocks(
    comm: MPI.Comm,
    name: str,
    elements: tuple[int, int],
    shift: float,
    cell: str,
    geometry_degree: int,
    width: float,
    height: float,
    layers: tuple[int, int] | None,
    arrangement: str,
    partitioner: typing.Callable | None = None,
) -> BlocksScene:
    _check(cell, geometry_degree, arrangement)
    one = arrangement == "one mesh"
    lay = layers if layers is not None else (None, None)
    blocks = [
        _block(
            "lower",
            1,
            (0.0, 0.0),
            (width, height),
            elements[0],
            lay[0],
            "blocks" if one else "lower",
            _TWO_BLOCKS_LOWER,
        ),
        _block(
            "upper",
            2,
            (shift, height),
            (width, height),
            elements[1],
            lay[1],
            "blocks" if one else "upper",
        ),
    ]
    return BlocksScene(
        name,
        {b.name: b for b in blocks},
        _mesh_blocks(comm, blocks, cell, geometry_degree, partitioner),
        fixed_x=(("lower", "left"), ("upper", "left")),
        fixed_y=(("lower", "bottom"),),
        loaded=(("upper", "top"),),
    )


def two_blocks_one_mesh(
    comm: MPI.Comm,
    elements: tuple[int, int] = (13, 9),
    *,
    cell: str = "triangle",
    geometry_degree: int = 1,
    width: float = 1.0,
    height: float = 0.5,
    layers: tuple[int, int] | None = None,
    partitioner: typing.Callable | None = None,
) -> BlocksScene:
    r"""The patch test of Figs. 4 and 6 with both blocks in ONE mesh.

    The lower block :math:`[0, W] \times [0, H]` and the upper block :math:`[0, W]
    \times [H, 2H]` are two plane surfaces of one Gmsh model with separate curves along
    :math:`y = H`: one mesh of two connected components that share no node, as a user
    meshes two bodies. Both bodies then live in one displacement space.

    Args:
        comm: Communicator the mesh is distributed over.
        elements: Elements along the contact line of the lower and the upper block.
        cell: ``"triangle"`` or ``"quadrilateral"``.
        geometry_degree: 1 or 2.
        width: :math:`W`.
        height: :math:`H`.
        layers: Elements across the height of each block (default: about square cells).
        partitioner: Cell partitioner of the mesh (see
            :func:`dolfinx_contact_s2s.meshing.model_to_mesh`); None: DOLFINx's.

    Returns:
        The scene, with its one mesh in ``parts["blocks"]``. Cells: lower 1, upper 2.
        Facets: lower bottom 1, right 2, top 10, left 4; upper bottom 20, right 22,
        top 23, left 24.
    """
    return _two_blocks(
        comm,
        "two blocks",
        elements,
        0.0,
        cell,
        geometry_degree,
        width,
        height,
        layers,
        "one mesh",
        partitioner,
    )


def overhang(
    comm: MPI.Comm,
    elements: tuple[int, int] = (13, 9),
    shift: float = 1.0 / 3.0,
    *,
    arrangement: str = "one mesh",
    cell: str = "triangle",
    geometry_degree: int = 1,
    width: float = 1.0,
    height: float = 0.5,
    layers: tuple[int, int] | None = None,
    partitioner: typing.Callable | None = None,
) -> BlocksScene:
    r"""The patch test with the upper block shifted by ``shift``: it overhangs the lower one.

    The upper block is :math:`[s, s + W] \times [H, 2H]`, so its bottom beyond
    :math:`x = W` faces no target. With the default 9 upper elements over :math:`W = 1`
    and :math:`s = 1/3`, the target's end :math:`x = W` is a node of the contactor
    (:math:`1/3 + 6/9`). The stress is no longer uniform; the total contact force on
    the upper block still balances the load :math:`p W`.

    Args:
        comm: Communicator the meshes are distributed over.
        elements: Elements along the lower and the upper block.
        shift: Horizontal offset :math:`s` of the upper block.
        arrangement: ``"one mesh"`` or ``"separate"`` (``"mixed"`` is the same).
        cell: ``"triangle"`` or ``"quadrilateral"``.
        geometry_degree: 1 or 2.
        width: :math:`W` of both blocks.
        height: :math:`H` of both blocks.
        layers: Elements across the height of each block.
        partitioner: Cell partitioner of the meshes (see
            :func:`dolfinx_contact_s2s.meshing.model_to_mesh`); None: DOLFINx's.

    Returns:
        The scene; tags as in :func:`two_blocks_one_mesh`, meshes ``"blocks"`` (one
        mesh) or ``"lower"`` and ``"upper"``.
    """
    return _two_blocks(
        comm,
        "overhang",
        elements,
        shift,
        cell,
        geometry_degree,
        width,
        height,
        layers,
        arrangement,
        partitioner,
    )


def three_blocks(
    comm: MPI.Comm,
    widths: tuple[float, float] = (0.45, 0.55),
    elements: tuple[int, int, int] = (5, 6, 7),
    *,
    arrangement: str = "mixed",
    cell: str = "triangle",
    geometry_degree: int = 1,
    height: float = 0.5,
    partitioner: typing.Callable | None = None,
) -> BlocksScene:
    r"""The patch test of Taylor and Papadopoulos (ref. [17], Fig. 3 of the paper).

    An upper block :math:`[0, W] \times [H, 2H]`, :math:`W = w_1 + w_2`, rests on two
    lower blocks :math:`[0, w_1] \times [0, H]` and :math:`[w_1, W] \times [0, H]`
    standing side by side. With the defaults the joint :math:`x = 0.45` of the lower
    blocks is no node of the upper block's bottom (nodes at :math:`k/7`), so a
    contactor facet faces two targets at once. The lower blocks are held horizontally
    at the joint (each expands away from it), the upper block at its left side. The
    lower blocks need the same vertical compliance (:math:`(1 - \nu^2)/E` in plane
    strain) for the exact solution to be uniform.

    Args:
        comm: Communicator the meshes are distributed over.
        widths: Widths :math:`w_1, w_2` of the left and the right lower block.
        elements: Elements along the left lower, the right lower and the upper block.
        arrangement: ``"mixed"`` (the lower blocks in mesh ``"lower"``, the upper block
            in mesh ``"upper"``), ``"one mesh"`` (mesh ``"blocks"``) or ``"separate"``
            (meshes named after the blocks).
        cell: ``"triangle"`` or ``"quadrilateral"``.
        geometry_degree: 1 or 2.
        height: :math:`H` of every block.
        partitioner: Cell partitioner of the meshes (see
            :func:`dolfinx_contact_s2s.meshing.model_to_mesh`); None: DOLFINx's.

    Returns:
        The scene. Blocks ``"lower_left"`` (cells 1, facets 10, 12, 13, 14),
        ``"lower_right"`` (cells 2, facets 20, 22, 23, 24) and ``"upper"`` (cells 3,
        facets 30, 32, 33, 34), facet tags in the order bottom, right, top, left.
    """
    _check(cell, geometry_degree, arrangement)
    w1, w2 = widths
    mesh = {
        "one mesh": ("blocks",) * 3,
        "mixed": ("lower", "lower", "upper"),
        "separate": ("lower_left", "lower_right", "upper"),
    }[arrangement]
    blocks = [
        _block("lower_left", 1, (0.0, 0.0), (w1, height), elements[0], None, mesh[0]),
        _block("lower_right", 2, (w1, 0.0), (w2, height), elements[1], None, mesh[1]),
        _block("upper", 3, (0.0, height), (w1 + w2, height), elements[2], None, mesh[2]),
    ]
    return BlocksScene(
        "three blocks",
        {b.name: b for b in blocks},
        _mesh_blocks(comm, blocks, cell, geometry_degree, partitioner),
        fixed_x=(("lower_left", "right"), ("lower_right", "left"), ("upper", "left")),
        fixed_y=(("lower_left", "bottom"), ("lower_right", "bottom")),
        loaded=(("upper", "top"),),
    )


def two_on_one(
    comm: MPI.Comm,
    widths: tuple[float, float] = (0.4, 0.6),
    elements: tuple[int, int, int] = (7, 3, 5),
    *,
    arrangement: str = "mixed",
    cell: str = "triangle",
    geometry_degree: int = 1,
    height: float = 0.5,
    partitioner: typing.Callable | None = None,
) -> BlocksScene:
    r"""Two upper blocks side by side resting on one lower block (Fig. 3 upside down).

    The lower block is :math:`[0, W] \times [0, H]`, :math:`W = w_1 + w_2`, the upper
    blocks :math:`[0, w_1] \times [H, 2H]` and :math:`[w_1, W] \times [H, 2H]`. With
    the defaults the joint :math:`x = 0.4` of the upper blocks is no node of the lower
    block's top (nodes at :math:`k/7`). The upper blocks are held horizontally at the
    joint, the lower block at its left side.

    Args:
        comm: Communicator the meshes are distributed over.
        widths: Widths :math:`w_1, w_2` of the left and the right upper block.
        elements: Elements along the lower, the left upper and the right upper block.
        arrangement: ``"mixed"`` (the upper blocks in mesh ``"upper"``, the lower block
            in mesh ``"lower"``), ``"one mesh"`` (mesh ``"blocks"``) or ``"separate"``
            (meshes named after the blocks).
        cell: ``"triangle"`` or ``"quadrilateral"``.
        geometry_degree: 1 or 2.
        height: :math:`H` of every block.
        partitioner: Cell partitioner of the meshes (see
            :func:`dolfinx_contact_s2s.meshing.model_to_mesh`); None: DOLFINx's.

    Returns:
        The scene. Blocks ``"lower"`` (cells 1, facets 10, 12, 13, 14),
        ``"upper_left"`` (cells 2, facets 20, 22, 23, 24) and ``"upper_right"``
        (cells 3, facets 30, 32, 33, 34), facet tags in the order bottom, right, top,
        left.
    """
    _check(cell, geometry_degree, arrangement)
    w1, w2 = widths
    mesh = {
        "one mesh": ("blocks",) * 3,
        "mixed": ("lower", "upper", "upper"),
        "separate": ("lower", "upper_left", "upper_right"),
    }[arrangement]
    blocks = [
        _block("lower", 1, (0.0, 0.0), (w1 + w2, height), elements[0], None, mesh[0]),
        _block("upper_left", 2, (0.0, height), (w1, height), elements[1], None, mesh[1]),
        _block("upper_right", 3, (w1, height), (w2, height), elements[2], None, mesh[2]),
    ]
    return BlocksScene(
        "two on one",
        {b.name: b for b in blocks},
        _mesh_blocks(comm, blocks, cell, geometry_degree, partitioner),
        fixed_x=(("lower", "left"), ("upper_left", "right"), ("upper_right", "left")),
        fixed_y=(("lower", "bottom"),),
        loaded=(("upper_left", "top"), ("upper_right", "top")),
    )

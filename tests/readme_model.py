# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""The README's Gmsh model, as the tests build it: two blocks in one mesh.

Lower block ``[0, 1] x [0, 0.5]`` (facet tags bottom 1, right 2, top 10, left 4), upper
block ``[0, 1] x [0.5, 1]`` (bottom 20, right 22, top 23, left 24), cell tag 1 for both;
the contact lines do not share nodes. Built as the README builds it (one
``synchronize`` before the mesh settings), with the element counts as arguments.
"""

from mpi4py import MPI

import gmsh

from dolfinx_contact_s2s.meshing import model_to_mesh

LOWER = {"bottom": 1, "right": 2, "top": 10, "left": 4}
UPPER = {"bottom": 20, "right": 22, "top": 23, "left": 24}


def readme_mesh(
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    lower: int = 13,
    upper: int = 9,
    sides: int = 4,
    quads: bool | str = False,
    partitioner=None,
):
    """The mesh and facet tags of the README model (collective).

    Args:
        comm: Communicator of the mesh (Gmsh runs on its rank 0).
        lower: Elements along the lower block's top and bottom.
        upper: Elements along the upper block's bottom and top.
        sides: Elements along the vertical sides of both blocks.
        quads: ``True`` recombines both blocks into quadrilaterals, ``"upper"`` only the
            upper one (a model of two cell types).
        partitioner: DOLFINx's cell partitioner, or None for its default.
    """
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        gmsh.model.add("readme")
        if comm.rank == 0:
            geo, blocks = gmsh.model.geo, []
            for y0, n, tags in ((0.0, lower, LOWER), (0.5, upper, UPPER)):
                corners = ((0, y0), (1, y0), (1, y0 + 0.5), (0, y0 + 0.5))
                p = [geo.addPoint(x, y, 0) for x, y in corners]
                lines = [geo.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
                blocks.append((geo.addPlaneSurface([geo.addCurveLoop(lines)]), lines, n, tags))
            geo.synchronize()  # once: mesh settings made before a later synchronize are lost
            for surface, lines, n, tags in blocks:
                counts = (n, sides, n, sides)
                for line, tag, count in zip(lines, tags.values(), counts, strict=True):
                    gmsh.model.mesh.setTransfiniteCurve(line, count + 1)
                    gmsh.model.addPhysicalGroup(1, [line], tag)
                if quads is True or (quads == "upper" and tags is UPPER):
                    gmsh.model.mesh.setTransfiniteSurface(surface)
                    gmsh.model.mesh.setRecombine(2, surface)
            gmsh.model.addPhysicalGroup(2, [b[0] for b in blocks], 1)
            gmsh.model.mesh.generate(2)
        mesh, _, facets = model_to_mesh(gmsh.model, comm, 0, gdim=2, partitioner=partitioner)
    finally:
        gmsh.finalize()
    return mesh, facets

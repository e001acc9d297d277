# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""The two-block setup shared by the studies: spaces, forms, supports and pairs.

Both the patch test (section 3.2, Figs. 4 and 6) and the inf-sup model (Fig. 2) are a
lower and an upper block of :func:`paper.scenes.patch_test`, each a mesh
and a displacement space of its own, with different materials on purpose:

- ``support="rollers"``: :math:`u_x = 0` on the left edges, :math:`u_y = 0` on the
  lower block's bottom (the patch test);
- ``support="clamped"``: :math:`\mathbf u = 0` on the lower block's bottom and on the
  upper block's top (the inf-sup model).
"""

from __future__ import annotations

import typing

import dolfinx
import numpy as np
import ufl

from dolfinx_contact_s2s.elasticity import Material
from dolfinx_contact_s2s.pair import ContactPair, contact_pairs
from dolfinx_contact_s2s.surface import ContactSurface, contact_surface
from paper.scenes import BOTTOM, LEFT, TOP, PatchTestScene

if typing.TYPE_CHECKING:
    from dolfinx_contact_s2s.problem import LinearContactProblem

__all__ = [
    "MATERIALS",
    "NAMES",
    "block_forms",
    "block_pairs",
    "block_problem",
    "block_spaces",
    "block_surfaces",
]

#: Materials of the lower and upper block; they differ on purpose.
MATERIALS = {"lower": Material(E=1.0, nu=0.3), "upper": Material(E=3.0, nu=0.2)}

#: The bodies in the order of the problem's spaces.
NAMES = ("lower", "upper")


def block_spaces(
    scene: PatchTestScene, degrees: tuple[int, int]
) -> dict[str, dolfinx.fem.FunctionSpace]:
    """Vector Lagrange spaces of degree ``degrees`` (lower, upper) on the two blocks."""
    return {
        name: dolfinx.fem.functionspace(
            scene.bodies[name].mesh, ("Lagrange", k, (scene.bodies[name].mesh.geometry.dim,))
        )
        for name, k in zip(NAMES, degrees, strict=True)
    }


def block_surfaces(
    scene: PatchTestScene, spaces: dict[str, dolfinx.fem.FunctionSpace]
) -> dict[str, ContactSurface]:
    """The contact surface of each block: the lower block's top, the upper one's bottom."""
    return {
        name: contact_surface(V, scene.bodies[name].facet_tags, scene.bodies[name].contact)
        for name, V in spaces.items()
    }


def block_pairs(
    scene: PatchTestScene,
    spaces: dict[str, dolfinx.fem.FunctionSpace],
    contactor: str,
    **pair_options: typing.Any,
) -> list[ContactPair]:
    """The pair(s) of a discretization with ``contactor`` (``"upper"``/``"lower"``)."""
    if contactor not in NAMES:
        raise ValueError("contactor must be 'upper' or 'lower'")
    surfaces = block_surfaces(scene, spaces)
    target = "lower" if contactor == "upper" else "upper"
    return contact_pairs(surfaces[contactor], surfaces[target], **pair_options)


def block_forms(
    scene: PatchTestScene,
    spaces: dict[str, dolfinx.fem.FunctionSpace],
    *,
    support: str,
    pressure: float = 0.0,
) -> tuple[list[ufl.Form], list[ufl.Form], list[dolfinx.fem.DirichletBC]]:
    """Elasticity forms, a pressure on the upper block's top and the supports."""
    if support not in ("rollers", "clamped"):
        raise ValueError(f"support must be 'rollers' or 'clamped', not {support!r}")
    a, L, bcs = [], [], []
    for name in NAMES:
        body, V = scene.bodies[name], spaces[name]
        mesh = body.mesh
        fdim = mesh.topology.dim - 1
        a_body, _, v = MATERIALS[name].forms(V)
        load = pressure if name == "upper" else 0.0
        t = dolfinx.fem.Constant(mesh, np.array([0.0, -load], dtype=dolfinx.default_scalar_type))
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=body.facet_tags)
        a.append(a_body)
        L.append(ufl.inner(t, v) * ds(TOP))
        zero = dolfinx.default_scalar_type(0.0)
        if support == "rollers":
            left = dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, body.facet_tags.find(LEFT))
            bcs.append(dolfinx.fem.dirichletbc(zero, left, V.sub(0)))
            if name == "lower":
                bottom = body.facet_tags.find(BOTTOM)
                dofs = dolfinx.fem.locate_dofs_topological(V.sub(1), fdim, bottom)
                bcs.append(dolfinx.fem.dirichletbc(zero, dofs, V.sub(1)))
        else:
            clamped = BOTTOM if name == "lower" else TOP
            dofs = dolfinx.fem.locate_dofs_topological(V, fdim, body.facet_tags.find(clamped))
            u0 = dolfinx.fem.Constant(mesh, np.zeros(2, dtype=dolfinx.default_scalar_type))
            bcs.append(dolfinx.fem.dirichletbc(u0, dofs, V))
    return a, L, bcs


def block_problem(
    scene: PatchTestScene,
    degrees: tuple[int, int],
    contactor: str,
    *,
    support: str,
    pressure: float = 0.0,
    petsc_options_prefix: str,
    petsc_options: dict | None = None,
    kind: str = "aij",
    **pair_options: typing.Any,
) -> LinearContactProblem:
    """The tied contact problem (Eq. 18) of the two blocks, not yet assembled.

    ``kind`` is passed to the problem (``"nest"`` for a field-split solver).
    """
    from dolfinx_contact_s2s.problem import LinearContactProblem

    spaces = block_spaces(scene, degrees)
    a, L, bcs = block_forms(scene, spaces, support=support, pressure=pressure)
    pairs = block_pairs(scene, spaces, contactor, **pair_options)
    return LinearContactProblem(
        a,
        L,
        pairs,
        bcs,
        petsc_options_prefix=petsc_options_prefix,
        petsc_options=petsc_options,
        kind=kind,
    )

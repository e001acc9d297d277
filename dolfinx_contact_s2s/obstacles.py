# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Rigid obstacles as contact targets: meshed rigid surfaces and analytic obstacles.

A rigid target carries no displacement unknowns: the saddle point of Eq. (18) has no
target block. In the coupling of Eq. (17),

.. math:: b(\mathbf v_h, \mu_h) = \int_{\Gamma_C} \mu_h\,
    [(\mathbf v_C - \mathbf v_T^*) \cdot \mathbf N + g_0]\, d\Gamma_C,

the target displacement :math:`\mathbf v_T` of a rigid target is known, so its part
moves to the gap:

- A **meshed rigid surface** (:func:`rigid_surface`) is a
  :class:`~dolfinx_contact_s2s.surface.ContactSurface` on the facets of any DOLFINx mesh
  that carries no form (a second body of the user's Gmsh model, say). Every
  discretization integrates it as a deformable target (Eqs. 37-42); the target block
  :math:`\mathbf B_T` (Eq. 40) is kept out of the saddle point and acts on the
  prescribed rigid motion :math:`\mathbf U_T(t)` of the load factor :math:`t` instead:
  :math:`\mathbf G(t) = \mathbf G + \mathbf B_T \mathbf U_T(t)`, the same place where
  the Dirichlet values enter (``-B U = G + t B U_D``). A rigid motion is affine in
  :math:`\mathbf x`, so its interpolation on the target's nodes is exact (affine cells).
- An **analytic obstacle** (:func:`plane_obstacle`, :func:`circle_obstacle`,
  :func:`obstacle`) is a signed distance :math:`d` (positive outside the obstacle, where
  the contactor is) with its gradient. At a contactor point :math:`\mathbf x` the gap
  after a displacement :math:`\mathbf u` is :math:`d(\mathbf x + \mathbf u) \approx
  d + \nabla d \cdot \mathbf u`; with :math:`\hat{\mathbf n} = \nabla d / |\nabla d|`
  the constraint of Eq. (17) reads

  .. math:: \int_{\Gamma_C} \mu_k \left(\frac{d}{|\nabla d|} + \hat{\mathbf n}\cdot
      \mathbf u_C\right) d\Gamma_C \ge 0 \quad (= 0 \text{ tied}),

  i.e. :math:`B_C[k, jc] = \int \mu_k h_j \hat n_c` and :math:`G_k = \int \mu_k\,
  d/|\nabla d|`: the contactor rows of Eq. (40) with :math:`\mathbf N =
  \hat{\mathbf n}` (which is :math:`-\mathbf n_C` where the surfaces touch) and no
  target rows. There are no target nodes, so the (composite) segments are the
  contactor's: the points and weights ``g.weights`` are the pair's rule on the contactor
  segments (:meth:`~dolfinx_contact_s2s.discretizations.Discretization.point_rule`), the
  same per-point weights as :meth:`~dolfinx_contact_s2s.pair.ContactPair._integrate`.

The contactor must be deformable: it carries the multiplier. The contact is linearized
about the reference configuration, as for deformable targets: prescribed motions must
be small compared to the contact's geometry.
"""

from __future__ import annotations

import typing
from collections.abc import Callable

import dolfinx
import numpy as np
import numpy.typing as npt

from dolfinx_contact_s2s.compat import blocked_sub_element
from dolfinx_contact_s2s.discretizations import PointGroups
from dolfinx_contact_s2s.multiplier import cell_rows
from dolfinx_contact_s2s.pair import ContactPair, CouplingBlocks
from dolfinx_contact_s2s.surface import ContactSurface

__all__ = [
    "AnalyticObstacle",
    "RigidSurface",
    "circle_obstacle",
    "obstacle",
    "plane_obstacle",
    "rigid_surface",
]

#: A prescribed motion: ``(translation, angle)`` at load factor 1 (scaled by the load
#: factor), or a callable of the load factor returning ``(translation, angle)``.
Motion = tuple[npt.ArrayLike, float] | Callable[[float], tuple[npt.ArrayLike, float]] | None


class RigidSurface(ContactSurface):
    r"""Tagged facets of a mesh that carries no form: a rigid contact target.

    A :class:`~dolfinx_contact_s2s.surface.ContactSurface` on a displacement space of its
    own (:attr:`V`, which no form of the problem uses), moved by a prescribed rigid
    motion :math:`\mathbf u(\mathbf x; t) = \mathbf d(t) + (\mathbf R(\theta(t)) -
    \mathbf I)(\mathbf x - \mathbf c)`. Give it to
    :func:`~dolfinx_contact_s2s.pair.contact_pair` as a target only.

    Attributes:
        motion: The prescribed motion as given (``None``: fixed).
        centre: :math:`\mathbf c`, the centre of rotation.
    """

    rigid = True

    def __init__(
        self,
        mesh: dolfinx.mesh.Mesh,
        facet_tags: dolfinx.mesh.MeshTags,
        tag: int,
        *,
        degree: int | None = None,
        motion: Motion = None,
        centre: npt.ArrayLike | None = None,
        backend: str = "auto",
    ):
        """See :func:`rigid_surface`."""
        gdim = mesh.geometry.dim
        if mesh.topology.dim != 2:
            # The prescribed motion is a plane one: a translation and one angle.
            raise NotImplementedError("rigid surfaces are implemented for 2D meshes only")
        if degree is None:
            degree = blocked_sub_element(mesh.ufl_domain().ufl_coordinate_element()).degree
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (gdim,)))
        super().__init__(V, facet_tags, tag, backend=backend)
        c = np.zeros(gdim) if centre is None else np.asarray(centre, dtype=np.float64)
        if c.shape != (gdim,) or not np.all(np.isfinite(c)):
            raise ValueError(f"centre must be {gdim} finite coordinates, not {centre!r}")
        if motion is not None and not callable(motion):
            motion = _checked_motion(motion, gdim, "motion")
        self.motion = motion
        self.centre = c
        # A wrong motion raises here, on every rank (the callable is the same on all).
        self.motion_at(1.0)

    def motion_at(self, load: float) -> tuple[npt.NDArray[np.floating], float]:
        """Translation and rotation angle (radians) at load factor ``load``.

        Raises:
            ValueError: If the motion (or the callable's value) is not a translation of
                ``gdim`` finite values and one finite angle.
        """
        gdim = self.V.mesh.geometry.dim
        if self.motion is None:
            return np.zeros(gdim), 0.0
        if callable(self.motion):
            return _checked_motion(self.motion(float(load)), gdim, "motion(load)")
        d, theta = self.motion
        return load * d, load * theta

    def displacement(self, load: float = 1.0) -> dolfinx.fem.Function:
        r"""The rigid motion at load factor ``load`` interpolated in :attr:`V` (exact)."""
        d, theta = self.motion_at(load)
        c, s = np.cos(theta), np.sin(theta)
        R = np.array([[c - 1.0, -s], [s, c - 1.0]])
        centre = self.centre

        def values(x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
            return d[:, None] + R @ (x[:2] - centre[:, None])

        u = dolfinx.fem.Function(self.V, name=f"rigid_motion_{self.tag}")
        u.interpolate(values)
        return u


def _checked_motion(value: typing.Any, gdim: int, what: str) -> tuple[np.ndarray, float]:
    """``(translation, angle)`` as arrays, or ValueError naming ``what``."""
    try:
        d, theta = value
        d = np.asarray(d, dtype=np.float64)
        theta = float(theta)
    except (TypeError, ValueError) as error:
        raise ValueError(
            f"{what} must be (translation, angle): a translation of {gdim} values and a "
            f"rotation angle in radians, not {value!r}"
        ) from error
    if d.shape != (gdim,) or not (np.all(np.isfinite(d)) and np.isfinite(theta)):
        raise ValueError(
            f"{what} must be (translation, angle) with a translation of shape ({gdim},) "
            f"and finite values; got a translation of shape {d.shape} and angle {theta!r}"
        )
    return d, theta


def rigid_surface(
    mesh: dolfinx.mesh.Mesh,
    facet_tags: dolfinx.mesh.MeshTags,
    tag: int,
    *,
    degree: int | None = None,
    motion: Motion = None,
    centre: npt.ArrayLike | None = None,
    backend: str = "auto",
) -> RigidSurface:
    r"""A rigid contact target: the facets marked ``tag`` of ``mesh`` (collective).

    The mesh carries no form and no unknowns (a tool, a die, a rigid floor: a second
    mesh of the user's Gmsh model). Use the surface as a target of
    :func:`~dolfinx_contact_s2s.pair.contact_pair`, with any discretization; the
    saddle point has no target block, and the prescribed motion moves the gap
    (:mod:`dolfinx_contact_s2s.obstacles`). A body held only by rigid obstacles is
    supported where it touches them; the unilateral solve names it when its contact
    opens.

    Args:
        mesh: A 2D triangle or quadrilateral mesh with ``gdim=2``.
        facet_tags: Facet markers of ``mesh``.
        tag: The marker of the rigid contact facets (on the mesh boundary).
        degree: Degree of the Lagrange space the coupling is integrated in; defaults to
            the degree of the mesh's geometry (exact for any rigid motion).
        motion: The prescribed rigid motion :math:`\mathbf u(\mathbf x) = \mathbf d +
            (\mathbf R(\theta) - \mathbf I)(\mathbf x - \mathbf c)`: ``None`` (fixed);
            ``(d, theta)``, the translation and the rotation angle (radians,
            counterclockwise) at load factor 1, scaled by the load factor :math:`t` as
            Dirichlet values are (:math:`t\mathbf d`, :math:`t\theta`); or a callable
            ``motion(t) -> (d, theta)`` of the load factor for any other path. The tied
            problem uses :math:`t = 1`; the unilateral problem each of its load steps.
        centre: :math:`\mathbf c`, the centre of rotation (default the origin).
        backend: The kernel backend, see
            :func:`~dolfinx_contact_s2s.surface.contact_surface`.

    Returns:
        The :class:`RigidSurface`.

    Raises:
        ValueError: On every rank: as :func:`~dolfinx_contact_s2s.surface.contact_surface`;
            a ``centre`` or ``motion`` (or the value of ``motion(1.0)``) of the wrong
            shape or not finite.
    """
    return RigidSurface(
        mesh, facet_tags, tag, degree=degree, motion=motion, centre=centre, backend=backend
    )


class AnalyticObstacle:
    r"""A rigid obstacle given by a signed distance :math:`d` and its gradient.

    :math:`d > 0` outside the obstacle (where the contactor lies), :math:`\nabla d`
    points out of it. Give it to :func:`~dolfinx_contact_s2s.pair.contact_pair` as a
    target; :meth:`coupling_blocks` integrates the contactor rows of Eq. (40) with
    :math:`\mathbf N = \nabla d / |\nabla d|` and :math:`g_0 = d / |\nabla d|`.

    Attributes:
        distance: ``distance(x) -> d``, ``x`` of shape ``(gdim, n)``, ``d`` of shape ``(n,)``.
        gradient: ``gradient(x) -> grad``, of shape ``(gdim, n)``.
        tag: A name for messages.
    """

    rigid = True
    analytic = True

    def __init__(
        self,
        distance: Callable[[npt.NDArray[np.floating]], npt.ArrayLike],
        gradient: Callable[[npt.NDArray[np.floating]], npt.ArrayLike],
        *,
        name: str = "obstacle",
    ):
        """See :func:`obstacle`."""
        if not (callable(distance) and callable(gradient)):
            raise ValueError("an obstacle needs callables distance(x) and gradient(x)")
        self.distance = distance
        self.gradient = gradient
        self.tag = name

    def evaluate(
        self, x: npt.NDArray[np.floating]
    ) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.floating]]:
        r"""Gap :math:`d/|\nabla d|` and unit normal at points ``x`` of shape ``(n, gdim)``.

        Raises:
            ValueError: For values of the wrong shape, not finite, or a zero gradient
                (on this rank: :meth:`coupling_blocks` raises on every rank).
        """
        n, gdim = x.shape
        points = np.ascontiguousarray(x.T)
        d = np.asarray(self.distance(points), dtype=np.float64)
        grad = np.asarray(self.gradient(points), dtype=np.float64)
        if d.shape != (n,) or grad.shape != (gdim, n):
            raise ValueError(
                f"obstacle {self.tag}: distance(x) must return shape ({n},) and gradient(x) "
                f"shape ({gdim}, {n}) for x of shape ({gdim}, {n}); got {d.shape} and "
                f"{grad.shape}"
            )
        norm = np.linalg.norm(grad, axis=0)
        if not (np.all(np.isfinite(d)) and np.all(np.isfinite(grad)) and np.all(norm > 0)):
            raise ValueError(
                f"obstacle {self.tag}: the distance and its gradient must be finite, the "
                "gradient nonzero, at every contactor point"
            )
        return d / norm, (grad / norm).T

    def coupling_blocks(self, pair: ContactPair) -> CouplingBlocks:
        r"""The contactor rows of Eq. (40) against this obstacle (collective).

        The points are the pair's rule on the contactor segments; a point takes part when
        it faces the obstacle (:math:`\mathbf N_C \cdot \hat{\mathbf n} > 0`,
        :math:`\mathbf N_C = -\mathbf n_C`) within the pair's search radius along its
        normal, as the search pairs facets.

        Raises:
            ValueError: On every rank, for a contactor on the wrong side: a point inside
                the obstacle by more than the search radius, or points within reach that
                all face away from it.
        """
        cs, C = pair.contactor, pair.contactor.data
        comm = cs.comm
        rows, xi, weights, _ = pair.discretization.point_rule(pair)
        _, x, _ = cs.evaluate(C, rows, xi)
        N = -cs.outward_normals(C, rows, xi)
        message = ""
        try:
            gap, normal = self.evaluate(x)
        except ValueError as error:
            message = str(error)
        message = next((m for m in comm.allgather(message) if m), "")
        if message:
            raise ValueError(message)
        cos = np.einsum("pc,pc->p", N, normal)
        radius = pair.search_radius
        near = np.abs(gap) <= radius
        facing = (cos > 0.0) & (np.abs(gap) <= radius * cos)
        inside = gap < -radius
        counts = comm.allreduce(
            np.array([np.count_nonzero(inside), np.count_nonzero(facing), np.count_nonzero(near)])
        )
        if counts[0] or (counts[1] == 0 and counts[2] > 0):
            where = x[inside][:1] if counts[0] else x[near][:1]
            first = next(w for w in comm.allgather(where) if w.size)[0]
            cause = (
                f"{counts[0]} contactor point(s) lie inside it by more than the search "
                f"radius {radius:g}"
                if counts[0]
                else "the contactor's points within reach all face away from it"
            )
            raise ValueError(
                f"contactor {cs.tag} is on the wrong side of obstacle {self.tag}: {cause} "
                f"(the first at ({first[0]:.6g}, {first[1]:.6g})). The obstacle's distance "
                "must be positive outside it, where the contactor is, and its gradient "
                "point out of it (flip the plane's normal, or the circle's inside=)"
            )
        sel = np.flatnonzero(facing)
        r = rows[sel]
        mu = pair.multiplier.basis(r, xi[sel], cs.backend)
        phi = cs.facet_basis(C, r, xi[sel])
        rows_q = cell_rows(pair.multiplier, r)
        none = np.full(sel.size, -1, np.int32)
        g = PointGroups(r, none, xi[sel, None], weights[sel, None], rows_q)
        S = sel.size
        b_c, _, gap_int = cs.backend.segment_to_segment(
            mu[:, None, :],
            phi[:, None, :],
            np.zeros((S, 1, 1)),
            np.ascontiguousarray(normal[sel, None, :]),
            pair.point_weights(g, x[sel]),
            gap[sel, None],
        )
        signed = mu * g.weights
        return CouplingBlocks(
            self,  # type: ignore[arg-type]
            g.rows,
            C.dofs[r],
            b_c,
            np.zeros((S, 0), np.int64),
            np.zeros((S, mu.shape[1], 0)),
            gap_int,
            mu**2 * g.weights if pair.squared_coverage else signed,
            signed,
        )


def obstacle(
    distance: Callable[[npt.NDArray[np.floating]], npt.ArrayLike],
    gradient: Callable[[npt.NDArray[np.floating]], npt.ArrayLike],
    *,
    name: str = "obstacle",
) -> AnalyticObstacle:
    r"""A rigid obstacle of any shape, from its signed distance and gradient.

    Args:
        distance: ``distance(x)`` for points ``x`` of shape ``(gdim, n)`` (the layout of
            DOLFINx's ``Function.interpolate``, without the third row), returning shape
            ``(n,)``: positive outside the obstacle, where the contactor is.
        gradient: ``gradient(x)``, shape ``(gdim, n)``: pointing out of the obstacle. Only
            its direction matters; the gap is :math:`d / |\nabla d|` (a level set that is
            not a distance is read to first order).
        name: A name for messages.

    Returns:
        The :class:`AnalyticObstacle`, a target of
        :func:`~dolfinx_contact_s2s.pair.contact_pair`.
    """
    return AnalyticObstacle(distance, gradient, name=name)


def plane_obstacle(
    point: npt.ArrayLike, normal: npt.ArrayLike, *, name: str = "plane"
) -> AnalyticObstacle:
    r"""The rigid half-plane :math:`(\mathbf x - \mathbf p) \cdot \mathbf n \le 0`.

    Args:
        point: A point :math:`\mathbf p` of its boundary line.
        normal: Its outward normal :math:`\mathbf n` (towards the contactor; normalized).
        name: A name for messages.
    """
    p = np.asarray(point, dtype=np.float64)
    n = np.asarray(normal, dtype=np.float64)
    if p.shape != n.shape or p.ndim != 1 or not np.linalg.norm(n) > 0:
        raise ValueError("a plane needs a point and a nonzero normal of the same dimension")
    n = n / np.linalg.norm(n)
    return AnalyticObstacle(
        lambda x: n @ (x - p[:, None]),
        lambda x: np.repeat(n[:, None], x.shape[1], axis=1),
        name=name,
    )


def circle_obstacle(
    centre: npt.ArrayLike, radius: float, *, inside: bool = False, name: str = "circle"
) -> AnalyticObstacle:
    r"""A rigid disc (or, axisymmetric, a sphere) of ``radius`` about ``centre``.

    Args:
        centre: Its centre.
        radius: Its radius.
        inside: ``False``: the contactor is outside the disc (a roller, a ball); ``True``:
            inside it (a rigid hole, a die): the obstacle is the disc's complement.
        name: A name for messages.
    """
    c = np.asarray(centre, dtype=np.float64)
    R = float(radius)
    if c.ndim != 1 or not R > 0:
        raise ValueError("a circle needs a centre and a positive radius")
    sign = -1.0 if inside else 1.0

    def distance(x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        return sign * (np.linalg.norm(x - c[:, None], axis=0) - R)

    def gradient(x: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
        r = x - c[:, None]
        return sign * r / np.linalg.norm(r, axis=0)

    return AnalyticObstacle(distance, gradient, name=name)

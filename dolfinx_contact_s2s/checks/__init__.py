# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
r"""Diagnostics run before Eq. (18) is solved: floating bodies and redundant constraints.

The saddle point problem of Eq. (18),

.. math::
    \begin{bmatrix} \mathbf K & -\mathbf B^T \\ -\mathbf B & \mathbf 0 \end{bmatrix}
    \begin{bmatrix} \mathbf U \\ \mathbf\Lambda \end{bmatrix} =
    \begin{bmatrix} \mathbf F \\ \mathbf G \end{bmatrix},

is solvable only if (Eq. 33) :math:`\mathbf V^T\mathbf K\mathbf V > 0` for every
:math:`\mathbf V \ne 0` in the kernel of :math:`\mathbf B` -- the ellipticity of Eq. (19)
on the constrained space, "a properly supported structure" -- and (Eqs. 34-35)
:math:`\mathbf B` has full row rank. A direct solver does not always notice when either
fails: it returns displacements of :math:`10^{13}` for a floating body, or multipliers
that change by orders of magnitude with the number of processes for a rank-deficient
:math:`\mathbf B`. The functions here detect both cases, with a cost linear in the
number of degrees of freedom:

* :func:`unsupported_motions` (Eq. 33). An elastic body is stiff against every motion
  except its rigid motions (:func:`rigid_body_modes`, one set per connected component
  of the mesh, :func:`connected_components`), so Eq. (33) fails iff some combination
  :math:`\mathbf R\alpha` of rigid modes vanishes at every Dirichlet dof, is not
  resisted by any active contact row, and costs no energy in the user's form (which
  may contain springs). With every row of :math:`\mathbf R_D` and of
  :math:`\mathbf B\mathbf R` scaled to unit size and the energy measured relative to
  :math:`k_{max} h` (see the function), the motions are the eigenvectors of the small
  Gram matrix :math:`\mathbf G = \mathbf G_D + \mathbf G_B + \mathbf G_K` (order
  :math:`3c` in 2D, :math:`6c` in 3D for :math:`c` bodies) whose eigenvalues lie below
  :data:`UNSUPPORTED_TOL` :math:`\cdot\max(1, \lambda_{max})`. :math:`10^{-10}` is far
  above round-off (that of the normalized sums, :math:`\epsilon` times their trace;
  that of the elastic energy of a rigid mode, measured :math:`10^{-14}` for
  :math:`6\cdot 10^5` nodes in 2D and :math:`5\cdot 10^{-15}` for :math:`6\cdot 10^4`
  in 3D, growing as :math:`h^{-1}`) and far below the support a single Dirichlet dof
  or contact row gives (of order one): a motion resisted :math:`10^{10}` times less
  than that makes Eq. (18) as ill-conditioned as a floating body, and is reported as
  one. A spring of stiffness :math:`k` per unit area of the boundary of a body of unit
  size counts as a support while :math:`k h / E \gtrsim 10^{-10}`.
* :func:`redundant_constraints` (Eqs. 34-35). With the active rows of
  :math:`\tilde{\mathbf B} = \mathbf B\mathbf D` (Dirichlet columns removed) scaled to
  unit length, the number of dependent rows is the number of eigenvalues of
  :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T` below :data:`REDUNDANT_TOL`
  :math:`= 10^{-12}` (singular values of :math:`\tilde{\mathbf B}` below
  :math:`10^{-6}`), counted exactly and for any size as the number of negative pivots
  of an :math:`\mathbf L\mathbf D\mathbf L^T` factorization of
  :math:`\tilde{\mathbf B}\tilde{\mathbf B}^T - \tau\mathbf I` (Sylvester's law of
  inertia, MUMPS). Rows that vanish after the Dirichlet elimination (norm below
  :math:`\sqrt\tau` times their norm before it) are redundant by definition and
  counted separately. The round-off of the unit-row Gram matrix is
  :math:`\epsilon` times the number of overlapping rows, four orders of magnitude below
  :math:`\tau`. :func:`redundant_multipliers` names the dependent rows of small
  problems. :func:`joint_redundant_constraints` and
  :func:`joint_redundant_multipliers` do the same for the rows of several pairs
  stacked: each pair may have full row rank while two pairs together constrain a
  motion twice (the passes of a two-pass method).
* :func:`check_cover`: a contactor part that faces another pair's surface but none of
  its own pair's targets is constrained by nothing (a contactor side split into two
  tags with a facet lying over both targets); raised at problem construction.

Every function is collective on the communicator of its arguments and returns the same
result on every process. The package needs petsc4py and is imported explicitly.
"""

from dolfinx_contact_s2s.checks.bodies import connected_components, near_nullspace, rigid_body_modes
from dolfinx_contact_s2s.checks.cover import (
    COVER_TOL,
    Unconstrained,
    check_cover,
    unconstrained_parts,
)
from dolfinx_contact_s2s.checks.rank import (
    REDUNDANT_TOL,
    Redundancy,
    joint_redundant_constraints,
    joint_redundant_multipliers,
    redundant_constraints,
    redundant_multipliers,
)
from dolfinx_contact_s2s.checks.ring import RING_TOLERANCE, translation_residuals
from dolfinx_contact_s2s.checks.support import (
    UNSUPPORTED_TOL,
    RigidMotion,
    SupportGram,
    UnsupportedMotion,
    support_gram,
    unsupported_motions,
)

__all__ = [
    "COVER_TOL",
    "REDUNDANT_TOL",
    "RING_TOLERANCE",
    "UNSUPPORTED_TOL",
    "Redundancy",
    "RigidMotion",
    "SupportGram",
    "Unconstrained",
    "UnsupportedMotion",
    "check_cover",
    "connected_components",
    "joint_redundant_constraints",
    "joint_redundant_multipliers",
    "near_nullspace",
    "redundant_constraints",
    "redundant_multipliers",
    "rigid_body_modes",
    "support_gram",
    "translation_residuals",
    "unconstrained_parts",
    "unsupported_motions",
]

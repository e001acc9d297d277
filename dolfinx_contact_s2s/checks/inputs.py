# Copyright (C) 2026 dolfinx_contact_s2s developers
# SPDX-License-Identifier: MIT
"""Checks of a contact problem's input, made before PETSc or the assembly sees it.

Each check raises the same exception with the same message on every process, so that a
user's mistake (a misspelt solver type, the arguments in :class:`dolfinx.fem.petsc.
LinearProblem`'s order, a zero Young's modulus) is named instead of surfacing as a PETSc
traceback that differs from rank to rank, an ``AttributeError`` deep in the package, or
a factorization that runs out of workspace.
"""

from __future__ import annotations

import typing
from collections.abc import Sequence

from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import numpy as np
import numpy.typing as npt
import ufl

from dolfinx_contact_s2s.options import PETScOptions
from dolfinx_contact_s2s.pair import ContactPair

__all__ = [
    "SOLVER_TYPE_KEYS",
    "check_inequality_multipliers",
    "check_problem_arguments",
    "check_solver_types",
    "check_stiffness",
]

#: The options whose value names a PETSc implementation, checked by
#: :func:`check_solver_types`, and the PETSc class that registers it.
SOLVER_TYPE_KEYS = {"ksp_type": "KSP", "pc_type": "PC", "snes_type": "SNES"}


def _is_registered(kind: str, value: str) -> bool:
    """Whether PETSc knows the ``kind`` (``"KSP"``, ``"PC"``, ``"SNES"``) type ``value``.

    Asked of a throw-away object on ``COMM_SELF``: PETSc's own registry, so types that
    plugins or external packages registered count too. Not collective.
    """
    obj = getattr(PETSc, kind)().create(PETSc.COMM_SELF)
    try:
        obj.setType(value)
    except PETSc.Error:
        return False
    finally:
        obj.destroy()
    return True


def _registered_names(kind: str) -> list[str]:
    """The type names petsc4py lists for ``kind`` (for the message; plugins may add more)."""
    names = vars(getattr(PETSc, kind).Type)
    return sorted({v for k, v in names.items() if k.isupper() and isinstance(v, str)})


def check_solver_types(
    options: PETScOptions,
    comm: MPI.Comm,
    keys: Sequence[str] = ("ksp_type", "pc_type", "snes_type"),
) -> None:
    """Raise :class:`ValueError` on every rank if a solver type under the prefix is unknown.

    Reads ``keys`` (of :data:`SOLVER_TYPE_KEYS`) under the prefix of ``options`` from the
    options database (``petsc_options``, the command line, the defaults) and asks PETSc
    whether it registers each value, before any solver reads them: PETSc itself would
    stop with error 86 (``PETSC_ERR_UNKNOWN_TYPE``) in ``setFromOptions``, with a
    traceback that differs from rank to rank. Collective. Before raising, the options
    are removed from the database (:meth:`PETScOptions.clear`): the problem is not built.

    Args:
        options: The problem's options.
        comm: The problem's communicator.
        keys: The options to check.

    Raises:
        ValueError: Naming the option, its value and the prefix; the same on every rank.
    """
    bad = []
    for key in keys:
        value = options.get(key)
        if value is not None and not _is_registered(SOLVER_TYPE_KEYS[key], value):
            bad.append((key, value))
    # The database may differ between ranks (a rank's own PETSC_OPTIONS): decide together.
    found = sorted({item for items in comm.allgather(bad) for item in items})
    if not found:
        return
    key, value = found[0]
    kind = SOLVER_TYPE_KEYS[key]
    options.clear()
    raise ValueError(
        f"unknown {kind} type {value!r} for the option {key} under the prefix "
        f"{options.prefix!r} (petsc_options={{{key!r}: {value!r}}} or -{options.prefix}{key}); "
        f"PETSc knows {', '.join(_registered_names(kind))}"
    )


def _kind(obj: typing.Any) -> str:
    """The class of ``obj`` in words, as a message names it."""
    if isinstance(obj, Sequence) and not isinstance(obj, str) and len(obj) > 0:
        inner = sorted({type(item).__name__ for item in obj})
        return f"{type(obj).__name__} of {', '.join(inner)}"
    return type(obj).__name__


def check_problem_arguments(
    a: typing.Any, L: typing.Any, pairs: typing.Any, bcs: typing.Any, problem: str
) -> None:
    """Raise :class:`TypeError` if the positional arguments are not what the problem takes.

    ``problem(a, L, pairs, bcs)`` differs from :class:`dolfinx.fem.petsc.LinearProblem`'s
    ``(a, L, bcs)``; a swap of ``pairs`` and ``bcs`` would otherwise end in an
    ``AttributeError`` deep in the set-up. Not collective: the types are the same on
    every rank of a correct (SPMD) program.

    Args:
        a: Bilinear forms (a UFL form or a sequence of them).
        L: Linear forms.
        pairs: Contact pairs.
        bcs: Dirichlet conditions.
        problem: Name of the problem class, for the message.

    Raises:
        TypeError: Naming the argument, its position, what was expected and what was given.
    """
    order = f"The order is {problem}(a, L, pairs, bcs)"
    for name, position, forms in (("a", 1, a), ("L", 2, L)):
        items = list(forms) if isinstance(forms, Sequence) else [forms]
        if not items or not all(isinstance(f, ufl.Form) for f in items):
            raise TypeError(
                f"{problem}: argument {position}, {name}, must be a UFL form or a list of UFL "
                f"forms (one per displacement space, not compiled by dolfinx.fem.form); "
                f"got {_kind(forms)}. {order}."
            )
    swapped = "did you swap pairs and bcs? " if _holds(pairs, dolfinx.fem.DirichletBC) else ""
    if isinstance(pairs, ContactPair):
        raise TypeError(
            f"{problem}: argument 3, pairs, must be a list of ContactPair objects (from "
            "contact_pair or contact_pairs); got one ContactPair: give [pair]. " + order + "."
        )
    if not isinstance(pairs, Sequence) or not all(isinstance(p, ContactPair) for p in pairs):
        raise TypeError(
            f"{problem}: argument 3, pairs, must be a list of ContactPair objects (from "
            f"contact_pair or contact_pairs); got {_kind(pairs)}: {swapped}{order}."
        )
    swapped = "did you swap pairs and bcs? " if _holds(bcs, ContactPair) else ""
    if isinstance(bcs, dolfinx.fem.DirichletBC):
        raise TypeError(
            f"{problem}: argument 4, bcs, must be a list of DirichletBC objects (from "
            f"dolfinx.fem.dirichletbc); got one DirichletBC: give [bc]. {order}."
        )
    if not isinstance(bcs, Sequence) or not all(
        isinstance(bc, dolfinx.fem.DirichletBC) for bc in bcs
    ):
        raise TypeError(
            f"{problem}: argument 4, bcs, must be a list of DirichletBC objects (from "
            f"dolfinx.fem.dirichletbc); got {_kind(bcs)}: {swapped}{order}."
        )


def _holds(obj: typing.Any, cls: type) -> bool:
    """Whether ``obj`` is a ``cls`` or a sequence with one."""
    if isinstance(obj, cls):
        return True
    return isinstance(obj, Sequence) and any(isinstance(item, cls) for item in obj)


def check_stiffness(
    spaces: Sequence[dolfinx.fem.FunctionSpace],
    stiffness: Sequence[PETSc.Mat],
    masks: Sequence[PETSc.Vec],
    labels: Sequence[npt.NDArray[np.int32]],
) -> None:
    r"""Raise :class:`ValueError` on every rank if a body's stiffness is zero or negative.

    The diagonal of an elastic :math:`\mathbf K` is positive at every free dof; a zero
    Young's modulus in the user's form leaves it zero (the factorization then fails,
    on some versions and rank counts as a MUMPS workspace error that no workspace
    cures), a negative one negative. Checked per body (connected component) on its free
    dofs (``masks`` 1, Dirichlet dofs 0), against the largest diagonal entry of all
    spaces: a body whose free diagonal entries are all at most :math:`10^{-14}` times
    that is reported as zero. Collective.

    Args:
        spaces: The displacement spaces.
        stiffness: The assembled :math:`\mathbf K` of every space (Dirichlet rows unit).
        masks: Per space, 1 at the free dofs and 0 at the Dirichlet dofs (owned layout).
        labels: Per space, the connected component of every local cell.

    Raises:
        ValueError: Naming the space and body; the same on every rank.
    """
    comm = spaces[0].mesh.comm
    per_space = []
    for V, K, mask, cell_labels in zip(spaces, stiffness, masks, labels, strict=True):
        d = K.getDiagonal()
        bs = V.dofmap.index_map_bs
        n = V.dofmap.index_map.size_local
        free = mask.array_r > 0
        # The body of every owned dof, from the cells around its node.
        body = np.full(n, -1, dtype=np.int64)
        cells = np.arange(len(cell_labels))
        dofs = V.dofmap.list[cells]
        owner = np.repeat(np.asarray(cell_labels)[cells], dofs.shape[1])
        flat = dofs.ravel()
        keep = flat < n
        body[flat[keep]] = owner[keep]
        body = np.repeat(body, bs)
        values = d.array_r.copy()
        d.destroy()
        count = int(max(np.max(np.asarray(cell_labels), initial=-1), -1)) + 1
        count = comm.allreduce(count, op=MPI.MAX)
        largest = np.full(count, -np.inf)
        smallest = np.full(count, np.inf)
        for b in range(count):
            mine = values[free & (body == b)]
            if mine.size:
                largest[b] = float(np.max(mine))
                smallest[b] = float(np.min(mine))
        per_space.append(
            (
                np.max(np.array(comm.allgather(largest)), axis=0),
                np.min(np.array(comm.allgather(smallest)), axis=0),
            )
        )
    scale = max(
        (float(np.max(np.abs(v[np.isfinite(v)]), initial=0.0)) for pair in per_space for v in pair),
        default=0.0,
    )
    for i, (largest, smallest) in enumerate(per_space):
        for b, (hi, lo) in enumerate(zip(largest, smallest, strict=True)):
            if not np.isfinite(hi):
                continue  # no free dof: held by Dirichlet conditions alone
            if lo < 0.0:
                raise ValueError(
                    f"the stiffness of body {b} of space {i} is not positive (a diagonal entry "
                    f"of K on its free dofs is {lo:.3g}): check E in your form a[{i}] (a "
                    "negative Young's modulus, or a form with the wrong sign)"
                )
            if hi <= 1e-14 * scale or hi <= 0.0:
                raise ValueError(
                    f"the stiffness of body {b} of space {i} is zero (largest diagonal entry "
                    f"of K on its free dofs: {hi:.3g}): check E in your form a[{i}] (a zero "
                    "Young's modulus, or a material coefficient that vanishes on this body)"
                )


def check_inequality_multipliers(pairs: Sequence[ContactPair]) -> None:
    r"""Refuse multiplier bases that unilateral contact cannot use (collective).

    The contact conditions of Eq. (1) act on each multiplier and its weighted gap
    :math:`\int \mu_k g`. A basis function with :math:`\int \mu_k = 0`, as the vertex
    functions of a P2 triangle (faces of quadratic tetrahedra), transmits no force under
    a uniform pressure and its sign says nothing about contact: the active set is then
    meaningless and the answer wrong without a word.

    Raises:
        ValueError: On every rank, naming the pair and the remedies.
    """
    for j, pair in enumerate(pairs):
        integrals, squares = pair.multiplier_integrals(), pair.multiplier_supports()
        # Relative to the square's integral: 2 for a P1 triangle's function, 0 for a P2 vertex.
        count = int(np.count_nonzero(integrals <= 1e-8 * squares))
        count = pair.contactor.comm.allreduce(count, op=MPI.SUM)
        if count:
            raise ValueError(
                f"pair {j}: {count} multiplier basis functions integrate to zero (the vertex "
                "functions of the P2 multiplier on triangular faces): unilateral contact "
                "cannot use them. Use a P1 multiplier, contact_pair(..., multiplier="
                "('Lagrange', 1)), hexahedra (Q2) for the contactor, or tied contact"
            )

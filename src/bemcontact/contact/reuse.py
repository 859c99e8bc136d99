"""Re-solves that reuse the condensed bodies.

The condensation (:mod:`bemcontact.bem.condensation`) depends on a body's
mesh, material, the *kinds* of its boundary conditions (which dofs have a
prescribed displacement, which are force controlled), its quadrature, the
frame's traction modes and the linear solver; the *values* of the boundary
conditions enter only through the response x0 to each load state, which is
linear in them.  A :class:`Condensation` condenses each body once on a basis
of load fields (per region that may carry a condition: a unit value of each
component and the outward normal, the fields of uniform displacements,
tractions and pressures; and the values of the states it was built for,
which covers conditions given as functions of position) and gives the
condensed bodies of any later states with the same kinds by combining those
responses (:meth:`Condensation.bodies_for`).  The friction coefficient, the
penalty, the load values and history and the Newton options then change
without assembling or factoring anything
(:meth:`bemcontact.contact.ContactProblem.solve` with ``condensed=``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import numpy as np
import scipy.linalg

from ..errors import ConfigError
from ..linalg.options import LinearSolverOptions
from ..bem.condensation import CondensedBody
from .frame import ContactFrame
from .frames import FrameSet
from .pair import ContactPair

#: Largest relative residual of a state's values in the span of the
#: condensed load fields; above it the state is refused (re-condense).
SPAN_TOLERANCE = 1e-12
#: The contact pair's fields that shape the frame and the condensation (all
#: but the friction coefficient and the penalty).
FRAME_FIELDS = tuple(f.name for f in dataclasses.fields(ContactPair)
                     if f.name not in ("friction_coefficient", "penalty"))


def load_basis(body, states: Sequence, contact_surface) -> np.ndarray:
    """(3N, r) independent load fields whose span holds the boundary values
    of ``states`` and of any uniform displacement, traction or pressure on a
    region other than the ``contact_surface`` (a region name, or several):
    per region the unit x, y and z
    fields and the outward normal, then each state's own values; columns
    kept in that order when independent (pivoted QR)."""
    d = body.trace
    N = d.n_points
    cols = []
    surfaces = {contact_surface} if isinstance(contact_surface, str) else set(contact_surface)
    for r, name in enumerate(body.region_names):
        if name in surfaces:
            continue
        idx = np.flatnonzero(d.region == r)
        if idx.size == 0:
            continue
        for c in range(3):
            f = np.zeros((N, 3))
            f[idx, c] = 1.0
            cols.append(f.ravel())
        f = np.zeros((N, 3))
        f[idx] = d.normals[idx]
        cols.append(f.ravel())
    cols += [body.load_values(st) for st in states]
    raw = np.column_stack(cols) if cols else np.zeros((3 * N, 0))
    if raw.shape[1] == 0:
        return raw
    scale = np.linalg.norm(raw, axis=0)
    keep = scale > 0
    raw = raw[:, keep]
    _, R, piv = scipy.linalg.qr(raw / scale[keep], mode="economic", pivoting=True)
    diag = np.abs(np.diag(R))
    rank = int(np.count_nonzero(diag > 1e-10 * diag[0]))
    return raw[:, np.sort(piv[:rank])]


def _kinds(body, state) -> tuple[np.ndarray, list]:
    return body.condition_kinds(state) > 0, [c.dofs for c in body.controls(state)]


def _same_kinds(a, b) -> bool:
    return bool(np.array_equal(a[0], b[0]) and len(a[1]) == len(b[1])
                and all(np.array_equal(x, y) for x, y in zip(a[1], b[1])))


@dataclasses.dataclass
class Condensation:
    """The bodies condensed once on the frames' traction modes and on a
    basis of load fields (:func:`load_basis`), for re-solves with other
    friction, penalty, load values or histories and Newton options
    (:meth:`bemcontact.contact.ContactProblem.solve` with ``condensed=``).

    Attributes: ``bodies`` the bodies it was built from, ``pairs`` their
    contact pairs, ``frames`` the contact frames
    (:class:`~bemcontact.contact.frames.FrameSet`), ``linear`` the linear
    solver options of the condensation, ``condensed`` per body the
    :class:`~bemcontact.bem.condensation.CondensedBody` whose load
    states are the basis fields, ``kinds`` per body (known displacement per
    dof, the dofs of each force control)."""

    bodies: tuple
    pairs: tuple[ContactPair, ...]
    frames: FrameSet
    linear: LinearSolverOptions
    condensed: tuple[CondensedBody, ...]
    kinds: tuple

    @property
    def frame(self) -> ContactFrame:
        """The first (in a two-body problem the only) pair's frame."""
        return self.frames.frames[0]

    def check(self, bodies, pairs, linear: LinearSolverOptions) -> None:
        """Refuse (ConfigError, one line) bodies, pairs or linear options
        other than those condensed: a different mesh, material, quadrature
        or frame, or other linear solver options."""
        if linear != self.linear:
            raise ConfigError(
                "the condensed bodies were solved with other linear solver options "
                "([solver.linear]); condense again to change them"
            )
        pairs = (pairs,) if isinstance(pairs, ContactPair) else tuple(pairs)
        if len(pairs) != len(self.pairs) or len(bodies) != len(self.bodies):
            raise ConfigError(
                f"the condensed problem has {len(self.bodies)} bodies and {len(self.pairs)} "
                f"pair(s), this one {len(bodies)} and {len(pairs)}; condense again")
        for pair, old in zip(pairs, self.pairs):
            for f in FRAME_FIELDS:
                if getattr(pair, f) != getattr(old, f):
                    raise ConfigError(
                        f"contact.{f} is {getattr(pair, f)!r}, the condensed bodies have "
                        f"{getattr(old, f)!r}; condense again to change the frame"
                    )
        for a, (b, o) in enumerate(zip(bodies, self.bodies)):
            if b is o:
                continue
            same = b.same_model(o)
            if not same:
                raise ConfigError(
                    f"body {b.name!r}: its mesh, material or quadrature differ from the "
                    f"condensed body {o.name!r}; condense again"
                )

    def bodies_for(self, bodies, states) -> tuple[CondensedBody, CondensedBody]:
        """The condensed bodies for the load ``states`` (per state, per body
        the checked condition mapping, as :meth:`ContactProblem.states`
        gives): the responses to the basis fields combined by the
        coefficients of each state's values.  Refuses (ConfigError) states
        whose kinds of condition differ from the condensed ones, or whose
        values are not in the span of the basis."""
        out = []
        for a, (body, cb) in enumerate(zip(bodies, self.condensed)):
            body_states = [st[a] for st in states]
            kinds = _kinds(body, body_states[0])
            if not _same_kinds(kinds, self.kinds[a]):
                raise ConfigError(
                    f"{body.name}: the kinds of its boundary conditions (displacement, "
                    "traction or force per component) differ from those of the condensed "
                    "body; a re-solve may change values only"
                )
            values = np.column_stack([body.load_values(st) for st in body_states])
            coef, *_ = np.linalg.lstsq(cb.values, values, rcond=None)
            resid = np.linalg.norm(cb.values @ coef - values, axis=0)
            size = np.maximum(np.linalg.norm(values, axis=0), np.finfo(float).tiny)
            if np.any(resid > SPAN_TOLERANCE * size):
                raise ConfigError(
                    f"{body.name}: a load (a condition given as a function of position) is "
                    "not among the condensed load fields; condense again for it"
                )
            controls = body.controls(body_states[0])
            forces = np.array([[c.force for c in body.controls(st)] for st in body_states])
            forces = forces.reshape(len(body_states), len(controls)).T
            out.append(cb.recombined(body, coef, values, controls, forces))
        return tuple(out)


#: condense's signature: (body, nodes, threads, states, progress, linear, modes,
#: load_fields=...)
CondenseBody = Callable[..., CondensedBody]


def condense_any(body, *args, **kwargs):
    """The body's own condensation (``body.condense(...)``, the body seam)."""
    return body.condense(*args, **kwargs)


def condense_problem(
    bodies, pairs, links, frames: FrameSet, states, threads: int | None,
    linear: LinearSolverOptions, progress=None, condense_body: CondenseBody | None = None,
) -> Condensation:
    """Condense every body on the frames' traction modes and on its
    :func:`load_basis` of ``states`` (checked states, as
    :meth:`ContactProblem.states` gives) by ``condense_body`` (default
    :func:`~bemcontact.contact.condense`; a cache may stand in for it).
    ``links[p]``: the body indices of ``pairs[p]``."""
    run = condense_body or condense_any
    modes = frames.traction_modes()
    cbs, kinds = [], []
    for a, body in enumerate(bodies):
        surfaces = [(p.surface1, p.surface2)[side]
                    for p, link in zip(pairs, links) for side, b in enumerate(link) if b == a]
        body_states = [st[a] for st in states]
        basis = load_basis(body, body_states, surfaces)
        cbs.append(run(body, frames.nodes(a), threads, body_states[:1], progress, linear,
                       modes[a], load_fields=basis))
        kinds.append(_kinds(body, body_states[0]))
    return Condensation(tuple(bodies), tuple(pairs), frames, linear, tuple(cbs), tuple(kinds))


__all__ = ["Condensation", "condense_problem", "load_basis"]

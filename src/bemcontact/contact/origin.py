"""Bodies far from the origin (a rigid offset of 1e12 would change the
normal force of two cubes by 0.5 % and every frame state).  Far from the origin a
double holds a coordinate only to its ulp (1.2e-4 at 1e12), so quadrature
points, kernels and the frame's clipping lose the digits that the bodies'
own size needs.  The solve therefore runs on the bodies translated by an
origin of their own, a node's coordinates (the lowest corner of both
bodies' nodes), chosen only when the bodies lie farther from the global
origin than a few times their size; the subtraction of a node's coordinate
is exact where the nodes lie within a factor two of it, so a rigid offset
of the whole problem changes nothing, and the results are translated back.
:class:`~bemcontact.contact.ContactProblem` does this itself (its solve and
its condensation), so every caller, the problem file and the sweep
included, gets results at the bodies' own position."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..bem.conditions import Displacement, Traction

#: The bodies are solved relative to their own origin when their
#: coordinates exceed this multiple of their extent.
FAR = 8.0


def own_origin(bodies) -> np.ndarray | None:
    """The origin the bodies are solved relative to (None: the global one)."""
    nodes = np.vstack([b.trace.mesh.nodes for b in bodies])
    lo, hi = nodes.min(axis=0), nodes.max(axis=0)
    extent = float(np.max(hi - lo))
    if float(np.max(np.abs(nodes))) <= FAR * extent:
        return None
    return lo.copy()


def translated_bodies(bodies, origin: np.ndarray):
    """Copies of ``bodies`` whose meshes are translated by ``-origin`` (the
    mesh checks hold as they are; conditions given as functions of position
    are evaluated at the user's points)."""
    out = []
    for b in bodies:
        c = b.translated(origin)
        c.boundary_conditions = translated_states([[b.boundary_conditions]], origin)[0][0]
        out.append(c)
    return tuple(out)


def _shifted(condition, origin: np.ndarray):
    """``condition`` for the translated body: a value given as a function of
    position is evaluated at the user's points (translated back)."""
    f = getattr(condition, "value", None)
    if not callable(f):
        return condition
    if isinstance(condition, Displacement):
        return Displacement(lambda X: f(X + origin))
    if isinstance(condition, Traction):
        return Traction(lambda X, n: f(X + origin, n))
    return condition  # pragma: no cover - only these two take callables


def translated_states(states, origin: np.ndarray):
    """Checked states (per state, per body: region -> conditions, as
    :meth:`ContactProblem.states` gives) for the translated bodies: the
    same objects except conditions given as functions of position."""
    return [[{r: tuple(_shifted(c, origin) for c in items) for r, items in body.items()}
             for body in st] for st in states]


def translated_result(result, origin: np.ndarray, meshes):
    """``result`` (a ContactResult of the translated bodies, with its history)
    at the original position: the bodies' ``meshes``, points + ``origin``."""
    done: dict[int, object] = {}

    def one(r):
        if id(r) in done:
            return done[id(r)]
        bodies = tuple(
            dataclasses.replace(
                b, points=b.points + origin,
                discretization=dataclasses.replace(b.discretization, mesh=mesh,
                                                   points=b.discretization.points + origin))
            for b, mesh in zip(r.bodies, meshes)
        )
        pairs = [
            dataclasses.replace(
                p, interfaces=tuple(dataclasses.replace(i, points=i.points + origin)
                                    for i in p.interfaces),
                frame=dataclasses.replace(p.frame, points=p.frame.points + origin))
            for p in r.pairs
        ]
        new = dataclasses.replace(
            r, bodies=bodies, pairs=pairs, interfaces=pairs[0].interfaces,
            frame=pairs[0].frame, history=[],
        )
        done[id(r)] = new
        new.history = [one(h) for h in r.history]
        return new

    return one(result)


__all__ = ["FAR", "own_origin", "translated_bodies", "translated_result", "translated_states"]

"""Bodies far from the origin (issue 24: two cubes offset by 1e12 changed
the normal force by 0.5 % and every frame state).  Far from the origin a
double holds a coordinate only to its ulp (1.2e-4 at 1e12), so quadrature
points, kernels and the frame's clipping lose the digits that the bodies'
own size needs.  The solve therefore runs on the bodies translated by an
origin of their own, a node's coordinates (the lowest corner of both
bodies' nodes), chosen only when the bodies lie farther from the global
origin than a few times their size; the subtraction of a node's coordinate
is exact where the nodes lie within a factor two of it, so a rigid offset
of the whole problem changes nothing, and the results are translated back."""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from ..mesh import SurfaceMesh

#: The bodies are solved relative to their own origin when their
#: coordinates exceed this multiple of their extent.
FAR = 8.0


def own_origin(bodies) -> np.ndarray | None:
    """The origin the bodies are solved relative to (None: the global one)."""
    nodes = np.vstack([b.mesh.nodes for b in bodies])
    lo, hi = nodes.min(axis=0), nodes.max(axis=0)
    extent = float(np.max(hi - lo))
    if float(np.max(np.abs(nodes))) <= FAR * extent:
        return None
    return lo.copy()


def translated_bodies(bodies, origin: np.ndarray):
    """Copies of ``bodies`` whose meshes are translated by ``-origin`` (their
    conditions are translation invariant; the mesh checks hold as they are)."""
    out = []
    for b in bodies:
        m = b.mesh
        c = copy.copy(b)
        c.mesh = SurfaceMesh(m.nodes - origin, m.elements, m.element_type, m.regions,
                             source=m.source)
        c._disc = None
        out.append(c)
    return tuple(out)


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
        new = dataclasses.replace(
            r, bodies=bodies,
            interfaces=tuple(dataclasses.replace(i, points=i.points + origin)
                             for i in r.interfaces),
            frame=dataclasses.replace(r.frame, points=r.frame.points + origin),
            history=[],
        )
        done[id(r)] = new
        new.history = [one(h) for h in r.history]
        return new

    return one(result)


__all__ = ["FAR", "own_origin", "translated_bodies", "translated_result"]

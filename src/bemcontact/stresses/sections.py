"""The stresses written without being asked for: under the peak pressure.

For each contact pair and each of its bodies, when the contact is small
compared with the body (the body's smallest bounding-box extent at least
:data:`SMALL` contact radii), three probes under the point of peak pressure c:

* ``profile``: the depth profile along the body's inward normal, from
  :data:`DEPTHS` ``[0]`` to ``[1]`` contact radii below its surface
  (:data:`PROFILE_POINTS` points);
* ``section1`` and ``section2``: the two planes through the normal, the first
  along the tangential force (or, when there is none, the global axis least
  aligned with the normal, projected), −2a ≤ u ≤ 2a, from the same depths (:data:`SECTION_POINTS`; on the
  multiscale path along the grid's axes, the one nearer the tangential force
  first, at every cell centre).

The points follow the body's surface: a point at depth d below the surface
point above (u, v) is c + u e_u + v e_v + (h(u, v) + d) n, with n the body's
inward normal and h the height of its contact surface (interpolated from its
contact nodes on the full path, its fitted quartic on the multiscale path),
so that a curved body (a sphere) is sampled at the same depths as a flat one.
The contact radius is √(A/π), A the contact area.
"""

from __future__ import annotations

import numpy as np
import scipy.interpolate

from ..contact.law import OPEN
from ..contact.results import ContactResult
from ..multiscale.assembly import GridAssemblyResult
from ..multiscale.pair import GridResult
from ..multiscale.surface import quartic_terms
from .fields import Lattice
from .probes import Line, Plane, StressRequest

#: A body takes the default probes when its smallest extent is at least this
#: many contact radii.
SMALL = 8.0
#: Depths of the default probes, in contact radii below the surface.
DEPTHS = (0.02, 3.0)
#: Half-width of the default sections, in contact radii.
HALF_WIDTH = 2.0
PROFILE_POINTS = 100
SECTION_POINTS = (41, 31)


def _contacts(result) -> list[dict]:
    """Per pair: its bodies, the peak-pressure point, normal (body 1 into
    body 2), tangent, contact radius and each body's surface height h(u, v)
    relative to the plane through the peak normal to n (along its own
    inward normal)."""
    if isinstance(result, GridAssemblyResult):
        return [c for r in result.pairs for c in _contacts(r)]
    if isinstance(result, GridResult):
        st = result.history[-1]
        k = int(np.argmax(st.p[:, 2]))
        A = result.axes
        closed = float(np.sum(st.state != OPEN)) * result.grid.cell_area
        f = st.force[:2]
        # the sections along the grid's axes (their points then lie below
        # cell centres: FFT layers), the first the nearer the tangential force
        t = A[1] if abs(f[1]) > abs(f[0]) else A[0]
        c = result.points[k]
        cl = (c - result.origin) @ A.T

        def height(b):
            coef = result.surfaces[b]
            sign = 1.0 if b == 1 else -1.0

            def h(uv, e_u, e_v):
                L = (c - result.origin + uv[:, :1] * e_u + uv[:, 1:] * e_v) @ A.T
                return sign * (quartic_terms(L[:, 0], L[:, 1]) @ coef - cl[2])
            return h
        return [{"names": result.names, "bodies": [corr.body for corr in result.corrections],
                 "centre": c, "normal": A[2], "tangent": t, "radius": np.sqrt(closed / np.pi),
                 "heights": [height(0), height(1)], "cells": (result.grid, k, A)}]
    if not isinstance(result, ContactResult):
        return []
    models = result.models
    out = []
    for pair in (result.pairs or [result]):
        fr = pair.frame
        if not fr.pressure.size or fr.pressure.max() <= 0.0:
            continue
        k = int(np.argmax(fr.pressure))
        n = fr.normals[k]
        c = fr.points[k]
        area = float(fr.weights[fr.state != 0].sum())
        f = np.asarray(pair.contact_force, dtype=float)
        ft = f - (f @ n) * n
        if np.linalg.norm(ft) > 1e-9 * abs(f @ n):
            t = ft / np.linalg.norm(ft)
        else:
            t = np.eye(3)[int(np.argmin(np.abs(n)))]
            t = t - (t @ n) * n
            t /= np.linalg.norm(t)

        def height(iface, sign):
            P = iface.points - c
            e1 = t
            e2 = np.cross(n, t)
            uv = np.column_stack([P @ e1, P @ e2])
            z = sign * (P @ n)
            lin = scipy.interpolate.LinearNDInterpolator(uv, z)
            near = scipy.interpolate.NearestNDInterpolator(uv, z)

            def h(q, e_u, e_v):
                X = q[:, :1] * e_u + q[:, 1:] * e_v
                w = np.column_stack([X @ e1, X @ e2])
                v = lin(w)
                return np.where(np.isfinite(v), v, near(w))
            return h
        names = tuple(pair.names) if hasattr(pair, "names") else tuple(result.names)
        out.append({"names": names, "bodies": [models.get(m) for m in names], "centre": c,
                    "normal": n, "tangent": t, "radius": np.sqrt(area / np.pi),
                    "heights": [height(pair.interfaces[0], -1.0),
                                height(pair.interfaces[1], 1.0)]})
    return out


def _cells(grid, k: int, axes: np.ndarray, e_u: np.ndarray):
    """Along ``e_u`` (± one of the grid's axes) from cell ``k``: the cell
    size and the range of whole cells, in steps along ``e_u``, to the grid's
    edges."""
    i, j = divmod(k, grid.ny)
    d = axes[:2] @ e_u
    a = int(np.argmax(np.abs(d)))
    step, first, last = ((grid.dx, -i, grid.nx - 1 - i), (grid.dy, -j, grid.ny - 1 - j))[a]
    return (step, first, last) if d[a] > 0 else (step, -last, -first)


def _extent(body) -> float:
    if body is None:
        return 0.0
    P = body.discretization.points
    return float((P.max(axis=0) - P.min(axis=0)).min())


def default_requests(result) -> tuple[list[tuple[StressRequest, Lattice]], list[str]]:
    """The default probes of a solved result (module docstring) as
    (request, surface-following lattice) pairs, and one line per body
    without them saying why."""
    out, skipped = [], []
    seen = set()
    for info in _contacts(result):
        a = float(info["radius"])
        for b, (name, body) in enumerate(zip(info["names"], info["bodies"])):
            if name in seen or a <= 0.0:
                continue
            seen.add(name)
            if _extent(body) < SMALL * a:
                skipped.append(f"{name}: the contact (radius {a:.3g}) is not small against the "
                               f"body (smallest extent {_extent(body):.3g}); ask for stresses "
                               "with [[output.stresses]]")
                continue
            n_in = info["normal"] if b == 1 else -info["normal"]
            t = info["tangent"]
            h = info["heights"][b]
            c = info["centre"]
            d0, d1 = DEPTHS[0] * a, DEPTHS[1] * a
            depth = np.linspace(d0, d1, PROFILE_POINTS)
            h0 = float(h(np.zeros((1, 2)), t, np.cross(n_in, t))[0])
            top = c + h0 * n_in
            pts = top + depth[:, None] * n_in
            out.append((StressRequest(name, Line(tuple(pts[0]), tuple(pts[-1]), PROFILE_POINTS),
                                      "profile"),
                        Lattice(pts, (PROFILE_POINTS,), (depth,), ("depth",))))
            for k, e_u in enumerate((t, np.cross(n_in, t)), start=1):
                if "cells" in info:  # the grid: below cell centres, within the grid
                    step, lo, hi = _cells(*info["cells"], e_u)
                    m = int(HALF_WIDTH * a / step)
                    u = step * np.arange(max(-m, lo), min(m, hi) + 1)
                    if u.size < 2:  # the grid too narrow along this direction
                        continue
                else:
                    u = np.linspace(-HALF_WIDTH * a, HALF_WIDTH * a, SECTION_POINTS[0])
                d = np.linspace(d0, d1, SECTION_POINTS[1])
                U, D = np.meshgrid(u, d, indexing="ij")
                uv = np.column_stack([U.ravel(), np.zeros(U.size)])
                hh = h(uv, e_u, np.cross(n_in, e_u))
                P = c + U.reshape(-1, 1) * e_u + (hh + D.ravel())[:, None] * n_in
                shape = (u.size, d.size)
                mid = c + 0.5 * (u[0] + u[-1]) * e_u + (h0 + 0.5 * (d0 + d1)) * n_in
                plane = Plane(tuple(mid), tuple(np.cross(e_u, n_in)),
                              (float(u[-1] - u[0]), d1 - d0), shape, tuple(e_u))
                out.append((StressRequest(name, plane, f"section{k}"),
                            Lattice(P, shape, (u, d), ("u", "depth"))))
    return out, skipped


__all__ = ["DEPTHS", "HALF_WIDTH", "PROFILE_POINTS", "SECTION_POINTS", "SMALL",
           "default_requests"]

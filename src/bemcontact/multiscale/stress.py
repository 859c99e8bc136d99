"""Stresses inside the bodies of a contact solved on the grid.

Each body is the half-space the grid solve takes it for: the stress at a
point is Love's closed-form field of the grid's piecewise-constant tractions
(:class:`~bemcontact.halfspace.HalfSpaceStress`), at the point's position in
the contact frame (ξ, η) and its depth below the body's own contact surface
(the quartic fitted to its nodes, ``GridResult.surfaces``), with the body's
Poisson ratio.  Body 2 (ζ > 0 side) carries the tractions p; body 1 carries
−p: it is the half-space mirrored in ζ, so its stress is the module's field of
(−p_ξ, −p_η, p_ζ) with the σ_ηζ and σ_ξζ components negated.  The frame
components are then turned to global ones, σ = Aᵀ σ_frame A (A: the frame's
axes as rows).

The body's correction (its finite size) is not in this field: near the
contact, where contact stresses matter, it is smooth and small (the
difference it makes to the pressure is measured in docs/validation.md); far
from the contact, in the body's bulk, the half-space field is not the body's.
Points are refused when they lie above the body's contact surface."""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError
from ..halfspace import stress_tensors
from .surface import quartic_terms


def frame_depths(result, body: str, points, clip: bool = False) -> tuple[int, np.ndarray]:
    """(body index, (n, 3) = (ξ, η, depth below the body's contact surface))
    of global ``points`` (n, 3); depth > 0 inside the body.  A point above
    the surface is refused, or with ``clip`` taken on it (the field of
    another contact of the body, read where this one's surface fit does not
    reach)."""
    b = body_index(result, body)
    try:
        X = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise ConfigError("points must be an (n, 3) array of numbers") from None
    if X.ndim != 2 or X.shape[1] != 3 or not len(X) or not np.all(np.isfinite(X)):
        raise ConfigError(f"points must be a finite (n, 3) array with n >= 1, got shape "
                          f"{X.shape}")
    L = (X - result.origin) @ result.axes.T
    zeta = quartic_terms(L[:, 0], L[:, 1]) @ result.surfaces[b]
    depth = L[:, 2] - zeta if b == 1 else zeta - L[:, 2]
    if clip:
        g = result.grid
        return b, np.column_stack([L[:, :2], np.maximum(depth, 1e-9 * min(g.dx, g.dy))])
    bad = np.flatnonzero(~(depth > 0.0))
    if bad.size:
        i = int(bad[0])
        raise ConfigError(f"point {i} at ({', '.join(f'{c:.6g}' for c in X[i])}) is not inside "
                          f"body {body!r}: {-depth[i]:.3g} above its contact surface",
                          location={"point": i, "body": body})
    return b, np.column_stack([L[:, :2], depth])


def grid_stresses(result, body: str, points, step: int = -1, clip: bool = False) -> np.ndarray:
    """The stress tensor (n, 6) = (σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz), global
    components, tension positive, at global ``points`` (n, 3) inside ``body``
    at the end of load step ``step`` (an index into ``result.history``);
    ``clip``: as :func:`frame_depths`."""
    check_step(result, step)
    b, local = frame_depths(result, body, points, clip)
    field, p = _field(result, b, step)
    return _global(result, b, _sum(field, result.grid, local, p))


#: Points at one depth, above cell centres, from which a whole FFT layer is
#: cheaper than the direct sum (a layer costs about as much as 7 points on the
#: benchmark's 60 x 60 grid; more on larger grids).
LAYER_POINTS = 16

#: Depth layers computed in one call (their traction spectra shared).
LAYERS_AT_ONCE = 8


def _sum(field, g, local, p) -> np.ndarray:
    """The field at ``local`` (n, 3) = (ξ, η, depth): points that lie below
    cell centres, many at one depth, from that depth's FFT layer; the others
    by the direct sum (the same sums, to round-off)."""
    out = np.empty((len(local), 6))
    h = min(g.dx, g.dy)
    i = (local[:, 0] - g.origin[0]) / g.dx - 0.5
    j = (local[:, 1] - g.origin[1]) / g.dy - 0.5
    ii, jj = np.rint(i).astype(np.int64), np.rint(j).astype(np.int64)
    centre = ((np.abs(i - ii) < 1e-6) & (np.abs(j - jj) < 1e-6) & (ii >= 0) & (ii < g.nx)
              & (jj >= 0) & (jj < g.ny))
    key = np.rint(local[:, 2] / h * 1e9).astype(np.int64)
    done = np.zeros(len(local), dtype=bool)
    keys, counts = np.unique(key[centre], return_counts=True)
    groups = [np.flatnonzero(centre & (key == k)) for k in keys[counts >= LAYER_POINTS]]
    for start in range(0, len(groups), LAYERS_AT_ONCE):
        part = groups[start:start + LAYERS_AT_ONCE]
        layers = field.layers(p, [float(local[sel, 2].mean()) for sel in part])
        for layer, sel in zip(layers, part):
            out[sel] = layer[ii[sel], jj[sel]]
            done[sel] = True
    if not done.all():
        out[~done] = field.at(local[~done], p)
    return out


def grid_surface_stresses(result, body: str, step: int = -1) -> np.ndarray:
    """The stress tensor (n, 6), global components, on ``body``'s contact
    surface at each grid cell (cell order; the point of the body's surface
    above or below the cell's centre), at the end of load step ``step``: the
    half-space field's limit at the surface (evaluated at a depth of 1e-9
    cells, by FFT), whose σ_iζ are the cell's tractions."""
    check_step(result, step)
    b = body_index(result, body)
    field, p = _field(result, b, step)
    g = result.grid
    return _global(result, b, field.layer(p, 1e-9 * min(g.dx, g.dy)).reshape(-1, 6))


def grid_surface_points(result, body: str) -> np.ndarray:
    """(n, 3) global points of ``body``'s contact surface at the grid cells
    (where :func:`grid_surface_stresses` gives the stresses)."""
    b = body_index(result, body)
    c = result.grid.centres
    zeta = quartic_terms(c[:, 0], c[:, 1]) @ result.surfaces[b]
    return result.origin + np.column_stack([c[:, :2], zeta]) @ result.axes


def body_index(result, body: str) -> int:
    if body not in result.names:
        raise ConfigError(f"unknown body {body!r}; the bodies are {list(result.names)}",
                          location={"body": body})
    return result.names.index(body)


def check_step(result, step) -> None:
    if (isinstance(step, bool) or not isinstance(step, (int, np.integer))
            or not -len(result.history) <= step < len(result.history)):
        raise ConfigError(f"step must index the {len(result.history)} load steps, got {step!r}",
                          location={"field": "step"})


def _field(result, b: int, step: int):
    """The body's half-space stress field and the tractions it carries (body
    1: mirrored, module docstring)."""
    p = result.history[step].p
    return result.half_space(b), p * np.array([-1.0, -1.0, 1.0]) if b == 0 else p


def _global(result, b: int, s: np.ndarray) -> np.ndarray:
    """Frame components of body b (body 1 mirrored) to global ones."""
    if b == 0:
        s[:, 4:] *= -1.0
    A = result.axes
    T = np.einsum("ai,nab,bj->nij", A, stress_tensors(s), A)
    return np.stack([T[:, 0, 0], T[:, 1, 1], T[:, 2, 2], T[:, 0, 1], T[:, 1, 2], T[:, 0, 2]],
                    axis=1)


__all__ = ["frame_depths", "grid_stresses", "grid_surface_points", "grid_surface_stresses"]

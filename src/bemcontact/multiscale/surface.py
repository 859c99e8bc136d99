"""A contact surface near the contact point, as the frame sees it: a quartic
ζ(ξ, η) in the frame's coordinates fitted to the surface's mesh nodes (which
lie on the true surface even when the facets between them do not), and the
size of its elements there."""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError


#: Nodes of each contact surface the quartic fit uses (the nearest to the
#: contact point, at least): 15 coefficients, so the fit is overdetermined.
FIT_NODES = 60


def region_nodes(body, region: str) -> np.ndarray:
    """The functional nodes of ``body`` on its ``region``."""
    d = body.discretization
    return np.flatnonzero(d.region == body.mesh.region_names.index(region))


def surface_fit(body, region: str, origin, axes, radius: float | None = None):
    """The quartic ζ(ξ, η) fitted to the nodes of ``region`` nearest to
    ``origin`` in the frame (ξ, η, ζ); returns (coefficients, the fit's
    radius, its rms residual)."""
    P = (body.discretization.points[region_nodes(body, region)] - origin) @ axes.T
    r = np.hypot(P[:, 0], P[:, 1])
    order = np.argsort(r)
    take = order[: max(FIT_NODES, int(np.sum(r <= radius)) if radius else 0)]
    if take.size < 20:
        raise ConfigError(f"{body.name}: the contact surface {region!r} has {take.size} nodes "
                          "near the contact point: too few to fit its shape (at least 20)")
    V = quartic_terms(P[take, 0], P[take, 1])
    coef, *_ = np.linalg.lstsq(V, P[take, 2], rcond=None)
    resid = float(np.sqrt(np.mean((V @ coef - P[take, 2]) ** 2)))
    return coef, float(r[take].max()), resid


def contact_spacing(body, region: str, origin) -> float:
    """The distance from ``origin`` to the 8th nearest node of ``region``."""
    P = body.discretization.points[region_nodes(body, region)]
    d = np.sort(np.linalg.norm(P - origin, axis=1))
    return float(d[min(7, d.size - 1)])


def element_size(body, region: str, origin, axes, radius: float) -> float:
    """The mean diameter of ``body``'s elements on ``region`` whose centroid
    lies within ``radius`` of ``origin`` in the frame's plane (the nearest
    element if none does): the resolution its mesh gives a contact there."""
    mesh = body.mesh
    elements = mesh.region(region)
    X = mesh.nodes[mesh.elements[elements]]  # (m, k, 3)
    c = (X.mean(axis=1) - origin) @ axes[:2].T
    r = np.hypot(c[:, 0], c[:, 1])
    near = r <= radius
    if not near.any():
        near = r == r.min()
    Y = X[near]
    return float(np.mean(np.linalg.norm(Y[:, :, None] - Y[:, None], axis=3).max(axis=(1, 2))))


def quartic_terms(x, y) -> np.ndarray:
    """The 15 monomials x^i y^j, i + j <= 4, of a quartic: shape (..., 15)."""
    return np.stack([x**i * y**(d - i) for d in range(5) for i in range(d, -1, -1)], axis=-1)


__all__ = ["FIT_NODES", "contact_spacing", "element_size", "quartic_terms", "region_nodes",
           "surface_fit"]

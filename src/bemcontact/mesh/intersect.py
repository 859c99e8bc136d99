"""Self-intersection of a surface: pairs of its (flat) triangles that cross.

Candidate pairs come from a spatial index (k-d trees of the triangles'
box centres, one per size class, sizes within a factor of two, so a
triangle meets O(1) candidates of each class: O(n log n) for n triangles),
are kept when their bounding boxes overlap and their elements share no node
(elements next to each other touch by construction), and are tested exactly by
separating axes (the two normals, the six in-plane edge normals, the nine
edge-edge cross products).  Triangles that share no node and touch (within a
relative 1e-9 of the surface's size) count as crossing: a closed surface
whose edges all pass the closure check touches itself only where it is
folded onto itself, and two surfaces crossing along a line of the mesh
(structured boxes offset by whole elements) only touch pairwise."""

from __future__ import annotations

import numpy as np

#: Relative tolerance of the overlap (of the bounding-box diagonal).
TOLERANCE = 1e-9
_CHUNK = 200_000


def crossing_triangles(nodes: np.ndarray, tris: np.ndarray,
                       near: np.ndarray | None = None) -> tuple[int, int] | None:
    """The first pair (i, j), i < j, of triangles (rows of ``tris``: node
    indices into ``nodes``) that cross or touch each other, or None.  Pairs
    whose rows of ``near`` (default ``tris``: the element's nodes of which a
    triangle is a part) share a node are neighbours and not tested."""
    from scipy.spatial import cKDTree

    if tris.shape[0] < 2:
        return None
    P = nodes[tris]  # (n, 3 corners, 3)
    lo, hi = P.min(axis=1), P.max(axis=1)
    scale = float(np.linalg.norm(nodes.max(axis=0) - nodes.min(axis=0)))
    tol = TOLERANCE * scale
    centre = 0.5 * (lo + hi)
    radius = 0.5 * np.linalg.norm(hi - lo, axis=1)
    floor = max(float(np.median(radius)) * 1e-3, tol, np.finfo(float).tiny)
    level = np.floor(np.log2(np.maximum(radius, floor) / floor)).astype(np.int64)
    classes = [np.flatnonzero(level == k) for k in np.unique(level)]
    trees = [cKDTree(centre[c]) for c in classes]
    reach = [float(radius[c].max()) + tol for c in classes]
    found: list[tuple[int, int]] = []
    for a, (ca, ta) in enumerate(zip(classes, trees)):
        for b in range(a, len(classes)):
            if a == b:
                pairs = ta.query_pairs(2.0 * reach[a], output_type="ndarray")
                i, j = ca[pairs[:, 0]], ca[pairs[:, 1]]
            else:
                m = ta.sparse_distance_matrix(trees[b], reach[a] + reach[b], output_type="ndarray")
                i, j = ca[m["i"]], classes[b][m["j"]]
            hit = _first_crossing(P, tris if near is None else near, lo, hi, i, j, tol)
            if hit is not None:
                found.append(hit)
    return min(found) if found else None


def _first_crossing(P, near, lo, hi, i, j, tol) -> tuple[int, int] | None:
    overlap = np.minimum(hi[i], hi[j]) - np.maximum(lo[i], lo[j])
    keep = np.all(overlap >= -tol, axis=1)
    i, j = i[keep], j[keep]
    shared = (near[i][:, :, None] == near[j][:, None, :]).any(axis=(1, 2))
    i, j = i[~shared], j[~shared]
    for s in range(0, i.size, _CHUNK):
        a, b = i[s:s + _CHUNK], j[s:s + _CHUNK]
        cross = _cross(P[a], P[b], tol)
        if cross.any():
            k = int(np.flatnonzero(cross)[0])
            return (int(min(a[k], b[k])), int(max(a[k], b[k])))
    return None


def _axes(group: int, T: np.ndarray, U: np.ndarray) -> np.ndarray:
    """Separating-axis candidates (K, n, 3) of one group, cheapest first: 0
    the two normals, 1 the in-plane edge normals of each, 2 the edge-edge
    cross products."""
    eT = np.roll(T, -1, axis=1) - T  # (K, 3 edges, 3)
    eU = np.roll(U, -1, axis=1) - U
    if group == 2:
        return np.cross(eT[:, :, None], eU[:, None, :]).reshape(-1, 9, 3)
    nT = np.cross(eT[:, 0], eT[:, 1])
    nU = np.cross(eU[:, 0], eU[:, 1])
    if group == 0:
        return np.stack([nT, nU], axis=1)
    return np.concatenate([np.cross(nT[:, None], eT), np.cross(nU[:, None], eU)], axis=1)


def _cross(T: np.ndarray, U: np.ndarray, tol: float) -> np.ndarray:
    """Per pair (K, 3, 3) x (K, 3, 3): whether the triangles cross or touch
    (no candidate axis separates their projections by more than ``tol``).
    Pairs are dropped as soon as a group of axes separates them."""
    live = np.arange(T.shape[0])
    for group in range(3):
        if live.size == 0:
            break
        Tl, Ul = T[live], U[live]
        ax = _axes(group, Tl, Ul)
        length = np.sqrt(np.einsum("kac,kac->ka", ax, ax))
        pT = np.einsum("kac,kvc->kav", ax, Tl)
        pU = np.einsum("kac,kvc->kav", ax, Ul)
        gap = np.maximum(pU.min(axis=2) - pT.max(axis=2), pT.min(axis=2) - pU.max(axis=2))
        live = live[~(gap > tol * length).any(axis=1)]
    out = np.zeros(T.shape[0], dtype=bool)
    out[live] = True
    return out


__all__ = ["TOLERANCE", "crossing_triangles"]

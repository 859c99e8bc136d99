"""Geometric search between two contact surfaces: candidate element pairs
(k-d trees over element-size classes), projection of points on a surface,
and the polygon clipping and triangle rules of the mortar integrals."""

from __future__ import annotations

import math

import numpy as np
import scipy.spatial

from ..bem.discretization import Discretization
from ..mesh.element import CORNERS, element_geometry, inverse_map


def tangent_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal t1, t2 with (t1, t2, n) right-handed.  t1 is the global
    axis least aligned with n, made orthogonal to n (a deterministic choice:
    reversing n keeps t1 and reverses t2)."""
    axis = np.argmin(np.abs(n), axis=1)
    e = np.zeros_like(n)
    e[np.arange(len(n)), axis] = 1.0
    t1 = e - np.einsum("ij,ij->i", e, n)[:, None] * n
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    t2 = np.cross(n, t1)
    return t1, t2


def polygon_areas(P: np.ndarray, count: np.ndarray) -> np.ndarray:
    """Signed areas of padded polygons ``P`` (n, V, 2) with ``count`` (n,)
    vertices each (counter-clockwise positive)."""
    V = P.shape[1]
    idx = np.arange(V)
    nxt = np.where(idx[None, :] + 1 < count[:, None], idx[None, :] + 1, 0)
    Q = np.take_along_axis(P, nxt[:, :, None], axis=1)
    terms = P[:, :, 0] * Q[:, :, 1] - Q[:, :, 0] * P[:, :, 1]
    return 0.5 * np.where(idx[None, :] < count[:, None], terms, 0.0).sum(axis=1)


def clip_polygons(subject: np.ndarray, clip: np.ndarray, vmax: int = 10):
    """Sutherland-Hodgman for many polygon pairs at once: the intersection
    of each ``subject`` (n, ks, 2) with the convex counter-clockwise
    ``clip`` (n, kc, 2).  Returns (vertices (n, vmax, 2), counts (n,))."""
    n, ks = subject.shape[:2]
    out = np.zeros((n, vmax, 2))
    out[:, :ks] = subject
    count = np.full(n, ks)
    idx = np.arange(vmax)[None, :]
    for i in range(clip.shape[1]):
        a = clip[:, i]
        e = clip[:, (i + 1) % clip.shape[1]] - a
        s = e[:, None, 0] * (out[:, :, 1] - a[:, None, 1]) - e[:, None, 1] * (out[:, :, 0] - a[:, None, 0])
        valid = idx < count[:, None]
        j1 = np.where(idx + 1 < count[:, None], idx + 1, 0)
        s1 = np.take_along_axis(s, j1, axis=1)
        inside, inside1 = s >= 0, s1 >= 0
        keep = valid & inside
        cross = valid & (inside != inside1)
        emitted = keep.astype(int) + cross
        pos = np.cumsum(emitted, axis=1) - emitted
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.where(cross, s / np.where(cross, s - s1, 1.0), 0.0)
        nb = np.take_along_axis(out, j1[:, :, None], axis=1)
        xpt = out + t[:, :, None] * (nb - out)
        new = np.zeros_like(out)
        r, c = np.nonzero(keep)
        new[r, pos[r, c]] = out[r, c]
        r, c = np.nonzero(cross)
        new[r, pos[r, c] + keep[r, c]] = xpt[r, c]
        out = new
        count = emitted.sum(axis=1)
    return out, count


def triangle_rule(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Collapsed Gauss rule on the unit triangle: (points (q, 2), weights),
    exact for polynomials of degree 2 order - 2."""
    g, w = np.polynomial.legendre.leggauss(order)
    g = 0.5 * (g + 1)
    w = 0.5 * w
    u, v = np.meshgrid(g, g, indexing="ij")
    wu, wv = np.meshgrid(w, w, indexing="ij")
    pts = np.stack([u.ravel(), (v * (1 - u)).ravel()], axis=1)
    return pts, (wu * wv * (1 - u)).ravel()



def candidate_pairs(Co, c_o, t1, t2, n_o, Ct, search: float, chunk: int = 100000):
    """(i, j) pairs (sorted) of owner elements i (corners Co (Eo, k, 3),
    centroid c_o, plane basis t1, t2, n_o) and other elements j (corners Ct)
    whose corner rectangles overlap in i's plane (inflated by a quarter of
    the larger element) and whose nearest corner is within ``search`` along
    n_o[i].  Pairs passing that test have centroids closer than
    sqrt2 (r_i + r_j + M/2) + search + M/2 + r_j, r the largest corner
    distance to the centroid and M = max(r_i, r_j); k-d tree queries per
    pair of element-size classes give the candidates within that bound, and
    the test runs on those only."""
    if len(Co) == 0 or len(Ct) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    ro = np.linalg.norm(Co - c_o[:, None, :], axis=2).max(axis=1)
    ct = Ct.mean(axis=1)
    rt = np.linalg.norm(Ct - ct[:, None, :], axis=2).max(axis=1)

    def classes(r):
        # size classes a factor 1.5 apart (all points: one class)
        if r.max() <= 0:
            return np.zeros(r.size, dtype=np.int64)
        return np.floor(np.log(np.maximum(r, r.max() * 1e-6) / r.max()) / np.log(1.5)).astype(np.int64)

    co_cls, ct_cls = classes(ro), classes(rt)
    codes = []
    for a in np.unique(co_cls):
        ia = np.flatnonzero(co_cls == a)
        ta = scipy.spatial.cKDTree(c_o[ia])
        Ra = ro[ia].max()
        for b in np.unique(ct_cls):
            jb = np.flatnonzero(ct_cls == b)
            Rb = rt[jb].max()
            M = max(Ra, Rb)
            reach = 1.01 * (math.sqrt(2.0) * (Ra + Rb + 0.5 * M) + search + 0.5 * M + Rb)
            d = ta.sparse_distance_matrix(scipy.spatial.cKDTree(ct[jb]), reach, output_type="ndarray")
            codes.append(ia[d["i"]] * len(Ct) + jb[d["j"]])
    code = np.unique(np.concatenate(codes))
    I, J = code // len(Ct), code % len(Ct)
    out = []
    for s0 in range(0, len(I), chunk):
        i, j = I[s0 : s0 + chunk], J[s0 : s0 + chunk]
        T = np.stack([t1[i], t2[i], n_o[i]], axis=2)  # (p, 3, 3)
        A = np.einsum("pkd,pdl->pkl", Co[i] - c_o[i][:, None, :], T)  # (p, k, 3)
        B = np.einsum("pkd,pdl->pkl", Ct[j] - c_o[i][:, None, :], T)
        alo, ahi = A[..., :2].min(axis=1), A[..., :2].max(axis=1)  # (p, 2)
        blo, bhi = B[..., :2].min(axis=1), B[..., :2].max(axis=1)
        tol = 0.25 * np.maximum((ahi - alo).max(axis=1), (bhi - blo).max(axis=1))
        hit = np.all((alo - tol[:, None] <= bhi) & (blo <= ahi + tol[:, None]), axis=1)
        hit &= np.abs(B[..., 2]).min(axis=1) <= search + tol
        out.append(np.stack([i[hit], j[hit]], axis=1))
    return np.concatenate(out) if out else np.zeros((0, 2), dtype=np.int64)


def locate(disc: Discretization, elements: np.ndarray, points: np.ndarray,
            search: float | None = None):
    """For each point, the element of ``elements`` whose plane-projection
    contains it (nearest along the normal when several do; the least-outside
    one when none does), looking no further than ``search`` along the normal
    (default a quarter of the largest element): (element (P,), xi (P, 2),
    inside (P,) bool)."""
    mesh = disc.mesh
    nc = CORNERS[mesh.element_type]
    C = mesh.nodes[mesh.elements[elements, :nc]]
    lo, hi = C.min(axis=1), C.max(axis=1)
    size = float(np.max(hi - lo))
    if search is None:
        search = 0.25 * size
    etype = mesh.element_type
    cen0 = np.tile(np.array([1 / 3, 1 / 3]) if etype.startswith("tri") else np.zeros(2), (len(elements), 1))
    c_e, n_e, _ = mesh.map(elements, cen0)
    t1e, t2e = tangent_basis(n_e)
    # candidates: the point inside the element's rectangle in its plane (with a
    # quarter-element margin) and within the search distance along its normal
    pairs = candidate_pairs(C, c_e, t1e, t2e, n_e, points[:, None, :], search)
    ei, pi = pairs[:, 0], pairs[:, 1]
    P = len(points)
    best_el = np.full(P, elements[0] if len(elements) else -1, dtype=np.int64)
    best_xi = np.zeros((P, 2))
    inside = np.zeros(P, dtype=bool)
    if pi.size == 0:
        return best_el, best_xi, inside
    cen = np.tile(np.array([1 / 3, 1 / 3]) if etype.startswith("tri") else np.zeros(2), (len(ei), 1))
    _, n, _ = mesh.map(elements[ei], cen)
    t1, t2 = tangent_basis(n)
    T = np.stack([t1, t2], axis=2)
    xi = inverse_map(disc.mesh, elements[ei], points[pi], T)
    x, _, _ = element_geometry(disc.mesh, elements[ei], xi)
    dist = np.abs(np.einsum("pd,pd->p", points[pi] - x, n))
    # outside-ness of the local coordinates
    if etype.startswith("tri"):
        out = np.maximum.reduce([-xi[:, 0], -xi[:, 1], xi.sum(axis=1) - 1, np.zeros(len(xi))])
    else:
        out = np.maximum(np.abs(xi).max(axis=1) - 1, 0.0)
    # an element that contains the projection, the nearest along the normal;
    # else the one whose nearest point (projection clipped to the element) is
    # closest in space (a point between two elements' normal prisms)
    clipped = _clip_local(etype, xi)
    y, _, _ = element_geometry(disc.mesh, elements[ei], clipped)
    outside = out > 1e-9
    key = np.where(outside, np.linalg.norm(points[pi] - y, axis=1), dist)
    order = np.lexsort((key, outside, pi))
    first = np.ones(order.size, dtype=bool)
    first[1:] = pi[order][1:] != pi[order][:-1]
    sel = order[first]
    best_el[pi[sel]] = elements[ei[sel]]
    best_xi[pi[sel]] = clipped[sel]
    inside[pi[sel]] = ~outside[sel]
    return best_el, best_xi, inside


def _clip_local(etype: str, xi: np.ndarray) -> np.ndarray:
    """Local coordinates moved onto the reference element (triangles: into
    the unit triangle; quadrilaterals: into [-1, 1]^2)."""
    if etype.startswith("tri"):
        xi = np.clip(xi, 0, 1)
        s = xi.sum(axis=1)
        xi[s > 1] /= s[s > 1, None]
        return xi
    return np.clip(xi, -1, 1)




__all__ = ["tangent_basis", "polygon_areas", "clip_polygons", "triangle_rule", "candidate_pairs",
           "locate"]

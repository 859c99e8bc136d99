"""Surface meshes: nodes, elements and named regions.

Conventions (see ``docs/theory.md``):

* ``nodes`` is an (n, 3) C-contiguous float64 array.
* Element types and node order follow gmsh/VTK: ``tri3``, ``tri6``, ``quad4``,
  ``quad8`` (serendipity) and ``quad9`` (Lagrange).  Corner nodes come first,
  counter-clockwise seen from outside the body, so the element normal
  ``dx/dxi x dx/deta`` points *out of* the body.
* Every element belongs to exactly one region (a face of a box, a gmsh
  physical group).  Boundary conditions and reactions are given per region.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import core
from ..errors import MeshError
from .element import (
    CENTROIDS, CORNERS, ELEMENT_TYPES, MAX_NODES, NODES_PER_ELEMENT, REFERENCE_NODES, REVERSED,
)

MAX_COORDINATE = 1e100
#: Most surface elements a mesh may have (far beyond what fits in memory).
MAX_ELEMENTS = 10_000_000

#: meshio cell-type names of the supported surface elements.
MESHIO_TYPES: dict[str, str] = {
    "triangle": "tri3",
    "triangle6": "tri6",
    "quad": "quad4",
    "quad8": "quad8",
    "quad9": "quad9",
}
_TO_MESHIO = {v: k for k, v in MESHIO_TYPES.items()}


def _boxes_containing(lo: np.ndarray, hi: np.ndarray, points: np.ndarray) -> list[np.ndarray]:
    """For each of ``points`` (P, 3), the indices of the boxes [lo, hi] (each
    (S, 3)) that contain it: a uniform grid of about S cells over all the
    boxes, each box listed in the cells it overlaps, each point tested
    against the boxes of its cell only (every point against every shell
    would be O(S²) winding numbers: 1,500 shells take 4 minutes that way)."""
    S = lo.shape[0]
    if S == 0:
        return [np.zeros(0, dtype=np.int64) for _ in range(len(points))]
    origin = lo.min(axis=0)
    span = np.maximum(hi.max(axis=0) - origin, 1e-300)
    n = max(1, int(round(S ** (1.0 / 3.0))))
    scale = n / span

    def cell(x):
        return np.clip(np.floor((x - origin) * scale).astype(np.int64), 0, n - 1)

    c0, c1 = cell(lo), cell(hi)
    cells: dict[int, list[int]] = {}
    for j in range(S):
        for ix in range(c0[j, 0], c1[j, 0] + 1):
            for iy in range(c0[j, 1], c1[j, 1] + 1):
                for iz in range(c0[j, 2], c1[j, 2] + 1):
                    cells.setdefault((ix * n + iy) * n + iz, []).append(j)
    pc = cell(np.asarray(points, dtype=float))
    out = []
    for p, (ix, iy, iz) in zip(points, pc):
        cand = np.asarray(cells.get((ix * n + iy) * n + iz, []), dtype=np.int64)
        inside = np.all((lo[cand] <= p) & (p <= hi[cand]), axis=1)
        out.append(cand[inside])
    return out


class SurfaceMesh:
    """A boundary surface made of one element type, split into named regions.

    Parameters
    ----------
    nodes:
        (n, 3) node coordinates.
    elements:
        (m, k) node indices, k the node count of ``element_type``.
    element_type:
        One of ``"tri3"``, ``"tri6"``, ``"quad4"``, ``"quad8"``, ``"quad9"``.
    regions:
        Region name -> element indices.  Every element must belong to exactly
        one region.  Default: one region ``"surface"``.
    source:
        Where the mesh came from (a file name), used in error messages.

    Cheap checks (shapes, finite coordinates, index range, repeated nodes,
    degenerate elements) run here; the topological checks (closed, outward
    oriented) run in :meth:`check`.
    """

    def __init__(
        self,
        nodes: Any,
        elements: Any,
        element_type: str,
        regions: Mapping[str, Iterable[int]] | None = None,
        *,
        source: str | None = None,
    ) -> None:
        where = f"{source}: " if source else ""
        self.source = source
        if element_type not in NODES_PER_ELEMENT:
            raise MeshError(
                f"{where}unknown element_type {element_type!r}; expected one of {ELEMENT_TYPES}"
            )
        try:
            X = np.ascontiguousarray(nodes, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise MeshError(f"{where}nodes must be a numeric (n, 3) array: {exc}") from None
        if X.ndim != 2 or X.shape[1] != 3 or X.shape[0] == 0:
            raise MeshError(f"{where}nodes must have shape (n, 3) with n > 0, got {X.shape}")
        bad = np.flatnonzero(~np.isfinite(X).all(axis=1))
        if bad.size:
            raise MeshError(
                f"{where}node {bad[0]} has non-finite coordinates {X[bad[0]].tolist()}"
                + (f" ({bad.size} such nodes)" if bad.size > 1 else "")
            )
        big = np.flatnonzero((np.abs(X) > MAX_COORDINATE).any(axis=1))
        if big.size:
            raise MeshError(
                f"{where}node {big[0]} has coordinates {X[big[0]].tolist()} beyond "
                f"±{MAX_COORDINATE:g}; use other length units"
            )
        k = NODES_PER_ELEMENT[element_type]
        try:
            C = np.asarray(elements)
        except (TypeError, ValueError) as exc:  # pragma: no cover - ragged input
            raise MeshError(f"{where}elements must be an (m, {k}) integer array: {exc}") from None
        if C.ndim != 2 or C.shape[1] != k or C.shape[0] == 0:
            raise MeshError(
                f"{where}elements of type {element_type} must have shape (m, {k}) with m > 0, "
                f"got {C.shape}"
            )
        if not np.issubdtype(C.dtype, np.integer):
            if not np.all(np.isfinite(C)) or np.any(C != np.round(C)):
                raise MeshError(f"{where}elements must hold integer node indices")
        C = np.ascontiguousarray(C, dtype=np.int64)
        out = np.flatnonzero((C < 0).any(axis=1) | (C >= X.shape[0]).any(axis=1))
        if out.size:
            raise MeshError(
                f"{where}element {out[0]} refers to node indices {C[out[0]].tolist()} outside "
                f"0..{X.shape[0] - 1}"
            )
        srt = np.sort(C, axis=1)
        rep = np.flatnonzero((srt[:, 1:] == srt[:, :-1]).any(axis=1))
        if rep.size:
            raise MeshError(
                f"{where}element {rep[0]} is degenerate: it repeats a node {C[rep[0]].tolist()}"
            )
        self.nodes = X
        self.elements = C
        self.element_type = element_type
        m = C.shape[0]
        if regions is None:
            regions = {"surface": np.arange(m)}
        owner = np.full(m, -1, dtype=np.int64)
        names: list[str] = []
        for name, idx in regions.items():
            if not isinstance(name, str) or not name:
                raise MeshError(f"{where}region names must be non-empty strings, got {name!r}")
            idx = np.asarray(list(idx) if not isinstance(idx, np.ndarray) else idx, dtype=np.int64)
            if idx.size == 0:
                raise MeshError(f"{where}region {name!r} has no elements")
            if idx.min() < 0 or idx.max() >= m:
                raise MeshError(
                    f"{where}region {name!r} refers to element {int(idx.max())} outside 0..{m - 1}"
                )
            twice = idx[owner[idx] >= 0]
            if twice.size:
                other = names[owner[twice[0]]]
                raise MeshError(
                    f"{where}element {int(twice[0])} is in both regions {other!r} and {name!r}"
                )
            owner[idx] = len(names)
            names.append(name)
        if (owner < 0).any():
            e = int(np.flatnonzero(owner < 0)[0])
            raise MeshError(
                f"{where}element {e} belongs to no region ({int((owner < 0).sum())} such "
                "elements); every element must be in exactly one region"
            )
        self.region_names: tuple[str, ...] = tuple(names)
        self.element_region = owner
        self._check_jacobians(where)

    # ------------------------------------------------------------------ basics
    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.elements.shape[0])

    @property
    def type_code(self) -> int:
        return ELEMENT_TYPES.index(self.element_type)

    @property
    def order(self) -> int:
        """Polynomial order of the elements (1 linear, 2 quadratic)."""
        return 1 if self.element_type in ("tri3", "quad4") else 2

    def region(self, name: str) -> np.ndarray:
        """Element indices of region ``name``."""
        if name not in self.region_names:
            raise MeshError(
                f"{self._where()}unknown region {name!r}; regions are {list(self.region_names)}"
            )
        return np.flatnonzero(self.element_region == self.region_names.index(name))

    @property
    def regions(self) -> dict[str, np.ndarray]:
        return {n: self.region(n) for n in self.region_names}

    def _where(self) -> str:
        return f"{self.source}: " if self.source else ""

    def padded_connectivity(self) -> tuple[np.ndarray, np.ndarray]:
        """(etype (m,) int32, conn (m, 9) int64 padded with -1) for the core."""
        m = self.n_elements
        etype = np.full(m, self.type_code, dtype=np.int32)
        conn = np.full((m, MAX_NODES), -1, dtype=np.int64)
        conn[:, : self.elements.shape[1]] = self.elements
        return etype, conn

    def map(self, elements: Any, local: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Positions (P, 3), unit normals (P, 3) and area Jacobians (P,) at local
        coordinates ``local`` (P, 2) of ``elements`` (P,)."""
        etype, conn = self.padded_connectivity()
        e = np.ascontiguousarray(elements, dtype=np.int64)
        xi = np.ascontiguousarray(local, dtype=np.float64).reshape(-1, 2)
        return core().map_points(self.nodes, etype, conn, e, xi)

    def _check_jacobians(self, where: str) -> None:
        t = self.element_type
        ref = REFERENCE_NODES[t]
        c = CENTROIDS[t]
        # corners pulled slightly inward, midpoints, centroid
        pts = np.vstack([c + 0.98 * (ref - c), c[None, :]])
        m, p = self.n_elements, pts.shape[0]
        e = np.repeat(np.arange(m), p)
        xi = np.tile(pts, (m, 1))
        _, n, J = self.map(e, xi)
        J = J.reshape(m, p)
        n = n.reshape(m, p, 3)
        corners = self.nodes[self.elements[:, : CORNERS[t]]]
        size = np.linalg.norm(corners - corners.mean(axis=1, keepdims=True), axis=2).max(axis=1)
        ref_area = 0.5 if t.startswith("tri") else 4.0
        bad = np.flatnonzero((J.min(axis=1) <= 1e-10 * size**2 / ref_area) | (size == 0))
        if bad.size:
            i = int(bad[0])
            raise MeshError(
                f"{where}element {i} is degenerate (zero or near-zero area; nodes "
                f"{self.elements[i].tolist()})" + (f", {bad.size} such elements" if bad.size > 1 else "")
            )
        # the normal must not flip inside an element (folded element)
        flip = np.einsum("mpk,mk->mp", n, n[:, -1, :]).min(axis=1)
        bad = np.flatnonzero(flip <= 0.0)
        if bad.size:
            i = int(bad[0])
            raise MeshError(
                f"{where}element {i} is folded: its normal reverses inside the element "
                f"(nodes {self.elements[i].tolist()}); check the node order"
            )

    # -------------------------------------------------------------- topology
    def _corner_edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Directed corner-to-corner edges (E*nc, 2) and their element."""
        nc = CORNERS[self.element_type]
        cor = self.elements[:, :nc]
        a = cor
        b = np.roll(cor, -1, axis=1)
        edges = np.stack([a.ravel(), b.ravel()], axis=1)
        owner = np.repeat(np.arange(self.n_elements), nc)
        return edges, owner

    def quality(self) -> dict[str, np.ndarray]:
        """Per element: ``min_edge`` and ``max_edge`` (corner-to-corner edge
        lengths), ``aspect`` (their ratio, 1 for a square or an equilateral
        triangle's edges) and ``area``."""
        edges, owner = self._corner_edges()
        length = np.linalg.norm(self.nodes[edges[:, 1]] - self.nodes[edges[:, 0]], axis=1)
        L = length.reshape(self.n_elements, -1)
        lo, hi = L.min(axis=1), L.max(axis=1)
        W = self.surface_quadrature(4).weights
        with np.errstate(divide="ignore"):
            aspect = np.where(lo > 0, hi / np.where(lo > 0, lo, 1.0), np.inf)
        return {"min_edge": lo, "max_edge": hi, "aspect": aspect, "area": W.sum(axis=1)}

    def components(self) -> list[np.ndarray]:
        """Connected components (element index arrays) through shared edges."""
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        edges, owner = self._corner_edges()
        key = np.sort(edges, axis=1)
        _, inv = np.unique(key, axis=0, return_inverse=True)
        inv = inv.ravel()
        m = self.n_elements
        g = coo_matrix((np.ones(inv.size), (owner, inv)), shape=(m, inv.max() + 1)).tocsr()
        adj = g @ g.T
        n, lab = connected_components(adj, directed=False)
        return [np.flatnonzero(lab == i) for i in range(n)]

    def signed_volume(self, elements: np.ndarray | None = None) -> float:
        """Volume enclosed by (a closed part of) the surface, V = 1/3 ∮ x·n dS;
        negative when the normals point inward.  x is taken from a node of the
        surface (the same for a closed one): far from the origin (1e12) the
        absolute x cancelled to a wrong sign."""
        q = self.surface_quadrature(4, elements)
        first = self.elements[0 if elements is None else np.asarray(elements).ravel()[0], 0]
        x = q.points - self.nodes[first]
        return float(np.einsum("eqk,eqk,eq->", x, q.normals, q.weights) / 3.0)

    def surface_quadrature(self, order: int = 4, elements: np.ndarray | None = None):
        """Gauss points of the elements: a :class:`SurfaceQuadrature` with
        points (E, Q, 3), normals (E, Q, 3), weights (E, Q) including the area
        Jacobian, ``order`` x ``order`` points per element."""
        etype, conn = self.padded_connectivity()
        if elements is not None:
            etype, conn = etype[elements], np.ascontiguousarray(conn[elements])
        fxi = np.zeros((etype.size, MAX_NODES, 2))
        fxi[:, : NODES_PER_ELEMENT[self.element_type]] = REFERENCE_NODES[self.element_type]
        X, N, W, _ = core().surface_quadrature(self.nodes, etype, conn, conn, fxi, int(order))
        return SurfaceQuadrature(X, N, W)

    @property
    def area(self) -> float:
        return float(self.surface_quadrature(4).weights.sum())

    def winding_number(self, points: Any, elements: np.ndarray | None = None) -> np.ndarray:
        """Generalized winding number of the (flat-facet approximation of the)
        surface around each point: ~1 inside an outward surface, ~0 outside."""
        P = np.atleast_2d(np.asarray(points, dtype=float))
        nc = CORNERS[self.element_type]
        el = self.elements if elements is None else self.elements[elements]
        cor = el[:, :nc]
        if nc == 3:
            tris = cor
        else:
            tris = np.vstack([cor[:, [0, 1, 2]], cor[:, [0, 2, 3]]])
        A = self.nodes[tris[:, 0]]
        B = self.nodes[tris[:, 1]]
        C = self.nodes[tris[:, 2]]
        out = np.empty(P.shape[0])
        for i, p in enumerate(P):
            a, b, c = A - p, B - p, C - p
            la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
            num = np.einsum("ij,ij->i", a, np.cross(b, c))
            den = (
                la * lb * lc
                + np.einsum("ij,ij->i", a, b) * lc
                + np.einsum("ij,ij->i", b, c) * la
                + np.einsum("ij,ij->i", c, a) * lb
            )
            out[i] = np.arctan2(num, den).sum() / (2.0 * math.pi)
        return out

    def check(self) -> SurfaceMesh:
        """Check that the surface bounds a solid: every edge shared by exactly
        two elements with opposite directions (closed, consistently oriented),
        and normals pointing out of the solid (outer shells enclose positive
        volume; cavities, i.e. shells inside another shell, negative).

        Raises :class:`MeshError` naming the first offending edge or shell.
        Returns the mesh, so ``mesh = read_mesh(path).check()`` works.
        """
        where = self._where()
        edges, owner = self._corner_edges()
        key = np.sort(edges, axis=1)
        uniq, inv, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        inv = inv.ravel()
        if (count != 2).any():
            j = int(np.flatnonzero(count != 2)[0])
            els = owner[inv == j].tolist()
            kind = "an open boundary" if count[j] == 1 else "a non-manifold edge"
            raise MeshError(
                f"{where}surface is not closed: edge between nodes {uniq[j].tolist()} belongs to "
                f"{count[j]} element(s) {els} ({kind}); a body's surface must be closed"
            )
        # orientation: the two uses of an edge must run in opposite directions
        fwd = edges[:, 0] < edges[:, 1]
        s = np.zeros(uniq.shape[0], dtype=np.int64)
        np.add.at(s, inv, np.where(fwd, 1, -1))
        if (s != 0).any():
            j = int(np.flatnonzero(s != 0)[0])
            els = owner[inv == j].tolist()
            raise MeshError(
                f"{where}inconsistent orientation: elements {els} run the shared edge "
                f"{uniq[j].tolist()} in the same direction (one of them is inverted; corner "
                "nodes must be counter-clockwise seen from outside)"
            )
        # before the shells: inside and outside mean nothing on a surface through itself
        self._check_crossings(where)
        for c, depth, v, inverted in self._shells():
            want_positive = depth % 2 == 0
            if inverted:
                what = "outer surface" if want_positive else "cavity surface"
                regions = sorted({self.region_names[r] for r in self.element_region[c]})
                raise MeshError(
                    f"{where}inverted orientation: the {what} made of regions {regions} has "
                    f"normals pointing into the solid (signed "
                    f"volume {v:.6g}); reverse its elements' node order (SurfaceMesh.oriented() "
                    "does this for whole shells)"
                )
        return self

    def _check_crossings(self, where: str) -> None:
        """Refuse a surface that crosses itself (:mod:`bemcontact.mesh.intersect`,
        on the flat facets through the corner nodes: quadrilaterals as two
        triangles)."""
        from .intersect import crossing_triangles

        nc = CORNERS[self.element_type]
        cor = self.elements[:, :nc]
        tris = cor if nc == 3 else np.vstack([cor[:, [0, 1, 2]], cor[:, [0, 2, 3]]])
        hit = crossing_triangles(self.nodes, np.ascontiguousarray(tris),
                                 near=None if nc == 3 else np.vstack([cor, cor]))
        if hit is None:
            return
        a, b = (t % self.n_elements for t in hit)
        regions = sorted({self.region_names[r] for r in self.element_region[[a, b]]})
        near = self.nodes[self.elements[a, :nc]].mean(axis=0)
        raise MeshError(
            f"{where}the surface intersects itself: elements {a} and {b} (regions "
            f"{', '.join(regions)}) cross near ({near[0]:.6g}, {near[1]:.6g}, {near[2]:.6g}); "
            "a body's surface must not pass through itself"
        )

    def _shells(self) -> list[tuple[np.ndarray, int, float, bool]]:
        """Per shell (connected component): its elements, its depth (number of
        other shells enclosing it; 0 = outer surface), its signed volume, and
        whether its normals point into the solid (outer shells must enclose
        positive volume, cavities negative)."""
        comps = self.components()
        points = np.array([self.nodes[self.elements[c[0], 0]] for c in comps])
        boxes = [self.nodes[np.unique(self.elements[c])] for c in comps]
        lo = np.array([b.min(axis=0) for b in boxes])
        hi = np.array([b.max(axis=0) for b in boxes])
        out = []
        for i, (c, enclosing) in enumerate(zip(comps, _boxes_containing(lo, hi, points))):
            depth = sum(
                1 for j in enclosing
                if j != i and abs(self.winding_number(points[i], comps[j])[0]) > 0.5
            )
            v = self.signed_volume(c)
            out.append((c, depth, v, (v > 0) != (depth % 2 == 0)))
        return out

    def reversed(self, elements: np.ndarray | None = None) -> SurfaceMesh:
        """A copy with the node order (and so the normal) of ``elements``
        (default: all) reversed."""
        perm = REVERSED[self.element_type]
        E = self.elements.copy()
        sel = np.arange(self.n_elements) if elements is None else np.asarray(elements)
        E[sel] = E[sel][:, perm]
        return SurfaceMesh(self.nodes, E, self.element_type, self.regions, source=self.source)

    def oriented(self) -> SurfaceMesh:
        """A copy in which every shell (connected component) whose normals point
        into the solid is reversed: outer shells outward, cavity shells toward
        the cavity.  Each shell must already be consistently oriented (as
        gmsh writes them); the result passes :meth:`check` if the surface is
        closed."""
        flip = [c for c, _, _, inverted in self._shells() if inverted]
        if not flip:
            return self
        return self.reversed(np.concatenate(flip))

    # ------------------------------------------------------------- conversions
    def to_meshio(self):
        import meshio

        reg = self.element_region.astype(np.int64)
        return meshio.Mesh(
            self.nodes,
            [(_TO_MESHIO[self.element_type], self.elements)],
            cell_data={"region": [reg]},
        )

    def __repr__(self) -> str:
        return (
            f"SurfaceMesh({self.n_nodes} nodes, {self.n_elements} {self.element_type} elements, "
            f"regions {list(self.region_names)})"
        )


@dataclass(frozen=True)
class SurfaceQuadrature:
    points: np.ndarray
    normals: np.ndarray
    weights: np.ndarray



__all__ = ["MAX_COORDINATE", "MAX_ELEMENTS", "MESHIO_TYPES", "SurfaceMesh", "SurfaceQuadrature"]

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

import contextlib
import io
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import MeshError

#: Element type names in code order (the compiled core uses the index).
#: Largest accepted |coordinate| (beyond it, Jacobians and normals overflow).
MAX_COORDINATE = 1e100
#: Most surface elements a mesh may have (far beyond what fits in memory).
MAX_ELEMENTS = 10_000_000
ELEMENT_TYPES: tuple[str, ...] = ("tri3", "tri6", "quad4", "quad8", "quad9")
NODES_PER_ELEMENT: dict[str, int] = {"tri3": 3, "tri6": 6, "quad4": 4, "quad8": 8, "quad9": 9}
CORNERS: dict[str, int] = {"tri3": 3, "tri6": 3, "quad4": 4, "quad8": 4, "quad9": 4}
#: meshio cell-type names of the supported surface elements.
MESHIO_TYPES: dict[str, str] = {
    "triangle": "tri3",
    "triangle6": "tri6",
    "quad": "quad4",
    "quad8": "quad8",
    "quad9": "quad9",
}
_TO_MESHIO = {v: k for k, v in MESHIO_TYPES.items()}
MAX_NODES = 9

#: Reference coordinates of the element nodes (triangle: xi, eta >= 0,
#: xi + eta <= 1; quadrilateral: [-1, 1]^2), gmsh/VTK order.
REFERENCE_NODES: dict[str, np.ndarray] = {
    "tri3": np.array([[0, 0], [1, 0], [0, 1]], float),
    "tri6": np.array([[0, 0], [1, 0], [0, 1], [0.5, 0], [0.5, 0.5], [0, 0.5]], float),
    "quad4": np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float),
    "quad8": np.array(
        [[-1, -1], [1, -1], [1, 1], [-1, 1], [0, -1], [1, 0], [0, 1], [-1, 0]], float
    ),
    "quad9": np.array(
        [[-1, -1], [1, -1], [1, 1], [-1, 1], [0, -1], [1, 0], [0, 1], [-1, 0], [0, 0]], float
    ),
}
_REVERSE: dict[str, list[int]] = {
    "tri3": [0, 2, 1],
    "tri6": [0, 2, 1, 5, 4, 3],
    "quad4": [0, 3, 2, 1],
    "quad8": [0, 3, 2, 1, 7, 6, 5, 4],
    "quad9": [0, 3, 2, 1, 7, 6, 5, 4, 8],
}
CENTROIDS: dict[str, np.ndarray] = {
    t: (np.array([1 / 3, 1 / 3]) if t.startswith("tri") else np.zeros(2)) for t in ELEMENT_TYPES
}


def _core():
    from . import _core

    return _core


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
        return _core().map_points(self.nodes, etype, conn, e, xi)

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
        negative when the normals point inward."""
        q = self.surface_quadrature(4, elements)
        return float(np.einsum("eqk,eqk,eq->", q.points, q.normals, q.weights) / 3.0)

    def surface_quadrature(self, order: int = 4, elements: np.ndarray | None = None):
        """Gauss points of the elements: a :class:`SurfaceQuadrature` with
        points (E, Q, 3), normals (E, Q, 3), weights (E, Q) including the area
        Jacobian, ``order`` x ``order`` points per element."""
        etype, conn = self.padded_connectivity()
        if elements is not None:
            etype, conn = etype[elements], np.ascontiguousarray(conn[elements])
        fxi = np.zeros((etype.size, MAX_NODES, 2))
        fxi[:, : NODES_PER_ELEMENT[self.element_type]] = REFERENCE_NODES[self.element_type]
        X, N, W, _ = _core().surface_quadrature(self.nodes, etype, conn, conn, fxi, int(order))
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

    def _shells(self) -> list[tuple[np.ndarray, int, float, bool]]:
        """Per shell (connected component): its elements, its depth (number of
        other shells enclosing it; 0 = outer surface), its signed volume, and
        whether its normals point into the solid (outer shells must enclose
        positive volume, cavities negative)."""
        comps = self.components()
        out = []
        for i, c in enumerate(comps):
            p = self.nodes[self.elements[c[0], 0]]
            depth = sum(
                1 for j, d in enumerate(comps)
                if j != i and abs(self.winding_number(p, d)[0]) > 0.5
            )
            v = self.signed_volume(c)
            out.append((c, depth, v, (v > 0) != (depth % 2 == 0)))
        return out

    def reversed(self, elements: np.ndarray | None = None) -> SurfaceMesh:
        """A copy with the node order (and so the normal) of ``elements``
        (default: all) reversed."""
        perm = _REVERSE[self.element_type]
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


# --------------------------------------------------------------------- box
def _graded(n: int, lo: float, hi: float, ratio: float) -> np.ndarray:
    """n + 1 coordinates from lo to hi; element sizes in geometric progression
    with last/first = ratio."""
    if n == 1 or ratio == 1.0:
        return np.linspace(lo, hi, n + 1)
    q = ratio ** (1.0 / (n - 1))
    h = q ** np.arange(n)
    x = np.concatenate([[0.0], np.cumsum(h)])
    return lo + (hi - lo) * x / x[-1]


def box(
    lower: Sequence[float] = (0.0, 0.0, 0.0),
    upper: Sequence[float] = (1.0, 1.0, 1.0),
    divisions: int | Sequence[int] = 4,
    element_type: str = "quad4",
    grading: float | Sequence[float] = 1.0,
) -> SurfaceMesh:
    """Structured surface mesh of the box ``lower`` <= x <= ``upper``.

    Parameters
    ----------
    divisions:
        Elements along x, y and z (an int for all three).  Two boxes with
        different divisions have non-matching faces.
    element_type:
        ``quad4``, ``quad8``, ``quad9``, ``tri3`` or ``tri6`` (triangles split
        each quadrilateral cell along a diagonal).
    grading:
        Per direction, ratio of the last to the first element size (1:
        uniform; < 1 refines toward the upper face).

    Regions: ``xmin``, ``xmax``, ``ymin``, ``ymax``, ``zmin``, ``zmax``.
    """
    lo = np.asarray(lower, float)
    hi = np.asarray(upper, float)
    if lo.shape != (3,) or hi.shape != (3,) or not (np.isfinite(lo).all() and np.isfinite(hi).all()):
        raise MeshError(f"box: lower and upper must be 3 finite numbers, got {lower!r}, {upper!r}")
    if (hi <= lo).any():
        a = int(np.flatnonzero(hi <= lo)[0])
        raise MeshError(f"box: upper[{a}] = {hi[a]} must exceed lower[{a}] = {lo[a]}")
    div = np.broadcast_to(np.asarray(divisions, dtype=object), (3,))

    def whole(d) -> bool:
        if isinstance(d, (bool, np.bool_)):
            return False
        if isinstance(d, (int, np.integer)):
            return d >= 1
        return isinstance(d, (float, np.floating)) and math.isfinite(d) and d.is_integer() \
            and d >= 1

    if not all(whole(d) for d in div):
        raise MeshError(f"box: divisions must be integers >= 1, got {divisions!r}")
    nx, ny, nz = (int(d) for d in div)
    count = 2 * (nx * ny + ny * nz + nx * nz)
    if count > MAX_ELEMENTS:
        raise MeshError(
            f"box: divisions {[nx, ny, nz]} give {count:,} surface elements, more than the "
            f"{MAX_ELEMENTS:,} bemcontact accepts"
        )
    div = np.array([nx, ny, nz], dtype=int)
    grd = np.broadcast_to(np.asarray(grading, float), (3,))
    if not (np.isfinite(grd).all() and (grd > 0).all()):
        raise MeshError(f"box: grading must be positive numbers, got {grading!r}")
    if element_type not in NODES_PER_ELEMENT:
        raise MeshError(f"box: unknown element_type {element_type!r}; expected one of {ELEMENT_TYPES}")
    quadratic = element_type in ("quad8", "quad9", "tri6")
    # 1D coordinates on the (possibly refined) node grid
    coords = []
    for a in range(3):
        c = _graded(int(div[a]), lo[a], hi[a], float(grd[a]))
        if quadratic:
            f = np.empty(2 * c.size - 1)
            f[0::2] = c
            f[1::2] = 0.5 * (c[1:] + c[:-1])
            c = f
        coords.append(c)
    step = 2 if quadratic else 1
    ids: dict[tuple[int, int, int], int] = {}
    nodes: list[tuple[float, float, float]] = []

    def node(ix: int, iy: int, iz: int) -> int:
        k = (ix, iy, iz)
        if k not in ids:
            ids[k] = len(nodes)
            nodes.append((coords[0][ix], coords[1][iy], coords[2][iz]))
        return ids[k]

    elements: list[list[int]] = []
    regions: dict[str, list[int]] = {}
    names = ("x", "y", "z")
    for a in range(3):
        b, c = (a + 1) % 3, (a + 2) % 3  # e_b x e_c = e_a
        nb, nc = coords[b].size, coords[c].size
        for side, fixed in (("min", 0), ("max", coords[a].size - 1)):
            reg = regions.setdefault(f"{names[a]}{side}", [])

            def g(i: int, j: int, a=a, b=b, c=c, fixed=fixed) -> int:
                idx = [0, 0, 0]
                idx[a], idx[b], idx[c] = fixed, i, j
                return node(*idx)

            for i in range(0, nb - 1, step):
                for j in range(0, nc - 1, step):
                    s = step
                    # counter-clockwise in (b, c) -> normal +e_a (max side)
                    if element_type in ("quad4", "tri3"):
                        q = [g(i, j), g(i + s, j), g(i + s, j + s), g(i, j + s)]
                    else:
                        q = [g(i, j), g(i + 2, j), g(i + 2, j + 2), g(i, j + 2),
                             g(i + 1, j), g(i + 2, j + 1), g(i + 1, j + 2), g(i, j + 1),
                             g(i + 1, j + 1)]  # fmt: skip
                    if side == "min":  # reverse orientation
                        if len(q) == 4:
                            q = [q[0], q[3], q[2], q[1]]
                        else:
                            q = [q[0], q[3], q[2], q[1], q[7], q[6], q[5], q[4], q[8]]
                    if element_type in ("quad4", "quad9"):
                        cells = [q]
                    elif element_type == "quad8":
                        cells = [q[:8]]
                    elif element_type == "tri3":
                        cells = [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
                    else:  # tri6 from the quad9 pattern
                        cells = [[q[0], q[1], q[2], q[4], q[5], q[8]],
                                 [q[0], q[2], q[3], q[8], q[6], q[7]]]  # fmt: skip
                    for cell in cells:
                        reg.append(len(elements))
                        elements.append(cell)
    used = sorted({n for e in elements for n in e})
    remap = np.full(len(nodes), -1)
    remap[used] = np.arange(len(used))
    X = np.asarray(nodes)[used]
    E = remap[np.asarray(elements)]
    return SurfaceMesh(X, E, element_type, regions, source="box")


# ------------------------------------------------------------------- files
def _gmsh_physical_names(path: str) -> list[tuple[int, int, str]]:
    """(dimension, tag, name) of a gmsh .msh file's $PhysicalNames section
    (ASCII in both the ASCII and the binary formats); [] if there is none."""
    with open(path, "rb") as f:
        data = f.read()
    start = data.find(b"$PhysicalNames")
    end = data.find(b"$EndPhysicalNames", start)
    if start < 0 or end < 0:
        return []
    out = []
    for line in data[start:end].decode("utf-8", "replace").splitlines()[2:]:
        parts = line.split(maxsplit=2)
        if len(parts) == 3 and parts[0].isdigit() and parts[1].lstrip("-").isdigit():
            out.append((int(parts[0]), int(parts[1]), parts[2].strip().strip('"')))
    return out


def read_mesh(path: str | os.PathLike, element_type: str | None = None) -> SurfaceMesh:
    """Read a surface mesh from any file meshio reads (gmsh ``.msh``, VTU, ...).

    gmsh physical groups of dimension 2 become regions (named by their
    physical name, or ``"group<tag>"`` when unnamed).  Without physical
    groups, cell data ``region`` (as written by bemcontact) is used, else one
    region ``"surface"``.  Line, vertex and volume cells are ignored.  The
    file must hold one surface element type (``element_type`` picks one when
    it holds several).
    """
    import meshio

    p = os.fspath(path)
    if not os.path.exists(p):
        raise MeshError(f"{p}: no such file")
    if os.path.isdir(p):
        raise MeshError(f"{p}: is a directory, not a mesh file")
    if p.lower().endswith(".msh"):
        seen: dict[str, int] = {}
        for dim, tag, name in _gmsh_physical_names(p):
            if dim != 2:
                continue
            if name in seen:
                raise MeshError(
                    f"{p}: two physical surface groups are named {name!r} (tags {seen[name]} "
                    f"and {tag}); give each group its own name (or merge them in gmsh)"
                )
            seen[name] = tag
    captured = io.StringIO()
    try:
        with contextlib.redirect_stderr(captured), contextlib.redirect_stdout(captured):
            m = meshio.read(p)
    except (Exception, SystemExit) as exc:  # meshio raises many types, even SystemExit
        detail = " ".join(captured.getvalue().split()) or f"{type(exc).__name__}: {exc}"
        raise MeshError(f"{p}: cannot read mesh: {detail}") from None
    blocks = [(i, MESHIO_TYPES[b.type]) for i, b in enumerate(m.cells) if b.type in MESHIO_TYPES]
    found = sorted({b.type for b in m.cells})
    if not blocks:
        raise MeshError(
            f"{p}: no surface elements (found cell types {found}); bemcontact needs the "
            "boundary surface: triangle, triangle6, quad, quad8 or quad9"
        )
    types = sorted({t for _, t in blocks})
    if element_type is None:
        if len(types) > 1:
            raise MeshError(
                f"{p}: mixed surface element types {types}; pass element_type= to pick one "
                "(or remesh with one type)"
            )
        element_type = types[0]
    elif element_type not in types:
        raise MeshError(f"{p}: element_type {element_type!r} not in the file (found {types})")
    blocks = [i for i, t in blocks if t == element_type]
    conn = np.vstack([m.cells[i].data for i in blocks])
    names_by_tag: dict[int, str] = {}
    for name, data in (m.field_data or {}).items():
        arr = np.asarray(data).ravel()
        if arr.size >= 2 and int(arr[1]) == 2:
            names_by_tag[int(arr[0])] = name
    tags = None
    if "gmsh:physical" in m.cell_data:
        tags = np.concatenate([np.asarray(m.cell_data["gmsh:physical"][i]) for i in blocks])
        regions: dict[str, list[int]] = {}
        for t in np.unique(tags):
            regions[names_by_tag.get(int(t), f"group{int(t)}")] = np.flatnonzero(tags == t)
    elif "region" in m.cell_data:
        tags = np.concatenate([np.asarray(m.cell_data["region"][i]) for i in blocks])
        regions = {f"region{int(t)}": np.flatnonzero(tags == t) for t in np.unique(tags)}
    else:
        regions = {"surface": np.arange(conn.shape[0])}
    # drop nodes not used by surface elements (volume meshes keep interior nodes)
    used = np.unique(conn)
    if used.size and (used[0] < 0 or used[-1] >= m.points.shape[0]):
        raise MeshError(
            f"{p}: an element refers to node {int(used[-1] if used[-1] >= 0 else used[0])}, but "
            f"the file has {m.points.shape[0]} nodes (numbered from 0)"
        )
    remap = np.full(m.points.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    pts = np.asarray(m.points, dtype=float)
    if pts.shape[1] == 2:
        raise MeshError(f"{p}: the mesh is 2D (points have 2 coordinates); a 3D surface is needed")
    return SurfaceMesh(pts[used], remap[conn], element_type, regions, source=p)


__all__ = ["MAX_COORDINATE", "MAX_ELEMENTS", "SurfaceMesh", "SurfaceQuadrature", "box", "read_mesh", "ELEMENT_TYPES"]

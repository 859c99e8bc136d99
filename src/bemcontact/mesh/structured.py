"""Structured surface meshes of boxes (no external mesher)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..errors import MeshError
from .element import ELEMENT_TYPES, NODES_PER_ELEMENT
from .surface import MAX_ELEMENTS, SurfaceMesh


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




__all__ = ["box"]

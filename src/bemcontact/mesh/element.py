"""Element types: node counts, reference nodes and the Lagrange basis.

Element types and node order follow gmsh/VTK: ``tri3``, ``tri6``, ``quad4``,
``quad8`` (serendipity) and ``quad9`` (Lagrange).  Corner nodes come first,
counter-clockwise seen from outside the body.  The basis here (NumPy, for the
frame and the search) spans the same monomials as cpp/bemcontact's elements.
"""

from __future__ import annotations

import numpy as np

#: Element type names in code order (the compiled core uses the index).
ELEMENT_TYPES: tuple[str, ...] = ("tri3", "tri6", "quad4", "quad8", "quad9")
NODES_PER_ELEMENT: dict[str, int] = {"tri3": 3, "tri6": 6, "quad4": 4, "quad8": 8, "quad9": 9}
CORNERS: dict[str, int] = {"tri3": 3, "tri6": 3, "quad4": 4, "quad8": 4, "quad9": 4}
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
REVERSED: dict[str, list[int]] = {
    "tri3": [0, 2, 1],
    "tri6": [0, 2, 1, 5, 4, 3],
    "quad4": [0, 3, 2, 1],
    "quad8": [0, 3, 2, 1, 7, 6, 5, 4],
    "quad9": [0, 3, 2, 1, 7, 6, 5, 4, 8],
}
CENTROIDS: dict[str, np.ndarray] = {
    t: (np.array([1 / 3, 1 / 3]) if t.startswith("tri") else np.zeros(2)) for t in ELEMENT_TYPES
}



# Monomial exponents (p, q) of xi^p eta^q spanning each element's space (the
# order of the compiled core's elements).
_MONOMIALS = {
    "tri3": ((0, 0), (1, 0), (0, 1)),
    "tri6": ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)),
    "quad4": ((0, 0), (1, 0), (0, 1), (1, 1)),
    "quad8": ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2), (2, 1), (1, 2)),
    "quad9": ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2), (2, 1), (1, 2), (2, 2)),
}


def monomials(etype: str, xi: np.ndarray):
    """Monomials and their d/dxi, d/deta at ``xi`` (P, 2): each (P, k)."""
    x, y = xi[:, 0], xi[:, 1]
    one, zero = np.ones_like(x), np.zeros_like(x)
    px, py = (one, x, x * x), (one, y, y * y)
    dpx, dpy = (zero, one, 2 * x), (zero, one, 2 * y)
    e = _MONOMIALS[etype]
    M = np.stack([px[a] * py[b] for a, b in e], axis=1)
    Mx = np.stack([dpx[a] * py[b] for a, b in e], axis=1)
    My = np.stack([px[a] * dpy[b] for a, b in e], axis=1)
    return M, Mx, My


def lagrange_basis(etype: str, nodes_xi: np.ndarray, xi: np.ndarray):
    """Lagrange basis (values, d/dxi, d/deta), each (P, k), of element type
    ``etype`` through local nodes ``nodes_xi`` ((k, 2) shared by all points,
    or (P, k, 2) one set per point) at ``xi`` (P, 2)."""
    e = _MONOMIALS[etype]
    nodes_xi = np.asarray(nodes_xi, dtype=float)
    # V[..., i, m] = monomial m at node i; basis_k = sum_m mono_m inv(V)[m, k]
    V = np.stack([nodes_xi[..., 0] ** a * nodes_xi[..., 1] ** b for a, b in e], axis=-1)
    C = np.linalg.inv(V)
    M, Mx, My = monomials(etype, np.asarray(xi, dtype=float))
    if C.ndim == 2:
        return M @ C, Mx @ C, My @ C
    return (np.einsum("pm,pmk->pk", M, C), np.einsum("pm,pmk->pk", Mx, C),
            np.einsum("pm,pmk->pk", My, C))



def element_geometry(mesh, elements: np.ndarray, xi: np.ndarray, X: np.ndarray | None = None):
    """x, dx/dxi, dx/deta (each (P, 3)) of the mesh map of ``mesh`` (a
    :class:`~bemcontact.mesh.SurfaceMesh`) at ``xi`` in ``elements``; ``X``
    (P, k, 3), the elements' node positions, may be passed when it is reused."""
    N, Nx, Ny = lagrange_basis(mesh.element_type, REFERENCE_NODES[mesh.element_type], xi)
    if X is None:
        X = mesh.nodes[mesh.elements[elements]]
    # (P, 3, k) @ (P, k, 3) -> rows x, dx/dxi, dx/deta
    out = np.matmul(np.stack([N, Nx, Ny], axis=1), X)
    return out[:, 0], out[:, 1], out[:, 2]


def inverse_map(
    mesh, elements: np.ndarray, z: np.ndarray, T: np.ndarray, iters: int = 30
) -> np.ndarray:
    """Local coordinates xi (P, 2) with T^T (x(xi) - z) = 0: the point of
    element ``elements[p]`` whose orthogonal projection on the plane spanned
    by T[p] (P, 3, 2) is the projection of z[p]."""
    etype = mesh.element_type
    xi = np.tile(CENTROIDS[etype], (len(z), 1))
    X = mesh.nodes[mesh.elements[elements]]
    # Newton on each point until its own update is below 1e-14, or stalls
    # below 1e-10 (round-off of coordinates far from the origin); converged
    # points drop out (NaN: a degenerate projection, left to the caller's checks)
    todo = np.arange(len(z))
    last = np.full(len(z), np.inf)
    for _ in range(iters):
        if not todo.size:
            break
        Tp = T[todo]
        x, a, b = element_geometry(mesh, None, xi[todo], X[todo])
        r = np.einsum("pdi,pd->pi", Tp, x - z[todo])
        J00, J01 = np.einsum("pd,pd->p", Tp[:, :, 0], a), np.einsum("pd,pd->p", Tp[:, :, 0], b)
        J10, J11 = np.einsum("pd,pd->p", Tp[:, :, 1], a), np.einsum("pd,pd->p", Tp[:, :, 1], b)
        det = J00 * J11 - J01 * J10
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        dxi = np.stack([(J11 * r[:, 0] - J01 * r[:, 1]) / det,
                        (-J10 * r[:, 0] + J00 * r[:, 1]) / det], axis=1)
        xi[todo] -= dxi
        step = np.abs(dxi).max(axis=1)
        stalled = (step < 1e-10) & (step > 0.25 * last[todo])
        last[todo] = step
        todo = todo[(step >= 1e-14) & ~stalled]
    return xi


__all__ = [
    "ELEMENT_TYPES", "NODES_PER_ELEMENT", "CORNERS", "MAX_NODES", "REFERENCE_NODES", "CENTROIDS",
    "REVERSED", "lagrange_basis", "monomials", "element_geometry", "inverse_map",
]

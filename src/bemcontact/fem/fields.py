"""The fields of a solved finite-element body: its displacement at every
volume node (:class:`VolumeSolution`, the trace solution with the volume
displacement beside it) and its stresses, σ = C : ε(u) from the gradient of
the element's displacement at the point (no smoothing: a stress jumps
across a material boundary as it should).

Stress components (σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz), tension positive,
in the problem's stress units, as for a BEM body.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bem.solution import BodySolution
from ..errors import ConfigError
from .material import elasticity_tensor

#: (i, j) of each stress component in the order of the outputs
COMPONENTS = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))


@dataclass
class VolumeSolution(BodySolution):
    """A finite-element body's solution: the trace fields of
    :class:`~bemcontact.bem.solution.BodySolution` and
    ``volume_displacement`` (n, 3) at its volume nodes
    (:attr:`~bemcontact.fem.mesh.VolumeMesh.node_points`)."""

    volume_displacement: np.ndarray | None = None


def stresses_in(body, u: np.ndarray, cells: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Stresses (p, 6) at ``points`` (p, 3) of the given ``cells`` (p,) for
    the volume displacement ``u`` (n, 3)."""
    v = body.volume
    basis = v.basis()
    x = np.ascontiguousarray(np.asarray(points, dtype=float).T)
    cells = np.asarray(cells, dtype=np.int64)
    local = basis.mapping.invF(x[:, :, None], tind=cells)
    U = np.zeros((basis.N, 3))
    U[v.dof_order] = u
    grad = np.zeros((cells.size, 3, 3))  # grad[p, i, l] = ∂_l u_i
    for k in range(basis.Nbfun):
        g = basis.elem.gbasis(basis.mapping, local, k, tind=cells)[0].grad[:, :, 0]  # (3, p)
        grad += U[basis.element_dofs[k, cells]][:, :, None] * g.T[:, None, :]
    eps = 0.5 * (grad + grad.transpose(0, 2, 1))
    out = np.empty((cells.size, 6))
    region = v.cell_region[cells]
    for r, name in enumerate(v.volume_names):
        at = np.flatnonzero(region == r)
        if at.size:
            sig = np.einsum("ijkl,pkl->pij", elasticity_tensor(body.materials[name]), eps[at])
            out[at] = np.stack([sig[:, i, j] for i, j in COMPONENTS], axis=1)
    return out


def point_stresses(body, u: np.ndarray, points) -> np.ndarray:
    """Stresses (p, 6) at ``points`` (p, 3) inside the body (the cell that
    holds each found by scikit-fem); a point outside is a one-line
    :class:`ConfigError`."""
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    v = body.volume
    try:
        cells = v.skfem.element_finder(mapping=v.basis().mapping)(*P.T)
    except ValueError:
        raise ConfigError(f"{body.name}: a stress point lies outside the body's volume mesh",
                          location={"body": body.name}) from None
    return stresses_in(body, u, cells, P)


def trace_stresses(body, u: np.ndarray) -> np.ndarray:
    """Stresses (N, 6) at the trace's functional nodes, each in the cell
    under the first boundary face that holds it (so a node where regions
    meet gets its own region's cell)."""
    d = body.trace
    k = d.mesh.elements.shape[1]
    owner = np.full(d.n_points, -1)
    f = d.fconn[:, :k]
    faces = np.repeat(np.arange(f.shape[0]), k)
    owner[f.ravel()[::-1]] = faces[::-1]
    return stresses_in(body, u, body.volume.face_cell[owner], d.points)


def cell_stresses(body, u: np.ndarray) -> np.ndarray:
    """Stresses (c, 6) at the centroid of every cell."""
    m = body.volume.skfem
    return stresses_in(body, u, np.arange(m.t.shape[1]), m.p[:, m.t].mean(axis=1).T)


def volume_fields(body, u: np.ndarray):
    """(points, cells, point data, cell data) of the volume mesh for a VTU
    file: the cells on their vertices (a quadratic element drawn by its
    corners), ``displacement`` at the vertices, and per cell the
    ``stress`` (6 components) and ``von_mises`` at its centroid and its
    volume ``region`` (the index into the body's volume region names)."""
    from skfem.io.meshio import to_meshio

    from ..halfspace import von_mises

    m = body.volume.skfem
    mio = to_meshio(m, encode_cell_data=False)
    s = cell_stresses(body, u)
    return (m.p.T, [(c.type, c.data) for c in mio.cells],
            {"displacement": u[: m.p.shape[1]]},
            {"stress": [s], "von_mises": [von_mises(s)],
             "region": [body.volume.cell_region.astype(np.int32)]})


__all__ = ["COMPONENTS", "VolumeSolution", "cell_stresses", "point_stresses", "stresses_in",
           "trace_stresses", "volume_fields"]

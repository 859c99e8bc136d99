"""The trace of a finite-element body: its boundary with functional nodes,
as the contact frame and the boundary conditions see a body
(:class:`~bemcontact.bem.discretization.Discretization`).

A finite-element displacement is continuous, so every functional node sits
on a mesh node (no shifted discontinuous nodes as a BEM body has at edges).
A mesh node where regions meet gets one functional node per region, each
owned by that region's faces: the tractions of two regions stay separate
(a contact surface's and a support's), while both nodes move as the one
volume node under them.  ``volume_node`` maps functional node -> volume
node."""

from __future__ import annotations

import numpy as np

from ..bem.discretization import Discretization, DiscretizationOptions
from ..mesh import SurfaceMesh
from ..mesh.element import MAX_NODES, NODES_PER_ELEMENT, REFERENCE_NODES


def trace_discretization(surface: SurfaceMesh, surface_to_volume: np.ndarray
                         ) -> tuple[Discretization, np.ndarray]:
    """(the trace of ``surface``, volume node of each functional node)."""
    t = surface.element_type
    k = NODES_PER_ELEMENT[t]
    m = surface.n_elements
    region = np.repeat(surface.element_region, k)
    geo = surface.elements.ravel()
    # one functional node per (surface node, region)
    key = geo * (len(surface.region_names) + 1) + region
    uniq, first, fid = np.unique(key, return_index=True, return_inverse=True)
    N = uniq.size
    fconn = np.full((m, MAX_NODES), -1, dtype=np.int64)
    fconn[:, :k] = fid.reshape(m, k)
    fxi = np.zeros((m, MAX_NODES, 2))
    fxi[:, :k] = REFERENCE_NODES[t]
    geometric = geo[first]
    points = surface.nodes[geometric]
    # normals averaged over each functional node's elements
    e_idx = np.repeat(np.arange(m), k)
    _, n_at, _ = surface.map(e_idx, np.tile(REFERENCE_NODES[t], (m, 1)))
    acc = np.zeros((N, 3))
    np.add.at(acc, fid, n_at)
    normals = acc / np.linalg.norm(acc, axis=1)[:, None]
    d = Discretization(surface, fconn, fxi, np.ascontiguousarray(points), normals, geometric,
                       np.full(N, -1, dtype=np.int64), region[first], np.zeros(N),
                       DiscretizationOptions())
    _, _, W, phi = d.surface_quadrature(6)
    w = np.zeros(N)
    np.add.at(w, fconn[:, :k].ravel(), np.einsum("mq,mqa->ma", W, phi)[:, :k].ravel())
    object.__setattr__(d, "weights", w)
    return d, surface_to_volume[geometric]


def trace_mass(d: Discretization):
    """The consistent mass ∫ phi_p phi_q dS of the trace (N, N), sparse:
    the nodal forces of a nodal traction field are ``M t``."""
    import scipy.sparse

    k = d.mesh.elements.shape[1]
    _, _, W, phi = d.surface_quadrature(6)
    phi = phi[:, :, :k]
    Me = np.einsum("mq,mqa,mqb->mab", W, phi, phi)
    f = d.fconn[:, :k]
    rows = np.repeat(f, k, axis=1).ravel()
    cols = np.tile(f, (1, k)).ravel()
    return scipy.sparse.csr_array((Me.ravel(), (rows, cols)), shape=(d.n_points,) * 2)


__all__ = ["trace_discretization", "trace_mass"]

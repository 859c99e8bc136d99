"""BEM operators: the collocation layout and the influence matrices H and G.

The boundary integral equation at a collocation point x,

    c(x) u(x) + PV ∫ T*(x, y) u(y) dS_y = ∫ U*(x, y) t(y) dS_y,

is discretized with the element's Lagrange basis for u and t, and collocated
at the *functional nodes* (:class:`Discretization`).  Row block i of
``H u = G t`` is the equation at functional node i; the free term c and the
principal value of the diagonal block come from rigid-body translation (the
rows of H annihilate a constant displacement).

Edges and corners
-----------------
At a geometric node where the surface normal jumps (an edge or corner of
the body) or where two regions meet (so the boundary conditions may jump),
traction is not single-valued.  Such a node gets one *discontinuous*
functional node per incident element, moved from the node toward the element
centroid in local coordinates (``xi = c + alpha (xi_node - c)``, alpha =
``discontinuity_shift``).  Every other node is an ordinary continuous node
shared by its elements.  So collocation points always lie where the surface is
smooth and t is single valued, and a collocation point never lies on an
element of which it is not a functional node (no hidden singular integrals).
See docs/theory.md for why this was preferred over multiple nodes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._native import core
from ..errors import ConfigError, MeshError
from ..mesh import SurfaceMesh
from ..mesh.element import CENTROIDS, MAX_NODES, NODES_PER_ELEMENT, REFERENCE_NODES, lagrange_basis


@dataclass(frozen=True)
class DiscretizationOptions:
    """How functional (collocation) nodes are laid out.

    Attributes
    ----------
    feature_angle:
        Degrees.  A node whose incident element normals differ by more than
        this is an edge/corner node (discontinuous).
    discontinuity_shift:
        alpha in (0, 1): a discontinuous node sits at ``c + alpha (xi - c)``
        in local coordinates (c the element centroid).
    fully_discontinuous:
        Make every node discontinuous (each element carries its own nodes).
    """

    feature_angle: float = 30.0
    discontinuity_shift: float = 2.0 / 3.0
    fully_discontinuous: bool = False

    def __post_init__(self) -> None:
        if not (0 < self.feature_angle < 180):
            raise ConfigError(
                f"DiscretizationOptions.feature_angle must be in (0, 180) degrees, got "
                f"{self.feature_angle!r}"
            )
        if not (0 < self.discontinuity_shift < 1):
            raise ConfigError(
                f"DiscretizationOptions.discontinuity_shift must be in (0, 1), got "
                f"{self.discontinuity_shift!r}"
            )


@dataclass(frozen=True)
class Discretization:
    """Functional nodes of a mesh (the collocation points and unknowns).

    Attributes (N functional nodes, m elements)
    ----------
    mesh: the surface mesh.
    fconn: (m, 9) int64, functional node of each element node (-1 padded).
    fxi: (m, 9, 2) local coordinates of each element's functional nodes.
    points: (N, 3) collocation points.
    normals: (N, 3) unit outward normals (averaged over elements at shared nodes).
    geometric_node: (N,) the mesh node each functional node belongs to.
    element: (N,) owning element of a discontinuous node, -1 for shared nodes.
    region: (N,) region index (into ``mesh.region_names``).
    weights: (N,) ∫ phi_i dS, so ∫ t dS ≈ Σ weights_i t_i.
    """

    mesh: SurfaceMesh
    fconn: np.ndarray
    fxi: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    geometric_node: np.ndarray
    element: np.ndarray
    region: np.ndarray
    weights: np.ndarray
    options: DiscretizationOptions = field(default_factory=DiscretizationOptions)

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0])

    @property
    def discontinuous(self) -> np.ndarray:
        return self.element >= 0

    def core_arrays(self):
        etype, conn = self.mesh.padded_connectivity()
        return self.mesh.nodes, etype, conn, self.fconn, self.fxi

    def surface_quadrature(self, order: int = 6):
        """Gauss points with functional basis values: (X (m,Q,3), normals,
        weights (m,Q), phi (m,Q,9))."""
        return core().surface_quadrature(*self.core_arrays(), int(order))

    def interpolate(self, values: np.ndarray, order: int = 6):
        """Values of a nodal field (N, k) at the Gauss points: (X, normals,
        weights, field (m, Q, k))."""
        X, Nn, W, phi = self.surface_quadrature(order)
        f = np.where(self.fconn >= 0, self.fconn, 0)
        vals = np.asarray(values)[f]  # (m, 9, k)
        vals = np.where((self.fconn >= 0)[..., None], vals, 0.0)
        return X, Nn, W, np.einsum("mqa,mak->mqk", phi, vals)

    def basis_at(self, elements: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """(P, k) functional basis of ``elements`` at local coordinates ``xi``
        (P, 2): the weights of the element's functional nodes at those points."""
        k = self.mesh.elements.shape[1]
        N, _, _ = lagrange_basis(self.mesh.element_type, self.fxi[elements, :k], xi)
        return N


def discretize(mesh: SurfaceMesh, options: DiscretizationOptions | None = None) -> Discretization:
    """Lay out the functional nodes of ``mesh`` (see the module docstring)."""
    opt = options or DiscretizationOptions()
    t = mesh.element_type
    k = NODES_PER_ELEMENT[t]
    m = mesh.n_elements
    ref = REFERENCE_NODES[t]
    cen = CENTROIDS[t]
    # element normal at each of its nodes
    e_idx = np.repeat(np.arange(m), k)
    _, n_at, _ = mesh.map(e_idx, np.tile(ref, (m, 1)))
    n_at = n_at.reshape(m, k, 3)
    flat_nodes = mesh.elements.ravel()
    flat_n = n_at.reshape(-1, 3)
    flat_reg = np.repeat(mesh.element_region, k)
    nn = mesh.n_nodes
    singular = np.zeros(nn, dtype=bool)
    if opt.fully_discontinuous:
        singular[:] = True
    else:
        # region change
        rmin = np.full(nn, np.iinfo(np.int64).max)
        rmax = np.full(nn, -1)
        np.minimum.at(rmin, flat_nodes, flat_reg)
        np.maximum.at(rmax, flat_nodes, flat_reg)
        singular |= rmin != rmax
        # normal jump: compare each element normal with the node's mean normal
        mean = np.zeros((nn, 3))
        np.add.at(mean, flat_nodes, flat_n)
        norm = np.linalg.norm(mean, axis=1)
        cos_half = math.cos(math.radians(opt.feature_angle) / 2)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean_u = mean / norm[:, None]
        dev = np.einsum("ij,ij->i", flat_n, mean_u[flat_nodes])
        bad = np.zeros(nn, dtype=bool)
        np.logical_or.at(bad, flat_nodes, ~(dev >= cos_half))
        singular |= bad | (norm < 1e-12)
    # numbering: shared nodes in mesh-node order, then discontinuous copies
    shared_nodes = np.flatnonzero(~singular & np.isin(np.arange(nn), flat_nodes))
    fid_of_node = np.full(nn, -1, dtype=np.int64)
    fid_of_node[shared_nodes] = np.arange(shared_nodes.size)
    fconn = np.full((m, MAX_NODES), -1, dtype=np.int64)
    fxi = np.zeros((m, MAX_NODES, 2))
    fxi[:, :k] = ref
    fconn[:, :k] = fid_of_node[mesh.elements]
    disc = fconn[:, :k] < 0
    n_disc = int(disc.sum())
    fconn[:, :k][disc] = shared_nodes.size + np.arange(n_disc)
    a = opt.discontinuity_shift
    shifted = cen + a * (ref - cen)
    fxi[:, :k] = np.where(disc[..., None], shifted[None, :, :], ref[None, :, :])
    N = shared_nodes.size + n_disc
    geo = np.empty(N, dtype=np.int64)
    geo[: shared_nodes.size] = shared_nodes
    geo[shared_nodes.size :] = mesh.elements[disc]
    owner = np.full(N, -1, dtype=np.int64)
    ee, _ = np.nonzero(disc)
    owner[shared_nodes.size :] = ee
    # collocation points and normals
    el = np.empty(N, dtype=np.int64)
    loc = np.empty((N, 2))
    valid = fconn[:, :k]
    el[valid.ravel()] = np.repeat(np.arange(m), k)
    loc[valid.ravel()] = fxi[:, :k].reshape(-1, 2)
    pts, nrm, _ = mesh.map(el, loc)
    # averaged normals at shared nodes
    acc = np.zeros((N, 3))
    np.add.at(acc, valid.ravel(), flat_n)
    shared = owner < 0
    nrm[shared] = acc[shared] / np.linalg.norm(acc[shared], axis=1)[:, None]
    region = mesh.element_region[el]
    cond = core().basis_conditioning(np.full(m, mesh.type_code, dtype=np.int32), fxi)
    if (cond < 1e-10).any():
        i = int(np.argmin(cond))
        raise MeshError(
            f"{mesh._where()}element {i}: its functional nodes are not unisolvent "
            f"(conditioning {cond[i]:.3g}); try DiscretizationOptions(fully_discontinuous=True)"
        )
    d = Discretization(
        mesh, fconn, fxi, np.ascontiguousarray(pts), np.ascontiguousarray(nrm), geo, owner,
        region, np.zeros(N), opt,
    )
    _, _, W, phi = d.surface_quadrature(6)
    w = np.zeros(N)
    contrib = np.einsum("mq,mqa->ma", W, phi)[:, :k]
    np.add.at(w, valid.ravel(), contrib.ravel())
    object.__setattr__(d, "weights", w)
    return d



__all__ = ["DiscretizationOptions", "Discretization", "discretize"]

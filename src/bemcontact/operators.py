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

import contextlib
import math
from dataclasses import dataclass, field

import numpy as np

from .errors import ConfigError, MeshError
from .mesh import CENTROIDS, MAX_NODES, NODES_PER_ELEMENT, REFERENCE_NODES, SurfaceMesh


def _core():
    from . import _core

    return _core


@dataclass(frozen=True)
class QuadratureOptions:
    """Element integration settings.

    Attributes
    ----------
    tolerance:
        Target relative error of each regular element integral; sets the
        Gauss order from the distance/size ratio and the subdivision of nearly
        singular elements.
    min_order, max_order:
        Gauss points per direction of the regular rule; beyond ``max_order``
        the element is subdivided (quadtree) instead.
    singular_order:
        Radial and angular Gauss order of the polar (Duffy) rule on the
        sub-triangles around a collocation point lying on the element.
    max_angle:
        Largest angle (radians) spanned by one polar sub-triangle.
    max_depth:
        Subdivision depth limit for nearly singular integrals.
    """

    tolerance: float = 1e-8
    min_order: int = 2
    max_order: int = 10
    singular_order: int = 12
    max_angle: float = math.pi / 4
    max_depth: int = 14

    def __post_init__(self) -> None:
        if not (0 < self.tolerance < 1):
            raise ConfigError(f"QuadratureOptions.tolerance must be in (0, 1), got {self.tolerance!r}")
        for name in ("min_order", "max_order", "singular_order"):
            v = getattr(self, name)
            if not isinstance(v, int) or not 1 <= v <= 64:
                raise ConfigError(f"QuadratureOptions.{name} must be an integer in 1..64, got {v!r}")
        if self.max_order < self.min_order:
            raise ConfigError("QuadratureOptions.max_order must be >= min_order")
        if not (0 < self.max_angle <= math.pi):
            raise ConfigError(f"QuadratureOptions.max_angle must be in (0, pi], got {self.max_angle!r}")
        if not isinstance(self.max_depth, int) or not 0 <= self.max_depth <= 30:
            raise ConfigError(f"QuadratureOptions.max_depth must be in 0..30, got {self.max_depth!r}")

    def to_core(self):
        q = _core().QuadratureParams()
        q.tolerance = float(self.tolerance)
        q.min_order = int(self.min_order)
        q.max_order = int(self.max_order)
        q.singular_order = int(self.singular_order)
        q.max_angle = float(self.max_angle)
        q.max_depth = int(self.max_depth)
        return q


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
        return _core().surface_quadrature(*self.core_arrays(), int(order))

    def interpolate(self, values: np.ndarray, order: int = 6):
        """Values of a nodal field (N, k) at the Gauss points: (X, normals,
        weights, field (m, Q, k))."""
        X, Nn, W, phi = self.surface_quadrature(order)
        f = np.where(self.fconn >= 0, self.fconn, 0)
        vals = np.asarray(values)[f]  # (m, 9, k)
        vals = np.where((self.fconn >= 0)[..., None], vals, 0.0)
        return X, Nn, W, np.einsum("mqa,mak->mqk", phi, vals)


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
    cond = _core().basis_conditioning(np.full(m, mesh.type_code, dtype=np.int32), fxi)
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


def blas_threads(threads: int | None):
    """A context in which BLAS/LAPACK (OpenBLAS, through NumPy and SciPy)
    uses at most ``threads`` threads, so that ``threads`` bounds the LU and
    the products as it bounds the OpenMP assembly; ``None`` leaves OpenBLAS
    at its own setting (all cores, or ``OMP_NUM_THREADS`` /
    ``OPENBLAS_NUM_THREADS``)."""
    if threads is None:
        return contextlib.nullcontext()
    import threadpoolctl

    return threadpoolctl.threadpool_limits(limits=int(threads), user_api="blas")


def assemble_influence(
    disc: Discretization,
    shear_modulus: float,
    poisson_ratio: float,
    quadrature: QuadratureOptions | None = None,
    threads: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Dense influence matrices (H, G), each (3N, 3N) float64 row-major; dof
    3 i + j is component j of functional node i.  Runs in parallel over rows
    (OpenMP, ``threads``: default all available)."""
    q = (quadrature or QuadratureOptions()).to_core()
    nthreads = _core().max_threads() if threads is None else int(threads)
    if nthreads < 1:
        raise ConfigError(f"threads must be >= 1, got {threads!r}")
    n = 3 * disc.n_points
    H = np.empty((n, n))
    G = np.empty((n, n))
    _core().assemble_influence(
        *disc.core_arrays(), disc.points, float(shear_modulus), float(poisson_ratio), q,
        nthreads, H, G,
    )
    return H, G


def assemble_system(
    disc: Discretization,
    shear_modulus: float,
    poisson_ratio: float,
    known_u: np.ndarray,
    W: np.ndarray | None = None,
    bcols: np.ndarray | None = None,
    quadrature: QuadratureOptions | None = None,
    threads: int | None = None,
    border: int = 0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The mixed system without storing H and G: returns (A, BW, BC).

    A is ((3N + border), (3N + border)) Fortran-ordered (ready for LAPACK
    ``getrf`` in place) with the columns of H at traction-given dofs and of -G
    at displacement-given dofs (``known_u`` (3N,) bool) in its top-left
    block, zeros in the ``border`` rows and columns (for extra unknowns).  B
    (G at traction-given, -H at displacement-given dofs, so b = B values) is
    applied to ``W`` (3N, s) into BW and its columns ``bcols`` are copied into
    BC (3N, len(bcols)).  Row-parallel (OpenMP)."""
    q = (quadrature or QuadratureOptions()).to_core()
    nthreads = _core().max_threads() if threads is None else int(threads)
    if nthreads < 1:
        raise ConfigError(f"threads must be >= 1, got {threads!r}")
    n = 3 * disc.n_points
    ku = np.ascontiguousarray(np.asarray(known_u, dtype=bool), dtype=np.uint8)
    if ku.shape != (n,):
        raise ConfigError(f"known_u must have shape ({n},), got {ku.shape}")
    w = np.zeros((n, 0)) if W is None else np.ascontiguousarray(np.asarray(W, dtype=float).reshape(n, -1))
    cols = np.zeros(0, np.int64) if bcols is None else np.ascontiguousarray(bcols, dtype=np.int64)
    if cols.size and (cols.min() < 0 or cols.max() >= n):
        raise ConfigError(f"bcols must be dof indices in 0..{n - 1}")
    if not isinstance(border, int) or border < 0:
        raise ConfigError(f"border must be an integer >= 0, got {border!r}")
    A = np.zeros((n + border, n + border), order="F")
    BW = np.empty((n, w.shape[1]))
    BC = np.empty((n, cols.size))
    _core().assemble_system(
        *disc.core_arrays(), disc.points, float(shear_modulus), float(poisson_ratio), q, ku, w,
        cols, nthreads, A, BW, BC,
    )
    return A, BW, BC


def element_influence(
    disc: Discretization,
    element: int,
    point,
    shear_modulus: float,
    poisson_ratio: float,
    local: int = -1,
    quadrature: QuadratureOptions | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Influence (H_e, G_e), each (3, 3k), of one element on one point: column
    3 j + c is component c of the element's j-th functional node.  ``local``
    >= 0 says the point is that functional node of the element (polar
    singular rule; the H column block of that node is then left zero, as the
    assembly fills it from rigid-body translation).  Exposed for tests and
    diagnostics; :func:`assemble_influence` does all elements at once."""
    q = (quadrature or QuadratureOptions()).to_core()
    if not 0 <= int(element) < disc.mesh.n_elements:
        raise ConfigError(f"element {element!r} out of range 0..{disc.mesh.n_elements - 1}")
    x = np.ascontiguousarray(np.asarray(point, dtype=float).reshape(1, 3))
    return _core().element_influence(
        *disc.core_arrays(), int(element), x, int(local), float(shear_modulus),
        float(poisson_ratio), q,
    )


__all__ = [
    "QuadratureOptions",
    "DiscretizationOptions",
    "Discretization",
    "discretize",
    "assemble_influence",
    "assemble_system",
    "element_influence",
]

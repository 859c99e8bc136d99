"""BEM influence operators: the matrices H and G of the boundary integral
equation and the mixed system A x = B values, assembled by the compiled core
(see :mod:`bemcontact.bem.discretization` for the collocation layout).

The boundary integral equation at a collocation point x,

    c(x) u(x) + PV ∫ T*(x, y) u(y) dS_y = ∫ U*(x, y) t(y) dS_y,

is discretized with the element's Lagrange basis for u and t, and collocated
at the *functional nodes*.  Row block i of ``H u = G t`` is the equation at
functional node i; the free term c and the principal value of the diagonal
block come from rigid-body translation (the rows of H annihilate a constant
displacement).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._native import core
from ..errors import ConfigError
from .discretization import Discretization


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
        q = core().QuadratureParams()
        q.tolerance = float(self.tolerance)
        q.min_order = int(self.min_order)
        q.max_order = int(self.max_order)
        q.singular_order = int(self.singular_order)
        q.max_angle = float(self.max_angle)
        q.max_depth = int(self.max_depth)
        return q



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
    nthreads = core().max_threads() if threads is None else int(threads)
    if nthreads < 1:
        raise ConfigError(f"threads must be >= 1, got {threads!r}")
    n = 3 * disc.n_points
    H = np.empty((n, n))
    G = np.empty((n, n))
    core().assemble_influence(
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
    nthreads = core().max_threads() if threads is None else int(threads)
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
    core().assemble_system(
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
    return core().element_influence(
        *disc.core_arrays(), int(element), x, int(local), float(shear_modulus),
        float(poisson_ratio), q,
    )




__all__ = ["QuadratureOptions", "assemble_influence", "assemble_system", "element_influence"]

"""Fields inside a body from its boundary solution: Somigliana's identity.

For a point x inside the body (no body forces), with the boundary fields u, t
of a :class:`~bemcontact.bem.solution.BodySolution`,

    u_i(x)    = ∫ U*_ij t_j dS − ∫ T*_ij u_j dS
    σ_ij(x)   = ∫ D_kij t_k dS − ∫ S_kij u_k dS

(Kelvin kernels; r = y − x from the interior point to the boundary point y,
d = r/|r|, n the outward normal at y, G shear modulus, ν Poisson's ratio):

    D_kij = [(1 − 2ν)(δ_ki d_j + δ_kj d_i − δ_ij d_k) + 3 d_i d_j d_k] / (8π(1 − ν)|r|²)
    S_kij = G/(4π(1 − ν)|r|³) { 3 ∂r/∂n [(1 − 2ν) δ_ij d_k + ν(δ_ik d_j + δ_jk d_i)
            − 5 d_i d_j d_k] + 3ν (n_i d_j + n_j d_i) d_k
            + (1 − 2ν)(3 n_k d_i d_j + n_j δ_ik + n_i δ_jk) − (1 − 4ν) n_k δ_ij }

(Brebbia & Domínguez, *Boundary Elements: An Introductory Course*, ch. 5;
U*, T* as in docs/theory.md).  D is the Kelvin stress at x of a unit force at
y; S follows from T* by Hooke's law.  A rigid translation of the boundary
displacement changes neither identity's result (∫ S_kij dS = 0 and
−∫ T*_ij dS = δ_ij over a closed surface), so the displacement of the surface
point nearest to x is subtracted from u before integrating: near the surface
the large, cancelling contributions of the nearby elements then act on a
small difference.

Quadrature: the fields are evaluated in each element's own polynomial
(monomial) form, so the integrals use the element's exact geometry and basis.
Per point and element (or piece of an element), a Gauss rule (tensor
Gauss–Legendre; collapsed Gauss on triangles) of order
``n = ⌈ln(1/tol) / (2 ln ρ)⌉ + 1`` (at least 2), ρ = β + √(β² + 1),
β = 2 d / L (d distance, L diameter), as the boundary assembly does; d is the
distance of the element's bounding sphere, or, where that asks for more than
:data:`MAX_ORDER` points per direction, the smallest distance of the piece's
samples (3 × 3 on a quadrilateral, 7 on a triangle) minus a quarter of its
diameter.  Pieces that would need more than :data:`MAX_ORDER` points per
direction are cut into four, recursively (a quadtree in local coordinates
that refines toward the nearest point).  The integration and the
nearest-point search are compiled (cpp/bemcontact/bem/interior.cpp, OpenMP
over the points); this module holds the API, the checks and the elements'
polynomial form.  Accuracy and cost are measured in docs/theory.md
("Stresses inside a body") and docs/benchmarks.md.
"""

from __future__ import annotations

import numpy as np

from .._native import core
from ..errors import ConfigError
from ..mesh.element import ELEMENT_TYPES, REFERENCE_NODES, monomials
from .material import LinearElastic
from .solution import BodySolution

#: largest Gauss order per direction before a piece of an element is cut in four
MAX_ORDER = 10
#: deepest quadtree level (pieces 2^-MAX_LEVEL of the element)
MAX_LEVEL = 20


def interior_displacements(
    solution: BodySolution, points, material: LinearElastic, *, tolerance: float = 1e-6,
    min_depth: float = 0.005,
) -> np.ndarray:
    """Displacement (n, 3) at interior ``points`` (n, 3) of the body whose
    boundary solution is ``solution`` (global components, the units of the
    solution's displacements).

    Parameters
    ----------
    solution: a :class:`BodySolution` covering the body's whole boundary.
    points: (n, 3) finite points strictly inside the body.
    material: the body's :class:`LinearElastic` material.
    tolerance: relative accuracy asked of each element integral.
    min_depth: a point closer to the surface than ``min_depth`` times the size
        of the nearest element raises :class:`ConfigError` (there, use the
        boundary solution itself).
    """
    return _Evaluator(solution, material, tolerance).run(points, min_depth, stresses=False)


def interior_stresses(
    solution: BodySolution, points, material: LinearElastic, *, tolerance: float = 1e-6,
    min_depth: float = 0.005,
) -> np.ndarray:
    """Cauchy stress (n, 6) = (σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz) at interior
    ``points`` (n, 3), tension positive, in the units of the solution's
    tractions.  Arguments as :func:`interior_displacements`; the scalar
    measures (von Mises, Tresca, principal stresses) are in
    :mod:`bemcontact.halfspace.measure`."""
    return _Evaluator(solution, material, tolerance).run(points, min_depth, stresses=True)


# ------------------------------------------------------------------ evaluator

class _Evaluator:
    """The boundary solution in per-element monomial form, handed to the
    compiled evaluator (``_core.InteriorEvaluator``)."""

    def __init__(self, solution: BodySolution, material: LinearElastic, tol: float) -> None:
        if not isinstance(solution, BodySolution):
            raise ConfigError(f"solution must be a BodySolution, got {type(solution).__name__}")
        if not isinstance(material, LinearElastic):
            raise ConfigError(f"material must be a LinearElastic, got {type(material).__name__}")
        if not solution.whole_boundary:
            raise ConfigError("interior fields need the body's whole boundary; this solution "
                              "covers only part of it")
        if not (isinstance(tol, (int, float)) and 1e-14 <= tol < 1):
            raise ConfigError(f"tolerance must lie in [1e-14, 1), got {tol!r}")
        disc = solution.discretization
        mesh = disc.mesh
        etype = mesh.element_type
        k = mesh.elements.shape[1]
        m = mesh.n_elements
        # geometry and fields as polynomials: value(xi) = M(xi) @ coef[e]
        Mref = monomials(etype, REFERENCE_NODES[etype])[0]
        geo = np.einsum("ab,mbc->mac", np.linalg.inv(Mref), mesh.nodes[mesh.elements])
        V = monomials(etype, disc.fxi[:, :k].reshape(-1, 2))[0].reshape(m, k, k)
        f = disc.fconn[:, :k]
        vals = np.concatenate([solution.displacement[f], solution.traction[f]], axis=2)
        coef = np.linalg.solve(V, vals)  # (m, k, 6)
        self.core = core().InteriorEvaluator(
            ELEMENT_TYPES.index(etype), np.ascontiguousarray(geo), np.ascontiguousarray(coef),
            material.shear_modulus, material.poisson_ratio, float(tol), MAX_ORDER, MAX_LEVEL)
        self.threads = core().max_threads()

    def run(self, points, min_depth, stresses):
        X = _checked_points(points)
        if not (isinstance(min_depth, (int, float)) and 0 < min_depth < 1):
            raise ConfigError(f"min_depth must lie in (0, 1), got {min_depth!r}")
        n = len(X)
        dist, e, xi, cos = np.empty(n), np.empty(n, dtype=np.int64), np.empty((n, 2)), np.empty(n)
        self.core.nearest(X, self.threads, dist, e, xi, cos)
        h = self.core.sizes[e]
        outside = (cos > 0) & (dist > 1e-12 * h)
        bad = np.flatnonzero(outside | (dist < min_depth * h))
        if bad.size:
            i = int(bad[0])
            where = f"point {i} at ({', '.join(f'{c:.6g}' for c in X[i])})"
            if outside[i]:
                raise ConfigError(f"{where} lies outside the body, {dist[i]:.3g} from its "
                                  "surface", location={"point": i})
            raise ConfigError(
                f"{where} is {dist[i]:.3g} from the surface, closer than min_depth "
                f"{min_depth:g} × the local element size {h[i]:.3g}; use the boundary "
                "solution there", location={"point": i})
        out = np.empty((n, 6 if stresses else 3))
        self.core.integrate(X, e, xi, stresses, self.threads, out)
        return out


def _checked_points(points) -> np.ndarray:
    try:
        X = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise ConfigError("points must be an (n, 3) array of numbers") from None
    if X.ndim != 2 or X.shape[1] != 3:
        raise ConfigError(f"points must be an (n, 3) array, got shape {X.shape}")
    if X.shape[0] == 0:
        raise ConfigError("points must be an (n, 3) array with n >= 1, got no points")
    bad = np.flatnonzero(~np.isfinite(X).all(axis=1))
    if bad.size:
        i = int(bad[0])
        raise ConfigError(f"point {i} is not finite: {X[i].tolist()}", location={"point": i})
    return np.ascontiguousarray(X)


__all__ = ["interior_displacements", "interior_stresses", "MAX_ORDER", "MAX_LEVEL"]

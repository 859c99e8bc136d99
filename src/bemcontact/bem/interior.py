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
``n = ⌈ln(1/tol) / (2 ln ρ)⌉ + 1``, ρ = β + √(β² + 1), β = 2 d / L (d distance,
L diameter), as the boundary assembly does.  Pieces that would need more
than :data:`MAX_ORDER` points per direction are cut into four, recursively (a
quadtree in local coordinates that refines toward the nearest point).  Accuracy and cost are measured in
docs/theory.md ("Stresses inside a body").
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ConfigError
from ..mesh.element import REFERENCE_NODES, monomials
from .material import LinearElastic
from .solution import BodySolution

#: largest Gauss order per direction before a piece of an element is cut in four
MAX_ORDER = 10
#: deepest quadtree level (pieces 2^-MAX_LEVEL of the element)
MAX_LEVEL = 20
#: orders added to the Gauss estimate, and the smallest order used
_EXTRA, _MIN_ORDER = 1, 2
#: a piece's distance is its sampled distance minus this fraction of its diameter
#: (3 x 3 samples of a quadrilateral leave no point farther than 1/4 of the
#: diameter from a sample; the 7 samples of a triangle, 0.16)
_SAFETY = 0.25
#: quadrature rows (point × Gauss point) evaluated at once: bounds the memory
_ROWS = 1 << 17
#: Voigt order of the (n, 6) stress arrays: (xx, yy, zz, xy, yz, xz)
_I = np.array([0, 1, 2, 0, 1, 0])
_J = np.array([0, 1, 2, 1, 2, 2])
_DIAG = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])


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


# ------------------------------------------------------------------ reference rules

def _gauss(n: int):
    return np.polynomial.legendre.leggauss(n)


def _rule(triangle: bool, n: int):
    """Reference rule of order n: points (Q, 2), weights (Q,)."""
    g, w = _gauss(n)
    u, v = np.meshgrid(g, g, indexing="ij")
    wu, wv = np.meshgrid(w, w, indexing="ij")
    u, v, ww = u.ravel(), v.ravel(), (wu * wv).ravel()
    if not triangle:
        return np.stack([u, v], axis=1), ww
    # collapsed (Duffy) Gauss on the triangle xi, eta >= 0, xi + eta <= 1
    xi = (1 + u) / 2
    eta = (1 - u) * (1 + v) / 4
    return np.stack([xi, eta], axis=1), ww * (1 - u) / 8


def _samples(triangle: bool) -> np.ndarray:
    """Points of a reference cell at which distance and size are sampled."""
    if triangle:
        return np.array([[0, 0], [1, 0], [0, 1], [0.5, 0], [0.5, 0.5], [0, 0.5], [1 / 3, 1 / 3]])
    g = np.array([-1.0, 0.0, 1.0])
    u, v = np.meshgrid(g, g, indexing="ij")
    return np.stack([u.ravel(), v.ravel()], axis=1)


def _children(triangle: bool):
    """The four children of the reference cell as affine maps xi = c + B xi_ref."""
    if triangle:
        half = 0.5 * np.eye(2)
        return [(np.array([0.0, 0.0]), half), (np.array([0.5, 0.0]), half),
                (np.array([0.0, 0.5]), half), (np.array([0.5, 0.5]), -half)]
    return [(np.array([sx, sy]) * 0.5, 0.5 * np.eye(2)) for sx in (-1, 1) for sy in (-1, 1)]


def _order(d: np.ndarray, size: np.ndarray, tol: float) -> np.ndarray:
    """Gauss order per direction for a piece of diameter ``size`` at distance
    ``d`` (a large number where d <= 0: the piece must be cut)."""
    beta = 2.0 * np.maximum(d, 0.0) / size
    rho = beta + np.sqrt(beta * beta + 1.0)
    with np.errstate(divide="ignore"):
        n = np.ceil(math.log(1.0 / tol) / (2.0 * np.log(rho))) + _EXTRA
    return np.where(d > 0, np.maximum(n, _MIN_ORDER), 10 * MAX_ORDER).astype(np.int64)


# ------------------------------------------------------------------ kernels

def _accumulate(out, rows, x, y, nJw, Jw, u, t, G, nu, stresses):
    """Add the integrand rows (Gauss points y with n J w, J w, fields u, t)
    to ``out[rows]``: displacement (3) or stress (6) contributions of the
    interior points x (rows' own points, (R, 3))."""
    r = y - x
    R2 = np.einsum("ij,ij->i", r, r)
    R = np.sqrt(R2)
    d = r / R[:, None]
    du = np.einsum("ij,ij->i", d, u)
    dt = np.einsum("ij,ij->i", d, t)
    dn = np.einsum("ij,ij->i", d, nJw)   # ∂r/∂n · J w
    nu_ = np.einsum("ij,ij->i", nJw, u)  # (n · u) J w
    if not stresses:
        cu = Jw / (16.0 * math.pi * G * (1.0 - nu) * R)
        val = cu[:, None] * ((3.0 - 4.0 * nu) * t + d * dt[:, None])
        ct = 1.0 / (8.0 * math.pi * (1.0 - nu) * R2)
        Tu = dn[:, None] * ((1.0 - 2.0 * nu) * u + 3.0 * d * du[:, None]) \
            - (1.0 - 2.0 * nu) * (d * nu_[:, None] - nJw * du[:, None])
        val += ct[:, None] * Tu  # − T* u, T* = −(…)/(8π(1−ν)r²)
    else:
        di, dj = d[:, _I], d[:, _J]
        dd = di * dj
        cd = Jw / (8.0 * math.pi * (1.0 - nu) * R2)
        Dt = (1.0 - 2.0 * nu) * (t[:, _I] * dj + t[:, _J] * di - _DIAG * dt[:, None]) \
            + 3.0 * dd * dt[:, None]
        cs = G / (4.0 * math.pi * (1.0 - nu) * R2 * R)
        Su = 3.0 * dn[:, None] * ((1.0 - 2.0 * nu) * _DIAG * du[:, None]
                                  + nu * (u[:, _I] * dj + u[:, _J] * di) - 5.0 * dd * du[:, None]) \
            + 3.0 * nu * du[:, None] * (nJw[:, _I] * dj + nJw[:, _J] * di) \
            + (1.0 - 2.0 * nu) * (3.0 * nu_[:, None] * dd + nJw[:, _J] * u[:, _I]
                                  + nJw[:, _I] * u[:, _J]) \
            - (1.0 - 4.0 * nu) * nu_[:, None] * _DIAG
        val = cd[:, None] * Dt - cs[:, None] * Su
    for c in range(val.shape[1]):
        out[:, c] += np.bincount(rows, weights=val[:, c], minlength=out.shape[0])


# ------------------------------------------------------------------ evaluator

class _Evaluator:
    """The boundary solution in per-element monomial form, and the quadrature."""

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
        self.etype = mesh.element_type
        self.triangle = self.etype.startswith("tri")
        self.tol = float(tol)
        self.G, self.nu = material.shear_modulus, material.poisson_ratio
        k = mesh.elements.shape[1]
        m = mesh.n_elements
        # geometry and fields as polynomials: value(xi) = M(xi) @ coef[e]
        Mref = monomials(self.etype, REFERENCE_NODES[self.etype])[0]
        self.geo = np.einsum("ab,mbc->mac", np.linalg.inv(Mref), mesh.nodes[mesh.elements])
        V = monomials(self.etype, disc.fxi[:, :k].reshape(-1, 2))[0].reshape(m, k, k)
        f = disc.fconn[:, :k]
        vals = np.concatenate([solution.displacement[f], solution.traction[f]], axis=2)
        self.coef = np.linalg.solve(V, vals)  # (m, k, 6)
        # per element: samples, centre, radius, diameter
        s = _samples(self.triangle)
        ys = self._map(np.repeat(np.arange(m), len(s)), np.tile(s, (m, 1)))[0].reshape(m, len(s), 3)
        self.centre = ys.mean(axis=1)
        self.radius = 1.05 * np.linalg.norm(ys - self.centre[:, None], axis=2).max(axis=1)
        self.size = np.linalg.norm(ys[:, :, None] - ys[:, None], axis=3).max(axis=(1, 2))
        self.sample_y = ys
        self.cache: dict[int, tuple] = {}

    # geometry ---------------------------------------------------------------
    def _map(self, e, xi, fields=False):
        """Positions (P, 3), n J (P, 3) and, with ``fields``, u and t (P, 6)."""
        M, Mx, My = monomials(self.etype, xi)
        g = self.geo[e]
        y = np.einsum("pk,pkc->pc", M, g)
        nJ = np.cross(np.einsum("pk,pkc->pc", Mx, g), np.einsum("pk,pkc->pc", My, g))
        if not fields:
            return y, nJ, None
        return y, nJ, np.einsum("pk,pkc->pc", M, self.coef[e])

    def _element_rule(self, n: int):
        """Order-n rule on every element (cached): y, n J w, J w, fields."""
        if n not in self.cache:
            xi, w = _rule(self.triangle, n)
            m, Q = self.geo.shape[0], len(w)
            y, nJ, F = self._map(np.repeat(np.arange(m), Q), np.tile(xi, (m, 1)), fields=True)
            nJw = nJ * np.tile(w, m)[:, None]
            self.cache[n] = (y.reshape(m, Q, 3), nJw.reshape(m, Q, 3),
                             np.linalg.norm(nJw, axis=1).reshape(m, Q), F.reshape(m, Q, 6))
        return self.cache[n]

    # nearest point ----------------------------------------------------------
    def _clamp(self, xi):
        if not self.triangle:
            return np.clip(xi, -1.0, 1.0)
        xi = np.maximum(xi, 0.0)
        over = xi.sum(axis=1) > 1.0
        if over.any():
            a = np.clip((xi[over, 0] - xi[over, 1] + 1.0) / 2.0, 0.0, 1.0)
            xi[over] = np.stack([a, 1.0 - a], axis=1)
        return xi

    def nearest(self, X):
        """Per point: distance to the surface, the nearest element and local
        coordinates, and the cosine of (x − y) with that element's normal."""
        P = len(X)
        lb = np.linalg.norm(X[:, None] - self.centre[None], axis=2) - self.radius[None]
        ds = np.linalg.norm(X[:, None, None] - self.sample_y[None], axis=3)  # (P, m, S)
        ub = ds.min(axis=(1, 2))
        pp, ee = np.nonzero(lb <= ub[:, None] * (1 + 1e-9))
        s = _samples(self.triangle)
        xi = s[np.argmin(ds[pp, ee], axis=1)].copy()
        g = self.geo[ee]
        for _ in range(12):
            M, Mx, My = monomials(self.etype, xi)
            y = np.einsum("pk,pkc->pc", M, g)
            A = np.stack([np.einsum("pk,pkc->pc", Mx, g), np.einsum("pk,pkc->pc", My, g)], axis=2)
            AtA = np.einsum("pci,pcj->pij", A, A)
            Atg = np.einsum("pci,pc->pi", A, y - X[pp])
            xi = self._clamp(xi - np.linalg.solve(AtA, Atg[..., None])[..., 0])
        y, nJ, _ = self._map(ee, xi)
        r = X[pp] - y
        dist = np.linalg.norm(r, axis=1)
        cos = np.einsum("ij,ij->i", r, nJ) / np.maximum(
            dist * np.linalg.norm(nJ, axis=1), 1e-300)
        dmin = np.full(P, np.inf)
        np.minimum.at(dmin, pp, dist)
        tie = dist <= dmin[pp] * (1 + 1e-6) + 1e-12 * self.size[ee]
        score = np.where(tie, np.abs(cos), -1.0)
        order = np.lexsort((-score, pp))
        first = order[np.r_[True, pp[order][1:] != pp[order][:-1]]]
        return dist[first], ee[first], xi[first], cos[first]

    # integration -----------------------------------------------------------
    def run(self, points, min_depth, stresses):
        X = _checked_points(points)
        if not (isinstance(min_depth, (int, float)) and 0 < min_depth < 1):
            raise ConfigError(f"min_depth must lie in (0, 1), got {min_depth!r}")
        n_out = 6 if stresses else 3
        out = np.zeros((len(X), n_out))
        m = self.geo.shape[0]
        chunk = max(1, min(len(X), 4096 // max(1, m // 64 + 1)))
        for a in range(0, len(X), chunk):
            Xc = X[a:a + chunk]
            dist, e, xi, cos = self.nearest(Xc)
            h = self.size[e]
            for i in range(len(Xc)):
                where = f"point {a + i} at ({', '.join(f'{c:.6g}' for c in Xc[i])})"
                if cos[i] > 0 and dist[i] > 1e-12 * h[i]:
                    raise ConfigError(f"{where} lies outside the body, {dist[i]:.3g} from its "
                                      "surface", location={"point": a + i})
                if dist[i] < min_depth * h[i]:
                    raise ConfigError(
                        f"{where} is {dist[i]:.3g} from the surface, closer than min_depth "
                        f"{min_depth:g} × the local element size {h[i]:.3g}; use the boundary "
                        "solution there", location={"point": a + i})
            uref = np.einsum("pk,pkc->pc", monomials(self.etype, xi)[0], self.coef[e, :, :3])
            res = np.zeros((len(Xc), n_out))
            self._integrate(Xc, uref, res, stresses)
            out[a:a + chunk] = res if stresses else res + uref
        return out

    def _integrate(self, X, uref, out, stresses):
        lb = np.maximum(np.linalg.norm(X[:, None] - self.centre[None], axis=2) - self.radius, 0.0)
        order = _order(lb, self.size[None, :], self.tol)
        pp, ee = np.nonzero(order > MAX_ORDER)  # the sampled distance, as in _near
        d = np.linalg.norm(self.sample_y[ee] - X[pp][:, None], axis=2).min(axis=1)
        order[pp, ee] = _order(d - _SAFETY * self.size[ee], self.size[ee], self.tol)
        far = order <= MAX_ORDER
        for n in np.unique(order[far]):
            pp, ee = np.nonzero(order == n)
            y, nJw, Jw, F = self._element_rule(int(n))
            Q = y.shape[1]
            step = max(1, _ROWS // Q)
            for b in range(0, len(pp), step):
                p, e = pp[b:b + step], ee[b:b + step]
                rows = np.repeat(p, Q)
                Fe = F[e].reshape(-1, 6)
                _accumulate(out, rows, X[rows], y[e].reshape(-1, 3), nJw[e].reshape(-1, 3),
                            Jw[e].ravel(), Fe[:, :3] - uref[rows], Fe[:, 3:], self.G, self.nu,
                            stresses)
        pp, ee = np.nonzero(~far)
        self._near(X, uref, out, stresses, pp, ee)

    def _near(self, X, uref, out, stresses, pp, ee):
        """Quadtree over the near (point, element) pairs: pieces are affine
        images c + B xi_ref of the reference cell."""
        tri = self.triangle
        s = _samples(tri)
        c = np.zeros((len(pp), 2))
        B = np.tile(np.eye(2), (len(pp), 1, 1))
        accepted: dict[int, list] = {}
        for level in range(MAX_LEVEL + 1):
            if not len(pp):
                break
            xs = c[:, None] + np.einsum("cij,sj->csi", B, s)  # (C, S, 2)
            ys = self._map(np.repeat(ee, len(s)), xs.reshape(-1, 2))[0].reshape(len(pp), len(s), 3)
            size = np.linalg.norm(ys[:, :, None] - ys[:, None], axis=3).max(axis=(1, 2))
            d = np.linalg.norm(ys - X[pp][:, None], axis=2).min(axis=1) - _SAFETY * size
            n = _order(d, size, self.tol)
            ok = (n <= MAX_ORDER) | (level == MAX_LEVEL)
            n = np.minimum(n, MAX_ORDER)
            for k in np.unique(n[ok]):
                sel = ok & (n == k)
                accepted.setdefault(int(k), []).append((pp[sel], ee[sel], c[sel], B[sel]))
            cut = ~ok
            pp, ee, c, B = pp[cut], ee[cut], c[cut], B[cut]
            kids = _children(tri)
            c = np.concatenate([c + np.einsum("cij,j->ci", B, ck) for ck, _ in kids])
            B = np.concatenate([np.einsum("cij,jk->cik", B, Bk) for _, Bk in kids])
            pp, ee = np.tile(pp, len(kids)), np.tile(ee, len(kids))
        for k, parts in accepted.items():
            xi_ref, w_ref = _rule(tri, k)
            Q = len(w_ref)
            p_all = np.concatenate([q[0] for q in parts])
            e_all = np.concatenate([q[1] for q in parts])
            c_all = np.concatenate([q[2] for q in parts])
            B_all = np.concatenate([q[3] for q in parts])
            step = max(1, _ROWS // Q)
            for b in range(0, len(p_all), step):
                p, e = p_all[b:b + step], e_all[b:b + step]
                cb, Bb = c_all[b:b + step], B_all[b:b + step]
                xi = (cb[:, None] + np.einsum("cij,qj->cqi", Bb, xi_ref)).reshape(-1, 2)
                w = (np.abs(np.linalg.det(Bb))[:, None] * w_ref[None]).ravel()
                rows = np.repeat(p, Q)
                y, nJ, F = self._map(np.repeat(e, Q), xi, fields=True)
                nJw = nJ * w[:, None]
                _accumulate(out, rows, X[rows], y, nJw, np.linalg.norm(nJw, axis=1),
                            F[:, :3] - uref[rows], F[:, 3:], self.G, self.nu, stresses)


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

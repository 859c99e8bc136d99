"""The stress tensor on a body's surface from its boundary solution.

At a surface point with outward unit normal n and unit tangents e1, e2
(e1 along the element's first local direction, e2 = n × e1), three stress
components are the traction t = σ n itself, and the in-plane strains come
from the tangential derivatives of the displacement ("traction recovery"; no
integral is needed):

    σ_nn = t·n,  σ_1n = t·e1,  σ_2n = t·e2
    ε_ab = ½ (e_a·H e_b + e_b·H e_a),  a, b = 1, 2,
    H = u_ξ ⊗ a^ξ + u_η ⊗ a^η  (the surface gradient of u; a^ξ, a^η the
        dual basis of the tangent vectors g_ξ = ∂x/∂ξ, g_η = ∂x/∂η),

and Hooke's law with the normal strain eliminated through σ_nn
(λ, G the Lamé constants):

    ε_nn = (σ_nn − λ (ε_11 + ε_22)) / (λ + 2G)
    σ_aa = λ (ε_11 + ε_22 + ε_nn) + 2G ε_aa,   σ_12 = 2G ε_12.

The tensor is formed in (e1, e2, n) and turned to global components.  Each
element evaluates it at its own functional nodes with its interpolants (the
displacement's derivative is the element's, which is one order lower than the
displacement: constant on a linear element), and a functional node shared by
several elements takes their mean.
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError
from ..mesh.element import element_geometry, lagrange_basis
from .material import LinearElastic
from .solution import BodySolution


def surface_stresses(solution: BodySolution, material: LinearElastic) -> np.ndarray:
    """The Cauchy stress (N, 6) = (σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz), global
    components, tension positive, at the N functional nodes of ``solution``
    (module docstring), in the units of its tractions."""
    if not isinstance(solution, BodySolution):
        raise ConfigError(f"solution must be a BodySolution, got {type(solution).__name__}")
    if not isinstance(material, LinearElastic):
        raise ConfigError(f"material must be a LinearElastic, got {type(material).__name__}")
    disc = solution.discretization
    mesh = disc.mesh
    et = mesh.element_type
    m, k = mesh.elements.shape
    e = np.repeat(np.arange(m), k)
    xi = disc.fxi[:, :k].reshape(-1, 2)
    fn = disc.fconn[:, :k].reshape(-1)
    _, Nx, Ny = lagrange_basis(et, disc.fxi[e, :k], xi)
    _, gx, gy = element_geometry(mesh, e, xi)
    U = solution.displacement[disc.fconn[e, :k]]
    ux, uy = np.einsum("pk,pkc->pc", Nx, U), np.einsum("pk,pkc->pc", Ny, U)
    n = np.cross(gx, gy)
    n /= np.linalg.norm(n, axis=1)[:, None]
    e1 = gx / np.linalg.norm(gx, axis=1)[:, None]
    e2 = np.cross(n, e1)
    # dual basis: a^α = Σ_β (g^-1)_αβ g_β with the metric g_αβ = g_α · g_β
    g11, g12, g22 = (gx * gx).sum(1), (gx * gy).sum(1), (gy * gy).sum(1)
    det = g11 * g22 - g12 * g12
    ax = (g22[:, None] * gx - g12[:, None] * gy) / det[:, None]
    ay = (g11[:, None] * gy - g12[:, None] * gx) / det[:, None]

    def strain(a, b):  # e_a · H e_b with H = u_ξ ⊗ a^ξ + u_η ⊗ a^η
        return ((a * ux).sum(1) * (ax * b).sum(1) + (a * uy).sum(1) * (ay * b).sum(1))

    e11, e22 = strain(e1, e1), strain(e2, e2)
    e12 = 0.5 * (strain(e1, e2) + strain(e2, e1))
    G, nu = material.shear_modulus, material.poisson_ratio
    lam = 2.0 * G * nu / (1.0 - 2.0 * nu)
    t = solution.traction[fn]
    snn, s1n, s2n = (t * n).sum(1), (t * e1).sum(1), (t * e2).sum(1)
    enn = (snn - lam * (e11 + e22)) / (lam + 2.0 * G)
    tr = lam * (e11 + e22 + enn)
    s11, s22, s12 = tr + 2.0 * G * e11, tr + 2.0 * G * e22, 2.0 * G * e12
    B = np.stack([e1, e2, n], axis=1)  # rows: the local axes
    L = np.stack([np.stack([s11, s12, s1n], -1), np.stack([s12, s22, s2n], -1),
                  np.stack([s1n, s2n, snn], -1)], -2)
    T = np.einsum("pai,pab,pbj->pij", B, L, B)
    per = np.stack([T[:, 0, 0], T[:, 1, 1], T[:, 2, 2], T[:, 0, 1], T[:, 1, 2], T[:, 0, 2]], 1)
    out = np.zeros((disc.n_points, 6))
    np.add.at(out, fn, per)
    count = np.bincount(fn, minlength=disc.n_points)
    return out / np.maximum(count, 1)[:, None]


__all__ = ["surface_stresses"]

"""Kelvin's solution: a point force in an infinite isotropic elastic solid.

For a force F applied at the source point s, with r = x - s, |r| = r and
unit vector d = r / r (G shear modulus, nu Poisson's ratio):

    u_i = F_k [ (3 - 4 nu) delta_ik + d_i d_k ] / (16 pi G (1 - nu) r)

    sigma_ij = -F_k / (8 pi (1 - nu) r^2)
               [ (1 - 2 nu)(delta_ik d_j + delta_jk d_i - delta_ij d_k) + 3 d_i d_j d_k ]

(e.g. Brebbia & Dominguez, Boundary Elements: An Introductory Course, ch. 5.)
These are the BEM kernels U* and, contracted with a normal, T*.
"""

from __future__ import annotations

import numpy as np


def _geometry(points, source):
    x = np.atleast_2d(np.asarray(points, dtype=float))
    r = x - np.asarray(source, dtype=float)[None, :]
    rn = np.linalg.norm(r, axis=1)
    return r / rn[:, None], rn


def kelvin_displacement(points, source, force, shear_modulus, poisson_ratio):
    """Displacement (n, 3) at ``points`` (n, 3) due to ``force`` (3,) at ``source`` (3,)."""
    d, r = _geometry(points, source)
    F = np.asarray(force, dtype=float)
    nu = poisson_ratio
    c = 1.0 / (16.0 * np.pi * shear_modulus * (1.0 - nu) * r)
    return c[:, None] * ((3.0 - 4.0 * nu) * F[None, :] + d * (d @ F)[:, None])


def kelvin_stress(points, source, force, poisson_ratio):
    """Stress tensor (n, 3, 3) at ``points`` due to ``force`` at ``source``."""
    d, r = _geometry(points, source)
    F = np.asarray(force, dtype=float)
    nu = poisson_ratio
    dF = d @ F
    c = -1.0 / (8.0 * np.pi * (1.0 - nu) * r**2)
    eye = np.eye(3)[None]
    s = (1.0 - 2.0 * nu) * (
        F[None, :, None] * d[:, None, :] + d[:, :, None] * F[None, None, :] - eye * dF[:, None, None]
    ) + 3.0 * d[:, :, None] * d[:, None, :] * dF[:, None, None]
    return c[:, None, None] * s


def kelvin_traction(points, normals, source, force, poisson_ratio):
    """Traction sigma n (n, 3) on surfaces with unit normals ``normals`` (n, 3)."""
    s = kelvin_stress(points, source, force, poisson_ratio)
    return np.einsum("nij,nj->ni", s, np.asarray(normals, dtype=float))

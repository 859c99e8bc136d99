"""Lamé's solution: a thick-walled hollow sphere under internal pressure.

Inner radius a, outer radius b, internal pressure p (> 0 pushes the inner
wall outward), outer surface traction free.  Radial displacement

    u_r(r) = p a^3 / (E (b^3 - a^3)) [ (1 - 2 nu) r + (1 + nu) b^3 / (2 r^2) ]

and stresses sigma_rr = p a^3 (b^3 - r^3) / (r^3 (a^3 - b^3)),
sigma_tt = p a^3 (b^3 + 2 r^3) / (2 r^3 (b^3 - a^3))
(Timoshenko & Goodier, Theory of Elasticity, §141).
"""

from __future__ import annotations

import numpy as np


def lame_sphere_radial_displacement(r, inner_radius, outer_radius, pressure, youngs_modulus,
                                    poisson_ratio):
    """u_r at radius r (array-like)."""
    a, b, p, E, nu = inner_radius, outer_radius, pressure, youngs_modulus, poisson_ratio
    r = np.asarray(r, dtype=float)
    return p * a**3 / (E * (b**3 - a**3)) * ((1 - 2 * nu) * r + (1 + nu) * b**3 / (2 * r**2))


def lame_sphere_stress(r, inner_radius, outer_radius, pressure):
    """(sigma_rr, sigma_tt) at radius r."""
    a, b, p = inner_radius, outer_radius, pressure
    r = np.asarray(r, dtype=float)
    srr = p * a**3 * (b**3 - r**3) / (r**3 * (a**3 - b**3))
    stt = p * a**3 * (b**3 + 2 * r**3) / (2 * r**3 * (b**3 - a**3))
    return srr, stt

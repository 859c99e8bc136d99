"""Elastic materials a finite-element body may have besides the isotropic
:class:`~bemcontact.bem.material.LinearElastic`: an anisotropic material
given by its 6 × 6 stiffness in its own axes (:class:`AnisotropicElastic`),
of which an orthotropic material (:meth:`AnisotropicElastic.orthotropic`,
from engineering constants) is the common case.

Conventions.  Voigt order (11, 22, 33, 23, 13, 12) with engineering shear
strains (γ_23 = 2 ε_23): σ = C ε in the material axes.  The material axes
in global coordinates are ``axis1`` and ``axis2`` (made orthonormal, axis 2
first projected off axis 1; axis 3 = axis 1 × axis 2).  Poisson's ratio
ν_ij is the contraction along j under a stress along i: ν_ij / E_i =
ν_ji / E_j.  Stress units are the problem's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bem.material import LinearElastic
from ..errors import MaterialError

#: Voigt index of each tensor index pair (i, j).
VOIGT = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]])


def _unit(name: str, v) -> np.ndarray:
    a = np.asarray(v, dtype=float)
    if a.shape != (3,) or not np.isfinite(a).all() or not np.linalg.norm(a) > 0:
        raise MaterialError(f"{name} must be 3 finite numbers, not all zero, got {v!r}")
    return a / np.linalg.norm(a)


@dataclass(frozen=True)
class AnisotropicElastic:
    """A linear elastic material of any symmetry (module docstring).

    Parameters
    ----------
    stiffness:
        The 6 × 6 stiffness in the material axes (Voigt order, engineering
        shear strains; stress units), symmetric positive definite.
    axis1, axis2:
        The material's axes 1 and 2 in global coordinates (axis 3 = 1 × 2).
    """

    stiffness: tuple
    axis1: tuple = (1.0, 0.0, 0.0)
    axis2: tuple = (0.0, 1.0, 0.0)

    def __post_init__(self) -> None:
        C = np.asarray(self.stiffness, dtype=float)
        if C.shape != (6, 6) or not np.isfinite(C).all():
            raise MaterialError(f"stiffness must be 6 x 6 finite numbers, got shape {C.shape}")
        if not np.allclose(C, C.T, rtol=1e-9, atol=1e-12 * np.abs(C).max()):
            i, j = np.unravel_index(int(np.argmax(np.abs(C - C.T))), C.shape)
            raise MaterialError(f"stiffness must be symmetric: C[{i}][{j}] = {C[i, j]:g} but "
                                f"C[{j}][{i}] = {C[j, i]:g}")
        C = 0.5 * (C + C.T)
        w = np.linalg.eigvalsh(C)
        if not w[0] > 1e-12 * w[-1]:
            raise MaterialError(f"stiffness is not positive definite (smallest eigenvalue "
                                f"{w[0]:.4g}, largest {w[-1]:.4g}): some strain would store no "
                                "or negative energy")
        a1 = _unit("axis1", self.axis1)
        a2 = np.asarray(_unit("axis2", self.axis2))
        a2 = a2 - (a2 @ a1) * a1
        if not np.linalg.norm(a2) > 1e-6:
            raise MaterialError(f"axis2 {self.axis2!r} must not be parallel to axis1 {self.axis1!r}")
        a2 = a2 / np.linalg.norm(a2)
        object.__setattr__(self, "stiffness", tuple(map(tuple, C.tolist())))
        object.__setattr__(self, "axis1", tuple(a1.tolist()))
        object.__setattr__(self, "axis2", tuple(a2.tolist()))

    @classmethod
    def orthotropic(cls, youngs_moduli, poisson_ratios, shear_moduli,
                    axis1=(1.0, 0.0, 0.0), axis2=(0.0, 1.0, 0.0)) -> AnisotropicElastic:
        """An orthotropic material from E = (E1, E2, E3), ν = (ν12, ν13,
        ν23) and G = (G12, G13, G23) (module docstring's conventions); not
        positive definite (e.g. ν12² > E1 / E2) is a :class:`MaterialError`."""
        vals = {}
        for name, v in (("youngs_moduli", youngs_moduli), ("poisson_ratios", poisson_ratios),
                        ("shear_moduli", shear_moduli)):
            a = np.asarray(v, dtype=float)
            if a.shape != (3,) or not np.isfinite(a).all():
                raise MaterialError(f"{name} must be 3 finite numbers, got {v!r}")
            vals[name] = a
        E, nu, G = vals["youngs_moduli"], vals["poisson_ratios"], vals["shear_moduli"]
        for name, a in (("youngs_moduli", E), ("shear_moduli", G)):
            if not (a > 0).all():
                raise MaterialError(f"{name} must all be > 0, got {list(a)}")
        S = np.zeros((6, 6))
        S[[0, 1, 2], [0, 1, 2]] = 1.0 / E
        for (i, j), v in zip(((0, 1), (0, 2), (1, 2)), nu):
            S[i, j] = S[j, i] = -v / E[i]
        S[3, 3], S[4, 4], S[5, 5] = 1.0 / G[2], 1.0 / G[1], 1.0 / G[0]
        w = np.linalg.eigvalsh(S)
        if not w[0] > 0:
            raise MaterialError(
                f"the orthotropic constants E = {list(E)}, nu = {list(nu)} are not positive "
                "definite (need 1 - nu12 nu21 - nu13 nu31 - nu23 nu32 - 2 nu21 nu32 nu13 > 0 "
                "and nu_ij^2 < E_i / E_j)")
        return cls(tuple(map(tuple, np.linalg.inv(S).tolist())), axis1, axis2)

    def rotation(self) -> np.ndarray:
        """(3, 3) columns: the material axes 1, 2, 3 in global coordinates."""
        a1, a2 = np.asarray(self.axis1), np.asarray(self.axis2)
        return np.column_stack([a1, a2, np.cross(a1, a2)])

    def tensor(self) -> np.ndarray:
        """C_ijkl (3, 3, 3, 3) in global coordinates."""
        C = np.asarray(self.stiffness)[VOIGT[:, :, None, None], VOIGT[None, None, :, :]]
        A = self.rotation()
        return np.einsum("ia,jb,kc,ld,abcd->ijkl", A, A, A, A, C, optimize=True)

    def isotropic_estimate(self) -> LinearElastic:
        """The isotropic material of the same Voigt-average bulk and shear
        moduli (for estimates: contact size, penalty scale)."""
        C = np.asarray(self.stiffness)
        K = (C[0, 0] + C[1, 1] + C[2, 2] + 2 * (C[0, 1] + C[0, 2] + C[1, 2])) / 9.0
        G = (C[0, 0] + C[1, 1] + C[2, 2] - C[0, 1] - C[0, 2] - C[1, 2]
             + 3 * (C[3, 3] + C[4, 4] + C[5, 5])) / 15.0
        return LinearElastic(9 * K * G / (3 * K + G), min((3 * K - 2 * G) / (2 * (3 * K + G)), 0.499))


def elasticity_tensor(material) -> np.ndarray:
    """C_ijkl (3, 3, 3, 3) of an isotropic or anisotropic material."""
    if isinstance(material, AnisotropicElastic):
        return material.tensor()
    E, nu = material.youngs_modulus, material.poisson_ratio
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    d = np.eye(3)
    return (lam * np.einsum("ij,kl->ijkl", d, d)
            + mu * (np.einsum("ik,jl->ijkl", d, d) + np.einsum("il,jk->ijkl", d, d)))


def isotropic_estimate(material) -> LinearElastic:
    """``material`` itself if isotropic, else its isotropic estimate."""
    return material.isotropic_estimate() if isinstance(material, AnisotropicElastic) else material


MATERIAL_TYPES = (LinearElastic, AnisotropicElastic)

__all__ = ["AnisotropicElastic", "elasticity_tensor", "isotropic_estimate", "MATERIAL_TYPES",
           "VOIGT"]

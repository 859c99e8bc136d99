"""Scalar measures of a stress state: principal stresses, von Mises, Tresca.

A stress tensor is given by its six components in the order of
:data:`COMPONENTS`, (σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz), as an array of
shape (..., 6); tension positive.  Depends on NumPy only, so any stress field
of the package (half-space layers, BEM interior points) can use it.
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError

#: Stress components, in the order of every (..., 6) stress array.
COMPONENTS = ("xx", "yy", "zz", "xy", "yz", "xz")


def _checked(owner: str, stresses: object) -> np.ndarray:
    s = np.asarray(stresses, dtype=float)
    if s.ndim == 0 or s.shape[-1] != 6:
        raise ConfigError(f"{owner}: stresses must have shape (..., 6) = (σ_xx, σ_yy, σ_zz, "
                          f"σ_xy, σ_yz, σ_xz), got {s.shape}")
    return s


def stress_tensors(stresses: np.ndarray) -> np.ndarray:
    """The symmetric 3 × 3 tensors of (..., 6) components: shape (..., 3, 3)."""
    s = _checked("stress_tensors", stresses)
    xx, yy, zz, xy, yz, xz = np.moveaxis(s, -1, 0)
    return np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1),
                     np.stack([xz, yz, zz], -1)], -2)


def principal_stresses(stresses: np.ndarray) -> np.ndarray:
    """The principal stresses σ_1 ≥ σ_2 ≥ σ_3 of (..., 6) components: shape
    (..., 3), by ``numpy.linalg.eigvalsh`` on the stacked tensors."""
    s = _checked("principal_stresses", stresses)
    return np.linalg.eigvalsh(stress_tensors(s))[..., ::-1]


def von_mises(stresses: np.ndarray) -> np.ndarray:
    """The von Mises equivalent stress √(3 J₂) of (..., 6) components:
    √(½[(σ_xx − σ_yy)² + (σ_yy − σ_zz)² + (σ_zz − σ_xx)²] + 3(σ_xy² + σ_yz² +
    σ_xz²)), shape (...)."""
    s = _checked("von_mises", stresses)
    xx, yy, zz, xy, yz, xz = np.moveaxis(s, -1, 0)
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2)
                   + 3.0 * (xy * xy + yz * yz + xz * xz))


def tresca(stresses: np.ndarray) -> np.ndarray:
    """The maximum shear stress (σ_1 − σ_3)/2 of (..., 6) components, shape
    (...) (Tresca's equivalent stress is twice it)."""
    p = principal_stresses(_checked("tresca", stresses))
    return 0.5 * (p[..., 0] - p[..., 2])

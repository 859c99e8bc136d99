"""Material laws.

Units are the user's, but consistent: with lengths in mm and forces in N,
``youngs_modulus`` is in MPa (N/mm^2) and tractions come out in MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import MaterialError


@dataclass(frozen=True)
class LinearElastic:
    """Homogeneous isotropic linear elastic material.

    Parameters
    ----------
    youngs_modulus:
        Young's modulus E > 0 (stress units, e.g. MPa).
    poisson_ratio:
        Poisson's ratio, -1 < nu < 0.5 (0.5, incompressible, is excluded: the
        Kelvin solution degenerates there).
    """

    youngs_modulus: float
    poisson_ratio: float

    def __post_init__(self) -> None:
        E, nu = self.youngs_modulus, self.poisson_ratio
        for name, value in (("youngs_modulus", E), ("poisson_ratio", nu)):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise MaterialError(f"{name} must be a number, got {value!r}")
            if not math.isfinite(value):
                raise MaterialError(f"{name} must be finite, got {value!r}")
        if E <= 0:
            raise MaterialError(f"youngs_modulus must be > 0, got {E!r}")
        if not -1.0 < nu < 0.5:
            raise MaterialError(
                f"poisson_ratio must lie in (-1, 0.5), got {nu!r}"
                + (" (use e.g. 0.499 for a nearly incompressible solid)" if nu == 0.5 else "")
            )
        object.__setattr__(self, "youngs_modulus", float(E))
        object.__setattr__(self, "poisson_ratio", float(nu))

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu))."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def plane_strain_modulus(self) -> float:
        """E / (1 - nu^2), the body's contribution to the contact modulus E*."""
        return self.youngs_modulus / (1.0 - self.poisson_ratio**2)

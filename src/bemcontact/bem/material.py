"""Material laws.

Units are the user's, but consistent: with lengths in mm and forces in N,
``youngs_modulus`` is in MPa (N/mm^2) and tractions come out in MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import MaterialError
from ..settings import Key, in_range, key_of, setting


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

    youngs_modulus: float = setting(Key(
        "youngs_modulus", "number", "Young's modulus E (stress)", required=True, lo=0,
        lo_open=True))
    poisson_ratio: float = setting(Key(
        "poisson_ratio", "number", "Poisson's ratio ν", required=True, lo=-1, lo_open=True,
        hi=0.5, hi_open=True))

    def __post_init__(self) -> None:
        E, nu = self.youngs_modulus, self.poisson_ratio
        for name, value in (("youngs_modulus", E), ("poisson_ratio", nu)):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise MaterialError(f"{name} must be a number, got {value!r}")
            if not math.isfinite(value):
                raise MaterialError(f"{name} must be finite, got {value!r}")
            key = key_of(LinearElastic, name)
            if not in_range(value, key.lo, key.lo_open, key.hi, key.hi_open):
                raise MaterialError(
                    f"{name} must {'be' if key.hi is None else 'lie'} {key.range_text()}, got {value!r}"
                    + (" (use e.g. 0.499 for a nearly incompressible solid)" if nu == 0.5
                       and name == "poisson_ratio" else "")
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

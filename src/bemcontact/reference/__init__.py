"""Analytic solutions used by tests, examples and plots.

Each function is small and documented with its source formula; inputs and
outputs follow the package conventions (docs/theory.md).
"""

from __future__ import annotations

from .kelvin import kelvin_displacement, kelvin_stress, kelvin_traction
from .lame import lame_sphere_radial_displacement, lame_sphere_stress

__all__ = [
    "kelvin_displacement",
    "kelvin_stress",
    "kelvin_traction",
    "lame_sphere_radial_displacement",
    "lame_sphere_stress",
]

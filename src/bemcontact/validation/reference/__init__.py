"""Analytic solutions used by tests, examples and plots.

Each function is small and documented with its source formula; inputs and
outputs follow the package conventions (docs/theory.md).
"""

from __future__ import annotations

from .contact import (
    Hertz,
    boussinesq_punch_force,
    boussinesq_punch_pressure,
    cattaneo_mindlin_displacement,
    cattaneo_mindlin_stick_radius,
    cattaneo_mindlin_traction,
    dundurs_beta,
    effective_modulus,
    fretting_loop_energy,
    hertz,
    hertz_force,
    mindlin_deresiewicz_unloading,
    spence_stick_radius,
    spence_traction,
    tangential_compliance_factor,
)
from .kelvin import kelvin_displacement, kelvin_stress, kelvin_traction
from .lame import lame_sphere_radial_displacement, lame_sphere_stress
from .stress import (
    HertzAxisStresses,
    HertzSurfaceStresses,
    hamilton_sliding_sphere_stresses,
    hertz_axis_stresses,
    hertz_surface_stresses,
)

__all__ = [
    "Hertz",
    "boussinesq_punch_force",
    "boussinesq_punch_pressure",
    "cattaneo_mindlin_displacement",
    "cattaneo_mindlin_stick_radius",
    "cattaneo_mindlin_traction",
    "dundurs_beta",
    "effective_modulus",
    "fretting_loop_energy",
    "hertz",
    "hertz_force",
    "mindlin_deresiewicz_unloading",
    "spence_stick_radius",
    "spence_traction",
    "tangential_compliance_factor",
    "kelvin_displacement",
    "kelvin_stress",
    "kelvin_traction",
    "lame_sphere_radial_displacement",
    "lame_sphere_stress",
    "HertzAxisStresses",
    "HertzSurfaceStresses",
    "hamilton_sliding_sphere_stresses",
    "hertz_axis_stresses",
    "hertz_surface_stresses",
]

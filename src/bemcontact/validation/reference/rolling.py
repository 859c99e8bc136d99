"""Rolling-contact references: Carter's 2D creep-force curve, Kalker's
linear-theory coefficients for a circular contact, and CONTACT's published
steady-state figures (its exact half-space solver, the examples named).

Conventions: :mod:`bemcontact.contact.rolling` (a positive creepage comes
with a negative creep force on body 2)."""

from __future__ import annotations

import math

#: Kalker's coefficients C11, C22, C23 of a circular contact (a/b = 1) by
#: Poisson's ratio (Kalker 1967, the table in his 1990 book):
#: F_x = −G c² C11 ξ, F_y = −G c² C22 η − G c³ C23 φ.
KALKER_CIRCLE = {0.0: (3.40, 3.40, 1.33), 0.25: (4.12, 3.67, 1.47), 0.5: (5.20, 3.98, 1.63)}

#: CONTACT, examples/fastsim.inp (first case: steady rolling, exact solver):
#: identical bodies, the Hertzian ellipse with undeformed distance
#: A x² + B y², 44 × 44 cells over 1.1 × the semi-axes, and its result.
CONTACT_SPIN = {"G": 82000.0, "nu": 0.28, "mu": 0.3, "Fn": 82000.0, "a": 8.0, "b": 4.0,
                "A": 0.8464e-3, "B": 0.2406e-2, "eta": -0.000625, "phi": 0.000625,
                "cells": (44, 44), "scale": 1.1, "Fy_over_muFn": -0.6074}

#: CONTACT, examples/tractcurv.inp (first series, a wheel-rail case):
#: identical bodies, A = 0.0008, B = 0.2814e-3 (1/mm; a = 6.304, b = 12.61),
#: 48 × 44 cells over ±6.934 × ±13.87 mm, F_x/(μ F_n) by ξ.
CONTACT_CURVE = {"G": 82000.0, "nu": 0.28, "mu": 0.33, "Fn": 106.7e3, "A": 0.0008,
                 "B": 0.2814e-3, "cells": (48, 44), "half_widths": (6.934, 13.87),
                 "Fx_over_muFn": {0.0004: -0.2588, 0.0008: -0.4742, 0.0012: -0.6482,
                                  0.0020: -0.8816, 0.0028: -0.9832, 0.0032: -0.9976}}


def carter_ratio(creepage: float, radius: float, friction: float, half_width: float) -> float:
    """|F_x| / (μ F_n) of Carter's 2D steady rolling (identical elastic
    cylinders, or a cylinder on a flat, relative radius ``radius``, contact
    half-width ``half_width``): 1 − (a′/a)² with a′/a = 1 − R|ξ|/(μ a) up
    to full sliding (R|ξ| ≥ μ a: 1)."""
    x = radius * abs(creepage) / (friction * half_width)
    return 1.0 if x >= 1.0 else 1.0 - (1.0 - x) ** 2


def carter_stick(ratio: float, half_width: float) -> tuple[float, float]:
    """The stick zone (x_min, x_max) of Carter's steady state carrying the
    tangential force ``ratio`` μ F_n: at the leading edge (x = a), of
    half-width a √(1 − ratio) (the same width as Cattaneo's centred zone)."""
    w = half_width * math.sqrt(1.0 - ratio)
    return half_width - 2.0 * w, half_width


__all__ = ["CONTACT_CURVE", "CONTACT_SPIN", "KALKER_CIRCLE", "carter_ratio", "carter_stick"]

"""A contact surface near the contact point, as the frame sees it: a quartic
ζ(ξ, η) in the frame's coordinates (fitted to the surface's mesh nodes by
:func:`~bemcontact.multiscale.pair.surface_fit`)."""

from __future__ import annotations

import numpy as np


def quartic_terms(x, y) -> np.ndarray:
    """The 15 monomials x^i y^j, i + j <= 4, of a quartic: shape (..., 15)."""
    return np.stack([x**i * y**(d - i) for d in range(5) for i in range(d, -1, -1)], axis=-1)


__all__ = ["quartic_terms"]

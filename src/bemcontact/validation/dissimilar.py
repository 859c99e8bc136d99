"""Spence's problem (docs/validation.md): a hemisphere pressed on a block of a
different material with friction under a monotonically growing normal load.

With dissimilar materials (Dundurs' beta != 0) the pressure draws the two
surfaces inward by different amounts; friction resists, leaving a central
stick zone whose radius c/a depends on beta/mu alone in the uncoupled
approximation (:func:`~bemcontact.validation.reference.contact.spence_stick_radius`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bem import Displacement, ElasticBody, Fixed, LinearElastic
from ..contact import ContactPair, ContactProblem, FrameResult, LoadStep
from ..errors import ConfigError
from ..mesh import shapes as geometry
from .cases import SphereOnBlock
from .reference.contact import dundurs_beta, effective_modulus


@dataclass(frozen=True)
class DissimilarSphereOnBlock:
    """A stiff hemisphere on a compliant block with small Poisson ratio
    (defaults: sphere 10x stiffer than the block, nu 0.3 on nu 0, so
    beta = 0.434 with the block as body 1; mu = 0.25 gives beta/mu = 1.74
    and c/a = 0.597).  Geometry and grading as :class:`SphereOnBlock`."""

    block_youngs_modulus: float = 210000.0
    block_poisson_ratio: float = 0.0
    sphere_youngs_modulus: float = 2100000.0
    sphere_poisson_ratio: float = 0.3
    geometry: SphereOnBlock = SphereOnBlock()

    @property
    def beta(self) -> float:
        """Dundurs' beta with the block as body 1 (> 0: friction pulls the
        block's surface outward, the sphere's inward)."""
        return dundurs_beta(self.block_youngs_modulus, self.block_poisson_ratio,
                            self.sphere_youngs_modulus, self.sphere_poisson_ratio)

    @property
    def contact_modulus(self) -> float:
        return effective_modulus(self.block_youngs_modulus, self.block_poisson_ratio,
                                 self.sphere_youngs_modulus, self.sphere_poisson_ratio)


def dissimilar_sphere_on_block(fine_size: float, approach: float = 0.03,
                               friction_coefficient: float = 0.25,
                               setup: DissimilarSphereOnBlock | None = None,
                               cap_height: float | None = None, order: int = 1) -> ContactProblem:
    """Body ``block`` (top face z = 0, base clamped) and body ``sphere``
    (apex at the origin, flat base z = R pushed down by ``approach`` with
    all components prescribed: nothing tangential is applied, so the shear
    comes from the materials' mismatch alone), meshed as
    :func:`~bemcontact.validation.cases.sphere_on_block`; the frame by the
    default rule (``auto``: on the flat block).  Use :func:`spence_steps`
    for the monotonic loading.  ``cap_height`` (default R: a hemisphere)
    cuts the sphere lower, a smaller mesh for the same contact."""
    s = setup or DissimilarSphereOnBlock()
    g = s.geometry
    if not (isinstance(fine_size, (int, float)) and 0 < fine_size <= g.fine_radius):
        raise ConfigError(f"dissimilar_sphere_on_block: fine_size must be in (0, "
                          f"{g.fine_radius:g}], got {fine_size!r}")
    w, d = g.block_half_width, g.block_depth
    blk = geometry.graded_block((-w, -w, -d), (w, w, 0.0), (0.0, 0.0, 0.0), fine_size=fine_size,
                                coarse_size=g.coarse_size, order=order, **g.grading())
    cap = geometry.spherical_cap(g.radius, cap_height or g.radius, apex=(0.0, 0.0, 0.0), axis=1,
                                 fine_size=fine_size, coarse_size=g.coarse_size, order=order,
                                 **g.grading())
    block = ElasticBody(blk, LinearElastic(s.block_youngs_modulus, s.block_poisson_ratio),
                        {"zmin": Fixed()}, name="block")
    sphere = ElasticBody(cap, LinearElastic(s.sphere_youngs_modulus, s.sphere_poisson_ratio),
                         {"base": Displacement((0.0, 0.0, -float(approach)))}, name="sphere")
    pair = ContactPair("zmax", "contact", friction_coefficient, search_distance=g.search_distance)
    return ContactProblem(block, sphere, pair)


def spence_steps(approach: float, increments: int, ratio: float = 1.0) -> list[LoadStep]:
    """Monotonic loading of :func:`dissimilar_sphere_on_block` to
    ``approach`` in ``increments`` steps, the approach of step i (1-based)
    ``approach * ratio**(increments - i)`` when ``ratio`` < 1 (geometric:
    every step grows the contact radius by the same factor ratio^(-1/2),
    as the self-similar solution does) or ``approach * i / increments``
    when ``ratio`` = 1."""
    if not (isinstance(increments, int) and increments >= 1 and 0 < ratio <= 1):
        raise ConfigError(f"spence_steps: need increments >= 1 and 0 < ratio <= 1, got "
                          f"{increments!r}, {ratio!r}")
    if ratio == 1.0:
        d = [approach * (i + 1) / increments for i in range(increments)]
    else:
        d = [approach * ratio ** (increments - 1 - i) for i in range(increments)]
    return [LoadStep({"sphere": {"base": Displacement((0.0, 0.0, -x))}}, 1, f"d={x:.4g}")
            for x in d]


def radial_shear(frame: FrameResult, center=(0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """(r, q_r) at the frame nodes: the distance from ``center`` and the
    radial component of the tangential traction on body 1 (> 0 pointing
    away from the axis), in the frame's node order."""
    d = frame.points[:, :2] - np.asarray(center, dtype=float)
    r = np.hypot(d[:, 0], d[:, 1])
    e = np.divide(d, r[:, None], out=np.zeros_like(d), where=r[:, None] > 0)
    # the frame's traction acts on body 2; body 1 receives the opposite
    return r, -np.einsum("ij,ij->i", frame.tangential_traction[:, :2], e)


__all__ = ["DissimilarSphereOnBlock", "dissimilar_sphere_on_block", "spence_steps", "radial_shear"]

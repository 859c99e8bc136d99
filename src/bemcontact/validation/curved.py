"""Curved-on-curved validation problems other than two convex spheres
(:func:`~bemcontact.validation.cases.two_spheres`), for the frame between the
surfaces (docs/frame.md, docs/validation.md):

* :func:`crossed_cylinders`: two identical half cylinders, axes crossed at
  right angles, touching at one point.  For equal radii the initial gap is
  x²/2R + y²/2R: a circular Hertz contact with R_eff = R, that of a sphere of
  radius R on a flat (Johnson, *Contact Mechanics*, §4.2).
* :func:`sphere_in_seat`: a hemisphere of radius R1 in a spherical seat of a
  slightly larger radius R2 (a conforming contact): the initial gap is
  r²/2 (1/R1 − 1/R2), Hertz with R_eff = R1 R2 / (R2 − R1).

Both use the materials and grading of
:class:`~bemcontact.validation.cases.SphereOnBlock` (steel, R = 10 mm, fine
zone 0.7 mm); the lower body's base is clamped and the upper body's base
pushed down by ``approach``.  Identical materials: Hertz theory decouples
the normal and tangential problems, so the tangential traction under a
normal load is zero in the small-slope limit.
"""

from __future__ import annotations

import math

import numpy as np

from ..bem import Displacement, ElasticBody, Fixed, LinearElastic
from ..contact import ContactPair, ContactProblem
from ..errors import ConfigError
from ..mesh import curved as curved_shapes
from ..mesh import shapes as geometry
from .cases import SphereOnBlock

#: Search distance / the initial gap at the edge of the fine zone (the frame
#: covers the fine zone with a margin; as in ``cases.two_spheres``).
SEARCH_MARGIN = 1.2


def _check(who: str, setup: SphereOnBlock | None, fine_size, approach) -> SphereOnBlock:
    s = setup or SphereOnBlock()
    if not (isinstance(fine_size, (int, float)) and 0 < fine_size <= s.fine_radius):
        raise ConfigError(
            f"{who}: fine_size must be in (0, fine_radius = {s.fine_radius:g}], got {fine_size!r}"
        )
    ok = isinstance(approach, (int, float)) and math.isfinite(approach)
    if not (ok and 0 < approach < s.radius):
        raise ConfigError(f"{who}: approach must be in (0, R = {s.radius:g}), got {approach!r}")
    return s


def _problem(lower, upper, s: SphereOnBlock, approach: float, mu: float, frame_on: str,
             search: float, swap: bool) -> ContactProblem:
    mat = LinearElastic(s.youngs_modulus, s.poisson_ratio)
    bodies = [ElasticBody(lower, mat, {"base": Fixed()}, name="lower"),
              ElasticBody(upper, mat, {"base": Displacement((0.0, 0.0, -float(approach)))},
                          name="upper")]
    if swap:
        bodies.reverse()
    pair = ContactPair("contact", "contact", mu, search_distance=search, frame_on=frame_on)
    return ContactProblem(bodies[0], bodies[1], pair)


def crossed_cylinders(
    fine_size: float,
    approach: float = 0.03,
    setup: SphereOnBlock | None = None,
    order: int = 1,
    friction_coefficient: float = 0.0,
    frame_on: str = "auto",
    length: float = 20.0,
    swap: bool = False,
) -> ContactProblem:
    """Two half cylinders of radius ``setup.radius`` and length ``length``
    touching at the origin: ``lower`` (axis along x, below; flat base
    clamped) and ``upper`` (axis along y, above; flat base pushed down by
    ``approach``), meshed with :func:`~bemcontact.mesh.curved.half_cylinder`
    graded toward the origin.  Coulomb friction ``friction_coefficient``,
    the frame placed by ``frame_on``; ``swap`` names ``upper`` first.

    Hertz with R_eff = R (circular contact): a ≈ sqrt(R approach), 0.55 mm
    at the default approach, inside the 0.7 mm fine zone.  The 180° rotation
    about the line x = y in the plane z = 0 swaps the two bodies."""
    s = _check("crossed_cylinders", setup, fine_size, approach)
    L = float(length)
    if not (math.isfinite(L) and L > 2 * s.fine_radius):
        raise ConfigError(f"crossed_cylinders: length must exceed 2 fine_radius, got {length!r}")
    kw = dict(fine_size=fine_size, coarse_size=s.coarse_size, order=order, **s.grading())
    lower = curved_shapes.half_cylinder(s.radius, L, axis=-1, direction="x", **kw)
    upper = curved_shapes.half_cylinder(s.radius, L, axis=1, direction="y", **kw)
    search = SEARCH_MARGIN * s.fine_radius**2 / (2.0 * s.radius)
    return _problem(lower, upper, s, approach, friction_coefficient, frame_on, search, swap)


def seat_effective_radius(radius: float, seat_radius: float) -> float:
    """R_eff = R1 R2 / (R2 - R1) of a ball of radius R1 in a seat of radius R2 > R1."""
    return radius * seat_radius / (seat_radius - radius)


def sphere_in_seat(
    fine_size: float,
    seat_radius: float = 12.0,
    approach: float = 0.005,
    setup: SphereOnBlock | None = None,
    order: int = 1,
    friction_coefficient: float = 0.0,
    frame_on: str = "auto",
    seat_depth: float = 2.0,
    swap: bool = False,
) -> ContactProblem:
    """A hemisphere of radius R1 = ``setup.radius`` (``upper``, apex at the
    origin, flat base at z = R1 pushed down by ``approach``) in a spherical
    seat of radius ``seat_radius`` R2 > R1 (``lower``: the block
    ``setup.block_half_width`` wide and ``setup.block_depth`` deep under the
    seat's bottom at the origin, the dimple ``seat_depth`` deep; base
    clamped), both graded toward the origin.  Coulomb friction
    ``friction_coefficient``, the frame placed by ``frame_on``; ``swap``
    names ``upper`` first.

    Hertz with R_eff = R1 R2 / (R2 - R1) (60 mm for the default 10 in 12):
    a ≈ sqrt(R_eff approach), 0.55 mm at the default approach.  The
    quadratic gap holds to a relative (3/4)(a/R1)² and the half-space
    idealization to O(a/R1), so Hertz needs a ≪ R1 however close R2 is to
    R1; a conforming seat reaches a given a at a smaller approach (a²/R_eff)
    and a smaller force."""
    s = _check("sphere_in_seat", setup, fine_size, approach)
    R1, R2 = s.radius, seat_radius
    if not (isinstance(R2, (int, float)) and math.isfinite(R2) and R2 > R1):
        raise ConfigError(f"sphere_in_seat: seat_radius must be a number > R = {R1:g}, got {R2!r}")
    upper = geometry.spherical_cap(R1, R1, apex=(0.0, 0.0, 0.0), axis=1, fine_size=fine_size,
                                   coarse_size=s.coarse_size, order=order, **s.grading())
    lower = curved_shapes.spherical_seat(R2, seat_depth, s.block_half_width, s.block_depth,
                                  fine_size=fine_size, coarse_size=s.coarse_size, order=order,
                                  **s.grading())
    search = SEARCH_MARGIN * s.fine_radius**2 / (2.0 * seat_effective_radius(R1, R2))
    return _problem(lower, upper, s, approach, friction_coefficient, frame_on, search, swap)


#: The tangential traction patterns the symmetries of the curved pairs allow
#: (unit fields in polar coordinates about the contact point): ``"radial"``,
#: e_r, the only one an axisymmetric pair (two spheres, a ball in a seat)
#: allows; ``"saddle"``, cos 2θ e_r − sin 2θ e_θ (the field (x, −y) / r),
#: the one the crossed cylinders' half-turn about the line x = y allows and
#: their opposite curvatures along x and y call for.
SHEAR_PATTERNS = ("radial", "saddle")


def shear_pattern(frame, pattern: str, rings: int = 8) -> tuple[float, float]:
    """How much of the tangential traction of ``frame`` (a
    :class:`~bemcontact.contact.results.FrameResult` whose contact plane is
    z = 0, contact point at the origin) is the symmetric ``pattern``
    (:data:`SHEAR_PATTERNS`) with an amplitude that depends on the radius
    only, and its size.  Over the closed nodes, weighted by their areas:
    the amplitude g is fitted in ``rings`` equal rings of radius (the mean
    of q . e per ring); returns (share, rms) with share = 1 − |q − g e|² /
    |q|² (1: all of it is the pattern; a field without the pattern, such as
    noise from node to node, gives about 0) and rms = the root mean square
    of |q| divided by the peak pressure."""
    if pattern not in SHEAR_PATTERNS:
        raise ConfigError(f"shear_pattern: pattern must be one of {SHEAR_PATTERNS}, got {pattern!r}")
    closed = frame.pressure > 0
    if closed.sum() < 2 * rings:
        raise ConfigError(f"shear_pattern: {int(closed.sum())} closed nodes, fewer than 2 per ring")
    x, y = frame.points[closed, 0], frame.points[closed, 1]
    q = frame.tangential_traction[closed][:, :2]
    w = frame.weights[closed]
    r, th = np.hypot(x, y), np.arctan2(y, x)
    # e_r, or cos 2θ e_r − sin 2θ e_θ = (cos θ, −sin θ)
    sign = 1.0 if pattern == "radial" else -1.0
    e = np.stack([np.cos(th), sign * np.sin(th)], axis=1)
    c = np.einsum("ij,ij->i", q, e)
    ring = np.minimum((r / r.max() * rings).astype(int), rings - 1)
    g = np.zeros_like(c)
    for k in np.unique(ring):
        s = ring == k
        g[s] = np.sum(w[s] * c[s]) / np.sum(w[s])
    q2 = np.sum(w * np.einsum("ij,ij->i", q, q))
    rest = q - g[:, None] * e
    share = 1.0 - np.sum(w * np.einsum("ij,ij->i", rest, rest)) / q2 if q2 > 0 else 0.0
    rms = float(np.sqrt(q2 / np.sum(w)) / frame.pressure.max())
    return float(share), rms


__all__ = ["crossed_cylinders", "sphere_in_seat", "seat_effective_radius", "shear_pattern",
           "SHEAR_PATTERNS", "SEARCH_MARGIN"]

"""Validation cases of assemblies (several bodies and contact pairs):
a ball squeezed between two blocks, mirror symmetric by construction
(docs/validation.md)."""

from __future__ import annotations

from ..bem.body import ElasticBody
from ..bem.conditions import Displacement, Fixed
from ..bem.material import LinearElastic
from ..contact.pair import ContactPair
from ..contact.problem import ContactProblem
from ..errors import ConfigError
from ..mesh import curved
from ..mesh import shapes as geometry
from .cases import SphereOnBlock


def ball_between_blocks(
    fine_size: float,
    approach: float = 0.06,
    friction_coefficient: float = 0.0,
    setup: SphereOnBlock | None = None,
    order: int = 1,
    band: float = 0.3,
) -> ContactProblem:
    """A ball (body ``ball``, radius R of ``setup``, lowest point at the
    origin) between two blocks (``lower``: top face z = 0, base clamped;
    ``upper``: its mirror image in the ball's equator plane z = R, bottom
    face z = 2R), all of ``setup``'s material and graded to ``fine_size``
    near the two contact points.  The upper block's top face is pushed down
    by ``approach`` (and held in x and y); the ball is held in x and y on
    its equatorial ``band`` (|z - R| < band R) and free in z, so the
    contacts alone carry it.  Two pairs, lower block/ball bottom and ball
    top/upper block, with Coulomb friction ``friction_coefficient``, the
    frames on the flat blocks.  The whole problem is mirror symmetric in
    the equator plane (meshes included; the load differs from its mirror
    image by a rigid translation of the ball and upper block), so both
    contacts carry the same solution: Hertz with R and E* each, for the
    force P that the upper block transmits."""
    s = setup or SphereOnBlock()
    if not (isinstance(fine_size, (int, float)) and 0 < fine_size <= s.fine_radius):
        raise ConfigError(f"ball_between_blocks: fine_size must be in (0, fine_radius = "
                          f"{s.fine_radius:g}], got {fine_size!r}")
    if not (isinstance(approach, (int, float)) and 0 < approach < 0.1 * s.radius):
        raise ConfigError(
            f"ball_between_blocks: approach must be in (0, R/10 = {0.1 * s.radius:g}), "
            f"got {approach!r}")
    R, w, d = s.radius, s.block_half_width, s.block_depth
    lower_mesh = geometry.graded_block(
        (-w, -w, -d), (w, w, 0.0), (0.0, 0.0, 0.0), fine_size=fine_size,
        coarse_size=s.coarse_size, order=order, **s.grading(),
    )
    upper_mesh = curved.mirrored(lower_mesh, R, {"zmin": "zmax", "zmax": "zmin"})
    mat = LinearElastic(s.youngs_modulus, s.poisson_ratio)
    lower = ElasticBody(lower_mesh, mat, {"zmin": Fixed()}, name="lower")
    ball_mesh = curved.ball(R, fine_size=fine_size, coarse_size=s.coarse_size, order=order,
                            band=band, **s.grading())
    ball = ElasticBody(ball_mesh, mat,
                       {"band": Displacement((0.0, 0.0, None))}, name="ball")
    upper = ElasticBody(upper_mesh, mat, {"zmax": Displacement((0.0, 0.0, -float(approach)))},
                        name="upper")
    search = 0.6 * s.fine_radius**2 / R
    mu = friction_coefficient
    pairs = [
        ContactPair("zmax", "bottom", mu, search_distance=search, bodies=("lower", "ball")),
        ContactPair("top", "zmin", mu, search_distance=search, bodies=("ball", "upper")),
    ]
    return ContactProblem(bodies=[lower, ball, upper], pairs=pairs)


def transmitted_force(result, body: str = "upper", region: str = "zmax") -> float:
    """The downward force the loaded face carries (N, > 0 pressing)."""
    return -float(result.reactions()[body][region][2])


__all__ = ["ball_between_blocks", "transmitted_force"]

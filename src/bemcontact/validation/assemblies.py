"""Validation cases of assemblies (several bodies and contact pairs):
a ball squeezed between two blocks, mirror symmetric by construction
(docs/validation.md); the two indenters of
examples/two_indenters_multiscale.toml meshed finely for the full path (the
reference of the assembly on the contact grid)."""

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


#: examples/two_indenters_multiscale.toml's indenters: name -> (apex x in mm,
#: the approach its base is pushed down by in mm).
TWO_INDENTERS = {"left": (-2.0, 0.03), "right": (2.0, 0.02)}


def two_indenters_on_block(fine_size: float, names=tuple(TWO_INDENTERS)) -> ContactProblem:
    """examples/two_indenters_multiscale.toml's bodies meshed finely for the
    full path: the steel block (20 x 20 x 10 mm, top face z = 0, base
    ``zmin`` clamped) at ``fine_size`` over a ring 1.25-2.75 mm about its
    centre (both contacts; 0.5 mm inside and outside it, growth 0.45) and the
    steel hemispheres (R = 10 mm, apexes at (x, 0, 0) of :data:`TWO_INDENTERS`)
    ``names`` of ``left`` and ``right``, each at ``fine_size`` within 0.75 mm
    of its apex, its ``base`` pushed down by its approach; one pair per
    indenter, block ``zmax`` / indenter ``contact``, μ = 0.3, search distance
    0.05 mm, the frame on the block.  The example's history:
    ``SolverOptions(load_steps=4)``."""
    unknown = [n for n in names if n not in TWO_INDENTERS]
    if unknown or not names:
        raise ConfigError(f"two_indenters_on_block: names must be some of {list(TWO_INDENTERS)}, "
                          f"got {list(names)!r}")
    h = fine_size
    mat = LinearElastic(210e3, 0.3)
    ring = ((0.0, 0.5), (1.1, 0.5), (1.25, h), (2.75, h), (2.9, 0.5))
    block = ElasticBody(geometry.graded_block((-10, -10, -10), (10, 10, 0), (0, 0, 0),
                                              fine_size=h, coarse_size=2.5, size_profile=ring,
                                              growth=0.45), mat, {"zmin": Fixed()}, name="block")
    caps = [ElasticBody(geometry.spherical_cap(10.0, 10.0, apex=(x, 0.0, 0.0), axis=1,
                                               fine_size=h, coarse_size=2.5, fine_radius=0.75,
                                               growth=0.45, order=1), mat,
                        {"base": [Displacement((0.0, 0.0, -approach))]}, name=n)
            for n, (x, approach) in TWO_INDENTERS.items() if n in names]
    pairs = [ContactPair("zmax", "contact", 0.3, bodies=("block", c.name), search_distance=0.05,
                         frame_on="body1") for c in caps]
    return ContactProblem(bodies=[block, *caps], pairs=pairs)


__all__ = ["ball_between_blocks", "transmitted_force", "TWO_INDENTERS", "two_indenters_on_block"]

"""Validation cases of assemblies (several bodies and contact pairs):
a ball squeezed between two blocks, mirror symmetric by construction
(docs/validation.md)."""

from __future__ import annotations

import math

import numpy as np

from ..bem.body import ElasticBody
from ..bem.conditions import Displacement, Fixed
from ..bem.material import LinearElastic
from ..contact.pair import ContactPair
from ..contact.problem import ContactProblem
from ..errors import ConfigError
from ..mesh import shapes as geometry
from ..mesh.element import REVERSED
from ..mesh.surface import SurfaceMesh
from .cases import SphereOnBlock, _setup


def _mirrored(mesh: SurfaceMesh, z0: float, names: dict[str, str]) -> SurfaceMesh:
    """``mesh`` reflected in the plane z = z0 (node order reversed, so the
    normals stay outward), regions renamed by ``names``."""
    X = mesh.nodes.copy()
    X[:, 2] = 2.0 * z0 - X[:, 2]
    E = mesh.elements[:, REVERSED[mesh.element_type]]
    regions = {names.get(k, k): v for k, v in mesh.regions.items()}
    return SurfaceMesh(X, E, mesh.element_type, regions, source=mesh.source)


def _ball(s: SphereOnBlock, fine_size: float, order: int, band: float) -> SurfaceMesh:
    """A ball of radius R with its lowest point at the origin: the graded
    hemisphere of ``s`` and its mirror image in the equator plane, the
    equator's nodes merged.  Regions ``bottom`` and ``top`` (the contact
    caps) and ``band`` (|z - R| < band R, for the supports)."""
    R = s.radius
    cap = geometry.spherical_cap(R, R, apex=(0.0, 0.0, 0.0), axis=1, fine_size=fine_size,
                                 coarse_size=s.coarse_size, order=order, **s.grading())
    curved = cap.region("contact")
    used = np.unique(cap.elements[curved])
    index = np.full(cap.n_nodes, -1)
    index[used] = np.arange(used.size)
    X = cap.nodes[used]
    E = index[cap.elements[curved]]
    # the upper half: reflected nodes, the equator's (z = R) shared
    Xm = X.copy()
    Xm[:, 2] = 2.0 * R - Xm[:, 2]
    on_equator = np.abs(X[:, 2] - R) <= 1e-9 * R
    new = np.flatnonzero(~on_equator)
    upper = np.arange(X.shape[0])
    upper[new] = X.shape[0] + np.arange(new.size)
    nodes = np.vstack([X, Xm[new]])
    Em = upper[E][:, REVERSED[cap.element_type]]
    elements = np.vstack([E, Em])
    zc = nodes[elements].mean(axis=1)[:, 2]
    in_band = np.abs(zc - R) < band * R
    regions = {
        "bottom": np.flatnonzero(~in_band & (zc < R)),
        "band": np.flatnonzero(in_band),
        "top": np.flatnonzero(~in_band & (zc > R)),
    }
    return SurfaceMesh(nodes, elements, cap.element_type, regions,
                       source="ball").oriented().check()


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
    s = _setup("ball_between_blocks", setup, fine_size)
    if not (isinstance(approach, (int, float)) and 0 < approach < 0.1 * s.radius):
        raise ConfigError(
            f"ball_between_blocks: approach must be in (0, R/10 = {0.1 * s.radius:g}), "
            f"got {approach!r}")
    if not (isinstance(band, (int, float)) and 0 < band < 0.8):
        raise ConfigError(f"ball_between_blocks: band must be in (0, 0.8), got {band!r}")
    R, w, d = s.radius, s.block_half_width, s.block_depth
    lower_mesh = geometry.graded_block(
        (-w, -w, -d), (w, w, 0.0), (0.0, 0.0, 0.0), fine_size=fine_size,
        coarse_size=s.coarse_size, order=order, **s.grading(),
    )
    upper_mesh = _mirrored(lower_mesh, R, {"zmin": "zmax", "zmax": "zmin"})
    mat = LinearElastic(s.youngs_modulus, s.poisson_ratio)
    lower = ElasticBody(lower_mesh, mat, {"zmin": Fixed()}, name="lower")
    ball = ElasticBody(_ball(s, fine_size, order, band), mat,
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

"""Validation problems with a finite-element body (docs/validation.md,
"Finite-element bodies"): the Hertz block of :func:`.cases.sphere_on_block`
meshed in volume, of one material, anisotropic or coated.

* :func:`sphere_on_fem_block`: the hemisphere (a BEM body) pressed on the
  block as a :class:`~bemcontact.fem.body.FiniteElementBody` of quadratic
  tetrahedra graded to the contact (gmsh), with the block's material (or
  one per bonded layer) given.
* :func:`contact_ellipse`: the axes and orientation of a contact's
  pressure from its second moments (the orthotropic block's test).

Needs the ``fem`` extra (scikit-fem, cvxopt, pymetis).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bem import Displacement, ElasticBody, Fixed, Force, LinearElastic
from ..contact import ContactPair, ContactProblem, FrameResult
from ..mesh import shapes as geometry
from .cases import SphereOnBlock, checked_setup
from .reference.layered import pressure_moments


def sphere_on_fem_block(
    fine_size: float,
    approach: float = 0.03,
    setup: SphereOnBlock | None = None,
    block_material=None,
    layers=(),
    order: int = 2,
    normal_force: float | None = None,
    sphere_material=None,
) -> ContactProblem:
    """:func:`.cases.sphere_on_block` (frictionless) with the block a
    finite-element body: the solid of tetrahedra of ``order`` (1 or 2),
    graded as the BEM block is; the sphere the same BEM hemisphere (tri3).

    ``block_material``: the block's material (default the setup's steel),
    or with ``layers`` (thicknesses from the top face down) a mapping
    ``{"layer1": ..., "substrate": ...}``.  ``normal_force``: push the base
    down by that force (the base held in x and y) instead of by
    ``approach``.  ``sphere_material``: the sphere's (default the setup's
    steel).  The frame lies on the block, whose top face is the plane
    z = 0 of Hertz theory."""
    from ..fem.body import FiniteElementBody
    from ..fem.mesh import solid_volume

    s = checked_setup("sphere_on_fem_block", setup, fine_size)
    w, d = s.block_half_width, s.block_depth
    solid = geometry.graded_block(
        (-w, -w, -d), (w, w, 0.0), (0.0, 0.0, 0.0), fine_size=fine_size,
        coarse_size=s.coarse_size, solid=True, layers=layers, **s.grading(),
    )
    steel = LinearElastic(s.youngs_modulus, s.poisson_ratio)
    block = FiniteElementBody(solid_volume(solid, order), block_material or steel,
                              {"zmin": Fixed()}, name="block")
    cap = s.hemisphere(fine_size)
    if normal_force is None:
        base = [Displacement((0.0, 0.0, -float(approach)))]
    else:
        base = [Displacement((0.0, 0.0, None)), Force((None, None, -float(normal_force)))]
    sphere = ElasticBody(cap, sphere_material or steel, {"base": base}, name="sphere")
    pair = ContactPair("zmax", "contact", 0.0, search_distance=s.search_distance,
                       frame_on="body1")
    return ContactProblem(block, sphere, pair)


@dataclass(frozen=True)
class Ellipse:
    """Semi-axes (major >= minor, lengths) and the major axis's angle from
    the x axis (radians, in (-pi/2, pi/2]) of a contact area."""

    major: float
    minor: float
    angle: float

    @property
    def aspect(self) -> float:
        return self.major / self.minor


def contact_ellipse(frame: FrameResult) -> Ellipse:
    """The Hertz ellipse with the pressure's second moments: for p = p0
    sqrt(1 - x²/a² - y²/b²) the moments ∫ x² p dA / ∫ p dA are a² / 5 and
    b² / 5 about its axes (pressure-weighted, so the nodes at the edge,
    which open and close with the mesh, count least).  Centred at the
    pressure's centroid."""
    M = pressure_moments(frame.points[:, 0], frame.points[:, 1], frame.pressure, frame.weights)
    val, vec = np.linalg.eigh(M)
    angle = math.atan2(vec[1, 1], vec[0, 1])
    if angle <= -math.pi / 2:
        angle += math.pi
    elif angle > math.pi / 2:
        angle -= math.pi
    return Ellipse(math.sqrt(5.0 * val[1]), math.sqrt(5.0 * val[0]), angle)


__all__ = ["sphere_on_fem_block", "Ellipse", "contact_ellipse"]

"""Ready-made validation problems and the measures used to compare them with
their analytic solutions (docs/validation.md).

* :func:`sphere_on_block`: a hemisphere pressed on a block (Hertz; with
  friction and a tangential platen force, Cattaneo–Mindlin and
  Mindlin–Deresiewicz).  Meshes from :mod:`bemcontact.mesh.shapes`, graded
  toward the contact point.
* :func:`punch_on_block`: a much stiffer flat-ended cylinder pressed on a
  block (Boussinesq), with :func:`block_compliance`, the finite block's
  departure from the half-space measured on the same mesh.
* :func:`radial_profile`, :func:`hertz_errors`, :func:`stick_radius`,
  :func:`weighted_l2`: what the validation tests, the example and the
  benchmark measure, defined once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bem import Displacement, ElasticBody, Fixed, Force, LinearElastic, Traction
from ..contact import ContactPair, ContactProblem, FrameResult, LoadStep
from ..contact.law import OPEN, STICK
from ..errors import ConfigError
from ..mesh import shapes as geometry
from .reference.contact import (
    Hertz,
    boussinesq_punch_force,
    boussinesq_punch_pressure,
    effective_modulus,
    tangential_compliance_factor,
)


@dataclass(frozen=True)
class SphereOnBlock:
    """Sizes and materials of :func:`sphere_on_block` (defaults: steel on
    steel, R = 10 mm, a ≈ 0.55 mm at the default approach, so a/R ≈ 0.055
    and a/L ≈ 0.055 for the 20 × 20 × 10 mm block)."""

    radius: float = 10.0
    youngs_modulus: float = 210000.0
    poisson_ratio: float = 0.3
    block_half_width: float = 10.0
    block_depth: float = 10.0
    fine_radius: float = 0.7
    coarse_size: float = 2.5
    search_distance: float = 0.05
    growth: float = 0.3
    #: optional (distance, size) knots for both bodies instead of the uniform
    #: fine zone (``fine_radius``), e.g. a ring refined at a stick–slip
    #: boundary; see :func:`geometry.graded_block`
    size_profile: tuple | None = None

    def grading(self) -> dict:
        """The grading arguments of :mod:`bemcontact.mesh.shapes` for both bodies."""
        if self.size_profile is None:
            return {"fine_radius": self.fine_radius, "growth": self.growth}
        return {"size_profile": self.size_profile, "growth": self.growth}

    def hemisphere(self, fine_size: float, apex_z: float = 0.0, axis: int = 1, order: int = 1):
        """The graded hemisphere (a surface mesh) with its apex at
        (0, 0, ``apex_z``), its base at ``axis`` * R above it."""
        return geometry.spherical_cap(
            self.radius, self.radius, apex=(0.0, 0.0, apex_z), axis=axis, fine_size=fine_size,
            coarse_size=self.coarse_size, order=order, **self.grading(),
        )

    @property
    def contact_modulus(self) -> float:
        return self.youngs_modulus / (2.0 * (1.0 - self.poisson_ratio**2))

    @property
    def shear_modulus(self) -> float:
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def tangential_compliance_factor(self) -> float:
        """S = 2 (2 - nu) / G of the two identical bodies (Cattaneo–Mindlin)."""
        G, nu = self.shear_modulus, self.poisson_ratio
        return tangential_compliance_factor(G, nu, G, nu)


#: Cattaneo–Mindlin's stick–slip boundary ring: element size 0.03 mm on
#: 0.39 <= r <= 0.50 mm (c = 0.79 a to 0.91 a for Q = 0.5 and 0.75 mu P at
#: the default approach, a = 0.555 mm), 0.05 mm elsewhere out to 0.62 mm,
#: then growing by 0.45 per unit distance.  The traction's square-root kink
#: at c is the profile's largest error; this refines it to 0.03 mm with
#: fewer nodes (3,691) than the uniform 0.05 mm mesh with fine_radius 0.7
#: and growth 0.3 (3,775).
STICK_SLIP_RING = SphereOnBlock(
    size_profile=((0.0, 0.05), (0.35, 0.05), (0.39, 0.03), (0.50, 0.03), (0.54, 0.05), (0.62, 0.05)),
    growth=0.45,
)


def platen(approach: float, tangential_force: float = 0.0) -> list:
    """Conditions on the sphere's flat base: pushed down by ``approach``
    (displacement control), held in y, and force controlled in x with
    ``tangential_force`` (the Cattaneo–Mindlin loading Q)."""
    return [
        Displacement((None, 0.0, -float(approach))),
        Force((float(tangential_force), None, None)),
    ]


def checked_setup(who: str, setup: SphereOnBlock | None, fine_size) -> SphereOnBlock:
    """``setup`` (default :class:`SphereOnBlock`) once ``fine_size`` fits
    it (a :class:`ConfigError` naming ``who`` otherwise)."""
    s = setup or SphereOnBlock()
    if not (isinstance(fine_size, (int, float)) and 0 < fine_size <= s.fine_radius):
        raise ConfigError(
            f"{who}: fine_size must be in (0, fine_radius = {s.fine_radius:g}], got {fine_size!r}"
        )
    return s


def sphere_on_block(
    fine_size: float,
    approach: float = 0.03,
    friction_coefficient: float = 0.0,
    setup: SphereOnBlock | None = None,
    order: int = 1,
    normal_force: float | None = None,
) -> ContactProblem:
    """A hemisphere (body ``sphere``, apex at the origin, flat base at
    z = R) on a block (body ``block``, top face z = 0, base clamped), both
    meshed with element size ``fine_size`` within ``setup.fine_radius`` of
    the contact point.  The sphere's base is a rigid platen (see
    :func:`platen`; change its values with :class:`LoadStep`\\ s
    ``{"sphere": {"base": platen(...)}}``); without friction it is held
    in x as well (nothing else would: the frame lies on the flat block, so
    every contact normal is the z axis).  Identical materials, so the
    normal and tangential problems decouple (Cattaneo–Mindlin's setting).
    With ``normal_force`` the base is pushed down by that force instead of
    by ``approach`` (force control from the first touch at the apex; the
    approach is then the platen's computed translation)."""
    s = checked_setup("sphere_on_block", setup, fine_size)
    if normal_force is not None and not (
        isinstance(normal_force, (int, float)) and math.isfinite(normal_force) and normal_force > 0
    ):
        raise ConfigError(f"sphere_on_block: normal_force must be a number > 0, got {normal_force!r}")
    w, d = s.block_half_width, s.block_depth
    blk = geometry.graded_block(
        (-w, -w, -d), (w, w, 0.0), (0.0, 0.0, 0.0), fine_size=fine_size,
        coarse_size=s.coarse_size, order=order, **s.grading(),
    )
    cap = s.hemisphere(fine_size, 0.0, 1, order)
    mat = LinearElastic(s.youngs_modulus, s.poisson_ratio)
    block = ElasticBody(blk, mat, {"zmin": Fixed()}, name="block")
    # frictionless: nothing holds the sphere in x on the flat frame, so the
    # platen is held there too (force control needs friction)
    if normal_force is not None:
        held = (None, 0.0, None) if friction_coefficient > 0 else (0.0, 0.0, None)
        pushed = (0.0 if friction_coefficient > 0 else None, None, -float(normal_force))
        base = [Displacement(held), Force(pushed)]
    else:
        base = platen(approach) if friction_coefficient > 0 else [Displacement((0.0, 0.0, -float(approach)))]
    sphere = ElasticBody(cap, mat, {"base": base}, name="sphere")
    # the frame on the flat block: its normal is the z axis of Hertz theory
    pair = ContactPair(
        "zmax", "contact", friction_coefficient, search_distance=s.search_distance, frame_on="body1"
    )
    return ContactProblem(block, sphere, pair)


def two_spheres(
    fine_size: float,
    gap: float = 0.01,
    approach: float = 0.06,
    setup: SphereOnBlock | None = None,
    order: int = 1,
    friction_coefficient: float = 0.0,
    frame_on: str = "auto",
    upper_radius: float | None = None,
) -> ContactProblem:
    """Two hemispheres (radius, materials and mesh grading of ``setup``),
    apexes on the z axis ``gap`` apart (the lower one's at z = -gap/2, flat
    base clamped; the upper one's at z = +gap/2), the upper base pushed down
    by ``gap + approach`` (displacement control; Coulomb friction
    ``friction_coefficient``, the frame placed by ``frame_on``).  With
    ``upper_radius`` R2 the upper body is the cap of height R of a sphere
    of radius R2 (two convex spheres of different radii).  The bodies start
    apart: the frame pairs the surfaces by normal projection within
    ``gap + 0.6 fine_radius^2 (1/R + 1/R2)`` (the initial gap over the fine
    zone) and the contact closes under load.  Hertz with R_eff = R R2 /
    (R + R2) (R/2 for identical spheres): a = sqrt(R_eff approach)."""
    s = checked_setup("two_spheres", setup, fine_size)
    for name, v in (("gap", gap), ("approach", approach)):
        if not (isinstance(v, (int, float)) and 0 <= v < s.radius):
            raise ConfigError(f"two_spheres: {name} must be in [0, R = {s.radius:g}), got {v!r}")
    r2 = s.radius if upper_radius is None else upper_radius
    if not (isinstance(r2, (int, float)) and math.isfinite(r2) and r2 >= s.radius):
        raise ConfigError(f"two_spheres: upper_radius must be a number >= R = {s.radius:g}, got {r2!r}")
    caps = [s.hemisphere(fine_size, -0.5 * gap, -1, order),
            geometry.spherical_cap(r2, s.radius, apex=(0.0, 0.0, 0.5 * gap), axis=1,
                                   fine_size=fine_size, coarse_size=s.coarse_size, order=order,
                                   **s.grading())]
    mat = LinearElastic(s.youngs_modulus, s.poisson_ratio)
    lower = ElasticBody(caps[0], mat, {"base": Fixed()}, name="lower")
    upper = ElasticBody(
        caps[1], mat, {"base": Displacement((0.0, 0.0, -float(gap + approach)))}, name="upper"
    )
    search = gap + 0.6 * s.fine_radius**2 * (1.0 / s.radius + 1.0 / r2)
    pair = ContactPair("contact", "contact", friction_coefficient, search_distance=search,
                       frame_on=frame_on)
    return ContactProblem(lower, upper, pair)


def tangential_steps(
    forces, approach: float = 0.03, increments: int = 2, label: str = "Q"
) -> list[LoadStep]:
    """Load steps of :func:`sphere_on_block` that change the platen's
    tangential force to each value of ``forces`` in turn, the approach held
    at ``approach`` (pass the value the problem was built with)."""
    return [
        LoadStep({"sphere": {"base": platen(approach, q)}}, increments, f"{label}={q:.6g}")
        for q in forces
    ]


def cattaneo_mindlin_history(
    normal_force: float, mu: float, small: float, ratios, increments: int = 4
) -> list[LoadStep]:
    """The load steps of the Cattaneo–Mindlin validation on
    :data:`STICK_SLIP_RING`: the normal approach (step ``P``), a small
    all-stick tangential force ``small`` μP, then the forces ``ratios`` × μP
    in ``increments`` increments each."""
    return (
        [LoadStep(label="P")]
        + tangential_steps([small * mu * normal_force], increments=1, label="small")
        + tangential_steps([x * mu * normal_force for x in ratios], increments=increments)
    )


def fretting_history(
    normal_force: float, mu: float, small: float, ratios, loop_increments: int
) -> tuple[list[LoadStep], float]:
    """The validation's loading history of :func:`sphere_on_block` with
    friction: the normal approach (step ``P``), a small all-stick tangential
    force ``small`` μP, the Cattaneo–Mindlin forces ``ratios`` × μP (2
    increments each), then one fretting cycle Q* -> -Q* -> Q* (Q* the last
    ratio's force) in ``loop_increments`` increments per branch.  Returns
    (steps, Q*)."""
    q_max = ratios[-1] * mu * normal_force
    down = np.linspace(q_max, -q_max, loop_increments + 1)[1:]
    steps = (
        [LoadStep(label="P")]
        + tangential_steps([small * mu * normal_force], increments=1, label="small")
        + tangential_steps([x * mu * normal_force for x in ratios], increments=2)
        + tangential_steps(down, increments=1, label="unload")
        + tangential_steps(-down, increments=1, label="reload")
    )
    return steps, float(q_max)


@dataclass(frozen=True)
class PunchOnBlock:
    """Sizes and materials of :func:`punch_on_block` (defaults: a punch of
    radius a = 1 mm and height a, ``stiffness_ratio`` times stiffer than the
    steel block 20 x 20 x 10 mm, so a/L = 0.05 and a/depth = 0.1).

    The block's top face is meshed by :func:`geometry.graded_block` with a
    ``size_profile``: ``center_size`` under the punch's centre, the rim
    size at r = a (uniform over a band of +-2 rim sizes), and ``growth``
    per unit distance on both sides of the band."""

    radius: float = 1.0
    youngs_modulus: float = 210000.0
    poisson_ratio: float = 0.3
    stiffness_ratio: float = 1.0e4
    block_half_width: float = 10.0
    block_depth: float = 10.0
    center_size: float = 0.15
    coarse_size: float = 4.0
    growth: float = 0.3
    search_distance: float = 0.05

    @property
    def contact_modulus(self) -> float:
        """E* of the pair (the punch's own compliance included)."""
        E, nu = self.youngs_modulus, self.poisson_ratio
        return effective_modulus(E, nu, self.stiffness_ratio * E, nu)


def punch_on_block(rim_size: float, indentation: float = 1.0e-3, setup: PunchOnBlock | None = None,
                   order: int = 1) -> ContactProblem:
    """A flat-ended cylinder (body ``punch``, flat end the disc r <= a at
    z = 0, region ``contact``) pushed down by ``indentation`` through its top
    face (all components prescribed) into a block (body ``block``, top face
    z = 0, base clamped); frictionless, the frame on the block.  Element size
    ``rim_size`` at the rim on both bodies.  Boussinesq: F = 2 a E* delta for
    a half-space; see :func:`block_compliance` for the finite block."""
    s = setup or PunchOnBlock()
    a = s.radius
    if not (isinstance(rim_size, (int, float)) and 0 < rim_size <= min(s.center_size, 0.1 * a)):
        raise ConfigError(
            f"punch_on_block: rim_size must be in (0, min(center_size, 0.1 radius) = "
            f"{min(s.center_size, 0.1 * a):g}], got {rim_size!r}"
        )
    if not (isinstance(indentation, (int, float)) and 0 < indentation < 0.1 * a):
        raise ConfigError(f"punch_on_block: indentation must be in (0, 0.1 radius), got {indentation!r}")
    h, hc, g = float(rim_size), s.center_size, s.growth
    band = 2.0 * h
    knots = [(0.0, hc), (max(a - band - (hc - h) / g, 0.5 * (a - band)), hc), (a - band, h), (a + band, h)]
    if knots[1][0] >= knots[2][0]:  # rim_size == center_size: no inward ramp
        knots.pop(1)
    w, d = s.block_half_width, s.block_depth
    blk = geometry.graded_block(
        (-w, -w, -d), (w, w, 0.0), (0.0, 0.0, 0.0), fine_size=h, coarse_size=s.coarse_size,
        size_profile=knots, growth=g, order=order,
    )
    pm = geometry.punch(
        a, a, fine_size=h, coarse_size=min(s.coarse_size, 0.5 * a),
        center_size=min(2.0 * hc, 0.5 * a), growth=g, order=order,
    )
    E, nu = s.youngs_modulus, s.poisson_ratio
    block = ElasticBody(blk, LinearElastic(E, nu), {"zmin": Fixed()}, name="block")
    punch = ElasticBody(
        pm, LinearElastic(s.stiffness_ratio * E, nu),
        {"top": Displacement((0.0, 0.0, -float(indentation)))}, name="punch",
    )
    pair = ContactPair("zmax", "contact", 0.0, search_distance=s.search_distance * a, frame_on="body1")
    return ContactProblem(block, punch, pair)


@dataclass(frozen=True)
class BlockCompliance:
    """The finite block's departure from the half-space near a loaded disc
    (:func:`block_compliance`).

    compliance:
        Extra normal displacement per unit force, w_block - w_half-space
        (length/force; < 0 when the block is stiffer, e.g. a clamped base).
    spread:
        Standard deviation of w_block - w_half-space over the nodes with
        r < 0.7 a, relative to the mean half-space displacement there: how
        far the departure is from a uniform shift.
    force:
        Resultant of the applied (interpolated) load.
    """

    compliance: float
    spread: float
    force: float


def block_compliance(block: ElasticBody, radius: float, region: str = "zmax",
                     center=(0.0, 0.0), threads: int | None = None) -> BlockCompliance:
    """Measure how much a finite block's surface displacement near a loaded
    disc departs from the half-space's, per unit force.

    The block (its own conditions elsewhere, ``region`` a face z = const
    with outward normal +z) is loaded on the disc of ``radius`` about
    ``center`` by Hertz's pressure p0 sqrt(1 - r^2/a^2), whose half-space
    displacement pi p0 (2a^2 - r^2) / (4 a E*) is known in closed form, and
    the difference w_block - w_half-space is averaged over the nodes with
    r < 0.7 a.  For a small disc the departure is the smooth response of the
    far boundaries (base, sides) to what is nearly a point force: a uniform
    shift proportional to the force and nearly independent of how the force
    is spread (``spread`` checks that), so it corrects an indentation
    measured on the same block:  delta_half-space = delta - compliance * F."""
    a = float(radius)
    if not (a > 0 and np.isfinite(a)):
        raise ConfigError(f"block_compliance: radius must be a finite number > 0, got {radius!r}")
    cx, cy = (float(c) for c in center)
    p0 = 1.0  # linear: any scale

    def load(points, normals):
        r = np.hypot(points[:, 0] - cx, points[:, 1] - cy)
        t = np.zeros_like(points)
        t[:, 2] = -p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
        return t

    conditions = {**block.boundary_conditions, region: Traction(load)}
    loaded = ElasticBody(
        block.mesh, block.material, conditions, quadrature=block.quadrature,
        discretization=block.discretization_options, name=block.name,
    )
    sol = loaded.solve(threads=threads)
    force = -float(sol.reaction(region)[2])
    i = sol.nodes_of(region)
    r = np.hypot(sol.points[i, 0] - cx, sol.points[i, 1] - cy)
    inner = r < 0.7 * a
    m = block.material
    es = m.youngs_modulus / (1.0 - m.poisson_ratio**2)
    w_half = np.pi * p0 * (2 * a * a - r[inner] ** 2) / (4 * a * es)
    diff = -sol.displacement[i[inner], 2] - w_half
    return BlockCompliance(
        compliance=float(diff.mean() / force),
        spread=float(diff.std() / w_half.mean()),
        force=force,
    )


# --------------------------------------------------------------------------- measures


def platen_history(result, body: str = "sphere", region: str = "base", component: int = 0):
    """(Q, U): per load step of ``result.history``, the resultant of the
    platen's tractions and its translation in ``component`` (for
    :func:`sphere_on_block`: the tangential force and displacement)."""
    Q = np.array([s.bodies[[*s.names].index(body)].reaction(region)[component] for s in result.history])
    U = np.array([s.control_displacements[body][region][component] for s in result.history])
    return Q, U


def tangential_approach(Q, U, contact_radius: float, S: float, reference: int = 1,
                        origin: int = 0) -> np.ndarray:
    """Cattaneo–Mindlin's tangential approach from the platen's (Q, U),
    measured from the state ``origin`` (Q = 0 after the normal load: the
    platen's translation there, a drift of the discrete solution under a
    purely normal load, is not part of the approach).  The translation also
    holds the finite bodies' linear elastic compliance (the "distant
    points" of the theory are a half-space notion); it is measured as dU/dQ
    at an all-stick step ``reference`` (a small Q) and replaced by the
    contact's own initial compliance S / (8 a)."""
    Q, U = np.asarray(Q, dtype=float), np.asarray(U, dtype=float)
    dQ, dU = Q - Q[origin], U - U[origin]
    bulk = dU[reference] / dQ[reference] - S / (8.0 * contact_radius)
    return dU - bulk * dQ


def radial_profile(frame: FrameResult, center=(0.0, 0.0)) -> tuple[np.ndarray, ...]:
    """(r, pressure, q_x, weights, state) at the frame nodes, r the distance
    from ``center`` in the x-y plane, q_x the x traction on body 1 (the
    block), sorted by r."""
    r = np.hypot(frame.points[:, 0] - center[0], frame.points[:, 1] - center[1])
    o = np.argsort(r, kind="stable")
    # the frame's traction acts on body 2; body 1 receives the opposite
    return r[o], frame.pressure[o], -frame.tangential_traction[o, 0], frame.weights[o], frame.state[o]


def weighted_l2(values, exact, weights) -> float:
    """sqrt(sum w (v - e)^2 / sum w e^2): the relative L2 error of nodal
    values with the frame's nodal weights as quadrature."""
    v, e, w = (np.asarray(x, dtype=float) for x in (values, exact, weights))
    return float(np.sqrt(np.sum(w * (v - e) ** 2) / np.sum(w * e**2)))


@dataclass(frozen=True)
class BoussinesqErrors:
    """Relative errors of a :func:`punch_on_block` solve against Boussinesq
    for the computed force F: the force against 2 a E* delta (``raw_force``)
    and against 2 a E* (delta - c F), the indentation corrected by the
    block's measured compliance c (``force``); the pressure profile's
    weighted L2 error on r < 0.8 a (``profile_l2``)."""

    raw_force: float
    force: float
    profile_l2: float


def boussinesq_errors(result, setup: PunchOnBlock, indentation: float,
                      compliance: BlockCompliance) -> BoussinesqErrors:
    F, a, es = result.normal_force, setup.radius, setup.contact_modulus
    r, p, _, w, _ = radial_profile(result.frame)
    inner = r < 0.8 * a
    return BoussinesqErrors(
        raw_force=F / boussinesq_punch_force(a, indentation, es) - 1.0,
        force=F / boussinesq_punch_force(a, indentation - compliance.compliance * F, es) - 1.0,
        profile_l2=weighted_l2(p[inner], boussinesq_punch_pressure(r[inner], a, F), w[inner]),
    )


@dataclass(frozen=True)
class HertzErrors:
    """Relative errors of a computed pressure field against Hertz for the
    computed force: contact radius (from a least-squares fit of
    p^2 = p0^2 (1 - r^2/a^2) on r < 0.9 a), peak pressure (largest nodal
    pressure) and the profile's weighted L2 error on r < 0.9 a."""

    contact_radius: float
    peak_pressure: float
    profile_l2: float
    fitted_radius: float
    fitted_peak: float


def hertz_errors(frame: FrameResult, h: Hertz, center=(0.0, 0.0)) -> HertzErrors:
    r, p, _, w, _ = radial_profile(frame, center)
    a = h.contact_radius
    inner = r < 0.9 * a
    A = np.column_stack([np.ones(inner.sum()), r[inner] ** 2])
    c, *_ = np.linalg.lstsq(A, p[inner] ** 2, rcond=None)
    p0 = float(np.sqrt(max(c[0], 0.0)))
    af = float(np.sqrt(-c[0] / c[1])) if c[1] < 0 else np.inf
    return HertzErrors(
        contact_radius=af / a - 1.0,
        peak_pressure=float(p.max()) / h.peak_pressure - 1.0,
        profile_l2=weighted_l2(p[inner], h.pressure(r[inner]), w[inner]),
        fitted_radius=af,
        fitted_peak=p0,
    )


def stick_radius(frame: FrameResult) -> float:
    """Radius of the circle with the area of the stuck frame nodes
    (sqrt(sum of their weights / pi))."""
    return float(np.sqrt(frame.weights[frame.state == STICK].sum() / np.pi))


#: The stuck points that locate the stick–slip front: those whose traction
#: is within this fraction of the friction limit (g = 1 − |q|/(μp) < 0.5).
FRONT_BAND = 0.5


def stick_front_radius(xy, pressure, shear, state, weights, friction_coefficient: float,
                       band: float = FRONT_BAND) -> float:
    """The stick radius of a partial-slip contact located from the traction
    near the stick–slip front, not from the area of the stuck points.

    ``xy`` (n, 2) the points in the contact plane, ``pressure`` (n,) and
    ``shear`` (n,) the magnitudes of the normal and tangential traction
    there, ``state`` (n,) their contact states, ``weights`` (n,) their areas
    (frame nodes' weights, or the cells' area).  With the contact radius a
    from the area of the closed points and r the distance from their
    pressure-weighted centre, each stuck point of g = 1 − |q|/(μp) < ``band``
    gives c² = r² + g² (a² − r²); the radius is the root of their mean.

    Why: Mindlin's traction inside the stick zone has exactly g² = (c² −
    r²)/(a² − r²), and near any smooth stick–slip front g² falls linearly to
    zero, so the estimate uses the field's values where the front is; the
    area of the points marked stuck counts whole cells (or nodal areas)
    across the front, an error of a fraction of a cell that is first order in
    the spacing.  NaN when no stuck point lies in the band."""
    xy, p, q, w = (np.asarray(v, dtype=float) for v in (xy, pressure, shear, weights))
    state = np.asarray(state)
    closed = (state != OPEN) & (p > 0.0)
    if not closed.any():
        return float("nan")
    a2 = float(w[closed].sum()) / math.pi
    load = (w * p)[closed]
    centre = (xy[closed] * load[:, None]).sum(axis=0) / load.sum()
    r2 = ((xy - centre) ** 2).sum(axis=1)
    g = 1.0 - q / (friction_coefficient * np.where(p > 0.0, p, 1.0))
    near = (state == STICK) & (p > 0.0) & (g >= 0.0) & (g < band)
    if not near.any():
        return float("nan")
    return float(np.sqrt(np.mean(r2[near] + g[near] ** 2 * (a2 - r2[near]))))


def fitted_rate(sizes, errors) -> float:
    """Slope of log(error) against log(size) (least squares)."""
    return float(np.polyfit(np.log(sizes), np.log(np.abs(errors)), 1)[0])


__all__ = [
    "SphereOnBlock",
    "checked_setup",
    "sphere_on_block",
    "platen",
    "tangential_steps",
    "fretting_history",
    "cattaneo_mindlin_history",
    "two_spheres",
    "STICK_SLIP_RING",
    "PunchOnBlock",
    "punch_on_block",
    "BlockCompliance",
    "block_compliance",
    "BoussinesqErrors",
    "boussinesq_errors",
    "radial_profile",
    "platen_history",
    "tangential_approach",
    "weighted_l2",
    "HertzErrors",
    "hertz_errors",
    "stick_radius",
    "FRONT_BAND",
    "stick_front_radius",
    "fitted_rate",
]

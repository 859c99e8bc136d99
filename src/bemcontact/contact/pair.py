"""A contact pair: which surfaces of two bodies may touch, and how."""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ConfigError
from ..settings import Key, check_settings, setting


#: Values of :attr:`ContactPair.frame_on`.
FRAME_ON = ("auto", "between", "coarser", "body1", "body2")
#: Values of :attr:`ContactPair.frame`.
FRAME_RULES = ("mortar", "collocation")
#: Values of :attr:`ContactPair.relative_displacement`.
RELATIVE_DISPLACEMENTS = ("projected", "weighted")
#: How a pair is solved: on the frame at full resolution, on a contact grid
#: with the bodies' coarse corrections, or chosen by applicability.
METHODS = ("full", "multiscale", "auto")


@dataclass(frozen=True)
class ContactPair:
    """Which surfaces of the two bodies may touch, and how.

    Attributes
    ----------
    surface1, surface2:
        Region names of body 1 and body 2 forming the contact interface.
    friction_coefficient:
        Coulomb coefficient mu >= 0 (0: frictionless).
    frame:
        Frame discretization rule: ``"mortar"`` (default; area-consistent
        coupling, passes the patch test) or ``"collocation"`` (the paper's
        point evaluation of the frame basis at the body nodes; for comparison).
    search_distance:
        Largest distance along the normal at which points of the two
        surfaces are paired (length units).  Bodies that start apart (curved
        surfaces, an initial gap) need it at least as large as the initial
        gap anywhere the contact zone may grow to.  Default: a quarter of the
        largest contact element (enough for surfaces that start in touch).
        Pairing is by normal projection; the initial gap comes from the
        geometry.
    frame_on:
        Where the frame lies (its nodes, elements and local bases, hence the
        normal direction of the gap and of the slip): ``"auto"`` (default)
        on the flat surface when exactly one of the two is flat (the contact
        plane of small-slope theories: a sphere, cylinder or punch on a
        block), between the surfaces when both are curved (gears, bearings,
        crossed cylinders, a ball in a groove), on the coarser one when both
        are flat; or always ``"between"`` the two surfaces (the coarser
        surface's elements moved midway, normals bisecting the surfaces'
        normals: docs/frame.md), or on a surface: ``"coarser"`` (independent
        of the body order), ``"body1"`` or ``"body2"``.  A frame on a curved
        surface tilts the normal by r/R against the contact surface, so the
        relative approach shows a tangential component of order a/R that
        friction resists (measured between two identical spheres: up to
        0.038 p0 of shear where symmetry gives none; 0.0086 p0 between).
    penalty:
        This pair's augmentation factor c of r = c E*/h (default: that of
        the :class:`~bemcontact.contact.SolverOptions`).  It changes the
        Newton path, not the converged solution.
    bodies:
        The names of the bodies of ``surface1`` and ``surface2``, in that
        order (the frame normal points from the first into the second).
        Needed in an assembly (:class:`~bemcontact.contact.ContactProblem`
        with ``bodies=`` and ``pairs=``); in a two-body problem optional, and
        if given it must name body 1 and body 2.
    relative_displacement:
        What the nodal contact law acts on (docs/frame.md): ``"projected"``
        (default) the L2 projection of the bodies' relative displacement on
        the frame's linear basis, M_f k = ∫ N [u] (M_f the frame's consistent
        mass), so that k_j is the value at node j; or ``"weighted"`` its
        average over the node's support, a_j k_j = ∫ N_j [u] (the weighted
        gap of mortar methods), which spreads each stick or contact
        condition over two elements and smears the stick-slip front and the
        contact edge (Cattaneo–Mindlin traction error 12 % against 3.9 %
        projected at a/h = 12).  ``frame = "collocation"`` (the paper's point
        evaluation, for comparison) always takes the weighted one.
    """

    surface1: str
    surface2: str
    friction_coefficient: float = setting(Key(
        "friction_coefficient", "number", "Coulomb coefficient μ (0: frictionless)",
        default=0.0, lo=0))
    frame: str = setting(Key(
        "frame", "string", "frame coupling rule: mortar passes the contact patch test; "
        "collocation is the founding paper's rule, for comparison", default="mortar",
        choices=FRAME_RULES))
    search_distance: float | None = setting(Key(
        "search_distance", "number", "largest distance (length) along the normal at which "
        "the surfaces are paired; bodies that start apart need at least their initial gap "
        "wherever contact may reach", default=None, lo=0, lo_open=True,
        default_text="a quarter of the largest contact element"))
    frame_on: str = setting(Key(
        "frame_on", "string", "where the frame lies", default="auto",
        choices=FRAME_ON))
    relative_displacement: str = setting(Key(
        "relative_displacement", "string", "what the nodal contact law acts on: the relative "
        "displacement `projected` on the frame's linear basis (nodal values) or `weighted` "
        "over each node's support (mortar weighted gap)", default="projected",
        choices=RELATIVE_DISPLACEMENTS))
    penalty: float | None = setting(Key(
        "penalty", "number", "this pair's augmentation factor c (overrides "
        "`solver.penalty`)", default=None, lo=1e-2, hi=1e2,
        default_text="`solver.penalty`"))
    method: str = setting(Key(
        "method", "string", "how the pair is solved: `full` (both bodies condensed on the "
        "frame at the contact's resolution), `multiscale` (the contact zone on a regular grid: "
        "the pair's half-space operator plus each body's correction from its own, coarse, "
        "mesh; bodies loaded through rigid supports and platen forces; an assembly: one "
        "grid per pair, coupled through the bodies they share) or `auto` "
        "(`full` when both meshes have 4 or more elements per contact half-width at the "
        "contact, else `multiscale` where it applies and its error estimate is small, else "
        "`full`; the choice is said in one line).  An assembly's pairs follow one method: "
        "`full` if any pair asks for it, else `multiscale` if any does, else `auto`",
        default="auto", choices=METHODS))
    grid_size: float | None = setting(Key(
        "grid_size", "number", "the cell size (a length) of the multiscale contact grid",
        default=None, lo=0, lo_open=True,
        default_text="the largest contact's smaller half-width / 25"))
    bodies: tuple[str, str] | None = None

    def __post_init__(self) -> None:
        for name in ("surface1", "surface2"):
            v = getattr(self, name)
            if not isinstance(v, str) or not v:
                raise ConfigError(f"ContactPair.{name} must be a region name, got {v!r}")
        if self.bodies is not None:
            b = self.bodies
            if (isinstance(b, str) or not hasattr(b, "__len__") or len(b) != 2
                    or not all(isinstance(x, str) and x for x in b)):
                raise ConfigError(f"ContactPair.bodies must be two body names, got {b!r}")
            if b[0] == b[1]:
                raise ConfigError(
                    f"ContactPair.bodies names {b[0]!r} twice; a pair couples two bodies")
            object.__setattr__(self, "bodies", (b[0], b[1]))
        check_settings(self)

    @property
    def label(self) -> str:
        """``body1:surface1/body2:surface2`` (``surface1/surface2`` without
        body names): the pair in messages."""
        if self.bodies is None:
            return f"{self.surface1}/{self.surface2}"
        return f"{self.bodies[0]}:{self.surface1}/{self.bodies[1]}:{self.surface2}"


__all__ = ["ContactPair", "FRAME_ON", "FRAME_RULES", "METHODS", "RELATIVE_DISPLACEMENTS"]

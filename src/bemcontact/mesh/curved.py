"""Graded gmsh meshes of curved contact bodies beyond the sphere (optional
dependency gmsh, as :mod:`bemcontact.mesh.shapes`): :func:`half_cylinder`
(two of them crossed at right angles touch at a point, a circular Hertz
contact for equal radii) and :func:`spherical_seat`, a block with a
spherical dimple (a concave surface: a ball of a slightly smaller radius in
it is a conforming contact).  Both are graded toward the point that touches
first, with the grading arguments of :func:`~bemcontact.mesh.shapes.spherical_cap`
(``fine_size`` within ``fine_radius`` of that point, or the knots of
``size_profile``, then growing by ``growth`` per unit distance up to
``coarse_size``).
"""

from __future__ import annotations

import math

from ..errors import ConfigError
from .shapes import (
    _axis, _expect_regions, _grading, _grading_ramp, _mesh_with_gmsh, _number, _point,
)
from .surface import SurfaceMesh

#: Relative tolerance of the face classification (face centroids vs planes).
_FACE_TOL = 1e-9


def half_cylinder(
    radius: float,
    length: float,
    *,
    fine_size: float,
    coarse_size: float,
    fine_radius: float | None = None,
    apex=(0.0, 0.0, 0.0),
    axis: int = 1,
    direction: str = "x",
    growth: float = 0.3,
    order: int = 1,
    size_profile=None,
) -> SurfaceMesh:
    """The half of a solid circular cylinder (radius ``radius``, length
    ``length`` along the ``direction`` "x" or "y", centred on ``apex``) on
    one side of the plane through its axis normal to z, meshed with triangles
    graded toward ``apex``, the point of its curved face nearest that plane's
    opposite side (the point that touches first).

    ``axis`` +1: the body lies above the apex (cylinder axis at apex +
    R e_z, flat face there), pressing down on a counter-body; -1: below.
    ``order`` 1: flat tri3; 2: curved tri6 with midside nodes on the
    cylinder.  Grading arguments as for
    :func:`~bemcontact.mesh.shapes.spherical_cap` (distance from ``apex``).

    Regions: ``contact`` (the curved face), ``base`` (the flat rectangle
    through the axis) and ``ends`` (the two half discs).  Example, two
    cylinders R = 10 crossed at right angles, touching at the origin::

        half_cylinder(10, 20, fine_size=0.1, coarse_size=2.5, fine_radius=0.8,
                      axis=-1, direction="x")
        half_cylinder(10, 20, fine_size=0.1, coarse_size=2.5, fine_radius=0.8,
                      axis=1, direction="y")
    """
    name = "half_cylinder"
    R = _number(name, "radius", radius)
    L = _number(name, "length", length)
    if direction not in ("x", "y"):
        raise ConfigError(f"{name}: direction must be 'x' or 'y', got {direction!r}")
    fine, coarse, g = _grading(name, fine_size, coarse_size, growth)
    ramp = _grading_ramp(name, fine, coarse, g, fine_radius, size_profile)
    a = _point(name, "apex", apex)
    ax = _axis(name, axis)
    along = 0 if direction == "x" else 1
    z_axis = a[2] + ax * R

    def build(gmsh):
        occ = gmsh.model.occ
        start = list(a)
        start[along] -= 0.5 * L
        start[2] = z_axis
        vec = [0.0, 0.0, 0.0]
        vec[along] = L
        cyl = occ.addCylinder(*start, *vec, R)
        # a box holding the half between the apex' side and the axis plane
        z_lo = a[2] - R if ax > 0 else z_axis
        box = occ.addBox(a[0] - R - L, a[1] - R - L, z_lo, 2 * (R + L), 2 * (R + L), 2 * R)
        vol, _ = occ.intersect([(3, cyl)], [(3, box)])
        occ.synchronize()
        faces = [t for _, t in gmsh.model.getBoundary(vol, oriented=False)]
        occ.remove(vol)
        occ.synchronize()
        groups: dict[str, list[int]] = {"contact": [], "base": [], "ends": []}
        for t in faces:
            c = occ.getCenterOfMass(2, t)
            if abs(c[2] - z_axis) <= _FACE_TOL * R:
                groups["base"].append(t)
            elif abs(abs(c[along] - a[along]) - 0.5 * L) <= _FACE_TOL * (R + L):
                groups["ends"].append(t)
            else:
                groups["contact"].append(t)
        for key, tags in groups.items():
            gmsh.model.addPhysicalGroup(2, tags, name=key)

    def size(x: float, y: float, z: float) -> float:
        return ramp(math.sqrt((x - a[0]) ** 2 + (y - a[1]) ** 2 + (z - a[2]) ** 2))

    mesh = _mesh_with_gmsh(build, (fine, coarse), order, name, size)
    return _expect_regions(mesh, {"contact", "base", "ends"}, name)


def spherical_seat(
    radius: float,
    depth: float,
    half_width: float,
    height: float,
    *,
    fine_size: float,
    coarse_size: float,
    fine_radius: float | None = None,
    bottom=(0.0, 0.0, 0.0),
    growth: float = 0.3,
    order: int = 1,
    size_profile=None,
) -> SurfaceMesh:
    """A block with a spherical dimple opening upward (+z): the box of
    half-width ``half_width`` in x and y around ``bottom``, from ``height``
    below the dimple's lowest point ``bottom`` up to ``depth`` above it,
    minus the ball of radius ``radius`` centred at ``bottom`` + R e_z.  Meshed
    with triangles graded toward ``bottom`` (grading arguments as for
    :func:`~bemcontact.mesh.shapes.spherical_cap`); ``order`` 1 or 2.

    The dimple's rim, of radius sqrt(depth (2R - depth)), must lie inside
    the top face (``depth`` < R and rim radius < ``half_width``).

    Regions: ``contact`` (the dimple), ``top`` (the flat top around it),
    ``side`` (the four sides) and ``base`` (the bottom face).
    """
    name = "spherical_seat"
    R = _number(name, "radius", radius)
    d = _number(name, "depth", depth)
    W = _number(name, "half_width", half_width)
    H = _number(name, "height", height)
    if not d < R:
        raise ConfigError(f"{name}: depth = {depth!r} must be below radius = {radius!r}")
    rim = math.sqrt(d * (2 * R - d))
    if not rim < W:
        raise ConfigError(
            f"{name}: the dimple's rim radius sqrt(depth (2 radius - depth)) = {rim:.6g} must "
            f"be below half_width = {half_width!r}"
        )
    fine, coarse, g = _grading(name, fine_size, coarse_size, growth)
    ramp = _grading_ramp(name, fine, coarse, g, fine_radius, size_profile)
    b = _point(name, "bottom", bottom)
    z_top, z_base = b[2] + d, b[2] - H

    def build(gmsh):
        occ = gmsh.model.occ
        box = occ.addBox(b[0] - W, b[1] - W, z_base, 2 * W, 2 * W, H + d)
        ball = occ.addSphere(b[0], b[1], b[2] + R, R)
        vol, _ = occ.cut([(3, box)], [(3, ball)])
        occ.synchronize()
        faces = [t for _, t in gmsh.model.getBoundary(vol, oriented=False)]
        occ.remove(vol)
        occ.synchronize()
        groups: dict[str, list[int]] = {"contact": [], "top": [], "side": [], "base": []}
        tol = _FACE_TOL * (W + H + R)
        for t in faces:
            c = occ.getCenterOfMass(2, t)
            if abs(c[2] - z_base) <= tol:
                groups["base"].append(t)
            elif abs(c[2] - z_top) <= tol:
                groups["top"].append(t)
            elif max(abs(c[0] - b[0]), abs(c[1] - b[1])) >= W - tol:
                groups["side"].append(t)
            else:
                groups["contact"].append(t)
        for key, tags in groups.items():
            gmsh.model.addPhysicalGroup(2, tags, name=key)

    def size(x: float, y: float, z: float) -> float:
        return ramp(math.sqrt((x - b[0]) ** 2 + (y - b[1]) ** 2 + (z - b[2]) ** 2))

    mesh = _mesh_with_gmsh(build, (fine, coarse), order, name, size)
    return _expect_regions(mesh, {"contact", "top", "side", "base"}, name)


__all__ = ["half_cylinder", "spherical_seat"]

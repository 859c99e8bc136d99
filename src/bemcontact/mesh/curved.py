"""Graded gmsh meshes of curved contact bodies beyond the sphere (optional
dependency gmsh, as :mod:`bemcontact.mesh.shapes`): :func:`half_cylinder`
(two of them crossed at right angles touch at a point, a circular Hertz
contact for equal radii) and :func:`spherical_seat`, a block with a
spherical dimple (a concave surface: a ball of a slightly smaller radius in
it is a conforming contact).  Both are graded toward the point that touches
first, with the grading arguments of :func:`~bemcontact.mesh.shapes.spherical_cap`
(``fine_size`` within ``fine_radius`` of that point, or the knots of
``size_profile``, then growing by ``growth`` per unit distance up to
``coarse_size``).  :func:`ball`: a whole ball graded toward its two poles,
mirror symmetric in its equator plane (:func:`mirrored`), for a ball between
two bodies.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ConfigError
from .element import REVERSED
from .mesher import (
    around,
    SolidMesh, check_axis, check_grading, check_number, check_point, expect_regions,
    grading_ramp, mesh_with_gmsh, solid_with_gmsh, the_rest,
)
from .shapes import spherical_cap
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
    R = check_number(name, "radius", radius)
    L = check_number(name, "length", length)
    if direction not in ("x", "y"):
        raise ConfigError(f"{name}: direction must be 'x' or 'y', got {direction!r}")
    fine, coarse, g = check_grading(name, fine_size, coarse_size, growth)
    ramp = grading_ramp(name, fine, coarse, g, fine_radius, size_profile)
    a = check_point(name, "apex", apex)
    ax = check_axis(name, axis)
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

    size = around(ramp, a)

    mesh = mesh_with_gmsh(build, (fine, coarse), order, name, size)
    return expect_regions(mesh, {"contact", "base", "ends"}, name)


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
    R = check_number(name, "radius", radius)
    d = check_number(name, "depth", depth)
    W = check_number(name, "half_width", half_width)
    H = check_number(name, "height", height)
    if not d < R:
        raise ConfigError(f"{name}: depth = {depth!r} must be below radius = {radius!r}")
    rim = math.sqrt(d * (2 * R - d))
    if not rim < W:
        raise ConfigError(
            f"{name}: the dimple's rim radius sqrt(depth (2 radius - depth)) = {rim:.6g} must "
            f"be below half_width = {half_width!r}"
        )
    fine, coarse, g = check_grading(name, fine_size, coarse_size, growth)
    ramp = grading_ramp(name, fine, coarse, g, fine_radius, size_profile)
    b = check_point(name, "bottom", bottom)
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

    size = around(ramp, b)

    mesh = mesh_with_gmsh(build, (fine, coarse), order, name, size)
    return expect_regions(mesh, {"contact", "top", "side", "base"}, name)


def mirrored(mesh: SurfaceMesh, z0: float, names: dict[str, str] | None = None) -> SurfaceMesh:
    """``mesh`` reflected in the plane z = ``z0`` (each element's node order
    reversed, so the normals stay outward), its regions renamed by ``names``
    (e.g. ``{"zmin": "zmax", "zmax": "zmin"}`` for a box)."""
    X = mesh.nodes.copy()
    X[:, 2] = 2.0 * float(z0) - X[:, 2]
    E = mesh.elements[:, REVERSED[mesh.element_type]]
    regions = {(names or {}).get(k, k): v for k, v in mesh.regions.items()}
    return SurfaceMesh(X, E, mesh.element_type, regions, source=mesh.source)


def ball(
    radius: float,
    *,
    fine_size: float,
    coarse_size: float,
    fine_radius: float | None = None,
    lowest=(0.0, 0.0, 0.0),
    band: float = 0.3,
    growth: float = 0.3,
    order: int = 1,
    size_profile=None,
    solid: bool = False,
) -> SurfaceMesh | SolidMesh:
    """A solid ball of radius ``radius`` whose lowest point is ``lowest``,
    graded toward its lowest and highest points (the poles, where two
    counter-bodies above and below touch it): the lower hemisphere of
    :func:`~bemcontact.mesh.shapes.spherical_cap` and its mirror image in
    the equator plane, the equator's nodes shared, so the mesh (and a
    problem built symmetrically around it) is exactly mirror symmetric.

    Regions: ``bottom`` and ``top`` (the two caps, the contact surfaces) and
    ``band``, the elements within ``band`` R of the equator plane (0 < band
    < 0.8; where a cage or a support holds the ball).  Grading arguments as
    for :func:`~bemcontact.mesh.shapes.spherical_cap`.  ``solid``: the ball
    meshed with tetrahedra graded toward both poles (as
    :mod:`~bemcontact.mesh.shapes` says; not mirror symmetric)."""
    name = "ball"
    R = check_number(name, "radius", radius)
    if not (isinstance(band, (int, float)) and 0 < band < 0.8):
        raise ConfigError(f"{name}: band must be in (0, 0.8), got {band!r}")
    lo = check_point(name, "lowest", lowest)
    grading = ({"fine_radius": fine_radius} if size_profile is None
               else {"size_profile": size_profile})
    zc = lo[2] + R  # the equator plane
    if solid:
        fine, coarse, g = check_grading(name, fine_size, coarse_size, growth)
        ramp = grading_ramp(name, fine, coarse, g, fine_radius, size_profile)
        low, high = around(ramp, lo), around(ramp, (lo[0], lo[1], lo[2] + 2 * R))

        def build(gmsh):
            vol = gmsh.model.occ.addSphere(lo[0], lo[1], zc, R)
            gmsh.model.occ.synchronize()
            gmsh.model.addPhysicalGroup(3, [vol], name="body")

        return solid_with_gmsh(build, (fine, coarse), name,
                               lambda x, y, z: min(low(x, y, z), high(x, y, z)), {
                                   "band": lambda c: np.abs(c[:, 2] - zc) < band * R,
                                   "bottom": lambda c: c[:, 2] < zc, "top": the_rest})
    cap = spherical_cap(R, R, apex=lo, axis=1, fine_size=fine_size, coarse_size=coarse_size,
                        order=order, growth=growth, **grading)
    curved = cap.region("contact")
    used = np.unique(cap.elements[curved])
    index = np.full(cap.n_nodes, -1)
    index[used] = np.arange(used.size)
    X = cap.nodes[used]
    E = index[cap.elements[curved]]
    # the upper half: reflected nodes, the equator's shared
    on_equator = np.abs(X[:, 2] - zc) <= 1e-9 * R
    new = np.flatnonzero(~on_equator)
    upper = np.arange(X.shape[0])
    upper[new] = X.shape[0] + np.arange(new.size)
    Xm = X[new].copy()
    Xm[:, 2] = 2.0 * zc - Xm[:, 2]
    nodes = np.vstack([X, Xm])
    elements = np.vstack([E, upper[E][:, REVERSED[cap.element_type]]])
    z = nodes[elements].mean(axis=1)[:, 2]
    in_band = np.abs(z - zc) < band * R
    regions = {
        "bottom": np.flatnonzero(~in_band & (z < zc)),
        "band": np.flatnonzero(in_band),
        "top": np.flatnonzero(~in_band & (z > zc)),
    }
    mesh = SurfaceMesh(nodes, elements, cap.element_type, regions, source=name)
    return expect_regions(mesh.oriented().check(), {"bottom", "band", "top"}, name)


__all__ = ["ball", "half_cylinder", "mirrored", "spherical_seat"]

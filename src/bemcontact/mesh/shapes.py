"""Surface meshes of simple solids generated with gmsh (optional dependency:
``pip install gmsh``).  Each returns an outward-oriented, checked
:class:`~bemcontact.mesh.SurfaceMesh` with named regions.

Uniform meshes: :func:`hollow_sphere`, :func:`gmsh_box`.  Meshes graded toward
the expected contact zone, for the classic contact validation cases:
:func:`spherical_cap` (Hertz), :func:`graded_block` (the flat counter-body),
:func:`punch` (Boussinesq's flat-ended cylinder).  In a graded mesh the
element size is ``fine_size`` near the contact zone and grows linearly with
distance, by ``growth`` per unit distance (0.3: each element about 30 % larger
than its neighbour toward the contact), up to ``coarse_size``.
"""

from __future__ import annotations

import math

from ..errors import ConfigError
import numpy as np

from .mesher import (  # noqa: F401  (load_gmsh, GMSH_INSTALL, element_estimate: re-exported)
    around,
    GMSH_INSTALL, SolidMesh, check_axis, check_grading, check_number, check_point,
    element_estimate, expect_regions, grading_ramp, load_gmsh, mesh_with_gmsh, size_ramp,
    solid_with_gmsh, the_rest,
)
from .surface import SurfaceMesh

# ------------------------------------------------------------ uniform meshes
def hollow_sphere(inner_radius: float, outer_radius: float, mesh_size: float, order: int = 2,
                  center=(0.0, 0.0, 0.0)) -> SurfaceMesh:
    """Thick-walled hollow sphere; regions ``inner`` (cavity wall) and ``outer``.
    Triangles (tri3, or curved tri6 with ``order=2``) of size ``mesh_size``."""
    if not 0 < inner_radius < outer_radius:
        raise ConfigError(
            f"hollow_sphere: need 0 < inner_radius < outer_radius, got {inner_radius!r}, "
            f"{outer_radius!r}"
        )

    def build(gmsh):
        occ = gmsh.model.occ
        outer = occ.addSphere(*center, outer_radius)
        inner = occ.addSphere(*center, inner_radius)
        occ.synchronize()
        s_outer = [t for _, t in gmsh.model.getBoundary([(3, outer)], oriented=False)]
        s_inner = [t for _, t in gmsh.model.getBoundary([(3, inner)], oriented=False)]
        occ.remove([(3, outer), (3, inner)])
        occ.synchronize()
        gmsh.model.addPhysicalGroup(2, s_outer, name="outer")
        gmsh.model.addPhysicalGroup(2, s_inner, name="inner")

    mesh = mesh_with_gmsh(build, mesh_size, order, "hollow_sphere")
    return expect_regions(mesh, {"inner", "outer"}, "hollow_sphere")


_BOX_REGIONS = {f"{a}{s}" for a in "xyz" for s in ("min", "max")}


def _on_plane(axis: int, ref: float, tol: float):
    """Chooses faces whose centroids lie on the plane x[axis] = ref."""
    return lambda c: np.abs(c[:, axis] - ref) <= tol


def _box_regions(lo, hi) -> dict:
    tol = 1e-9 * max(b - a for a, b in zip(lo, hi))
    return {f"{'xyz'[a]}{side}": _on_plane(a, ref, tol) for a in range(3)
            for side, ref in (("min", lo[a]), ("max", hi[a]))}


def _box_surfaces(gmsh, lo, hi) -> None:
    """Add the box [lo, hi] as six surfaces (no volume), physical groups
    ``xmin`` .. ``zmax``."""
    occ = gmsh.model.occ
    vol = occ.addBox(*lo, *(b - a for a, b in zip(lo, hi)))
    occ.synchronize()
    faces = [t for _, t in gmsh.model.getBoundary([(3, vol)], oriented=False)]
    occ.remove([(3, vol)])
    occ.synchronize()
    for tag in faces:
        c = occ.getCenterOfMass(2, tag)
        for axis in range(3):
            for side, ref in (("min", lo[axis]), ("max", hi[axis])):
                if abs(c[axis] - ref) <= 1e-9 * (1 + abs(ref)):
                    gmsh.model.addPhysicalGroup(2, [tag], name=f"{'xyz'[axis]}{side}")


def gmsh_box(lower, upper, mesh_size: float, order: int = 1, quads: bool = False,
             seed: int = 0) -> SurfaceMesh:
    """Box [lower, upper] with *unstructured* faces (gmsh frontal-Delaunay
    triangles, or recombined quadrilaterals with ``quads=True``); regions
    ``xmin``, ``xmax``, ``ymin``, ``ymax``, ``zmin``, ``zmax`` as for
    :func:`~bemcontact.mesh.box`.  ``seed`` perturbs gmsh's mesher so that
    two calls give different (non-matching) meshes of the same size."""
    lo = [float(v) for v in lower]
    hi = [float(v) for v in upper]
    if len(lo) != 3 or len(hi) != 3 or not all(b > a for a, b in zip(lo, hi)):
        raise ConfigError(f"gmsh_box: need lower < upper componentwise, got {lower!r}, {upper!r}")

    def build(gmsh):
        gmsh.option.setNumber("Mesh.RandomSeed", 1 + int(seed))
        gmsh.option.setNumber("Mesh.Algorithm", 8 if quads else 6)
        if quads:
            gmsh.option.setNumber("Mesh.RecombineAll", 1)
        _box_surfaces(gmsh, lo, hi)

    mesh = mesh_with_gmsh(build, mesh_size, order, "gmsh_box")
    return expect_regions(mesh, _BOX_REGIONS, "gmsh_box")


# ------------------------------------------------------------- graded meshes
def spherical_cap(
    radius: float,
    height: float,
    *,
    fine_size: float,
    coarse_size: float,
    fine_radius: float | None = None,
    apex=(0.0, 0.0, 0.0),
    axis: int = 1,
    growth: float = 0.3,
    order: int = 2,
    size_profile=None,
    solid: bool = False,
) -> SurfaceMesh | SolidMesh:
    """Solid spherical segment (a Hertz indenter): the part of a ball of
    radius ``radius`` within ``height`` (along z) of its point ``apex``,
    meshed with triangles graded toward the apex.

    Parameters
    ----------
    radius:
        Sphere radius R (length).
    height:
        Distance from the apex to the flat base, 0 < height < 2R: a cap for
        height < R, a hemisphere for height = R.
    fine_size:
        Element size (length) within distance ``fine_radius`` of the apex.
    coarse_size:
        Largest element size (length), >= ``fine_size``.
    fine_radius:
        Radius (length) of the uniformly fine zone around the apex; take it
        larger than the expected contact radius (1.5 to 2 times).  Measured
        as the distance from the apex, which on the sphere is the horizontal
        distance rho to within a factor 1 + rho**2 / (8 R**2).
    apex:
        The point of the sphere that touches first.
    axis:
        +1: the body lies above the apex (centre at apex + R e_z, base at
        apex + height e_z), pressing down on a counter-body; -1: below.
    growth:
        Size gradient beyond ``fine_radius`` (dimensionless; see the module
        docstring).
    order:
        1: flat 3-node triangles; 2: curved 6-node triangles, midside nodes
        on the sphere.
    size_profile:
        Optional (distance, size) knots replacing the uniform fine zone: the
        element size at a distance from the apex, linear between knots
        (distances from 0, increasing; sizes between ``fine_size`` and
        ``coarse_size``), growing by ``growth`` beyond the last knot.  E.g.
        a ring refined at the stick–slip boundary of Cattaneo–Mindlin.
        Give either ``fine_radius`` or ``size_profile``.
    solid:
        Mesh the solid with tetrahedra (module docstring; ``order`` unused).

    Regions: ``contact`` (the curved surface) and ``base`` (the flat disc).
    Example, a hemisphere R = 10 resting on the plane z = 0 with about ten
    elements across a contact diameter of 1::

        spherical_cap(10.0, 10.0, fine_size=0.1, coarse_size=2.5, fine_radius=0.8)
    """
    name = "spherical_cap"
    R = check_number(name, "radius", radius)
    h = check_number(name, "height", height)
    if not h < 2 * R:
        raise ConfigError(
            f"{name}: height = {height!r} must be below 2 * radius = {2 * R!r} (height = radius "
            "is a hemisphere)"
        )
    fine, coarse, g = check_grading(name, fine_size, coarse_size, growth)
    ramp = grading_ramp(name, fine, coarse, g, fine_radius, size_profile)
    a = check_point(name, "apex", apex)
    ax = check_axis(name, axis)
    center = (a[0], a[1], a[2] + ax * R)
    z_base = a[2] + ax * h
    lat = math.asin((h - R) / R)  # latitude of the base plane for axis = +1

    def build(gmsh):
        occ = gmsh.model.occ
        lims = (-math.pi / 2, lat) if ax > 0 else (-lat, math.pi / 2)
        vol = occ.addSphere(*center, R, -1, *lims)
        occ.synchronize()
        if solid:
            gmsh.model.addPhysicalGroup(3, [vol], name="body")
            return
        faces = [t for _, t in gmsh.model.getBoundary([(3, vol)], oriented=False)]
        occ.remove([(3, vol)])
        occ.synchronize()
        flat = [t for t in faces if abs(occ.getCenterOfMass(2, t)[2] - z_base) <= 1e-9 * R]
        gmsh.model.addPhysicalGroup(2, [t for t in faces if t not in flat], name="contact")
        gmsh.model.addPhysicalGroup(2, flat, name="base")

    size = around(ramp, a)
    if solid:
        return solid_with_gmsh(build, (fine, coarse), name, size, {
            "base": _on_plane(2, z_base, 1e-9 * R), "contact": the_rest})
    mesh = mesh_with_gmsh(build, (fine, coarse), order, name, size)
    return expect_regions(mesh, {"contact", "base"}, name)


def graded_block(
    lower,
    upper,
    focus,
    *,
    fine_size: float,
    coarse_size: float,
    fine_radius: float | None = None,
    growth: float = 0.3,
    order: int = 1,
    quads: bool = False,
    seed: int = 0,
    size_profile=None,
    solid: bool = False,
    layers=(),
) -> SurfaceMesh | SolidMesh:
    """Box [lower, upper] (the flat counter-body of a contact) meshed with
    triangles, or quadrilaterals with ``quads=True``, graded toward the point
    ``focus`` on one of its faces.

    ``fine_size`` (length) within distance ``fine_radius`` of ``focus``, then
    growing by ``growth`` per unit distance up to ``coarse_size``; ``order``
    1 or 2 (tri6, or quad9); ``seed`` as for :func:`gmsh_box`;
    ``size_profile`` (distance, size) knots in place of the uniform fine
    zone, as for :func:`spherical_cap` (e.g. a ring refined at a punch's
    rim); ``solid``: mesh the solid with tetrahedra (module docstring), in
    ``layers`` (thicknesses, from the face holding ``focus`` inward) bonded
    on the substrate.  Regions
    ``xmin``, ``xmax``, ``ymin``, ``ymax``, ``zmin``, ``zmax`` as for
    :func:`gmsh_box`.  Example, the half-space under
    :func:`spherical_cap`'s example::

        graded_block((-10, -10, -10), (10, 10, 0), (0, 0, 0),
                     fine_size=0.1, coarse_size=2.5, fine_radius=0.8)
    """
    name = "graded_block"
    lo = check_point(name, "lower", lower)
    hi = check_point(name, "upper", upper)
    if not all(b > a for a, b in zip(lo, hi)):
        raise ConfigError(f"{name}: need lower < upper componentwise, got {lower!r}, {upper!r}")
    f = check_point(name, "focus", focus)
    tol = 1e-9 * max(b - a for a, b in zip(lo, hi))
    inside = all(a - tol <= v <= b + tol for a, v, b in zip(lo, f, hi))
    on_face = any(min(abs(v - a), abs(v - b)) <= tol for a, v, b in zip(lo, f, hi))
    if not (inside and on_face):
        raise ConfigError(
            f"{name}: focus = {focus!r} must lie on a face of the box {lower!r} .. {upper!r}"
        )
    fine, coarse, g = check_grading(name, fine_size, coarse_size, growth)
    ramp = grading_ramp(name, fine, coarse, g, fine_radius, size_profile)
    size = around(ramp, f)
    if solid:
        return _layered_block(name, lo, hi, f, tol, layers, seed, (fine, coarse), size)
    if layers:
        raise ConfigError(f"{name}: layers need solid=True (a surface mesh has one material)")

    def build(gmsh):
        gmsh.option.setNumber("Mesh.RandomSeed", 1 + int(seed))
        # frontal-Delaunay (6) also for quads=True: with a graded size the
        # quadrilateral variant (8) left triangles after recombination in
        # most cases tried, and its full-quad fallback ignored the grading
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        if quads:
            gmsh.option.setNumber("Mesh.RecombineAll", 1)
        _box_surfaces(gmsh, lo, hi)

    mesh = mesh_with_gmsh(build, (fine, coarse), order, name, size)
    return expect_regions(mesh, _BOX_REGIONS, name)


def _layered_block(name, lo, hi, focus, tol, layers, seed, sizes, size) -> SolidMesh:
    """The box as a solid, in bonded layers from the face holding ``focus``."""
    axis = next(a for a in range(3) if min(abs(focus[a] - lo[a]), abs(focus[a] - hi[a])) <= tol)
    top = abs(focus[axis] - hi[axis]) <= tol  # the layers start at the upper face
    depth = [check_number(name, f"layers[{k}]", t) for k, t in enumerate(layers)]
    if sum(depth) >= hi[axis] - lo[axis] - tol:
        raise ConfigError(f"{name}: the layers ({sum(depth):g} thick) must be thinner than the "
                          f"box ({hi[axis] - lo[axis]:g} along {'xyz'[axis]})")
    cuts = np.cumsum([0.0, *depth])
    planes = (hi[axis] - cuts) if top else (lo[axis] + cuts)
    bounds = [*planes, lo[axis] if top else hi[axis]]

    def build(gmsh):
        gmsh.option.setNumber("Mesh.RandomSeed", 1 + int(seed))
        occ = gmsh.model.occ
        parts = []
        for k in range(len(bounds) - 1):
            a, b = sorted((bounds[k], bounds[k + 1]))
            p, q = list(lo), list(hi)
            p[axis], q[axis] = a, b
            parts.append((3, occ.addBox(*p, *(y - x for x, y in zip(p, q)))))
        if len(parts) > 1:  # one conforming mesh across the bonded interfaces
            _, pieces = occ.fragment(parts[:1], parts[1:])
            parts = [piece[0] for piece in pieces]
        occ.synchronize()
        for k, (_, tag) in enumerate(parts):
            label = f"layer{k + 1}" if k < len(depth) else ("substrate" if depth else "body")
            gmsh.model.addPhysicalGroup(3, [tag], name=label)

    return solid_with_gmsh(build, sizes, name, size, _box_regions(lo, hi))


def punch(
    radius: float,
    height: float,
    *,
    fine_size: float,
    coarse_size: float,
    center_size: float | None = None,
    base_center=(0.0, 0.0, 0.0),
    axis: int = 1,
    growth: float = 0.3,
    order: int = 2,
    solid: bool = False,
) -> SurfaceMesh | SolidMesh:
    """Flat-ended cylindrical punch (Boussinesq): the cylinder of radius
    ``radius`` and height ``height`` standing on the disc centred at
    ``base_center`` in the plane z = base_center[2].

    The contact pressure is singular at the rim of the flat end, so the
    element size is ``fine_size`` at the rim, grows inward to
    ``center_size`` (default 2 * ``fine_size``, at most ``coarse_size``)
    and, along the side and onto the top, by ``growth`` per unit distance up
    to ``coarse_size``.  ``axis`` +1: the body lies above its flat end (the
    end's outward normal is -e_z); -1: below.  ``order`` 1: tri3; 2: curved
    tri6 with midside nodes on the cylinder.  ``solid``: mesh the solid
    with tetrahedra (module docstring).

    Regions: ``contact`` (the flat end), ``side``, ``top``.
    """
    name = "punch"
    a = check_number(name, "radius", radius)
    H = check_number(name, "height", height)
    fine, coarse, g = check_grading(name, fine_size, coarse_size, growth)
    if center_size is None:
        mid = min(2.0 * fine, coarse)
    else:
        mid = check_number(name, "center_size", center_size)
        if not fine <= mid <= coarse:
            raise ConfigError(
                f"{name}: center_size = {center_size!r} must lie between fine_size = "
                f"{fine_size!r} and coarse_size = {coarse_size!r}"
            )
    c = check_point(name, "base_center", base_center)
    ax = check_axis(name, axis)
    z_top = c[2] + ax * H

    def build(gmsh):
        occ = gmsh.model.occ
        vol = occ.addCylinder(*c, 0.0, 0.0, ax * H, a)
        occ.synchronize()
        if solid:
            gmsh.model.addPhysicalGroup(3, [vol], name="body")
            return
        faces = [t for _, t in gmsh.model.getBoundary([(3, vol)], oriented=False)]
        occ.remove([(3, vol)])
        occ.synchronize()
        groups: dict[str, list[int]] = {"contact": [], "side": [], "top": []}
        for t in faces:
            zc = occ.getCenterOfMass(2, t)[2]
            if abs(zc - c[2]) <= 1e-9 * H:
                groups["contact"].append(t)
            elif abs(zc - z_top) <= 1e-9 * H:
                groups["top"].append(t)
            else:
                groups["side"].append(t)
        for key, tags in groups.items():
            gmsh.model.addPhysicalGroup(2, tags, name=key)

    rim = size_ramp(fine, coarse, g, 0.0)
    face = size_ramp(mid, coarse, g, 0.0)

    def size(x: float, y: float, z: float) -> float:
        w = max(0.0, ax * (z - c[2]))  # height above the flat end
        rho = math.sqrt((x - c[0]) ** 2 + (y - c[1]) ** 2)
        return min(rim(math.hypot(rho - a, w)), face(w))

    if solid:
        return solid_with_gmsh(build, (fine, coarse), name, size, {
            "contact": _on_plane(2, c[2], 1e-9 * H), "top": _on_plane(2, z_top, 1e-9 * H),
            "side": the_rest})
    mesh = mesh_with_gmsh(build, (fine, coarse), order, name, size)
    return expect_regions(mesh, {"contact", "side", "top"}, name)


__all__ = ["load_gmsh", "GMSH_INSTALL", "hollow_sphere", "gmsh_box", "spherical_cap", "graded_block", "punch"]

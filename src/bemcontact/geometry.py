"""Surface meshes of simple solids generated with gmsh (optional dependency:
``pip install gmsh``).  Each returns an outward-oriented, checked
:class:`~bemcontact.mesh.SurfaceMesh` with named regions."""

from __future__ import annotations

import os
import tempfile

from .errors import ConfigError, MeshError
from .mesh import SurfaceMesh, read_mesh


def _gmsh():
    try:
        import gmsh
    except ImportError:  # pragma: no cover - depends on the environment
        raise ConfigError(
            "gmsh is needed to generate this geometry: pip install gmsh (or bemcontact[gmsh])"
        ) from None
    return gmsh


def _mesh_with_gmsh(build, mesh_size: float, order: int, name: str) -> SurfaceMesh:
    gmsh = _gmsh()
    if order not in (1, 2):
        raise ConfigError(f"{name}: order must be 1 or 2, got {order!r}")
    if not mesh_size > 0:
        raise ConfigError(f"{name}: mesh_size must be > 0, got {mesh_size!r}")
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(name)
        build(gmsh)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMin", mesh_size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", mesh_size)
        gmsh.option.setNumber("Mesh.ElementOrder", order)
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)
        gmsh.model.mesh.generate(2)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, f"{name}.msh")
            gmsh.write(path)
            mesh = read_mesh(path)
    finally:
        gmsh.finalize()
    mesh.source = name
    return mesh.oriented().check()


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

    mesh = _mesh_with_gmsh(build, mesh_size, order, "hollow_sphere")
    if set(mesh.region_names) != {"inner", "outer"}:  # pragma: no cover - gmsh behaviour
        raise MeshError(f"hollow_sphere: unexpected regions {mesh.region_names}")
    return mesh


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
        occ = gmsh.model.occ
        vol = occ.addBox(*lo, *(b - a for a, b in zip(lo, hi)))
        occ.synchronize()
        gmsh.option.setNumber("Mesh.RandomSeed", 1 + int(seed))
        gmsh.option.setNumber("Mesh.Algorithm", 8 if quads else 6)
        if quads:
            gmsh.option.setNumber("Mesh.RecombineAll", 1)
        faces = [t for _, t in gmsh.model.getBoundary([(3, vol)], oriented=False)]
        occ.remove([(3, vol)])
        occ.synchronize()
        for tag in faces:
            c = occ.getCenterOfMass(2, tag)
            for axis in range(3):
                for side, ref in (("min", lo[axis]), ("max", hi[axis])):
                    if abs(c[axis] - ref) <= 1e-9 * (1 + abs(ref)):
                        gmsh.model.addPhysicalGroup(2, [tag], name=f"{'xyz'[axis]}{side}")

    mesh = _mesh_with_gmsh(build, mesh_size, order, "gmsh_box")
    if sorted(mesh.region_names) != sorted(f"{a}{s}" for a in "xyz" for s in ("min", "max")):
        raise MeshError(f"gmsh_box: unexpected regions {mesh.region_names}")  # pragma: no cover
    return mesh


__all__ = ["hollow_sphere", "gmsh_box"]

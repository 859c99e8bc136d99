"""The mesh and material of a ``[[body]]``: a BEM body's closed surface
mesh (``model = "bem"``, the default) or a finite-element body's volume
mesh (``model = "fem"``), generated or read from a file, and its material
(isotropic; for a finite-element body also orthotropic or a 6 × 6
stiffness, one for the body or one per volume region).  Every problem is a
one-line error naming the field (:class:`~.checks.Checker`)."""

from __future__ import annotations

import hashlib
import pathlib
from typing import Any

from ..bem import LinearElastic
from ..errors import BemcontactError, ConfigError
from ..inputs import MAX_MESH_BYTES, check_regular_file
from ..mesh import SurfaceMesh, box, read_mesh
from . import schema
from .checks import Checker, one_line
from .sizes import check_generated_size

#: The finite elements a ``model = "fem"`` body takes: name -> (cells, order).
FEM_ELEMENTS = {"tet4": ("tet4", 1), "tet10": ("tet4", 2), "hex8": ("hex8", 1),
                "hex27": ("hex8", 2)}
FEM_ELEMENT_TEXT = ", ".join(FEM_ELEMENTS)


def _sha256(path: pathlib.Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def read_mesh_table(c: Checker, where: str, value: Any, fem: bool, hashes: dict):
    """The body's mesh: a :class:`~bemcontact.mesh.SurfaceMesh`, or with
    ``fem`` a :class:`~bemcontact.fem.mesh.VolumeMesh`; ``hashes`` gets the
    SHA-256 of a mesh file by the name the file gives it."""
    t = c.table(where, value, schema.MESH)
    given = [k for k in schema.MESH_SOURCES if k in t]
    if len(given) != 1:
        c.fail(where, "give exactly one of " + ", ".join(schema.MESH_SOURCES)
               + (f" (given: {', '.join(given)})" if given else ""), value)
    source = given[0]
    if "element_type" in t and source != "file":
        c.fail(f"{where}.element_type", f"belongs inside {source} = {{...}} for a "
               "generated mesh" if source == "box" else "applies only to mesh files",
               t["element_type"])
    if source == "box":
        return _box(c, f"{where}.box", t["box"], fem)
    if source != "file":
        return _generated(c, f"{where}.{source}", source, t[source], fem)
    fwhere = f"{where}.file"
    name = c.string(fwhere, t["file"])
    etype = None
    if "element_type" in t:
        etype = c.value(f"{where}.element_type", t["element_type"],
                        schema.MESH.key("element_type"))
        _element_kind(c, f"{where}.element_type", etype, fem)
    full = c.base / name
    if full.is_dir():
        c.fail(fwhere, f"is a directory ({full}), not a mesh file", name)
    if not full.exists():
        c.fail(fwhere, f"no such mesh file ({full})", name,
               "mesh files are relative to the problem file's directory")
    try:
        check_regular_file(full, "mesh file", MAX_MESH_BYTES)
    except ConfigError as exc:
        c.fail(fwhere, one_line(str(exc)).removeprefix(f"{full}: "), name)
    try:
        if fem:
            from ..fem.mesh import read_volume_mesh

            mesh = read_volume_mesh(str(full), FEM_ELEMENTS[etype or "tet4"][1])
            if etype is not None and mesh.cell_type != FEM_ELEMENTS[etype][0]:
                c.fail(f"{where}.element_type", f"the file holds {mesh.cell_type} cells", etype,
                       f"use {'tet4 or tet10' if mesh.cell_type == 'tet4' else 'hex8 or hex27'}")
        else:
            mesh = read_mesh(full, etype)
        hashes[name] = _sha256(full)
        return mesh
    except BemcontactError as exc:
        text = one_line(str(exc))
        if text.startswith(f"{full}: "):
            text = text[len(f"{full}: "):]
        c.fail(fwhere, f"cannot use the mesh file: {text.rstrip('.')}", name)


def _element_kind(c: Checker, where: str, etype: str, fem: bool) -> None:
    """A volume element for a finite-element body, a surface one otherwise."""
    if fem and etype not in FEM_ELEMENTS:
        c.fail(where, f"is a surface element; a finite-element body (model = \"fem\") takes "
               f"{FEM_ELEMENT_TEXT}", etype)
    if not fem and etype in FEM_ELEMENTS:
        c.fail(where, "is a volume element, for a finite-element body", etype,
               'add model = "fem" to the body, or use a surface element type')


def _box(c: Checker, where: str, value: Any, fem: bool):
    t = c.table(where, value, schema.BOX)
    f = c.fields(where, t, schema.BOX)
    lo, hi = f["lower"], f["upper"]
    for a in range(3):
        if hi[a] <= lo[a]:
            c.fail(f"{where}.upper[{a}]", f"must exceed lower[{a}] = {lo[a]:g}", t["upper"][a])
    etype = f["element_type"] if "element_type" in t else ("hex8" if fem else "quad4")
    _element_kind(c, f"{where}.element_type", etype, fem)
    if fem and f["grading"] != 1.0:
        c.fail(f"{where}.grading", "applies to a BEM body's surface mesh; a finite-element box "
               "is uniform", t["grading"],
               "use graded_box for a finite-element body graded toward the contact")
    try:
        if fem:
            from ..fem.mesh import box_volume

            return box_volume(lo, hi, f["divisions"], *FEM_ELEMENTS[etype])
        return box(lo, hi, f["divisions"], etype, f["grading"])
    except BemcontactError as exc:
        c.wrap(where, exc, value)


def _generated(c: Checker, where: str, source: str, value: Any, fem: bool):
    """``cap``, ``punch``, ``graded_box`` or ``ball``: a gmsh-generated
    surface mesh, or (``fem``) the solid meshed with tetrahedra."""
    from ..mesh import shapes as geometry

    key = schema.MESH.key(source)
    t = c.table(where, value, key)
    f = c.fields(where, t, key)
    if f["coarse_size"] < f["fine_size"]:
        c.fail(f"{where}.coarse_size", f"must be >= fine_size = {f['fine_size']:g}",
               t["coarse_size"])
    check_generated_size(c, where, source, f, t, solid=fem)
    layers = f.pop("layers", ())
    if layers and not fem:
        c.fail(f"{where}.layers", "need a finite-element body (a BEM body has one material)",
               t["layers"], 'add model = "fem" to the body')
    if fem and f.get("quads"):
        c.fail(f"{where}.quads", "applies to a BEM body's surface mesh; a finite-element "
               "body's generated solid is meshed with tetrahedra", t["quads"])
    if source == "cap":
        if not f["height"] < 2 * f["radius"]:
            c.fail(f"{where}.height", f"must be below 2 * radius = {2 * f['radius']:g}",
                   t["height"], "height = radius is a hemisphere")
        make, args = geometry.spherical_cap, (f.pop("radius"), f.pop("height"))
    elif source == "punch":
        make, args = geometry.punch, (f.pop("radius"), f.pop("height"))
    elif source == "ball":
        from ..mesh import curved

        make, args = curved.ball, (f.pop("radius"),)
    else:
        lo, hi = f.pop("lower"), f.pop("upper")
        for a in range(3):
            if hi[a] <= lo[a]:
                c.fail(f"{where}.upper[{a}]", f"must exceed lower[{a}] = {lo[a]:g}",
                       t["upper"][a])
        make, args = geometry.graded_block, (lo, hi, f.pop("focus"))
        if fem:
            f["layers"] = layers
    try:
        geometry.load_gmsh()
    except ConfigError as exc:  # one line without the table's echo
        raise ConfigError(one_line(f"{c.src}: {where}: {exc}")) from None
    order = f.pop("order")
    try:
        if not fem:
            return make(*args, order=order, **f)
        from ..fem.mesh import solid_volume

        return solid_volume(make(*args, solid=True, **f), order)
    except BemcontactError as exc:
        c.wrap(where, exc, value)


def read_material(c: Checker, where: str, value: Any, fem: bool):
    """An isotropic :class:`~bemcontact.bem.LinearElastic`, or (``fem``)
    also an orthotropic or 6 × 6 :class:`~bemcontact.fem.AnisotropicElastic`."""
    t = c.table(where, value, schema.MATERIAL)
    f = c.fields(where, t, schema.MATERIAL)
    kinds = {"isotropic": ("youngs_modulus", "poisson_ratio"),
             "orthotropic": ("youngs_moduli", "poisson_ratios", "shear_moduli"),
             "stiffness": ("stiffness",)}
    given = [k for k, names in kinds.items() if any(n in t for n in names)]
    if len(given) != 1:
        c.fail(where, "give youngs_modulus and poisson_ratio (isotropic)" + (
            ", or youngs_moduli, poisson_ratios and shear_moduli (orthotropic), or stiffness "
            "(6 x 6)" if fem else "") + (f"; not both {given[0]} and {given[1]} constants"
                                         if len(given) > 1 else ""), value)
    kind = given[0]
    if kind != "isotropic" and not fem:
        c.fail(f"{where}.{next(n for n in kinds[kind] if n in t)}", "needs a finite-element "
               "body (a BEM body is isotropic)", value, 'add model = "fem" to the body')
    missing = [n for n in kinds[kind] if n not in t]
    if missing:
        c.fail(f"{where}.{missing[0]}", "missing required key", value, f"add {missing[0]} = ...")
    axes = [n for n in ("axis1", "axis2") if n in t]
    if axes and kind == "isotropic":
        c.fail(f"{where}.{axes[0]}", "applies to an anisotropic material", t[axes[0]])
    try:
        if kind == "isotropic":
            return LinearElastic(f["youngs_modulus"], f["poisson_ratio"])
        from ..fem import AnisotropicElastic

        frame = {n: f[n] for n in axes}
        if kind == "orthotropic":
            return AnisotropicElastic.orthotropic(f["youngs_moduli"], f["poisson_ratios"],
                                                  f["shear_moduli"], **frame)
        return AnisotropicElastic(f["stiffness"], **frame)
    except BemcontactError as exc:
        c.wrap(where, exc, value)


def read_materials(c: Checker, where: str, b: dict, volume) -> Any:
    """A finite-element body's ``material`` (the whole body) or
    ``materials`` (one per volume region of ``volume``)."""
    if ("material" in b) == ("materials" in b):
        c.fail(where, "give material (the whole body) or materials (one table per volume "
               "region)" + (", not both" if "material" in b else ""), sorted(b))
    if "material" in b:
        return read_material(c, f"{where}.material", b["material"], True)
    value = b["materials"]
    if not isinstance(value, dict) or not value:
        c.fail(f"{where}.materials", "must be a table of volume regions, each a material "
               "table", value)
    out = {}
    for region, spec in value.items():
        if region not in volume.volume_names:
            c.fail(f"{where}.materials.{region}", f"the mesh has no volume region {region!r} "
                   f"(its volume regions: {', '.join(volume.volume_names)})", region)
        out[region] = read_material(c, f"{where}.materials.{region}", spec, True)
    for region in volume.volume_names:
        if region not in out:
            c.fail(f"{where}.materials", f"volume region {region!r} has no material", sorted(out),
                   f"add [{where.split('[')[0]}.materials.{region}]")
    return out


def read_body_force(c: Checker, where: str, b: dict, fem: bool, volume):
    """(density, body force) of a ``[[body]]`` at ``where``: ``body_force``
    (a finite-element body's only) and its materials' ``density``, one per
    volume region; (None, None) without a body force."""
    if "body_force" not in b:
        return None, None
    value = b["body_force"]
    if not fem:
        c.fail(f"{where}.body_force", "needs a finite-element body (a BEM body's volume is not "
               "meshed)", value, 'add model = "fem" to the body')
    t = c.table(f"{where}.body_force", value, schema.BODY_FORCE)
    f = c.fields(f"{where}.body_force", t, schema.BODY_FORCE)
    from ..fem.loads import BodyForce

    force = BodyForce(**f)
    if "material" in b:
        tables = {r: (f"{where}.material", b["material"]) for r in volume.volume_names}
    else:
        tables = {r: (f"{where}.materials.{r}", b["materials"][r]) for r in volume.volume_names}
    density = {}
    for region, (at, table) in tables.items():
        if "density" not in table:
            if force.is_zero:
                return None, force
            c.fail(f"{at}.density", "missing: the body force needs the density of every volume "
                   "region", table, "add density = ... (mass per volume)")
        density[region] = table["density"]
    return density, force


def surface_of(mesh) -> SurfaceMesh:
    """The surface a body's regions and contact surfaces are on."""
    return mesh if isinstance(mesh, SurfaceMesh) else mesh.boundary()[0]


__all__ = ["FEM_ELEMENTS", "read_body_force", "read_material", "read_materials", "read_mesh_table", "surface_of"]

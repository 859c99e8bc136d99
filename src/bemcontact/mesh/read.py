"""Reading surface meshes from files (meshio; gmsh physical groups as regions)."""

from __future__ import annotations

import contextlib
import io
import os

import numpy as np

from ..errors import ConfigError, MeshError
from ..inputs import MAX_MESH_BYTES, check_regular_file
from .surface import MESHIO_TYPES, SurfaceMesh


def _gmsh_physical_names(path: str) -> list[tuple[int, int, str]]:
    """(dimension, tag, name) of a gmsh .msh file's $PhysicalNames section
    (ASCII in both the ASCII and the binary formats); [] if there is none."""
    with open(path, "rb") as f:
        data = f.read()
    start = data.find(b"$PhysicalNames")
    end = data.find(b"$EndPhysicalNames", start)
    if start < 0 or end < 0:
        return []
    out = []
    for line in data[start:end].decode("utf-8", "replace").splitlines()[2:]:
        parts = line.split(maxsplit=2)
        if len(parts) == 3 and parts[0].isdigit() and parts[1].lstrip("-").isdigit():
            out.append((int(parts[0]), int(parts[1]), parts[2].strip().strip('"')))
    return out


def read_mesh(path: str | os.PathLike, element_type: str | None = None) -> SurfaceMesh:
    """Read a surface mesh from any file meshio reads (gmsh ``.msh``, VTU, ...).

    gmsh physical groups of dimension 2 become regions (named by their
    physical name, or ``"group<tag>"`` when unnamed).  Without physical
    groups, cell data ``region`` (as written by bemcontact) is used, else one
    region ``"surface"``.  Line, vertex and volume cells are ignored.  The
    file must hold one surface element type (``element_type`` picks one when
    it holds several).
    """
    import meshio

    p = os.fspath(path)
    if not os.path.lexists(p):  # a link to nothing or a loop: check_regular_file says which
        raise MeshError(f"{p}: no such file")
    if os.path.isdir(p):
        raise MeshError(f"{p}: is a directory, not a mesh file")
    try:
        check_regular_file(p, "mesh file", MAX_MESH_BYTES)
    except ConfigError as exc:
        raise MeshError(str(exc)) from None
    if p.lower().endswith(".msh"):
        seen: dict[str, int] = {}
        for dim, tag, name in _gmsh_physical_names(p):
            if dim != 2:
                continue
            if name in seen:
                raise MeshError(
                    f"{p}: two physical surface groups are named {name!r} (tags {seen[name]} "
                    f"and {tag}); give each group its own name (or merge them in gmsh)"
                )
            seen[name] = tag
    captured = io.StringIO()
    try:
        with contextlib.redirect_stderr(captured), contextlib.redirect_stdout(captured):
            m = meshio.read(p)
    except MemoryError:
        raise MeshError(f"{p}: cannot read mesh: out of memory while reading it") from None
    except (Exception, SystemExit) as exc:  # meshio raises many types, even SystemExit
        detail = " ".join(captured.getvalue().split()) or f"{type(exc).__name__}: {exc}"
        if not isinstance(exc, meshio.ReadError):  # a reader tripping over what is missing
            kind = os.path.splitext(p)[1] or "mesh"
            detail = f"malformed or empty {kind} file (meshio failed: {detail})"
        raise MeshError(f"{p}: cannot read mesh: {detail}") from None
    if not m.points.size or not any(len(b.data) for b in m.cells):
        raise MeshError(f"{p}: the mesh is empty ({len(m.points)} nodes, "
                        f"{sum(len(b.data) for b in m.cells)} elements)")
    blocks = [(i, MESHIO_TYPES[b.type]) for i, b in enumerate(m.cells) if b.type in MESHIO_TYPES]
    found = sorted({b.type for b in m.cells})
    if not blocks:
        raise MeshError(
            f"{p}: no surface elements (found cell types {found}); bemcontact needs the "
            "boundary surface: triangle, triangle6, quad, quad8 or quad9"
        )
    types = sorted({t for _, t in blocks})
    if element_type is None:
        if len(types) > 1:
            raise MeshError(
                f"{p}: mixed surface element types {types}; pass element_type= to pick one "
                "(or remesh with one type)"
            )
        element_type = types[0]
    elif element_type not in types:
        raise MeshError(f"{p}: element_type {element_type!r} not in the file (found {types})")
    blocks = [i for i, t in blocks if t == element_type]
    conn = np.vstack([m.cells[i].data for i in blocks])
    names_by_tag: dict[int, str] = {}
    for name, data in (m.field_data or {}).items():
        arr = np.asarray(data).ravel()
        if arr.size >= 2 and int(arr[1]) == 2:
            names_by_tag[int(arr[0])] = name
    tags = None
    if "gmsh:physical" in m.cell_data:
        tags = np.concatenate([np.asarray(m.cell_data["gmsh:physical"][i]) for i in blocks])
        regions: dict[str, list[int]] = {}
        for t in np.unique(tags):
            regions[names_by_tag.get(int(t), f"group{int(t)}")] = np.flatnonzero(tags == t)
    elif "region" in m.cell_data:
        tags = np.concatenate([np.asarray(m.cell_data["region"][i]) for i in blocks])
        regions = {f"region{int(t)}": np.flatnonzero(tags == t) for t in np.unique(tags)}
    else:
        regions = {"surface": np.arange(conn.shape[0])}
    # drop nodes not used by surface elements (volume meshes keep interior nodes)
    used = np.unique(conn)
    if used.size and (used[0] < 0 or used[-1] >= m.points.shape[0]):
        raise MeshError(
            f"{p}: an element refers to node {int(used[-1] if used[-1] >= 0 else used[0])}, but "
            f"the file has {m.points.shape[0]} nodes (numbered from 0)"
        )
    remap = np.full(m.points.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    pts = np.asarray(m.points, dtype=float)
    if pts.shape[1] == 2:
        raise MeshError(f"{p}: the mesh is 2D (points have 2 coordinates); a 3D surface is needed")
    return SurfaceMesh(pts[used], remap[conn], element_type, regions, source=p)



__all__ = ["read_mesh"]

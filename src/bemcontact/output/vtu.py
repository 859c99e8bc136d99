"""ParaView files of contact results: VTU surfaces and PVD time series
(written by :func:`bemcontact.output.write.write_results`).

The bodies' and interfaces' VTU files hold the true geometry: points are the
mesh nodes and cells the mesh elements (no gaps along edges), with cell data
``region`` (the index into the mesh's region names) and the region names as
VTU field data (:func:`region_field_data`).  The solution lives at the
*functional nodes* (the collocation points): away from edges they are the
mesh nodes and their values are written as computed; at edges and corners
each element has its own copy of a node, moved toward the element centroid
(docs/theory.md), and the value written at the mesh node is each element's
interpolant there averaged over the node's elements
(:func:`geometric_values`).  ``frame.vtu`` holds the frame nodes (the
contact law's unknowns) as computed.
"""

from __future__ import annotations

import os
import pathlib
from collections.abc import Mapping

import numpy as np

from ..contact.results import ContactResult
from ..mesh.element import CORNERS, REFERENCE_NODES
from ..stresses import measures
from .layout import Layout, result_layout

_MESHIO_CELL = {"tri3": "triangle", "tri6": "triangle6", "quad4": "quad", "quad8": "quad8",
                "quad9": "quad9"}  # fmt: skip


def write_vtu(path: pathlib.Path, points, cells, point_data, cell_data=None,
               field_data=None) -> None:
    import meshio

    mesh = meshio.Mesh(
        np.ascontiguousarray(points, dtype=float),
        cells,
        point_data={k: np.ascontiguousarray(v) for k, v in point_data.items()},
        cell_data=cell_data or {},
    )
    meshio.write(os.fspath(path), mesh, file_format="vtu")
    if field_data:
        _add_field_data(path, field_data)


def _add_field_data(path: pathlib.Path, field_data: Mapping[str, np.ndarray]) -> None:
    """Insert a VTK ``FieldData`` block of int32 arrays (meshio 5 reads it
    but does not write it) at the top of the ``UnstructuredGrid``."""
    from xml.sax.saxutils import quoteattr

    arrays = "".join(
        f'<DataArray type="Int32" Name={quoteattr(name)} NumberOfTuples="1" '
        f'NumberOfComponents="{np.size(v)}" format="ascii">'
        + " ".join(str(int(x)) for x in np.ravel(v)) + "</DataArray>\n"
        for name, v in field_data.items()
    )
    data = path.read_bytes()
    tag = b"<UnstructuredGrid>"
    at = data.index(tag) + len(tag)
    path.write_bytes(data[:at] + b"\n<FieldData>\n" + arrays.encode() + b"</FieldData>" + data[at:])


def geometric_values(disc, values: np.ndarray, elements: np.ndarray | None = None,
                     how: str = "mean") -> tuple[np.ndarray, np.ndarray]:
    """A field given at the functional nodes, at the mesh's geometric nodes:
    (nodes (g,), values (g, ...)) for the nodes of ``elements`` (default all).

    Each element's functional basis is evaluated at its own geometric nodes
    (``discretization.basis_at``), which gives each element's value there:
    the nodal value itself at a continuous node, the element's interpolant
    extrapolated from its shifted copy at an edge or corner node.
    ``how``: ``"mean"`` over a node's elements (displacement is continuous,
    so the elements agree to interpolation accuracy; traction jumps at an
    edge, where this is the mean of its sides), ``"max"`` (the state: a node
    any of whose copies is closed is closed) or ``"sum"`` of the functional
    nodes' own values (weights: the copies of a node share its area)."""
    mesh = disc.mesh
    k = mesh.elements.shape[1]
    els = np.arange(mesh.n_elements) if elements is None else np.asarray(elements)
    geo = mesh.elements[els]  # (m, k) geometric nodes
    nodes, local = np.unique(geo, return_inverse=True)
    local = local.reshape(geo.shape)
    v = np.asarray(values)
    out = np.zeros((nodes.size, *v.shape[1:]), dtype=float if how != "max" else v.dtype)
    if how == "sum":
        f = disc.fconn[els, :k].ravel()
        first = np.unique(f, return_index=True)[1]  # each functional node once
        np.add.at(out, local.ravel()[first], v[f[first]])
        return nodes, out
    if how == "max":
        np.maximum.at(out, local.ravel(), v[disc.fconn[els, :k]].reshape(-1, *v.shape[1:]))
        return nodes, out
    xi = np.tile(REFERENCE_NODES[mesh.element_type], (els.size, 1))
    N = disc.basis_at(np.repeat(els, k), xi)  # (m k, k): element's basis at its nodes
    own = v[disc.fconn[np.repeat(els, k), :k]]  # (m k, k, ...)
    at = np.einsum("pa,pa...->p...", N, own)
    np.add.at(out, local.ravel(), at)
    count = np.bincount(local.ravel(), minlength=nodes.size).astype(float)
    return nodes, out / count.reshape(-1, *[1] * (out.ndim - 1))


def _geometric_vtu(path: pathlib.Path, disc, elements, fields) -> None:
    """The mesh's ``elements`` at their true geometry (points = mesh nodes,
    no gaps at edges), ``fields``: name -> (functional-node values, how)."""
    mesh = disc.mesh
    nodes, _ = geometric_values(disc, np.zeros(disc.n_points), elements, "max")
    index = np.full(mesh.n_nodes, -1, dtype=np.int64)
    index[nodes] = np.arange(nodes.size)
    conn = index[mesh.elements[elements]]
    point_data = {}
    for name, (values, how) in fields.items():
        v = geometric_values(disc, values, elements, how)[1]
        if name == "normal":
            v = v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)
        point_data[name] = v
    if "stress" in point_data:
        point_data.update(measures(point_data["stress"]))
    cell_data = {"region": [mesh.element_region[elements].astype(np.int32)]}
    write_vtu(path, mesh.nodes[nodes], [(_MESHIO_CELL[mesh.element_type], conn)], point_data,
               cell_data, region_field_data(mesh))


def region_field_data(mesh) -> dict[str, np.ndarray]:
    """The region names as VTU field data in meshio's (and gmsh's) convention
    for named groups: name -> [index, 2] (the ``region`` cell data's value,
    dimension 2)."""
    return {n: np.array([i, 2], dtype=np.int32) for i, n in enumerate(mesh.region_names)}


def _vertices(n: int):
    return [("vertex", np.arange(n, dtype=np.int64)[:, None])]


def write_body_vtu(path: pathlib.Path, sol, stress=None) -> None:
    """A body's surface fields (a BodySolution: displacement, traction, normal,
    weight; its surface stresses when given) on its mesh's elements."""
    d = sol.discretization
    fields = {
        "displacement": (sol.displacement, "mean"), "traction": (sol.traction, "mean"),
        "normal": (sol.normals, "mean"), "weight": (sol.weights, "sum"),
    }
    if stress is not None:
        fields["stress"] = (stress, "mean")
    _geometric_vtu(path, d, np.arange(d.mesh.n_elements), fields)


def _surface_stresses(result: ContactResult) -> dict:
    """Body name -> its surface stresses (N, 6), for the bodies that give them."""
    out = {}
    for name in result.names:
        model = getattr(result, "models", {}).get(name)
        if model is not None and hasattr(model, "surface_stresses"):
            out[name] = result.surface_stresses(name)
    return out


def _write_interface_vtu(path: pathlib.Path, sol, iface, stress=None) -> None:
    d = sol.discretization
    elements = d.mesh.region(iface.surface)
    full = np.full(d.n_points, -1, dtype=np.int64)
    full[iface.nodes] = np.arange(iface.nodes.size)
    fields = _interface_fields(iface)
    if stress is not None:
        fields["stress"] = stress[iface.nodes]
    if elements.size == 0 or (full[d.fconn[elements, :d.mesh.elements.shape[1]]] < 0).any():
        if stress is not None:
            fields.update(measures(fields["stress"]))
        write_vtu(path, iface.points, _vertices(iface.nodes.size), fields)
        return

    def spread(values):  # interface values onto all functional nodes (others unused)
        v = np.asarray(values)
        out = np.zeros((d.n_points, *v.shape[1:]), dtype=v.dtype)
        out[iface.nodes] = v
        return out

    how = {"state": "max", "weight": "sum"}
    _geometric_vtu(path, d, elements, {
        name: (spread(v), how.get(name, "mean")) for name, v in fields.items()
    })


def _interface_fields(iface) -> dict[str, np.ndarray]:
    return {
        "pressure": iface.pressure, "tangential_traction": iface.tangential_traction,
        "gap": iface.gap, "slip": iface.slip, "state": iface.state.astype(np.int8),
        "displacement": iface.displacement, "traction": iface.traction,
        "normal": iface.normals, "weight": iface.weights,
    }


def _solutions(result: ContactResult, interfaces) -> list:
    """The body solutions of ``interfaces``' bodies (by name)."""
    return [result.bodies[list(result.names).index(i.body)] for i in interfaces]


def frame_cells(result: ContactResult, pair=None):
    """The elements of the frame of ``pair`` (a
    :class:`~bemcontact.contact.results.PairResult` of ``result``; default
    the result's first pair): the frame lies on the corner nodes of one
    body's contact elements (frame.py); find that body and rebuild the
    linear cells, else None.  The match is checked against the frame's
    points."""
    src = result if pair is None else pair
    pts = src.frame.points
    for sol, iface in zip(_solutions(result, src.interfaces), src.interfaces):
        mesh = sol.discretization.mesh
        nc = CORNERS[mesh.element_type]
        corners = mesh.elements[mesh.region(iface.surface), :nc]
        geo, inv = np.unique(corners, return_inverse=True)
        if geo.size == pts.shape[0] and np.allclose(mesh.nodes[geo], pts, rtol=0, atol=1e-12 * (
            1.0 + np.abs(pts).max()
        )):
            kind = "quad" if nc == 4 else "triangle"
            return [(kind, inv.reshape(corners.shape).astype(np.int64))]
    return None


def _write_frame_vtu(path: pathlib.Path, fr, cells) -> None:
    cells = cells or _vertices(fr.points.shape[0])
    write_vtu(
        path, fr.points, cells,
        {
            "pressure": fr.pressure, "tangential_traction": fr.tangential_traction,
            "gap": fr.gap, "slip": fr.slip, "state": fr.state.astype(np.int8),
            "normal": fr.normals, "weight": fr.weights,
            **({} if fr.microslip is None else {"microslip": fr.microslip,
                                               "power_density": fr.power_density}),
        },
    )


def write_state_vtus(directory: pathlib.Path, result: ContactResult, suffix: str,
                     files: Layout | None = None) -> None:
    """The VTU files of one state, ``<stem><suffix>.vtu``, stems from
    ``files`` (default: :func:`~bemcontact.output.layout.result_layout`)."""
    files = result_layout(result) if files is None else files
    stress = _surface_stresses(result)
    for sol, name, n in zip(result.bodies, result.names, files.bodies):
        write_body_vtu(directory / f"{n}{suffix}.vtu", sol, stress.get(name))
        if f"{n}_volume" in files.volumes:
            points, cells, point_data, cell_data = result.models[name].volume_fields(sol)
            write_vtu(directory / f"{n}_volume{suffix}.vtu", points, cells, point_data,
                      cell_data)
    if not files.assembly:
        for sol, iface in zip(_solutions(result, result.interfaces), result.interfaces):
            _write_interface_vtu(directory / f"{iface.body}_interface{suffix}.vtu", sol, iface,
                                 stress.get(iface.body))
        _write_frame_vtu(directory / f"frame{suffix}.vtu", result.frame, frame_cells(result))
        return
    for pair, names in zip(result.pairs, files.pairs):
        for sol, iface, stem in zip(_solutions(result, pair.interfaces), pair.interfaces,
                                    names.interfaces):
            _write_interface_vtu(directory / f"{stem}{suffix}.vtu", sol, iface,
                                 stress.get(iface.body))
        _write_frame_vtu(directory / f"{names.frame}{suffix}.vtu", pair.frame,
                         frame_cells(result, pair))


def write_pvd(path: pathlib.Path, entries: list[tuple[float, str]]) -> None:
    """A ParaView collection: one ``DataSet`` per (time, relative file)."""
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
        "  <Collection>",
        *(f'    <DataSet timestep="{t:g}" group="" part="0" file="{f}"/>' for t, f in entries),
        "  </Collection>",
        "</VTKFile>",
    ]
    path.write_text("\n".join(lines) + "\n")


__all__ = ["frame_cells", "geometric_values", "region_field_data", "write_body_vtu",
           "write_state_vtus", "write_pvd"]

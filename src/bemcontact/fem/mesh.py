"""Volume meshes of finite-element bodies: the cells (scikit-fem's mesh),
their boundary as a :class:`~bemcontact.mesh.SurfaceMesh` with named regions
(the body's trace, where its conditions and contact surfaces live), and the
map from each boundary node to its volume node.

Cells: tetrahedra (``tet4``) and hexahedra (``hex8``), straight-sided, with
linear (``order=1``: P1, Q1) or quadratic (``order=2``: P2, Q2) elements on
them; the boundary faces are ``tri3`` / ``quad4`` (linear) or ``tri6`` /
``quad9`` (quadratic) elements, outward oriented.  The *volume nodes* are
the elements' nodes (vertices, then edge, face and cell nodes of quadratic
elements), volume dof ``3 i + c`` component c of node i."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import ConfigError, MeshError
from ..mesh import SurfaceMesh

#: cell type -> (scikit-fem mesh class name, boundary element type per order,
#: scikit-fem element class per order)
CELL_TYPES = {"tet4": ("MeshTet", ("tri3", "tri6"), ("ElementTetP1", "ElementTetP2")),
              "hex8": ("MeshHex", ("quad4", "quad9"), ("ElementHex1", "ElementHex2"))}
SKFEM_INSTALL = 'pip install "bemcontact[fem]"'


def load_skfem():
    """The scikit-fem module; one line naming the install command if absent."""
    try:
        import skfem
    except ImportError:
        raise ConfigError(
            f"a finite-element body needs scikit-fem, which is not installed; {SKFEM_INSTALL}"
        ) from None
    return skfem


class VolumeMesh:
    """A volume mesh (n nodes, cells of one type) with named boundary regions.

    Parameters
    ----------
    nodes:
        (n, 3) coordinates.
    cells:
        (c, 4) tetrahedra or (c, 8) hexahedra, in scikit-fem's node order.
    cell_type:
        ``"tet4"`` or ``"hex8"``.
    regions:
        Boundary region name -> a function of the boundary faces' centroids
        (f, 3) returning a boolean (f,) choice, or an array of boundary-face
        indices (into ``faces``); faces no region claims form ``"free"``.
    volumes:
        Volume region name (a material's domain) -> a function of the
        cells' centroids (c, 3) returning a boolean (c,) choice, or an array
        of cell indices; cells no region claims form ``"body"`` (all of
        them without ``volumes``).
    order:
        1 (linear elements) or 2 (quadratic) on the cells.
    source:
        Named in messages.
    """

    def __init__(self, nodes, cells, cell_type: str, regions: Mapping | None = None, *,
                 volumes: Mapping | None = None, order: int = 1,
                 source: str = "volume mesh") -> None:
        if order not in (1, 2):
            raise MeshError(f"{source}: order must be 1 or 2, got {order!r}")
        self.order = order
        if cell_type not in CELL_TYPES:
            raise MeshError(f"{source}: cell_type must be one of {sorted(CELL_TYPES)}, got {cell_type!r}")
        skfem = load_skfem()
        self.source, self.cell_type = source, cell_type
        X = np.ascontiguousarray(nodes, dtype=float)
        C = np.ascontiguousarray(cells, dtype=np.int64)
        width = 4 if cell_type == "tet4" else 8
        if X.ndim != 2 or X.shape[1] != 3 or C.ndim != 2 or C.shape[1] != width:
            raise MeshError(f"{source}: nodes must be (n, 3) and cells (c, {width}), got "
                            f"{X.shape} and {C.shape}")
        if C.size and (C.min() < 0 or C.max() >= X.shape[0]):
            raise MeshError(f"{source}: a cell refers to a node that does not exist")
        self.skfem = getattr(skfem, CELL_TYPES[cell_type][0])(np.ascontiguousarray(X.T),
                                                              np.ascontiguousarray(C.T))
        m = self.skfem
        faces = m.boundary_facets()
        verts = m.facets[:, faces].T.copy()  # (f, 3|4), cyclic for hexahedra
        # outward: against the owning cell's centroid
        cell = m.f2t[0, faces]
        cc = m.p[:, m.t[:, cell]].mean(axis=1).T
        P = m.p.T[verts]
        n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
        flip = np.einsum("ij,ij->i", n, P.mean(axis=1) - cc) < 0
        verts[flip] = verts[flip][:, ::-1]
        self.faces = verts
        claimed, names = _claim(m.p.T[verts].mean(axis=1), regions, "free", source, "region")
        self.face_region = claimed
        self.region_names = tuple(names)
        self.cell_region, self.volume_names = _claim(
            m.p[:, m.t].mean(axis=1).T, volumes, "body", source, "volume")
        #: the cell owning each boundary face
        self.face_cell = cell

        self._basis = None

    def basis(self):
        """The scikit-fem basis of the scalar elements (built once); a
        displacement component is one such field per direction."""
        if self._basis is None:
            skfem = load_skfem()
            el = getattr(skfem, CELL_TYPES[self.cell_type][2][self.order - 1])()
            b = skfem.Basis(self.skfem, el)
            parts = [np.asarray(getattr(b, k)).ravel()
                     for k in ("nodal_dofs", "edge_dofs", "facet_dofs", "interior_dofs")]
            self._basis = b
            #: the basis's dof of each volume node
            self.dof_order = np.concatenate(parts).astype(np.int64)
            self.node_points = np.ascontiguousarray(b.doflocs[:, self.dof_order].T)
        return self._basis

    @property
    def n_nodes(self) -> int:
        self.basis()
        return int(self.node_points.shape[0])

    def _face_nodes(self) -> np.ndarray:
        """(f, k) volume nodes of each boundary face in the surface element's
        order: corners, then (quadratic) the edges' nodes, the face's."""
        V = self.faces
        if self.order == 1:
            return V
        m = self.skfem
        nv = m.p.shape[1]
        e = np.sort(m.edges, axis=0)
        ekey = e[0] * nv + e[1]
        srt = np.argsort(ekey)
        a, b = V, np.roll(V, -1, axis=1)
        key = np.minimum(a, b) * nv + np.maximum(a, b)
        edge = srt[np.searchsorted(ekey[srt], key)]
        cols = [V, nv + edge]
        if self.cell_type == "hex8":
            faces = m.boundary_facets()
            cols.append((nv + m.edges.shape[1] + faces)[:, None])
        return np.hstack(cols)

    def boundary(self) -> tuple[SurfaceMesh, np.ndarray]:
        """(the boundary as a checked, outward :class:`SurfaceMesh` with the
        regions, volume node of each of its nodes)."""
        F = self._face_nodes()
        used = np.unique(F)
        local = np.full(self.n_nodes, -1, dtype=np.int64)
        local[used] = np.arange(used.size)
        regions = {r: np.flatnonzero(self.face_region == i) for i, r in enumerate(self.region_names)}
        surf = SurfaceMesh(self.node_points[used], local[F],
                           CELL_TYPES[self.cell_type][1][self.order - 1], regions, source=self.source)
        return surf.check(), used


def _claim(centroids: np.ndarray, choices: Mapping | None, rest: str, source: str, what: str
           ) -> tuple[np.ndarray, tuple[str, ...]]:
    """(index of the region of each item, names): each choice takes the
    items it selects that no earlier one took; the others form ``rest``."""
    claimed = np.full(len(centroids), -1)
    names: list[str] = []
    for name, choose in (choices or {}).items():
        if callable(choose):
            sel = np.flatnonzero(np.asarray(choose(centroids), dtype=bool) & (claimed < 0))
        else:
            sel = np.asarray(choose, dtype=np.int64)
            if sel.size and (sel.min() < 0 or sel.max() >= len(centroids)):
                raise MeshError(f"{source}: {what} {name!r} names an index beyond the "
                                f"{len(centroids)} there are")
        claimed[sel] = len(names)
        names.append(name)
    if (claimed < 0).any():
        claimed[claimed < 0] = len(names)
        names.append(rest)
    return claimed, tuple(names)


def solid_volume(solid, order: int = 1) -> VolumeMesh:
    """The :class:`VolumeMesh` of a gmsh-meshed solid
    (:class:`~bemcontact.mesh.mesher.SolidMesh`: the makers of
    :mod:`bemcontact.mesh.shapes` with ``solid=True``), ``order`` 1 or 2 on
    its tetrahedra."""
    return VolumeMesh(solid.nodes, solid.cells, "tet4", solid.regions, volumes=solid.volumes,
                      order=order, source=solid.source)


def read_volume_mesh(path: str, order: int = 1) -> VolumeMesh:
    """A volume mesh from any file meshio reads (gmsh ``.msh`` with named
    physical groups: its surface groups become the boundary regions, its
    volume groups the volume regions), tetrahedra or hexahedra, with
    elements of ``order`` on them.  A file
    without cells of a volume (a surface mesh) is one line naming it."""
    import os

    skfem = load_skfem()
    if not os.path.isfile(path):
        raise MeshError(f"{path}: no such file")
    try:
        m = skfem.Mesh.load(path)
    except Exception as exc:  # noqa: BLE001 - meshio/scikit-fem: many kinds
        raise MeshError(f"{path}: cannot read a volume mesh from it ({type(exc).__name__}: "
                        f"{exc}); a finite-element body needs tetrahedra or hexahedra") from None
    kinds = {"MeshTet1": "tet4", "MeshHex1": "hex8"}
    if type(m).__name__ not in kinds:
        raise MeshError(f"{path}: holds {type(m).__name__} cells; a finite-element body needs "
                        "linear tetrahedra or hexahedra (a volume mesh, not a surface mesh)")
    faces = m.boundary_facets()
    where = np.full(m.facets.shape[1], -1)
    where[faces] = np.arange(faces.size)
    regions = {}
    for name, facets in (m.boundaries or {}).items():
        if name.startswith("gmsh:"):  # meshio's own sets, not physical groups
            continue
        idx = where[np.asarray(facets)]
        regions[name] = idx[idx >= 0]
    volumes = {name: np.asarray(cells) for name, cells in (m.subdomains or {}).items()
               if not name.startswith("gmsh:")}
    return VolumeMesh(m.p.T, m.t.T, kinds[type(m).__name__], regions, volumes=volumes,
                      order=order, source=path)


def box_volume(lower: Sequence[float] = (0.0, 0.0, 0.0), upper: Sequence[float] = (1.0, 1.0, 1.0),
               divisions: int | Sequence[int] = 4, cell_type: str = "hex8", order: int = 1,
               *, coordinates: Sequence | None = None, volumes: Mapping | None = None
               ) -> VolumeMesh:
    """A structured mesh of the box ``lower`` <= x <= ``upper`` (hexahedra,
    or each cut into tetrahedra), boundary regions ``xmin`` .. ``zmax`` as
    for :func:`~bemcontact.mesh.box`.  ``coordinates``: instead of uniform
    divisions, the planes of the lattice along x, y and z (three increasing
    arrays from lower to upper; ``None`` entries stay uniform);
    ``volumes``: volume regions as for :class:`VolumeMesh`."""
    lo = np.asarray(lower, dtype=float)
    hi = np.asarray(upper, dtype=float)
    div = np.broadcast_to(np.asarray(divisions, dtype=int), (3,))
    if not (hi > lo).all() or (div < 1).any():
        raise ConfigError(f"box_volume: need lower < upper and divisions >= 1, got {lower}, "
                          f"{upper}, {divisions}")
    skfem = load_skfem()
    axes = [np.linspace(lo[i], hi[i], div[i] + 1) for i in range(3)]
    for i, c in enumerate(coordinates or (None,) * 3):
        if c is not None:
            c = np.asarray(c, dtype=float)
            if (c.ndim != 1 or c.size < 2 or not np.isclose(c[0], lo[i]) or not np.isclose(c[-1], hi[i])
                    or not (np.diff(c) > 0).all()):
                raise ConfigError(f"box_volume: coordinates[{i}] must increase from {lo[i]:g} to "
                                  f"{hi[i]:g}, got {c}")
            axes[i] = c
    m = getattr(skfem, CELL_TYPES.get(cell_type, ("MeshHex",))[0]).init_tensor(*axes)
    tol = 1e-9 * float(np.max(hi - lo))
    regions = {}
    for a in range(3):
        for side, ref in (("min", lo[a]), ("max", hi[a])):
            regions[f"{'xyz'[a]}{side}"] = (lambda c, a=a, ref=ref: np.abs(c[:, a] - ref) <= tol)
    return VolumeMesh(m.p.T, m.t.T, cell_type, regions, volumes=volumes, order=order,
                      source="box_volume")


__all__ = ["CELL_TYPES", "VolumeMesh", "box_volume", "load_skfem", "read_volume_mesh",
           "solid_volume"]

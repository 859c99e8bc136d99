import numpy as np
import pytest

import bemcontact as bc
from bemcontact.mesh import NODES_PER_ELEMENT


@pytest.mark.parametrize("element_type", ["quad4", "quad8", "quad9", "tri3", "tri6"])
def test_box_is_closed_outward_with_exact_area_and_volume(element_type):
    m = bc.box((0, 0, 0), (1.0, 2.0, 3.0), (2, 3, 4), element_type).check()
    assert m.region_names == ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
    assert m.area == pytest.approx(2 * (2 + 3 + 6), rel=1e-13)
    assert m.signed_volume() == pytest.approx(6.0, rel=1e-13)
    per_cell = 2 if element_type.startswith("tri") else 1
    assert m.region("zmax").size == 2 * 3 * per_cell
    assert m.region("xmin").size == 3 * 4 * per_cell
    assert m.elements.shape[1] == NODES_PER_ELEMENT[element_type]


def test_box_node_count_and_grading():
    m = bc.box(divisions=(2, 3, 4))
    # surface nodes of a 3 x 4 x 5 grid
    assert m.n_nodes == 3 * 4 * 5 - 1 * 2 * 3
    g = bc.box((0, 0, 0), (1, 1, 1), (4, 4, 4), grading=(8.0, 1.0, 1.0))
    xs = np.unique(np.round(g.nodes[:, 0], 12))
    h = np.diff(xs)
    assert h[-1] / h[0] == pytest.approx(8.0, rel=1e-9)  # coordinates rounded to 1e-12 above
    assert h.sum() == pytest.approx(1.0)


def test_box_faces_do_not_match_with_different_divisions():
    a = bc.box((0, 0, 0), (1, 1, 1), 3)
    b = bc.box((0, 0, 1), (1, 1, 2), 4)
    top = a.nodes[np.unique(a.elements[a.region("zmax")])]
    bottom = b.nodes[np.unique(b.elements[b.region("zmin")])]
    assert top.shape[0] == 16 and bottom.shape[0] == 25


def test_discretization_edges_and_corners_are_discontinuous():
    m = bc.box(divisions=2)
    d = bc.discretize(m)
    # interior face nodes (1 per face) are shared; every node on a cube edge
    # has one copy per incident element
    assert (~d.discontinuous).sum() == 6
    assert d.discontinuous.sum() == 6 * 4 * 3  # 4 elements per face, 3 edge/corner nodes each
    assert d.weights.sum() == pytest.approx(6.0, rel=1e-13)
    # a discontinuous collocation point lies inside its element
    assert np.all(d.points[d.discontinuous].min(axis=1) > -1e-14)


def test_meshio_roundtrip_keeps_regions(tmp_path):
    m = bc.box(divisions=2, element_type="quad8")
    path = tmp_path / "box.vtu"
    m.to_meshio().write(path)
    r = bc.read_mesh(path).check()
    assert r.n_elements == m.n_elements and r.element_type == "quad8"
    assert len(r.region_names) == 6


def test_read_gmsh_physical_groups(tmp_path):
    import gmsh  # a test dependency (pyproject [test])
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("cube")
        gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        gmsh.model.occ.synchronize()
        faces = [t for _, t in gmsh.model.getEntities(2)]
        gmsh.model.addPhysicalGroup(2, faces[:1], name="bottom")
        gmsh.model.addPhysicalGroup(2, faces[1:], name="rest")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.4)
        gmsh.model.mesh.generate(2)
        path = str(tmp_path / "cube.msh")
        gmsh.write(path)
    finally:
        gmsh.finalize()
    m = bc.read_mesh(path)
    assert set(m.region_names) == {"bottom", "rest"}
    m = m.oriented().check()
    assert m.signed_volume() == pytest.approx(1.0, rel=1e-12)
    assert m.area == pytest.approx(6.0, rel=1e-12)


# --------------------------------------------------------------- bad input
def test_non_finite_node():
    m = bc.box(divisions=1)
    X = m.nodes.copy()
    X[5, 1] = np.nan
    with pytest.raises(bc.MeshError, match=r"node 5 has non-finite coordinates"):
        bc.SurfaceMesh(X, m.elements, "quad4")


def test_degenerate_element_zero_area():
    X = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], float)
    with pytest.raises(bc.MeshError, match=r"element 0 is degenerate \(zero or near-zero area"):
        bc.SurfaceMesh(X, [[0, 1, 2, 3]], "quad4")


def test_degenerate_element_repeated_node():
    X = np.eye(3)
    with pytest.raises(bc.MeshError, match="element 0 is degenerate: it repeats a node"):
        bc.SurfaceMesh(X, [[0, 1, 1]], "tri3")


def test_node_index_out_of_range():
    with pytest.raises(bc.MeshError, match=r"element 0 refers to node indices \[0, 1, 7\]"):
        bc.SurfaceMesh(np.eye(3), [[0, 1, 7]], "tri3")


def test_unknown_element_type_and_bad_shapes():
    with pytest.raises(bc.MeshError, match="unknown element_type 'hex8'"):
        bc.SurfaceMesh(np.eye(3), [[0, 1, 2]], "hex8")
    with pytest.raises(bc.MeshError, match=r"nodes must have shape \(n, 3\)"):
        bc.SurfaceMesh(np.zeros((3, 2)), [[0, 1, 2]], "tri3")


def test_inverted_element_is_named():
    m = bc.box(divisions=2)
    E = m.elements.copy()
    E[3] = E[3][[0, 3, 2, 1]]
    with pytest.raises(bc.MeshError, match=r"inconsistent orientation: elements \[.*3.*\]"):
        bc.SurfaceMesh(m.nodes, E, "quad4", m.regions).check()


def test_whole_surface_inverted():
    m = bc.box(divisions=2).reversed()
    with pytest.raises(bc.MeshError, match="inverted orientation: the outer surface"):
        m.check()
    assert m.oriented().signed_volume() == pytest.approx(1.0)


def test_open_surface():
    m = bc.box(divisions=2)
    keep = np.setdiff1d(np.arange(m.n_elements), m.region("zmax"))
    regions = {r: np.searchsorted(keep, m.region(r)) for r in m.region_names if r != "zmax"}
    open_mesh = bc.SurfaceMesh(m.nodes, m.elements[keep], "quad4", regions)
    with pytest.raises(bc.MeshError, match="surface is not closed: edge between nodes"):
        open_mesh.check()


def test_region_errors():
    m = bc.box(divisions=1)
    with pytest.raises(bc.MeshError, match="unknown region 'top'"):
        m.region("top")
    with pytest.raises(bc.MeshError, match="element 0 is in both regions 'a' and 'b'"):
        bc.SurfaceMesh(m.nodes, m.elements, "quad4", {"a": [0, 1], "b": [0, 2, 3, 4, 5]})
    with pytest.raises(bc.MeshError, match="element 5 belongs to no region"):
        bc.SurfaceMesh(m.nodes, m.elements, "quad4", {"a": [0, 1, 2, 3, 4]})


def test_read_mesh_errors(tmp_path):
    with pytest.raises(bc.MeshError, match="nope.msh: no such file"):
        bc.read_mesh(tmp_path / "nope.msh")
    bad = tmp_path / "garbage.msh"
    bad.write_text("this is not a mesh\n")
    with pytest.raises(bc.MeshError, match="garbage.msh: cannot read mesh"):
        bc.read_mesh(bad)


def test_box_errors():
    with pytest.raises(bc.MeshError, match=r"upper\[2\] = 0.0 must exceed lower\[2\] = 0.0"):
        bc.box((0, 0, 0), (1, 1, 0))
    with pytest.raises(bc.MeshError, match="divisions must be integers >= 1"):
        bc.box(divisions=0)


def _shells(centers, size, outward=True):
    """Tetrahedral shells of edge ``size`` at ``centers`` as one tri3 mesh."""
    faces = np.array([(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)])
    if not outward:
        faces = faces[:, ::-1]
    corner = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    nodes = np.vstack([c + size * corner for c in centers])
    elements = np.vstack([faces + 4 * i for i in range(len(centers))])
    return nodes, elements


def test_boxes_containing_equals_brute_force():
    """The grid-indexed box search returns exactly the boxes a brute-force
    test finds (random boxes of very different sizes, points inside and
    outside, points on box faces)."""
    from bemcontact.mesh.surface import _boxes_containing

    rng = np.random.default_rng(7)
    lo = rng.uniform(0, 10, (300, 3))
    hi = lo + rng.uniform(0, 1, (300, 3)) ** 4 * 10
    pts = np.vstack([rng.uniform(-1, 21, (200, 3)), lo[:50], hi[50:100]])
    got = _boxes_containing(lo, hi, pts)
    for p, g in zip(pts, got):
        want = np.flatnonzero(np.all((lo <= p) & (p <= hi), axis=1))
        assert np.array_equal(np.sort(g), want)


def test_many_shells_are_checked_in_about_one_winding_number_each(monkeypatch):
    """1,500 separate shells (1,500^2 winding numbers took 4 minutes): a
    shell is tested only against the shells whose bounding box holds its
    point, here none; a cavity inside a cube is still found and must point
    inward."""
    centers = [np.array([i % 40, (i // 40) % 40, 0.0]) * 3.0 for i in range(1500)]
    mesh = bc.SurfaceMesh(*_shells(centers, 1.0), "tri3")
    calls = []
    real = bc.SurfaceMesh.winding_number
    monkeypatch.setattr(bc.SurfaceMesh, "winding_number",
                        lambda self, *a, **k: calls.append(1) or real(self, *a, **k))
    assert mesh.check() is mesh and len(calls) == 0
    # a small tetrahedral cavity inside a big one: depth 1, so it must be inward
    n1, e1 = _shells([np.zeros(3)], 10.0)
    n2, e2 = _shells([np.full(3, 1.0)], 1.0, outward=False)
    nested = bc.SurfaceMesh(np.vstack([n1, n2]), np.vstack([e1, e2 + 4]), "tri3")
    assert nested.check() is nested and len(calls) == 1
    n2, e2 = _shells([np.full(3, 1.0)], 1.0, outward=True)
    with pytest.raises(bc.MeshError, match="cavity surface"):
        bc.SurfaceMesh(np.vstack([n1, n2]), np.vstack([e1, e2 + 4]), "tri3").check()

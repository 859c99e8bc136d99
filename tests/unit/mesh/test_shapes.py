"""Graded gmsh meshes of the contact validation cases (bemcontact.mesh.shapes).

Tolerances:

* Volume, flat tri3 on a curved surface: the corners lie on the surface, so the
  mesh is inscribed and its volume is below the exact one.  A flat triangle
  with circumradius rho on a sphere of radius R lies within the sagitta
  R - sqrt(R^2 - rho^2) of the sphere (on a cylinder of radius a, within
  a (1 - cos(span/2)), span the angle its corners cover), so the missing
  volume is at most sum(area * gap) ("the sagitta bound"; measured 0.74 of
  it on spheres, 0.53 on cylinders).
* Volume, curved tri6: the midside nodes lie on the surface too, so the
  geometric error is of higher order; measured 0.001-0.006 of the sagitta
  bound, asserted below 0.02 of it.
* Nodes on the sphere / cylinder: gmsh evaluates the exact OpenCASCADE surface
  (measured error 4e-15 R); asserted to 1e-10 R.  A chord midpoint instead
  of a surface point would be off by ~h^2 / (8 R) ~ 1e-3 here.
* Grading: the mean corner-to-corner edge length of the elements near the
  contact point is within 35 % of ``fine_size`` (measured 0.94-1.03), in
  the growth zone within 35 % of the prescribed size at the elements'
  centroids (measured 0.86-0.96), and beyond the growth zone in
  [0.7, 1.15] * ``coarse_size`` (measured 0.84-0.96: gmsh fits whole
  elements between the face's boundary nodes, which shortens them).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.mesh.shapes import gmsh_box, graded_block, punch, spherical_cap

R = 10.0


def corners(mesh, elements):
    nc = 3 if mesh.element_type.startswith("tri") else 4
    return mesh.nodes[mesh.elements[elements, :nc]]


def mean_edges(mesh, elements):
    """Mean corner-to-corner edge length (per element) and centroids."""
    c = corners(mesh, elements)
    return np.linalg.norm(c - np.roll(c, -1, axis=1), axis=2).mean(axis=1), c.mean(axis=1)


def triangle_areas(c):
    return 0.5 * np.linalg.norm(np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), axis=1)


def sphere_sagitta_bound(mesh, radius):
    c = corners(mesh, mesh.region("contact"))
    A = triangle_areas(c)
    sides = [np.linalg.norm(c[:, i] - c[:, (i + 1) % 3], axis=1) for i in range(3)]
    rho = sides[0] * sides[1] * sides[2] / (4 * A)  # circumradius
    return float((A * (radius - np.sqrt(radius**2 - rho**2))).sum())


def cylinder_sagitta_bound(mesh, radius, axis_xy):
    c = corners(mesh, mesh.region("side"))
    theta = np.unwrap(np.arctan2(c[:, :, 1] - axis_xy[1], c[:, :, 0] - axis_xy[0]), axis=1)
    span = np.ptp(theta, axis=1)
    return float((triangle_areas(c) * radius * (1 - np.cos(span / 2))).sum())


def assert_volume(mesh, exact, bound):
    """Inscribed tri3: 0 < missing volume < bound; tri6: |error| < 0.02 bound."""
    missing = exact - mesh.signed_volume()
    if mesh.order == 1:
        assert 0 < missing < bound, f"missing volume {missing:.4g}, sagitta bound {bound:.4g}"
    else:
        assert abs(missing) < 0.02 * bound, f"volume error {missing:.4g}, bound {bound:.4g}"


def ramp(fine, coarse, growth, start):
    return lambda d: np.minimum(coarse, fine + growth * np.maximum(0.0, d - start))


def assert_graded(L, d, fine, coarse, growth, fine_radius):
    """Mean edge length vs the prescribed size: fine zone, growth zone, far."""
    size = ramp(fine, coarse, growth, fine_radius)
    end = fine_radius + (coarse - fine) / growth  # where the size reaches coarse
    near = d < fine_radius / 2
    assert near.sum() >= 10
    assert L[near].mean() == pytest.approx(fine, rel=0.35), (
        f"mean edge {L[near].mean():.4g} within fine_radius/2, fine_size {fine}"
    )
    for lo in (fine_radius + 1.0, 0.5 * (fine_radius + end)):
        ring = (d >= lo) & (d < lo + 1.0)
        assert ring.sum() >= 5
        want = size(d[ring]).mean()
        assert L[ring].mean() == pytest.approx(want, rel=0.35), (
            f"mean edge {L[ring].mean():.4g} at distance {lo}..{lo + 1}, prescribed {want:.4g}"
        )
    far = d > end + coarse
    assert far.sum() >= 10
    ratio = L[far].mean() / coarse
    assert 0.7 <= ratio <= 1.15, f"far mean edge / coarse_size = {ratio:.3f}"


# ------------------------------------------------------------ spherical cap
@functools.lru_cache(maxsize=None)
def cap(height, axis, order, apex=(0.0, 0.0, 0.0), fine=0.25, fine_radius=1.2):
    return spherical_cap(R, height, fine_size=fine, coarse_size=2.5, fine_radius=fine_radius,
                         apex=apex, axis=axis, order=order)


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize(
    "height, axis, apex",
    [(R, 1, (0.0, 0.0, 0.0)), (4.0, -1, (1.0, -2.0, 3.0)), (15.0, 1, (0.0, 0.0, 0.0))],
)
def test_spherical_cap_is_closed_outward_with_the_cap_volume(height, axis, apex, order):
    m = cap(height, axis, order, apex)
    assert m.region_names == ("contact", "base")
    assert m.element_type == ("tri3", "tri6")[order - 1]
    assert len(m.components()) == 1
    m.check()
    exact = math.pi * height**2 * (3 * R - height) / 3
    assert m.signed_volume() > 0
    assert_volume(m, exact, sphere_sagitta_bound(m, R))
    # the apex is the lowest (axis=+1) / highest point, its normal points away from the body
    z = m.nodes[:, 2] - apex[2]
    assert (axis * z).min() == pytest.approx(0.0, abs=1e-12 * R)
    assert (axis * z).max() == pytest.approx(height, rel=1e-12)
    _, cen = mean_edges(m, m.region("contact"))
    e = m.region("contact")[np.argmin(np.linalg.norm(cen - apex, axis=1))]
    _, n, _ = m.map([e], [[1 / 3, 1 / 3]])
    assert n[0, 2] * axis < -0.99
    _, n, _ = m.map(m.region("base")[:1], [[1 / 3, 1 / 3]])
    assert n[0, 2] * axis == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("order", [1, 2])
def test_spherical_cap_nodes_lie_on_the_sphere_and_the_base_plane(order):
    apex = (1.0, -2.0, 3.0)
    m = cap(4.0, -1, order, apex)
    center = np.array(apex) - [0, 0, R]
    contact = m.elements[m.region("contact")]
    dist = np.linalg.norm(m.nodes - center, axis=1)
    err = np.abs(dist[np.unique(contact)] - R).max()
    assert err < 1e-10 * R, f"contact nodes off the sphere by {err:.3g}"
    base = np.unique(m.elements[m.region("base")])
    assert np.abs(m.nodes[base, 2] - (apex[2] - 4.0)).max() < 1e-12 * R
    if order == 2:
        # midside nodes are on the sphere, not at the chord midpoints
        mid = m.nodes[contact[:, 3:]]
        chord = 0.5 * (m.nodes[contact[:, [0, 1, 2]]] + m.nodes[contact[:, [1, 2, 0]]])
        assert np.abs(np.linalg.norm(mid - center, axis=2) - R).max() < 1e-10 * R
        assert np.abs(np.linalg.norm(chord - center, axis=2) - R).max() > 1e-3


def test_spherical_cap_is_graded_toward_the_apex():
    # the brief's hemisphere: R = 10, 0.1 within 1.2 of the apex, up to 2.5
    fine, fine_radius = 0.1, 1.2
    m = cap(R, 1, 1, fine=fine, fine_radius=fine_radius)
    L, cen = mean_edges(m, np.arange(m.n_elements))
    assert_graded(L, np.linalg.norm(cen, axis=1), fine, 2.5, 0.3, fine_radius)
    # grading pays: a uniform 0.1 mesh of the hemisphere would need ~270 000 triangles
    uniform = 3 * math.pi * R**2 / (math.sqrt(3) / 4 * fine**2)
    assert m.n_elements < 0.02 * uniform, f"{m.n_elements} elements"


# ------------------------------------------------------------- graded block
@functools.lru_cache(maxsize=None)
def block(order, quads, focus=(0.0, 0.0, 0.0), fine=0.1, fine_radius=1.2):
    return graded_block((-10, -10, -10), (10, 10, 0), focus, fine_size=fine, coarse_size=2.5,
                        fine_radius=fine_radius, order=order, quads=quads)


@pytest.mark.parametrize(
    "order, quads, element_type", [(1, False, "tri3"), (2, False, "tri6"), (1, True, "quad4"),
                                   (2, True, "quad9")]
)
def test_graded_block_is_a_closed_box_graded_toward_the_focus(order, quads, element_type):
    m = block(order, quads, fine=0.2) if order == 2 else block(order, quads)
    fine = 0.2 if order == 2 else 0.1
    assert m.region_names == ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
    assert m.element_type == element_type
    m.check()
    assert m.signed_volume() == pytest.approx(20 * 20 * 10, rel=1e-12)
    # every node on a face of the box
    X = m.nodes
    on_face = (np.abs(np.abs(X[:, :2]) - 10) < 1e-9).any(axis=1) | (np.abs(X[:, 2] + 5) > 5 - 1e-9)
    assert on_face.all()
    L, cen = mean_edges(m, np.arange(m.n_elements))
    assert_graded(L, np.linalg.norm(cen, axis=1), fine, 2.5, 0.3, 1.2)
    # the fine elements are on the focus' face
    near = np.linalg.norm(cen, axis=1) < 1.2
    assert set(m.element_region[near]) == {m.region_names.index("zmax")}


def test_graded_block_focus_on_a_side_face():
    focus = (10.0, 2.0, -5.0)
    m = block(1, False, focus, fine=0.2, fine_radius=1.0)
    L, cen = mean_edges(m, np.arange(m.n_elements))
    d = np.linalg.norm(cen - focus, axis=1)
    assert set(m.element_region[d < 1.0]) == {m.region_names.index("xmax")}
    assert_graded(L, d, 0.2, 2.5, 0.3, 1.0)


def test_size_profile_refines_a_ring():
    # a ring of size 0.05 at distance 1 (a punch's rim), 0.2 at the centre,
    # then growth 0.3 per unit distance up to 1.5
    knots = [(0.0, 0.2), (0.5, 0.2), (0.9, 0.05), (1.1, 0.05)]
    m = graded_block((-4, -4, -3), (4, 4, 0), (0, 0, 0), fine_size=0.05, coarse_size=1.5,
                     size_profile=knots)
    m.check()
    assert m.signed_volume() == pytest.approx(8 * 8 * 3, rel=1e-12)
    L, cen = mean_edges(m, np.arange(m.n_elements))
    d = np.linalg.norm(cen, axis=1)
    want = lambda x: np.interp(x, *zip(*knots)) if x < 1.1 else min(1.5, 0.05 + 0.3 * (x - 1.1))  # noqa: E731
    for lo, hi in ((0.0, 0.3), (0.95, 1.05), (2.0, 2.5)):
        band = (d >= lo) & (d < hi)
        assert band.sum() >= 5
        expected = np.mean([want(x) for x in d[band]])
        assert L[band].mean() == pytest.approx(expected, rel=0.35), (lo, hi, L[band].mean(), expected)
    # the same knots on a cap: fine at the ring, coarser at the apex
    c = spherical_cap(10.0, 10.0, fine_size=0.05, coarse_size=2.5, size_profile=knots, order=1)
    Lc, cc = mean_edges(c, c.region("contact"))
    dc = np.linalg.norm(cc, axis=1)
    ring = (dc > 0.95) & (dc < 1.05)
    apex = dc < 0.3
    assert Lc[ring].mean() == pytest.approx(0.05, rel=0.35)
    assert Lc[apex].mean() == pytest.approx(0.2, rel=0.35)


def test_gmsh_box_quads_are_all_quadrilaterals():
    # at this size blossom recombination can leave triangles (mixed tri3/quad4)
    m = gmsh_box((0, 0, 0), (2, 2, 1), 0.2, quads=True)
    assert m.element_type == "quad4"
    assert m.signed_volume() == pytest.approx(4.0, rel=1e-12)


# -------------------------------------------------------------------- punch
@functools.lru_cache(maxsize=None)
def flat_punch(order, axis, fine=0.05, center_size=None):
    return punch(1.0, 2.0, fine_size=fine, coarse_size=0.5, center_size=center_size,
                 base_center=(1.0, 2.0, 3.0), axis=axis, order=order)


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("axis", [1, -1])
def test_punch_is_a_closed_cylinder_refined_at_the_rim(order, axis):
    a, H, fine, coarse = 1.0, 2.0, 0.05, 0.5
    m = flat_punch(order, axis)
    assert m.region_names == ("contact", "side", "top")
    m.check()
    assert_volume(m, math.pi * a**2 * H, cylinder_sagitta_bound(m, a, (1.0, 2.0)))
    X = m.nodes - [1.0, 2.0, 3.0]
    side = np.unique(m.elements[m.region("side")])
    err = np.abs(np.linalg.norm(X[side, :2], axis=1) - a).max()
    assert err < 1e-10 * a, f"side nodes off the cylinder by {err:.3g}"
    contact = np.unique(m.elements[m.region("contact")])
    assert np.abs(X[contact, 2]).max() < 1e-12
    assert (axis * X[:, 2]).max() == pytest.approx(H, rel=1e-12)
    _, n, _ = m.map(m.region("contact")[:1], [[1 / 3, 1 / 3]])
    assert n[0, 2] * axis == pytest.approx(-1.0, abs=1e-12)
    # size: fine_size at the rim, center_size (2 * fine_size) at the centre, coarse on top
    L, cen = mean_edges(m, m.region("contact"))
    rho = np.linalg.norm(corners(m, m.region("contact"))[:, :, :2] - [1.0, 2.0], axis=2)
    at_rim = (np.abs(rho - a) < 1e-9).sum(axis=1) >= 2  # an edge on the rim
    assert at_rim.sum() >= 2 * math.pi * a / fine * 0.7
    assert L[at_rim].mean() == pytest.approx(fine, rel=0.35)
    center = np.linalg.norm(cen[:, :2] - [1.0, 2.0], axis=1) < a / 4
    assert L[center].mean() == pytest.approx(2 * fine, rel=0.35)
    assert L.max() < 1.5 * 2 * fine, f"coarsest contact element {L.max():.3g}"
    Lt, _ = mean_edges(m, m.region("top"))
    assert 0.7 <= Lt.mean() / coarse <= 1.15


def test_punch_center_size():
    m = flat_punch(1, 1, fine=0.05, center_size=0.15)
    L, cen = mean_edges(m, m.region("contact"))
    center = np.linalg.norm(cen[:, :2] - [1.0, 2.0], axis=1) < 0.25
    assert L[center].mean() == pytest.approx(0.15, rel=0.35)


# ---------------------------------------------------------------- bad input
CAP = dict(radius=10.0, height=10.0, fine_size=0.1, coarse_size=2.5, fine_radius=1.0)
BLOCK = dict(lower=(-1, -1, -1), upper=(1, 1, 0), focus=(0, 0, 0), fine_size=0.1,
             coarse_size=0.5, fine_radius=0.2)
PUNCH = dict(radius=1.0, height=1.0, fine_size=0.05, coarse_size=0.5)


@pytest.mark.parametrize(
    "function, base, change, match",
    [
        (spherical_cap, CAP, {"radius": -1.0}, r"radius must be a finite number > 0, got -1"),
        (spherical_cap, CAP, {"radius": "ten"}, r"radius must be a number, got 'ten'"),
        (spherical_cap, CAP, {"height": 0.0}, r"height must be a finite number > 0, got 0"),
        (spherical_cap, CAP, {"height": -2.0}, r"height must be .* > 0, got -2"),
        (spherical_cap, CAP, {"height": 20.0}, r"height = 20.0 must be below 2 \* radius = 20"),
        (spherical_cap, CAP, {"height": 25.0}, r"height = 25.0 must be below"),
        (spherical_cap, CAP, {"fine_size": 3.0}, r"fine_size = 3.0 must not exceed coarse_size"),
        (spherical_cap, CAP, {"fine_size": 0.0}, r"fine_size must be .* > 0, got 0"),
        (spherical_cap, CAP, {"coarse_size": math.inf}, r"coarse_size must be a finite"),
        (spherical_cap, CAP, {"fine_radius": -0.5}, r"fine_radius must be .* >= 0, got -0.5"),
        (spherical_cap, CAP, {"growth": 0.0}, r"growth must be .* > 0, got 0"),
        (spherical_cap, CAP, {"axis": 0}, r"axis must be \+1 or -1 .*, got 0"),
        (spherical_cap, CAP, {"axis": 2}, r"axis must be \+1 or -1 .*, got 2"),
        (spherical_cap, CAP, {"apex": (0, 0)}, r"apex must be 3 finite numbers"),
        (spherical_cap, CAP, {"apex": (0, 0, math.nan)}, r"apex must be 3 finite numbers"),
        (spherical_cap, CAP, {"order": 3}, r"order must be 1 or 2, got 3"),
        (graded_block, BLOCK, {"upper": (1, -2, 0)}, r"need lower < upper componentwise"),
        (graded_block, BLOCK, {"focus": (0, 0, -0.5)}, r"focus = \(0, 0, -0.5\) must lie on a"),
        (graded_block, BLOCK, {"focus": (0, 0, 0.5)}, r"focus = \(0, 0, 0.5\) must lie on a face"),
        (graded_block, BLOCK, {"fine_size": 1.0}, r"fine_size = 1.0 must not exceed"),
        (graded_block, BLOCK, {"order": 0}, r"order must be 1 or 2, got 0"),
        (graded_block, BLOCK, {"size_profile": [(0, 0.1)]}, r"exactly one of fine_radius and size_profile"),
        (graded_block, {**BLOCK, "fine_radius": None}, {}, r"exactly one of fine_radius and size_profile"),
        (graded_block, {**BLOCK, "fine_radius": None}, {"size_profile": [(0.1, 0.1)]},
         r"size_profile must start at distance 0"),
        (graded_block, {**BLOCK, "fine_radius": None}, {"size_profile": [(0, 0.1), (0, 0.2)]},
         r"distances must increase strictly, got 0.0 then 0.0"),
        (graded_block, {**BLOCK, "fine_radius": None}, {"size_profile": [(0, 0.05)]},
         r"size 0.05 at distance 0.0 must lie between fine_size = 0.1 and coarse_size = 0.5"),
        (graded_block, {**BLOCK, "fine_radius": None}, {"size_profile": [(0, "x")]},
         r"size_profile must be \(distance, size\) pairs"),
        (spherical_cap, {**CAP, "fine_radius": None}, {"size_profile": 3},
         r"size_profile must be \(distance, size\) pairs"),
        (punch, PUNCH, {"radius": 0.0}, r"radius must be .* > 0, got 0"),
        (punch, PUNCH, {"height": -1.0}, r"height must be .* > 0, got -1"),
        (punch, PUNCH, {"center_size": 0.01}, r"center_size = 0.01 must lie between"),
        (punch, PUNCH, {"center_size": 1.0}, r"center_size = 1.0 must lie between"),
        (punch, PUNCH, {"axis": -2}, r"axis must be \+1 or -1"),
        (punch, PUNCH, {"base_center": "origin"}, r"base_center must be 3 numbers"),
    ],
)
def test_bad_input_raises_config_error_naming_the_argument(function, base, change, match):
    with pytest.raises(ConfigError, match=match):
        function(**{**base, **change})


def test_element_estimate_of_a_uniform_mesh_is_the_area_over_a_triangle():
    """With the fine zone covering the whole surface, N = area / ((√3/4) h²)
    to the midpoint rule's accuracy (1e-6); a rim adds the band around it;
    coarser grading gives fewer elements."""
    from bemcontact.mesh.shapes import element_estimate

    area, h = 100.0, 0.1
    want = area / (np.sqrt(3) / 4 * h * h)
    assert element_estimate(area, h, 1.0, 0.3, fine_radius=1e3) == pytest.approx(want, rel=1e-6)
    assert element_estimate(area, h, 1.0, 0.3, fine_radius=1e3, rim=2.0) == pytest.approx(
        want, rel=1e-6)
    graded = element_estimate(area, h, 1.0, 0.3, fine_radius=0.5)
    assert graded < 0.2 * want


def test_element_estimate_bounds_the_meshes_from_above():
    """On the example's cap and graded box (fine 0.1 within 0.7, coarse
    2.5): the estimate is above gmsh's count and within 2x of it (measured
    2,262 / 1,502 and 2,505 / 1,756)."""
    pytest.importorskip("gmsh")
    from bemcontact.mesh.shapes import element_estimate, graded_block, spherical_cap

    cap = spherical_cap(10.0, 10.0, fine_size=0.1, coarse_size=2.5, fine_radius=0.7)
    est = element_estimate(2 * np.pi * 100 + np.pi * 100, 0.1, 2.5, 0.3, 0.7)
    assert cap.n_elements < est < 2 * cap.n_elements
    block = graded_block((-10, -10, -10), (10, 10, 0), (0, 0, 0), fine_size=0.1,
                         coarse_size=2.5, fine_radius=0.7)
    est = element_estimate(2 * (400 + 200 + 200), 0.1, 2.5, 0.3, 0.7)
    assert block.n_elements < est < 2 * block.n_elements

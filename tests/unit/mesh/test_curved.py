"""Graded gmsh meshes of bemcontact.mesh.curved: regions, closed and outward,
volumes, nodes on the exact surfaces, grading toward the contact point, bad
input.

Tolerances: volumes as in test_shapes.py (flat tri3 are inscribed: the half
cylinder misses a volume below its sagitta bound, measured 0.53 of it on
cylinders; the seat's concave dimple is inscribed from the cavity side, so
the block has *more* volume, by less than the dimple's area times
h_max^2 / (8 R2)); nodes on the cylinder / sphere to 1e-10 R (gmsh evaluates
the OpenCASCADE surface, measured 1e-14 R).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.mesh.curved import half_cylinder, spherical_seat

R, L = 10.0, 20.0


@functools.lru_cache(maxsize=None)
def cylinder(axis, direction, order=1):
    return half_cylinder(R, L, fine_size=0.3, coarse_size=2.5, fine_radius=1.0,
                         apex=(1.0, 2.0, 3.0), axis=axis, direction=direction, order=order)


@pytest.mark.parametrize("axis, direction", [(1, "x"), (-1, "y")])
def test_half_cylinder(axis, direction):
    m = cylinder(axis, direction)
    assert m.region_names == ("contact", "base", "ends")
    assert len(m.components()) == 1
    m.check()
    exact = 0.5 * math.pi * R**2 * L
    assert 0 < exact - m.signed_volume() < 0.02 * exact
    apex = np.array([1.0, 2.0, 3.0])
    along = "xy".index(direction)
    across = 1 - along
    contact = np.unique(m.elements[m.region("contact")])
    X = m.nodes[contact]
    dist = np.hypot(X[:, across] - apex[across], X[:, 2] - (apex[2] + axis * R))
    assert np.abs(dist - R).max() < 1e-10 * R
    # the body lies on the axis side of the apex, the base through the axis
    z = axis * (m.nodes[:, 2] - apex[2])
    assert z.min() == pytest.approx(0.0, abs=1e-6) and z.max() == pytest.approx(R, rel=1e-12)
    base = np.unique(m.elements[m.region("base")])
    assert np.abs(m.nodes[base, 2] - (apex[2] + axis * R)).max() < 1e-12 * R
    ends = np.unique(m.elements[m.region("ends")])
    assert np.allclose(np.abs(m.nodes[ends, along] - apex[along]), L / 2, atol=1e-12 * L)
    # graded: the elements near the apex have about fine_size, the far ones coarse
    c = m.nodes[m.elements[:, :3]]
    edge = np.linalg.norm(c - np.roll(c, -1, axis=1), axis=2).mean(axis=1)
    d = np.linalg.norm(c.mean(axis=1) - apex, axis=1)
    assert edge[d < 0.5].mean() == pytest.approx(0.3, rel=0.35)
    assert edge[d > 12].mean() == pytest.approx(2.5, rel=0.3)


def test_spherical_seat():
    R2, depth, W, H = 12.0, 2.0, 10.0, 10.0
    m = spherical_seat(R2, depth, W, H, fine_size=0.3, coarse_size=2.5, fine_radius=1.0,
                       bottom=(0.5, -0.5, 1.0))
    assert m.region_names == ("contact", "top", "side", "base")
    m.check()
    cap = math.pi * depth**2 * (3 * R2 - depth) / 3
    exact = (2 * W) ** 2 * (H + depth) - cap
    extra = m.signed_volume() - exact
    area = 2 * math.pi * R2 * depth
    assert 0 < extra < area * 2.5**2 / (8 * R2)
    center = np.array([0.5, -0.5, 1.0 + R2])
    contact = np.unique(m.elements[m.region("contact")])
    assert np.abs(np.linalg.norm(m.nodes[contact] - center, axis=1) - R2).max() < 1e-10 * R2
    assert m.nodes[:, 2].min() == pytest.approx(1.0 - H)
    # the dimple's outward normal (into the cavity) points up at its bottom
    cen = m.nodes[m.elements[m.region("contact"), :3]].mean(axis=1)
    e = m.region("contact")[np.argmin(np.linalg.norm(cen - [0.5, -0.5, 1.0], axis=1))]
    _, n, _ = m.map([e], [[1 / 3, 1 / 3]])
    assert n[0, 2] > 0.99


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: half_cylinder(R, L, fine_size=0.3, coarse_size=2.5, fine_radius=1.0,
                               direction="z"), "direction"),
        (lambda: half_cylinder(R, -1.0, fine_size=0.3, coarse_size=2.5, fine_radius=1.0),
         "length"),
        (lambda: spherical_seat(12.0, 12.0, 20.0, 10.0, fine_size=0.3, coarse_size=2.5,
                                fine_radius=1.0), "depth"),
        (lambda: spherical_seat(12.0, 6.0, 8.0, 10.0, fine_size=0.3, coarse_size=2.5,
                                fine_radius=1.0), "rim radius"),
    ],
)
def test_bad_input(call, match):
    with pytest.raises(ConfigError, match=match):
        call()


def test_ball_is_closed_graded_and_mirror_symmetric():
    """The ball of bemcontact.mesh.curved: regions, one closed outward
    shell, nodes on the sphere (1e-10 R), inscribed volume (below the
    sagitta bound), and its mirror image in the equator plane is itself:
    every node's reflection is a node (1e-12 R) and the caps swap."""
    from bemcontact.mesh.curved import ball, mirrored

    lo = (1.0, 2.0, 3.0)
    m = ball(R, fine_size=0.4, coarse_size=2.5, fine_radius=1.0, lowest=lo, band=0.3)
    assert set(m.region_names) == {"bottom", "band", "top"}
    assert len(m.components()) == 1
    m.check()
    centre = np.array([lo[0], lo[1], lo[2] + R])
    assert np.abs(np.linalg.norm(m.nodes - centre, axis=1) - R).max() <= 1e-10 * R
    exact = 4.0 / 3.0 * math.pi * R**3
    assert 0 < exact - m.signed_volume() < 0.02 * exact
    image = mirrored(m, centre[2], {"bottom": "top", "top": "bottom"})
    key = lambda X: np.round(X / (1e-12 * R)).astype(np.int64)  # noqa: E731
    assert {tuple(p) for p in key(image.nodes)} == {tuple(p) for p in key(m.nodes)}
    assert image.signed_volume() == pytest.approx(m.signed_volume(), rel=1e-12)
    # graded toward both poles: small elements there, large at the equator
    sizes = np.sqrt(m.surface_quadrature(2).weights.sum(axis=1))
    z = m.nodes[m.elements].mean(axis=1)[:, 2] - centre[2]
    assert sizes[np.abs(z) > 0.99 * R].max() < sizes[np.abs(z) < 0.1 * R].min()
    with pytest.raises(ConfigError, match="ball: band must be in"):
        ball(R, fine_size=0.4, coarse_size=2.5, fine_radius=1.0, band=0.9)

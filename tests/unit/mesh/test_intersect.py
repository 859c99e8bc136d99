"""Self-intersection of a surface (bemcontact.mesh.intersect): a closed
surface that intersects itself is not reported by mesh-info as "usable as a
body"."""

from __future__ import annotations

import itertools
import time

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.mesh.intersect import _cross, crossing_triangles

T = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])


@pytest.mark.parametrize("other, crossing", [
    ([[0.2, 0.2, -1], [0.2, 0.2, 1], [0.3, 0.5, 0]], True),     # pierces it
    ([[0.2, 0.2, 1], [0.2, 0.2, 3], [0.3, 0.5, 2]], False),     # above it
    ([[0.2, 0.2, 0], [1.2, 0.2, 0], [0.2, 1.2, 0]], True),      # coplanar, overlapping
    ([[1, 1, 0], [2, 1, 0], [1, 2, 0]], False),                 # coplanar, apart
    ([[1, 0, 0], [2, 0, 0], [1, 1, 0]], True),                  # touches a corner
    ([[0, 0, 1e-3], [1, 0, 1e-3], [0, 1, 1e-3]], False),        # parallel plane
    ([[0.6, 0.6, -1], [0.6, 0.6, 1], [2, 2, 0]], False),        # beside the hypotenuse
    ([[0.4, 0.4, -1], [0.4, 0.4, 1], [2, 2, 0]], True),         # through it near it
])
def test_a_pair_of_triangles(other, crossing):
    U = np.array(other, dtype=float)
    assert _cross(T[None], U[None], 1e-12)[0] == crossing
    assert _cross(U[None], T[None], 1e-12)[0] == crossing


def test_the_index_finds_what_all_pairs_find():
    """Random triangle soups: the k-d-tree search reports a crossing exactly
    when testing every pair does, and the pair it reports is one."""
    rng = np.random.default_rng(7)
    outcomes = set()
    for trial in range(40):
        n = 30
        nodes = rng.uniform(0, 4, (3 * n, 3))
        sizes = rng.choice([0.05, 0.3, 1.0], n)  # three size classes
        centre = rng.uniform(0, 4, (n, 3))
        nodes = (centre[:, None, :] + sizes[:, None, None] * rng.normal(size=(n, 3, 3))).reshape(-1, 3)
        tris = np.arange(3 * n).reshape(n, 3)
        brute = {(i, j) for i, j in itertools.combinations(range(n), 2)
                 if _cross(nodes[tris[i]][None], nodes[tris[j]][None], 1e-9 * 4)[0]}
        hit = crossing_triangles(nodes, tris)
        assert (hit is not None) == bool(brute), (trial, hit, brute)
        assert hit is None or hit in brute
        outcomes.add(hit is None)
    assert outcomes == {True, False}


@pytest.mark.parametrize("offset", [(1.0, 1.0, 1.0), (0.5, 0.25, 0.75), (0.0, 0.0, 1.5)])
def test_two_boxes_through_each_other(offset):
    """Including boxes offset by whole elements, which cross along mesh lines
    where every pair of triangles only touches."""
    a = bc.box((0, 0, 0), (2, 2, 2), 2, "tri3")
    nodes = np.vstack([a.nodes, a.nodes + offset])
    both = bc.SurfaceMesh(nodes, np.vstack([a.elements, a.elements + a.n_nodes]), "tri3")
    with pytest.raises(bc.MeshError, match=r"the surface intersects itself: elements \d+ and "
                       r"\d+ \(regions surface\) cross near \("):
        both.check()
    apart = bc.SurfaceMesh(np.vstack([a.nodes, a.nodes + (3.0, 0, 0)]), both.elements, "tri3")
    assert apart.check() is apart


@pytest.mark.parametrize("mesh", [
    lambda: bc.box((0, 0, 0), (1, 2, 3), (7, 5, 3), "quad8"),
    lambda: bc.box((0, 0, 0), (1, 1, 1), 6, "tri6", grading=(2.0, 1.0, 0.5)),
    lambda: bc.box((-1e-3, 0, 0), (1e-3, 1e-3, 1e-6), (4, 4, 1), "quad4"),  # thin plate
], ids=["quad8", "graded-tri6", "thin-plate"])
def test_valid_surfaces_pass(mesh):
    m = mesh()
    assert m.check() is m


def test_a_quadrilateral_folded_through_the_surface_is_found():
    m = bc.box((0, 0, 0), (2, 2, 2), 4, "quad4")
    nodes = m.nodes.copy()
    inner_top = np.flatnonzero(np.all(np.isclose(nodes, [1, 1, 2]), axis=1))[0]
    nodes[inner_top] = [1, 1, -0.5]  # the top's centre node pulled through the bottom
    folded = bc.SurfaceMesh(nodes, m.elements, "quad4", m.regions)
    with pytest.raises(bc.MeshError, match=r"intersects itself: .* \(regions zmax, zmin\)"):
        folded.check()


def test_the_search_is_not_quadratic():
    """120,000 triangles (a box of 60,000 quadrilaterals): all pairs would be
    7.2e9 tests; the index does it in seconds."""
    m = bc.box((0, 0, 0), (2, 2, 2), 100)
    start = time.perf_counter()
    m._check_crossings("")
    assert time.perf_counter() - start < 10.0

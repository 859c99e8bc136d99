"""Probes: their points, lattices and one-line errors."""

from __future__ import annotations

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.stresses import Box, Lattice, Line, Plane, StressRequest


def test_a_line_spaces_its_points_evenly_from_start_to_end():
    line = Line((0, 0, -0.1), (0, 0, -2.1), 5)
    X = line.locations()
    assert X.shape == (5, 3) and line.shape == (5,)
    assert np.allclose(X[:, 2], [-0.1, -0.6, -1.1, -1.6, -2.1], rtol=0, atol=1e-15)
    assert np.allclose(line.distance(), [0, 0.5, 1.0, 1.5, 2.0], rtol=0, atol=1e-15)


def test_a_plane_is_a_rectangle_normal_to_its_normal_centred_on_its_origin():
    plane = Plane((1, 2, 3), (0, 2, 0), (4, 2), (5, 3), u_axis=(1, 1, 0))
    X = plane.locations()
    assert X.shape == (15, 3) and plane.shape == (5, 3)
    A = plane.axes()
    assert np.allclose(A @ A.T, np.eye(3), atol=1e-15)  # orthonormal, right-handed
    assert np.linalg.det(A) == pytest.approx(1.0, abs=1e-15)
    assert np.allclose(A[2], [0, 1, 0]) and np.allclose(A[0], [1, 0, 0])  # u projected
    assert np.allclose(X[:, 1], 2.0, atol=1e-15)  # in the plane y = 2
    assert np.allclose(X.mean(axis=0), [1, 2, 3], atol=1e-14)
    u = (X - [1, 2, 3]) @ A[0]
    v = (X - [1, 2, 3]) @ A[1]
    assert u.min() == pytest.approx(-2.0) and u.max() == pytest.approx(2.0)
    assert v.min() == pytest.approx(-1.0) and v.max() == pytest.approx(1.0)


def test_a_box_holds_its_faces_and_a_flat_box_is_a_slice():
    box = Box((0, 0, 0), (1, 2, 3), (2, 3, 4))
    X = box.locations()
    assert X.shape == (24, 3)
    assert np.allclose(X.min(axis=0), [0, 0, 0]) and np.allclose(X.max(axis=0), [1, 2, 3])
    flat = Box((0, 0, -1), (1, 1, -1), (3, 3, 1))
    assert np.all(flat.locations()[:, 2] == -1.0) and flat.shape == (3, 3, 1)
    lat = Lattice.of(box)
    assert lat.names == ("x", "y", "z") and [len(c) for c in lat.coordinates] == [2, 3, 4]


@pytest.mark.parametrize("make, field", [
    (lambda: Line((0, 0, 0), (0, 0, 0)), "to"),
    (lambda: Line((0, 0, 0), (0, 0, 1), 1), "points"),
    (lambda: Line((0, 0, float("nan")), (0, 0, 1)), "from"),
    (lambda: Plane((0, 0, 0), (0, 0, 0), (1, 1)), "normal"),
    (lambda: Plane((0, 0, 0), (0, 0, 1), (1, -1)), "size"),
    (lambda: Plane((0, 0, 0), (0, 0, 1), (1, 1), u_axis=(0, 0, 2)), "u_axis"),
    (lambda: Box((0, 0, 0), (1, -1, 1)), "upper"),
    (lambda: Box((0, 0, 0), (1, 1, 0), (3, 3, 3)), "points"),
    (lambda: Box((0, 0, 0), (1, 1, 1), (200, 200, 200)), "points"),
])
def test_bad_probes_are_one_line_errors_naming_the_field(make, field):
    with pytest.raises(ConfigError) as e:
        make()
    assert "\n" not in str(e.value) and e.value.location["field"] == field


def test_a_request_needs_a_body_a_probe_and_a_file_name_label():
    line = Line((0, 0, 0), (0, 0, 1))
    assert StressRequest("block", line, "axis").kind == "line"
    for body, probe, label in (("", line, "a"), ("b", "line", "a"), ("b", line, "a b"),
                               ("b", line, "_a")):
        with pytest.raises(ConfigError):
            StressRequest(body, probe, label)

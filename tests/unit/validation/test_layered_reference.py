"""The coated half-space reference (validation.reference.layered) against
what it must reduce to: Boussinesq's compliance without a layer, each
material's own at the long- and short-wave limits, and Hertz for a
uniform half-space."""

from __future__ import annotations

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.validation.reference import contact as ref
from bemcontact.validation.reference import layered

STEEL = (210000.0, 0.3)
CERAMIC = (600000.0, 0.25)


def _boussinesq(m):
    return 2.0 * (1.0 - m[1] ** 2) / m[0]


def test_a_layer_of_the_substrate_s_material_is_boussinesq():
    """To round-off: a 4 × 4 matrix exponential and a 2 × 2 solve in
    units of the substrate's modulus (1e-10; measured 1e-12)."""
    c = layered.surface_compliance(np.geomspace(1e-3, 30.0, 7), STEEL, STEEL)
    np.testing.assert_allclose(c, _boussinesq(STEEL), rtol=1e-10)


def test_long_waves_see_the_substrate_and_short_waves_the_layer():
    """c(kt) → the substrate's as kt → 0 (to O(kt): 1e-3 at kt = 1e-4 is
    generous, measured 5e-5) and the layer's for kt ≥ 10 (the substrate's
    effect falls as e^(-2kt): 1e-6 at kt = 10), monotone between (a
    stiffer layer stiffens ever shorter waves more)."""
    kt = np.geomspace(1e-4, 30.0, 60)
    c = layered.surface_compliance(kt, CERAMIC, STEEL)
    assert abs(c[0] / _boussinesq(STEEL) - 1.0) <= 1e-3
    np.testing.assert_allclose(c[kt >= 10.0], _boussinesq(CERAMIC), rtol=1e-6)
    assert np.all(np.diff(c) <= 1e-15)


def test_a_sphere_on_a_uniform_half_space_is_hertz():
    """Force 2640 N on a 10 mm steel sphere (a ≈ 0.55 mm), cells a/40:
    the moment radius and the peak pressure within 0.3 % of Hertz
    (measured -0.06 % and +0.09 %: the grid's discretization), the force
    exact, with and without a layer of the substrate's material."""
    h = ref.hertz(2640.0, 10.0, STEEL[0] / (2.0 * (1.0 - STEEL[1] ** 2)))
    for t in (0.0, 0.5):
        g = layered.sphere_on_coated_half_space(2640.0, 10.0, STEEL, STEEL, t, STEEL)
        assert g.normal_force == pytest.approx(2640.0, rel=1e-12)
        assert abs(g.moment_radius / h.contact_radius - 1.0) <= 3e-3
        assert abs(g.peak_pressure / h.peak_pressure - 1.0) <= 3e-3
        r = np.linspace(0.0, 0.8, 9) * h.contact_radius
        pts = np.column_stack([r, np.zeros_like(r)])
        np.testing.assert_allclose(g.pressure_at(pts), h.pressure(r), rtol=0.01)


@pytest.mark.parametrize("kwargs, message", [
    ({"thickness": -1.0}, "thickness must be a number >= 0"),
    ({"layer": (0.0, 0.3)}, "layer: youngs_modulus must be a number > 0"),
    ({"substrate": (210000.0, 0.5)}, "substrate: poisson_ratio must be in (-1, 0.5)"),
    ({"normal_force": -2.0}, "normal_force must be a number > 0"),
])
def test_bad_arguments_are_one_line_errors(kwargs, message):
    args = dict(normal_force=10.0, radius=10.0, sphere=STEEL, layer=CERAMIC, thickness=0.5,
                substrate=STEEL) | kwargs
    with pytest.raises(ConfigError, match=message.replace("(", r"\(").replace(")", r"\)")):
        layered.sphere_on_coated_half_space(**args)

"""bemcontact.validation.curved.shear_pattern on synthetic frame fields:
a pure pattern is all share, noise is none of it, the rms is the
area-weighted root mean square of |q| over the peak pressure."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.validation.curved import shear_pattern


def _frame(q_of, n=4000, seed=0):
    rng = np.random.default_rng(seed)
    r = np.sqrt(rng.uniform(0, 1, n))
    th = rng.uniform(-np.pi, np.pi, n)
    x, y = r * np.cos(th), r * np.sin(th)
    q = np.zeros((n, 3))
    q[:, :2] = q_of(x, y, rng)
    pts = np.column_stack([x, y, np.zeros(n)])
    return SimpleNamespace(points=pts, tangential_traction=q, pressure=2.0 * np.sqrt(1 - r**2) + 1e-3,
                           weights=np.full(n, 1.0 / n))


def test_a_pure_saddle_is_all_share():
    fr = _frame(lambda x, y, _: 0.01 * np.column_stack([x, -y]))
    share, rms = shear_pattern(fr, "saddle")
    # the amplitude 0.01 r is fitted as a constant per ring of 1/8 the
    # radius: what the rings miss of it is 0.3 % of |q|^2
    assert share == pytest.approx(1.0, abs=0.005)
    # |q| = 0.01 r, rms over the unit disc 0.01 sqrt(1/2) (uniform points), peak p ~ 2
    assert rms == pytest.approx(0.01 * np.sqrt(0.5) / fr.pressure.max(), rel=0.03)
    # the saddle has no radial part with an amplitude per ring
    assert shear_pattern(fr, "radial")[0] < 0.02


def test_a_radial_field_is_radial():
    fr = _frame(lambda x, y, _: np.column_stack([x, y]) * (1 - x**2 - y**2)[:, None])
    assert shear_pattern(fr, "radial")[0] == pytest.approx(1.0, abs=0.02)
    assert shear_pattern(fr, "saddle")[0] < 0.02


def test_noise_is_no_pattern():
    fr = _frame(lambda x, y, rng: rng.standard_normal((x.size, 2)))
    assert shear_pattern(fr, "saddle")[0] < 0.02
    assert shear_pattern(fr, "radial")[0] < 0.02


def test_bad_arguments():
    fr = _frame(lambda x, y, _: np.column_stack([x, -y]))
    with pytest.raises(ConfigError, match="pattern must be one of"):
        shear_pattern(fr, "swirl")
    fr.pressure[:] = 0.0
    fr.pressure[:5] = 1.0
    with pytest.raises(ConfigError, match="closed nodes"):
        shear_pattern(fr, "saddle")

"""Measures of bemcontact.validation.cases on synthetic data (the solves are in
tests/validation/test_hertz_mindlin.py)."""

import numpy as np
import pytest

from bemcontact.validation import cases
from bemcontact.validation.reference import contact as ref


def test_tangential_approach_removes_the_linear_bulk_compliance():
    """U = C_bulk Q + delta_CM(Q): the measure returns delta_CM exactly when
    the reference step is all-stick (delta = S Q / 8a there, to O(Q^2):
    at Q = 1e-6 mu P the initial-slope error is 1e-7 relative)."""
    s = cases.SphereOnBlock()
    S, P, mu = s.tangential_compliance_factor, 2600.0, 0.3
    a = ref.hertz(P, s.radius, s.contact_modulus).contact_radius
    Q = np.array([0.0, 1e-6 * mu * P, 0.5 * mu * P, 0.75 * mu * P])
    exact = np.array([ref.cattaneo_mindlin_displacement(q, mu, P, a, S) for q in Q])
    U = 3.7e-6 * Q + exact
    d = cases.tangential_approach(Q, U, a, S)
    np.testing.assert_allclose(d[2:], exact[2:], rtol=1e-6)
    # a platen drift at Q = 0 (the state after the normal load) is not approach
    np.testing.assert_allclose(cases.tangential_approach(Q, U + 2e-5, a, S)[2:], exact[2:],
                               rtol=1e-6)
    G, nu = s.shear_modulus, s.poisson_ratio
    assert S == pytest.approx(2 * (2 - nu) / G, rel=1e-15)

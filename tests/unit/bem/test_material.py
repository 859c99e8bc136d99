import math

import pytest

import bemcontact as bc


def test_derived_moduli():
    m = bc.LinearElastic(youngs_modulus=210e3, poisson_ratio=0.3)
    assert m.shear_modulus == pytest.approx(210e3 / 2.6, rel=1e-15)
    assert m.plane_strain_modulus == pytest.approx(210e3 / 0.91, rel=1e-15)


@pytest.mark.parametrize(
    "E, nu, match",
    [
        (0.0, 0.3, "youngs_modulus must be > 0, got 0.0"),
        (-1.0, 0.3, "youngs_modulus must be > 0"),
        (math.nan, 0.3, "youngs_modulus must be finite"),
        (1.0, 0.5, r"poisson_ratio must lie in \(-1, 0.5\), got 0.5 \(use e.g. 0.499"),
        (1.0, -1.0, "poisson_ratio must lie in"),
        (1.0, 0.7, "got 0.7"),
        (1.0, math.inf, "poisson_ratio must be finite"),
        ("steel", 0.3, "youngs_modulus must be a number, got 'steel'"),
    ],
)
def test_bad_material(E, nu, match):
    with pytest.raises(bc.MaterialError, match=match):
        bc.LinearElastic(youngs_modulus=E, poisson_ratio=nu)


def test_material_error_is_value_error_and_bemcontact_error():
    with pytest.raises(ValueError):
        bc.LinearElastic(-1.0, 0.3)
    with pytest.raises(bc.BemcontactError):
        bc.LinearElastic(-1.0, 0.3)

"""Materials of a finite-element body (bemcontact.fem.material, the
stiffness per volume region in bemcontact.fem.body).

* An isotropic material written as a 6 x 6 stiffness, in any axes, gives
  the isotropic body's stiffness matrix to round-off (1e-12 of its largest
  entry: the same sums in another order).
* Homogeneous states are exact in linear elements, so a block of an
  orthotropic material under uniaxial stress has the engineering constants'
  strains (-p/E_i along the load, +nu_ij p/E_i across) and a bar of two
  materials in series the sum of their shortenings, to round-off of a
  sparse solve (1e-10 relative).
* A stiffness that stores no energy for some strain, orthotropic constants
  that are not positive definite, a volume region without a material: a
  one-line MaterialError / ConfigError naming what is wrong.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg

from bemcontact import ConfigError, LinearElastic, MaterialError

pytest.importorskip("skfem")

from bemcontact.fem import AnisotropicElastic, FiniteElementBody, box_volume  # noqa: E402
from bemcontact.fem.fields import cell_stresses  # noqa: E402
from bemcontact.fem.material import elasticity_tensor  # noqa: E402

STEEL = LinearElastic(2.1e5, 0.3)
ORTHO = dict(youngs_moduli=(140e3, 10e3, 12e3), poisson_ratios=(0.3, 0.28, 0.45),
             shear_moduli=(5e3, 5.5e3, 3.5e3))


def voigt(material) -> np.ndarray:
    C = elasticity_tensor(material)
    pairs = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
    return np.array([[C[i, j, k, l_] for k, l_ in pairs] for i, j in pairs])


@pytest.mark.parametrize("axes", [((1, 0, 0), (0, 1, 0)), ((1, 1, 0), (-1, 1, 0.5))])
def test_isotropic_stiffness_as_a_6x6_gives_the_same_matrix(axes):
    volume = box_volume((0, 0, 0), (1, 2, 1), (2, 3, 2), "tet4", 2)
    K_iso, _ = FiniteElementBody(volume, STEEL).stiffness()
    aniso = AnisotropicElastic(voigt(STEEL), *axes)
    K_ani, _ = FiniteElementBody(volume, aniso).stiffness()
    assert abs(K_ani - K_iso).max() <= 1e-12 * abs(K_iso).max()


def uniaxial(body, p: float):
    """Displacements (n, 3) of ``body`` (a box on [0, 1]^3 or taller) with
    rollers on xmin, ymin, zmin and pressure p on zmax, by a direct sparse
    solve of its stiffness."""
    K, _ = body.stiffness()
    X = body.volume.node_points
    n = X.shape[0]
    fixed = np.zeros((n, 3), dtype=bool)
    for a in range(3):
        fixed[np.isclose(X[:, a], 0.0), a] = True
    # consistent nodal forces of p on zmax: the trace's mass times the traction
    from bemcontact.fem.trace import trace_mass

    d = body.trace
    top = d.region == body.region_names.index("zmax")
    t = np.zeros((d.n_points, 3))
    t[top, 2] = -p
    f = np.zeros((n, 3))
    np.add.at(f, body.volume_node, trace_mass(d) @ t)
    free = ~fixed.ravel()
    u = np.zeros(3 * n)
    u[free] = scipy.sparse.linalg.spsolve(K.tocsr()[free][:, free].tocsc(), f.ravel()[free])
    return u.reshape(n, 3), X


def test_orthotropic_block_under_uniaxial_stress_has_the_engineering_strains():
    p = 50.0
    # material axis 1 along z, axis 2 along x (axis 3 = 1 x 2 along y)
    mat = AnisotropicElastic.orthotropic(**ORTHO, axis1=(0, 0, 1), axis2=(1, 0, 0))
    body = FiniteElementBody(box_volume((0, 0, 0), (1, 1, 1), 2, "hex8", 1), mat)
    u, X = uniaxial(body, p)
    E1 = ORTHO["youngs_moduli"][0]
    nu12, nu13 = ORTHO["poisson_ratios"][:2]
    expect = np.column_stack([nu12 * p / E1 * X[:, 0], nu13 * p / E1 * X[:, 1],
                              -p / E1 * X[:, 2]])
    assert np.abs(u - expect).max() <= 1e-10 * p / E1
    s = cell_stresses(body, u)
    assert np.abs(s - [0, 0, -p, 0, 0, 0]).max() <= 1e-9 * p


def test_two_materials_in_series_shorten_by_the_sum():
    p, E1, E2 = 20.0, 1.0e4, 4.0e4
    coords = (None, None, np.array([0.0, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0]))
    volume = box_volume((0, 0, 0), (1, 1, 2), (2, 2, 6), "hex8", 2, coordinates=coords,
                        volumes={"coating": lambda c: c[:, 2] > 1.0})
    assert volume.volume_names == ("coating", "body")
    body = FiniteElementBody(volume, {"coating": LinearElastic(E2, 0.0),
                                      "body": LinearElastic(E1, 0.0)})
    u, X = uniaxial(body, p)
    top = np.isclose(X[:, 2], 2.0)
    assert np.abs(u[top, 2] + p * (1.0 / E1 + 1.0 / E2)).max() <= 1e-10 * p / E1
    # the stress is -p in both materials; the strain jumps at z = 1
    assert np.abs(cell_stresses(body, u) - [0, 0, -p, 0, 0, 0]).max() <= 1e-9 * p
    # a Poisson-free material keeps its width
    assert np.abs(u[:, :2]).max() <= 1e-12


def test_rotating_the_material_rotates_the_response():
    p = 50.0
    base = FiniteElementBody(box_volume((0, 0, 0), (1, 1, 1), 2, "tet4", 1),
                             AnisotropicElastic.orthotropic(**ORTHO))
    turned = FiniteElementBody(box_volume((0, 0, 0), (1, 1, 1), 2, "tet4", 1),
                               AnisotropicElastic.orthotropic(**ORTHO, axis1=(0, 1, 0),
                                                              axis2=(-1, 0, 0)))
    u0, X = uniaxial(base, p)
    u1, _ = uniaxial(turned, p)
    # the lateral strains swap between x and y; the axial one is E3's
    assert np.isclose(u0[np.argmax(X[:, 0]), 0] / X[:, 0].max(),
                      ORTHO["poisson_ratios"][1] * p / ORTHO["youngs_moduli"][0], rtol=1e-9)
    assert np.isclose(u1[np.argmax(X[:, 1]), 1] / X[:, 1].max(),
                      ORTHO["poisson_ratios"][1] * p / ORTHO["youngs_moduli"][0], rtol=1e-9)
    assert np.isclose(u0[:, 2].min(), u1[:, 2].min(), rtol=1e-10)


def test_a_stiffness_that_is_not_positive_definite_is_refused():
    C = voigt(STEEL)
    C[3, 3] = -1.0
    with pytest.raises(MaterialError, match="not positive definite"):
        AnisotropicElastic(C)
    with pytest.raises(MaterialError, match="not positive definite"):
        AnisotropicElastic.orthotropic((1e3, 1e4, 1e4), (0.9, 0.3, 0.3), (1e3, 1e3, 1e3))
    C = voigt(STEEL)
    C[0, 1] += 1.0
    with pytest.raises(MaterialError, match="symmetric"):
        AnisotropicElastic(C)
    with pytest.raises(MaterialError, match="parallel"):
        AnisotropicElastic(voigt(STEEL), (1, 0, 0), (2, 0, 0))


def test_a_volume_region_without_material_is_refused():
    volume = box_volume((0, 0, 0), (1, 1, 1), 2, "hex8", 1,
                        volumes={"coating": lambda c: c[:, 2] > 0.5})
    with pytest.raises(ConfigError, match="volume region 'body' has no material"):
        FiniteElementBody(volume, {"coating": STEEL}, name="block")
    with pytest.raises(ConfigError, match="no volume region 'coat'"):
        FiniteElementBody(volume, {"coat": STEEL, "coating": STEEL, "body": STEEL})

"""ElasticBody and boundary conditions: API behaviour and bad input."""

import numpy as np
import pytest

import bemcontact as bc

MAT = bc.LinearElastic(youngs_modulus=1.0e4, poisson_ratio=0.3)


def test_unknown_region_name_is_named():
    with pytest.raises(bc.ConfigError, match=r"unknown region 'top'; the mesh has regions \['xmin'"):
        bc.ElasticBody(bc.box(divisions=1), MAT, {"top": bc.Fixed()})


def test_same_component_prescribed_twice():
    with pytest.raises(
        bc.ConfigError,
        match=r"region 'zmax': component z is prescribed twice \(Displacement and Traction\)",
    ):
        bc.ElasticBody(
            bc.box(divisions=1),
            MAT,
            {"zmax": [bc.Displacement((None, None, -0.1)), bc.Traction((0.0, 0.0, 1.0))]},
        )
    with pytest.raises(bc.ConfigError, match="component x is prescribed twice"):
        bc.ElasticBody(bc.box(divisions=1), MAT, {"zmax": [bc.Fixed(), bc.Pressure(1.0)]})


def test_bad_values():
    with pytest.raises(bc.ConfigError, match="Displacement: value must have 3 components"):
        bc.Displacement((0.0, 0.0))
    with pytest.raises(bc.ConfigError, match="Traction: component nan is not finite"):
        bc.Traction((float("nan"), 0.0, 0.0))
    with pytest.raises(bc.ConfigError, match="Pressure: pressure must be a finite number"):
        bc.Pressure(float("inf"))
    with pytest.raises(bc.ConfigError, match="component 'a' is not a number"):
        bc.Displacement(("a", 0, 0))


def test_wrong_types_at_the_boundary():
    with pytest.raises(bc.ConfigError, match="material must be a LinearElastic, got dict"):
        bc.ElasticBody(bc.box(divisions=1), {"E": 1}, {})
    with pytest.raises(bc.ConfigError, match="is not a Displacement, Traction, Pressure or Force"):
        bc.ElasticBody(bc.box(divisions=1), MAT, {"zmin": 0.0})


def test_inverted_mesh_rejected_by_body():
    with pytest.raises(bc.MeshError, match="inverted orientation"):
        bc.ElasticBody(bc.box(divisions=1).reversed(), MAT, {"zmin": bc.Fixed()})


def test_callable_with_wrong_shape():
    body = bc.ElasticBody(bc.box(divisions=1), MAT, {"zmin": bc.Displacement(lambda X: X[:, 0])})
    with pytest.raises(bc.ConfigError, match=r"region 'zmin': the Displacement callable returned shape"):
        body.solve()


def test_unsupported_body_is_reported_not_solved():
    # only z held anywhere: free to translate in x and y
    body = bc.ElasticBody(
        bc.box(divisions=2), MAT, {"zmin": bc.Displacement((None, None, 0.0)), "zmax": bc.Pressure(1.0)}
    )
    with pytest.raises(bc.ConfigError, match="singular .* do not fix the body against rigid motion"):
        body.solve()


def test_reactions_balance_and_pressure_sign():
    """Clamped bottom, pressure p on top: the bottom reaction is +p A in z
    (pushes back up), the top load is -p A, and all reactions sum to zero."""
    m = bc.box((0, 0, 0), (1, 2, 1), 3)
    sol = bc.ElasticBody(m, MAT, {"zmin": bc.Fixed(), "zmax": bc.Pressure(5.0)}).solve()
    top = sol.reaction("zmax")
    np.testing.assert_allclose(top, [0, 0, -10.0], atol=1e-12)
    # collocation does not enforce global equilibrium exactly, and the clamped
    # edges carry singular tractions: balance holds to discretization error
    # (measured 1e-3 relative on this 3 x 6 x 3 mesh)
    total = sum(sol.reactions().values())
    assert np.abs(total).max() < 2e-3 * 10.0
    assert sol.reaction("zmin")[2] == pytest.approx(10.0, rel=2e-3)
    assert sol.displacement[sol.nodes_of("zmax"), 2].mean() < 0


def test_force_control_uniform_compression():
    """A platen pushed with force F on a block on rollers: uniform stress, so
    the platen's translation is F L / (E A) to the uniform-stress floor of
    the BEM (1e-8 relative, see tests/validation/test_exact_fields.py) and the
    rollers carry -F."""
    F, L = -100.0, 2.0
    rollers = {
        "zmin": bc.Displacement((None, None, 0.0)),
        "xmin": bc.Displacement((0.0, None, None)),
        "ymin": bc.Displacement((None, 0.0, None)),
    }
    body = bc.ElasticBody(bc.box((0, 0, 0), (L, L, L), 3), MAT, {**rollers, "zmax": bc.Force((None, None, F))})
    sol = body.solve()
    i = sol.nodes_of("zmax")
    expected = F * L / (MAT.youngs_modulus * L * L)
    assert np.allclose(sol.displacement[i, 2], expected, rtol=1e-8)
    assert sol.reaction("zmax")[2] == pytest.approx(F, rel=1e-12)
    assert sol.reaction("zmin")[2] == pytest.approx(-F, rel=1e-8)


@pytest.mark.parametrize("E", [1e-50, 1e50])
def test_solution_scales_with_the_modulus(E):
    """Clamped bottom, displacement on top: the displacements do not depend
    on E and the tractions are proportional to it, from E = 1e-50 to 1e50
    (the mixed matrix's -G columns scale as 1/E: unscaled, the singularity
    check read E = 1e-50 as a body free to move).  To 1e-12: the columns are
    scaled by powers of two, so the factorization is the same up to the
    rounding of E itself."""
    top = bc.Displacement((0.01, 0.0, -0.02))
    ref = bc.ElasticBody(bc.box(divisions=2), bc.LinearElastic(1.0, 0.3),
                         {"zmin": bc.Fixed(), "zmax": top}).solve()
    sol = bc.ElasticBody(bc.box(divisions=2), bc.LinearElastic(E, 0.3),
                         {"zmin": bc.Fixed(), "zmax": top}).solve()
    np.testing.assert_allclose(sol.displacement, ref.displacement, rtol=0,
                               atol=1e-12 * np.abs(ref.displacement).max())
    np.testing.assert_allclose(sol.traction / E, ref.traction, rtol=0,
                               atol=1e-12 * np.abs(ref.traction).max())

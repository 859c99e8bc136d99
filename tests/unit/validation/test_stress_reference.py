"""bemcontact.validation.reference.stress: the Hertz stresses on the axis and
the surface (Johnson eqs. 3.44-3.45) and Hamilton's explicit field of a
sliding sphere.

Hamilton's formulas are checked against an independent computation, the Love
rectangle sums of bemcontact.halfspace.HalfSpaceStress with the Hertz pressure
and the shear mu p sampled at cell centres on grids of a/h = 32, 64, 128 (the
error falls like h^1.7-1.85, the fitted rate is asserted, and so is the finest
error); against themselves in 60-digit arithmetic (round-off, the near-axis
interpolation, the exact reduction to Johnson's axis formulas); against the
surface tractions, equilibrium, Johnson's surface formulas and the
trailing-edge tension; and the classic facts (max tau1 = 0.31 p0 at 0.48 a;
the von Mises maximum below the surface for mu = 0.25, on it for mu = 0.5)."""

from __future__ import annotations

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest

from bemcontact import ConfigError
from bemcontact.halfspace import Grid, HalfSpaceStress, von_mises
from bemcontact.validation.reference import (
    hamilton_sliding_sphere_stresses,
    hertz_axis_stresses,
    hertz_surface_stresses,
)
from bemcontact.validation.reference.stress import _hamilton_unit

NU = 0.3
A, P0 = 1.3, 2.0  # not 1, so that a missing scale shows


# ----------------------------------------------------------------- 60-digit evaluation

_DIGITS = 60


def _atan(x: Decimal) -> Decimal:
    """atan x for x >= 0 (halving the argument, then the Taylor series)."""
    k = 0
    while x > Decimal("0.05"):
        x = x / (1 + (1 + x * x).sqrt())
        k += 1
    s, term, n, x2 = Decimal(0), x, 1, x * x
    while abs(term) > Decimal(10) ** (2 - _DIGITS):
        s += term / n
        term *= -x2
        n += 2
    return s * 2**k


def _acot(m: Decimal) -> Decimal:
    """arccot m = atan(1/m) for m >= 0."""
    return 2 * _atan(Decimal(1)) - _atan(m) if m < 1 else _atan(1 / m)


def exact_unit_field(x: float, y: float, z: float, nu: float) -> np.ndarray:
    """Hamilton's off-axis formulas in 60-digit arithmetic (units of a; rows:
    per p0, per q0), rounded to float64 at the end: (2, 6)."""
    with localcontext() as ctx:
        ctx.prec = _DIGITS
        p, q = _hamilton_unit(Decimal(x), Decimal(y), Decimal(z), Decimal(nu),
                              lambda v: v.sqrt(), _acot)
        return np.array([[float(v) for v in p], [float(v) for v in q]])


def unit_fields(points_in_a: np.ndarray, nu: float = NU) -> np.ndarray:
    """The module's float64 field per p0 and per q0 at points in units of a: (n, 2, 6)."""
    p = hamilton_sliding_sphere_stresses(points_in_a, 1.0, 1.0, 0.0, nu)
    pq = hamilton_sliding_sphere_stresses(points_in_a, 1.0, 1.0, 1.0, nu)
    return np.stack([p, pq - p], 1)


# ----------------------------------------------------------------- frictionless Hertz


def test_axis_maximum_shear_is_johnsons_031_p0_at_048_a():
    """Johnson §3.4: for nu = 0.3 the principal shear tau1 on the axis peaks at
    0.31 p0 at z = 0.48 a (his two digits); the maximiser is a stationary point
    (central difference of tau1 < 1e-9 p0/a) and scales with a and p0."""
    h = hertz_axis_stresses([0.0], A, P0, NU)
    assert round(h.max_shear / P0, 2) == 0.31, h.max_shear / P0
    assert round(h.max_shear_depth / A, 2) == 0.48, h.max_shear_depth / A
    zm, d = h.max_shear_depth, 1e-5 * A
    s = hertz_axis_stresses([zm - d, zm, zm + d], A, P0, NU)
    tau = 0.5 * np.abs(s.sigma_z - s.sigma_r)
    assert abs(tau[2] - tau[0]) / (2 * d) < 1e-9 * P0 / A
    assert tau[1] >= tau[[0, 2]].max() and abs(tau[1] - h.max_shear) < 1e-14 * P0
    unit = hertz_axis_stresses([0.0], 1.0, 1.0, NU)
    assert math.isclose(h.max_shear, P0 * unit.max_shear, rel_tol=1e-12)
    assert math.isclose(h.max_shear_depth, A * unit.max_shear_depth, rel_tol=1e-9)


def test_axis_stresses_at_the_surface_and_far_below():
    """z = 0: s_z = -p0, s_r = -(1 + 2 nu) p0 / 2 (= the surface formula at
    r = 0).  Far below, the field of the point load P = 2 pi a^2 p0 / 3
    (Boussinesq on the axis: s_z = -3P/(2 pi z^2), s_r = (1 - 2 nu) P/(4 pi z^2))
    to O(a^2/z^2) (3.6 a^2/z^2 relative for s_r); the large-depth series and
    the direct form agree where they meet (z = 10 a) to 1e-12."""
    s = hertz_axis_stresses([0.0], A, P0, NU)
    surf = hertz_surface_stresses([0.0], A, P0, NU)
    assert s.sigma_z[0] == pytest.approx(-P0, rel=1e-15)
    assert s.sigma_r[0] == pytest.approx(-(1 + 2 * NU) / 2 * P0, rel=1e-15)
    assert surf.sigma_r[0] == pytest.approx(s.sigma_r[0], rel=1e-14)
    assert surf.sigma_theta[0] == pytest.approx(s.sigma_r[0], rel=1e-14)
    P = 2 * math.pi * A**2 * P0 / 3
    z = np.array([1e3, 1e4]) * A
    far = hertz_axis_stresses(z, A, P0, NU)
    tol = 5 * (A / z) ** 2
    assert np.all(np.abs(far.sigma_z * 2 * math.pi * z**2 / (-3 * P) - 1) < tol), far.sigma_z
    assert np.all(np.abs(far.sigma_r * 4 * math.pi * z**2 / ((1 - 2 * NU) * P) - 1) < tol)
    meet = hertz_axis_stresses(A * np.array([10.0 * (1 - 1e-15), 10.0 * (1 + 1e-15)]), A, P0, NU)
    assert abs(meet.sigma_r[1] / meet.sigma_r[0] - 1) < 1e-12, meet.sigma_r


def test_surface_stresses_at_the_edge_and_against_hamilton():
    """Johnson eq. 3.44: at r = a and just outside s_r = -s_theta =
    (1 - 2 nu) p0 / 3, the largest tension of the surface, the limit from
    inside (where the stresses vary like (a - r)^(1/2)); s_z = -p inside, 0 outside.
    Hamilton's formulas at z = 0, mu = 0 on y = 0 (s_xx = s_r, s_yy = s_theta)
    agree to 1e-12 p0 inside and outside the contact."""
    t = (1 - 2 * NU) / 3 * P0
    s = hertz_surface_stresses(A * np.array([1.0, 1 + 1e-12, 1 - 1e-12]), A, P0, NU)
    np.testing.assert_allclose(s.sigma_r[:2], t, rtol=1e-11)
    np.testing.assert_allclose(s.sigma_theta[:2], -t, rtol=1e-11)
    # inside, the square root: s_r - t = -(1 + ...) p0 (2 * 1e-12)^(1/2)
    assert abs(s.sigma_r[2] - t) < 2 * math.sqrt(2e-12) * P0
    assert abs(s.sigma_theta[2] + t) < 2 * math.sqrt(2e-12) * P0
    r = A * np.linspace(0.0, 3.0, 301)
    s = hertz_surface_stresses(r, A, P0, NU)
    assert np.argmax(s.sigma_r) == 100 and s.sigma_r.max() == pytest.approx(t, rel=1e-14)
    np.testing.assert_allclose(s.sigma_z, -P0 * np.sqrt(np.clip(1 - (r / A) ** 2, 0, None)),
                               atol=1e-15 * P0)
    pts = np.stack([r, 0 * r, 0 * r], 1)
    h = hamilton_sliding_sphere_stresses(pts, A, P0, 0.0, NU)
    assert np.abs(h[:, 0] - s.sigma_r).max() < 1e-12 * P0
    assert np.abs(h[:, 1] - s.sigma_theta).max() < 1e-12 * P0
    assert np.abs(h[:, 2] - s.sigma_z).max() < 1e-12 * P0


# ----------------------------------------------------------------- Hamilton against Love


def _love_fields(n_cells: int, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """HalfSpaceStress at ``points`` for the Hertz pressure and for the shear p
    along +x (mu = 1), sampled at the cell centres of n_cells^2 cells covering
    [-a, a]^2: two (n, 6) arrays."""
    h = 2 * A / n_cells
    grid = Grid.centred(n_cells, n_cells, h, h)
    c = grid.centres
    p = P0 * np.sqrt(np.clip(1 - (c[:, 0] ** 2 + c[:, 1] ** 2) / A**2, 0.0, None))
    stress = HalfSpaceStress(grid, NU)
    normal, shear = np.zeros((grid.size, 3)), np.zeros((grid.size, 3))
    normal[:, 2], shear[:, 0] = p, p
    return stress.at(points, normal), stress.at(points, shear)


@pytest.mark.validation
def test_hamilton_against_love_rectangle_sums():
    """The independent check: HalfSpaceStress (Love's rectangle solutions) with
    the Hertz pressure and the shear p along +x sampled at the centres of
    a/h = 32, 64, 128 cells, at 35 points of the plane y = 0 (depths 0.1a-2a,
    x from -1.5a to 1.5a, the axis included) and 6 off it, every component.
    The sampling error is O(h^2) for a smooth traction; the square-root edge
    of the Hertz profile slows it near the edge.  Measured max errors over
    all points: pressure 4.0e-3, 1.3e-3, 3.7e-4 p0 (at the point below the
    edge, x = -a, z = 0.1a; fitted rate 1.72), shear 1.1e-3, 3.1e-4, 8.5e-5 p0
    (rate 1.85); at the points >= 0.3a from the edge circle <= 1.6e-5 p0 at
    a/h = 128; the Richardson value (4 f_h/2 - f_h)/3 of the two finest grids
    within 6.6e-5 p0 everywhere.  Asserted: rate > 1.6 and finest < 4.5e-4 p0
    everywhere, < 2.5e-5 p0 away from the edge, Richardson < 1e-4 p0."""
    xs = A * np.array([-1.5, -1.0, -0.5, 0.0, 0.3, 0.9, 1.5])
    zs = A * np.array([0.1, 0.25, 0.5, 1.0, 2.0])
    plane = np.array([[x, 0.0, z] for z in zs for x in xs])
    off = A * np.array([[0.4, 0.3, 0.4], [-0.6, 0.5, 0.2], [0.2, -0.9, 0.3], [1.1, 0.7, 0.6],
                        [0.05, 0.02, 0.15], [-0.3, -1.2, 1.5]])
    points = np.vstack([plane, off])
    from_edge = np.hypot(np.hypot(points[:, 0], points[:, 1]) - A, points[:, 2])
    away = from_edge >= 0.3 * A
    cells = [64, 128, 256]
    loves = [_love_fields(n, points) for n in cells]
    h = np.array([2 * A / n for n in cells])
    ham_n = hamilton_sliding_sphere_stresses(points, A, P0, 0.0, NU)
    ham_t = hamilton_sliding_sphere_stresses(points, A, P0, 1.0, NU) - ham_n
    for which, name, ham in ((0, "pressure", ham_n), (1, "shear", ham_t)):
        err = np.array([np.abs(love[which] - ham).max(axis=1) / P0 for love in loves])
        worst = err.max(axis=1)
        rate = np.polyfit(np.log(h), np.log(worst), 1)[0]
        assert rate > 1.6, f"{name}: errors {worst} p0 at a/h = {A / h}, rate {rate:.2f}"
        assert worst[-1] < 4.5e-4, f"{name}: finest error {worst[-1]:.2e} p0"
        assert err[-1, away].max() < 2.5e-5, f"{name}: away from the edge {err[-1, away].max():.2e}"
        rich = (4 * loves[2][which] - loves[1][which]) / 3
        assert np.abs(rich - ham).max() < 1e-4 * P0, np.abs(rich - ham).max() / P0


# ----------------------------------------------------------------- exactness and round-off


def test_hamilton_reduces_to_the_axis_formulas():
    """mu = 0 on the axis: the module equals hertz_axis_stresses to 1e-10
    (relative to p0), and so does the near-axis interpolation at r = 1e-12 a.
    The off-axis formulas themselves, in 60-digit arithmetic at r = 1e-12 a,
    reduce to Johnson's axis stresses (pressure) and to s_xz = -1 +
    3/2 z atan(1/z) - z^2/(2(1 + z^2)) (shear, the only non-zero component)
    to 1e-10: the limits are exact, not fitted."""
    z = np.array([0.0, 0.05, 0.3, 0.48, 1.0, 2.0, 5.0])
    ax = hertz_axis_stresses(z * A, A, P0, NU)
    for r in (0.0, 1e-12):
        pts = np.stack([r * A + 0 * z, 0 * z, z * A], 1)
        h = hamilton_sliding_sphere_stresses(pts, A, P0, 0.0, NU)
        assert np.abs(h[:, 2] - ax.sigma_z).max() < 1e-10 * P0
        assert np.abs(h[:, 0] - ax.sigma_r).max() < 1e-10 * P0
        assert np.abs(h[:, 1] - ax.sigma_r).max() < 1e-10 * P0
        assert np.abs(h[:, 3:]).max() < 1e-10 * P0
    unit = hertz_axis_stresses(z[1:], 1.0, 1.0, NU)
    for k, zk in enumerate(z[1:]):
        f = exact_unit_field(1e-12, 0.0, float(zk), NU)
        expected_p = [unit.sigma_r[k], unit.sigma_r[k], unit.sigma_z[k], 0, 0, 0]
        shear_xz = -1 + 1.5 * zk * math.atan(1 / zk) - zk**2 / (2 * (1 + zk**2))
        np.testing.assert_allclose(f[0], expected_p, rtol=0, atol=1e-10)
        np.testing.assert_allclose(f[1], [0, 0, 0, 0, 0, shear_xz], rtol=0, atol=1e-10)


def test_hamilton_round_off_against_60_digits():
    """The float64 field (the near-axis interpolation included) against the
    same formulas in 60-digit arithmetic at points from r = 1e-6 a to 4 a and
    depths 0.01 a to 4 a: absolute error < 5e-12 per unit p0 and per unit q0
    (measured <= 2e-12)."""
    rng = np.random.default_rng(7)
    pts = []
    for r in (1e-6, 1e-3, 0.02, 0.1, 0.24, 0.3, 0.9, 1.05, 2.5, 4.0):
        for z in (0.01, 0.4, 1.5, 4.0):
            th = rng.uniform(0, 2 * np.pi)
            pts.append((r * math.cos(th), r * math.sin(th), z))
    pts = np.array(pts)
    ours = unit_fields(pts)
    exact = np.array([exact_unit_field(*p, NU) for p in pts])
    err = np.abs(ours - exact).max(axis=(1, 2))
    assert err.max() < 5e-12, (err.max(), pts[np.argmax(err)])


# ----------------------------------------------------------------- boundary, equilibrium


def test_surface_tractions_and_trailing_edge_tension():
    """At z = 0: s_zz = -p, s_xz = -mu p, s_yz = 0 inside the contact and all
    three 0 outside (the tractions on the body).  On the contact edge the
    surface s_xx is p0 [(1 - 2 nu)/3 +- (4 + nu) pi mu / 8] (tension at the
    trailing edge x = -a, Hamilton 1983), to 1e-12 p0, and it is the limit
    from inside the contact (1e-6 p0 at 1e-12 a inside: the field is
    continuous)."""
    mu = 0.4
    rng = np.random.default_rng(3)
    r, th = A * rng.uniform(0, 2, 400), rng.uniform(0, 2 * np.pi, 400)
    pts = np.stack([r * np.cos(th), r * np.sin(th), 0 * r], 1)
    s = hamilton_sliding_sphere_stresses(pts, A, P0, mu, NU)
    p = P0 * np.sqrt(np.clip(1 - (r / A) ** 2, 0, None))
    assert np.abs(s[:, 2] + p).max() < 1e-12 * P0
    assert np.abs(s[:, 5] + mu * p).max() < 1e-12 * P0
    assert np.abs(s[:, 4]).max() < 1e-12 * P0
    edge = hamilton_sliding_sphere_stresses(
        A * np.array([[-1.0, 0, 0], [1.0, 0, 0], [-1 + 1e-12, 0, 0]]), A, P0, mu, NU)
    jump = (4 + NU) * math.pi * mu / 8
    assert edge[0, 0] == pytest.approx(P0 * ((1 - 2 * NU) / 3 + jump), abs=1e-12 * P0)
    assert edge[1, 0] == pytest.approx(P0 * ((1 - 2 * NU) / 3 - jump), abs=1e-12 * P0)
    assert abs(edge[2, 0] - edge[0, 0]) < 1e-5 * P0


def test_hamilton_field_is_in_equilibrium():
    """div s = 0 inside the body, by central differences (step 1e-4 a: the
    truncation ~1e-8 and the round-off ~1e-12/1e-4 are both below the bound
    1e-6 p0/a), at points on and off y = 0 and near the axis."""
    mu, d = 0.3, 1e-4 * A
    pts = A * np.array([[0.3, 0.0, 0.2], [-0.8, 0.4, 0.5], [1.2, -0.3, 0.1], [0.0, 0.0, 0.7],
                        [0.01, 0.02, 0.3], [2.0, 1.0, 1.5]])
    idx = {"xx": 0, "yy": 1, "zz": 2, "xy": 3, "yz": 4, "xz": 5}
    comp = [["xx", "xy", "xz"], ["xy", "yy", "yz"], ["xz", "yz", "zz"]]
    div = np.zeros((len(pts), 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = d
        ds = (hamilton_sliding_sphere_stresses(pts + e, A, P0, mu, NU)
              - hamilton_sliding_sphere_stresses(pts - e, A, P0, mu, NU)) / (2 * d)
        for i in range(3):
            div[:, i] += ds[:, idx[comp[i][j]]]
    assert np.abs(div).max() < 1e-6 * P0 / A, np.abs(div).max()


# ----------------------------------------------------------------- von Mises maximum


def test_von_mises_maximum_moves_to_the_surface_with_friction():
    """On the plane y = 0 (x in [-1.5a, 1.5a], z in [0, a], step 0.01 a),
    nu = 0.3: mu = 0, the maximum 0.62 p0 lies on the axis at z = 0.48 a;
    mu = 0.25, it lies below the surface (z = 0.445 a, 0.648 p0; the surface's
    best, at the trailing edge, is 0.579 p0); mu = 0.5, it lies on the
    surface at the trailing edge x = -a (0.957 p0; the subsurface peak has
    merged into the surface one, the switch is near mu = 0.3)."""
    x = A * np.linspace(-1.5, 1.5, 301)
    z = A * np.linspace(0.0, 1.0, 101)
    X, Z = np.meshgrid(x, z, indexing="ij")
    pts = np.stack([X.ravel(), 0 * X.ravel(), Z.ravel()], 1)
    at_surface = pts[:, 2] == 0.0

    def peak(mu):
        vm = von_mises(hamilton_sliding_sphere_stresses(pts, A, P0, mu, NU)) / P0
        k = int(np.argmax(vm))
        return vm[k], pts[k] / A, vm[at_surface].max()

    v, where, _ = peak(0.0)
    assert round(v, 2) == 0.62 and abs(where[0]) < 1e-12 and where[2] == pytest.approx(0.48)
    v, where, surface = peak(0.25)
    assert where[2] > 0.3 and v > surface + 0.05, (v, where, surface)
    v, where, surface = peak(0.5)
    assert where[2] == 0.0 and where[0] == pytest.approx(-1.0), (v, where)
    assert v == pytest.approx(0.957, abs=1e-3)


# ----------------------------------------------------------------- bad input


@pytest.mark.parametrize("kwargs, match", [
    ({"contact_radius": 0.0}, "contact_radius"),
    ({"peak_pressure": -1.0}, "peak_pressure"),
    ({"friction_coefficient": -0.1}, "friction_coefficient"),
    ({"friction_coefficient": math.nan}, "friction_coefficient"),
    ({"poisson_ratio": 0.5}, "poisson_ratio"),
    ({"points": np.zeros((2, 2))}, "shape"),
    ({"points": np.array([[0.0, 0.0, -1e-9]])}, "depth"),
    ({"points": np.array([[np.inf, 0.0, 1.0]])}, "finite"),
])
def test_hamilton_rejects_bad_input(kwargs, match):
    args = {"points": np.array([[0.0, 0.0, 1.0]]), "contact_radius": 1.0, "peak_pressure": 1.0,
            "friction_coefficient": 0.2, "poisson_ratio": NU}
    args.update(kwargs)
    with pytest.raises(ConfigError, match=match):
        hamilton_sliding_sphere_stresses(**args)


def test_hertz_formulas_reject_bad_input():
    with pytest.raises(ConfigError, match="z must be"):
        hertz_axis_stresses([-0.1], 1.0, 1.0, NU)
    with pytest.raises(ConfigError, match="r must be"):
        hertz_surface_stresses([np.nan], 1.0, 1.0, NU)
    with pytest.raises(ConfigError, match="poisson_ratio"):
        hertz_axis_stresses([0.1], 1.0, 1.0, -1.0)
    with pytest.raises(ConfigError, match="contact_radius"):
        hertz_surface_stresses([0.1], -1.0, 1.0, NU)

"""Subsurface stresses of the half-space (halfspace/stress.py): far cells
against the Boussinesq and Cerruti point loads, the Hertz field on the axis
against Johnson's closed forms, the FFT layers against the direct sum,
equilibrium and the surface traction, signs, and the checks of bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from bemcontact.errors import ConfigError
from bemcontact.halfspace import (Grid, HalfSpaceStress, rectangle_stresses, stress_blocks,
                                  tresca)

NU = 0.3


def point_load_stresses(x, y, z, nu: float) -> np.ndarray:
    """Stresses (rows σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz; tension positive)
    at (x, y, z), z > 0, of a unit point force at the origin of the surface
    of the half-space z > 0 (columns: force along x, y, z; z into the body);
    shape (6, 3, ...) for (x, y, z) broadcast, off the axis x = y = 0.
    Cerruti (force along x): Johnson, Contact Mechanics (1985), ch. 3, in
    Cartesian form; along y by the mirror x <-> y.  Boussinesq (force along
    z, pressing): Johnson ch. 3, in cylindrical form (σ_r, σ_θ, σ_z, τ_rz),
    rotated to x, y; σ_z = −3 P z³ / (2π ρ⁵)."""
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    rho = np.sqrt(x * x + y * y + z * z)
    w = (1.0 - 2.0 * nu) / (rho + z) ** 2

    def cerruti(x, y):  # force along +x
        c = -x / (2.0 * np.pi * rho**3)
        return [c * (3 * x * x / rho**2 - w * (rho**2 - y * y - 2 * rho * y * y / (rho + z))),
                c * (3 * y * y / rho**2 - w * (3 * rho**2 - x * x - 2 * rho * x * x / (rho + z))),
                c * 3 * z * z / rho**2,
                -y / (2.0 * np.pi * rho**3)
                * (3 * x * x / rho**2 + w * (rho**2 - x * x - 2 * rho * x * x / (rho + z))),
                c * 3 * y * z / rho**2,
                c * 3 * x * z / rho**2]

    along_x = cerruti(x, y)
    xx, yy, zz, xy, xz, yz = cerruti(y, x)  # the force along y: swap the axes
    along_y = [yy, xx, zz, xy, yz, xz]
    r2 = x * x + y * y
    r = np.sqrt(r2)
    a = (1.0 - z / rho) / r2
    s_r = ((1.0 - 2.0 * nu) * a - 3.0 * z * r2 / rho**5) / (2.0 * np.pi)
    s_t = -(1.0 - 2.0 * nu) * (a - z / rho**3) / (2.0 * np.pi)
    s_z = -3.0 * z**3 / (2.0 * np.pi * rho**5)
    t_rz = -3.0 * r * z * z / (2.0 * np.pi * rho**5)
    c, s = x / r, y / r
    along_z = [s_r * c * c + s_t * s * s, s_r * s * s + s_t * c * c, s_z, (s_r - s_t) * c * s,
               t_rz * s, t_rz * c]
    return np.array([along_x, along_y, along_z]).swapaxes(0, 1)


def test_cell_integral_equals_a_fine_quadrature():
    """The closed form is the exact integral of the point-load stresses over
    the cell: against a Gauss–Legendre product rule (16 × 16 sub-rectangles of
    8 × 8 points) at points below the cell, below a corner and beside it, at
    depths down to a tenth of the cell's shorter side.  The rule's error is
    set by the sub-rectangle size against the depth (observed ≤ 3e-11 of the
    largest entry; an adaptive quadrature agrees to 4e-15); asserted 1e-8."""
    a, b = 0.5, 0.3
    g, w = np.polynomial.legendre.leggauss(8)
    edges_x, edges_y = np.linspace(-a, a, 17), np.linspace(-b, b, 17)
    xs = (0.5 * (edges_x[1:, None] + edges_x[:-1, None]) + 0.5 * np.diff(edges_x)[:, None] * g)
    ys = (0.5 * (edges_y[1:, None] + edges_y[:-1, None]) + 0.5 * np.diff(edges_y)[:, None] * g)
    wx = (0.5 * np.diff(edges_x)[:, None] * w).ravel()
    wy = (0.5 * np.diff(edges_y)[:, None] * w).ravel()
    for x, y, z in [(0.1, 0.05, 0.2), (0.5, 0.3, 0.1), (0.7, -0.2, 0.3), (0.0, 0.0, 0.06)]:
        k = point_load_stresses(x - xs.ravel()[:, None], y - ys.ravel()[None, :], z, NU)
        quad = np.einsum("clij,i,j->cl", k, wx, wy)
        closed = rectangle_stresses(x, y, z, a, b, NU)
        assert np.abs(closed - quad).max() < 1e-8 * np.abs(quad).max(), (x, y, z)


@pytest.mark.parametrize("offset", [(20, 0, 5), (0, 20, 5), (20, 13, 8), (-14, -20, 3),
                                    (6, 4, 30)])
def test_far_cells_approach_the_point_loads(offset):
    """A cell far from the point acts as a point force of the same total (dx
    dy times the traction), to second order in h/ρ: the rectangle integral is
    the midpoint rule plus (dx² ∂xx + dy² ∂yy)/24 of the kernel, and the
    kernels are homogeneous of degree −2, so the error is a bounded multiple
    of (h/ρ)².  Observed 0.08–0.30 (h/ρ)² block-wise and ≤ 0.64 (h/ρ)² for
    each entry above a tenth of the block's largest; asserted 0.5 and 1.0.
    Doubling the distance divides the error by 4 (observed 3.999–4.001; the
    next term is O((h/ρ)⁴))."""
    dx, dy = 0.3, 0.2  # unequal, so a swap of x and y shows
    h = max(dx, dy)
    errors = []
    for scale in (1, 2):
        x, y, z = offset[0] * dx * scale, offset[1] * dy * scale, offset[2] * 0.25 * scale
        block = rectangle_stresses(x, y, z, dx / 2, dy / 2, NU)
        point = point_load_stresses(x, y, z, NU) * dx * dy
        rho = math.sqrt(x * x + y * y + z * z)
        size = np.abs(point).max()
        err = np.abs(block - point).max() / size
        assert err < 0.5 * (h / rho) ** 2, (offset, scale, err / (h / rho) ** 2)
        big = np.abs(point) > 0.1 * size
        per_entry = np.abs(block - point)[big] / np.abs(point)[big]
        assert per_entry.max() < 1.0 * (h / rho) ** 2, (offset, scale, per_entry)
        errors.append(err)
    assert 3.9 < errors[0] / errors[1] < 4.1, errors


def test_signs():
    """Tension positive: a pressure compresses the material beneath it
    (σ_zz < 0, and σ_xx, σ_yy < 0 just below the surface); a shear traction
    along +x gives σ_xz < 0 beneath it (the material below holds the layer
    above back), compresses the surface layer ahead of it (σ_xx < 0 at
    x > 0) and stretches it behind (σ_xx > 0 at x < 0)."""
    s = rectangle_stresses(np.array([0.0, 1.0, -1.0]), 0.0, 0.05, 0.5, 0.5, NU)
    centre, ahead, behind = s
    assert centre[2, 2] < 0 and centre[0, 2] < 0 and centre[1, 2] < 0
    assert centre[5, 0] < 0 and centre[4, 1] < 0
    assert ahead[0, 0] < 0 < behind[0, 0]


def _hertz_axis(cells_per_radius: int, nu: float):
    """The Hertz pressure p = √(1 − r²/a²) (p0 = a = 1) sampled at the cell
    centres of a grid with a/h = ``cells_per_radius`` (odd size: the middle
    cell is centred on the axis), and its stress field."""
    h = 1.0 / cells_per_radius
    n = 2 * cells_per_radius + 3
    grid = Grid.centred(n, n, h, h)
    c = grid.centres
    t = np.zeros((grid.size, 3))
    t[:, 2] = np.sqrt(np.clip(1.0 - c[:, 0] ** 2 - c[:, 1] ** 2, 0.0, None))
    return HalfSpaceStress(grid, nu), t


def _hertz_exact(z: np.ndarray, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """σ_z/p0 and σ_r/p0 on the axis at depth z/a (Johnson §3.4)."""
    s_z = -1.0 / (1.0 + z * z)
    s_r = -(1.0 + nu) * (1.0 - z * np.arctan(1.0 / z)) + 0.5 / (1.0 + z * z)
    return s_z, s_r


@pytest.mark.validation
def test_hertz_axis_stresses_converge_to_johnson():
    """The Hertz pressure on a grid: on the axis, from z = 0.05a to 3a, σ_z
    and σ_r (= σ_xx = σ_yy there) against Johnson's closed forms.  The errors
    come from sampling the pressure piecewise constant (midpoint values; the
    square-root edge and the staircase of the contact circle); measured, as a
    fraction of p0: 1.8e-3, 3.9e-4, 8.2e-5 at a/h = 10, 20, 40 (fitted rate
    2.2).  Asserted: within 1 % of p0 on every grid, 5e-4 at a/h = 40, a rate
    above 1.5.  The shears vanish on the axis by symmetry (to 1e-9 p0;
    observed 2e-11)."""
    z = np.linspace(0.05, 3.0, 60)
    points = np.zeros((z.size, 3))
    points[:, 2] = z
    s_z, s_r = _hertz_exact(z, NU)
    sizes = np.array([10, 20, 40])
    errors = []
    for m in sizes:
        field, t = _hertz_axis(int(m), NU)
        s = field.at(points, t)
        err = max(np.abs(s[:, 2] - s_z).max(), np.abs(s[:, 0] - s_r).max(),
                  np.abs(s[:, 1] - s_r).max())
        assert err < 0.01, (m, err)
        assert np.abs(s[:, 3:]).max() < 1e-9, (m, np.abs(s[:, 3:]).max())
        errors.append(err)
    rate = -np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert rate > 1.5, (rate, errors)
    assert errors[-1] < 5e-4, errors


@pytest.mark.validation
def test_hertz_maximum_shear_below_the_surface():
    """τ₁ = ½ |σ_z − σ_r| on the axis peaks at 0.31 p0 at z = 0.48a for
    ν = 0.3 (Johnson §3.4); the exact maximum of the closed forms is 0.310021
    p0 at z = 0.480864a.  On the grid (a/h = 40) τ₁ is the maximum shear
    (the principal stresses there are σ_z, σ_r, σ_r), maximized in z:
    observed 0.310003 p0 at 0.48081a (6e-5 and 5e-5 a off); asserted 0.5 %
    and 0.02a, the bounds asked of the method."""
    def exact(z):
        s_z, s_r = _hertz_exact(np.asarray(z), NU)
        return -0.5 * abs(s_z - s_r)

    best = minimize_scalar(exact, bounds=(0.2, 0.8), method="bounded",
                           options={"xatol": 1e-8})
    assert -best.fun == pytest.approx(0.31, abs=5e-4) and best.x == pytest.approx(0.48, abs=1e-3)
    field, t = _hertz_axis(40, NU)
    found = minimize_scalar(lambda z: -tresca(field.at(np.array([[0.0, 0.0, z]]), t))[0],
                            bounds=(0.2, 0.8), method="bounded", options={"xatol": 1e-5})
    assert -found.fun == pytest.approx(-best.fun, rel=5e-3), (-found.fun, -best.fun)
    assert abs(found.x - best.x) < 0.02, (found.x, best.x)


@pytest.mark.parametrize("loaded", [(0, 1, 2), (2,), (0,)])
def test_fft_layers_equal_the_direct_sum(loaded):
    """The FFT layers are the direct sum over the cells computed another way
    (the same kernels, a Toeplitz product by FFT); FFT round-off is ~ε log n
    of the field and the corner differences are taken at offsets computed
    differently (observed ≤ 4e-14 of the largest stress, at the deepest
    layer, where the field is smallest against the corner values), so
    1e-12.  Unloaded traction components are skipped, which changes
    nothing."""
    grid = Grid((0.3, -0.1), 9, 7, 0.3, 0.2)  # non-square, unequal cells
    field = HalfSpaceStress(grid, NU)
    rng = np.random.default_rng(3)
    t = np.zeros((grid.size, 3))
    t[:, list(loaded)] = rng.standard_normal((grid.size, len(loaded)))
    depths = [0.02, 0.2, 1.0, 5.0]
    layers = field.layers(t, depths)
    assert layers.shape == (4, 9, 7, 6)
    for d, layer in zip(depths, layers):
        points = grid.centres
        points[:, 2] = d
        direct = field.at(points, t)
        assert np.abs(layer.reshape(-1, 6) - direct).max() < 1e-12 * np.abs(direct).max()
        assert np.array_equal(field.layer(t, d), layer)
    blocks = stress_blocks(9, 7, 0.3, 0.2, 1.0, NU)
    assert blocks.shape == (17, 13, 6, 3)
    # the block of offset (di, dj) = (2, -1) is the stress of cell (0, 1) at cell (2, 0)
    one = np.zeros((grid.size, 3))
    one[1, :] = [0.3, -0.7, 1.1]
    expected = blocks[2 + 8, -1 + 6] @ one[1]
    got = field.layer(one, 1.0)[2, 0]
    assert np.abs(got - expected).max() < 1e-12 * np.abs(expected).max()
    assert np.array_equal(field.layers(np.zeros((grid.size, 3)), depths), np.zeros(layers.shape))


def test_kept_kernels_serve_other_tractions(monkeypatch):
    """What does not depend on the tractions (the depth kernels, the points'
    corner sums) is computed once: under a second traction at the same depths
    and points no corner function is evaluated, and the stresses are those
    of a field that keeps nothing (the same kernels, the same products:
    equal to FFT round-off, 1e-13 of the largest stress).  A traction
    component first loaded later gets its kernels then."""
    import bemcontact.halfspace.stress as module

    grid = Grid((0.3, -0.1), 9, 7, 0.3, 0.2)
    rng = np.random.default_rng(5)
    normal = np.zeros((grid.size, 3))
    normal[:, 2] = rng.standard_normal(grid.size)
    t = rng.standard_normal((grid.size, 3))
    depths, points = [0.05, 0.4, 2.0], np.array([[0.5, 0.3, 0.1], [-0.2, 0.9, 0.7]])
    field = HalfSpaceStress(grid, NU)
    field.layers(normal, depths)
    field.layers(t, depths)  # the tangential kernels are added here
    field.at(points, normal)
    calls = []
    real = module.corner_functions
    monkeypatch.setattr(module, "corner_functions", lambda *a: calls.append(1) or real(*a))
    layers, direct = field.layers(t, depths), field.at(points, t)
    assert calls == []
    monkeypatch.setattr(module, "KEEP_BYTES", 0)
    fresh = HalfSpaceStress(grid, NU)
    expected_layers, expected_direct = fresh.layers(t, depths), fresh.at(points, t)
    assert len(calls) == len(depths) + 1
    fresh.layers(t, depths)
    assert len(calls) == 2 * len(depths) + 1  # nothing kept under a budget of 0
    for got, want in ((layers, expected_layers), (direct, expected_direct)):
        assert np.abs(got - want).max() <= 1e-13 * np.abs(want).max()


@pytest.mark.parametrize("point", [(0.1, 0.05, 0.03), (0.3, 0.25, 0.02), (-0.45, 0.7, 0.1),
                                   (2.0, -1.5, 0.8)])
def test_equilibrium(point):
    """div σ = 0: every stress is an exact integral of point-load fields that
    satisfy equilibrium.  The field is smooth on the scale L = z of the
    depth (its nearest singularities, the cell's edges, are at least z away),
    so central differences with step δ = 1e-3 L leave a
    truncation error ~(δ/L)² = 1e-6 and a round-off ~ε L/δ = 1e-13 of
    max|σ|/L; a wrong coefficient would leave O(1).  Observed ≤ 2e-7;
    asserted 1e-5."""
    a, b = 0.3, 0.25
    x, y, z = point
    L = z
    d = 1e-3 * L

    def s(dx, dy, dz):
        return rectangle_stresses(x + dx, y + dy, z + dz, a, b, NU)

    gx = (s(d, 0, 0) - s(-d, 0, 0)) / (2 * d)
    gy = (s(0, d, 0) - s(0, -d, 0)) / (2 * d)
    gz = (s(0, 0, d) - s(0, 0, -d)) / (2 * d)
    xx, yy, zz, xy, yz, xz = range(6)
    div = np.array([gx[xx] + gy[xy] + gz[xz], gx[xy] + gy[yy] + gz[yz],
                    gx[xz] + gy[yz] + gz[zz]])
    scale = np.abs(s(0, 0, 0)).max() / L
    assert np.abs(div).max() < 1e-5 * scale, (np.abs(div).max() / scale)


def test_surface_traction_is_recovered_beneath_a_loaded_region():
    """Just below a uniformly loaded region, σ·n on the plane z = depth
    (outward normal of the slab above it: +z) balances the applied traction:
    σ_iz → −p_i as depth/h → 0.  At depth 1e-4 h below the middle of 21 × 21
    loaded cells the rest is O(depth/h) (the loaded cell's own field) and
    O(depth/(21h)) from the others: asserted 1e-3 (observed 5e-6)."""
    h = 0.2
    grid = Grid.centred(21, 21, h, h)
    p = np.array([0.4, -0.3, 1.0])
    t = np.tile(p, (grid.size, 1))
    s = HalfSpaceStress(grid, NU).at(np.array([[0.0, 0.0, 1e-4 * h]]), t)[0]
    assert np.abs(s[[5, 4, 2]] + p).max() < 1e-3, s


def _grid():
    return Grid((0.0, 0.0), 2, 2, 1.0, 1.0)


@pytest.mark.parametrize("call, match", [
    (lambda: HalfSpaceStress("grid", NU), "HalfSpaceStress: grid must be a Grid"),
    (lambda: HalfSpaceStress(_grid(), 0.5), "HalfSpaceStress: poisson_ratio must be"),
    (lambda: HalfSpaceStress(_grid(), NU).layer(np.zeros((4, 3)), 0.0),
     "HalfSpaceStress.layer: depth must be a finite number > 0"),
    (lambda: HalfSpaceStress(_grid(), NU).layer(np.zeros((4, 3)), -1.0), "depth must be"),
    (lambda: HalfSpaceStress(_grid(), NU).layer(np.zeros((4, 3)), math.nan), "depth must be"),
    (lambda: HalfSpaceStress(_grid(), NU).layers(np.zeros((4, 3)), [1.0, 0.0]),
     "HalfSpaceStress.layers: depths must be"),
    (lambda: HalfSpaceStress(_grid(), NU).layers(np.zeros((4, 3)), [[1.0]]), "depths must be"),
    (lambda: HalfSpaceStress(_grid(), NU).layer(np.zeros((5, 3)), 1.0),
     r"HalfSpaceStress.layers: tractions must have shape \(n, 3\) with n = 4 cells, got \(5, 3\)"),
    (lambda: HalfSpaceStress(_grid(), NU).layer(np.full((4, 3), np.inf), 1.0),
     "tractions must be finite"),
    (lambda: HalfSpaceStress(_grid(), NU).at(np.zeros((2, 3)) + [0, 0, 1], np.zeros((4, 2))),
     r"HalfSpaceStress.at: tractions must have shape \(n, 3\)"),
    (lambda: HalfSpaceStress(_grid(), NU).at(np.zeros((2, 2)), np.zeros((4, 3))),
     r"HalfSpaceStress.at: points must have shape \(m, 3\)"),
    (lambda: HalfSpaceStress(_grid(), NU).at(np.array([[0.5, 0.5, 0.0]]), np.zeros((4, 3))),
     "HalfSpaceStress.at: points must lie inside the body, depth z > 0"),
    (lambda: HalfSpaceStress(_grid(), NU).at(np.array([[0.5, np.nan, 1.0]]), np.zeros((4, 3))),
     "points must be finite"),
    (lambda: rectangle_stresses(0.0, 0.0, -0.1, 0.5, 0.5, NU), "rectangle_stresses: z must be"),
    (lambda: rectangle_stresses(0.0, 0.0, 0.1, 0.0, 0.5, NU),
     "rectangle_stresses: half_width_x must be > 0"),
    (lambda: rectangle_stresses(np.nan, 0.0, 0.1, 0.5, 0.5, NU), "x and y must be finite"),
    (lambda: stress_blocks(2, 2, 1.0, 1.0, 0.0, NU), "stress_blocks: depth must be"),
    (lambda: stress_blocks(0, 2, 1.0, 1.0, 1.0, NU), "stress_blocks: nx must be"),
])
def test_bad_input_is_rejected(call, match):
    with pytest.raises(ConfigError, match=match):
        call()

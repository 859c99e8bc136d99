"""The grid and the FFT-applied half-space operator (halfspace/grid.py): the
FFT product against the dense block-Toeplitz matrix, reciprocity, a uniformly
pressed circle against its closed form, and the checks of bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.sparse.linalg import LinearOperator

from bemcontact.errors import ConfigError
from bemcontact.halfspace import Compliance, Grid, HalfSpaceOperator

G, NU = 80.0, 0.3
E = 2.0 * G * (1.0 + NU)

COMPLIANCES = {
    "one body": Compliance.half_space(G, NU),
    "dissimilar pair": Compliance.pair(30.0, 0.1, 70.0, 0.45),
}


def test_grid_numbers_cells_in_c_order():
    """Cell (i, j) is I = i ny + j, centred at origin + ((i + ½) dx, (j + ½) dy);
    the centres are exact binary fractions here, so they compare exactly."""
    grid = Grid((1.0, -2.0), 3, 2, 0.5, 0.25)
    centres = grid.centres
    assert centres.shape == (6, 3) and centres.flags.c_contiguous
    assert centres[1].tolist() == [1.25, -1.625, 0.0]  # (i, j) = (0, 1)
    assert centres[2].tolist() == [1.75, -1.875, 0.0]  # (1, 0)
    assert (grid.size, grid.shape, grid.cell_area) == (6, (3, 2), 0.125)
    middle = Grid.centred(5, 3, 0.5, 0.25, centre=(1.0, 2.0)).centres[2 * 3 + 1]
    assert middle.tolist() == [1.0, 2.0, 0.0]


@pytest.mark.parametrize("name", sorted(COMPLIANCES))
def test_fft_product_equals_the_dense_toeplitz_product(name):
    """The FFT product is the dense block-Toeplitz product computed another
    way; FFT round-off is ~ε log n of the field's norm, so 1e-12 (observed
    2e-16).  Every accepted shape gives the same numbers."""
    grid = Grid((0.3, -0.1), 7, 5, 0.3, 0.2)  # non-square, unequal cells
    op = HalfSpaceOperator(grid, COMPLIANCES[name])
    dense = op.dense()
    assert dense.shape == op.shape == (3 * grid.size, 3 * grid.size)
    rng = np.random.default_rng(7)
    t = rng.standard_normal((4, grid.size, 3))
    expected = (dense @ t.reshape(4, -1).T).T.reshape(t.shape)

    def rel(a, b):
        return np.linalg.norm(a - b) / np.linalg.norm(b)

    assert rel(op.matvec(t[0]), expected[0]) < 1e-12
    assert rel(op.matvec(t), expected) < 1e-12  # (k, n, 3)
    assert rel(op @ t[1].reshape(-1), expected[1].reshape(-1)) < 1e-12  # (3n,)
    columns = t.reshape(4, -1).T
    assert rel(op.matvec(columns), expected.reshape(4, -1).T) < 1e-12  # (3n, k)
    linear = op.as_linear_operator()
    assert isinstance(linear, LinearOperator) and linear.shape == op.shape
    assert rel(linear.matvec(columns[:, 0]), expected[0].reshape(-1)) < 1e-12
    assert rel(linear.matmat(columns), expected.reshape(4, -1).T) < 1e-12
    assert rel(linear.rmatvec(columns[:, 2]), expected[2].reshape(-1)) < 1e-12


def test_one_cell_grid():
    """A single cell: the operator is its self-block (no padding artefacts)."""
    op = HalfSpaceOperator(Grid((0.0, 0.0), 1, 1, 1.0, 2.0), COMPLIANCES["one body"])
    t = np.array([[0.3, -0.2, 1.0]])
    assert np.abs(op.matvec(t) - t @ op.blocks[0, 0].T).max() < 1e-14 * np.abs(op.blocks).max()


@pytest.mark.parametrize("name", sorted(COMPLIANCES))
def test_operator_is_symmetric_and_positive(name):
    """Reciprocity (Betti): C_IJ = C_JIᵀ; the even kernels are symmetric and
    the coupling changes sign with both the offset and the transpose.  Exact in
    arithmetic, so to 1e-13 of the largest entry.  The flexibility is positive
    definite (stored energy): the smallest eigenvalue is 0.02–0.09 of the
    largest on such grids (observed), so 0.01 is a safe floor."""
    grid = Grid((0.0, 0.0), 6, 5, 0.3, 0.2)
    dense = HalfSpaceOperator(grid, COMPLIANCES[name]).dense()
    scale = np.abs(dense).max()
    assert np.abs(dense - dense.T).max() < 1e-13 * scale
    eig = np.linalg.eigvalsh(0.5 * (dense + dense.T))
    assert eig[0] > 0.01 * eig[-1], (eig[0], eig[-1])


def _pressed_circle(cells_per_radius: int, component: int) -> tuple[np.ndarray, int]:
    """Displacements of a uniform unit traction (along ``component``) on the
    cells whose centres lie within the unit circle; and the middle cell."""
    h = 1.0 / cells_per_radius
    n = 2 * cells_per_radius + 3
    grid = Grid.centred(n, n, h, h)  # odd n: the middle cell is centred at 0
    x = grid.centres
    t = np.zeros((grid.size, 3))
    t[x[:, 0] ** 2 + x[:, 1] ** 2 < 1.0, component] = 1.0
    u = HalfSpaceOperator(grid, Compliance.half_space(G, NU)).matvec(t)
    return u, (n // 2) * n + n // 2


@pytest.mark.validation
@pytest.mark.parametrize("component", [2, 0])
def test_uniformly_loaded_circle_converges_to_the_closed_form(component):
    """A uniform pressure p on a circle of radius a moves its centre by
    2(1 − ν²) p a / E (Johnson ch. 3); a uniform shear q by (2 − ν) q a / (2G)
    (Cerruti's kernel integrated over the disc: 2πa (1 − ν) + πa ν, over 2πG).
    The cells whose centres lie in the circle make a staircase region that
    contains the disc of radius a − h/√2 and lies in that of radius a + h/√2,
    and the centre's displacement is an integral of ray lengths, so the
    relative error is at most h/(√2 a) (the cell integrals themselves are
    exact).  Measured on a/h = 8, 16, 32, 64: 2.1e-2, 7.2e-3, 1.9e-3, 7.5e-4
    (normal), a fitted rate of 1.6 (the staircase's errors partly cancel
    around the circle, irregularly: 1.1–1.8 on other sequences); asserted:
    first order or better.  The shear gives the same relative errors (the
    staircase is symmetric in x ↔ y, so x²/r³ integrates to half of 1/r over
    it).  The other components vanish at the centre (it is also symmetric in
    x → −x and y → −y): 1e-12 of the loaded one (observed 4e-17)."""
    if component == 2:
        exact = 2.0 * (1.0 - NU**2) / E
    else:
        exact = (2.0 - NU) / (2.0 * G)
    sizes = np.array([8, 16, 32, 64])
    errors = []
    for m in sizes:
        u, middle = _pressed_circle(int(m), component)
        errors.append(abs(u[middle, component] / exact - 1.0))
        assert errors[-1] < 1.0 / (math.sqrt(2.0) * m), (m, errors[-1])
        others = np.delete(u[middle], component)
        assert np.abs(others).max() < 1e-12 * abs(u[middle, component])
    rate = -np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert rate > 1.0, (rate, errors)
    assert errors[-1] < 2e-3, errors


@pytest.mark.parametrize("call, match", [
    (lambda: Grid((0.0, 0.0), 0, 3, 1.0, 1.0), "Grid: nx must be an integer >= 1, got 0"),
    (lambda: Grid((0.0, 0.0), 3, -1, 1.0, 1.0), "Grid: ny must be an integer >= 1"),
    (lambda: Grid((0.0, 0.0), 3, 3, -0.5, 1.0), "Grid: dx must be > 0, got -0.5"),
    (lambda: Grid((0.0, 0.0), 3, 3, 1.0, math.nan), "Grid: dy must be finite"),
    (lambda: Grid((0.0,), 3, 3, 1.0, 1.0), "Grid: origin must be two finite numbers"),
    (lambda: Grid((0.0, math.inf), 3, 3, 1.0, 1.0), "Grid: origin must be two finite"),
    (lambda: Grid("corner", 3, 3, 1.0, 1.0), "Grid: origin must be two numbers"),
    (lambda: HalfSpaceOperator("grid", COMPLIANCES["one body"]), "grid must be a Grid"),
    (lambda: HalfSpaceOperator(Grid((0, 0), 2, 2, 1, 1), (1.0, 0.3)),
     "compliance must be a Compliance"),
    (lambda: HalfSpaceOperator(Grid((0, 0), 2, 2, 1, 1), COMPLIANCES["one body"]).matvec(
        np.zeros((5, 3))), r"traction must have shape .* n = 4 cells, got \(5, 3\)"),
    (lambda: HalfSpaceOperator(Grid((0, 0), 2, 2, 1, 1), COMPLIANCES["one body"]).matvec(
        np.zeros((4, 2))), "traction must have shape"),
])
def test_bad_input_names_the_field(call, match):
    with pytest.raises(ConfigError, match=match):
        call()


def test_grid_accepts_numpy_numbers():
    """Sizes from NumPy arithmetic are numbers like any other."""
    grid = Grid(np.array([0.0, 1.0]), np.int64(3), np.int32(2), np.float32(0.5), 0.25)
    assert (grid.nx, grid.ny, grid.dx, grid.origin) == (3, 2, 0.5, (0.0, 1.0))
    assert type(grid.nx) is int and type(grid.dx) is float

"""The contact law (bemcontact.contact.law): residual, generalized Jacobian, states.

Conventions under test (law.py docstring): per frame node, components
(t1, t2, n); lam is the traction on body 2 (lam_n > 0 compressive), k the
displacement of body 2 relative to body 1 (k_n > 0 open);
sn = lam_n - r_n k_n, st = lam_t - r_t (k_t - k_prev),
Phi_n = lam_n - max(0, sn), Phi_t = lam_t - P_R(st), R = mu max(0, sn).

Tolerances
----------
* Jacobians against central differences with step h = 1e-6 at points at
  least 0.1 away (in sn and in |st| - R) from every kink, so the stencil never
  crosses one.  Open and stick are linear pieces: only round-off remains,
  ~eps |Phi| / h ~ 1e-10.  Slip is smooth with third derivatives
  ~ mu sn / |st|^3 = O(1) here: truncation ~ h^2 = 1e-12.  Hence 1e-8
  (absolute; all entries of lam, k, r are O(1)), a margin of ~100 over the
  largest measured error (~1e-10).
* Known solutions: open and stick give Phi = 0 exactly (only exact
  operations on the solution: x - 0, max, x - x).  Slip involves a norm, a
  division and a product: a few ulps, asserted as 8 eps |lam|.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from bemcontact.contact import law
from bemcontact.contact.law import OPEN, SLIP, STICK

EPS = np.finfo(float).eps
MU = 0.3
R_N, R_T = 1.0, 3.0

# (lam, k, k_prev, r_n, r_t) strictly inside each state, margins stated
POINTS = {
    # sn = 0.05 - 1.0 = -0.95: open by 0.95
    "open": ((0.1, -0.2, 0.05), (0.3, -0.1, 1.0), (0.1, 0.2), R_N, R_T),
    # sn = 1.9, R = 0.57, st = (0.07, -0.11), |st| = 0.13: stick by 0.44
    "stick": ((0.1, -0.05, 2.0), (0.01, 0.02, 0.1), (0.0, 0.0), R_N, R_T),
    # sn = 1.05, R = 0.315, st = (1.4, -1.3), |st| = 1.91: slip by 1.6
    "slip": ((0.8, -0.4, 1.0), (-0.2, 0.3, -0.05), (0.0, 0.0), R_N, R_T),
    # same with other penalties and a nonzero k_prev (r_n = 0.5, r_t = 2):
    # sn = 1.2 + 0.1 = 1.3, R = 0.39, st = (-0.5 - 0.8, 0.6 + 0.4) = (-1.3, 1.0)
    "slip2": ((-0.5, 0.6, 1.2), (0.5, -0.1, -0.2), (0.1, 0.1), 0.5, 2.0),
}
EXPECTED_STATE = {"open": OPEN, "stick": STICK, "slip": SLIP, "slip2": SLIP}


def _arrays(lam, k, kp):
    return (np.array([lam], float), np.array([k], float), np.array([kp], float))


def _fd(f, x, h):
    """Central differences of f: (m, 3) -> (m, 3) w.r.t. each column of x,
    node-wise: J[i, a, b] = dPhi[i, a] / dx[i, b]."""
    J = np.zeros(x.shape + (3,))
    for b in range(3):
        e = np.zeros_like(x)
        e[:, b] = h
        J[:, :, b] = (f(x + e) - f(x - e)) / (2 * h)
    return J


def _check_fd(lam, k, kp, mu, rn, rt, h=1e-6, tol=1e-8):
    Jl, Jk, state = law.jacobian(lam, k, kp, mu, rn, rt)
    Jl_fd = _fd(lambda x: law.residual(x, k, kp, mu, rn, rt), lam, h)
    Jk_fd = _fd(lambda x: law.residual(lam, x, kp, mu, rn, rt), k, h)
    err_l = np.abs(Jl - Jl_fd).max()
    err_k = np.abs(Jk - Jk_fd).max()
    assert err_l < tol, f"J_lam vs central differences: max error {err_l:.3g}"
    assert err_k < tol, f"J_k vs central differences: max error {err_k:.3g}"
    return Jl, Jk, state


# ------------------------------------------------------------------ Jacobians
@pytest.mark.parametrize("mu", [MU, 0.0])
@pytest.mark.parametrize("name", list(POINTS))
def test_jacobian_matches_central_differences(name, mu):
    lam, k, kp, rn, rt = POINTS[name]
    Jl, Jk, state = _check_fd(*_arrays(lam, k, kp), mu, rn, rt)
    want = EXPECTED_STATE[name]
    if mu == 0.0 and want == STICK:
        want = SLIP  # frictionless closed nodes count as SLIP
    assert state.tolist() == [want]
    # the pieces themselves, written out: open Phi = lam; closed normal row
    # Phi_n = r_n k_n; stick Phi_t = r_t (k_t - k_prev); frictionless Phi_t = lam_t
    if want == OPEN:
        np.testing.assert_array_equal(Jl[0], np.eye(3))
        np.testing.assert_array_equal(Jk[0], np.zeros((3, 3)))
    else:
        np.testing.assert_array_equal(Jl[0, 2], [0.0, 0.0, 0.0])
        np.testing.assert_array_equal(Jk[0, 2], [0.0, 0.0, rn])
    if want == STICK:
        np.testing.assert_array_equal(Jl[0], np.zeros((3, 3)))
        np.testing.assert_array_equal(Jk[0, :2], [[rt, 0, 0], [0, rt, 0]])
    if want == SLIP and mu == 0.0:
        np.testing.assert_array_equal(Jl[0, :2], [[1, 0, 0], [0, 1, 0]])
        np.testing.assert_array_equal(Jk[0, :2], np.zeros((2, 3)))


def test_jacobian_vectorized_with_per_node_penalties():
    """All points in one call, with per-node r_n, r_t arrays: the blocks are
    those of the single-node calls, and they match central differences."""
    names = list(POINTS)
    lam = np.array([POINTS[n][0] for n in names], float)
    k = np.array([POINTS[n][1] for n in names], float)
    kp = np.array([POINTS[n][2] for n in names], float)
    rn = np.array([POINTS[n][3] for n in names], float)
    rt = np.array([POINTS[n][4] for n in names], float)
    Jl, Jk, state = _check_fd(lam, k, kp, MU, rn, rt)
    assert Jl.shape == Jk.shape == (len(names), 3, 3)
    assert state.tolist() == [EXPECTED_STATE[n] for n in names]
    for i, n in enumerate(names):
        l1, k1, s1 = law.jacobian(*_arrays(*POINTS[n][:3]), MU, rn[i], rt[i])
        np.testing.assert_array_equal(Jl[i], l1[0])
        np.testing.assert_array_equal(Jk[i], k1[0])


def test_jacobian_on_a_kink_is_that_of_the_reported_state():
    """On sn = 0 (reported OPEN) and on |st| = R (reported STICK) the
    Jacobian is the (constant) one of the open / stick piece, i.e. the
    one-sided derivative from the reported side."""
    # sn = 1 - 1*1 = 0 exactly
    lam, k, kp = _arrays((0.2, 0.1, 1.0), (0.0, 0.0, 1.0), (0.0, 0.0))
    Jl, Jk, st = law.jacobian(lam, k, kp, MU, 1.0, 1.0)
    assert st.tolist() == [OPEN]
    np.testing.assert_array_equal(Jl[0], np.eye(3))
    np.testing.assert_array_equal(Jk[0], np.zeros((3, 3)))
    # sn = 2, R = 0.5 (mu = 0.25), st = (0.5, 0): |st| = R exactly
    lam, k, kp = _arrays((0.5, 0.0, 2.0), (0.0, 0.0, 0.0), (0.0, 0.0))
    Jl, Jk, st = law.jacobian(lam, k, kp, 0.25, 1.0, 2.0)
    assert st.tolist() == [STICK]
    np.testing.assert_array_equal(Jl[0], np.zeros((3, 3)))
    np.testing.assert_array_equal(Jk[0], np.diag([2.0, 2.0, 1.0]))


# ------------------------------------------------------------ known solutions
R_VALUES = [1e-3, 1.0, 1e3]


@pytest.mark.parametrize("r_n, r_t", list(itertools.product(R_VALUES, R_VALUES)))
def test_known_solutions_are_zeros_for_every_penalty(r_n, r_t):
    """Phi = 0 at an open, a stick and a slip solution whatever r_n, r_t > 0:
    the solution set does not depend on the penalties."""
    rng = np.random.default_rng(7)
    m = 6
    kp = rng.uniform(-1, 1, (m, 2))
    # open: lam = 0, gap > 0, any tangential displacement
    lam_o = np.zeros((m, 3))
    k_o = np.column_stack([rng.uniform(-1, 1, (m, 2)), rng.uniform(0.01, 1, m)])
    # stick: gap = 0, k_t = k_prev, |lam_t| < mu lam_n (strictly, 0 included)
    p = rng.uniform(0.5, 2.0, m)
    ang = rng.uniform(0, 2 * np.pi, m)
    frac = np.array([0.0, 0.1, 0.5, 0.9, 0.99, 0.3])
    lam_s = np.column_stack([frac * MU * p * np.cos(ang), frac * MU * p * np.sin(ang), p])
    k_s = np.column_stack([kp, np.zeros(m)])
    # slip: gap = 0, body 2 slips by s d; the friction on body 2 opposes it
    d = np.column_stack([np.cos(ang), np.sin(ang)])
    s = rng.uniform(1e-3, 1.0, m)
    lam_sl = np.column_stack([-MU * p[:, None] * d, p])
    k_sl = np.column_stack([kp + s[:, None] * d, np.zeros(m)])

    for lam, k, state, exact in (
        (lam_o, k_o, OPEN, True),
        (lam_s, k_s, STICK, True),
        (lam_sl, k_sl, SLIP, False),
    ):
        phi = law.residual(lam, k, kp, MU, r_n, r_t)
        if exact:
            np.testing.assert_array_equal(phi, 0.0)
        else:
            err = np.abs(phi).max()
            assert err <= 8 * EPS * np.abs(lam).max(), f"slip residual {err:.3g}"
        assert law.contact_state(lam, k, kp, MU, r_n, r_t).tolist() == [state] * m


@pytest.mark.parametrize("r_t", R_VALUES)
def test_friction_along_the_slip_is_not_a_solution(r_t):
    """Sign convention: lam_t = +mu lam_n d while body 2 slips by s d (the
    friction pushing body 2 along its own slip) leaves Phi_t != 0.  With
    st = (mu p - r_t s) d: stick if r_t s <= mu p (Phi_t = r_t s d), otherwise
    slip the other way (Phi_t = 2 mu p d)."""
    p, s = 1.0, 0.1
    d = np.array([0.6, 0.8])
    lam, k, kp = _arrays((MU * p * d[0], MU * p * d[1], p), (s * d[0], s * d[1], 0.0), (0, 0))
    phi = law.residual(lam, k, kp, MU, 1.0, r_t)[0]
    want = r_t * s * d if r_t * s <= MU * p else 2 * MU * p * d
    # lam_t - st cancels: a few ulps of |lam| (~0.3), not of Phi (down to 6e-5)
    np.testing.assert_allclose(phi[:2], want, rtol=0, atol=4 * EPS * np.abs(lam).max())
    assert phi[2] == 0.0


@pytest.mark.parametrize("r_n", R_VALUES)
def test_normal_non_solutions(r_n):
    """Pressure on an open gap: Phi_n = min(lam_n, r_n g) > 0 (to the one
    rounding of the subtraction); penetration without pressure:
    Phi_n = -r_n |g| (exact: one product, one max)."""
    lam = np.array([[0.0, 0.0, 0.7], [0.0, 0.0, 0.0]])
    k = np.array([[0.0, 0.0, 0.2], [0.0, 0.0, -0.2]])
    kp = np.zeros((2, 2))
    phi = law.residual(lam, k, kp, MU, r_n, 1.0)
    assert phi[0, 2] == 0.7 - max(0.0, 0.7 - r_n * 0.2)  # same operations: bitwise
    assert phi[0, 2] == pytest.approx(min(0.7, r_n * 0.2), rel=4 * EPS)  # one rounding
    assert phi[1, 2] == -r_n * 0.2
    np.testing.assert_array_equal(phi[:, :2], 0.0)


# ------------------------------------------------------------------- states
def test_state_classification_and_boundaries():
    lam = np.array(
        [
            [0.1, -0.2, 0.05],  # sn = -0.95: open
            [0.1, -0.05, 2.0],  # stick (see POINTS)
            [0.8, -0.4, 1.0],  # slip (see POINTS with k below)
            [5.0, 0.0, 1.0],  # sn = 0 exactly: open (sn <= 0), whatever st
            [0.5, 0.0, 2.0],  # |st| = R = 0.25 * 2 exactly: stick (|st| <= R)
            [0.0, 0.0, 1.0],  # st = 0, closed: stick
        ]
    )
    k = np.array(
        [
            [0.3, -0.1, 1.0],
            [0.01, 0.02, 0.1],
            [-0.2, 0.3, -0.05],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
        ]
    )
    kp = np.zeros((6, 2))
    rn, rt = np.array([1, 1, 1, 1, 1, 1.0]), np.array([3, 3, 3, 3, 1, 1.0])
    mu = np.array([MU, MU, MU, MU, 0.25, MU])
    for i in range(6):  # mu is a scalar in the API: one call per node where it differs
        st = law.contact_state(lam[i : i + 1], k[i : i + 1], kp[i : i + 1], mu[i], rn[i], rt[i])
        assert st.dtype == np.int8 and st.shape == (1,)
        assert st[0] == [OPEN, STICK, SLIP, OPEN, STICK, STICK][i], i
    # vectorized (m, 3) call with mu = 0.3: row 4 has R = 0.6 > |st| = 0.5, still stick
    st = law.contact_state(lam, k, kp, MU, rn, rt)
    assert st.shape == (6,) and st.dtype == np.int8
    assert st.tolist() == [OPEN, STICK, SLIP, OPEN, STICK, STICK]
    # frictionless: every closed node is SLIP, open ones stay OPEN
    st0 = law.contact_state(lam, k, kp, 0.0, rn, rt)
    assert st0.tolist() == [OPEN, SLIP, SLIP, OPEN, SLIP, SLIP]
    # jacobian reports the same states
    assert law.jacobian(lam, k, kp, MU, rn, rt)[2].tolist() == st.tolist()
    assert law.STATE_NAMES[OPEN] == "open" and law.STATE_NAMES[STICK] == "stick"
    assert law.STATE_NAMES[SLIP] == "slip"


def test_state_on_a_large_random_batch():
    """Vectorized classification equals the definition applied row by row."""
    rng = np.random.default_rng(3)
    m = 400
    lam = np.column_stack([rng.uniform(-0.3, 0.3, (m, 2)), rng.uniform(-1, 2, m)])
    k = rng.uniform(-0.1, 0.1, (m, 3))
    kp = rng.uniform(-0.1, 0.1, (m, 2))
    rn = rng.uniform(0.1, 3, m)
    rt = rng.uniform(0.1, 3, m)
    st = law.contact_state(lam, k, kp, MU, rn, rt)
    sn = lam[:, 2] - rn * k[:, 2]
    stt = lam[:, :2] - rt[:, None] * (k[:, :2] - kp)
    want = np.where(sn <= 0, OPEN, np.where(np.linalg.norm(stt, axis=1) <= MU * sn, STICK, SLIP))
    np.testing.assert_array_equal(st, want)
    counts = np.bincount(st, minlength=3)
    assert (counts > 20).all(), f"every state represented: {counts}"


# ------------------------------------------------------------- broadcasting
def test_per_node_penalties_broadcast():
    """r_n, r_t may be scalars or (m,) arrays; node i of an array call equals
    a scalar call with r[i] (bitwise: the same operations), and a constant
    array equals the scalar."""
    rng = np.random.default_rng(11)
    m = 50
    lam = rng.uniform(-1, 2, (m, 3))
    k = rng.uniform(-0.5, 0.5, (m, 3))
    kp = rng.uniform(-0.5, 0.5, (m, 2))
    rn = rng.uniform(0.1, 10, m)
    rt = rng.uniform(0.1, 10, m)
    phi = law.residual(lam, k, kp, MU, rn, rt)
    Jl, Jk, st = law.jacobian(lam, k, kp, MU, rn, rt)
    for i in range(m):
        sl = slice(i, i + 1)
        phi_i = law.residual(lam[sl], k[sl], kp[sl], MU, rn[i], rt[i])
        np.testing.assert_array_equal(phi[i], phi_i[0])
        jl, jk, s1 = law.jacobian(lam[sl], k[sl], kp[sl], MU, rn[i], rt[i])
        np.testing.assert_array_equal(Jl[i], jl[0])
        np.testing.assert_array_equal(Jk[i], jk[0])
        assert st[i] == s1[0]
    # scalar r == constant array r; mixed scalar / array
    np.testing.assert_array_equal(
        law.residual(lam, k, kp, MU, 2.0, 0.5),
        law.residual(lam, k, kp, MU, np.full(m, 2.0), np.full(m, 0.5)),
    )
    np.testing.assert_array_equal(
        law.residual(lam, k, kp, MU, 2.0, rt), law.residual(lam, k, kp, MU, np.full(m, 2.0), rt)
    )
    # a penalty array of the wrong length is refused (numpy's broadcast error)
    with pytest.raises(ValueError):
        law.residual(lam, k, kp, MU, np.ones(m + 1), 1.0)


def test_the_law_object_is_the_functions_at_its_history():
    """CoulombLaw (the interface system's ``law``) owns the coefficients in
    effect, the augmentation and the stick reference: its state, residual
    and Jacobian are the module's functions with those, bit for bit."""
    rng = np.random.default_rng(3)
    m = 40
    lam = rng.standard_normal((m, 3))
    k = 1e-3 * rng.standard_normal((m, 3))
    friction = rng.uniform(0.0, 0.5, m)
    r = rng.uniform(1e3, 1e4, m)
    c = law.CoulombLaw(friction, r)
    assert np.array_equal(c.mu, friction) and c.mu is not c.friction
    c.reference = 1e-3 * rng.standard_normal((m, 2))
    c.mu[::3] = 0.0  # closing nodes: frictionless in this increment
    assert np.array_equal(c.state(lam, k), law.contact_state(lam, k, c.reference, c.mu, r, r))
    assert np.array_equal(c.residual(lam, k), law.residual(lam, k, c.reference, c.mu, r, r))
    for a, b in zip(c.jacobian(lam, k), law.jacobian(lam, k, c.reference, c.mu, r, r)):
        assert np.array_equal(a, b)
    assert c.m == m and not c.anchors.any()

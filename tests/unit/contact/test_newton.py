"""Newton steps (contact/newton.py): a reused factorization as GMRES
preconditioner gives the step of a fresh LU to the forcing tolerance, and
the whole solve the same answer."""

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.contact import law
from bemcontact.contact.newton import NewtonSteps, newton

from .test_problem import MU, P, _problem, _q, _system


@pytest.fixture(scope="module")
def partial_slip():
    """The two-block problem of test_problem at Q = 0.85 mu P after two
    Newton iterations (a partial-slip point), and the system."""
    system = _system(_problem(), [bc.LoadStep(label="P"), _q(0.85 * MU * P)])
    z, _, msg = newton(system, system.zero(), np.array([1.0, 0.0]), bc.SolverOptions())
    assert msg is None
    system.law.reference = system.k(z, np.array([1.0, 0.0]))[:, :2].copy()
    ell = np.array([0.0, 1.0])
    return system, z, ell


@pytest.fixture(autouse=True)
def _small_systems_reuse(monkeypatch):
    """Reuse from the first unknown (the production threshold, 4,000, is
    beyond these small problems)."""
    monkeypatch.setattr("bemcontact.contact.newton.SINGLE_MIN", 0)


def test_reused_factorization_gives_the_direct_step(partial_slip):
    """Factor the Newton matrix at one iterate, then take the step at the
    next one (same closed set, stick/slip changed) by GMRES preconditioned
    with that factorization: it equals the fresh LU's step to the forcing
    tolerance (relative residual 1e-10 -> step error <= 1e-8 with the
    matrix's condition; measured 6e-14; 8 of 16 nodes changed state)."""
    system, z, ell = partial_slip
    steps = NewtonSteps(max_change=0.1)
    phi = system.residual(z, ell)
    A, b, keep, state0 = system.newton_system(z, ell, phi)
    dz = steps(A, b, keep, phi)
    # the first step: a single-precision LU as GMRES preconditioner
    assert steps.stats["factorizations"] == 1 and steps.stats["krylov_steps"] == 1
    first = steps.stats["krylov_iterations"]
    assert 0 < first <= 5
    z1 = z + dz
    phi1 = system.residual(z1, ell)
    A1, b1, keep1, state1 = system.newton_system(z1, ell, phi1)
    assert np.array_equal(keep1, keep) and not np.array_equal(state1, state0)
    assert (state1 == law.STICK).any() and (state1 == law.SLIP).any()
    reused = steps(A1.copy(), b1, keep1, phi1, forcing=1e-10)
    # the second: GMRES with that same factorization, nothing factored
    assert steps.stats["factorizations"] == 1 and steps.stats["krylov_steps"] == 2
    # (measured 20 and 21 on these 50 unknowns with the single-precision
    # factors of two BLAS kernels: the count follows the factors' rounding,
    # hence a bound)
    assert 0 < steps.stats["krylov_iterations"] - first <= 30
    direct = NewtonSteps(reuse=False)(A1, b1, keep1, phi1)
    assert np.abs(reused - direct).max() <= 1e-8 * np.abs(direct).max()


def test_mixed_precision_changes_nothing_but_the_factorizations():
    """The whole P, Q cycle with newton_steps = "lu" and "mixed": the same
    forces to 1e-9 (the Newton tolerance 1e-10 of the traction scale), the
    same contact states and Newton iterations; with "mixed" every step is a
    single-precision LU and 1-2 GMRES iterations (measured 1-2)."""
    prob = _problem()
    steps = [bc.LoadStep(label="P"), _q(0.85 * MU * P, P), _q(0.5 * MU * P, P)]
    a = prob.solve(bc.SolverOptions(newton_steps="lu"), steps=steps)
    b = prob.solve(bc.SolverOptions(newton_steps="mixed"), steps=steps)
    for ra, rb in zip(a.history, b.history):
        np.testing.assert_allclose(rb.contact_force, ra.contact_force, rtol=0,
                                   atol=1e-9 * abs(ra.normal_force))
        np.testing.assert_array_equal(rb.frame.state, ra.frame.state)
    assert [s.iterations for s in a.steps] == [s.iterations for s in b.steps]
    fa = sum(s.factorizations for s in a.steps)
    fb = sum(s.factorizations for s in b.steps)
    kb = sum(s.krylov_iterations for s in b.steps)
    assert fa == fb == a.newton_iterations
    assert sum(s.krylov_iterations for s in a.steps) == 0
    assert b.newton_iterations <= kb <= 2 * b.newton_iterations


def test_newton_steps_option_is_checked():
    with pytest.raises(bc.ConfigError, match="newton_steps"):
        bc.SolverOptions(newton_steps="cg")


def test_the_newton_matrix_is_the_jacobian_block_and_its_rows_of_k_are_kept(partial_slip):
    """newton_system builds A = J[keep, keep] row by row (C order) from K's
    closed rows, which it keeps while the closed set stays: the next
    iterate's block (stick/slip changed, same closed set) reuses them and
    equals a block built from scratch bit for bit; a different closed set
    gathers new rows."""
    system, z, ell = partial_slip
    phi = system.residual(z, ell)
    A, b, keep, _ = system.newton_system(z, ell, phi)
    assert A.flags.c_contiguous
    J, rows, _ = system.jacobian(z, ell)
    np.testing.assert_array_equal(A, J[:, keep])
    kept = system._dk
    dz = NewtonSteps(reuse=False)(A.copy(), b, keep, phi)
    z1 = z + dz
    phi1 = system.residual(z1, ell)
    A1, _, keep1, _ = system.newton_system(z1, ell, phi1)
    assert np.array_equal(keep1, keep) and system._dk[2] is kept[2]
    system.release()
    assert system._dk is None
    fresh, _, _, _ = system.newton_system(z1, ell, phi1)
    np.testing.assert_array_equal(fresh, A1)
    # a closed set with one node fewer: new rows, K's
    cdofs = keep[keep < 3 * system.m][3:]
    dk = system._rows_of_k(cdofs, keep)
    assert dk is not A1 and dk.shape == (cdofs.size, keep.size)
    lc = keep[keep < 3 * system.m]
    np.testing.assert_array_equal(dk[:, : lc.size], system.K[np.ix_(cdofs, lc)])


def test_newton_step_of_a_c_ordered_matrix(partial_slip):
    """The step from the C-ordered Newton matrix, by a double LU and by a
    single-precision LU with GMRES, solves A dz = b: residual <= 1e-12 and
    <= 1e-9 of |b| (the forcing 1e-10 times the matrix's condition)."""
    system, z, ell = partial_slip
    phi = system.residual(z, ell)
    A, b, keep, _ = system.newton_system(z, ell, phi)
    for reuse, tol in ((False, 1e-12), (True, 1e-9)):
        dz = NewtonSteps(reuse=reuse)(A.copy(), b, keep, phi)
        r = A @ dz[keep] - b
        assert np.linalg.norm(r) <= tol * np.linalg.norm(b), (reuse, np.linalg.norm(r))
        open_ = np.setdiff1d(np.arange(phi.size), keep)
        np.testing.assert_array_equal(dz[open_], -phi[open_])

"""The sparse factor behind a finite-element body's condensation: the
flexibility on the trailing dofs read in place from the supernodal factor
is the inverse's block, the factor still solves after it, and a factor it
cannot vouch for is read the slow way."""

import numpy as np
import pytest
import scipy.sparse

pytest.importorskip("cvxopt")

from bemcontact.fem.condensation import SchurFactor
from bemcontact.fem.supernodal import trailing_block


def _stiffness(m: int = 9):
    """An SPD matrix with a stiffness's pattern: three dofs per node of an
    m³ grid, 7-point coupling, a random SPD 3 × 3 block per node pair."""
    rng = np.random.default_rng(3)
    lap1 = scipy.sparse.diags([-1.0, 2.05, -1.0], [-1, 0, 1], shape=(m, m))
    eye = scipy.sparse.identity(m)
    lap = (scipy.sparse.kron(scipy.sparse.kron(lap1, eye), eye)
           + scipy.sparse.kron(scipy.sparse.kron(eye, lap1), eye)
           + scipy.sparse.kron(scipy.sparse.kron(eye, eye), lap1))
    C = rng.normal(size=(3, 3))
    C = C @ C.T + 3 * np.eye(3)
    A = scipy.sparse.kron(lap, C, format="csr")
    top = np.flatnonzero(np.arange(m ** 3) % m == m - 1)  # a face of nodes
    return A, (3 * top[:, None] + np.arange(3)).ravel()


def test_the_flexibility_is_the_inverse_on_the_trailing_dofs():
    A, last = _stiffness()
    f = SchurFactor(A, last, groups=np.arange(A.shape[0]) // 3)
    want = np.linalg.inv(A.toarray())[np.ix_(last, last)]
    got = f.contact_inverse()
    # a well-conditioned SPD matrix of 2,187 rows: round-off only
    assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()
    assert np.array_equal(got, got.T)
    b = np.random.default_rng(0).normal(size=(A.shape[0], 2))
    x = f.solve(b)  # the factor is kept as it was: no second factorization
    assert np.abs(A @ x - b).max() <= 1e-11 * np.abs(b).max()


def test_the_block_read_in_place_is_the_one_read_out_exactly():
    A, last = _stiffness(7)
    f = SchurFactor(A, last)
    fast = trailing_block(f._F, f.perm, last.size)
    slow = f._trailing_block_read_out()
    assert fast is not None
    assert np.array_equal(fast, np.tril(slow))  # the same numbers, bit for bit


def test_a_factor_it_cannot_vouch_for_is_not_read():
    A, last = _stiffness(5)
    f = SchurFactor(A, last)
    wrong = f.perm.copy()
    wrong[[0, 1]] = wrong[[1, 0]]
    assert trailing_block(f._F, wrong, last.size) is None  # another permutation
    assert trailing_block(object(), f.perm, last.size) is None  # not a factor
    assert trailing_block(f._F, f.perm[:-1], last.size) is None  # another size


def test_the_groups_order_a_nodes_dofs_together():
    A, last = _stiffness(6)
    f = SchurFactor(A, last, groups=np.arange(A.shape[0]) // 3)
    rest = f.perm[: -last.size]
    nodes = rest // 3
    # each node's dofs are consecutive in the ordering
    assert np.all(np.diff(nodes)[np.diff(nodes) != 0] != 0)
    assert np.unique(nodes).size == np.count_nonzero(np.diff(nodes)) + 1
    assert np.array_equal(f.perm[-last.size:], last)

"""H-matrix operators (bemcontact.bem.compressed) against the dense assembly."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.bench import linear_field_cube
from bemcontact import mesh as M
from bemcontact import bem as O
from bemcontact.errors import ConfigError
from bemcontact.bem import CompressedSystem
from bemcontact.bem.compressed import MATVEC_COLUMNS
from bemcontact.linalg import HMatrixOptions, LinearSolverOptions

MU, NU = 1.0, 0.3


@pytest.fixture(scope="module")
def cube():
    d = O.discretize(M.box((0, 0, 0), (1, 1, 1), (8, 8, 8)))
    H, G = O.assemble_influence(d, MU, NU)
    return d, H, G


def _mixed(d, seed=0):
    # displacement given on a random half of the dofs
    return np.random.default_rng(seed).random(3 * d.n_points) < 0.5


@pytest.mark.parametrize("eps", [1e-4, 1e-6])
def test_matvec_and_bw_match_dense_to_eps(cube, eps):
    # small leaves so that a 654-node cube has many low-rank blocks
    d, H, G = cube
    ku = _mixed(d)
    A = np.where(ku[None, :], -G, H)
    B = np.where(ku[None, :], -H, G)
    rng = np.random.default_rng(1)
    W = rng.standard_normal((3 * d.n_points, 2))
    op = CompressedSystem(
        d, MU, NU, ku, W, options=HMatrixOptions(eps=eps, leaf_size=12), threads=2
    )
    assert op.stats()["low_rank_blocks"] > 50
    x = rng.standard_normal((op.n, 3))
    ref = A @ x
    # each block is within ~eps (Frobenius, relative), so a product with a
    # random vector is within eps of the product's norm (measured 0.03-0.1 eps)
    assert np.linalg.norm(op.matvec(x) - ref) <= eps * np.linalg.norm(ref)
    assert np.linalg.norm(op.BW - B @ W) <= eps * np.linalg.norm(B @ W)
    # one vector (not a block of columns) gives the same
    y = op.matvec(x)
    np.testing.assert_allclose(op.matvec(x[:, 0]), y[:, 0], rtol=0, atol=1e-13 * np.abs(y).max())
    # more columns than one compiled call takes (MATVEC_COLUMNS), from a
    # Fortran-ordered block: each column as its own product, to round-off
    many = np.asfortranarray(rng.standard_normal((op.n, MATVEC_COLUMNS + 7)))
    Y = op.matvec(many)
    for j in (0, MATVEC_COLUMNS - 1, MATVEC_COLUMNS, MATVEC_COLUMNS + 6):
        np.testing.assert_allclose(Y[:, j], op.matvec(many[:, j].copy()), rtol=0,
                                   atol=1e-13 * np.abs(Y[:, j]).max())


def test_aca_blocks_meet_their_tolerance(cube):
    d, H, G = cube
    eps = 1e-4
    for ku, dense in ((None, H), (np.ones(3 * d.n_points, bool), -G)):
        op = CompressedSystem(d, MU, NU, ku, options=HMatrixOptions(eps=eps, leaf_size=12))
        perm = op._h.perm()
        info = op.block_info()
        errs = []
        for i, (tb, ts, sb, ss, rank, aca_rank, _) in enumerate(info):
            if rank < 0:
                continue
            assert rank <= aca_rank
            rows = (3 * perm[tb : tb + ts][:, None] + np.arange(3)).ravel()
            cols = (3 * perm[sb : sb + ss][:, None] + np.arange(3)).ravel()
            exact = dense[np.ix_(rows, cols)]
            errs.append(np.linalg.norm(op._h.block_matrix(i) - exact) / np.linalg.norm(exact))
        e = np.array(errs)
        assert e.size > 500
        # ACA bounds the error of [H | s G] jointly, so either part alone may
        # exceed eps by the ratio of the joint norm to its own, and the
        # recompression adds up to eps; measured: H max 8 eps, median 1.5 eps;
        # G max 2 eps, median 0.6 eps
        assert np.median(e) <= 2 * eps
        assert e.max() <= 10 * eps


def test_recompression_lowers_the_rank(cube):
    d, _, _ = cube
    op = CompressedSystem(d, MU, NU, _mixed(d), options=HMatrixOptions(eps=1e-6, leaf_size=12))
    st = op.stats()
    # A alone has a lower rank than [H | s G] (measured mean 24 vs 37)
    assert st["mean_rank"] <= 0.8 * st["mean_aca_rank"]


def test_exact_entries_and_rigid_body_rows(cube):
    d, H, G = cube
    op = CompressedSystem(d, MU, NU, options=HMatrixOptions(leaf_size=12))
    rng = np.random.default_rng(2)
    rows = rng.choice(op.n, 15, replace=False)
    cols = np.concatenate([rng.choice(op.n, 20, replace=False), rows[:3]])  # incl. diagonal
    eh, eg = op.entries(rows, cols)
    # the same element integrals as the dense assembly; the diagonal 3x3 blocks
    # of H come from compressed row sums, so they carry the eps error
    scale = np.abs(H).max()
    np.testing.assert_allclose(eh, H[np.ix_(rows, cols)], rtol=0, atol=1e-5 * scale)
    np.testing.assert_allclose(eg, G[np.ix_(rows, cols)], rtol=0, atol=1e-14 * np.abs(G).max())
    # A = H annihilates rigid translations (up to eps)
    t = np.tile(np.eye(3), (d.n_points, 1))
    assert np.abs(op.matvec(t)).max() <= 1e-5 * scale


def test_threads_give_the_same_operator(cube):
    d, _, _ = cube
    opts = HMatrixOptions(eps=1e-6, leaf_size=12)
    ku = _mixed(d)
    a = np.random.default_rng(3).standard_normal(3 * d.n_points)
    o1 = CompressedSystem(d, MU, NU, ku, a, options=opts, threads=1)
    o2 = CompressedSystem(d, MU, NU, ku, a, options=opts, threads=2)
    # same blocks (the pivoting is seeded per block); only the order of the
    # final sums differs
    y1, y2 = o1.matvec(a), o2.matvec(a)
    assert np.linalg.norm(y1 - y2) <= 1e-13 * np.linalg.norm(y1)
    assert np.linalg.norm(o1.BW - o2.BW) <= 1e-13 * np.linalg.norm(o1.BW)


def _linear_field_body(divisions, force=False):
    body, A, sigma = linear_field_cube(divisions=divisions)
    if force:
        # zmax pushed as a rigid platen with the exact resultant of sigma n
        bcs = dict(body.boundary_conditions)
        bcs["zmax"] = [bc.Force((None, None, sigma[2, 2])), bc.Traction((sigma[0, 2], sigma[1, 2], None))]
        body = bc.ElasticBody(body.mesh, body.material, bcs)
    return body, A, sigma


def test_compressed_solve_matches_exact_linear_field():
    body, A, sigma = _linear_field_body(8)
    lin = LinearSolverOptions(method="hmatrix", hmatrix=HMatrixOptions(eps=1e-7, leaf_size=12))
    sol = body.solve(linear=lin)
    assert sol.solver["method"] == "hmatrix" and sol.solver["low_rank_blocks"] > 20
    et = sol.normals @ sigma
    eu = sol.points @ A.T
    # the dense path is exact to quadrature (1e-9); the compressed one to
    # about eps times the conditioning (measured 2.5e-7 t, 1e-8 u, 53 iterations)
    assert np.abs(sol.traction - et).max() <= 1e-5 * np.abs(sigma).max()
    assert np.abs(sol.displacement - eu).max() <= 1e-6 * np.abs(eu).max()
    assert sol.solver["iterations"] < 100


def test_compressed_solve_with_force_control_matches_dense():
    body, A, sigma = _linear_field_body(8, force=True)
    dense = body.solve(linear=LinearSolverOptions(method="dense"))
    comp = body.solve(
        linear=LinearSolverOptions(method="hmatrix", hmatrix=HMatrixOptions(eps=1e-7, leaf_size=8))
    )
    assert comp.solver["low_rank_blocks"] > 0
    # measured 7.5e-9 (u) and 4.4e-8 (t) at eps = 1e-7
    for f in ("displacement", "traction"):
        a, b = getattr(dense, f), getattr(comp, f)
        assert np.abs(a - b).max() <= 1e-6 * np.abs(a).max(), f


def test_compressed_solve_of_a_free_body_matches_dense():
    # only tractions given (uniaxial tension on zmin/zmax): rigid modes
    # bordered as in the dense path
    mesh = M.box((0, 0, 0), (1, 1, 1), 8)
    body = bc.ElasticBody(
        mesh, bc.LinearElastic(1e4, 0.3),
        {"zmax": bc.Traction((0.0, 0.0, 10.0)), "zmin": bc.Traction((0.0, 0.0, -10.0))},
    )
    dense = body.solve(linear=LinearSolverOptions(method="dense"))
    comp = body.solve(
        linear=LinearSolverOptions(method="hmatrix", hmatrix=HMatrixOptions(eps=1e-7, leaf_size=12))
    )
    assert comp.solver["low_rank_blocks"] > 20
    a, b = dense.displacement, comp.displacement
    # displacement of a stress-free-ish free body: eps-level agreement (measured 1e-8)
    assert np.abs(a - b).max() <= 1e-6 * np.abs(a).max()


def test_too_loose_eps_warns_instead_of_a_silent_wrong_answer():
    from bemcontact.errors import AccuracyWarning

    body, A, sigma = _linear_field_body(8)
    opts = dict(method="hmatrix", accuracy=1e-6)
    # eps 1e-3: exact residual 1.3e-4 sampled, traction error 7e-3 -> warning
    with pytest.warns(AccuracyWarning, match=r"lower HMatrixOptions.eps \(now 1.0e-03\)"):
        sol = body.solve(linear=LinearSolverOptions(hmatrix=HMatrixOptions(eps=1e-3, leaf_size=12), **opts))
    assert sol.solver["exact_residual"] > 1e-6
    # eps 1e-7: residual 7e-9, no warning (warnings are errors in this suite)
    sol = body.solve(linear=LinearSolverOptions(hmatrix=HMatrixOptions(eps=1e-7, leaf_size=12), **opts))
    assert sol.solver["exact_residual"] < 1e-7


def test_options_are_checked():
    with pytest.raises(ConfigError, match="eps"):
        HMatrixOptions(eps=0)
    with pytest.raises(ConfigError, match="leaf_size"):
        HMatrixOptions(leaf_size=0)
    with pytest.raises(ConfigError, match="method"):
        LinearSolverOptions(method="fast")
    with pytest.raises(ConfigError, match="accuracy"):
        LinearSolverOptions(accuracy=0.0)
    with pytest.raises(ConfigError, match="matvec"):
        CompressedSystem(O.discretize(M.box(divisions=2)), MU, NU).matvec(np.zeros(5))
    with pytest.raises(ConfigError, match="known_u"):
        CompressedSystem(O.discretize(M.box(divisions=2)), MU, NU, known_u=np.zeros(4, bool))


def _assembled(op, shape):
    """The compressed A block by block, as a dense matrix (original order)."""
    perm = op._h.perm()
    out = np.zeros(shape)
    for i, (tb, ts, sb, ss, *_rest) in enumerate(op.block_info()):
        rows = (3 * perm[tb : tb + ts][:, None] + np.arange(3)).ravel()
        cols = (3 * perm[sb : sb + ss][:, None] + np.arange(3)).ravel()
        out[np.ix_(rows, cols)] = op._h.block_matrix(i)
    return out


def _column_errors(F, A, H, G, ku):
    """Frobenius errors of the H and of the G columns, relative to H's and G's."""
    eh = np.linalg.norm((F - A)[:, ~ku]) / np.linalg.norm(H[:, ~ku])
    eg = np.linalg.norm((F - A)[:, ku]) / np.linalg.norm(G[:, ku])
    return eh, eg


def test_mixed_storage_halves_the_tail_and_keeps_the_accuracy(cube):
    d, H, G = cube
    eps = 1e-4
    ku = _mixed(d)
    A = np.where(ku[None, :], -G, H)
    ops = {
        s: CompressedSystem(d, MU, NU, ku, options=HMatrixOptions(eps=eps, leaf_size=12, storage=s))
        for s in ("double", "mixed")
    }
    # the same blocks and ranks; mixed stores trailing terms in float32
    np.testing.assert_array_equal(ops["double"].block_info(), ops["mixed"].block_info())
    # measured 0.77 (the dense near field of these small leaves stays double)
    assert ops["mixed"].stored_bytes <= 0.85 * ops["double"].stored_bytes
    e_double = _column_errors(_assembled(ops["double"], A.shape), A, H, G, ku)
    e_mixed = _column_errors(_assembled(ops["mixed"], A.shape), A, H, G, ku)
    # the rounding may spend at most half the budget of each block: the whole
    # matrix's error grows by at most 1.5x (measured: unchanged to 3 digits,
    # 0.08 eps on H, 0.29 eps on G)
    for a, b in zip(e_double, e_mixed):
        assert b <= 1.5 * a
    assert max(e_mixed) <= eps


def test_global_truncation_meets_its_frobenius_budget(cube):
    d, H, G = cube
    eps = 1e-4
    ku = _mixed(d)
    A = np.where(ku[None, :], -G, H)
    glob = CompressedSystem(d, MU, NU, ku,
                            options=HMatrixOptions(eps=eps, leaf_size=12, truncation="global"))
    block = CompressedSystem(d, MU, NU, ku, options=HMatrixOptions(eps=eps, leaf_size=12))
    # the sampled root-mean-square entries (64 of 654 nodes' full rows) are
    # those of the dense matrices to within 10 % (measured 1-3 %)
    n = 3 * d.n_points
    assert glob._h.rms_h() == pytest.approx(np.linalg.norm(H) / n, rel=0.1)
    assert glob._h.rms_g() == pytest.approx(np.linalg.norm(G) / n, rel=0.1)
    # blocks' squared budgets add up to eps^2 times the squared norm: the H
    # and G columns of A are within eps (measured 0.19 eps and 0.69 eps)
    eh, eg = _column_errors(_assembled(glob, A.shape), A, H, G, ku)
    assert eh <= eps and eg <= eps
    # ... for less memory than each block to eps of its own norm (measured 0.92)
    assert glob.stored_bytes <= 0.96 * block.stored_bytes


def test_gmres_runs_with_single_threaded_blas(monkeypatch):
    """GMRES holds OpenBLAS to one thread while it runs: its spinning
    threads otherwise take the cores from the product's OpenMP threads
    (GMRES 2x slower at 10k-50k nodes, measured).  Checked from inside the
    product: every BLAS library reports one thread there."""
    import threadpoolctl

    from bemcontact.bem import compressed as HM

    body, _, _ = _linear_field_body(6)
    seen = []
    original = HM.CompressedSystem.matvec

    def spy(self, x):
        seen.append(max(i["num_threads"] for i in threadpoolctl.threadpool_info()
                        if i["user_api"] == "blas"))
        return original(self, x)

    monkeypatch.setattr(HM.CompressedSystem, "matvec", spy)
    lin = LinearSolverOptions(method="hmatrix", hmatrix=HMatrixOptions(eps=1e-6, leaf_size=12))
    with threadpoolctl.threadpool_limits(limits=2, user_api="blas"):
        sol = body.solve(threads=2, linear=lin)
    assert sol.solver["iterations"] > 5 and len(seen) > 5
    assert set(seen[:-1]) == {1}  # the last call is the residual check after GMRES


_OUT_OF_MEMORY = """
import resource, sys
import numpy as np
import bemcontact as bc
from bemcontact.bem import CompressedSystem
from bemcontact.linalg import HMatrixOptions
body = bc.ElasticBody(bc.box((0, 0, 0), (1, 1, 1), 10), bc.LinearElastic(1e4, 0.3),
                      {"zmin": bc.Fixed(), "zmax": bc.Displacement((0, 0, -0.01))})
known_u = body.boundary_data(body.boundary_conditions)[0]
cs = CompressedSystem(body.discretization, 1e4 / 2.6, 0.3, known_u, quadrature=body.quadrature,
                      options=HMatrixOptions(eps=1e-6), threads=2)
x = np.ones((cs.n, 256))
cs.matvec(x)
vm = next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmSize")) * 1024
resource.setrlimit(resource.RLIMIT_AS, (int(vm + float(sys.argv[1]) * x.nbytes), -1))
try:
    cs.matvec(x)
    print("done")
except MemoryError as exc:
    print("MemoryError:", exc)
"""


def test_memory_running_out_inside_the_threaded_product_is_a_memory_error():
    """The compiled product allocates its per-thread accumulators inside its
    OpenMP region, where a std::bad_alloc leaving the region would abort the
    process ("terminate called after throwing an instance of
    'std::bad_alloc'", at 3.5 and 4.5 blocks of room): every address-space
    limit from 2.5 to 4.5 times the block's size gives either the product or
    a MemoryError, and the process ends normally."""
    import subprocess
    import sys

    said = []
    for room in (2.5, 3.0, 3.5, 4.0, 4.5):
        r = subprocess.run([sys.executable, "-c", _OUT_OF_MEMORY, str(room)],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 0 and "terminate" not in r.stderr, (room, r.returncode, r.stderr)
        said.append(r.stdout.strip())
    assert all(s == "done" or s.startswith("MemoryError:") for s in said), said
    # the compiled product itself ran out (not only NumPy before it)
    assert "MemoryError: std::bad_alloc" in said, said

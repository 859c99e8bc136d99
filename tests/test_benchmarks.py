"""Smoke run of the benchmark scripts so they cannot rot (no timings asserted)."""

from __future__ import annotations

import importlib.util
import pathlib

import numpy as np
import pytest

BENCH = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"


def test_one_body_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b", BENCH / "bem_one_body_N500_5000.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    row = mod.one(3)
    assert row["nodes"] == 144
    # the benchmark's problem has an exact (linear) solution: the error is
    # quadrature-level, as in the uniform-stress validation (1e-8)
    assert row["error"] < 1e-8
    assert row["assembly_s_2t"] > 0 and row["peak_rss_mb"] > 0


def test_two_cubes_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b2", BENCH / "two_cubes_N4_16.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    row = mod.one(3)
    # functional nodes: lower 3x3x3 quad4 (as in the one-body smoke run), upper 2x2x2
    assert row["nodes_lower"] == 144 and row["nodes_upper"] == 78
    assert row["nodes"] == row["nodes_lower"] + row["nodes_upper"]
    # mortar frame on the coarser (upper, 2x2) face: 3x3 nodes, all in contact
    assert row["frame_nodes"] == 9
    assert row["converged"] and row["newton_iterations"] >= 1
    # validation.md: dissimilar case, uniaxial-stress / confined-modulus bounds
    assert 800.0 < row["normal_force"] < 1077.0
    assert row["open"] == 0 and row["stick"] + row["slip"] == row["frame_nodes"]
    for k in ("assembly_s", "condensation_s", "frame_s", "newton_s", "total_s", "peak_rss_mb"):
        assert row[k] > 0, k
    assert row["total_s"] >= row["assembly_s"] + row["newton_s"]


def test_scaling_script_smoke(capsys):
    spec = importlib.util.spec_from_file_location("b3", BENCH / "scaling.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.main(["--sizes", "150,400", "--cubes", "3", "--repeat", "1", "--no-write"])
    out = capsys.readouterr().out
    assert "Fitted exponents over 144–414 nodes" in out
    assert "| 3 | 222 |" in out  # two cubes K = 3: 144 + 78 nodes
    assert abs(mod.fit([1, 2, 4], [3, 12, 48]) - 2.0) < 1e-12


def test_hlu_factor_benchmark_smoke():
    """benchmarks/hlu_factor.py's record on a small cube with a leaf small
    enough to compress: refined residual at rounding (1e-10, as in
    tests/unit/linalg/test_hlu.py), sizes consistent."""
    from bemcontact.bench import hlu_factor

    rec = hlu_factor(300, eps=1e-8, rhs=3)
    assert rec["nodes"] == 312 and rec["unknowns"] == 936
    assert rec["refined_residual"] <= 1e-10
    assert rec["factor_mb"] > 0 and rec["dense_mb"] == pytest.approx(8 * 936**2 / 1e6)


def test_output_formats_benchmark_smoke():
    """benchmarks/output_formats_N100_160.py on a tiny box: every format writes
    both series and reads back to the values written (the script checks);
    XDMF and VTKHDF only where h5py and vtk are installed (benchmark-only
    dependencies)."""
    spec = importlib.util.spec_from_file_location("b5", BENCH / "output_formats_N100_160.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    expected = {"pvd": 6}  # 2 series x (2 steps + the .pvd)
    if importlib.util.find_spec("h5py") and importlib.util.find_spec("vtk"):
        expected |= {"xdmf": 4, "vtkhdf": 2, "vtkhdf_gz4": 2}  # .xdmf + .h5; one file
    rows = mod.measure(3, steps=2, repeat=1, formats=list(expected))
    assert {r["format"]: r["files"] for r in rows} == expected
    for r in rows:
        assert r["nodes"] == 56 and r["interface_nodes"] == 16 and r["bytes"] > 0
        assert r["write_fsync_s"] >= r["write_s"] > 0
    assert "| 3 | 56 | pvd |" in mod.table(rows)


def test_interface_compression_counts_stored_entries():
    """benchmarks/interface_compression.py's measures on matrices whose answer
    is known: a rank-one K has rank 1 in every far block (stored entries
    r + c each) and in every off-diagonal block, a random K is full rank
    everywhere (compression exactly 1; off-diagonal blocks of 100, 50 and 25
    nodes, 3 dofs each), and the frame's node blocks are dense near the
    diagonal."""
    spec = importlib.util.spec_from_file_location("b6", BENCH / "interface_compression.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    rng = np.random.default_rng(0)
    pts = np.column_stack([rng.random((200, 2)), np.zeros(200)])  # a flat frame
    u = rng.standard_normal(600)
    (one,) = mod.compression(np.outer(u, u), pts, [1e-8], leaf=16, eta=2.0)
    assert one["far_blocks"] > 0 and one["mean_rank"] == 1.0 and one["max_rank"] == 1
    assert one["compression"] > 1.5
    (full,) = mod.compression(rng.standard_normal((600, 600)), pts, [1e-8], leaf=16, eta=2.0)
    assert full["compression"] == 1.0 and full["max_rank"] > 1
    assert 0 < full["dense_share"] < 1
    # the largest off-diagonal blocks of the top three bisections (HODLR ranks)
    assert mod.weak_ranks(np.outer(u, u), pts, 1e-8) == [1, 1, 1]
    assert mod.weak_ranks(rng.standard_normal((600, 600)), pts, 1e-8) == [300, 150, 75]


def test_grid_mindlin_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b_grid", BENCH / "grid_mindlin_vs_tamaas.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    row = mod.one(8.0)
    assert row["converged"] and row["cells"] == 400
    # the measures of tests/unit/multiscale (a/h = 12 there), coarser here
    assert abs(row["p0_err"]) < 5e-3 and row["q_l2"] < 0.05 and abs(row["dt_err"]) < 5e-3
    assert row["cpu_s"] > 0 and row["peak_rss_mb"] > 0


def test_multiscale_mindlin_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b_ms", BENCH / "multiscale_mindlin_vs_tamaas.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    row = mod.one(8.0)
    # the whole run on the coarse bodies at a/h = 8 against the half-space
    # closed forms, measured: p0 -0.46 %, q L2 3.5 % (the finite bodies' own
    # departure from Mindlin is in it: the full path on the same bodies has
    # 3.9 % at a/h = 12, docs/benchmarks.md), stick radius +3.0 % (the grid's
    # first-order cell error: +1.6 % at a/h = 12), delta_t -1.2 %, the
    # estimate 9e-4; bounds about 1.5x those
    assert row["applies"] and row["estimate"] < 1.5e-3
    assert abs(row["p0_err"]) < 0.007 and abs(row["c_err"]) < 0.045 and abs(row["dt_err"]) < 0.02
    assert row["q_l2"] < 0.05 and row["cpu_s"] > 0


def test_multiscale_edges_layers_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b_el", BENCH / "multiscale_edges_layers.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    # the sphere 10 contact radii from the edge, the full path at a/h = 4 (the
    # smoke; 1.8 % above its converged force) and the grid (cells of a/25, as
    # in the benchmark): against the full path's force at a/h = 8 (2,638.0 N,
    # docs/validation.md) the grid with corrections within 0.6 % (measured
    # -0.40 %: the a/h = 8 reference is itself about 0.15 % high), the
    # half-spaces alone 3-5.5 % low (measured -4.19 %)
    row = mod.case(4.0, 10.0 - 10.0 * mod.A, 10.0)
    assert row["auto"] == "multiscale"
    assert abs(row["P_multiscale"] / 2638.0 - 1.0) < 0.006
    assert -0.055 < row["P_halfspace"] / 2638.0 - 1.0 < -0.03
    assert 0.0 < row["P_full"] / 2638.0 - 1.0 < 0.03


def test_interior_stress_points_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b_is", BENCH / "interior_stress_points.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    # 400 points below the Hertz contact, both meshes at h = 0.2 mm (a/h = 2.8):
    # measured 62 near / 338 deep, the largest shear 0.299 p0 at 0.44 a (Hertz:
    # 0.310 p0 at 0.481 a), 3.0e-2 p0 from Hamilton's field at the deep points
    row = mod.one(400, fine_size=0.2, repeat=1)
    assert row["near"] > 0 and row["deep"] > 0 and row["near"] + row["deep"] == 400
    assert 0.27 < row["tau_max_p0"] < 0.34 and 0.3 < row["tau_max_depth_a"] < 0.7, row
    assert row["hamilton_deep_p0"] < 0.05, row
    for k in ("wall_s", "cpu_s", "near_wall_us", "deep_wall_us", "peak_rss_mb"):
        assert row[k] > 0, k


def test_grid_stress_points_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b_gs", BENCH / "grid_stress_points.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    # 6 depths below the 60 x 60 cells of the example's grid: the largest Tresca
    # stress of the box within 3 % of Hertz's 0.310 p0 (measured 0.303 with
    # depths 0.6a apart; the tangential load of the later steps raises it)
    row = mod.one(22_000, repeat=1)
    assert row["points"] == row["cells"] * row["depths"] and row["depths"] >= 5
    assert 0.30 < row["tresca_max_p0"] < 0.32, row
    for k in ("wall_s", "cpu_s", "scattered_wall_s", "per_point_us", "peak_rss_mb"):
        assert row[k] > 0, k


def test_rolling_contact_cases_benchmark_smoke(capsys):
    """One run of 4 creep-force points: the curve at CONTACT's creepages
    within 1.5e-4 of its values (the same discretization) and the spin case
    with CONTACT's offset at its -0.6074."""
    spec = importlib.util.spec_from_file_location("b_rc", BENCH / "rolling_contact_cases.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = mod.main(["--repeat", "1", "--points", "4"])
    got, want = out["curve"]["0.0004"]
    assert abs(got - want) < 1.5e-4
    assert abs(out["spin_44"][1] + 0.6074) < 1e-4
    assert all(r["wall"] > 0 and r["cpu"] > 0 for r in out["rows"].values())
    assert "CONTACT -0.2588" in capsys.readouterr().out


def test_fem_sparse_solvers_benchmark_smoke(monkeypatch):
    """benchmarks/fem_sparse_solvers.py on a tiny box: bemcontact's solver
    (the Schur complement of the contact-last CHOLMOD factor) and SciPy's
    SuperLU (a solve per contact dof) give the same flexibility; a unit
    force on the top corner of a clamped column moves it by a positive
    amount."""
    pytest.importorskip("skfem")
    pytest.importorskip("cvxopt")
    monkeypatch.syspath_prepend(str(BENCH))
    spec = importlib.util.spec_from_file_location("b_fem", BENCH / "fem_sparse_solvers.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    a, b = mod.one("schur", 3, 4), mod.one("splu", 3, 4)
    assert a["dofs"] == 3 * 16 * 5 and a["contact_nodes"] == 16
    assert a["F00"] > 0
    assert a["F00"] == pytest.approx(b["F00"], rel=1e-10)


def test_fem_bem_two_cubes_benchmark_smoke():
    """The side-by-side benchmark at N = 4: the FEM and the BEM lower cube
    carry the same force within 0.5 % (measured +0.24 %: the paper's
    dissimilar cubes, docs/validation.md, converge together under
    refinement)."""
    spec = importlib.util.spec_from_file_location("b_fb", BENCH / "fem_bem_two_cubes.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    bem, fem = mod.one(4, "bem"), mod.one(4, "fem")
    assert bem["converged"] and fem["converged"]
    assert fem["unknowns"] > bem["unknowns"]
    assert abs(fem["normal_force"] / bem["normal_force"] - 1.0) < 0.005

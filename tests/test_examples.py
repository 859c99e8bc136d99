"""Examples are tests: each asserts its key number."""

from __future__ import annotations

import importlib.util
import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("element_type", ["quad4", "quad8"])
def test_compress_cube_reaction_equals_EA_strain(element_type):
    """Uniaxial compression is a uniform-stress state, which the elements
    represent exactly: the reaction must equal E A delta / L = 400 N to
    quadrature precision (1e-8, the uniform-stress tolerance)."""
    r = load("compress_cube").run(divisions=2, element_type=element_type)
    assert r["exact_N"] == 400.0
    assert r["reaction_N"] == pytest.approx(400.0, rel=1e-8)


def test_compress_cube_script_prints_the_comparison():
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / "compress_cube.py")], capture_output=True, text=True,
        check=True,
    ).stdout
    assert "reaction on top face 400" in out and "E * A * strain" in out


# ---------------------------------------------------------------- two cubes (problem files)

#: normal_force measured for these exact meshes (6^3 / 5^3 quad4, mortar
#: frame).  A regression check: 1e-3 relative leaves room for quadrature and
#: BLAS round-off across machines but catches any change of formulation; the
#: physics is asserted by the validation tests.
TWO_CUBES = {
    "similar": {"normal_force": 412.178, "iterations": (1, 1), "state": "stick"},
    "dissimilar": {"normal_force": 834.137, "iterations": (5, 7), "state": "slip"},
}


def _run(problem_file: str, out) -> dict:
    """``bemcontact run examples/<problem_file> --out <out> --quiet`` (must
    succeed); its summary.json."""
    subprocess.run(
        [sys.executable, "-m", "bemcontact", "run", str(EXAMPLES / problem_file),
         "--out", str(out), "--quiet"],
        check=True, capture_output=True, text=True,
    )
    return json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def two_cubes_out(tmp_path_factory):
    base = tmp_path_factory.mktemp("two_cubes")
    for case in TWO_CUBES:
        _run(f"two_cubes_{case}.toml", base / case)
    return base


@pytest.mark.parametrize("case", list(TWO_CUBES))
def test_two_cubes_normal_force(two_cubes_out, case):
    s = json.loads((two_cubes_out / case / "summary.json").read_text())
    want = TWO_CUBES[case]
    assert s["converged"] is True
    assert s["normal_force"] == pytest.approx(want["normal_force"], rel=1e-3), s["normal_force"]
    lo, hi = want["iterations"]
    assert lo <= s["newton_iterations"] <= hi, s["newton_iterations"]
    # similar: all stick; dissimilar: (nearly) all slip
    frame = s["states"]["frame"]
    assert frame[want["state"]] >= 0.9 * sum(frame.values()), frame


def test_two_cubes_figure_script_writes_a_png(two_cubes_out):
    png = two_cubes_out / "figure1.png"
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / "two_cubes_figure.py"), str(two_cubes_out / "similar"),
         str(two_cubes_out / "dissimilar"), str(png)],
        check=True, capture_output=True, text=True,
    ).stdout
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"wrote {png}" in out
    # key numbers: the nearly rigid upper cube hardly moves sideways; the
    # lower cube's lateral expansion is of the order nu * strain * width
    v = {
        k.strip(): float(x.split()[0])
        for k, x in (line.split("=") for line in out.splitlines() if "=" in line)
    }
    assert v["dissimilar_upper_max_abs_uy"] < 1e-3 * v["dissimilar_lower_max_abs_uy"]
    assert 1e-4 < v["similar_lower_max_abs_uy"] < 1e-2
    # Figure 1a: the curves coincide (sticking interface) up to the weak tie's
    # discretization error and the linear interpolation onto the line
    # (measured 9.1e-7 mm, 6e-4 of |u_y|); Figure 1b: they differ by |u_y|
    assert v["similar_max_abs_uy_difference"] < 2e-3 * v["similar_lower_max_abs_uy"]
    assert v["dissimilar_max_abs_uy_difference"] > 0.9 * v["dissimilar_lower_max_abs_uy"]


# ---------------------------------------------------------------- frame rules, refinement tables


def test_patch_test_frame_rules_example():
    """docs/frame.md's table: the mortar rule passes the patch test to the
    BEM floor (1e-8, see tests/validation/test_contact_patch.py), the
    collocation rule fails it (measured pressure error 1.7 on this pair)."""
    m = load("patch_test_frame_rules")
    pair = "gmsh tri3 / quad4 6x6"
    mortar = m.run(pair, "mortar")
    colloc = m.run(pair, "collocation")
    assert mortar["condition"] <= 1e-12 and mortar["pressure_error"] <= 1e-8
    assert mortar["normal_force"] == pytest.approx(40.0, rel=1e-9)
    assert colloc["condition"] > 1e-2 and colloc["pressure_error"] > 0.1


def test_two_cubes_refinement_example():
    """docs/validation.md's refinement table, coarsest row (n = 3): the
    similar pair sticks everywhere and matches the column within the 5e-4 of
    the validation test; the dissimilar pair slips everywhere but the centre
    node and stays inside the 800-1077 N bounds."""
    m = load("two_cubes_refinement")
    sim = m.row(3, 1.0e4)
    assert sim["stick"] == sim["frame_nodes"] == 9
    assert sim["normal_force"] == pytest.approx(sim["column_force"], rel=5e-4)
    dis = m.row(3, 1.0e8)
    assert (dis["stick"], dis["slip"], dis["stick_extent"]) == (1, 8, 0.0)
    assert 800 <= dis["normal_force"] <= 1077


# ---------------------------------------------------------------- sphere on block


def test_cattaneo_mindlin_example(tmp_path):
    """h = 0.1 mm (11 elements across the contact): stick radius within 10 %
    of Cattaneo–Mindlin (measured -6.1 %, -1.9 % at h = 0.05 in
    docs/validation.md) and the loop energy within 10 % of
    Mindlin–Deresiewicz (measured -3.8 %, of which -1.7 % is the 8-increment
    polygon's quadrature); both figures written."""
    r = load("cattaneo_mindlin").run(tmp_path)
    assert r["stick_radius_mm"] == pytest.approx(r["stick_radius_exact_mm"], rel=0.10)
    assert r["loop_energy_Nmm"] == pytest.approx(r["loop_energy_exact_Nmm"], rel=0.10)
    assert r["newton_iterations"] <= 15 * 20
    for name in ("profiles.png", "fretting_loop.png"):
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"


# ---------------------------------------------------------------- Hertz problem file


def test_hertz_sphere_on_block_problem_file(tmp_path):
    """examples/hertz_sphere_on_block.toml (gmsh-generated cap and graded
    block from the problem file) is docs/validation.md's Hertz case at
    h = 0.1 mm, so it must reproduce that table's row: force 2646.85 N
    (1e-3: quadrature and BLAS round-off across machines, as for the two
    cubes), peak pressure within 3 % of Hertz at the computed force (the
    Hertz tier; +0.69 % in the table) and the fitted contact radius
    +2.3 % (±1 %: at this coarse h the least-squares fit is rough; it falls
    to 0.21 % at h = 0.05, which the validation test asserts)."""
    from bemcontact.output.read import read_csv
    from bemcontact.validation.reference.contact import effective_modulus, hertz

    out = tmp_path / "hertz"
    s = _run("hertz_sphere_on_block.toml", out)
    assert s["converged"] is True
    P = s["normal_force"]
    assert P == pytest.approx(2646.85, rel=1e-3)
    h = hertz(P, 10.0, effective_modulus(210e3, 0.3, 210e3, 0.3))
    f = read_csv(out / "frame.csv")
    assert f["pressure"].max() == pytest.approx(h.peak_pressure, rel=0.03)
    r = np.hypot(f["x"], f["y"])
    inner = r < 0.9 * h.contact_radius
    c1, c0 = np.polyfit(r[inner] ** 2, f["pressure"][inner] ** 2, 1)
    assert np.sqrt(-c0 / c1) / h.contact_radius - 1 == pytest.approx(0.023, abs=0.01)
    # the frame's normal is z (frame on the flat block): the resultant of the
    # frame pressures is the normal force (flat interface, see docs)
    assert np.sum(f["weight"] * f["pressure"]) == pytest.approx(P, rel=1e-9)
    # the default stresses: the block's largest Tresca stress on its depth
    # profile is Johnson's 0.310 p0 at 0.481a within 1.5 % and 0.03a
    # (docs/validation.md: 0.3087 p0 at 0.478a at this h)
    prof = next(x for x in s["stresses"]["fields"]
                if x["body"] == "block" and x["label"] == "profile")
    tau = prof["maximum"]["tresca"]
    assert tau["value"] == pytest.approx(0.3100 * h.peak_pressure, rel=0.015)
    assert abs(-tau["point"][2] - 0.4809 * h.contact_radius) < 0.03 * h.contact_radius
    assert (out / "stresses_block.png").is_file() and (out / "stresses_sphere.png").is_file()


def test_thrust_bearing_ball_assembly(tmp_path):
    """examples/thrust_bearing_ball.toml, an assembly (a ball between two
    washers, three gmsh meshes, two [[contact]] pairs): both contacts carry
    the regression force 675.40 N (1e-3, as for the two cubes) and the same
    force to 1e-6 (the problem is symmetric about the ball's equator up to
    the two washers' meshes); each contact's peak pressure is within 3 % of
    Hertz (R = 5 mm on a flat) at its force (measured +0.65 %) and its
    frame's pressures resolve its force (1e-9); the upper washer's reaction
    is the load to the collocation accuracy of its face (0.5 %, measured
    0.15 %); the run writes each pair's files and figure."""
    from bemcontact.output.read import read_csv
    from bemcontact.validation.reference.contact import effective_modulus, hertz

    out = tmp_path / "bearing"
    s = _run("thrust_bearing_ball.toml", out)
    assert s["converged"] is True
    pairs = s["pairs"]
    assert [p["bodies"] for p in pairs] == [["lower", "ball"], ["ball", "upper"]]
    forces = [p["normal_force"] for p in pairs]
    assert forces == pytest.approx([675.40, 675.40], rel=1e-3)
    assert forces[1] == pytest.approx(forces[0], rel=1e-6)
    load = -s["reactions"]["upper"]["zmax"][2]
    assert load == pytest.approx(forces[0], rel=5e-3)
    estar = effective_modulus(210e3, 0.3, 210e3, 0.3)
    for p, P in zip(pairs, forces):
        f = read_csv(out / f"{p['files']}_frame.csv")
        assert f["pressure"].max() == pytest.approx(hertz(P, 5.0, estar).peak_pressure, rel=0.03)
        assert np.sum(f["weight"] * f["pressure"]) == pytest.approx(P, rel=1e-9)
        assert (out / f"{p['files']}_frame_tractions.png").is_file()


def test_block_from_mesh_file(tmp_path):
    """examples/block_from_mesh_file.toml (a gmsh .msh body with named
    physical groups against a generated box): converges, the normal force is
    the regression value 228.347 N (1e-3, as for the two cubes), the frame's
    resultant equals the summary's contact force (1e-9: both are sums of the
    same weighted pressures) and the base's support reaction balances it to
    collocation accuracy (2e-3, as asserted for the two cubes)."""
    from bemcontact.output.read import read_csv

    out = tmp_path / "block"
    s = _run("block_from_mesh_file.toml", out)
    assert s["converged"] is True
    P = s["normal_force"]
    assert P == pytest.approx(228.347, rel=1e-3)
    f = read_csv(out / "frame.csv")
    assert np.sum(f["weight"] * f["pressure"]) == pytest.approx(P, rel=1e-9)
    assert s["reactions"]["base"]["bottom"][2] == pytest.approx(P, rel=2e-3)
    assert s["states"]["frame"]["open"] == 0


def test_make_block_mesh_script_writes_the_committed_mesh(tmp_path):
    """examples/meshes/make_block_mesh.py regenerates block.msh: the same
    regions with the same areas (4, 4, 8: exact for the flat faces, to
    rounding), a closed outward surface, and element size 0.25 (edges within
    the gmsh size band 0.15-0.3 the committed file shows)."""
    out = tmp_path / "block.msh"
    subprocess.run([sys.executable, str(EXAMPLES / "meshes" / "make_block_mesh.py"), str(out)],
                   check=True, capture_output=True, text=True)
    import bemcontact as bc

    for path in (out, EXAMPLES / "meshes" / "block.msh"):
        m = bc.read_mesh(path).check()
        q = m.quality()
        areas = {name: q["area"][els].sum() for name, els in m.regions.items()}
        assert areas == pytest.approx({"bottom": 4.0, "top": 4.0, "sides": 8.0}, rel=1e-12)
        assert 0.15 <= q["min_edge"].min() and q["max_edge"].max() <= 0.3


def test_cattaneo_mindlin_multiscale_example(tmp_path):
    """examples/cattaneo_mindlin_multiscale.toml: solved on the contact grid,
    P = 2,633.6 N (a regression check to 1e-3, as for the two cubes; its
    accuracy against the full path is tests/unit/multiscale's), the platen's
    396 N carried to 1e-9 along x (the lateral force, which the held y
    leaves free, is the coarse flat-triangle sphere's asymmetry: measured
    0.026 N, asserted 1e-4 of Q), and the stick radius (the stick cells' area) within
    1 % of Mindlin's for that P (measured +0.61 %)."""
    s = _run("cattaneo_mindlin_multiscale.toml", tmp_path / "out")
    assert s["method"]["used"] == "multiscale"
    last = s["steps"][-1]
    P = last["normal_force"]
    assert P == pytest.approx(2633.59, rel=1e-3)
    assert last["contact_force"][0] == pytest.approx(-396.0, rel=1e-9)
    assert abs(last["contact_force"][1]) < 1e-4 * 396.0
    E_star = 210e3 / (2.0 * (1.0 - 0.3**2))
    a = (3.0 * P * 10.0 / (4.0 * E_star)) ** (1.0 / 3.0)
    c_exact = a * (1.0 - 396.0 / (0.3 * P)) ** (1.0 / 3.0)
    h = s["grid"]["cell_size"][0]
    c = np.sqrt(last["cells"]["stick"] * h * h / np.pi)
    assert c == pytest.approx(c_exact, rel=0.01)


def test_two_indenters_multiscale_example(tmp_path):
    """examples/two_indenters_multiscale.toml: an assembly on the contact
    grid, one grid per pair coupled through the block, in 4 increments.
    P = 2,600.6 N and 1,371.1 N (a regression check to 1e-3, as for the two cubes; the
    coupling's accuracy is tests/unit/multiscale/test_assembly.py's), each
    pair's files under its stem and every body's once, the sweeps settled
    (every step's coupling check holds)."""
    out = tmp_path / "out"
    s = _run("two_indenters_multiscale.toml", out)
    assert s["method"]["used"] == "multiscale"
    P = [p["steps"][-1]["normal_force"] for p in s["pairs"]]
    assert P == [pytest.approx(2600.64, rel=1e-3), pytest.approx(1371.14, rel=1e-3)]
    # each indenter pulled toward the other (the block's surface moves toward
    # each contact under the other's load)
    fx = [p["steps"][-1]["contact_force"][0] for p in s["pairs"]]
    assert fx[0] > 0.0 > fx[1]
    assert [p["files"] for p in s["pairs"]] == ["block+left", "block+right"]
    for p in s["pairs"]:
        check = p["steps"][-1]["verification"]["coupling"]
        assert check["worst"] <= check["tolerance"]
        assert (out / f"{p['files']}_grid.csv").is_file()
    assert [c["body"] for c in s["couplings"]] == ["block", "block"]
    assert s["sweeps"][-1] <= 0.01 < s["sweeps"][0]
    assert all((out / f"{b}.vtu").is_file() for b in ("block", "left", "right"))


def test_rolling_ball_multiscale_example(tmp_path):
    """examples/rolling_ball_multiscale.toml: steady rolling on the contact
    grid.  F_x = 64.32 N (a regression check to 1e-3, as for the two cubes;
    the rolling physics is tests/unit/multiscale/test_rolling.py's), opposite
    to the creepage and below mu F_n, no lateral force without lateral
    creepage or spin (to 3e-5 of mu F_n: the coarse meshes are not symmetric
    about y = 0, and their free surfaces' data enter the corrections;
    measured -0.0084 N = 1.1e-5 mu F_n, on the 0.1 mm meshes of the Hertz
    example at zero creepage 1e-6), and adhesion ahead of slip."""
    s = _run("rolling_ball_multiscale.toml", tmp_path / "out")
    roll = s["steps"][-1]["rolling"]
    fx, fy = roll["creep_force"]
    assert fx == pytest.approx(64.32, rel=1e-3)
    assert 0.0 < roll["creep_force_ratio"][0] < 1.0
    assert abs(fy) < 3e-5 * 0.3 * s["steps"][-1]["normal_force"]
    assert roll["adhesion_area"] > roll["slip_area"] > 0.0
    assert roll["frictional_power"] == pytest.approx(1000.0 * roll["frictional_work_per_distance"])
    table = np.genfromtxt(tmp_path / "out" / "grid.csv", delimiter=",", names=True)
    stick, slip = table["state"] == 1, table["state"] == 2
    assert table["x"][stick].mean() > table["x"][slip].mean()
    assert np.all(table["power_density"][slip] >= 0.0)

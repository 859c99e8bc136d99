"""The peak-memory estimate (contact/memory.py) and the refusal of a solve
that cannot fit."""

import re
import warnings

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.contact import memory
from bemcontact.bem.compressed import compressed_fraction

from .test_problem import _problem


def test_estimate_follows_the_arrays_of_the_solve():
    """Two blocks (dense): each condensation phase holds the system matrix,
    the dense G columns of the contact dofs, the right-hand-side block
    (kept as the body's response) and the contact mass's Cholesky factor;
    the second body's phase adds the first body's response; Newton holds
    K, the responses and the closed block with its LU and a copy of K's
    rows.  Checked term by term against the sizes."""
    prob = _problem()
    est = prob.memory_estimate()
    frame = prob.frame
    m3 = 3 * int(frame.active.sum())
    kept = 0.0
    for a, b in enumerate(prob.bodies):
        N3 = 3 * b.discretization.n_points
        n3 = 3 * frame.nodes(a).size
        ctl = len(b.controls(b.boundary_conditions))
        response = N3 * (1 + m3 + ctl)
        want = 8 * ((N3 + 6) ** 2 + N3 * n3 + response + (n3 // 3) ** 2
                    + 2 * n3 * min(2048, N3) + min(2048, N3) * m3) + kept
        assert est.phases[f"condensation of {b.name}"] == pytest.approx(want, rel=1e-12)
        kept += 8 * response
    # K, the closed block, its LU and the copy of K rows, and the coarse Ks
    assert est.phases["newton"] == pytest.approx(8 * (4 + 1 / 15) * (m3 + 12) ** 2 + kept,
                                                 rel=1e-12)
    assert est.peak == pytest.approx(est.process + max(est.phases.values()), rel=1e-12)
    assert 0 < est.process < est.peak
    assert est.text().endswith(")") and "GB" in est.text()


def test_more_states_and_compressed_bodies_change_the_estimate():
    prob = _problem()
    one = prob.memory_estimate()
    steps = [bc.LoadStep(label="P"), bc.LoadStep(label="again")]
    two = prob.memory_estimate(steps=steps)
    b = prob.bodies[0]
    grow = 8 * 3 * b.discretization.n_points  # one more state column in body 1's block
    got = two.phases[f"condensation of {b.name}"] - one.phases[f"condensation of {b.name}"]
    assert got == pytest.approx(grow, rel=1e-12)
    # compressed operators: a fraction of the dense matrix (system and H-LU)
    h = bc.SolverOptions(linear=bc.LinearSolverOptions(method="hmatrix"))
    assert prob.memory_estimate(h).phases[f"condensation of {b.name}"] != one.phases[
        f"condensation of {b.name}"]
    assert compressed_fraction(4974) == pytest.approx(0.264, rel=1e-9)
    assert compressed_fraction(100) == 1.0
    f = [compressed_fraction(n) for n in (3000, 10000, 30000, 100000)]
    assert np.all(np.diff(f) < 0)


def test_a_solve_that_cannot_fit_is_refused_before_it_starts(monkeypatch):
    """Available memory below the estimate / 1.25: a one-line ConfigError
    naming the estimate and the fix; just below the estimate: a warning."""
    prob = _problem()
    peak = prob.memory_estimate().peak
    monkeypatch.setattr("bemcontact.contact.memory.machine_memory", lambda: (peak / 2, peak / 2))
    with pytest.raises(bc.ConfigError, match=r"the solve needs about .* GB .*, more than this "
                       r"machine's .* [MG]B of available memory; use compressed operators") as exc:
        prob.solve()
    assert "\n" not in str(exc.value)
    monkeypatch.setattr("bemcontact.contact.memory.machine_memory", lambda: (2 * peak, peak))
    with pytest.warns(bc.ResourceLimitWarning, match="close to this machine's"):
        res = prob.solve()
    assert res.converged
    monkeypatch.setattr("bemcontact.contact.memory.machine_memory", lambda: (8 * peak, 4 * peak))
    with warnings.catch_warnings():
        warnings.simplefilter("error", bc.ResourceLimitWarning)
        prob.solve()


def test_least_body_bytes_is_the_compressed_matrix_and_its_factors():
    """At a measured size (4,974 nodes: compressed A = 0.264 of the dense
    matrix) the least storage is A and its H-LU, 2 x 0.264 x (3N)^2 doubles;
    beyond the largest measured size the fraction stays at its last value."""
    from bemcontact.contact.memory import least_body_bytes

    assert least_body_bytes(4974) == pytest.approx(8 * 2 * 0.264 * (3 * 4974) ** 2, rel=1e-9)
    assert least_body_bytes(500_000) == pytest.approx(8 * 2 * 0.036 * 1.5e6 ** 2, rel=1e-9)


def test_the_frame_build_is_a_phase_from_the_element_counts():
    """The frame phase: FRAME_FAN (sqrt(E_1) + sqrt(E_2))^2 fan triangles of
    36 quadrature points (order 6), each 450 + 48 f k bytes (f frame
    corners, k element nodes); the blocks' contact faces have 16 and 9
    quad4 elements: 2 x 7^2 x 36 x (450 + 48 x 4 x 4) bytes."""
    prob = _problem()
    assert prob.frame_memory() == pytest.approx(2 * 49 * 36 * 1218, rel=1e-12)
    est = prob.memory_estimate()
    assert est.phases["frame"] == pytest.approx(4_297_104, rel=1e-12)
    assert est.peak == pytest.approx(est.process + max(est.phases.values()), rel=1e-12)
    # quadratic triangles: 3 corners x 6 nodes; the quadrature order enters squared
    assert memory.frame_bytes((100, 25), 6, 3) == pytest.approx(2 * 225 * 36 * 1314, rel=1e-12)
    assert memory.frame_bytes((100, 25), 6, 3, order=3) == pytest.approx(
        2 * 225 * 9 * 1314, rel=1e-12)


@pytest.mark.parametrize("n1, n2, element_type", [(21, 16, "quad4"), (21, 16, "tri3")])
def test_the_frame_estimate_bounds_the_measured_build(n1, n2, element_type):
    """tracemalloc's peak of the frame build of two box faces in general
    position (21 x 21 on 16 x 16 elements): between 0.75 and 1 times the
    estimate (measured 113.1 MB of 120.1 for quad4)."""
    import tracemalloc

    lower = bc.ElasticBody(bc.box((0, 0, 0), (2, 2, 1), (n1, n1, 2), element_type),
                           bc.LinearElastic(1e4, 0.3), {"zmin": bc.Fixed()}, name="lower")
    upper = bc.ElasticBody(bc.box((0, 0, 1), (2, 2, 2), (n2, n2, 2), element_type),
                           bc.LinearElastic(1e4, 0.3), {"zmax": bc.Fixed()}, name="upper")
    prob = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.1))
    for b in prob.bodies:
        b.discretization
    tracemalloc.start()
    try:
        prob.frame
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    ratio = peak / prob.frame_memory()
    assert 0.75 < ratio <= 1.0, (peak, prob.frame_memory())


def test_a_frame_that_cannot_fit_is_refused_before_it_is_built(monkeypatch):
    prob = _problem()
    frame = prob.frame_memory()
    monkeypatch.setattr("bemcontact.contact.memory.machine_memory",
                        lambda: (frame / 4, frame / 4))
    monkeypatch.setattr("bemcontact.contact.problem.resident_bytes", lambda: 0.0)
    with pytest.raises(bc.ConfigError, match=r"the solve needs about 0\.00 GB \(at the frame\), "
                       r"more than this machine's [\d.]+ [MG]B of available memory; use coarser or "
                       r"smaller contact surfaces$"):
        prob.solve()
    assert prob._frames is None  # refused before the build


def test_loading_a_problem_file_refuses_a_frame_that_cannot_fit(tmp_path, monkeypatch):
    """load_problem (and so ``check``) builds the frame to check the
    overlap: its estimate is checked first, one line naming the phase."""
    from ..test_cli import problem

    path = problem(tmp_path)
    need = bc.load_problem(path, check_overlap=False).contact_problem().frame_memory()
    monkeypatch.setattr("bemcontact.contact.memory.machine_memory", lambda: (need, need / 4))
    with pytest.raises(bc.ConfigError, match=r"the solve needs about \d\.\d\d GB \(at the "
                       r"frame\), more than this machine's [\d.]+ [MG]B of available memory; use "
                       r"coarser or smaller contact surfaces$") as exc:
        bc.load_problem(path)
    assert str(exc.value).startswith(f"{path}: the solve needs") and "\n" not in str(exc.value)


_UNDER_A_LIMIT = r"""
import resource, sys, warnings
import numpy as np
sys.path.insert(0, {tests!r})
from unit.contact.test_problem import _problem
import bemcontact as bc
from bemcontact.contact import memory
prob = _problem()
est = prob.memory_estimate()
phases = est.peak - est.process
with open("/proc/self/statm") as f:
    size = int(f.read().split()[0]) * resource.getpagesize()
# room for 0.3 of the solve's phases beyond what is mapped now
limit = size + int(0.3 * phases)
resource.setrlimit(resource.RLIMIT_AS, (limit, resource.RLIM_INFINITY))
total, available = memory.machine_memory()
print("available", available, "limit", limit)
try:
    prob.solve()
except bc.ConfigError as exc:
    print("refused:", exc)
"""


def test_an_address_space_limit_is_the_memory_a_solve_may_use(tmp_path):
    """Under ``ulimit -v`` (RLIMIT_AS) the available memory is the room the
    limit leaves, not the machine's: a solve that would fail half-way with
    an out-of-memory error is refused before it starts, in one line naming
    the limit (not compared with the machine's memory, 24 GB, under which
    it would start).  Run in a child process, where the limit can be set."""
    import os
    import subprocess
    import sys

    tests = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = subprocess.run([sys.executable, "-c", _UNDER_A_LIMIT.format(tests=tests)],
                         capture_output=True, text=True, timeout=120,
                         env={**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"})
    assert out.returncode == 0, out.stderr[-2000:]
    lines = out.stdout.splitlines()
    available, limit = float(lines[0].split()[1]), float(lines[0].split()[3])
    assert available < limit < 0.5 * memory.machine_memory()[1], lines
    refused = [x for x in lines if x.startswith("refused:")]
    assert len(refused) == 1, out.stdout
    assert re.search(r"the solve needs about \d\.\d\d GB \(at the [a-z ]+\), more than the "
                     r"[\d.]+ [MG]B that this process's address-space limit \(ulimit -v\) of "
                     r"[\d.]+ GB leaves; use compressed operators", refused[0]), refused[0]


def test_a_control_group_memory_limit_is_read(tmp_path, monkeypatch):
    """A batch scheduler's or a container's share of a node (cgroup v2
    memory.max, v1 memory.limit_in_bytes): the room is the limit less what
    the group uses besides this process's resident memory and its
    reclaimable page cache; "max" (v2) or a limit above the machine's
    memory (v1's unlimited 2^63) is no limit."""
    resident = memory.resident_bytes()
    total = 64e9
    v2 = tmp_path / "v2"
    v2.mkdir()
    (v2 / "memory.max").write_text("8000000000\n")
    (v2 / "memory.current").write_text("3000000000\n")
    (v2 / "memory.stat").write_text("anon 1\ninactive_file 500000000\nactive_file 7\n")
    monkeypatch.setattr(memory, "_cgroup_dirs", lambda: [(str(v2), "v2")])
    [(room, what, kind)] = memory.process_limits(total)[-1:]
    assert kind == "control group" and what == "its control group's memory limit of 8.0 GB"
    assert room == pytest.approx(8e9 - 3e9 + 0.5e9 + resident, rel=0.01)
    (v2 / "memory.max").write_text("max\n")
    assert not [x for x in memory.process_limits(total) if x.kind == "control group"]
    v1 = tmp_path / "v1"
    v1.mkdir()
    (v1 / "memory.limit_in_bytes").write_text("9223372036854771712\n")
    (v1 / "memory.usage_in_bytes").write_text("432353280\n")
    monkeypatch.setattr(memory, "_cgroup_dirs", lambda: [(str(v1), "v1")])
    assert not [x for x in memory.process_limits(total) if x.kind == "control group"]
    (v1 / "memory.limit_in_bytes").write_text("4000000000\n")
    (v1 / "memory.stat").write_text("cache 9\ntotal_inactive_file 1000000000\n")
    [(room, what, kind)] = memory.process_limits(total)[-1:]
    assert kind == "control group" and room == pytest.approx(4e9 - 432353280 + 1e9 + resident, rel=0.01)
    # the limit that gives the available memory is named in messages
    monkeypatch.setattr(memory, "_meminfo", lambda: (total, 20e9))
    total_, available = memory.machine_memory()
    assert available == pytest.approx(room, rel=0.01)
    assert memory.available_text(available) == (
        f"the {available / 1e9:.1f} GB that its control group's memory limit of 4.0 GB leaves")
    assert memory.available_text(20e9) == "this machine's 20.0 GB of available memory"
    # a control group's limit keeps the estimate's margin (going over it ends
    # in the out-of-memory killer, not in a hang)
    assert memory.allowed(available) == pytest.approx(memory.MARGIN * available)

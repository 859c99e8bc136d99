"""Hertz and Cattaneo–Mindlin: bemcontact against Tamaas at the same
contact-zone resolution a/h, in one run.

    python benchmarks/hertz_mindlin_vs_tamaas.py [--a-over-h 12 25]
        [--bem-max-a-over-h 60] [--no-install] [--json FILE]

Installs Tamaas (PyPI ``tamaas``, benchmark-only, AGPL-3.0) into the running
interpreter if it is missing (``--no-install`` refuses instead).  Prints, per
a/h and code, the errors against the analytic solutions and the CPU seconds
(``time.process_time``: all threads of the process) and wall seconds of the
solve, and the bemcontact / Tamaas CPU ratio.

The problems.  bemcontact: ``cases.sphere_on_block`` — a steel hemisphere
(R = 10 mm) on a steel block 20 × 20 × 10 mm, approach 0.03 mm (a ≈ 0.555 mm,
a/R = a/L ≈ 0.055), both surfaces meshed with element size h = a/(a/h) within
1.1 a of the contact point (a ``size_profile``), growing by 0.45 per mm
beyond, μ = 0.3, loading P, Q = 0.02 μP (measures the
finite bodies' compliance), Q = 0.5 μP in 4 increments (2 stall on the
finer meshes).  The whole run is
timed: meshing, BEM assembly and factorization of both bodies, condensation,
and Newton.  Tamaas: the same a/h on a half-space (benchmarks/_tamaas_side.py
explains its set-up: DC-FFT isolated half-space for Hertz, periodic L = 8a for
Cattaneo–Mindlin with ν_T = 0.5 so that it is decoupled like the analytic
solution).

Fairness.  Tamaas solves the half-space problem the analytic formulas
describe; bemcontact solves two finite bodies (what it is for), so its errors
against the half-space formulas include the finite-geometry effects (a/R and
a/L ≈ 0.055) besides discretization, and its cost includes both bodies'
whole surfaces (the boundary mesh grows from h to 2.5 mm away from the
contact).  The block is 36 contact radii wide and 18 deep, so the half-space
idealization is within the stated tolerances (docs/validation.md); the
resolution that matters for both codes, elements (grid cells) per contact
radius, is matched.  At a/h = 25 the default validation grading (fine zone
0.7 mm = 1.26 a, growth 0.3) gives 5,670 + 5,340 nodes, whose whole-surface
condensation does not fit in the machine's 24 GB; the 1.1 a fine zone gives 4,208
+ 3,881.  --bem-max-a-over-h skips bemcontact above a resolution; a solve the
memory estimate says cannot fit is recorded as refused, with the estimate.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import _tamaas_side as tamaas_side  # noqa: E402
from _common import machine_line  # noqa: E402

import bemcontact as bc  # noqa: E402
from bemcontact.contact import law
from bemcontact.validation import cases  # noqa: E402
from bemcontact.bench import peak_rss_mb  # noqa: E402
from bemcontact.validation.reference import contact as ref  # noqa: E402

MU, RATIO, SMALL, APPROACH = 0.3, 0.5, 0.02, 0.03


def bemcontact_side(a_over_h: float) -> dict:
    """Hertz (step P) and Cattaneo–Mindlin (Q = 0.5 mu P) errors of one
    frictional sphere-on-block solve at h = a / a_over_h, and its cost."""
    a_guess = math.sqrt(cases.SphereOnBlock().radius * APPROACH)
    h = a_guess / a_over_h
    s = cases.SphereOnBlock(size_profile=((0.0, h), (1.1 * a_guess, h)), growth=0.45)
    p_guess = ref.hertz_force(APPROACH, s.radius, s.contact_modulus)
    cpu0, wall0 = time.process_time(), time.perf_counter()
    prob = cases.sphere_on_block(h, APPROACH, friction_coefficient=MU, setup=s)
    steps = (
        [bc.LoadStep(label="P")]
        + cases.tangential_steps([SMALL * MU * p_guess], APPROACH, increments=1, label="small")
        + cases.tangential_steps([RATIO * MU * p_guess], APPROACH, increments=4)
    )
    est = prob.memory_estimate(steps=steps)
    try:
        res = prob.solve(steps=steps)
    except bc.ConfigError as exc:  # refused: it cannot fit in this machine's memory
        return {"code": "bemcontact", "a_over_h": a_over_h, "skipped": str(exc),
                "estimated_peak_mb": est.peak / 1e6,
                "nodes": [b.discretization.n_points for b in prob.bodies]}
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    P = res.history[0].normal_force
    hz = ref.hertz(P, s.radius, s.contact_modulus)
    e = cases.hertz_errors(res.history[0].frame, hz)
    Q, U = cases.platen_history(res)
    top = res.history[2]
    P2 = top.normal_force
    hz2 = ref.hertz(P2, s.radius, s.contact_modulus)
    a = hz2.contact_radius
    S = s.tangential_compliance_factor
    d_num = cases.tangential_approach(Q, U, a, S)[2]
    d_exact = ref.cattaneo_mindlin_displacement(Q[2], MU, P2, a, S)
    r, _, qx, w, _ = cases.radial_profile(top.frame)
    inner = r < 0.9 * a
    q_l2 = cases.weighted_l2(qx[inner], ref.cattaneo_mindlin_traction(r[inner], hz2, Q[2], MU), w[inner])
    c_exact = ref.cattaneo_mindlin_stick_radius(a, Q[2], MU, P2)

    def p_dev(frame, hz_):
        """largest |p - p_Hertz| / p0 inside 0.95 a (the measure of the weighted gap's "bump")"""
        rr, pp, *_ = cases.radial_profile(frame)
        inside = rr < 0.95 * hz_.contact_radius
        return float(np.abs(pp[inside] - hz_.pressure(rr[inside])).max() / hz_.peak_pressure)

    nodes = [b.discretization.points.shape[0] for b in prob.bodies]
    return {
        "code": "bemcontact", "a_over_h": hz.contact_radius / h, "h": h,
        "unknowns": 3 * sum(nodes), "nodes": nodes, "frame_nodes": int(prob.frame.n_frame),
        "a_err": e.contact_radius, "p0_err": e.peak_pressure, "p_l2": e.profile_l2,
        "q_ratio": Q[2] / (MU * P2),
        "c_err": cases.stick_radius(top.frame) / c_exact - 1, "q_l2": q_l2,
        "dt_err": d_num / d_exact - 1,
        "p_dev_095": p_dev(res.history[0].frame, hz), "p_dev_095_q": p_dev(top.frame, hz2),
        "newton_iterations": [x.iterations for x in res.steps],
        "factorizations": [x.factorizations for x in res.steps],
        "krylov_iterations": [x.krylov_iterations for x in res.steps],
        "coarse_iterations": [x.coarse_iterations for x in res.steps],
        "active_frame_nodes": int(prob.frame.active.sum()),
        "stick_nodes": int((top.frame.state == law.STICK).sum()),
        "cpu_s": cpu, "wall_s": wall, "timings": res.timings,
        "peak_rss_mb": peak_rss_mb(), "estimated_peak_mb": est.peak / 1e6,
        "estimate_phases_mb": {k: v / 1e6 for k, v in est.phases.items()},
    }


def tamaas_rows(a_over_h: float) -> tuple[dict, dict]:
    R, E, nu = 10.0, 210000.0, 0.3
    E_star = E / (2.0 * (1.0 - nu * nu))
    P = ref.hertz_force(APPROACH, R, E_star)
    hz = tamaas_side.hertz(R, E_star, P, a_over_h, method="dcfft")
    cm = tamaas_side.cattaneo_mindlin(R, E, nu, MU, P, RATIO, a_over_h)
    return hz, cm


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a-over-h", type=float, nargs="+", default=[12.0, 25.0])
    ap.add_argument("--bem-max-a-over-h", type=float, default=60.0)
    ap.add_argument("--no-install", action="store_true")
    ap.add_argument("--json", help="write all rows to this file")
    args = ap.parse_args(argv)
    try:
        if args.no_install:
            tamaas_side.tamaas_info()
        else:
            tamaas_side.ensure_tamaas()
        info = tamaas_side.tamaas_info()
    except (tamaas_side.TamaasMissing, OSError) as exc:
        print(exc, file=sys.stderr)
        return 2
    print(machine_line(f", bemcontact {bc.__version__}, Tamaas {info['version']} (single thread)"))
    rows = []
    for s in args.a_over_h:
        hz, cm = tamaas_rows(s)
        t = {
            "code": "tamaas", "a_over_h": s, "unknowns": cm["n_nodes"] * 3,
            "a_err": hz["a_fit"] / hz["a_exact"] - 1, "p0_err": hz["p0_num"] / hz["p0_exact"] - 1,
            "p_l2": hz["l2_error"], "c_err": cm["c_num"] / cm["c_exact"] - 1,
            "q_l2": cm["q_l2_error"], "dt_err": cm["delta_t_num"] / cm["delta_t_exact"] - 1,
            "cpu_s": hz["cpu_seconds"] + cm["cpu_seconds"],
            "wall_s": hz["wall_seconds"] + cm["wall_seconds"],
            "cpu_search_s": hz["cpu_seconds"] + cm["cpu_seconds_search"],
            "hertz": {k: v for k, v in hz.items() if np.isscalar(v)},
            "cattaneo_mindlin": {k: v for k, v in cm.items() if np.isscalar(v)},
        }
        rows.append(t)
        if s <= args.bem_max_a_over_h:
            b = bemcontact_side(s)
            if "cpu_s" in b:
                b["cpu_ratio"] = b["cpu_s"] / t["cpu_s"]
            rows.append(b)
        else:
            rows.append({"code": "bemcontact", "a_over_h": s, "skipped":
                         f"a/h > --bem-max-a-over-h = {args.bem_max_a_over_h:g}"})
    head = (f"{'code':>10} {'a/h':>5} {'unknowns':>9} {'a err':>7} {'p0 err':>7} {'p L2':>6} "
            f"{'c err':>7} {'q L2':>6} {'dt err':>7} {'CPU s':>8} {'wall s':>7} {'CPU ratio':>9}")
    print(f"\nHertz (step P) and Cattaneo–Mindlin at Q = {RATIO} μP, μ = {MU}; errors vs analytic")
    print(head)
    print("-" * len(head))
    for r in rows:
        if "skipped" in r:
            print(f"{r['code']:>10} {r['a_over_h']:>5.1f}  skipped: {r['skipped']}")
            continue
        ratio = f"{r['cpu_ratio']:.0f}" if "cpu_ratio" in r else ""
        print(f"{r['code']:>10} {r['a_over_h']:>5.1f} {r['unknowns']:>9d} {r['a_err']:>+7.2%} "
              f"{r['p0_err']:>+7.2%} {r['p_l2']:>6.1%} {r['c_err']:>+7.1%} {r['q_l2']:>6.1%} "
              f"{r['dt_err']:>+7.1%} {r['cpu_s']:>8.2f} {r['wall_s']:>7.2f} {ratio:>9}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Stresses inside a body: 10,000 and 100,000 points below the Hertz contact.

    python benchmarks/interior_stress_points.py [--sizes 10000 100000] [--json FILE]

The Hertz case of examples/hertz_sphere_on_block.toml
(``bemcontact.validation.cases.sphere_on_block(0.1)``: a steel hemisphere,
R = 10 mm, pressed 0.03 mm into a steel block, frictionless, elements of
h = 0.1 mm within 0.7 mm of the contact, a ≈ 0.556 mm) is solved once per
process; then the block's stresses by the full path (``ContactResult.stresses``,
i.e. Somigliana's identity, ``bemcontact.bem.interior.interior_stresses``) at N
points drawn uniformly (seed 0) in the box |x|, |y| <= 1.5 a,
0.01 a <= depth <= 2 a below the contact.  Timed, each the median of
three calls: all N points in one call, and apart the points within one
element of the surface (depth < h: the nearly singular quadrature) and the
deeper ones, as wall and CPU (all threads) seconds.  Each size runs in its own
process (its peak RSS is that size's).  Printed with them, as a check of the
field: the largest shear stress (σ1 − σ3)/2 found in the box against Hertz's
0.310 p0 at 0.481 a (ν = 0.3; p0 and a from the computed force), and the
largest difference of that shear stress from Hamilton's half-space field
over the deep points, in p0.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _common import machine_line, run_one  # noqa: E402

FINE = 0.1  # mm, the example's element size near the contact
SEED = 0
REPEAT = 3


def _timed(f, repeat: int) -> tuple[float, float]:
    """Median wall and CPU seconds of ``repeat`` calls of ``f``."""
    wall, cpu = [], []
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        f()
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    return statistics.median(wall), statistics.median(cpu)


def one(n: int, fine_size: float = FINE, repeat: int = REPEAT) -> dict:
    """The Hertz case at ``fine_size`` solved, then the stresses at ``n``
    points below its contact timed: all together, the near-surface ones and
    the deep ones (medians of ``repeat`` calls)."""
    import bemcontact as bc
    from bemcontact.bench import peak_rss_mb
    from bemcontact.halfspace.measure import tresca
    from bemcontact.validation.cases import SphereOnBlock, sphere_on_block
    from bemcontact.validation.reference import hamilton_sliding_sphere_stresses, hertz

    setup = SphereOnBlock()
    t0 = time.perf_counter()
    result = sphere_on_block(fine_size).solve(bc.SolverOptions(progress=False))
    solve_s = time.perf_counter() - t0
    hz = hertz(result.normal_force, setup.radius, setup.contact_modulus)
    a, p0 = hz.contact_radius, hz.peak_pressure
    rng = np.random.default_rng(SEED)
    points = rng.uniform([-1.5 * a, -1.5 * a, -2.0 * a], [1.5 * a, 1.5 * a, -0.01 * a], (n, 3))
    near = -points[:, 2] < fine_size
    stresses = result.stresses("block", points)  # the checks, and the field below
    wall, cpu = _timed(lambda: result.stresses("block", points), repeat)
    parts = {}
    for name, sel in (("near", near), ("deep", ~near)):
        if sel.any():
            w, c = _timed(lambda: result.stresses("block", points[sel]), repeat)
            parts[name] = (1e6 * w / sel.sum(), 1e6 * c / sel.sum())
        else:
            parts[name] = (float("nan"), float("nan"))
    tau = tresca(stresses)
    top = int(np.argmax(tau))
    depth = np.column_stack([points[:, :2], -points[:, 2]])
    ref = tresca(hamilton_sliding_sphere_stresses(depth[~near], a, p0, 0.0, setup.poisson_ratio))
    return {
        "n": n, "fine_size": fine_size, "near": int(near.sum()), "deep": int((~near).sum()),
        "elements": int(result.bodies[0].discretization.mesh.n_elements),
        "solve_s": solve_s, "wall_s": wall, "cpu_s": cpu,
        "near_wall_us": parts["near"][0], "near_cpu_us": parts["near"][1],
        "deep_wall_us": parts["deep"][0], "deep_cpu_us": parts["deep"][1],
        "tau_max_p0": float(tau[top] / p0), "tau_max_depth_a": float(-points[top, 2] / a),
        "hamilton_deep_p0": float(np.abs(tau[~near] - ref).max() / p0) if (~near).any() else 0.0,
        "peak_rss_mb": peak_rss_mb(),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000])
    ap.add_argument("--json", help="write all rows to this file")
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(one(args.one)))
        return 0
    print(machine_line(f", medians of {REPEAT} calls"))
    print("\n| points | near / deep | wall s | CPU s | near µs/point wall (CPU) | "
          "deep µs/point wall (CPU) | τmax/p0 at depth/a | Hamilton, deep | peak MB |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    rows = []
    for n in args.sizes:
        r = run_one(__file__, n)
        rows.append(r)
        print(f"| {n:,} | {r['near']:,} / {r['deep']:,} | {r['wall_s']:.2f} | {r['cpu_s']:.2f} | "
              f"{r['near_wall_us']:.0f} ({r['near_cpu_us']:.0f}) | "
              f"{r['deep_wall_us']:.0f} ({r['deep_cpu_us']:.0f}) | "
              f"{r['tau_max_p0']:.3f} at {r['tau_max_depth_a']:.2f} | "
              f"{r['hamilton_deep_p0']:.1e} p0 | {r['peak_rss_mb']:.0f} |", flush=True)
    print(f"\n(the Hertz solve, once per process: {rows[0]['solve_s']:.1f} s; "
          f"{rows[0]['elements']:,} block elements; Hertz: τmax = 0.310 p0 at 0.481 a)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine_line(), "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Subsurface stresses of the half-space on depth layers: 1,000,000 points.

    python benchmarks/halfspace_stress_layers.py [--cells 100] [--depths 100]

Random tractions on a cells × cells grid (`bemcontact.halfspace.HalfSpaceStress`),
the six stress components below every cell centre at `depths` depths (100 × 100
× 100 = 1e6 points by default), by FFT per layer.  Stages timed separately: the
kernels alone (`stress_blocks` at every depth: the corner functions on the
2n_x × 2n_y lattice, differenced and combined), the whole layered evaluation
with all three traction components and with the pressure only (the tangential
kernels skipped), and the direct sum (`HalfSpaceStress.at`) on a sample of
points, extrapolated to the same count.  One run each; prints a markdown table
with the machine, the commit and the peak resident memory.
"""

from __future__ import annotations

import argparse
import pathlib
import resource
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import machine_line  # noqa: E402

from bemcontact.halfspace import Grid, HalfSpaceStress, stress_blocks  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=100, help="cells along each side")
    ap.add_argument("--depths", type=int, default=100, help="number of depth layers")
    ap.add_argument("--direct", type=int, default=200, help="points of the direct-sum sample")
    args = ap.parse_args()
    n, h, nu = args.cells, 1.0 / args.cells, 0.3
    grid = Grid.centred(n, n, h, h)
    depths = np.linspace(0.5 * h, 1.0, args.depths)
    rng = np.random.default_rng(0)
    t = rng.standard_normal((grid.size, 3))
    field = HalfSpaceStress(grid, nu)
    points = grid.size * depths.size

    rows = []
    start = time.perf_counter()
    for z in depths:
        stress_blocks(n, n, h, h, z, nu)
    rows.append(("kernels only (stress_blocks per depth)", time.perf_counter() - start, points))

    start = time.perf_counter()
    layers = field.layers(t, depths)
    rows.append(("layers, 3 traction components", time.perf_counter() - start, points))

    pressure = t.copy()
    pressure[:, :2] = 0.0
    start = time.perf_counter()
    field.layers(pressure, depths)
    rows.append(("layers, pressure only", time.perf_counter() - start, points))

    pick = rng.choice(points, size=min(args.direct, points), replace=False)
    k, cell = np.divmod(pick, grid.size)
    sample = grid.centres[cell]
    sample[:, 2] = depths[k]
    start = time.perf_counter()
    direct = field.at(sample, t)
    elapsed = time.perf_counter() - start
    rows.append((f"direct sum, {pick.size} points, extrapolated", elapsed * points / pick.size,
                 points))
    diff = np.abs(layers.reshape(depths.size, grid.size, 6)[k, cell] - direct).max()

    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"{n} x {n} cells x {depths.size} depths = {points:,} points, {machine_line()}, "
          f"peak RSS {peak_mb:.0f} MB; layers vs direct: max difference "
          f"{diff / np.abs(direct).max():.1e} of the largest stress\n")
    print("| stage | time s | µs per point |")
    print("|---|---:|---:|")
    for name, seconds, count in rows:
        print(f"| {name} | {seconds:.2f} | {1e6 * seconds / count:.2f} |")


if __name__ == "__main__":
    main()

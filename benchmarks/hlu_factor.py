"""H-LU of the compressed system against the dense LU, by size.

    python benchmarks/hlu_factor.py [--nodes 1278 2094 3102 5694] [--eps 1e-7] [--leaf 96]

For the linear-field cube of `bemcontact bench one-body` (about N functional
nodes, quad4, mixed conditions): H-matrix build, H-LU factorization, solution
of 300 right-hand sides with one refinement step, memory of A and of its
factors against the dense matrix, the residuals before and after refinement,
and `scipy.linalg.lu_factor` on a random matrix of the same size (the dense
path's LU). One process per size, one run each (the larger sizes take
minutes); prints a markdown table.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import machine_line  # noqa: E402

ONE = """
import json, sys, time
import numpy as np, scipy.linalg
from bemcontact.bench import hlu_factor
rec = hlu_factor(int(sys.argv[1]), eps=float(sys.argv[2]), leaf_size=int(sys.argv[3]))
n = rec["unknowns"]
if n <= 20000:
    a = np.random.default_rng(0).standard_normal((n, n))
    t = time.perf_counter(); scipy.linalg.lu_factor(a, overwrite_a=True, check_finite=False)
    rec["dense_lu_s"] = time.perf_counter() - t
print(json.dumps(rec))
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=int, nargs="+", default=[1278, 2094, 3102, 5694])
    ap.add_argument("--eps", type=float, default=1e-7)
    ap.add_argument("--leaf", type=int, default=96, help="leaf size (the condensation's default)")
    args = ap.parse_args()
    rows = []
    for n in args.nodes:
        t = time.perf_counter()
        out = subprocess.run([sys.executable, "-c", ONE, str(n), str(args.eps), str(args.leaf)],
                             check=True, capture_output=True, text=True).stdout
        rec = json.loads(out.strip().splitlines()[-1])
        rows.append(rec)
        print(f"# {n}: {time.perf_counter() - t:.0f} s", file=sys.stderr)
    print(f"eps {args.eps:g}, leaf {args.leaf}, {machine_line()}, "
          f"{rows[0]['threads']} threads\n")
    print("| nodes | unknowns | build s | H-LU s | dense LU s | H-LU / dense | solve 300 rhs s | A / dense | "
          "factors / dense | max rank | residual | refined | peak RSS MB |")
    print("|---:" * 13 + "|")
    for r in rows:
        d = r.get("dense_lu_s")
        print(f"| {r['nodes']} | {r['unknowns']} | {r['build_s']:.1f} | {r['factor_s']:.1f} | "
              f"{d:.1f} | {r['factor_s'] / d:.2f} | " if d else
              f"| {r['nodes']} | {r['unknowns']} | {r['build_s']:.1f} | {r['factor_s']:.1f} | - | - | ",
              end="")
        print(f"{r['solve_s']:.1f} | {r['compressed_mb'] / r['dense_mb']:.3f} | "
              f"{r['factor_mb'] / r['dense_mb']:.3f} | {r['max_rank']} | {r['residual']:.1e} | "
              f"{r['refined_residual']:.1e} | {r['peak_rss_mb']:.0f} |")


if __name__ == "__main__":
    main()

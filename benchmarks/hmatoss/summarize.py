"""Markdown table from the JSON lines of run_all.sh (median over repeated
runs of the same configuration).

    python summarize.py /tmp/hmatoss/results.jsonl > table.md
"""

from __future__ import annotations

import json
import statistics
import sys
from collections import defaultdict


def key(d):
    variant = []
    if d["code"] == "hmat-oss":
        if d.get("gscale_mu"):
            variant.append(f"−G cols ×{d['gscale_mu']:g}μ")
        else:
            variant.append("unscaled")
        if d.get("boxes", "support") != "support":
            variant.append(f"boxes {d['boxes']}")
        if d.get("diag", "reference") != "reference":
            variant.append(f"diag {d['diag']}")
        if d.get("method", "aca_plus") != "aca_plus":
            variant.append(d["method"])
        if d.get("blas_threads") not in (None, "1"):
            variant.append(f"BLAS thr {d['blas_threads']}")
        if d.get("blas"):
            variant.append(d["blas"])
    else:
        if d.get("storage", "double") != "double":
            variant.append(d["storage"])
    if d.get("leaf_dofs", 144) != 144:
        variant.append(f"leaf {d['leaf_dofs'] // 3}")
    name = d["code"] + (" (" + ", ".join(variant) + ")" if variant else "")
    return (d["nodes"], d["eps"], d.get("threads", 1), name)


def main() -> None:
    runs = defaultdict(list)
    for line in open(sys.argv[1]):
        line = line.strip()
        if not line.startswith("{"):
            continue
        d = json.loads(line)
        if "error" in d:
            continue
        runs[key(d)].append(d)
    cols = [("build_s", "build s", "{:.1f}"), ("build_cpu_s", "build CPU s", "{:.1f}"),
            ("integrals_build", "element integrals (M)", "{:.1f}"),
            ("compressed_mb", "A MB", "{:.0f}"), ("lu_s", "LU s", "{:.1f}"),
            ("lu_cpu_s", "LU CPU s", "{:.1f}"), ("lu_mb", "LU MB", "{:.0f}"),
            ("matvec_rel_err", "matvec err (random x)", "{:.1e}"),
            ("phys_matvec_err", "matvec err (field)", "{:.1e}"),
            ("solve_rel_err", "solve err (random x)", "{:.1e}"),
            ("phys_err", "field err, LU solve", "{:.1e}"),
            ("phys_refined_err", "field err, +1 refinement", "{:.1e}")]
    print("| nodes | eps | thr | code | runs | " + " | ".join(c[1] for c in cols) + " |")
    print("|---:|---:|---:|---|---:|" + "---:|" * len(cols))
    for k in sorted(runs):
        rs = runs[k]
        cells = []
        for f, _, fmt in cols:
            vals = [r[f] for r in rs if r.get(f) is not None]
            if f == "integrals_build":
                vals = [v / 1e6 for v in vals]
            cells.append(fmt.format(statistics.median(vals)) if vals else "–")
        load = max(r.get("load1", 0) for r in rs)
        mark = " ⚠" if k[2] > 1 and load > 2.5 else ""
        print(f"| {k[0]} | {k[1]:g} | {k[2]}{mark} | {k[3]} | {len(rs)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

"""How far the interface flexibility K compresses as an H-matrix (a
compressed interface flexibility, docs/decisions.md), measured on the Cattaneo–Mindlin case
of ``hertz_mindlin_vs_tamaas.py`` at several contact resolutions a/h.

    python benchmarks/interface_compression.py [--a-over-h 12 18 25]
        [--eps 1e-4 1e-6] [--leaf 32] [--eta 2] [--json FILE]

K (3m x 3m, m the active frame nodes) is the dense matrix the contact solver
builds (``InterfaceSystem.K``: the relative displacement per unit frame
traction).  Its rows and columns are clustered by coordinate bisection of the
frame nodes (leaves of at most ``--leaf`` nodes); a block of two clusters is
admissible when max(diam) <= eta * dist.  Each admissible block is stored as
its truncated SVD at the smallest rank whose dropped singular values have a
Frobenius norm within eps ||K||_F sqrt(|block| / |K|) (so the whole matrix is
within eps ||K||_F), or dense when that is smaller; inadmissible leaf pairs
are dense.  Printed per a/h and eps: the compression (dense entries / stored
entries), the share of the dense near field, the ranks, and the ranks of the
largest off-diagonal block at the top three bisections (what a HODLR matrix,
or a peeling construction from random probes, needs per level).  This is the
best any H-matrix of that block structure can do at that accuracy (optimal
ranks), so it bounds what a compressed K can save; it says nothing about the
cost of building one without the dense K.
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

from _common import machine_line  # noqa: E402

from bemcontact.contact import condense  # noqa: E402
from bemcontact.contact.interface import InterfaceSystem  # noqa: E402
from bemcontact.validation import cases  # noqa: E402

MU, APPROACH = 0.3, 0.03


def interface_matrix(a_over_h: float) -> tuple[np.ndarray, np.ndarray]:
    """K and the active frame nodes' positions (m, 3) of the benchmark's
    sphere on block at h = a / a_over_h (as ``hertz_mindlin_vs_tamaas.py``)."""
    a_guess = math.sqrt(cases.SphereOnBlock().radius * APPROACH)
    h = a_guess / a_over_h
    s = cases.SphereOnBlock(size_profile=((0.0, h), (1.1 * a_guess, h)), growth=0.45)
    prob = cases.sphere_on_block(h, APPROACH, friction_coefficient=MU, setup=s)
    fs = prob.frames
    modes = fs.traction_modes()
    cb = tuple(condense(b, fs.nodes(i), modes=modes[i]) for i, b in enumerate(prob.bodies))
    system = InterfaceSystem(fs, cb, MU, prob.contact_modulus(0))
    frame = fs.frames[0]
    return system.K, frame.points[frame.active]


def _tree(points: np.ndarray, idx: np.ndarray, leaf: int) -> dict:
    box = (points[idx].min(0), points[idx].max(0))
    node = {"idx": idx, "box": box}
    if idx.size > leaf:
        d = int(np.argmax(box[1] - box[0]))
        order = idx[np.argsort(points[idx, d], kind="stable")]
        half = order.size // 2
        node["kids"] = [_tree(points, order[:half], leaf), _tree(points, order[half:], leaf)]
    return node


def _dofs(idx: np.ndarray) -> np.ndarray:
    return (3 * idx[:, None] + np.arange(3)).ravel()


def _rank(sv: np.ndarray, tol: float) -> int:
    """Smallest rank whose dropped singular values ``sv`` have Frobenius norm <= tol."""
    tail = np.sqrt(np.cumsum(sv[::-1] ** 2))[::-1]  # norm of what rank k drops
    return int(np.count_nonzero(tail > tol))


def compression(K: np.ndarray, points: np.ndarray, eps_list, leaf: int, eta: float) -> list[dict]:
    """Stored entries of the best H-matrix of K at each eps (see above)."""
    root = _tree(points, np.arange(points.shape[0]), leaf)
    norm = np.linalg.norm(K)
    dense_near = 0
    far = []  # (block rows, block cols, singular values), once for every eps

    def diam(t):
        return float(np.linalg.norm(t["box"][1] - t["box"][0]))

    def dist(a, b):
        gap = np.maximum(0.0, np.maximum(a["box"][0] - b["box"][1], b["box"][0] - a["box"][1]))
        return float(np.linalg.norm(gap))

    def visit(a, b):
        nonlocal dense_near
        if max(diam(a), diam(b)) <= eta * dist(a, b):
            block = K[np.ix_(_dofs(a["idx"]), _dofs(b["idx"]))]
            far.append((*block.shape, np.linalg.svd(block, compute_uv=False)))
        elif "kids" not in a and "kids" not in b:
            dense_near += 9 * a["idx"].size * b["idx"].size
        else:
            for x in a.get("kids", [a]):
                for y in b.get("kids", [b]):
                    visit(x, y)

    visit(root, root)
    rows = []
    for eps in eps_list:
        stored, ranks = dense_near, []
        for r, c, sv in far:
            k = _rank(sv, eps * norm * math.sqrt(r * c / K.size))
            ranks.append(k)
            stored += min(k * (r + c), r * c)
        rows.append({"eps": eps, "compression": K.size / stored,
                     "dense_share": dense_near / stored, "far_blocks": len(far),
                     "mean_rank": float(np.mean(ranks)), "max_rank": int(max(ranks))})
    return rows


def weak_ranks(K: np.ndarray, points: np.ndarray, eps: float, levels: int = 3) -> list[int]:
    """Ranks (at eps ||K||_F, the block's share as above) of the largest
    off-diagonal block at each of the top ``levels`` bisections: the ranks a
    HODLR matrix (weak admissibility) of K needs, and so about the number of
    random probes a peeling construction from solves would need per level."""
    norm = np.linalg.norm(K)
    ranks = []
    idx = [np.arange(points.shape[0])]
    for _ in range(levels):
        cluster = max(idx, key=lambda i: i.size)
        p = points[cluster]
        d = int(np.argmax(p.max(0) - p.min(0)))
        order = cluster[np.argsort(p[:, d], kind="stable")]
        a, b = order[: order.size // 2], order[order.size // 2 :]
        block = K[np.ix_(_dofs(a), _dofs(b))]
        ranks.append(_rank(np.linalg.svd(block, compute_uv=False),
                           eps * norm * math.sqrt(block.size / K.size)))
        idx = [a, b]
    return ranks


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--a-over-h", type=float, nargs="+", default=[12, 18, 25])
    ap.add_argument("--eps", type=float, nargs="+", default=[1e-4, 1e-6])
    ap.add_argument("--leaf", type=int, default=32)
    ap.add_argument("--eta", type=float, default=2.0)
    ap.add_argument("--json", help="also write the rows to this file")
    args = ap.parse_args(argv)
    print(machine_line())
    print(f"{'a/h':>5} {'m':>6} {'K MB':>8} {'eps':>7} {'compression':>11} "
          f"{'dense share':>11} {'mean rank':>9} {'max rank':>8} {'s':>6}")
    out = []
    for aoh in args.a_over_h:
        K, points = interface_matrix(aoh)
        t = time.perf_counter()
        rows = compression(K, points, args.eps, args.leaf, args.eta)
        seconds = time.perf_counter() - t
        for r in rows:
            r.update({"a_over_h": aoh, "m": int(points.shape[0]), "K_mb": K.nbytes / 1e6,
                      "leaf": args.leaf, "eta": args.eta, "seconds": seconds,
                      "weak_ranks": weak_ranks(K, points, r["eps"])})
            print(f"{aoh:5.0f} {r['m']:6d} {r['K_mb']:8.1f} {r['eps']:7.0e} "
                  f"{r['compression']:11.2f} {r['dense_share']:11.2f} {r['mean_rank']:9.1f} "
                  f"{r['max_rank']:8d} {seconds:6.1f}  HODLR ranks {r['weak_ranks']}", flush=True)
        out += rows
        del K
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine_line(), "rows": out}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The coarse-to-fine predictor of a load increment (nested iteration).

Active-set Newton moves the contact front, and the stick–slip front, by
about one ring of frame nodes per iteration, so its iteration count grows
with the contact zone's resolution: from all-open, the first iterate closes
every node the rigid approach makes overlap (the overlap disk of a sphere is
√2 times the contact radius) and the following ones open a ring at a time
(Cattaneo–Mindlin, docs/benchmarks.md: 38 iterations at a/h = 12, 67 at
a/h = 25).  Here each increment is first solved on the frame aggregated into
clusters of about :data:`CLUSTER` neighbouring nodes
(:func:`aggregated`), and that
recursively down to :data:`COARSE_MIN` nodes, every level started from the
one below it.  The coarse solution's change over the increment, prolongated
(each node takes its cluster's traction change), is added to the fine
starting point: the fine Newton then starts with about the right contact and
stick zones and corrects the fronts by a ring or two.

The predictor changes the starting point only: the fine increment is solved
to the same tolerance, so its solution is the same (to the tolerance; the
law's solution of an increment is unique for the friction coefficients of
practice), and a coarse level that does not converge is skipped (the fine
level starts where it would have without it).  Coarse levels are solved to
:data:`COARSE_TOLERANCE` (their states settle long before) with a double LU.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse

from ..errors import ConfigError
from .interface import InterfaceSystem
from .newton import newton
from .options import SolverOptions

#: Nodes per cluster (at most): recursive bisection stops at this size.
CLUSTER = 4
#: No coarser level is built from a level of at most this many nodes (its
#: Newton matrices are small: a prediction would save nothing).
COARSE_MIN = 150
#: Residual tolerance of the coarse levels' Newton solves.
COARSE_TOLERANCE = 1e-6


def clusters(points: np.ndarray, size: int = CLUSTER, groups: np.ndarray | None = None) -> np.ndarray:
    """(m,) cluster index (0..mc-1) of each of ``points`` (m, 3): recursive
    bisection across the longest side of the bounding box, a multiple of
    ``size`` points on one side, until a cluster has at most ``size`` points
    (so between size/2 and size, nearly all ``size``); each of ``groups``
    (m,) (e.g. the contact pair of each frame node) on its own."""
    points = np.asarray(points, dtype=float)
    out = np.empty(len(points), dtype=np.int64)
    if groups is None:
        stack = [np.arange(len(points))]
    else:
        stack = [np.flatnonzero(groups == g) for g in np.unique(groups)[::-1]]
    n = 0
    while stack:
        idx = stack.pop()
        if idx.size <= size:
            out[idx] = n
            n += 1
            continue
        x = points[idx]
        axis = int(np.argmax(x.max(axis=0) - x.min(axis=0)))
        order = np.argsort(x[:, axis], kind="stable")
        # a multiple of ``size`` on one side, so that most clusters are full
        n_ = idx.size
        half = n_ // 2 if n_ <= 2 * size else size * ((n_ // size + 1) // 2)
        stack.append(idx[order[half:]])
        stack.append(idx[order[:half]])
    return out


def aggregated(system: InterfaceSystem, groups: np.ndarray) -> InterfaceSystem:
    """The same interface system on clusters of frame nodes: one
    traction per cluster (``groups`` (m,) the cluster of each node,
    0..mc-1), taken by all its nodes (the prolongation P, 0 and 1), and
    one relative displacement per cluster, the area-weighted mean of its
    nodes' (the restriction R = diag(1/a_c) Pᵀ diag(a)); the extra
    unknowns stay.  K_c = R K P, the affine terms and the columns of the
    extra unknowns restricted by R, the equilibrium and resultant rows
    taken on P lam_c (exact for a traction constant over each cluster);
    augmentation r = r_scale / sqrt(cluster area), like a node's.  For
    the coarse-to-fine predictor (:mod:`~bemcontact.contact.predictor`):
    its Newton solve only (no recovery: ``act`` is None)."""
    g = np.asarray(groups, dtype=np.int64)
    m = system.m
    if g.shape != (m,) or g.min(initial=0) < 0:
        raise ConfigError(
            f"aggregated: one cluster index >= 0 per frame node ({m}) expected")
    mc = int(g.max(initial=-1)) + 1
    P1 = scipy.sparse.csr_matrix((np.ones(m), (np.arange(m), g)), shape=(m, mc))
    P = scipy.sparse.kron(P1, scipy.sparse.identity(3), format="csr")
    ac = P1.T @ system.a
    if np.any(ac <= 0.0):
        raise ConfigError("aggregated: every cluster needs at least one frame node")
    R = (scipy.sparse.diags(np.repeat(1.0 / ac, 3)) @ P.T
         @ scipy.sparse.diags(np.repeat(system.a, 3))).tocsr()
    # a cluster lies in one pair (the predictor's clusters do): it takes
    # that pair's friction and augmentation
    pair = np.zeros(mc, dtype=np.int64)
    pair[g] = system.pair_of
    if np.any(pair[g] != system.pair_of):
        raise ConfigError("aggregated: a cluster spans two contact pairs")
    first = np.zeros(mc, dtype=np.int64)
    first[g[::-1]] = np.arange(m)[::-1]  # a node of each cluster
    m3 = 3 * m
    eq = np.hstack([np.asarray((P.T @ system._eq[:, :m3].T).T), system._eq[:, m3:]])
    return InterfaceSystem.from_parts(
        system.frames, system.cb, system.mu, None, ac, np.sqrt(P1.T @ system.size**2), pair,
        system.law.friction[first], system.r_scale[first],
        system.kinematics.restricted(P, R), R @ system._Lz, eq, P, R, system.area)


class Predictor:
    """The coarse levels of an interface ``system`` whose active frame nodes
    lie at ``points`` (m, 3), and the prediction of an increment's starting
    point (:meth:`predict`)."""

    def __init__(self, system: InterfaceSystem, points: np.ndarray,
                 min_nodes: int = COARSE_MIN) -> None:
        self.system = system
        self.levels: list[InterfaceSystem] = []
        cur, x = system, np.asarray(points, dtype=float)
        while cur.m > min_nodes:
            g = clusters(x, groups=cur.pair_of)
            coarse = aggregated(cur, g)
            w = cur.a[:, None] * x
            x = np.stack([np.bincount(g, w[:, i], coarse.m) for i in range(3)], axis=1)
            x /= coarse.a[:, None]
            self.levels.append(coarse)
            cur = coarse
        #: Newton iterations on the coarse levels in the last :meth:`predict`
        self.iterations = 0

    @property
    def sizes(self) -> list[int]:
        """Frame nodes (clusters) of each coarse level, finest first."""
        return [c.m for c in self.levels]

    def predict(self, z: np.ndarray, ell_prev: np.ndarray, ell: np.ndarray,
                opt: SolverOptions) -> np.ndarray:
        """The fine system's starting point for the increment from the
        converged ``z`` at load ``ell_prev`` to ``ell`` (the fine system's
        law holds the increment's stick reference): ``z`` plus the
        prolongated change of the coarse solution (``z`` itself when there
        is no coarse level or the coarsest that converged gave nothing)."""
        self.iterations = 0
        if not self.levels:
            return z
        copt = dataclasses.replace(opt, tolerance=max(opt.tolerance, COARSE_TOLERANCE),
                                   newton_steps="lu", progress=False)
        return self._predict(0, z, ell_prev, ell, self.system.law.reference, copt)

    def _predict(self, i, z, ell_prev, ell, k_prev, opt):
        """The starting point of level i - 1 (the fine system for i = 0)
        from level i's solution of the increment."""
        c = self.levels[i]
        m3, mc3 = c.restriction.shape[1], 3 * c.m
        zc0 = np.concatenate([c.restriction @ z[:m3], z[m3:]])
        kt = np.column_stack([k_prev, np.zeros(len(k_prev))]).ravel()
        kc = (c.restriction @ kt).reshape(-1, 3)[:, :2]
        c.start_increment(zc0, ell_prev, reference=kc)
        start = zc0
        if i + 1 < len(self.levels):
            start = self._predict(i + 1, zc0, ell_prev, ell, kc, opt)
        zc, rec, msg = newton(c, start, ell, opt)
        self.iterations += rec.iterations
        if msg is not None and start is not zc0:
            zc, rec, msg = newton(c, zc0, ell, opt)
            self.iterations += rec.iterations
        if msg is not None:
            return z
        d = zc - zc0
        return z + np.concatenate([c.prolongation @ d[:mc3], d[mc3:]])


__all__ = ["CLUSTER", "COARSE_MIN", "COARSE_TOLERANCE", "Predictor", "aggregated", "clusters"]

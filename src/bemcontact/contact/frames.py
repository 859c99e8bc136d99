"""The frames of an assembly: several contact pairs seen as one interface.

Each contact pair p has its own :class:`~bemcontact.contact.frame.ContactFrame`
between the bodies ``links[p] = (a, b)`` (body a is the pair's body 1, b
its body 2).  The interface unknowns are the frame tractions of every pair,
stacked pair after pair (the active nodes of each frame, in its order).  A
body takes part in any number of pairs, on one surface or on several: it is
condensed once on the union of its contact surfaces' nodes, and on one
traction mode per frame traction component of every pair (zero for the
pairs it is not in).  With one pair of two bodies everything is that pair's
frame unchanged (the same node order, modes and numbers).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse

from .frame import ContactFrame
from .modes import TractionModes

#: Sign of the frame traction on each side of a pair: body 1 receives -lam,
#: body 2 +lam (the normal points from body 1 into body 2).
SIDE_SIGNS = (-1.0, 1.0)


class FrameSet:
    """The frames of ``M`` contact pairs between ``n_bodies`` bodies.

    ``frames[p]`` couples the bodies ``links[p] = (a, b)``; ``nodes(a)`` is
    body a's contact nodes (the union over its pairs' surfaces, the first
    surface's nodes first, in their own order); the active frame nodes of
    all pairs are numbered pair after pair: pair p's are ``slice(p)``
    (offsets into the m stacked nodes), ``pair_of`` (m,) the pair of each."""

    def __init__(self, frames, links, n_bodies: int) -> None:
        self.frames = tuple(frames)
        self.links = tuple((int(a), int(b)) for a, b in links)
        self.n_bodies = int(n_bodies)
        self.act = tuple(np.flatnonzero(f.active) for f in self.frames)
        counts = [a.size for a in self.act]
        self.offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        self.m = int(self.offsets[-1])
        self.pair_of = np.repeat(np.arange(len(self.frames)), counts)
        # body -> its contact nodes, and each (pair, side)'s rows in them
        nodes: list[list[np.ndarray]] = [[] for _ in range(self.n_bodies)]
        self._rows: dict[tuple[int, int], np.ndarray] = {}
        for p, (f, link) in enumerate(zip(self.frames, self.links)):
            for side, a in enumerate(link):
                own = f.nodes(side)
                known = np.concatenate(nodes[a]) if nodes[a] else np.zeros(0, dtype=own.dtype)
                new = own[~np.isin(own, known)]
                if new.size:
                    nodes[a].append(new)
                allnodes = np.concatenate(nodes[a])
                where = {int(v): i for i, v in enumerate(allnodes)}
                self._rows[p, side] = np.array([where[int(v)] for v in own], dtype=np.int64)
        self._nodes = tuple(np.concatenate(n) if n else np.zeros(0, dtype=np.int64)
                            for n in nodes)

    @classmethod
    def single(cls, frame: ContactFrame) -> FrameSet:
        """The one frame of a two-body problem (bodies 0 and 1)."""
        return cls([frame], [(0, 1)], 2)

    # ------------------------------------------------------------ numbering
    def slice(self, p: int) -> slice:
        """Pair p's active frame nodes among the m stacked ones."""
        return slice(int(self.offsets[p]), int(self.offsets[p + 1]))

    def dofs(self, p: int) -> slice:
        """Pair p's 3 m_p traction components among the 3 m."""
        return slice(3 * int(self.offsets[p]), 3 * int(self.offsets[p + 1]))

    def nodes(self, a: int) -> np.ndarray:
        """Body a's contact functional nodes (indices into its solution)."""
        return self._nodes[a]

    def rows(self, p: int, side: int) -> np.ndarray:
        """Positions of pair p's side-``side`` surface nodes in
        ``nodes(links[p][side])``."""
        return self._rows[p, side]

    def pairs_of(self, a: int) -> list[tuple[int, int]]:
        """(pair, side) of every pair body a takes part in."""
        return [(p, s) for p, link in enumerate(self.links) for s, b in enumerate(link) if b == a]

    # ------------------------------------------------- stacked node fields
    def _stack(self, get) -> np.ndarray:
        return np.concatenate([get(f)[act] for f, act in zip(self.frames, self.act)])

    @property
    def points(self) -> np.ndarray:
        """(m, 3) the active frame nodes."""
        return self._stack(lambda f: f.points)

    @property
    def weights(self) -> np.ndarray:
        """(m,) ∫ N_j over the common area."""
        return self._stack(lambda f: f.weights)

    @property
    def size(self) -> np.ndarray:
        """(m,) each node's frame element size."""
        return self._stack(lambda f: f.size)

    @property
    def Q(self) -> np.ndarray:
        """(m, 3, 3) the local bases (t1, t2, n)."""
        return self._stack(lambda f: f.Q)

    # ------------------------------------------------------- traction modes
    def _embedded(self, M, rows: np.ndarray, n: int):
        M = scipy.sparse.coo_array(M)
        return scipy.sparse.coo_array((M.data, (rows[M.row], rows[M.col])), shape=(n, n))

    def traction_modes(self) -> tuple[TractionModes, ...]:
        """Each body's traction modes on all frames' active nodes (3 m
        columns, zero for the pairs it is not in): what
        :func:`~bemcontact.contact.condense` condenses each body on for
        :class:`~bemcontact.contact.interface.InterfaceSystem`.  Its mass is
        that of the union of its contact surfaces (a surface shared by two
        pairs counted once)."""
        if len(self.frames) == 1:  # the pair's own arrays, bit for bit
            f, act = self.frames[0], self.act[0]
            return tuple(TractionModes(f.D[side][:, act], f.Q[act], f.M[side], SIDE_SIGNS[side])
                         for side in (self.links[0].index(a) for a in range(self.n_bodies)))
        Q = self.Q
        out = []
        for a in range(self.n_bodies):
            n = self._nodes[a].size
            r, c, v = [], [], []
            M = None
            seen: list[tuple[int, ...]] = []
            for p, side in self.pairs_of(a):
                f, rows = self.frames[p], self.rows(p, side)
                Dp = scipy.sparse.coo_array(f.D[side][:, self.act[p]])
                r.append(rows[Dp.row])
                c.append(Dp.col + self.offsets[p])
                v.append(SIDE_SIGNS[side] * Dp.data)
                key = tuple(rows.tolist())
                if key not in seen:  # one surface's mass once
                    seen.append(key)
                    Mp = self._embedded(f.M[side], rows, n)
                    M = Mp if M is None else M + Mp
            D = scipy.sparse.coo_array((np.concatenate(v), (np.concatenate(r), np.concatenate(c))),
                                       shape=(n, self.m))
            out.append(TractionModes(D, Q, M, 1.0))
        return tuple(out)


__all__ = ["FrameSet", "SIDE_SIGNS"]

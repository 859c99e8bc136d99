"""The contact law: augmented-Lagrangian projections and their generalized
Jacobians (founding paper, eqs. 4-5).

Everything here is per frame node and in frame-local components ordered
``(t1, t2, n)``; ``n`` points from body 1 into body 2.

* ``lam`` (m, 3): contact traction acting on body 2 (body 1 receives the
  opposite).  ``lam[:, 2] > 0`` is compressive pressure; ``lam[:, :2]`` is the
  tangential (friction) traction on body 2.
* ``k`` (m, 3): relative displacement of body 2 with respect to body 1, i.e.
  ``k[:, 2]`` the normal gap (> 0 open) and ``k[:, :2]`` the relative
  tangential displacement.
* ``k_prev`` (m, 2): ``k[:, :2]`` at the previous converged load step, so
  that stick means zero slip *increment* (exact for non-monotonic loading).

With augmented multipliers ``sn = lam_n - r_n k_n`` and
``st = lam_t - r_t (k_t - k_prev)``, the law is ``Phi(lam, k) = 0`` with

    Phi_n = lam_n - max(0, sn)                       (unilateral contact)
    Phi_t = lam_t - P_R(st),  R = mu max(0, sn)      (Coulomb)

where ``P_R`` projects onto the disk of radius R.  The paper writes the same
with compression negative (``min(., 0)``); here compression is positive.  The
solution does not depend on r_n, r_t > 0; they only change the Newton path.

States: OPEN (sn <= 0: lam = 0), STICK (|st| <= R: k_n = 0, k_t = k_prev),
SLIP (|st| > R: k_n = 0, lam_t = -R (k_t - k_prev)/|k_t - k_prev|).

``mu`` is a number or one coefficient per node (m,): the interface system
sets it to 0 for the increment in which a node closes (see
:meth:`~bemcontact.contact.interface.InterfaceSystem.start_increment`).
"""

from __future__ import annotations

import numpy as np

OPEN, STICK, SLIP = 0, 1, 2
STATE_NAMES = ("open", "stick", "slip")


def _augmented(lam, k, k_prev, r_n, r_t):
    m = lam.shape[0]
    r_n = np.broadcast_to(np.asarray(r_n, dtype=float), (m,))
    r_t = np.broadcast_to(np.asarray(r_t, dtype=float), (m,))
    sn = lam[:, 2] - r_n * k[:, 2]
    st = lam[:, :2] - r_t[:, None] * (k[:, :2] - k_prev)
    return r_n, r_t, sn, st


def contact_state(
    lam: np.ndarray, k: np.ndarray, k_prev: np.ndarray, mu: float, r_n, r_t
) -> np.ndarray:
    """(m,) int8: OPEN, STICK or SLIP for each node (frictionless closed
    nodes count as SLIP)."""
    _, _, sn, st = _augmented(lam, k, k_prev, r_n, r_t)
    mu = np.broadcast_to(np.asarray(mu, dtype=float), (lam.shape[0],))
    R = mu * np.maximum(sn, 0.0)
    state = np.full(lam.shape[0], SLIP, dtype=np.int8)
    state[(mu > 0) & (np.linalg.norm(st, axis=1) <= R)] = STICK
    state[sn <= 0] = OPEN
    return state


def residual(
    lam: np.ndarray, k: np.ndarray, k_prev: np.ndarray, mu: float, r_n, r_t
) -> np.ndarray:
    """Phi (m, 3) in traction units."""
    _, _, sn, st = _augmented(lam, k, k_prev, r_n, r_t)
    pn = np.maximum(sn, 0.0)
    R = mu * pn
    ns = np.linalg.norm(st, axis=1)
    scale = np.where(ns > R, R / np.where(ns > 0, ns, 1.0), 1.0)
    out = np.empty_like(lam, dtype=float)
    out[:, 2] = lam[:, 2] - pn
    out[:, :2] = lam[:, :2] - st * scale[:, None]
    return out


def jacobian(
    lam: np.ndarray, k: np.ndarray, k_prev: np.ndarray, mu: float, r_n, r_t
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Generalized Jacobian blocks at the current state.

    Returns ``(J_lam, J_k, state)`` with ``J_lam[j] = dPhi_j/dlam_j`` and
    ``J_k[j] = dPhi_j/dk_j``, each (m, 3, 3) in (t1, t2, n) order.  On a
    state boundary (a kink) the element of the generalized Jacobian of the
    state returned by :func:`contact_state` is used.
    """
    m = lam.shape[0]
    r_n, r_t, sn, st = _augmented(lam, k, k_prev, r_n, r_t)
    mu = np.broadcast_to(np.asarray(mu, dtype=float), (m,))
    pn = np.maximum(sn, 0.0)
    R = mu * pn
    state = contact_state(lam, k, k_prev, mu, r_n, r_t)
    Jl = np.zeros((m, 3, 3))
    Jk = np.zeros((m, 3, 3))
    I2 = np.eye(2)
    o = state == OPEN
    Jl[o] = np.eye(3)
    closed = ~o
    # normal row of a closed node: Phi_n = r_n k_n
    Jk[closed, 2, 2] = r_n[closed]
    s_ = state == STICK
    Jk[s_, 0, 0] = r_t[s_]
    Jk[s_, 1, 1] = r_t[s_]
    sl = state == SLIP
    if sl.any():
        ns = np.linalg.norm(st[sl], axis=1)
        safe = np.where(ns > 0, ns, 1.0)
        s = st[sl] / safe[:, None]
        s[ns == 0] = 0.0
        P = I2[None] - s[:, :, None] * s[:, None, :]
        c = np.where(ns > 0, R[sl] / safe, 0.0)
        Jl[sl, :2, :2] = I2[None] - c[:, None, None] * P
        Jl[sl, :2, 2] = -mu[sl][:, None] * s
        Jk[sl, :2, :2] = (c * r_t[sl])[:, None, None] * P
        Jk[sl, :2, 2] = (mu[sl] * r_n[sl])[:, None] * s
    return Jl, Jk, state


class CoulombLaw:
    """The law of an interface system's frame nodes (every pair's, stacked):
    it owns each node's friction coefficient ``friction`` (its pair's) and
    augmentation ``r`` (r_n = r_t, stress per length), the coefficient in
    effect in the current increment ``mu`` (0 for a node that closes in
    it: :meth:`~bemcontact.contact.interface.InterfaceSystem.start_increment`),
    the first-touch ``anchors``, and the history: the stick ``reference``
    (m, 2), the relative tangential displacement the increment's slip is
    counted from.  ``state``, ``residual`` and ``jacobian`` are those of
    the module's functions at that history; rolling convects ``reference``
    (:meth:`convect`)."""

    def __init__(self, friction, augmentation) -> None:
        self.friction = np.asarray(friction, dtype=float)
        m = self.friction.size
        self.r = np.broadcast_to(np.asarray(augmentation, dtype=float), (m,)).copy()
        self.mu = self.friction.copy()
        self.anchors = np.zeros(m, dtype=bool)
        self.reference = np.zeros((m, 2))

    @property
    def m(self) -> int:
        return self.friction.size

    def state(self, lam: np.ndarray, k: np.ndarray) -> np.ndarray:
        """(m,) OPEN, STICK or SLIP (:func:`contact_state`)."""
        return contact_state(lam, k, self.reference, self.mu, self.r, self.r)

    def residual(self, lam: np.ndarray, k: np.ndarray) -> np.ndarray:
        """Phi (m, 3) (:func:`residual`)."""
        return residual(lam, k, self.reference, self.mu, self.r, self.r)

    def jacobian(self, lam: np.ndarray, k: np.ndarray):
        """(J_lam, J_k, state) (:func:`jacobian`)."""
        return jacobian(lam, k, self.reference, self.mu, self.r, self.r)

    def start_increment(self, k: np.ndarray, pair_of: np.ndarray, size, lam: np.ndarray,
                        influence, reference: np.ndarray | None = None) -> None:
        """Before an increment from the converged relative displacements
        ``k`` (m, 3) and tractions ``lam`` (m, 3): the coefficients in effect
        and the stick reference (the rule and its reasons:
        :meth:`~bemcontact.contact.interface.InterfaceSystem.start_increment`).
        ``pair_of`` (m,) the pair of each node, ``size`` its element (cell)
        size; ``influence(nodes, t)`` the relative displacement (m, 3) of the
        tangential tractions ``t`` (len(nodes), 2) on ``nodes`` (the anchors
        released, whose displacement leaves the reference); ``reference``
        given: it is the stick reference."""
        gap = k[:, 2]
        tol = 1e-8 * size
        npairs = int(pair_of.max(initial=-1)) + 1
        # the first touch of each pair (every pair holds its bodies)
        first = np.full(npairs, np.inf)
        np.minimum.at(first, pair_of, gap)
        first = np.maximum(first, 0.0)
        self.mu = np.where(gap > first[pair_of] + tol, 0.0, self.friction)
        touching = gap <= tol
        held = np.zeros(npairs, dtype=bool)  # others than the anchors touch
        np.logical_or.at(held, pair_of, touching & ~self.anchors)
        done = self.anchors & touching & held[pair_of]
        self.anchors = ((self.mu > 0.0) & ~touching) | (self.anchors & ~done)
        if reference is not None:
            self.reference = reference
            return
        self.reference = k[:, :2].copy()
        if not done.any():
            return
        nodes = np.flatnonzero(done)
        self.reference = self.reference - influence(nodes, lam[nodes, :2])[:, :2]

    def convect(self, reference: np.ndarray) -> None:
        """Before a rolling increment: the stick reference is the convected
        field ``reference`` (m, 2) (:mod:`~bemcontact.contact.rolling`: the
        previous solution's k_t shifted upstream minus the rigid slip of the
        rolled distance; zeros in steady state, where the law is handed the
        convected slip itself), and every node has its friction: material
        that enters the contact at the leading edge sticks there, it does
        not close frictionless as a node reached by a growing normal load."""
        self.reference = np.asarray(reference, dtype=float).reshape(self.m, 2).copy()
        self.mu = self.friction.copy()
        self.anchors = np.zeros(self.m, dtype=bool)


__all__ = ["OPEN", "STICK", "SLIP", "STATE_NAMES", "CoulombLaw", "contact_state", "residual",
           "jacobian"]

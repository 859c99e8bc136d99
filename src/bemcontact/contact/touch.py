"""The first touch: the starting point of a load increment for bodies held
only by the contact, whose rigid motion the Newton matrix cannot fix while
their nodes are open (floating bodies, force-controlled platens).  Works on
an :class:`~bemcontact.contact.interface.InterfaceSystem`."""

from __future__ import annotations

import numpy as np

from . import law

#: Most sweeps of the floating bodies' first-touch moves (:func:`_float`).
FLOAT_SWEEPS = 30


def _root(g, step: float) -> float | None:
    """du with g(du) = 0 (to bisection accuracy, on the side of the change of
    sign) for a g monotone in du, e.g. a penalty resultant less its target:
    0 if g(0) = 0; else doubling steps in each direction bracket a change of
    sign, then 100 bisections.  None when neither direction finds one."""
    g0 = g(0.0)
    if g0 == 0.0:
        return 0.0
    for direction in (1.0, -1.0):
        lo, h = 0.0, step
        for _ in range(80):
            hi = direction * h
            v = g(hi)
            if v != 0.0 and np.sign(v) != np.sign(g0):
                for _ in range(100):
                    mid = 0.5 * (lo + hi)
                    if np.sign(g(mid)) == np.sign(g0):
                        lo = mid
                    else:
                        hi = mid
                return hi
            if v == 0.0:
                return hi
            lo, h = hi, 2.0 * h
    return None


def first_touch(system, z, ell) -> np.ndarray:
    """Predictor for bodies held only by the contact, whose rigid motion
    the Newton matrix cannot fix while their nodes are open.

    * Floating bodies (free rigid modes: a block resting on another under
      a pressure, a stack of them) at a solve's start (every traction
      zero): their free modes are moved until the trial pressures of
      all their pairs balance their modal loads (:func:`_float`); the
      nodes that touch up to round-off at the start would otherwise be
      open or closed by the sign of that round-off.
    * A force-controlled platen (a sphere pushed by a force onto a block,
      touching at a point) when every node is open at ``z``: each such
      translation (its resultant row has no stiffness of its own) is
      moved, traction multipliers held, until the augmented-Lagrangian
      trial pressures max(0, -r k_n) of the nodes it closes balance the
      prescribed force.

    Either gives Newton a penalty contact with a patch of about the right
    size; else ``z`` is returned unchanged (a node already closed, or no
    such translation moving the normal gaps: the singular matrix's error)."""
    lam, _ = system.split(z)
    if sum(system.nf) and not lam.any():  # a solve's start: no traction yet
        z = z.copy()
        _float(system, z, ell, lam)
    state = system.law.state(lam.reshape(-1, 3), system.law_k(z, ell))
    if (state != law.OPEN).any():
        return z
    z = z.copy()
    kn0 = system.k(z, ell)[:, 2]
    col = 3 * system.m
    for i, c in enumerate(system.cb):
        nf, nc = system.nf[i], system.nc[i]
        need = c.forces @ ell - c.control_resultants(ell) - system.CT[i] @ lam if nc else ()
        for k_ in range(nc):
            s = system.L[2 * i + 1][:, k_].reshape(-1, 3)[:, 2]  # dk_n / dU
            if np.any(system.CY[i][k_] != 0.0) or not np.any(s != 0.0) or need[k_] == 0.0:
                # restrained by the body's own supports, or tangential (the
                # friction of the closed nodes holds it), or nothing to carry
                continue
            ct = system.CT[i][k_].reshape(-1, 3)[:, 2]  # resultant per pressure
            # k is affine in z: only U_k moves
            u = _root(
                lambda du, s=s, ct=ct, t=float(need[k_]):
                float(ct @ np.maximum(0.0, -system.law.r * (kn0 + s * du))) - t,
                max(float(np.abs(kn0).max()), 1e-12) / float(np.abs(s).max()),
            )
            if u is not None:
                z[col + nf + k_] += u
                kn0 = kn0 + s * u
        col += nf + nc
    return z


def _float(system, z, ell, lam) -> np.ndarray:
    """Move the free rigid modes of floating bodies (held by the contact
    alone: a block resting on another under a pressure, a stack), in
    ``z`` in place, until the augmented-Lagrangian trial pressures
    max(0, -r k_n) of all their pairs balance their modal loads: one
    mode at a time, body after body, repeated (a stack passes its load
    down one body per sweep) until no mode moves by more than 1e-6 of
    its last move or :data:`FLOAT_SWEEPS` sweeps.  Returns the normal
    relative displacements k_n there."""
    kn = system.k(z, ell)[:, 2]
    modes = []
    col = 3 * system.m
    for i, c in enumerate(system.cb):
        if system.nf[i]:
            target = -(c.known_modal_force @ ell) - system.E[i] @ lam
            for k_ in range(system.nf[i]):
                s = system.L[2 * i][:, k_].reshape(-1, 3)[:, 2]  # dk_n / dalpha
                if np.any(s != 0.0):
                    e = system.E[i][k_].reshape(-1, 3)[:, 2]  # modal force per pressure
                    modes.append((col + k_, s, e, float(target[k_])))
        col += system.nf[i] + system.nc[i]
    if not modes:
        return kn
    scale = max(float(np.abs(kn).max()), 1e-12)
    for _ in range(FLOAT_SWEEPS):
        largest = 0.0
        for j, s, e, target in modes:
            u = _root(lambda du, s=s, e=e, t=target:
                      float(e @ np.maximum(0.0, -system.law.r * (kn + s * du))) - t,
                      scale / float(np.abs(s).max()))
            if u:
                z[j] += u
                kn = kn + s * u
                largest = max(largest, abs(u) * float(np.abs(s).max()))
        if largest <= 1e-6 * scale:
            break
        scale = largest
    return kn


__all__ = ["first_touch", "FLOAT_SWEEPS"]

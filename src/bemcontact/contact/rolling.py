"""Rolling: the rolling direction, Kalker's creepages and spin, and the
two ways the friction history is convected (steady state, transient).

Conventions (the one statement of them; docs/theory.md "Rolling" repeats it):

* The contact moves over the bodies' surfaces in the **rolling direction**
  x_r (a unit vector tangent to the contact); material enters the contact at
  its leading edge (largest x_r) and leaves it at the trailing edge.  The
  rolling frame is (x_r, y_r, n) with n the contact normal from body 1 into
  body 2 and y_r = n × x_r; its origin is the contact's centre.
* The **creepages** ξ (along x_r), η (along y_r) and the **spin** φ (about
  n, rad per length) are the rigid velocity of body 2's surface relative to
  body 1's at the contact, divided by the rolling speed V: the rigid slip
  per rolled distance at (x, y) of the rolling frame is

      w_x = ξ − φ y,   w_y = η + φ x.

* The **slip** s (per rolled distance, dimensionless) of body 2 relative to
  body 1, u the relative tangential displacement u_2 − u_1 of the surfaces:
  steady state s = w − ∂u/∂x; transient, over a rolled distance Δq,
  s Δq = w Δq + u(x, t) − u(x + Δq, t − Δt) (the material now at x was at
  x + Δq).  Stick: s = 0 with |p_t| ≤ μ p_n; slip: p_t = −μ p_n s/|s| (the
  traction on body 2 opposes its slip).  So the creep force on body 2 is
  opposite to the creepage: F_x = −G c² C11 ξ for small ξ.

In the augmented-Lagrangian law (:class:`~bemcontact.contact.law.CoulombLaw`)
the stick reference of a node becomes the convected field: transient,
k_ref(x) = k_t(x + Δq) − Δq w(x) from the previous increment's solution;
steady, the same with the current solution and Δq one cell (upwind, first
order in the cell size), so that the Jacobian of the tangential rows gains
(I − S), S the upstream shift.

A tangential component that the supports control by force is solved for:
its creepage (steady) or its rigid shift (transient) is the unknown that
carries the force."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..settings import Key, check_settings, setting

MODES = ("steady", "transient")


def _vector(owner: str, name: str, value, length: int) -> tuple[float, ...]:
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ConfigError(f"{owner}.{name} must be {length} numbers, got {value!r}",
                          location={"field": f"rolling.{name}"}) from None
    if v.size != length or not np.all(np.isfinite(v)) or isinstance(value, (str, bytes)):
        raise ConfigError(f"{owner}.{name} must be {length} finite numbers, got {value!r}",
                          location={"field": f"rolling.{name}"})
    return tuple(float(x) for x in v)


@dataclass(frozen=True)
class Rolling:
    """How a load step rolls the bodies (see the module docstring for the
    conventions).  ``direction`` (3,) the rolling direction in global
    coordinates (normalized here; it must be tangent to the contact);
    ``creepage`` (ξ, η); ``spin`` φ; ``mode`` ``"steady"`` or
    ``"transient"``; ``distance`` the rolled distance Δq per increment
    (transient only, required there); ``speed`` V (optional: the frictional
    power is the work per rolled distance times V)."""

    direction: tuple = (1.0, 0.0, 0.0)
    creepage: tuple = (0.0, 0.0)
    spin: float = setting(Key(
        "spin", "number", "the spin φ of body 2 relative to body 1 about the contact normal, "
        "per rolling speed (rad per length)", default=0.0))
    mode: str = setting(Key(
        "mode", "string", "steady-state rolling (no history: the Eulerian slip) or transient "
        "(the previous increment's field convected by `distance`)", default="steady",
        choices=MODES))
    distance: float | None = setting(Key(
        "distance", "number", "the rolled distance per increment (a length; transient rolling "
        "only, required there)", default=None, lo=0.0, lo_open=True))
    speed: float | None = setting(Key(
        "speed", "number", "the rolling speed V (length per time), for the frictional power; "
        "without it the power is reported per unit speed", default=None, lo=0.0,
        lo_open=True))

    def __post_init__(self) -> None:
        check_settings(self)
        d = np.array(_vector("Rolling", "direction", self.direction, 3))
        norm = float(np.linalg.norm(d))
        if norm == 0.0:
            raise ConfigError("Rolling.direction must not be zero, got [0, 0, 0]",
                              location={"field": "rolling.direction"})
        object.__setattr__(self, "direction", tuple(float(x) for x in d / norm))
        object.__setattr__(self, "creepage", _vector("Rolling", "creepage", self.creepage, 2))
        if self.mode == "transient" and self.distance is None:
            raise ConfigError("Rolling: mode = \"transient\" needs the rolled distance per "
                              "increment (distance = Δq, a length)",
                              location={"field": "rolling.distance"})
        if self.mode == "steady" and self.distance is not None:
            raise ConfigError("Rolling: distance is the rolled distance per increment of "
                              "transient rolling; steady-state rolling has none (remove it or "
                              "set mode = \"transient\")", location={"field": "rolling.distance"})

    def frame(self, normal) -> np.ndarray:
        """(3, 3) rows x_r, y_r, n of the rolling frame for the contact normal
        ``normal`` (3,); a direction not tangent to the contact (more than
        1e-6 rad off) is a one-line ConfigError."""
        n = np.asarray(normal, dtype=float)
        n = n / np.linalg.norm(n)
        x = np.asarray(self.direction)
        off = abs(float(x @ n))
        if off > 1e-6:
            angle = math.degrees(math.asin(min(off, 1.0)))
            raise ConfigError(f"rolling.direction {np.round(x, 6).tolist()} (normalized) is not "
                              "tangent to the "
                              f"contact (normal {np.round(n, 6).tolist()}; {angle:.3g} degrees "
                              "off the plane): give a direction in the contact plane",
                              location={"field": "rolling.direction"})
        return np.array([x, np.cross(n, x), n])

    def rigid_slip(self, xy: np.ndarray) -> np.ndarray:
        """(m, 2) Kalker's rigid slip per rolled distance (w_x, w_y) at the
        points ``xy`` (m, 2) of the rolling frame."""
        xi, eta = self.creepage
        w = np.empty((len(xy), 2))
        w[:, 0] = xi - self.spin * xy[:, 1]
        w[:, 1] = eta + self.spin * xy[:, 0]
        return w


def rolling_quantities(xy: np.ndarray, p: np.ndarray, slip: np.ndarray, area,
                       closed: np.ndarray, stick: np.ndarray, speed: float | None) -> dict:
    """JSON-ready per step: the creep force (F_x, F_y) on body 2 and the
    spin moment M_z about the rolling frame's origin, from the tractions
    ``p`` (m, 3) in rolling-frame components at the points ``xy`` (m, 2) of
    area ``area``; the frictional work per rolled distance Σ −p_t·s A (≥ 0,
    ``slip`` (m, 2) per rolled distance) and the power (times ``speed``);
    the adhesion and slip areas and the force ratios to μ F_n."""
    a = np.broadcast_to(np.asarray(area, dtype=float), (len(xy),))
    fx, fy = float(a @ p[:, 0]), float(a @ p[:, 1])
    mz = float(a @ (xy[:, 0] * p[:, 1] - xy[:, 1] * p[:, 0]))
    density = -np.einsum("ij,ij->i", p[:, :2], slip)
    work = float(a @ np.where(closed, density, 0.0))
    out = {
        "creep_force": [fx, fy],
        "spin_moment": mz,
        "frictional_work_per_distance": work,
        "frictional_power": None if speed is None else work * speed,
        "adhesion_area": float(a[stick].sum()),
        "slip_area": float(a[closed & ~stick].sum()),
    }
    return out





class FrameRolling:
    """The rolling of one load step on the full path's frame nodes: the
    upwind interpolation S (the field at x + Δq e_r, linear on a Delaunay
    triangulation of each pair's active nodes in its rolling plane, zero
    upstream of them), the rigid slip of each node and the rolled distance.

    ``points`` (m, 3) the active frame nodes (every pair's, stacked), ``Q``
    (m, 3, 3) their local bases (columns t1, t2, n, as
    :attr:`~bemcontact.contact.frames.FrameSet.Q`), ``size`` (m,) their frame
    element sizes, ``weights`` (m,) their areas, ``pair_of`` (m,) their pair.
    Per pair the rolling frame is the pair's mean normal's (a direction not
    tangent to it is a one-line ConfigError), its origin the node of the
    smallest initial ``gap`` (m,) (the first touch, as the grid's origin is
    its surfaces' closest point; without ``gap`` the nodes' area centroid); steady state rolls by Δq = the 5th percentile of the
    pair's node sizes (one upwind step of the contact's element size, first
    order in it), transient by ``distance``.  A
    tangential vector interpolated from node j to node i is rotated from
    j's local basis into i's."""

    def __init__(self, rolling: Rolling, points, Q, size, weights, pair_of, gap=None) -> None:
        import scipy.sparse
        import scipy.spatial

        self.rolling = rolling
        self.steady = rolling.mode == "steady"
        Q = np.swapaxes(np.asarray(Q, dtype=float), 1, 2)  # rows t1, t2, n
        m = len(points)
        self.m = m
        self.distance = np.zeros(m)
        #: (m, 2) Kalker's rigid slip per rolled distance in each node's (t1, t2)
        self.w = np.zeros((m, 2))
        #: (m, 2) each node's position in its pair's rolling frame
        self.xy = np.zeros((m, 2))
        #: (m, 2, 3) each node's rolling frame rows x_r, y_r (global)
        self.frames = np.zeros((m, 2, 3))
        #: (m, 3) each node's rolling frame origin (its pair's, global)
        self.origins = np.zeros((m, 3))
        rows, cols, vals = [], [], []
        for p in np.unique(pair_of):
            idx = np.flatnonzero(pair_of == p)
            normal = Q[idx, 2].mean(axis=0)
            frame = rolling.frame(normal / np.linalg.norm(normal))
            centre = (weights[idx] @ points[idx] / weights[idx].sum() if gap is None
                      else points[idx[int(np.argmin(np.asarray(gap)[idx]))]])
            xy = (points[idx] - centre) @ frame[:2].T
            # steady: one upwind step of the contact's own element size (a
            # graded mesh's finest nodes are at the contact: the 5th percentile)
            dq = float(np.percentile(size[idx], 5.0)) if self.steady else float(rolling.distance)
            self.distance[idx] = dq
            self.xy[idx] = xy
            self.frames[idx] = frame[:2]
            self.origins[idx] = centre
            w_global = rolling.rigid_slip(xy) @ frame[:2]
            self.w[idx] = np.einsum("nij,nj->ni", Q[idx, :2], w_global)
            tri = scipy.spatial.Delaunay(xy)
            up = xy + np.array([dq, 0.0])
            simplex = tri.find_simplex(up)
            inside = simplex >= 0
            T = tri.transform[simplex[inside]]
            b = np.einsum("nij,nj->ni", T[:, :2], up[inside] - T[:, 2])
            bary = np.column_stack([b, 1.0 - b.sum(axis=1)])
            corners = tri.simplices[simplex[inside]]
            for i_loc, cs, bs in zip(np.flatnonzero(inside), corners, bary):
                i = idx[i_loc]
                for j_loc, beta in zip(cs, bs):
                    if abs(beta) < 1e-14:
                        continue
                    j = idx[j_loc]
                    R = Q[i, :2] @ Q[j, :2].T  # j's (t1, t2) into i's
                    for a in range(2):
                        for c in range(2):
                            rows.append(2 * i + a)
                            cols.append(2 * j + c)
                            vals.append(beta * R[a, c])
        #: (2m, 2m) sparse: (S u)_i = u(x_i + Δq e_r) in i's basis, u flattened (m, 2)
        self.S = scipy.sparse.csr_array((vals, (rows, cols)), shape=(2 * m, 2 * m))

    def shift(self, u: np.ndarray) -> np.ndarray:
        """(m, 2) -> (m, 2): S u."""
        return (self.S @ u.reshape(-1)).reshape(-1, 2)

    def reference(self, k_t: np.ndarray) -> np.ndarray:
        """Transient: the stick reference S k_t − Δq w from the previous
        increment's relative tangential displacement ``k_t`` (m, 2)."""
        return self.shift(k_t) - self.distance[:, None] * self.w

    def to_rolling(self, t: np.ndarray, Q) -> np.ndarray:
        """(m, 2) local (t1, t2) components -> each node's rolling frame."""
        g = np.einsum("nji,ni->nj", Q[:, :, :2], t)  # Q's columns t1, t2
        return np.einsum("nij,nj->ni", self.frames, g)


__all__ = ["MODES", "FrameRolling", "Rolling", "rolling_quantities"]

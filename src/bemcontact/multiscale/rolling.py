"""Rolling on the contact grid: the upstream shift S of a cell field along
the rolling direction, the rigid slip of each cell, and the convected slip
the law sees (conventions: :mod:`bemcontact.contact.rolling`).

The rolling direction lies along one of the grid's axes (±t1 or ±t2), so a
shift by whole cells is an index shift and a fraction of a cell is a linear
(upwind) interpolation between the two upstream cells.  Upstream of the
grid's leading row the field is taken as zero: that row is outside the
contact (the grid covers the contact with a margin, and a contact that
reaches the grid's edge is refused), so no closed cell's reference uses it.

* Steady state: the law of a cell sees k̃_t = (I − S) u_t + h w + d_t, with
  u_t = (C p)_t, S the one-cell shift, h the cell size along the rolling
  direction (CONTACT's steady-state discretization), and d_t the unknown
  extra creepage times h of a tangential component controlled by force.
* Transient: the stick reference is S_Δq k_t^prev − Δq w (the previous
  increment's converged field shifted by the rolled distance)."""

from __future__ import annotations

import numpy as np

from ..contact.rolling import Rolling
from ..errors import ConfigError
from ..halfspace import Grid


class GridRolling:
    """The rolling of one load step on ``grid`` (frame ``axes`` rows t1, t2,
    n in global coordinates): ``rolling`` the step's :class:`Rolling`.

    ``spin_offset``: the rigid slip of the spin taken at x + offset · h along
    the rolling direction instead of at the cell centre (CONTACT's
    steady-state solver takes 1/6; both converge to the same limit, at first
    order in h)."""

    def __init__(self, rolling: Rolling, grid: Grid, axes: np.ndarray,
                 spin_offset: float = 0.0) -> None:
        self.rolling = rolling
        self.grid = grid
        frame = rolling.frame(axes[2])  # rows x_r, y_r, n (global)
        local = frame[:2] @ axes[:2].T  # x_r, y_r in (t1, t2) components
        a = int(np.argmax(np.abs(local[0])))
        if abs(local[0, a]) < 1.0 - 1e-9:
            raise ConfigError(f"rolling.direction {np.round(frame[0], 6).tolist()} is not along an "
                              "axis of the contact grid (its axes are "
                              f"{np.round(axes[0], 6).tolist()} and "
                              f"{np.round(axes[1], 6).tolist()}): method = \"multiscale\" rolls "
                              "along one of them", location={"field": "rolling.direction"})
        #: the grid axis (0 or 1) and the sign of the rolling direction on it
        self.axis = a
        self.sign = int(np.sign(local[0, a]))
        #: (2, 2) rows x_r, y_r in the frame's (t1, t2) components
        self.local = np.round(local)
        self.h = grid.dx if a == 0 else grid.dy
        self.steady = rolling.mode == "steady"
        self.distance = self.h if self.steady else float(rolling.distance)
        #: (n, 2) the cell centres in the rolling frame (origin: the contact centre)
        self.xy = grid.centres[:, :2] @ self.local.T
        #: (n, 2) Kalker's rigid slip per rolled distance, frame (t1, t2) components
        self.w = rolling.rigid_slip(self.xy) @ self.local
        if spin_offset:
            self.w[:, :] += (spin_offset * self.h * rolling.spin) * self.local[1]

    def to_rolling(self, f: np.ndarray) -> np.ndarray:
        """(n, 2) frame (t1, t2) components -> rolling-frame (x_r, y_r)."""
        return f @ self.local.T

    def shift(self, f: np.ndarray, distance: float | None = None) -> np.ndarray:
        """(n, c) -> (n, c): (S f)(x) = f(x + Δq e_r), Δq = ``distance``
        (default one cell), linear between cells, zero upstream of the grid."""
        q = (self.h if distance is None else distance) / self.h
        m = int(np.floor(q + 1e-12))
        theta = q - m
        out = (1.0 - theta) * self._whole(f, m)
        if theta > 1e-12:
            out += theta * self._whole(f, m + 1)
        return out

    def _whole(self, f: np.ndarray, m: int) -> np.ndarray:
        nx, ny = self.grid.shape
        F = f.reshape(nx, ny, -1)
        out = np.zeros_like(F)
        if m == 0:
            return F.reshape(f.shape).copy()
        step = self.sign * m
        size = F.shape[self.axis]
        if abs(step) < size:
            src = [slice(None)] * 2
            dst = [slice(None)] * 2
            if step > 0:
                src[self.axis], dst[self.axis] = slice(step, None), slice(0, size - step)
            else:
                src[self.axis], dst[self.axis] = slice(0, size + step), slice(-step, None)
            out[tuple(dst)] = F[tuple(src)]
        return out.reshape(f.shape)

    def difference(self, u: np.ndarray) -> np.ndarray:
        """(n, 2) -> (n, 2): (I − S) u, S the one-cell shift."""
        return u - self.shift(u)

    def undifference(self, v: np.ndarray) -> np.ndarray:
        """(n, 2) -> (n, 2): (I − S)⁻¹ v, the sum of ``v`` over the cell and
        every cell upstream of it along the rolling direction."""
        nx, ny = self.grid.shape
        V = v.reshape(nx, ny, -1)
        if self.sign > 0:
            out = np.flip(np.cumsum(np.flip(V, self.axis), axis=self.axis), self.axis)
        else:
            out = np.cumsum(V, axis=self.axis)
        return out.reshape(v.shape)

    def convected(self, u: np.ndarray) -> np.ndarray:
        """Steady state: (n, 2) the slip per shift that the law sees for the
        relative tangential displacement ``u`` (n, 2): (I − S) u + h w."""
        return self.difference(u) + self.h * self.w

    def reference(self, k_t: np.ndarray) -> np.ndarray:
        """Transient: (n, 2) the stick reference from the previous
        increment's relative tangential displacement ``k_t`` (n, 2):
        S_Δq k_t − Δq w."""
        return self.shift(k_t, self.distance) - self.distance * self.w

    def neighbour_offset(self) -> tuple[int, int]:
        """The (Δi, Δj) of the upstream cell (the block of S C on a cell's
        own traction is C's block at this offset)."""
        return (self.sign, 0) if self.axis == 0 else (0, self.sign)


__all__ = ["GridRolling"]

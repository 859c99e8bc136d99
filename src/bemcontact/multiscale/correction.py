"""A finite body's correction to the half-space flexibility on the contact
grid, from the body's own coarse BEM model (singular subtraction).

A point force F at a source s on the contact plane loads the body.  Its
displacement is the half-space field of that force (Boussinesq–Cerruti,
the half-space tangent to the body at the contact, the body on its side)
plus a remainder: the body's response to what the half-space field violates
on the body's boundary, the traction −σ_hs·n on its free surface (zero on a
flat contact face, the plane itself) and the displacement −u_hs on its
supports.  That data is smooth wherever it lies far from the source compared
with the contact zone, so the body's coarse mesh resolves it, and the
remainder is smooth on the contact zone: a low-degree polynomial in the
observation point and, over a few Chebyshev anchors, in the source point.
The correction is then of low rank (≤ 3 p² × 6 for p × p anchors and a
quadratic fit).

Frames.  The grid's frame (origin, axes t1, t2, n: n from body 1 into body
2) carries the pair; a body's local frame has z into the body: body 2's is
the grid's, body 1's the grid's seen through diag(1, −1, −1).  Local fields
use the half-space conventions of :mod:`bemcontact.halfspace.influence`.

The correction estimates its own error: the anchors' interpolant against a
direct solve for check sources off the anchors, and the fit's residual at
the mesh nodes it was fitted to, relative to the body's whole flexibility on
the grid (:attr:`BodyCorrection.estimate`)."""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.linalg

from ..errors import ConfigError
from ..halfspace import Compliance, Grid, HalfSpaceOperator, rectangle_stresses
from ..linalg import LinearSolverOptions
from .operator import ToeplitzOperator

#: Local frame of body 1 relative to the grid's frame (per component).
MIRROR = np.array([1.0, -1.0, -1.0])


def point_load_displacements(X: np.ndarray, shear_modulus: float,
                             poisson_ratio: float) -> np.ndarray:
    """(m, 3, 3): the displacement at local points ``X`` (m, 3), depth z ≥ 0,
    per unit point force at the origin along local x, y, z (columns), of a
    half-space (Boussinesq and Cerruti; Johnson §3.2; at z = 0 they are the
    surface kernels of :mod:`bemcontact.halfspace.influence`)."""
    G, nu = shear_modulus, poisson_ratio
    x, y, z = X[:, 0], X[:, 1], np.maximum(X[:, 2], 0.0)
    rho = np.sqrt(x * x + y * y + z * z)
    rz = rho + z
    c = 1.0 / (4.0 * math.pi * G)
    k = 1.0 - 2.0 * nu
    out = np.empty((X.shape[0], 3, 3))
    # Boussinesq (force along z, into the body)
    out[:, 0, 2] = c * (x * z / rho**3 - k * x / (rho * rz))
    out[:, 1, 2] = c * (y * z / rho**3 - k * y / (rho * rz))
    out[:, 2, 2] = c * (z * z / rho**3 + 2.0 * (1.0 - nu) / rho)
    # Cerruti (force along x; along y by symmetry)
    for j, (a, b) in enumerate(((x, y), (y, x))):
        ua = c * (1.0 / rho + a * a / rho**3 + k * (1.0 / rz - a * a / (rho * rz * rz)))
        ub = c * (a * b / rho**3 - k * a * b / (rho * rz * rz))
        uz = c * (a * z / rho**3 + k * a / (rho * rz))
        out[:, j, j], out[:, 1 - j, j], out[:, 2, j] = ua, ub, uz
    return out


def _voigt_times(s: np.ndarray, n: np.ndarray) -> np.ndarray:
    """σ·n for Voigt rows (xx, yy, zz, xy, yz, xz): s (m, 6, 3) per force
    direction, n (m, 3) -> (m, 3, 3) traction per force direction."""
    xx, yy, zz, xy, yz, xz = (s[:, i, :] for i in range(6))
    nx, ny, nz = (n[:, i, None] for i in range(3))
    return np.stack([xx * nx + xy * ny + xz * nz,
                     xy * nx + yy * ny + yz * nz,
                     xz * nx + yz * ny + zz * nz], axis=1)


def near_share(r: np.ndarray, radius: float) -> np.ndarray:
    """The near field's share of a curved face's residual traction at plane
    distance ``r`` from the source: 1 within half the ``radius``, 0 beyond
    it, a cosine taper between; the coarse data take the rest (1 − this).
    A step at the radius made each node's datum jump on or off as the
    source moved, which left the anchors' interpolation a 3-5 % error."""
    x = np.clip((np.asarray(r, dtype=float) / radius - 0.5) / 0.5, 0.0, 1.0)
    return 0.5 * (1.0 + np.cos(math.pi * x))


def near_field_blocks(grid: Grid, shear_modulus: float, poisson_ratio: float,
                      curvature: tuple[float, float], radius: float) -> np.ndarray:
    """(2nx − 1, 2ny − 1, 3, 3) the curved surface's near field (local
    components): the displacement at each cell offset per unit traction on
    a cell, of the traction −σ_hs·n that the half-space field of that cell
    leaves on a surface curved as ``curvature`` (κ_x, κ_y: depth
    ½ (κ_x x² + κ_y y²) from the plane tangent at the loaded cell) within
    ``radius`` of it, spread by the half-space operator, plus the
    half-space field of the cell read on that surface instead of on the
    plane (the cell's point force at the offset, at the surface's depth,
    less on the plane).  First order in κ a; for a surface of uniform
    curvature it depends on the offset only."""
    nx, ny = grid.shape
    big = Grid.centred(2 * nx - 1, 2 * ny - 1, grid.dx, grid.dy)
    c = big.centres
    kx, ky = curvature
    depth = 0.5 * (kx * c[:, 0] ** 2 + ky * c[:, 1] ** 2)
    n_out = np.stack([kx * c[:, 0], ky * c[:, 1], -np.ones(c.shape[0])], axis=1)
    n_out /= np.linalg.norm(n_out, axis=1)[:, None]
    hx, hy = 0.5 * grid.dx, 0.5 * grid.dy
    floor = 1e-6 * min(hx, hy)
    inside = (np.hypot(c[:, 0], c[:, 1]) <= radius) & (depth > floor)
    t = np.zeros((c.shape[0], 3, 3))
    sig = rectangle_stresses(c[inside, 0], c[inside, 1], depth[inside], hx, hy, poisson_ratio)
    t[inside] = -_voigt_times(sig, n_out[inside]) * near_share(
        np.hypot(c[inside, 0], c[inside, 1]), radius)[:, None, None]
    op = HalfSpaceOperator(big, Compliance.half_space(shear_modulus, poisson_ratio))
    u = np.stack([op.matvec(t[:, :, j]) for j in range(3)], axis=-1)  # (cells, comp, dir)
    # the body's surface lies `depth` inside the half-space tangent at the
    # loaded cell: the half-space field itself is read there, not on the
    # plane (to first order d ∂u/∂z = −d ∇_s u_z tangentially: as large as
    # the traction term in the tangential components; zero in u_z under a
    # normal load, whose surface divergence vanishes off the load)
    X = np.column_stack([c[inside, :2], depth[inside]])
    plane = X.copy()
    plane[:, 2] = 0.0
    u[inside] += grid.cell_area * (point_load_displacements(X, shear_modulus, poisson_ratio)
                                   - point_load_displacements(plane, shear_modulus,
                                                              poisson_ratio))
    return u.reshape(2 * nx - 1, 2 * ny - 1, 3, 3)


def chebyshev_points(p: int) -> np.ndarray:
    """The p Chebyshev points of the first kind on [−1, 1]."""
    return np.cos((2.0 * np.arange(p) + 1.0) * math.pi / (2.0 * p))[::-1]


def lagrange_weights(nodes: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(len(t), p) the Lagrange basis of ``nodes`` at ``t``."""
    L = np.ones((t.size, nodes.size))
    for i, xi in enumerate(nodes):
        for j, xj in enumerate(nodes):
            if i != j:
                L[:, i] *= (t - xj) / (xi - xj)
    return L


def _basis(xy: np.ndarray, centre: np.ndarray, scale: float) -> np.ndarray:
    """(m, 6) the quadratic monomials of the scaled local position."""
    u = (xy[:, 0] - centre[0]) / scale
    v = (xy[:, 1] - centre[1]) / scale
    return np.stack([np.ones_like(u), u, v, u * u, u * v, v * v], axis=1)


class BodyCorrection:
    """The correction of one body (see the module docstring).

    ``body``: an :class:`~bemcontact.bem.ElasticBody` (its coarse model, its
    boundary conditions: supports held, free surfaces free); ``side``: 1 or
    2, the body's side of the pair; ``origin`` (3,) and ``axes`` (3, 3, rows
    t1, t2, n) the grid's frame in global coordinates; ``grid`` the contact
    grid (in that frame); ``anchors`` p (p × p Chebyshev sources over the
    grid); ``fit_radius`` the radius (frame plane) of the nodes the
    remainder is fitted on (default twice the grid's half-diagonal, at
    least the 24 nearest nodes)."""

    def __init__(self, body, side: int, origin, axes, grid: Grid, anchors: int = 3,
                 fit_radius: float | None = None, threads: int | None = None,
                 curvature: tuple[float, float] = (0.0, 0.0)) -> None:
        if side not in (1, 2):
            raise ConfigError(f"BodyCorrection: side must be 1 or 2, got {side!r}")
        if not (isinstance(anchors, int) and 2 <= anchors <= 8):
            raise ConfigError(f"BodyCorrection: anchors must be an integer in [2, 8], got "
                              f"{anchors!r}")
        t0 = time.perf_counter()
        self.body, self.side, self.grid, self.p = body, side, grid, anchors
        self.origin = np.asarray(origin, dtype=float)
        self.axes = np.asarray(axes, dtype=float)
        self.flip = np.ones(3) if side == 2 else MIRROR
        d = body.discretization
        X = ((d.points - self.origin) @ self.axes.T) * self.flip
        n = (d.normals @ self.axes.T) * self.flip
        self._X, self._n = X, n
        mat = body.material
        self.G, self.nu = mat.shear_modulus, mat.poisson_ratio
        known_u, _ = body.boundary_data()
        if not known_u.any():
            raise ConfigError(f"{body.name}: the multiscale correction needs a support (a "
                              "prescribed displacement or a platen): a floating body's remainder "
                              "problem is singular")
        self._known = known_u
        # the sources: p x p Chebyshev points over the grid (local coordinates)
        half = 0.5 * np.array([grid.nx * grid.dx, grid.ny * grid.dy])
        mid = np.array(grid.origin) + half
        self._mid_frame, self._half = mid, half
        cheb = chebyshev_points(anchors)
        self._cheb = cheb
        sx, sy = np.meshgrid(mid[0] + half[0] * cheb, mid[1] + half[1] * cheb, indexing="ij")
        anchors_frame = np.stack([sx.ravel(), sy.ravel()], axis=1)
        checks_frame = mid + half * np.array([[0.37, -0.61], [-0.83, 0.29]])
        sources = np.vstack([anchors_frame, checks_frame])
        self._hw = 0.5 * min(grid.dx, grid.dy)
        # a curved contact face: its near field on the grid (Toeplitz), the
        # coarse data leaving out what it covers
        self.curvature = (float(curvature[0]), float(curvature[1]))
        # the near field loads the cells of its (2nx − 1) × (2ny − 1) window
        # about each source: the coarse data leave out what lies within it
        self.near_radius = min((grid.nx - 1) * grid.dx, (grid.ny - 1) * grid.dy)
        self._near = None
        self.near_blocks = None
        if any(self.curvature):
            blocks = near_field_blocks(grid, self.G, self.nu, self.curvature, self.near_radius)
            if side == 1:
                blocks = blocks[:, ::-1]
            self._near = ToeplitzOperator(grid, blocks)
            #: the near field's blocks in the grid frame's terms (its part of
            #: the relative displacement): :class:`~.operator.PairOperator`
            #: adds them to the half-space kernels, one FFT product for all
            F = np.diag(self.flip)
            self.near_blocks = np.einsum("ij,xyjk,kl->xyil", F, blocks, F)
        # the fit's nodes: within the radius of the grid's centre
        r_plane = np.sqrt((X[:, 0] - mid[0]) ** 2 + (X[:, 1] - self.flip[1] * mid[1]) ** 2
                          + X[:, 2] ** 2)
        radius = 2.0 * float(np.hypot(*half)) if fit_radius is None else float(fit_radius)
        order = np.argsort(r_plane)
        near = r_plane <= radius
        if near.sum() < 24:
            near = np.zeros(X.shape[0], dtype=bool)
            near[order[:24]] = True
        self._fit_nodes = np.flatnonzero(near)
        self.fit_radius = float(r_plane[self._fit_nodes].max())
        # one coarse solve for every source and direction
        W = np.concatenate([self._data(s) for s in sources], axis=1)
        lin = LinearSolverOptions(method="dense")
        A, BW, _, _ = body.mixed_system(known_u, W, lin, threads, border=0)
        lu = scipy.linalg.lu_factor(A, overwrite_a=True, check_finite=False)
        x = scipy.linalg.lu_solve(lu, BW, check_finite=False)
        u = np.where(known_u[:, None], W, x)  # (3N, 3 S): the remainder's displacement
        # back to local components at the fit nodes: (S, 3 dirs, nodes, 3)
        S = sources.shape[0]
        U = u.reshape(-1, 3, S, 3)  # (N, comp, S, dir) in global components
        Ul = np.einsum("nksd,jk->sdnj", U[self._fit_nodes], self.axes) * self.flip
        xy = X[self._fit_nodes, :2]
        self._centre = np.array([mid[0], self.flip[1] * mid[1]])
        self._scale = float(np.hypot(*half))
        Phi = _basis(xy, self._centre, self._scale)
        coef, *_ = np.linalg.lstsq(Phi, Ul.reshape(S * 3, -1, 3).transpose(1, 0, 2)
                                   .reshape(xy.shape[0], -1), rcond=None)
        fitted = Phi @ coef
        resid = fitted - Ul.reshape(S * 3, -1, 3).transpose(1, 0, 2).reshape(xy.shape[0], -1)
        coef = coef.reshape(6, S, 3, 3)  # (term, source, dir, comp)
        self._coef = coef[:, : anchors * anchors]
        # the estimates: the anchors' interpolant at the check sources, and the fit
        cells = self._cells_local(grid.centres)
        Phi_g = _basis(cells[:, :2], self._centre, self._scale)
        direct = np.einsum("im,msdc->sidc", Phi_g, coef[:, anchors * anchors:])
        Lc = self._source_weights(checks_frame)
        interp = np.einsum("sa,im,madc->sidc", Lc, Phi_g, self._coef)
        self.magnitude = max(float(np.abs(direct).max()), 1e-300)
        # both relative to the body's whole flexibility on the grid (the
        # half-space's point-load blocks plus the correction, the mean over
        # the cells of each block's largest entry, the source's own cell left
        # out): an error of the correction moves the contact's solution in
        # that proportion, not in proportion to the correction alone
        s_local = np.column_stack([checks_frame[:, 0], self.flip[1] * checks_frame[:, 1]])
        R = cells[None, :, :2] - s_local[:, None, :]
        own = np.hypot(R[..., 0], R[..., 1]) < 0.5 * min(grid.dx, grid.dy)
        Rz = np.concatenate([R, np.zeros(R.shape[:2] + (1,))], axis=-1).reshape(-1, 3)
        Rz[own.ravel()] = [grid.dx, 0.0, 0.0]  # any finite value: left out below
        hs = point_load_displacements(Rz, self.G, self.nu).reshape(*R.shape[:2], 3, 3)
        whole = np.abs(hs.transpose(0, 1, 3, 2) + direct).max(axis=(2, 3))
        self.whole = max(float(whole[~own].mean()), 1e-300)
        self.anchor_error = float(np.abs(interp - direct).max()) / self.whole
        self.fit_error = float(np.sqrt(np.mean(resid**2))) / self.whole
        self._Phi_cells = Phi_g
        self._L_cells = self._source_weights(grid.centres[:, :2])
        self.seconds = time.perf_counter() - t0

    @property
    def estimate(self) -> float:
        """The correction's relative error estimate: the larger of the
        anchors' interpolation error at the check sources (largest entry)
        and the fit's rms residual at its nodes, both relative to the body's
        whole flexibility on the grid (:attr:`whole`: the mean over the cells
        of the largest entry of the half-space's point-load block plus the
        correction, per unit force), the proportion in which such an error
        moves the contact's solution."""
        return max(self.anchor_error, self.fit_error)

    def _cells_local(self, centres: np.ndarray) -> np.ndarray:
        return centres * self.flip

    def _source_weights(self, xy_frame: np.ndarray) -> np.ndarray:
        """(m, p²) the anchors' tensor Lagrange weights at frame points."""
        t = (xy_frame - self._mid_frame) / self._half
        Lx = lagrange_weights(self._cheb, t[:, 0])
        Ly = lagrange_weights(self._cheb, t[:, 1])
        return (Lx[:, :, None] * Ly[:, None, :]).reshape(t.shape[0], -1)

    def _data(self, source_frame: np.ndarray) -> np.ndarray:
        """(3N, 3): the remainder problem's boundary values for a unit force
        at ``source_frame`` (x, y) along each local direction: −u_hs on the
        prescribed-displacement dofs, −σ_hs·n elsewhere (global components)."""
        s_local = np.array([source_frame[0], self.flip[1] * source_frame[1], 0.0])
        R = self._X - s_local
        u = point_load_displacements(R, self.G, self.nu)  # (N, 3, 3)
        depth = R[:, 2]
        floor = 1e-6 * self._hw
        area = 4.0 * self._hw * self._hw
        sig = rectangle_stresses(R[:, 0], R[:, 1], np.maximum(depth, floor), self._hw,
                                 self._hw, self.nu) / area  # per unit force
        t = _voigt_times(sig, self._n)
        # on the contact plane the half-space field is traction free (away
        # from the source's own cell); a curved face's near field is the
        # Toeplitz part's
        t[depth <= floor] = 0.0
        if self._near is not None:
            face = self._n[:, 2] < -0.5
            t[face] *= 1.0 - near_share(np.hypot(R[face, 0], R[face, 1]),
                                        self.near_radius)[:, None, None]
        # local components -> global, then per global dof its kind of datum
        def glob(v):
            return np.einsum("nkd,kj->njd", v * self.flip[None, :, None], self.axes)

        g = np.where(self._known.reshape(-1, 3)[:, :, None], glob(-u), glob(-t))
        return g.reshape(-1, 3)

    def matvec(self, p: np.ndarray) -> np.ndarray:
        """(n, 3) frame tractions on body 2 -> (n, 3) this body's part of the
        relative displacement's correction (:meth:`low_rank` plus the near
        field of a curved face)."""
        out = self.low_rank(p)
        if self._near is not None:
            sign = 1.0 if self.side == 2 else -1.0
            out = out + sign * self._near.matvec(sign * p * self.flip) * self.flip
        return out

    def low_rank(self, p: np.ndarray) -> np.ndarray:
        """The remainder's part of :meth:`matvec` (rank ≤ 3 p² × 6)."""
        sign = 1.0 if self.side == 2 else -1.0
        tl = sign * p * self.flip  # the traction on this body, local
        w = self.grid.cell_area * (self._L_cells.T @ tl)  # (p², 3)
        ul = self._Phi_cells @ np.einsum("ad,madc->mc", w, self._coef)
        return sign * ul * self.flip


__all__ = ["BodyCorrection", "chebyshev_points", "lagrange_weights",
           "point_load_displacements"]

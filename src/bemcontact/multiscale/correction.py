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
import scipy.fft
import scipy.linalg

from ..errors import ConfigError
from ..halfspace import Compliance, Grid, HalfSpaceOperator, rectangle_stresses
from ..halfspace.influence import blocks_from_integrals, rectangle_integrals
from .coarse import coarse_solve
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


def near_field_tractions(grid: Grid, poisson_ratio: float, curvature: tuple[float, float],
                         radius: float):
    """(window, t, depth, inside): the (2nx − 1) × (2ny − 1) window of cell
    offsets (a :class:`Grid` centred on the loaded cell), (cells, 3, 3) the
    near field's share
    (:func:`near_share`) of the residual traction −σ_hs·n (local components,
    per unit traction on the loaded cell along each local direction) that
    the half-space field of a cell leaves on a surface curved as
    ``curvature`` (κ_x, κ_y: depth ½ (κ_x x² + κ_y y²) from the plane
    tangent at the loaded cell) within ``radius`` of it, the surface's depth
    at the window's cells and the cells within the radius that carry it."""
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
    return big, t, depth, inside


def near_field_blocks(grid: Grid, shear_modulus: float, poisson_ratio: float,
                      curvature: tuple[float, float], radius: float) -> np.ndarray:
    """(2nx − 1, 2ny − 1, 3, 3) the curved surface's near field (local
    components): the displacement at each cell offset per unit traction on
    a cell, of the near field's share of the residual traction
    (:func:`near_field_tractions`) spread by the half-space operator, plus
    the half-space field of the cell read on that surface instead of on the
    plane (the cell's point force at the offset, at the surface's depth,
    less on the plane).  First order in κ a; for a surface of uniform
    curvature it depends on the offset only."""
    nx, ny = grid.shape
    big, t, depth, inside = near_field_tractions(grid, poisson_ratio, curvature, radius)
    c = big.centres
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


def _inside(g: Grid, xy: np.ndarray) -> np.ndarray:
    """Whether frame points ``xy`` (m, 2) lie on the grid."""
    lo = np.array(g.origin)
    hi = lo + [g.nx * g.dx, g.ny * g.dy]
    return np.all((xy >= lo) & (xy < hi), axis=1)


def _cell_of(g: Grid, xy: np.ndarray) -> np.ndarray:
    """The index of the cell holding each frame point ``xy`` (m, 2)."""
    r = xy - np.array(g.origin)
    i = np.clip(np.floor(r[:, 0] / g.dx).astype(int), 0, g.nx - 1)
    j = np.clip(np.floor(r[:, 1] / g.dy).astype(int), 0, g.ny - 1)
    return i * g.ny + j


#: Nodes farther from the loaded cells' centre than this many times their
#: radius see the tractions lumped on blocks of cells (a relative error of
#: about (block / distance)² / 12, below 1e-4 for blocks of an eighth of the
#: radius).
FAR = 3.0


def _half_space_field(X: np.ndarray, cells: np.ndarray, tl: np.ndarray, g: Grid,
                      shear_modulus: float, poisson_ratio: float,
                      stress_at: np.ndarray | None = None):
    """The half-space field of the cells' uniform tractions ``tl`` (n, 3,
    local) at local points ``X`` (N, 3), depth z ≥ 0: displacement (N, 3) and
    stress (N, 6) (Voigt xx, yy, zz, xy, yz, xz; at the points ``stress_at``
    marks, default all, zero elsewhere).  Love's rectangles for the stress
    and for the displacement of points within a cell of the contact plane;
    point forces for the displacement deeper down; cells lumped on blocks
    for points far away (:data:`FAR`)."""
    N = X.shape[0]
    u, sig = np.zeros((N, 3)), np.zeros((N, 6))
    loaded = np.flatnonzero(np.any(tl != 0.0, axis=1))
    if not loaded.size:
        return u, sig
    hx, hy = 0.5 * g.dx, 0.5 * g.dy
    c, t = cells[loaded], tl[loaded]
    centre = c.mean(axis=0)
    radius = float(np.max(np.linalg.norm(c - centre, axis=1))) + max(g.dx, g.dy)
    far = np.linalg.norm(X - centre, axis=1) > FAR * radius
    B = max(1, int(radius / (8.0 * max(g.dx, g.dy))))
    # the blocks of B x B cells: their resultant at their centre, uniform on them
    ij = np.column_stack(np.unravel_index(loaded, g.shape)) // B
    keys, inv = np.unique(ij, axis=0, return_inverse=True)
    tb = np.zeros((keys.shape[0], 3))
    np.add.at(tb, inv.ravel(), t)
    cb = np.zeros((keys.shape[0], 3))
    np.add.at(cb, inv.ravel(), c)
    cb /= np.bincount(inv.ravel(), minlength=keys.shape[0])[:, None]
    cb[:, 2] = 0.0
    tb /= B * B  # the block's mean traction over its B² cells
    compliance = Compliance.half_space(shear_modulus, poisson_ratio)
    for idx, (src, trac, ax, ay) in ((np.flatnonzero(~far), (c, t, hx, hy)),
                                     (np.flatnonzero(far), (cb, tb, B * hx, B * hy))):
        if not idx.size:
            continue
        step = max(1, 200_000 // src.shape[0])
        for k in range(0, idx.size, step):
            rows = idx[k:k + step]
            R = X[rows, None, :] - src[None, :, :]  # (m, L, 3)
            depth = np.maximum(R[..., 2], 1e-6 * min(hx, hy))
            want = np.ones(rows.size, dtype=bool) if stress_at is None else stress_at[rows]
            if want.any():
                s = rectangle_stresses(R[want, :, 0], R[want, :, 1], depth[want], ax, ay,
                                       poisson_ratio)
                sig[rows[want]] = np.einsum("mlcd,ld->mc", s, trac)
            # within a cell of the plane: Love's rectangle; else a point force
            shallow = (R[..., 2] < min(ax, ay)) & (np.hypot(R[..., 0], R[..., 1])
                                                    < 4.0 * max(ax, ay))
            Rp = np.where(shallow[..., None], [4.0 * max(ax, ay), 0.0, 0.0], R)
            G = point_load_displacements(Rp.reshape(-1, 3), shear_modulus,
                                         poisson_ratio).reshape(*R.shape, 3)
            G[shallow] = 0.0
            uu = (4.0 * ax * ay) * np.einsum("mlcd,ld->mc", G, trac)
            if shallow.any():
                m_, l_ = np.nonzero(shallow)
                blk = blocks_from_integrals(rectangle_integrals(R[m_, l_, 0], R[m_, l_, 1],
                                                                ax, ay), compliance)
                np.add.at(uu, m_, np.einsum("pcd,pd->pc", blk, trac[l_]))
            u[rows] = uu
    return u, sig


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


def quadratic_basis(xy: np.ndarray, centre: np.ndarray, scale: float) -> np.ndarray:
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
    least the 24 nearest nodes).  ``deferred``: the coarse solve is left
    to :func:`solve_together` (the body's corrections on several grids, an
    assembly's shared body, in one factorization); the correction is usable
    after it."""

    def __init__(self, body, side: int, origin, axes, grid: Grid, anchors: int = 3,
                 fit_radius: float | None = None, threads: int | None = None,
                 curvature: tuple[float, float] = (0.0, 0.0), deferred: bool = False) -> None:
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
        self._anchors_local = np.column_stack([anchors_frame[:, 0],
                                               self.flip[1] * anchors_frame[:, 1],
                                               np.zeros(anchors_frame.shape[0])])
        self._hw = 0.5 * min(grid.dx, grid.dy)
        # a curved contact face: its near field on the grid (Toeplitz), the
        # coarse data leaving out what it covers
        self.curvature = (float(curvature[0]), float(curvature[1]))
        # the near field loads the cells of its (2nx − 1) × (2ny − 1) window
        # about each source: the coarse data leave out what lies within it
        self.near_radius = min((grid.nx - 1) * grid.dx, (grid.ny - 1) * grid.dy)
        self._near = None
        self._near_kernel = None  # the near field's traction kernel, for fields()
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
        # one coarse solve for every source and direction (with deferred:
        # with the other corrections of the body, :func:`solve_together`)
        self._W = np.concatenate([self._data(s) for s in sources], axis=1)
        self._sources, self._checks_frame, self._t0 = sources, checks_frame, t0
        self._threads = threads
        if not deferred:
            solve_together([self])

    def _finish(self, x: np.ndarray) -> None:
        """The correction from its remainder problem's solution ``x`` (3N,
        3 S: the unknown displacement or traction of every dof per source
        and direction)."""
        known_u, W, X = self._known, self._W, self._X
        anchors, grid = self.p, self.grid
        sources, checks_frame = self._sources, self._checks_frame
        mid, half = self._mid_frame, self._half
        del self._W
        u = np.where(known_u[:, None], W, x)  # (3N, 3 S): the remainder's displacement
        # the anchors' whole responses (displacement, traction: global, per
        # anchor and local direction), from which :meth:`fields` superposes
        # the body's fields on its coarse mesh
        P2 = anchors * anchors
        self._responses = (u[:, : 3 * P2].reshape(-1, 3, P2, 3).copy(),
                           np.where(known_u[:, None], x, W)[:, : 3 * P2]
                           .reshape(-1, 3, P2, 3).copy())
        # back to local components at the fit nodes: (S, 3 dirs, nodes, 3)
        S = sources.shape[0]
        U = u.reshape(-1, 3, S, 3)  # (N, comp, S, dir) in global components
        Ul = np.einsum("nksd,jk->sdnj", U[self._fit_nodes], self.axes) * self.flip
        xy = X[self._fit_nodes, :2]
        self._centre = np.array([mid[0], self.flip[1] * mid[1]])
        self._scale = float(np.hypot(*half))
        Phi = quadratic_basis(xy, self._centre, self._scale)
        coef, *_ = np.linalg.lstsq(Phi, Ul.reshape(S * 3, -1, 3).transpose(1, 0, 2)
                                   .reshape(xy.shape[0], -1), rcond=None)
        fitted = Phi @ coef
        resid = fitted - Ul.reshape(S * 3, -1, 3).transpose(1, 0, 2).reshape(xy.shape[0], -1)
        coef = coef.reshape(6, S, 3, 3)  # (term, source, dir, comp)
        self._coef = coef[:, : anchors * anchors]
        # the estimates: the anchors' interpolant at the check sources, and the fit
        cells = self._cells_local(grid.centres)
        Phi_g = quadratic_basis(cells[:, :2], self._centre, self._scale)
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
        self.seconds = time.perf_counter() - self._t0

    @property
    def centre(self) -> np.ndarray:
        """(3,) global: the centre of the grid the correction is made on."""
        return self.origin + np.append(self._mid_frame, 0.0) @ self.axes

    @property
    def held(self) -> np.ndarray:
        """(3N,) bool: the body's dofs of prescribed displacement (its supports)."""
        return self._known

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
        prescribed-displacement dofs, −σ_hs·n elsewhere (global components;
        on a curved face less the near field's share)."""
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

    def _near_field_load(self, tl: np.ndarray) -> tuple[Grid, np.ndarray]:
        """The near field's share of a curved face's residual traction under
        the cell tractions ``tl`` (n, 3, local), on the plane: the grid
        extended by its width less a cell on every side, lumped into at most
        about 64 × 64 cells (the coarse nodes it is read at lie a coarse
        element apart), and the (cells, 3) local tractions on it."""
        g = self.grid
        if self._near_kernel is None:
            _, k, _, _ = near_field_tractions(g, self.nu, self.curvature, self.near_radius)
            k = k.reshape(2 * g.nx - 1, 2 * g.ny - 1, 3, 3)
            self._near_kernel = k[:, ::-1] if self.side == 1 else k
        K = self._near_kernel
        T = tl.reshape(g.nx, g.ny, 3)
        # the full linear convolution of T with K, (3 nx − 2, 3 ny − 2, 3)
        mx, my = T.shape[0] + K.shape[0] - 1, T.shape[1] + K.shape[1] - 1
        s = (scipy.fft.next_fast_len(mx, True), scipy.fft.next_fast_len(my, True))
        That = scipy.fft.rfft2(T, s=s, axes=(0, 1))
        Khat = scipy.fft.rfft2(K, s=s, axes=(0, 1))
        te = scipy.fft.irfft2(np.einsum("ijcd,ijd->ijc", Khat, That), s=s,
                              axes=(0, 1))[:mx, :my]
        L = max(1, math.ceil(max(mx, my) / 64))
        px, py = -mx % L, -my % L
        te = np.pad(te, ((0, px), (0, py), (0, 0))).reshape((mx + px) // L, L, (my + py) // L,
                                                            L, 3).mean(axis=(1, 3))
        E = Grid((g.origin[0] - (g.nx - 1) * g.dx, g.origin[1] - (g.ny - 1) * g.dy),
                 te.shape[0], te.shape[1], L * g.dx, L * g.dy)
        return E, te.reshape(-1, 3)

    def fields(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(displacement, traction), each (N, 3) global components at the
        body's functional nodes, of the frame tractions ``p`` (n, 3) on body
        2 with the body's supports held: the half-space field of the grid's
        tractions at the nodes' true positions, plus the remainder
        superposed from the anchors' responses (the same interpolation in
        the source as :meth:`low_rank`), plus for a curved face the
        half-space field of the near field's share of its residual traction
        (:meth:`_near_field_load`, on the tangent plane: first order in the
        face's slope).  The traction is the contact traction on the contact
        face, zero on the other free surfaces and the half-space field's
        traction plus the remainder's reaction on the supports."""
        sign = 1.0 if self.side == 2 else -1.0
        tl = sign * np.asarray(p, dtype=float) * self.flip  # on this body, local
        g = self.grid
        X, n = self._X, self._n
        known = self._known.reshape(-1, 3)  # per global dof
        held = known.any(axis=1)  # only the supports need the stress
        u_hs, sig = _half_space_field(X, self._cells_local(g.centres), tl, g, self.G, self.nu,
                                      held)
        w = self.source_loads(p)  # (p², 3)
        U, T = self._responses
        u = np.einsum("nkad,ad->nk", U, w)
        t = np.einsum("nkad,ad->nk", T, w)
        xy = X[:, :2] * self.flip[:2]  # frame (x, y) of the nodes
        face = (n[:, 2] < -0.5) & _inside(g, xy)
        ul = u_hs
        if self._near is not None:  # the near field's share of the curved face's residual
            E, te = self._near_field_load(tl)
            u_near, sig_near = _half_space_field(X, self._cells_local(E.centres), te, E,
                                                 self.G, self.nu, held)
            ul, sig = ul + u_near, sig + sig_near
        applied = np.zeros_like(X)
        applied[face] = tl[_cell_of(g, xy[face])]
        to_global = self.axes.T * self.flip  # local -> global: v_g = A^T (flip v_l)
        traction_hs = _voigt_times(sig[:, :, None], n)[:, :, 0] @ to_global.T
        # the supports: the half-space field's traction and the remainder's
        # reaction; the free surfaces: the tractions applied there
        u_glob = ul @ to_global.T + u
        t_glob = np.where(known, traction_hs + t, applied @ to_global.T)
        return u_glob, t_glob

    def low_rank(self, p: np.ndarray) -> np.ndarray:
        """The remainder's part of :meth:`matvec` (rank ≤ 3 p² × 6)."""
        sign = 1.0 if self.side == 2 else -1.0
        ul = self._Phi_cells @ np.einsum("ad,madc->mc", self.source_loads(p), self._coef)
        return sign * ul * self.flip

    def source_loads(self, p: np.ndarray) -> np.ndarray:
        """(p², 3) the forces (local components) at the anchors that stand
        for the frame tractions ``p`` (n, 3) on body 2 in the source's
        interpolation: this body's load, as :meth:`low_rank` and
        :meth:`fields` take it."""
        sign = 1.0 if self.side == 2 else -1.0
        tl = sign * np.asarray(p, dtype=float) * self.flip  # the traction on this body, local
        return self.grid.cell_area * (self._L_cells.T @ tl)

    def node_responses(self, nodes: np.ndarray) -> np.ndarray:
        """(m, 3, p², 3): the displacement (global components) at the body's
        functional nodes ``nodes`` per unit force at each anchor along each
        local direction, supports held: the half-space field of the point
        force plus the remainder.  Far from the grid (another contact of the
        body) it is smooth in the source, so :meth:`source_loads` carry a
        grid's tractions to it."""
        nodes = np.asarray(nodes, dtype=np.intp)
        X = self._X[nodes]
        out = self._responses[0][nodes].copy()
        for a, s in enumerate(self._anchors_local):
            G = point_load_displacements(X - s, self.G, self.nu)  # (m, comp, dir) local
            out[:, :, a, :] += np.einsum("nkd,kj->njd", G * self.flip[None, :, None], self.axes)
        return out


def solve_together(corrections) -> None:
    """The coarse solves of ``corrections`` (made ``deferred``): one
    factorization per body for all its corrections' sources (a body shared
    by an assembly's pairs has one correction per grid; the mixed system
    depends on the body and its supports only), kept for the next solve of
    the same body (:func:`~.coarse.coarse_solve`)."""
    groups: dict[int, list] = {}
    for c in corrections:
        groups.setdefault(id(c.body), []).append(c)
    for group in groups.values():
        body = group[0].body
        known_u = group[0]._known
        W = np.concatenate([c._W for c in group], axis=1)
        x = coarse_solve(body, known_u, W, group[0]._threads)
        k = 0
        for c in group:
            m = c._W.shape[1]
            c._finish(x[:, k:k + m])
            k += m


__all__ = ["BodyCorrection", "chebyshev_points", "lagrange_weights",
           "point_load_displacements", "quadratic_basis", "solve_together"]

"""A two-body contact problem solved on the contact grid: the bodies at the
scale of their geometry (their coarse BEM models give each its correction),
the contact zone at the scale of the contact.

From a :class:`~bemcontact.contact.ContactProblem` of two bodies and its
load steps, :func:`solve_on_grid`

1. finds the contact plane: the closest nodes of the two contact surfaces,
   the normal of body 1's surface there (it must lie along a coordinate axis,
   so that each frame component is one component of the bodies' supports);
2. fits each contact surface near that point with a quartic in the plane's
   coordinates, from its mesh nodes (which lie on the true surface even
   when the facets between them do not): the initial gap at the grid's
   cells and each surface's curvature;
3. reads the supports of each body in every step: each component of a
   body's supports is a rigid translation (prescribed displacement, the
   same on every region) or a platen force (``Force``); any other load is
   refused (the full path takes it);
4. sizes the grid: a pass on a coarse grid without corrections finds the
   largest contact over the history, the grid then covers it with a margin
   at cells of ``grid_size`` (default: its smaller half-width / 25);
5. builds each body's correction (:class:`~.correction.BodyCorrection`) and
   solves every increment (:class:`~.interface.GridInterface`), checking each
   step's solution against the contact conditions.

Body 1 is the pair's first body; the frame normal points from it into body
2, and the grid tractions act on body 2."""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.fft
import scipy.interpolate
import scipy.optimize
import scipy.spatial

from ..bem.conditions import Displacement, Force, Pressure, Traction
from ..contact.history import LoadStep, checked_states
from ..contact.law import OPEN
from ..contact.options import SolverOptions
from ..errors import BemcontactError, ConfigError, ConvergenceError
from ..halfspace import Compliance, Grid
from ..settings import Key, check_settings, setting
from .correction import BodyCorrection
from .interface import GridInterface
from .operator import PairOperator
from .result import GridResult, GridState, verified_state
from .rolling import GridRolling
from .surface import contact_spacing, element_size, quartic_terms, region_nodes, surface_fit

@dataclass(frozen=True)
class GridOptions:
    """How the contact grid is made (``[contact] grid_size``, ``cells_per_radius``)."""

    grid_size: float | None = setting(Key(
        "grid_size", "number", "the cell size of the contact grid (a length); default: the "
        "largest contact's smaller half-width / cells_per_radius", default=None, lo=0,
        lo_open=True))
    cells_per_radius: float = setting(Key(
        "cells_per_radius", "number", "cells per contact half-width when grid_size is not given",
        default=25.0, lo=4.0, hi=400.0))
    margin: float = setting(Key(
        "margin", "number", "the grid's half-width over the largest contact's", default=1.15,
        lo=1.02, hi=4.0))
    anchors: int = setting(Key(
        "anchors", "integer", "Chebyshev sources per direction of each body's correction",
        default=3, lo=2, hi=8))
    resolved: float | None = setting(Key(
        "resolved", "number", "stop after the sizing pass (a ConfigError saying so) when both "
        "bodies' meshes have at least this many elements per contact half-width at the "
        "contact: they resolve it, the full path solves it as meshed (method = \"auto\")",
        default=None, lo=0, lo_open=True))

    def __post_init__(self) -> None:
        check_settings(self)


def contact_plane(b1, s1: str, b2, s2: str) -> tuple[np.ndarray, np.ndarray]:
    """(origin (3,), axes (3, 3) rows t1, t2, n): the midpoint of the two
    contact surfaces' closest nodes and the normal there (from body 1 into
    body 2) of the plane fitted to the flatter surface's 12 nodes nearest
    to it (a curved surface's closest node need not be its apex), which must
    lie along a coordinate axis."""
    P1 = b1.discretization.points[region_nodes(b1, s1)]
    P2 = b2.discretization.points[region_nodes(b2, s2)]
    dist, j = scipy.spatial.cKDTree(P2).query(P1)
    i = int(np.argmin(dist))
    x0 = 0.5 * (P1[i] + P2[j[i]])
    fits = []
    for P in (P1, P2):
        near = P[scipy.spatial.cKDTree(P).query(x0, k=min(12, len(P)))[1]]
        _, sv, vt = np.linalg.svd(near - near.mean(axis=0))
        fits.append((sv[-1] / max(sv[0], 1e-300), vt[-1]))
    n = min(fits, key=lambda f: f[0])[1]
    c1 = b1.discretization.points.mean(axis=0)
    c2 = b2.discretization.points.mean(axis=0)
    if (c2 - c1) @ n < 0:
        n = -n
    k = int(np.argmax(np.abs(n)))
    # a plane fitted to a curved surface's nodes tilts by about their spacing
    # over its radius: an axis within 5 degrees is taken (the quartic fits of
    # both surfaces then carry the tilt)
    if abs(n[k]) < math.cos(math.radians(5.0)):
        raise ConfigError(
            f"method = \"multiscale\": the contact normal {np.round(n, 6).tolist()} at "
            f"{np.round(x0, 6).tolist()} does not lie along a coordinate axis (the supports' "
            "components must map to the frame's); use method = \"full\"",
            location={"field": "contact.method"})
    e = np.eye(3)
    normal = np.sign(n[k]) * e[k]
    t1 = e[(k + 1) % 3]
    t2 = np.cross(normal, t1)
    return x0, np.array([t1, t2, normal])


def _poly(coef, xy) -> float:
    return float(quartic_terms(np.array([xy[0]]), np.array([xy[1]]))[0] @ coef)


def _gap_minimum(coef, radius: float) -> np.ndarray:
    """(ξ, η) of the smallest value of the quartic gap within ``radius``
    (a bounded minimization from the origin)."""
    res = scipy.optimize.minimize(lambda v: _poly(coef, v), np.zeros(2), method="L-BFGS-B",
                                  bounds=[(-radius, radius)] * 2)
    return np.asarray(res.x, dtype=float)


def _supports(body, conditions) -> tuple[np.ndarray, np.ndarray]:
    """(U, F) (3,) global: per component the rigid translation of the body's
    supports (NaN where force controlled or free) and the platen force (NaN
    where not force controlled)."""
    U = np.full(3, np.nan)
    F = np.full(3, np.nan)
    for region, items in conditions.items():
        for bc in items:
            where = {"body": body.name, "region": region}
            if isinstance(bc, Pressure):
                if bc.pressure != 0.0:
                    raise ConfigError(f"{body.name}: region {region!r} carries a pressure: "
                                      "method = \"multiscale\" loads bodies only through rigid "
                                      "supports and platen forces; use method = \"full\"",
                                      location=where)
                continue
            if callable(bc.value):
                raise ConfigError(f"{body.name}: region {region!r}: a field-valued condition; "
                                  "method = \"multiscale\" takes constant supports only; use "
                                  "method = \"full\"", location=where)
            for c, v in enumerate(bc.value):
                if v is None:
                    continue
                if isinstance(bc, Traction):
                    if v != 0.0:
                        raise ConfigError(f"{body.name}: region {region!r} carries a traction: "
                                          "method = \"multiscale\" loads bodies only through "
                                          "rigid supports and platen forces; use method = "
                                          "\"full\"", location=where)
                elif isinstance(bc, Displacement):
                    if not np.isnan(U[c]) and U[c] != v:
                        raise ConfigError(f"{body.name}: its supports move apart in component "
                                          f"{'xyz'[c]} ({U[c]:g} and {v:g}): method = "
                                          "\"multiscale\" takes one rigid translation per body; "
                                          "use method = \"full\"", location=where)
                    U[c] = v
                elif isinstance(bc, Force):
                    F[c] = v if np.isnan(F[c]) else F[c] + v
                if not (np.isnan(U[c]) or np.isnan(F[c])):
                    raise ConfigError(f"{body.name}: component {'xyz'[c]} is both held and "
                                      "force controlled (on different regions): method = "
                                      "\"multiscale\" takes one rigid support per component; "
                                      "use method = \"full\"", location=where)
    return U, F


def _targets(states1, states2, axes) -> tuple[np.ndarray, np.ndarray]:
    """Per frame component: the contact force on body 2 (NaN where the
    rigid displacement is prescribed) and the rigid displacement of body 2
    relative to body 1."""
    (U1, F1), (U2, F2) = states1, states2
    force = np.full(3, np.nan)
    shift = np.zeros(3)
    for j in range(3):
        g = int(np.argmax(np.abs(axes[j])))
        s = float(np.sign(axes[j, g]))
        f1, f2 = not np.isnan(F1[g]), not np.isnan(F2[g])
        u1 = 0.0 if np.isnan(U1[g]) else U1[g]
        u2 = 0.0 if np.isnan(U2[g]) else U2[g]
        if f1 and f2:
            raise ConfigError(f"both bodies are force controlled in {'xyz'[g]}: nothing holds "
                              "them there", location={"field": "contact.method"})
        if f2:
            force[j] = -s * F2[g]
        elif f1:
            force[j] = s * F1[g]
        else:
            shift[j] = s * (u2 - u1)
    return force, shift


def _translations(states1, states2, axes, d) -> np.ndarray:
    """(2, 3) global: the rigid translation of each body's supports, the
    prescribed components as given, the force-controlled ones from the
    rigid displacement ``d`` (frame components) of body 2 relative to body 1."""
    (U1, _), (U2, _) = states1, states2
    rel = np.asarray(d, dtype=float) @ axes
    u1 = np.where(np.isnan(U1), np.nan_to_num(U2) - rel, U1)
    u2 = np.where(np.isnan(U2), u1 + rel, U2)
    return np.stack([u1, u2])


def _held(body, conditions):
    U, F = _supports(body, conditions)
    free = [c for c in range(3) if np.isnan(U[c]) and np.isnan(F[c])]
    if free:
        raise ConfigError(f"{body.name}: nothing holds it in {', '.join('xyz'[c] for c in free)}: "
                          "method = \"multiscale\" needs each body supported or force "
                          "controlled in every component; use method = \"full\"",
                          location={"body": body.name})


def solve_on_grid(problem, steps=None, options: GridOptions | None = None,
                  solver: SolverOptions | None = None) -> GridResult:
    """Solve ``problem`` (a two-body :class:`~bemcontact.contact.ContactProblem`)
    through its load ``steps`` (default: one step to the bodies' own
    conditions) on the contact grid (see the module docstring).  A
    geometry the fits or the sizing cannot take is a one-line ConfigError."""
    return fitted(_solve_on_grid, problem, steps, options, solver)


def fitted(solve, *args):
    """``solve(*args)`` (a solve on the grid) with what the fits of the contact's
    geometry raise (not bemcontact's own errors) a one-line ConfigError."""
    try:
        return solve(*args)
    except BemcontactError:
        raise
    except (np.linalg.LinAlgError, scipy.spatial.QhullError, ValueError) as exc:
        raise ConfigError(f"method = \"multiscale\": the contact's geometry could not be "
                          f"fitted ({type(exc).__name__}: {exc}); use method = \"full\"",
                          location={"field": "contact.method"}) from exc


def _solve_on_grid(problem, steps, options, solver) -> GridResult:
    t0 = time.perf_counter()
    opt = options or GridOptions(grid_size=getattr(problem.pairs[-1], "grid_size", None))
    if len(problem.bodies) != 2 or len(problem.pairs) != 1:
        raise ConfigError("solve_on_grid solves two bodies in one contact pair; an assembly: "
                          "bemcontact.multiscale.solve_assembly_on_grid",
                          location={"field": "contact.method"})
    setup = PairSetup(problem, 0, steps, solver)
    half, coarse = setup.size(opt)
    margin = opt.margin
    for attempt in range(3):
        t1 = time.perf_counter()
        grid, corrections = setup.build(half, opt, margin)
        t2 = time.perf_counter()
        history, records, _, _ = setup.run(grid, corrections, report=True, coarse=coarse)
        if not setup.reaches_edge(grid, history):
            break
        if attempt == 2:
            raise ConfigError("method = \"multiscale\": the contact reaches the edge of the "
                              f"contact grid ({grid.nx} x {grid.ny} cells of {grid.dx:.3g}) after "
                              "two enlargements; use method = \"full\"",
                              location={"field": "contact.method"})
        margin *= 1.5
    t3 = time.perf_counter()
    return setup.result(grid, history, records, corrections,
                        {"sizing": t1 - t0, "corrections": t2 - t1, "solve": t3 - t2,
                         "total": t3 - t0})


class PairSetup:
    """One contact pair of ``problem`` (index ``index``) made ready for the
    grid (steps 1-3 of the module docstring): its bodies, the contact plane,
    the fitted surfaces, the supports and targets of every load step, the
    pair's half-space compliance and friction; then :meth:`size` (step 4),
    :meth:`build` and :meth:`run` (step 5).  An assembly
    (:mod:`.assembly`) makes one per pair."""

    def __init__(self, problem, index: int, steps, solver: SolverOptions | None) -> None:
        solver = solver or SolverOptions()
        pair = problem.pairs[index]
        if pair.penalty is not None:
            solver = dataclasses.replace(solver, penalty=pair.penalty)
        self.pair, self.solver = pair, solver
        b1, b2 = (problem.bodies[a] for a in problem.links[index])
        s1, s2 = pair.surface1, pair.surface2
        self.bodies, self.surfaces = (b1, b2), (s1, s2)
        for b in (b1, b2):
            if not hasattr(b, "mixed_system"):
                raise ConfigError(f"{b.name}: method = \"multiscale\" needs a BEM body (its "
                                  "coarse model gives its correction)", location={"body": b.name})
        steps = list(steps) if steps else [LoadStep()]
        self.steps = steps
        states = checked_states([b1, b2], [(s1,), (s2,)], steps)
        for state in states:
            for b, c in zip((b1, b2), state):
                _held(b, c)
        origin, axes = contact_plane(b1, s1, b2, s2)
        # the closest nodes need not be the closest points of the surfaces (a
        # sphere's apex above a coarse block's node): the gap of the fitted
        # surfaces is minimized, and the fits are made again about its minimum
        for _ in range(3):
            c1, r1, e1 = surface_fit(b1, s1, origin, axes, 4.0 * contact_spacing(b1, s1, origin))
            c2, r2, e2 = surface_fit(b2, s2, origin, axes, 4.0 * contact_spacing(b2, s2, origin))
            xy = _gap_minimum(c2 - c1, 0.8 * min(r1, r2))
            moved = xy @ axes[:2] + 0.5 * (_poly(c1, xy) + _poly(c2, xy)) * axes[2]
            origin = origin + moved
            if np.linalg.norm(xy) <= 1e-9 * min(r1, r2):
                break
        c1, r1, e1 = surface_fit(b1, s1, origin, axes, 4.0 * contact_spacing(b1, s1, origin))
        c2, r2, e2 = surface_fit(b2, s2, origin, axes, 4.0 * contact_spacing(b2, s2, origin))
        self.origin, self.axes = origin, axes
        self.fits = [(c1, e1), (c2, e2)]
        self.fit_radius = min(r1, r2)
        #: per step, each body's (U, F) (:func:`_supports`)
        self.supports = [(_supports(b1, st[0]), _supports(b2, st[1])) for st in states]
        self.targets = [_targets(s1_, s2_, axes) for s1_, s2_ in self.supports]
        m1, m2 = b1.material, b2.material
        self.compliance = Compliance.pair(m1.shear_modulus, m1.poisson_ratio,
                                          m2.shear_modulus, m2.poisson_ratio)
        mu = float(pair.friction_coefficient)
        self.mu = mu
        for i, step in enumerate(steps):
            if step.rolling is None:
                continue
            where = {"step": i, "field": "rolling"}
            if mu == 0.0:
                raise ConfigError(f"step[{i}].rolling: a frictionless pair: rolling carries no "
                                  "creep force without friction; give contact.friction_"
                                  "coefficient > 0", location=where)
            try:  # the direction against the contact plane, before any solve
                GridRolling(step.rolling, Grid.centred(4, 4, 1.0, 1.0), axes)
            except ConfigError as exc:
                raise ConfigError(f"step[{i}].{exc}", location={**exc.location, **where}) from None
        self.half = None

    @property
    def increments(self) -> int:
        return sum(step.increments for step in self.steps)

    def gap_on(self, grid: Grid) -> np.ndarray:
        """(n,) the initial gap of the fitted surfaces at the grid's cells."""
        c = grid.centres
        V = quartic_terms(c[:, 0], c[:, 1])
        return V @ self.fits[1][0] - V @ self.fits[0][0]

    def run(self, grid, corrections, report, coarse=None, offsets=None, guesses=None):
        """Every increment on ``grid``; one that starts with nothing in
        contact starts from the ``coarse`` grid's solution of it when given
        (grid sequencing: the fine Newton then starts with about the right
        contact patch; from a first touch, Newton at a/h = 100 cycled), the
        others from the previous increment's solution, or from ``guesses``
        (per increment (p, d): an assembly's previous sweep) when given.
        ``offsets`` (per increment (n, 3), or None): the relative
        displacement the other pairs' tractions add
        (:attr:`~.interface.GridInterface.offset`).  Returns the states (or
        GridStates with ``report``), the records, the interface and the
        solution (p, d) of each increment."""
        gi = GridInterface(PairOperator(grid, self.compliance, corrections), self.gap_on(grid),
                           self.mu, self.solver)
        prev_f, prev_s = np.zeros(3), np.zeros(3)
        out, records, solutions = [], [], []
        axes = self.axes
        for i, ((force, shift), step) in enumerate(zip(self.targets, self.steps)):
            n_inc = step.increments
            rolling = None if step.rolling is None else GridRolling(step.rolling, grid, axes)
            for k in range(1, n_inc + 1):
                t = k / n_inc
                f = np.where(np.isnan(force), np.nan, prev_f + t * (np.nan_to_num(force) - prev_f))
                s = prev_s + t * (shift - prev_s)
                guess, predicted = None, False
                j = len(solutions)
                if guesses is not None:
                    guess, predicted = guesses[j], True
                elif coarse is not None and not np.any(gi.p[:, 2] > 0.0):
                    cg, (cp, cd) = coarse[0], coarse[1][j]
                    guess = (_prolong(cg, cp, grid), cd)
                elif k >= 2 and rolling is None and j >= 2:
                    # equal increments of one step: Newton starts from the
                    # secant extrapolation of the last two solutions, the
                    # step's start and its first increment at k = 2 (the
                    # law's history stays the last converged state's; the
                    # first step's start is the unloaded state, which has no
                    # solution to extrapolate from); measured at a/h = 100,
                    # the tangential increments took 7 Newton iterations
                    # instead of 13
                    (p1, d1), (p0, d0) = solutions[-1], solutions[-2]
                    guess, predicted = (2.0 * p1 - p0, 2.0 * d1 - d0), True
                start = gi.snapshot() if predicted else None
                offset = None if offsets is None else offsets[j]
                rec = gi.solve_increment(f, s, guess, rolling, offset=offset)
                if predicted and not rec.converged:  # again from the last solution
                    gi.restore(start)
                    rec = gi.solve_increment(f, s, None, rolling, offset=offset)
                solutions.append((gi.p.copy(), gi.d.copy()))
                records.append(rec)
                if not rec.converged:
                    hist = ", ".join(f"{x:.1e}" for x in rec.residual_history[-8:])
                    raise ConvergenceError(
                        f"step {i + 1}{f' ({step.label})' if step.label else ''}, increment "
                        f"{k}/{n_inc} on the contact grid: {rec.message} (residual history "
                        f"{hist})")
            prev_f = np.where(np.isnan(force), gi.force(), force)
            prev_s = gi.d.copy()
            if report:
                out.append(verified_state(gi, step.label or f"step {i + 1}", force))
                out[-1].translations = _translations(*self.supports[i], axes, gi.d)
            else:
                out.append(gi.state())
        return out, records, gi, solutions

    def size(self, opt: GridOptions):
        """The coarse pass (step 4): the largest contact's half-widths (2,)
        in the frame over the whole history, found on a 32 × 32 grid without
        corrections (enlarged until the contact lies inside it), and that
        grid with its solutions, (Grid, [(p, d)] per increment), from which
        :meth:`run` starts the fine grid.  With ``opt.resolved``, a
        ConfigError when the meshes already resolve the contact."""
        b1, b2 = self.bodies
        s1, s2 = self.surfaces
        a_est = max(self.fit_radius / 4.0, 1e-12)
        half = None
        for _ in range(8):
            cells = 32
            h = 2.0 * a_est * 1.5 / cells
            g = Grid.centred(cells, cells, h, h)
            st, _, _, coarse = self.run(g, [], report=False)
            closed = np.zeros(g.size, dtype=bool)
            for s in st:
                closed |= s != OPEN
            if not closed.any():
                a_est *= 2.0
                continue
            ij = np.argwhere(closed.reshape(g.nx, g.ny))
            if ij.min() == 0 or ij[:, 0].max() == g.nx - 1 or ij[:, 1].max() == g.ny - 1:
                a_est *= 2.0
                continue
            xy = g.centres[closed][:, :2]
            half = np.abs(xy).max(axis=0) + 0.5 * h
            if half.min() < 8.0 * h:  # too few cells across: size the pass on it again
                a_est = float(half.max()) * 1.1
                half = None
                continue
            break
        if half is None:
            raise ConfigError("method = \"multiscale\": no bounded contact zone found on the "
                              "grid (the bodies do not touch under these loads, or their contact "
                              "is not concentrated: flat on flat, or conforming)",
                              location={"field": "contact.method"})
        if opt.resolved is not None:
            r = 1.2 * float(np.hypot(*half))
            size = max(element_size(b1, s1, self.origin, self.axes, r),
                       element_size(b2, s2, self.origin, self.axes, r))
            if float(half.min()) >= opt.resolved * size:
                raise ConfigError(f"the meshes resolve the contact ({half.min() / size:.1f} "
                                  f"elements per contact half-width, >= {opt.resolved:g})",
                                  location={"field": "contact.method"})
        self.half = half
        return half, (g, coarse)

    def build(self, half, opt: GridOptions, margin: float, deferred: bool = False):
        """The grid over the contact's half-widths ``half`` with ``margin``
        (cells of ``opt.grid_size``, default the smaller half-width /
        ``opt.cells_per_radius``), the surfaces fitted again over it when it
        reaches past the first fits, and each body's correction on it
        (``deferred``: their coarse solves left to
        :func:`~.correction.solve_together`)."""
        b1, b2 = self.bodies
        s1, s2 = self.surfaces
        cell = opt.grid_size or float(half.min()) / opt.cells_per_radius
        if margin * float(np.hypot(*half)) > self.fit_radius:
            needed = margin * float(np.hypot(*half))
            c1, _, e1 = surface_fit(b1, s1, self.origin, self.axes, needed)
            c2, _, e2 = surface_fit(b2, s2, self.origin, self.axes, needed)
            self.fits = [(c1, e1), (c2, e2)]
        (c1, _), (c2, _) = self.fits
        nx = scipy.fft.next_fast_len(int(math.ceil(2.0 * margin * half[0] / cell)))
        ny = scipy.fft.next_fast_len(int(math.ceil(2.0 * margin * half[1] / cell)))
        grid = Grid.centred(nx, ny, cell, cell)
        k1 = (-2.0 * c1[3], -2.0 * c1[5])  # body 1's local depth is -ζ1
        k2 = (2.0 * c2[3], 2.0 * c2[5])
        corrections = [BodyCorrection(b1, 1, self.origin, self.axes, grid, opt.anchors,
                                      curvature=k1, deferred=deferred),
                       BodyCorrection(b2, 2, self.origin, self.axes, grid, opt.anchors,
                                      curvature=k2, deferred=deferred)]
        return grid, corrections

    def reaches_edge(self, grid: Grid, history) -> bool:
        """Whether a closed cell of ``history`` lies on the grid's border
        (the sizing pass fell short), in a band as wide as the longest
        transient roll (a cell takes its stick reference from that far
        upstream)."""
        cell = grid.dx
        band = 1 + max((math.ceil(s.rolling.distance / cell - 1e-9) for s in self.steps
                        if s.rolling is not None and s.rolling.distance), default=0)
        nx, ny = grid.shape
        edge = np.zeros((nx, ny), dtype=bool)
        edge[:band, :] = edge[-band:, :] = edge[:, :band] = edge[:, -band:] = True
        return any(np.any((st.state != OPEN).reshape(nx, ny) & edge) for st in history)

    def result(self, grid, history, records, corrections, timings) -> GridResult:
        b1, b2 = self.bodies
        return GridResult((b1.name, b2.name), grid, self.origin, self.axes, self.gap_on(grid),
                          history, records, corrections,
                          {**timings, "surface_fit_rms": [self.fits[0][1], self.fits[1][1]]},
                          surfaces=(self.fits[0][0], self.fits[1][0]))


#: The bounds of :func:`applicability`: the corrections' error estimate, the
#: contact's size against each surface's radius of curvature (the half-space
#: near field is first order in a/R), against the distance to the contact
#: surface's edge and against the body's thickness along the normal.
#: A curved contact face's coarse elements near the contact against the
#: radius of its near field: the coarse data carry the residual traction
#: from half that radius out (:func:`~.correction.near_share`), and measured
#: on the benchmark's sphere at a/h = 12 and 25 the force is within 0.05 % of
#: the converged one with elements of 0.27 and 0.47 near radii, 4 % low with
#: 0.70 (while the corrections' estimate there, 3.3e-3 to 3.8e-3, is only
#: just over its bound).
#: In an assembly, also the distance between two contacts of a shared body
#: against their grids' half-width (:func:`~.assembly.assembly_applicability`).
LIMITS = {"estimate": 3e-3, "a_over_R": 0.1, "edge_over_a": 5.0, "thickness_over_a": 5.0,
          "element_over_near_radius": 0.6, "separation_over_a": 5.0}


def applicability(result: GridResult, problem, index: int = 0) -> dict:
    """Whether the grid's answer can stand for the bodies': per check its
    value, its bound (:data:`LIMITS`) and whether it holds; ``reason`` those
    that fail ('' when all hold).  ``index``: the pair of ``problem`` that
    ``result`` solved."""
    g = result.grid
    a = 0.5 * min(g.nx * g.dx, g.ny * g.dy)  # the grid's half-width: above the contact's
    checks = {}
    est = max(c.estimate for c in result.corrections)
    checks["estimate"] = (est, LIMITS["estimate"], est <= LIMITS["estimate"])
    curv = max(abs(k) for c in result.corrections for k in c.curvature)
    checks["a_over_R"] = (curv * a, LIMITS["a_over_R"], curv * a <= LIMITS["a_over_R"])
    pair = problem.pairs[index]
    edge, thick = np.inf, np.inf
    for c, region in zip(result.corrections, (pair.surface1, pair.surface2)):
        d = c.body.discretization
        own = d.region == c.body.mesh.region_names.index(region)
        X = (d.points - result.origin) @ result.axes.T
        # the contact surface's edge: its nodes' hull in the plane
        try:
            hull = scipy.spatial.ConvexHull(X[own, :2])
            edge = min(edge, float(np.min(-hull.equations[:, 2])))
        except (scipy.spatial.QhullError, ValueError):  # a degenerate surface: no edge known
            edge = 0.0
        thick = min(thick, float(np.ptp(X[:, 2])))
    checks["edge_over_a"] = (edge / a, LIMITS["edge_over_a"], edge / a >= LIMITS["edge_over_a"])
    checks["thickness_over_a"] = (thick / a, LIMITS["thickness_over_a"],
                                  thick / a >= LIMITS["thickness_over_a"])
    coarse = 0.0
    for c, region in zip(result.corrections, (pair.surface1, pair.surface2)):
        if any(c.curvature):  # a flat face carries no coarse data near the contact
            size = element_size(c.body, region, result.origin, result.axes, c.near_radius)
            coarse = max(coarse, size / c.near_radius)
    bound = LIMITS["element_over_near_radius"]
    checks["element_over_near_radius"] = (coarse, bound, coarse <= bound)
    reasons = []
    for name, (value, bound, ok) in checks.items():
        if not ok:
            reasons.append({"estimate": f"the corrections' error estimate {value:.2g} > {bound:g}",
                      "a_over_R": f"a conformal contact (a/R = {value:.2g} > {bound:g})",
                      "edge_over_a": f"the contact {value:.2g} contact widths from an edge "
                                     f"(< {bound:g})",
                      "thickness_over_a": f"a thin body ({value:.2g} contact widths thick, "
                                          f"< {bound:g})",
                      "element_over_near_radius": f"a curved contact face meshed too coarsely "
                                                  f"for its near field (elements of {value:.2g} "
                                                  f"near-field radii, > {bound:g}: refine it "
                                                  "near the contact)"}[name])
    reason = "; ".join(reasons)
    return {"checks": {n: {"value": v, "bound": b, "holds": bool(ok)}
                       for n, (v, b, ok) in checks.items()}, "reason": reason}


def _prolong(coarse: Grid, p: np.ndarray, fine: Grid) -> np.ndarray:
    """Tractions (n_coarse, 3) on ``coarse`` interpolated (bilinear, zero
    outside) at the cell centres of ``fine``; a pressure stays ≥ 0."""
    x = coarse.origin[0] + (np.arange(coarse.nx) + 0.5) * coarse.dx
    y = coarse.origin[1] + (np.arange(coarse.ny) + 0.5) * coarse.dy
    at = fine.centres[:, :2]
    out = np.stack([scipy.interpolate.RegularGridInterpolator(
        (x, y), p[:, c].reshape(coarse.nx, coarse.ny), bounds_error=False, fill_value=0.0)(at)
        for c in range(3)], axis=1)
    out[:, 2] = np.maximum(out[:, 2], 0.0)
    return out


__all__ = ["LIMITS", "GridOptions", "GridResult", "GridState", "applicability", "contact_plane",
           "solve_on_grid"]

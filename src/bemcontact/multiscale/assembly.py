"""An assembly's contacts on the contact grid: one grid per pair, the pairs
coupled through the bodies they share.

Each pair is made ready, sized and given its bodies' corrections as a pair
alone (:class:`~.pair.PairSetup`).  A body shared by pairs i and j moves on
pair i's grid under pair j's tractions as well: :class:`SharedFlexibility`
gives that displacement, the body's response at its nodes near pair i per
unit force at each of pair j's anchors (the half-space field of the point
force plus the remainder its coarse model solved,
:meth:`~.correction.BodyCorrection.node_responses`), fitted by a quadratic
over pair i's grid.  Pair j's tractions reach the anchors through the same
interpolation in the source as the body's own correction
(:meth:`~.correction.BodyCorrection.source_loads`); that far from its
sources the response is smooth in both ends, so the coupling is of rank
≤ 3 p² and costs no solve beyond the corrections'.

The coupled system is solved by block Gauss–Seidel over whole load
histories: each sweep solves every pair's history with the relative
displacement its neighbours' latest solutions add
(:attr:`~.interface.GridInterface.offset`), Newton starting from the pair's
previous sweep.  The sweeps stop when no offset of any increment moved by
more than a hundredth of the penetration check's tolerance (EPS σ / r); the
last change is each step's ``coupling`` check.  A shared body is held
(prescribed displacement) in every component, so that the pairs' rigid
displacements stay their own (a force on a shared body would couple them
through its balance, which the full path solves); rolling is not taken."""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..bem.solution import BodySolution
from ..contact.verification import EPS
from ..errors import ConfigError, ConvergenceError
from ..halfspace import Grid
from .correction import BodyCorrection, quadratic_basis, solve_together
from .pair import LIMITS, GridOptions, PairSetup, applicability, fitted
from .result import GridResult
from .stress import check_step, grid_stresses

#: Largest Gauss–Seidel sweeps over the pairs' histories.
MAX_SWEEPS = 20
#: The sweeps stop when the offsets moved by at most this share of the
#: penetration check's tolerance (EPS σ / r).
SWEEP_SHARE = 0.01


class SharedFlexibility:
    """The relative displacement on pair i's grid (frame i components, the
    pair's u_2 − u_1) per frame traction on body 2 of pair j, through a body
    both pairs hold (module docstring).

    ``source``: the shared body's :class:`~.correction.BodyCorrection` on
    pair j's grid; ``side``: the body's side (1 or 2) in pair i; ``origin``,
    ``axes``, ``grid``: pair i's frame and grid; ``whole``: the body's whole
    flexibility on pair i's grid (its correction's
    :attr:`~.correction.BodyCorrection.whole`), which :attr:`estimate`
    is relative to."""

    def __init__(self, source: BodyCorrection, side: int, origin, axes, grid: Grid,
                 whole: float) -> None:
        self.source, self.side, self.grid = source, side, grid
        body = source.body
        d = body.discretization
        X = (d.points - np.asarray(origin, dtype=float)) @ np.asarray(axes, dtype=float).T
        half = 0.5 * np.array([grid.nx * grid.dx, grid.ny * grid.dy])
        mid = np.array(grid.origin) + half
        r = np.sqrt((X[:, 0] - mid[0]) ** 2 + (X[:, 1] - mid[1]) ** 2 + X[:, 2] ** 2)
        nodes = np.flatnonzero(r <= 2.0 * float(np.hypot(*half)))
        if nodes.size < 24:
            nodes = np.argsort(r)[:24]
        U = source.node_responses(nodes)  # (m, comp, p², dir) global
        Ui = np.einsum("mkad,jk->madj", U, np.asarray(axes, dtype=float))  # frame i comps
        scale = float(np.hypot(*half))
        Phi = quadratic_basis(X[nodes, :2], mid, scale)
        rhs = Ui.reshape(nodes.size, -1)
        coef, *_ = np.linalg.lstsq(Phi, rhs, rcond=None)
        resid = Phi @ coef - rhs
        self._coef = coef.reshape(6, *Ui.shape[1:])  # (term, p², dir, comp)
        self._Phi = quadratic_basis(grid.centres[:, :2], mid, scale)
        #: the fit's rms residual at its nodes relative to the body's whole
        #: flexibility on pair i's grid, as the corrections' estimates
        self.estimate = float(np.sqrt(np.mean(resid**2))) / max(whole, 1e-300)
        #: the largest entry of the coupling (per unit force): how strongly
        #: the pairs feel each other, relative to ``whole``
        self.strength = float(np.abs(rhs).max()) / max(whole, 1e-300)
        #: the distance between the two grids' centres (global)
        self.distance = float(np.linalg.norm(
            np.asarray(origin) + np.append(mid, 0.0) @ np.asarray(axes) - source.centre))

    def matvec(self, p: np.ndarray) -> np.ndarray:
        """(n_j, 3) frame tractions on pair j's body 2 -> (n_i, 3) the
        relative displacement they add on pair i's grid."""
        u = self._Phi @ np.einsum("ad,madc->mc", self.source.source_loads(p), self._coef)
        return u if self.side == 2 else -u


@dataclass
class GridAssemblyResult:
    """An assembly solved on the grid (:func:`solve_assembly_on_grid`): each
    pair's :class:`~.pair.GridResult` (its states with the coupling in their
    offsets), the couplings, and the sweeps' history."""

    names: tuple[str, ...]
    pairs: list[GridResult]
    #: (i, j, body name, :class:`SharedFlexibility`) for each coupling
    couplings: list
    #: per sweep the largest change of an offset over its tolerance
    sweeps: list[float]
    #: each pair's contact surfaces (body 1's, body 2's)
    regions: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    method: dict = field(default_factory=dict)
    _fields: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    stress_model: ClassVar[str] = ("the half-space field of the grid tractions below each "
                                   "body's contact surfaces (every pair the body is in)")

    @property
    def converged(self) -> bool:
        return all(p.converged for p in self.pairs)

    @property
    def history(self) -> list:
        """The first pair's states (every pair has one per load step)."""
        return self.pairs[0].history

    def _holding(self, body: str):
        """(pair result, the body's index in it) of every pair holding ``body``."""
        out = [(r, r.names.index(body)) for r in self.pairs if body in r.names]
        if not out:
            raise ConfigError(f"unknown body {body!r}; the bodies are {list(self.names)}",
                              location={"body": body})
        return out

    def stresses(self, body: str, points, step: int = -1) -> np.ndarray:
        """The stress tensor (n, 6), global components, tension positive, at
        ``points`` (n, 3) inside ``body``: the sum of each of its pairs'
        half-space fields (:func:`~.stress.grid_stresses`).  A point must lie
        inside the body below the contact surface of the pair whose grid is
        nearest (refused otherwise); the other pairs' fields are read at its
        depth below their own surface fits, or on them."""
        check_step(self, step)
        X = np.asarray(points, dtype=float) if not isinstance(points, np.ndarray) else points
        holding = self._holding(body)
        if len(holding) == 1:
            return holding[0][0].stresses(body, X, step)
        try:
            centres = np.array([r.points.mean(axis=0) for r, _ in holding])
            near = np.argmin(np.linalg.norm(X[:, None, :] - centres[None], axis=2), axis=1)
        except (TypeError, ValueError, IndexError):
            return holding[0][0].stresses(body, X, step)  # its one-line refusal
        out = np.zeros((X.shape[0], 6))
        for k, (r, _) in enumerate(holding):
            own = near == k
            if own.any():
                out[own] += r.stresses(body, X[own], step)
            if (~own).any():
                out[~own] += grid_stresses(r, body, X[~own], step, clip=True)
        return out

    def surface_points(self, body: str) -> np.ndarray:
        """(n, 3) the points of ``body``'s surface at the cells of each of its
        pairs' grids, one grid after the other."""
        return np.vstack([r.surface_points(body) for r, _ in self._holding(body)])

    def surface_stresses(self, body: str, step: int = -1) -> np.ndarray:
        """The stress tensor (n, 6) at :meth:`surface_points`: each grid's
        surface field plus the other pairs' fields there."""
        holding = self._holding(body)
        out = []
        for k, (r, _) in enumerate(holding):
            s = r.surface_stresses(body, step)
            pts = r.surface_points(body)
            for m, (q, _) in enumerate(holding):
                if m != k:
                    s = s + grid_stresses(q, body, pts, step, clip=True)
            out.append(s)
        return np.vstack(out)

    def body_fields(self, body: str, step: int = -1) -> BodySolution:
        """``body``'s displacement and traction at its own mesh's nodes, by
        superposition over the pairs it is in (each pair's
        :meth:`~.pair.GridResult.body_fields` without the supports'
        translation, which is added once)."""
        check_step(self, step)
        key = (body, step % len(self.history))
        if key not in self._fields:
            u = t = None
            for r, b in self._holding(body):
                s = r.history[key[1]]
                uu, tt = r.corrections[b].fields(s.p)
                u = uu if u is None else u + uu
                t = tt if t is None else t + tt
                move = s.translations[b] if s.translations is not None else 0.0
            c = self._holding(body)[0][0].corrections[self._holding(body)[0][1]]
            d = c.body.discretization
            self._fields[key] = BodySolution(
                points=d.points, normals=d.normals, displacement=u + move, traction=t,
                weights=d.weights, region=d.region, region_names=c.body.mesh.region_names,
                discretization=d)
        return self._fields[key]

    def reactions(self, step: int = -1) -> dict:
        """Body name -> the resultant (3,) global of its supports' reactions."""
        out = {}
        for name in self.names:
            r, b = self._holding(name)[0]
            sol = self.body_fields(name, step)
            known = r.corrections[b].held.reshape(-1, 3)
            out[name] = (sol.weights[:, None] * np.where(known, sol.traction, 0.0)).sum(axis=0)
        return out

    def summary(self) -> dict:
        """JSON-ready: the method, per pair its grid summary, the couplings
        and the sweeps."""
        return {
            "method": {"used": "multiscale", **self.method},
            "pairs": [{"names": list(r.names), **r.summary()} for r in self.pairs],
            "couplings": [{"pairs": [i, j], "body": name, "estimate": c.estimate,
                           "strength": c.strength, "distance": c.distance}
                          for i, j, name, c in self.couplings],
            "sweeps": self.sweeps,
            "timings": self.timings,
        }


def solve_assembly_on_grid(problem, steps=None, options: GridOptions | None = None,
                           solver=None) -> GridAssemblyResult:
    """Solve an assembly ``problem`` (a :class:`~bemcontact.contact.ContactProblem`
    of several pairs) through its load ``steps`` on one contact grid per
    pair (module docstring).  What the grid cannot take is a one-line
    ConfigError; sweeps that do not settle a ConvergenceError with their
    history."""
    return fitted(_solve, problem, steps, options, solver)


def _solve(problem, steps, options, solver) -> GridAssemblyResult:
    t0 = time.perf_counter()
    opt = options or GridOptions()
    npairs = len(problem.pairs)
    if any(s.rolling is not None for s in (steps or ())):
        raise ConfigError("method = \"multiscale\": an assembly on the grid does not roll; use "
                          "method = \"full\"", location={"field": "contact.method"})
    setups = [PairSetup(problem, i, steps, solver) for i in range(npairs)]
    # the shared bodies: held in every component in every step
    holders: dict[int, list[int]] = {}
    for i, link in enumerate(problem.links):
        for a in link:
            holders.setdefault(a, []).append(i)
    for a, ps in holders.items():
        if len(ps) < 2:
            continue
        body = problem.bodies[a]
        side = problem.links[ps[0]].index(a)
        for k, sup in enumerate(setups[ps[0]].supports):
            U, _ = sup[side]
            if np.isnan(U).any():
                free = ", ".join("xyz"[c] for c in range(3) if np.isnan(U[c]))
                raise ConfigError(f"{body.name}: a body in {len(ps)} contact pairs is held in "
                                  f"every component on the grid (step {k + 1}: not in {free}); "
                                  "use method = \"full\"", location={"body": body.name})
    grid_opt = [dataclasses.replace(opt, grid_size=getattr(problem.pairs[i], "grid_size", None)
                                    or opt.grid_size) for i in range(npairs)]
    sized = [s.size(o) for s, o in zip(setups, grid_opt)]
    t1 = time.perf_counter()
    built = [s.build(half, o, o.margin, deferred=True)
             for s, (half, _), o in zip(setups, sized, grid_opt)]
    solve_together([c for _, corrections in built for c in corrections])
    couplings = []
    for a, ps in holders.items():
        for i in ps:
            for j in ps:
                if i == j:
                    continue
                si, sj = problem.links[i].index(a) + 1, problem.links[j].index(a) + 1
                src = built[j][1][sj - 1]
                couplings.append((i, j, problem.bodies[a].name, SharedFlexibility(
                    src, si, setups[i].origin, setups[i].axes, built[i][0],
                    built[i][1][si - 1].whole)))
    t2 = time.perf_counter()
    runs = [None] * npairs  # (states, records, gi, solutions) per pair
    sweeps = []
    n_inc = setups[0].increments

    def offsets(i):
        out = [np.zeros((built[i][0].size, 3)) for _ in range(n_inc)]
        for ci, cj, _, c in couplings:
            if ci == i and runs[cj] is not None:
                for k, (p, _) in enumerate(runs[cj][3]):
                    out[k] += c.matvec(p)
        return out

    used = [None] * npairs
    for sweep in range(MAX_SWEEPS):
        for i, s in enumerate(setups):
            used[i] = offsets(i)
            guesses = None if runs[i] is None else runs[i][3]
            coarse = sized[i][1] if runs[i] is None else None
            runs[i] = s.run(built[i][0], built[i][1], report=True, coarse=coarse,
                            offsets=used[i], guesses=guesses)
        worst, change = 0.0, []
        for i in range(npairs):
            now = offsets(i)
            gi = runs[i][2]
            sigma = max(max(float(np.abs(p).max(initial=0.0)) for p, _ in runs[i][3]), 1e-300)
            tol = EPS * sigma / float(np.max(gi.law.r))
            per = [float(np.abs(a - b).max(initial=0.0)) for a, b in zip(now, used[i])]
            change.append((per, tol))
            worst = max(worst, max(per, default=0.0) / tol)
        sweeps.append(worst)
        if worst <= SWEEP_SHARE:
            break
    else:
        hist = ", ".join(f"{x:.1e}" for x in sweeps[-8:])
        raise ConvergenceError(f"the assembly's pairs on the grid: their coupling did not settle "
                               f"in {MAX_SWEEPS} sweeps (largest offset change over its "
                               f"tolerance per sweep: {hist})")
    t3 = time.perf_counter()
    results = []
    for i, s in enumerate(setups):
        states, records, _, _ = runs[i]
        per, tol = change[i]
        ends = np.cumsum([st.increments for st in s.steps]) - 1
        for st, e in zip(states, ends):
            st.checks["coupling"] = {"worst": per[e], "tolerance": tol}
        if s.reaches_edge(built[i][0], states):
            raise ConfigError(f"method = \"multiscale\": pair {i + 1}'s contact reaches the edge "
                              "of its contact grid; give it a larger contact.margin or use "
                              "method = \"full\"", location={"field": "contact.method"})
        results.append(s.result(built[i][0], states, records, built[i][1], {}))
    return GridAssemblyResult(tuple(b.name for b in problem.bodies), results, couplings, sweeps,
                              [s.surfaces for s in setups],
                              {"sizing": t1 - t0, "corrections": t2 - t1, "solve": t3 - t2,
                               "total": time.perf_counter() - t0})


def assembly_applicability(result: GridAssemblyResult, problem) -> dict:
    """Each pair's :func:`~.pair.applicability`, the couplings' fit
    estimates joined to the ``estimate`` check, and the pairs' separation
    on a shared body against their contacts' size (``separation_over_a``:
    the distance between the grids' centres over the larger grid
    half-width, bound :data:`~.pair.LIMITS` ``separation_over_a``)."""
    checks, reasons = {}, []
    for i, r in enumerate(result.pairs):
        app = applicability(r, problem, i)
        for name, c in app["checks"].items():
            old = checks.get(name)
            larger = name in ("estimate", "a_over_R", "element_over_near_radius")
            worse = old is None or (c["value"] > old["value"] if larger
                                    else c["value"] < old["value"])
            if worse:
                checks[name] = c
        if app["reason"]:
            reasons.append(f"pair {i + 1}: {app['reason']}")
    sep = np.inf
    for i, j, _, c in result.couplings:
        est = c.estimate
        if est > checks["estimate"]["value"]:
            checks["estimate"] = {"value": est, "bound": LIMITS["estimate"],
                                  "holds": est <= LIMITS["estimate"]}
            if not checks["estimate"]["holds"]:
                reasons.append(f"the coupling of pairs {i + 1} and {j + 1}: its error estimate "
                               f"{est:.2g} > {LIMITS['estimate']:g}")
        gi, gj = result.pairs[i].grid, result.pairs[j].grid
        a = 0.5 * max(gi.nx * gi.dx, gi.ny * gi.dy, gj.nx * gj.dx, gj.ny * gj.dy)
        sep = min(sep, c.distance / a)
    bound = LIMITS["separation_over_a"]
    checks["separation_over_a"] = {"value": sep, "bound": bound, "holds": bool(sep >= bound)}
    if sep < bound:
        reasons.append(f"two contacts of a shared body {sep:.2g} contact widths apart (< "
                       f"{bound:g})")
    return {"checks": checks, "reason": "; ".join(reasons)}


__all__ = ["GridAssemblyResult", "SharedFlexibility", "assembly_applicability",
           "solve_assembly_on_grid"]

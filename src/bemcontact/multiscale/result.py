"""The result of a contact solved on the contact grid: the state at the end
of each load step (:class:`GridState`), checked against the contact
conditions (:func:`verified_state`), and the whole solve
(:class:`GridResult`: its summary, and the stresses protocol of
:mod:`bemcontact.stresses`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..contact.law import OPEN, SLIP, STICK
from ..contact.rolling import rolling_quantities
from ..contact.verification import EPS
from ..errors import ConvergenceError
from ..halfspace import Grid, HalfSpaceStress
from .correction import BodyCorrection
from ..bem.solution import BodySolution
from .stress import (body_index, check_step, grid_stresses, grid_surface_points,
                     grid_surface_stresses)


@dataclass
class GridState:
    """The state at the end of one load step on the grid: tractions ``p``
    (n, 3) on body 2 (frame components), relative displacements ``k`` (n, 3)
    (``k[:, 2]`` the gap), contact ``state`` (n,), rigid displacement ``d``
    (3,) of body 2 relative to body 1 (frame components), contact force (3,)
    on body 2 (frame components), and the checks of the contact conditions."""

    label: str
    p: np.ndarray
    k: np.ndarray
    state: np.ndarray
    d: np.ndarray
    force: np.ndarray
    checks: dict
    #: a rolling step's creep force, spin moment, frictional work and power,
    #: adhesion and slip areas and creepages in effect
    #: (:func:`~bemcontact.contact.rolling.rolling_quantities`); None otherwise
    rolling: dict | None = None
    #: (n, 2) a rolling step's slip of body 2 relative to body 1 per rolled
    #: distance (frame t1, t2 components; zero in stick); None otherwise
    slip: np.ndarray | None = None
    #: (2, 3) global: the rigid translation of body 1's and body 2's supports
    translations: np.ndarray | None = None


@dataclass
class GridResult:
    """A contact solved on the grid (:func:`solve_on_grid`)."""

    names: tuple[str, str]
    grid: Grid
    origin: np.ndarray
    axes: np.ndarray
    gap: np.ndarray
    history: list[GridState]
    records: list
    corrections: list[BodyCorrection]
    timings: dict = field(default_factory=dict)
    #: how the method was chosen: ``requested``, ``used``, ``reason`` and the
    #: :func:`applicability` checks (set by the caller that chose it)
    method: dict = field(default_factory=dict)
    #: each body's contact surface ζ(ξ, η) in the frame: quartic coefficients
    #: (:func:`quartic_terms`), body 1's then body 2's
    surfaces: tuple = ()
    #: the bodies' fields, computed once per body and step (:meth:`body_fields`)
    _fields: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    #: the half-space stress field of each Poisson ratio (:meth:`half_space`)
    _half_spaces: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    #: how :meth:`stresses` computes them (said in the stress files' summary)
    stress_model: ClassVar[str] = ("the half-space field of the grid tractions below each "
                                   "body's contact surface")

    def stresses(self, body: str, points, step: int = -1) -> np.ndarray:
        """The stress tensor (n, 6), global components, tension positive, at
        ``points`` (n, 3) inside ``body`` at the end of load step ``step``
        (:func:`~bemcontact.multiscale.stress.grid_stresses`)."""
        return grid_stresses(self, body, points, step)

    def half_space(self, b: int) -> HalfSpaceStress:
        """Body ``b``'s (0 or 1) half-space stress field on the grid: one per
        Poisson ratio, kept with the kernels it has computed (the load steps
        and a body of the same ratio reuse them)."""
        nu = self.corrections[b].body.material.poisson_ratio
        if nu not in self._half_spaces:
            self._half_spaces[nu] = HalfSpaceStress(self.grid, nu)
        return self._half_spaces[nu]

    def surface_stresses(self, body: str, step: int = -1) -> np.ndarray:
        """The stress tensor (n, 6) on ``body``'s surface at each grid cell
        (:func:`~bemcontact.multiscale.stress.grid_surface_stresses`)."""
        return grid_surface_stresses(self, body, step)

    def surface_points(self, body: str) -> np.ndarray:
        """(n, 3) the points of ``body``'s surface where :meth:`surface_stresses`
        gives the stresses (:func:`~bemcontact.multiscale.stress.grid_surface_points`)."""
        return grid_surface_points(self, body)

    def body_fields(self, body: str, step: int = -1) -> BodySolution:
        """``body``'s displacement and traction at its own (coarse) mesh's
        functional nodes at the end of load step ``step``, by superposition
        (:meth:`~.correction.BodyCorrection.fields`: the half-space field of
        the grid tractions, the body's remainder, its supports' rigid
        translation); the traction is the contact traction on the contact
        face and the reaction on the supports."""
        check_step(self, step)
        b = body_index(self, body)
        key = (b, step % len(self.history))
        if key not in self._fields:
            s = self.history[key[1]]
            c = self.corrections[b]
            u, t = c.fields(s.p)
            if s.translations is not None:
                u = u + s.translations[b]
            d = c.body.discretization
            self._fields[key] = BodySolution(
                points=d.points, normals=d.normals, displacement=u, traction=t,
                weights=d.weights, region=d.region, region_names=c.body.mesh.region_names,
                discretization=d)
        return self._fields[key]

    def reactions(self, step: int = -1) -> dict:
        """Body name -> the resultant (3,) global of its supports' reactions
        at the end of load step ``step`` (:meth:`body_fields`)."""
        out = {}
        for b, name in enumerate(self.names):
            sol = self.body_fields(name, step)
            known = self.corrections[b].held.reshape(-1, 3)
            out[name] = (sol.weights[:, None] * np.where(known, sol.traction, 0.0)).sum(axis=0)
        return out

    @property
    def converged(self) -> bool:
        return all(r.converged for r in self.records)

    @property
    def points(self) -> np.ndarray:
        """(n, 3) the cell centres in global coordinates."""
        return self.origin + self.grid.centres @ self.axes

    def summary(self) -> dict:
        """JSON-ready: the method, the grid, the corrections' estimates, and
        per step the forces, the rigid displacement, the contact area and
        counts, and the checks."""
        g = self.grid
        steps = []
        for s in self.history:
            closed = s.state != OPEN
            steps.append({
                "label": s.label,
                "contact_force": (s.force @ self.axes).tolist(),
                "normal_force": float(s.force[2]),
                "tangential_force": float(np.hypot(s.force[0], s.force[1])),
                "rigid_displacement": (s.d @ self.axes).tolist(),
                "contact_area": float(closed.sum() * g.cell_area),
                "cells": {"closed": int(closed.sum()), "stick": int((s.state == STICK).sum()),
                          "slip": int((s.state == SLIP).sum())},
                "peak_pressure": float(s.p[:, 2].max(initial=0.0)),
                "verification": s.checks,
            })
            if s.rolling is not None:
                steps[-1]["rolling"] = s.rolling
        return {
            "method": {"used": "multiscale", **self.method},
            "grid": {"nx": g.nx, "ny": g.ny, "cell_size": [g.dx, g.dy],
                     "origin": self.origin.tolist(), "axes": self.axes.tolist()},
            "corrections": {c.body.name: {"estimate": c.estimate, "anchor_error": c.anchor_error,
                                          "fit_error": c.fit_error, "coarse_nodes":
                                          int(c.body.discretization.n_points),
                                          "curvature": list(c.curvature), "seconds": c.seconds}
                            for c in self.corrections},
            "newton_iterations": [r.iterations for r in self.records],
            "krylov_iterations": [r.krylov_iterations for r in self.records],
            "timings": self.timings,
            "steps": steps,
        }


def verified_state(gi, label: str, target) -> GridState:
    """The :class:`GridState` of the interface ``gi`` (a
    :class:`~.interface.GridInterface`) at its converged solution, checked
    against the contact conditions (penetration, tension, complementarity,
    the friction cone, the prescribed forces ``target``; a ConvergenceError
    names the check that fails), with a rolling step's quantities."""
    k = gi.k(gi.p, gi.d)
    state = gi.state()
    p = gi.p
    sigma = max(float(np.abs(p).max(initial=0.0)), 1e-300)
    r = float(np.max(gi.law.r))
    q = np.linalg.norm(p[:, :2], axis=1)
    mu = np.broadcast_to(gi.law.mu, (gi.n,))
    F = gi.force()
    free = np.isfinite(target)
    checks = {
        "penetration": {"worst": float(max(-k[:, 2].min(initial=0.0), 0.0)),
                        "tolerance": EPS * sigma / r},
        "tension": {"worst": float(max(-p[:, 2].min(initial=0.0), 0.0)), "tolerance": EPS * sigma},
        "complementarity": {"worst": float(np.abs(p[:, 2] * k[:, 2]).max(initial=0.0)),
                            "tolerance": EPS * sigma * sigma / r},
        "cone": {"worst": float(max((q - mu * p[:, 2]).max(initial=0.0), 0.0)),
                 "tolerance": EPS * sigma},
        "force": {"worst": float(np.abs(F[free] - target[free]).max(initial=0.0)),
                  "tolerance": EPS * max(float(np.abs(F).max()), 1e-300)},
    }
    failed = [n for n, c in checks.items() if c["worst"] > c["tolerance"]]
    if failed:
        raise ConvergenceError(f"{label}: the grid solution fails the {', '.join(failed)} "
                               f"check(s) ({checks[failed[0]]})")
    rolling, slip = None, None
    ro = gi.rolling
    if ro is not None:
        closed = state != OPEN
        slip = np.where(closed[:, None], gi.slip(), 0.0)
        slip[state == STICK] = 0.0
        pr = np.column_stack([ro.to_rolling(p[:, :2]), p[:, 2]])
        rolling = rolling_quantities(ro.xy, pr, ro.to_rolling(slip), gi.area, closed,
                                     state == STICK, ro.rolling.speed)
        creepage = np.array(ro.rolling.creepage)
        if ro.steady:  # a force-controlled component's extra creepage (d_t / h)
            creepage = creepage + ro.to_rolling(gi.d[None, :2] / ro.h)[0]
        fn = float(F[2])
        rolling.update({
            "mode": ro.rolling.mode, "direction": list(ro.rolling.direction),
            "creepage": creepage.tolist(), "spin": ro.rolling.spin,
            "normal_force": fn,
            "creep_force_ratio": [c / (float(np.max(mu)) * fn) if fn > 0 else 0.0
                                  for c in rolling["creep_force"]],
            "rolled_distance_per_increment": ro.distance,
            "speed_used": 1.0 if ro.rolling.speed is None else ro.rolling.speed})
    return GridState(label, p.copy(), k, state, gi.d.copy(), F, checks, rolling, slip)



__all__ = ["GridResult", "GridState", "verified_state"]

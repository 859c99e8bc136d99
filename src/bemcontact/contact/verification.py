"""A-posteriori verification of a contact solution against the contact
conditions, from the recovered fields alone (never from the Newton residual
or its scaling): a converged Newton iterate that violates one of them is not
an answer.

Checks (docs/theory.md, "Verified solutions", gives each tolerance and why
it is that tight):

* ``penetration``: frame gaps g_j >= -eps sigma / r_j (r_j the node's
  augmentation, stress per length: sigma / r_j is the displacement an
  element-sized patch takes under the traction scale sigma); and no
  contact node left unpaired by the search distance lies inside the other
  body (the contact would reach beyond the paired region, unheld).
* ``tension``: pressures p_j >= -eps sigma.
* ``complementarity``: |p_j g_j| <= eps sigma^2 / r_j.
* ``cone``: |q_j| <= mu_j p_j + eps sigma (mu_j the coefficient in effect
  at the node in its last increment; 0 while it closes).
* ``slip_direction``: at slipping nodes with friction, the tangential
  traction opposite to the slip increment: |q/|q| + s/|s|| <= 1e-3 where
  |s| >= 1e-4 sigma / r_j and |q| >= 1e-4 sigma.
* ``frame_equilibrium``: per pair, the resultants its tractions put on its
  two bodies equal and opposite, to eps of their size plus what the
  coupling does not transmit (``PairResult.untransmitted``: 0 for a mortar
  frame whose surfaces both cover every frame node's support); per body,
  the resultant of its recovered contact tractions equal to what its frames
  transmit, to eps.
* ``body_equilibrium``: per body, the resultant of all its surface
  tractions (contact, reactions, applied loads) and body forces against
  their total magnitude sum w_i |t_i| + ∫ |f| dV, to :data:`EQUILIBRIUM`
  (the collocation BEM balances forces only to its discretization error),
  or to the round-off of the forces its displacements cause
  (:data:`ROUND_OFF`), whichever is larger.
* ``small_displacements``: per body, max |u| (rigid motion included) at most
  :data:`SMALL` of its size (the formulation's small-displacement
  assumption).

``eps`` is :data:`EPS`.  Sign conventions as in :mod:`.results`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .law import SLIP

#: Relative tolerance of the conditions the Newton solve enforces on the
#: frame (at convergence they hold to the Newton tolerance, 1e-10 of the
#: traction scale by default: 1e-6 leaves four orders of margin and a wrong
#: answer violates them at order one).
EPS = 1e-6
#: The slip-direction check: |q̂ + ŝ| at most this (an angle in radians) ...
ANGLE = 1e-3
#: ... at nodes whose slip increment and traction exceed this fraction of
#: their scales (below it the direction rests on round-off).
DIRECTION_FLOOR = 1e-4
#: A body's force balance, relative to the total magnitude of its surface
#: forces.
EQUILIBRIUM = 2e-2
#: A body's force balance is also met below this fraction of the force its
#: displacements would cause at its contacts' stiffness (r |u| size²): the
#: round-off of tractions that balance nothing (a body moved clear of
#: every contact carries only that).
ROUND_OFF = 1e-10
#: Largest displacement, relative to the body's size.
SMALL = 0.1
#: Gaps are compared with at least this fraction of the bodies' size (the
#: round-off of coordinates).
GEOMETRY = 1e-12

#: The checks, in the order they are reported.
CHECKS = ("penetration", "tension", "complementarity", "cone", "slip_direction",
          "frame_equilibrium", "body_equilibrium", "small_displacements")


@dataclass
class Check:
    """One check's worst value over the solution and its tolerance
    (``value <= tolerance`` passes), with where it occurred: ``where`` a
    text ("frame a:zmax/b:zmin node 12 at (1, 2, 3)"), ``location`` the same
    as data (pair or body, node, point, step label)."""

    name: str
    value: float = 0.0
    tolerance: float = 0.0
    where: str = ""
    location: dict = field(default_factory=dict)
    #: the quantity behind ``value`` in the problem's units, for the message
    detail: str = ""

    @property
    def passed(self) -> bool:
        return bool(self.value <= self.tolerance)

    @property
    def ratio(self) -> float:
        """value / tolerance (0 when both are 0)."""
        if self.value <= 0.0:
            return 0.0
        return float(self.value / self.tolerance) if self.tolerance > 0.0 else float("inf")

    def line(self) -> str:
        """One line naming the check, the worst node and its value."""
        at = f" at {self.where}" if self.where else ""
        return (f"{self.name} violated{at}: {self.detail or f'{self.value:.3g}'} "
                f"(tolerance {self.tolerance:.3g})")

    def summary(self) -> dict:
        return {"value": float(self.value), "tolerance": float(self.tolerance),
                "passed": self.passed, "where": self.where,
                **({"step": self.location["step"]} if "step" in self.location else {})}


@dataclass
class Verification:
    """Every check of one solution (or the worst of each over a history)."""

    checks: dict[str, Check]

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks.values())

    @property
    def failed(self) -> list[Check]:
        """The failed checks, worst ratio first."""
        return sorted((c for c in self.checks.values() if not c.passed),
                      key=lambda c: -c.ratio)

    @property
    def worst_ratio(self) -> float:
        """The largest value / tolerance over the checks."""
        return max((c.ratio for c in self.checks.values()), default=0.0)

    def message(self) -> str:
        """'' when every check passed; else the worst failure in one line."""
        f = self.failed
        return "" if not f else "verification failed: " + f[0].line()

    def summary(self) -> dict:
        """JSON-ready: per check its worst value, tolerance and where."""
        return {"passed": self.passed, "worst_ratio": self.worst_ratio,
                "checks": {n: c.summary() for n, c in self.checks.items()}}

    @staticmethod
    def worst(verifications: list[Verification]) -> Verification:
        """The worst of each check over ``verifications`` (a load history)."""
        out: dict[str, Check] = {}
        for v in verifications:
            for name, c in v.checks.items():
                if name not in out or c.ratio > out[name].ratio:
                    out[name] = c
        return Verification({n: out[n] for n in CHECKS if n in out})


class _Worst:
    """The node with the largest value / tolerance of one check."""

    def __init__(self, name: str, tolerance: float = 0.0) -> None:
        self.check = Check(name, 0.0, tolerance)
        self._ratio = -np.inf

    def offer(self, value, tolerance, where, location, detail="") -> None:
        value = np.asarray(value, dtype=float)
        tolerance = np.broadcast_to(np.asarray(tolerance, dtype=float), value.shape)
        if not value.size:
            return
        ratio = np.where(tolerance > 0, value / np.where(tolerance > 0, tolerance, 1.0),
                         np.where(value > 0, np.inf, 0.0))
        j = int(np.argmax(ratio))
        if ratio[j] > self._ratio:
            self._ratio = float(ratio[j])
            w, loc = where(j), location(j)
            self.check = Check(self.check.name, float(value[j]), float(tolerance[j]), w, loc,
                               detail(j) if callable(detail) else detail)


def _at(p) -> str:
    return "(" + ", ".join(f"{c:.4g}" for c in p) + ")"


def _size(points: np.ndarray) -> float:
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))) if len(points) else 0.0


def verify(result) -> Verification:
    """The checks of one :class:`~bemcontact.contact.results.ContactResult`
    (its state at the end of its load step)."""
    w = {n: _Worst(n) for n in CHECKS}
    w["slip_direction"] = _Worst("slip_direction", ANGLE)
    sizes = {name: _size(b.points) for name, b in zip(result.names, result.bodies)}
    bodies = dict(zip(result.names, result.bodies))
    step = {"step": result.label} if result.label else {}
    received: dict[str, list] = {}
    stiffness: dict[str, float] = {}  # per body, its pairs' largest augmentation
    for pair in result.pairs:
        fr = pair.frame
        label = pair.label
        act = np.isfinite(fr.gap)
        idx = np.flatnonzero(act)
        p = fr.pressure[act]
        q = fr.tangential_traction[act]
        g = fr.gap[act]
        qn = np.linalg.norm(q, axis=1)
        tb = [bodies[n].traction for n in pair.names]
        sigma = max(float(np.abs(p).max(initial=0.0)), float(qn.max(initial=0.0)),
                    *(float(np.abs(t).max(initial=0.0)) for t in tb), 1e-300)
        r = fr.augmentation[act] if fr.augmentation.size else np.full(idx.size, np.inf)
        geo = GEOMETRY * max(sizes[n] for n in pair.names)
        mu = fr.friction[act] if fr.friction.size else np.zeros(idx.size)

        def where(j, idx=idx, fr=fr, label=label):
            return f"frame {label} node {int(idx[j])} {_at(fr.points[idx[j]])}"

        def location(j, idx=idx, fr=fr, label=label):
            return {"pair": label, "node": int(idx[j]),
                    "point": [float(c) for c in fr.points[idx[j]]], **step}

        w["penetration"].offer(-g, np.maximum(EPS * sigma / r, geo), where, location,
                               lambda j, g=g: f"gap {g[j]:.3g}")
        # a contact node never paired with the frame (its initial gap beyond
        # the search distance) but over the other surface must stay out of
        # it: nothing would hold it, and the contact cut there is wrong
        r_max = float(np.max(r, initial=0.0)) or np.inf
        for n in pair.names:
            if np.isfinite(r_max):
                stiffness[n] = max(stiffness.get(n, 0.0), r_max)
        for i in pair.interfaces:
            if not i.paired.size:
                continue
            k = np.flatnonzero(~i.paired & np.isfinite(i.gap))
            w["penetration"].offer(
                -i.gap[k], max(EPS * sigma / r_max, geo),
                lambda j, k=k, i=i: (f"body {i.body} node {int(i.nodes[k[j]])} "
                                     f"{_at(i.points[k[j]])}, beyond the paired region"),
                lambda j, k=k, i=i: {"body": i.body, "node": int(i.nodes[k[j]]),
                                     "point": [float(c) for c in i.points[k[j]]], **step},
                lambda j, k=k, i=i: (f"gap {i.gap[k[j]]:.3g} (raise contact.search_distance "
                                     "to pair it)"))
        w["tension"].offer(-p, EPS * sigma, where, location,
                           lambda j, p=p: f"pressure {p[j]:.3g}")
        w["complementarity"].offer(np.abs(p * g), np.maximum(EPS * sigma**2 / r, geo * sigma),
                                   where, location,
                                   lambda j, p=p, g=g: f"pressure {p[j]:.3g} with gap {g[j]:.3g}")
        w["cone"].offer(qn - mu * p, EPS * sigma, where, location,
                        lambda j, qn=qn, mu=mu, p=p:
                        f"|q| {qn[j]:.3g} > mu p {mu[j] * p[j]:.3g}")
        if fr.slip_increment.size:
            s = fr.slip_increment[act]
            sn = np.linalg.norm(s, axis=1)
            sel = ((fr.state[act] == SLIP) & (mu > 0) & (sn >= DIRECTION_FLOOR * sigma / r)
                   & (qn >= DIRECTION_FLOOR * sigma))
            if sel.any():
                k = np.flatnonzero(sel)
                dev = np.linalg.norm(q[k] / qn[k, None] + s[k] / sn[k, None], axis=1)
                w["slip_direction"].offer(
                    dev, ANGLE, lambda j, k=k, where=where: where(k[j]),
                    lambda j, k=k, location=location: location(k[j]),
                    lambda j, dev=dev: f"traction {dev[j]:.3g} off the direction opposite "
                                       "to the slip increment")
        # the two bodies' interface resultants, equal and opposite up to what
        # the coupling does not transmit
        T = pair.transmitted
        mag = float(np.linalg.norm(T, axis=1).sum())
        w["frame_equilibrium"].offer(
            [float(np.linalg.norm(T[0] + T[1]))], [EPS * max(mag, 1e-300) + pair.untransmitted],
            lambda j, label=label: f"pair {label}",
            lambda j, label=label: {"pair": label, **step},
            lambda j, T=T: f"interface resultants {_at(T[0])} and {_at(T[1])}")
        for side, name in enumerate(pair.names):
            received.setdefault(name, [np.zeros(3), set()])
            received[name][0] = received[name][0] + T[side]
            received[name][1].update(pair.interfaces[side].nodes.tolist())
    # each body's recovered contact tractions carry what the frames transmit
    for name, (T, nodes) in received.items():
        b = bodies[name]
        i = np.fromiter(sorted(nodes), dtype=np.int64)
        F = b.weights[i] @ b.traction[i]
        mag = float(np.abs(b.weights[i]) @ np.linalg.norm(b.traction[i], axis=1))
        w["frame_equilibrium"].offer(
            [float(np.linalg.norm(F - T))], [EPS * max(mag, 1e-300)],
            lambda j, name=name: f"body {name}'s contact surfaces",
            lambda j, name=name: {"body": name, **step},
            lambda j, F=F, T=T: f"contact tractions' resultant {_at(F)} against the frame's "
                                f"{_at(T)}")
    for name, b in zip(result.names, result.bodies):
        if not getattr(b, "whole_boundary", True):  # its reaction lies beyond its fields
            continue
        f = np.linalg.norm(b.traction, axis=1)
        mag = float(np.abs(b.weights) @ f)
        R = b.weights @ b.traction
        if b.volume_force is not None:  # a body force: the tractions balance it
            R = R + b.volume_force[0]
            mag += b.volume_force[1]
        u = np.linalg.norm(b.displacement, axis=1)
        noise = ROUND_OFF * stiffness.get(name, 0.0) * float(u.max(initial=0.0)) * sizes[name] ** 2
        w["body_equilibrium"].offer(
            [float(np.linalg.norm(R))], [max(EQUILIBRIUM * mag, noise, 1e-300)],
            lambda j, name=name: f"body {name}", lambda j, name=name: {"body": name, **step},
            lambda j, R=R, mag=mag: f"resultant {_at(R)} against {mag:.3g} of surface forces")
        if u.size:
            w["small_displacements"].offer(
                u, SMALL * sizes[name],
                lambda j, name=name, b=b: f"body {name} node {j} {_at(b.points[j])}",
                lambda j, name=name, b=b: {"body": name, "node": int(j),
                                           "point": [float(c) for c in b.points[j]], **step},
                lambda j, u=u, name=name: f"displacement {u[j]:.3g} for a body of size "
                                          f"{sizes[name]:.3g}")
    return Verification({n: w[n].check for n in CHECKS})


def verified(result, history=None) -> bool:
    """Set ``result.verification`` (its own checks, or with ``history`` the
    worst of each over the history's results, verified each in turn);
    True when a check failed."""
    if history:
        for h in history:
            if h.verification is None:
                h.verification = verify(h)
        result.verification = Verification.worst([h.verification for h in history])
    else:
        result.verification = verify(result)
    return not result.verification.passed


__all__ = ["Check", "Verification", "verify", "verified", "CHECKS", "EPS", "EQUILIBRIUM", "SMALL"]

"""A loading history solved increment by increment: each increment from the
law's history at its start (:meth:`~bemcontact.contact.interface.
InterfaceSystem.start_increment`), by Newton from the coarse predictor's
starting point (:mod:`~bemcontact.contact.increment`); each step's end
recovered and verified against the contact conditions
(:mod:`~bemcontact.contact.verification`)."""

from __future__ import annotations

import time

import numpy as np

from ..progress import ProgressEvent
from .increment import closed_text, solve_increment
from .newton import NewtonSteps
from .predictor import Predictor
from .recovery import Recovery
from .results import ContactResult, StepRecord
from ..errors import ConfigError
from .rolling import FrameRolling, rolling_quantities
from .verification import verified


def frame_rolling(frames, step, gap=None, index: int = 0, friction=None):
    """The :class:`~.rolling.FrameRolling` of ``step`` (the ``index``-th) on
    the active nodes of ``frames`` (a FrameSet; ``gap`` (m,) their initial
    gaps: the rolling frame's origin is each pair's first touch), None when
    it does not roll; a direction off a pair's contact plane, or a history
    rolling frictionless pairs only (``friction``, one per pair), is a
    one-line ConfigError naming ``step[index].rolling``."""
    if step.rolling is None:
        return None
    where = {"step": index, "field": "rolling"}
    if friction is not None and not any(f > 0.0 for f in friction):
        raise ConfigError(f"step[{index}].rolling: a frictionless pair: rolling carries no "
                          "creep force without friction; give contact.friction_coefficient > 0",
                          location=where)
    try:
        return FrameRolling(step.rolling, frames.points, frames.Q, frames.size, frames.weights,
                            frames.pair_of, gap)
    except ConfigError as exc:
        raise ConfigError(f"step[{index}].{exc}", location={**exc.location, **where}) from None


def microslip(result, system) -> None:
    """A rolling step's frame fields: each pair's micro-slip per rolled
    distance (the law's slip increment over Δq, zero where it sticks or is
    open) and frictional power density (:class:`~.results.FrameResult`)."""
    ro = system.rolling
    if ro is None:
        return
    speed = 1.0 if ro.rolling.speed is None else ro.rolling.speed
    for p, pr in enumerate(result.pairs):
        fr = pr.frame
        dq = float(ro.distance[system.frames.slice(p)][0])
        s = np.where((fr.state == 2)[:, None], fr.slip_increment / dq, 0.0)
        fr.microslip = s
        fr.power_density = -np.einsum("ij,ij->i", fr.tangential_traction, s) * speed


def rolled(system, z, ell) -> dict | None:
    """A rolling increment's quantities at its converged ``z``
    (:func:`~.rolling.rolling_quantities`: the first pair's, and with
    several pairs each pair's under ``pairs``), while the system still sees
    the convected slip; None when it does not roll."""
    ro = system.rolling
    if ro is None:
        return None
    from .law import OPEN, STICK

    lam = system.split(z)[0].reshape(-1, 3)
    k = system.law_k(z, ell)
    state = system.law.state(lam, k)
    slip = (k[:, :2] - system.law.reference) / ro.distance[:, None]
    slip[state != 2] = 0.0
    Q = system.frames.Q
    p_r = np.column_stack([ro.to_rolling(lam[:, :2], Q), lam[:, 2]])
    s_r = ro.to_rolling(slip, Q)
    upstream = np.zeros(system.m, dtype=bool)  # nodes the shift reaches from upstream
    upstream[np.unique(ro.S.tocoo().row // 2)] = True
    lv = np.zeros(3 * system.m)  # the rigid unknowns' shift: Δq times an extra creepage
    for L, v in zip(system.L, system.split(z)[1]):
        if v.size:
            lv = lv + L @ v

    def pair(p):
        on = system.pair_of == p
        out = rolling_quantities(ro.xy[on], p_r[on], s_r[on], system.a[on],
                                 (state != OPEN)[on], (state == STICK)[on], ro.rolling.speed)
        fn = float(system.a[on] @ lam[on, 2])
        mu = float(np.max(system.law.friction[on]))
        creepage = np.array(ro.rolling.creepage)
        if ro.steady:
            t = lv.reshape(-1, 3)[on, :2] / ro.distance[on][:, None]
            g = np.einsum("nji,ni->nj", Q[on][:, :, :2], t)  # global
            creepage = creepage + np.einsum("nij,nj->ni", ro.frames[on], g).mean(axis=0)
        out.update({"mode": ro.rolling.mode, "direction": list(ro.rolling.direction),
                    "creepage": creepage.tolist(), "spin": ro.rolling.spin,
                    "normal_force": fn,
                    "creep_force_ratio": [c / (mu * fn) if fn > 0 and mu > 0 else 0.0
                                          for c in out["creep_force"]],
                    "rolled_distance_per_increment": float(ro.distance[on][0]),
                    "origin": ro.origins[on][0].tolist()})
        return out

    npairs = int(system.pair_of.max()) + 1
    out = pair(0)
    if npairs > 1:
        out["pairs"] = [pair(p) for p in range(npairs)]
    out["without_upstream"] = bool(np.any((state != OPEN) & ~upstream))
    return out


def solve_history(system, pairs, steps, opt, report):
    """Solve the interface ``system`` (of the contact ``pairs``) along the
    load ``steps`` with the options ``opt``; ``report`` receives the
    progress events.  Returns (the :class:`ContactResult` at the end, with
    the result of every step's end in its ``history`` when there are
    several, the failure message or None, the seconds of the Newton
    phase)."""
    recover = Recovery(system)
    t3 = time.perf_counter()
    steps_solver = NewtonSteps(reuse=opt.newton_steps == "mixed")
    predictor = (Predictor(system, system.frames.points) if opt.predictor == "coarse"
                 else None)
    records: list[StepRecord] = []
    history: list[ContactResult] = []
    z = system.zero()
    failed: str | None = None
    S = len(steps)
    ell = np.zeros(S)
    total = sum(st.increments for st in steps)
    done = 0
    for s_, step in enumerate(steps):
        prev = ell.copy()
        target = np.zeros(S)
        target[s_] = 1.0
        name = f"step {s_ + 1}/{S}{f' ({step.label})' if step.label else ''}"
        rolling = frame_rolling(system.frames, step, system.k0X[2::3], s_)
        for i in range(1, step.increments + 1):
            tau = i / step.increments
            # the state this increment starts from: the law's history
            # (convected when the step rolls)
            system.roll(z, ell, rolling)
            ell_prev, ell = ell, (1 - tau) * prev + tau * target
            done += 1
            if report is not None:
                report(ProgressEvent("increment", "newton",
                                     f"{name} increment {i}/{step.increments}"
                                     + closed_text(system, pairs, z, ell_prev),
                                     index=done, total=total))
            # the coarse predictor's aggregated systems are the static map's
            z, rec, msg = solve_increment(system, predictor if rolling is None else None, z,
                                          ell_prev, ell, opt, report, done, total,
                                          steps_solver)
            rec.load_factor = tau
            rec.step = s_ + 1
            rec.label = step.label
            records.append(rec)
            if msg is not None:
                failed = f"{name}, increment {i}/{step.increments}: {msg}"
                break
        quantities = None if failed is not None else rolled(system, z, ell)
        if quantities is not None and quantities.pop("without_upstream"):
            failed = (f"{name}: the contact reaches the leading side of the frame's active "
                      "nodes (a closed node has no upstream point to convect from); give a "
                      "larger contact surface or search_distance")
        if failed is not None:
            break
        if S > 1:
            res = recover(z, ell, list(records))
            res.rolling = quantities
            microslip(res, system)
            res.label = step.label
            history.append(res)
            if verified(res):  # every step's end against the contact conditions
                failed = f"{name}: {res.verification.message()}"
                break
    t4 = time.perf_counter()
    system.release()
    if report is not None and failed is None:
        its = sum(r.iterations for r in records)
        report(ProgressEvent("end", "newton", f"{total} load increment(s), {its} Newton "
                             "iteration(s)" + closed_text(system, pairs, z, ell),
                             index=total, total=total, seconds=t4 - t3))
    # states are those of the last increment, judged against its starting slip
    result = recover(z, ell, records)
    result.rolling = None if failed else quantities
    if result.rolling is not None:
        microslip(result, system)
    result.label = steps[s_ if failed else -1].label
    result.history = history if S > 1 else [result]
    if verified(result, history if S > 1 else None) and failed is None:
        failed = f"{name}: {result.verification.message()}"
    result.converged = result.converged and failed is None
    return result, failed, t4 - t3


__all__ = ["solve_history"]

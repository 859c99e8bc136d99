"""Two elastic bodies in contact: the problem, its loading history and the
solve (condensation, then the generalized Newton method per load increment)."""

from __future__ import annotations

import difflib
import time
import warnings
from collections.abc import Mapping
import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._native import core
from ..errors import ConfigError, ConvergenceError, ResourceLimitWarning
from ..linalg.threads import blas_threads, usable_threads
from ..mesh.element import CORNERS
from ..settings import Key, check_settings, setting
from ..progress import Reporter, Stopwatch, print_lines, ProgressEvent
from .flexibility import Body
from .frame import ContactFrame
from .frames import FrameSet
from .increment import closed_text, solve_increment
from .interface import InterfaceSystem
from .memory import (
    MemoryEstimate, allowed, available_text, estimate, frame_bytes, machine_memory,
    resident_bytes,
)
from .newton import NewtonSteps
from .options import SolverOptions
from .origin import own_origin, translated_bodies, translated_result, translated_states
from .pair import ContactPair
from .predictor import Predictor
from .recovery import Recovery
from .verification import verified
from .results import ContactResult, StepRecord
from .reuse import Condensation, CondenseBody, condense_problem


# --------------------------------------------------------------------------- load steps


@dataclass(frozen=True)
class LoadStep:
    """One state of a loading history.

    Attributes
    ----------
    conditions:
        Body name -> region -> boundary condition(s) that *change* at this
        step; every other region keeps its condition of the previous state
        (the first step starts from the bodies' own conditions).  A step may
        change values only, not the kind of condition of a component
        (displacement, traction or force): to apply a tangential force later,
        give that component ``Force`` with value 0 from the start.
    increments:
        The step is reached in this many equal increments, each a linear
        interpolation between the previous state and this one (friction is
        path dependent: use several for a path that matters).
    label:
        Name used in messages and results.

    The history starts unloaded; slip is measured from the start of each
    increment, so a stuck point is one with no new slip in it.
    """

    conditions: Any = field(default_factory=dict)
    increments: int = setting(Key(
        "increments", "integer", "the step is reached in this many linear increments from "
        "the previous state", default=1, lo=1))
    label: str = setting(Key(
        "label", "string", "the step's name in messages and summary.json", default=""))

    def __post_init__(self) -> None:
        check_settings(self)
        if not isinstance(self.conditions, Mapping) or not all(
            isinstance(k, str) and isinstance(c, Mapping) for k, c in self.conditions.items()
        ):
            raise ConfigError(
                "LoadStep.conditions must map body names to {region: condition(s)}, got "
                f"{self.conditions!r}"
            )


_KIND_NAMES = ("traction", "displacement", "force")


def _sequence(name: str, value) -> list:
    if value is None or isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise ConfigError(f"{name} must be a list, got {value!r}")
    return list(value)


def _kinds(body, conditions) -> np.ndarray:
    """(3N,) 0 traction (or free), 1 displacement, 2 force per dof."""
    known_u, _ = body.boundary_data(conditions)
    k = known_u.astype(np.int8)
    for c in body.controls(conditions):
        k[c.dofs] = 2
    return k


# --------------------------------------------------------------------------- problem


class ContactProblem:
    """Elastic bodies in contact: two bodies and their contact pair, or an
    assembly of any number of bodies and pairs.

    Parameters
    ----------
    body1, body2, pair:
        Two bodies with distinct names (:class:`~bemcontact.bem.body.ElasticBody`
        objects, or any :class:`~bemcontact.contact.flexibility.Body`) and the
        :class:`ContactPair` between them (its ``bodies``, if given, must name
        them in this order).
    bodies, pairs:
        Instead (keywords only): an assembly, ``bodies`` (two or more, with
        distinct names) and ``pairs`` (one or more, each naming its two
        bodies in ``ContactPair.bodies``).  A body may take part in several
        pairs, on different surfaces or on one surface against several
        bodies; every body must be in a pair.  Each body is condensed once
        on the union of its contact surfaces, and one generalized Newton
        method solves all frames at once (docs/theory.md).

    A contact surface must carry no boundary condition.  Bodies far from the
    global origin (beyond :data:`~bemcontact.contact.origin.FAR` times their
    extent) are solved relative to ``origin``, a node's coordinates
    (:mod:`bemcontact.contact.origin`): a rigid offset of the whole problem
    changes nothing, and results are returned at the bodies' own position.
    The :attr:`frame` and a ``Condensation`` are those of the translated
    bodies (points relative to ``origin``).
    """

    def __init__(self, body1: Body | None = None, body2: Body | None = None,
                 pair: ContactPair | None = None, *, bodies=None, pairs=None) -> None:
        if bodies is not None or pairs is not None:
            if body1 is not None or body2 is not None or pair is not None:
                raise ConfigError(
                    "give either body1, body2 and pair, or bodies= and pairs=, not both")
            bodies, pairs = _sequence("bodies", bodies), _sequence("pairs", pairs)
            named = True
        else:
            for i, b in enumerate((body1, body2)):
                if not isinstance(b, Body):
                    raise ConfigError(f"body{i + 1} must be an ElasticBody (or a Body), got "
                                      f"{type(b).__name__}")
            bodies, pairs, named = [body1, body2], [pair], False
        for i, b in enumerate(bodies):
            if not isinstance(b, Body):
                raise ConfigError(f"bodies[{i}] must be an ElasticBody (or a Body), got "
                                  f"{type(b).__name__}")
        for i, p in enumerate(pairs):
            if not isinstance(p, ContactPair):
                what = "pair" if not named else f"pairs[{i}]"
                raise ConfigError(f"{what} must be a ContactPair, got {type(p).__name__}")
        names = [b.name for b in bodies]
        if len(bodies) < 2:
            raise ConfigError(f"an assembly needs at least two bodies, got {len(bodies)}")
        if not pairs:
            raise ConfigError("an assembly needs at least one contact pair (pairs=[])")
        for i, n in enumerate(names):
            if n in names[:i]:
                raise ConfigError(f"two bodies have the same name {n!r}; name them apart")
        self.bodies = tuple(bodies)
        self.pairs = tuple(pairs)
        self.links = tuple(self._link(i, p, names, named) for i, p in enumerate(pairs))
        self._check_surfaces()
        #: the first (in a two-body problem the only) contact pair
        self.pair = self.pairs[0]
        #: the point the bodies are solved relative to (None: the global origin)
        self.origin = own_origin(self.bodies)
        self._solved = (self.bodies if self.origin is None
                        else translated_bodies(self.bodies, self.origin))
        self._frames: FrameSet | None = None

    @staticmethod
    def _link(i: int, p: ContactPair, names: list[str], named: bool) -> tuple[int, int]:
        """The body indices of pair ``i`` (checked)."""
        if p.bodies is None:
            if named:
                raise ConfigError(
                    f"pairs[{i}] ({p.label}): name its two bodies (ContactPair.bodies); "
                    f"the bodies are {names}")
            return (0, 1)
        for b in p.bodies:
            if b not in names:
                close = difflib.get_close_matches(b, names, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise ConfigError(
                    f"{'pairs[%d]' % i if named else 'pair'} ({p.label}): unknown body {b!r}"
                    f"{hint}; the bodies are {names}")
        link = (names.index(p.bodies[0]), names.index(p.bodies[1]))
        if not named and link != (0, 1):
            raise ConfigError(
                f"pair.bodies is {list(p.bodies)}; it must name body 1 and body 2, "
                f"{names[:2]}, in this order")
        return link

    def _check_surfaces(self) -> None:
        """Every contact surface a region of its body without a boundary
        condition; no pair twice; every body in a pair."""
        seen: dict[frozenset, int] = {}
        for i, (p, link) in enumerate(zip(self.pairs, self.links)):
            where = f"pairs[{i}] ({p.label})" if len(self.pairs) > 1 else "pair"
            for b, s in zip((self.bodies[a] for a in link), (p.surface1, p.surface2)):
                if s not in b.region_names:
                    raise ConfigError(
                        f"{where}: {b.name}: unknown contact surface {s!r}; the mesh has regions "
                        f"{list(b.region_names)}"
                    )
                if s in b.boundary_conditions:
                    raise ConfigError(
                        f"{b.name}: the contact surface {s!r} also has a boundary condition; "
                        "remove it"
                    )
            key = frozenset({(link[0], p.surface1), (link[1], p.surface2)})
            if key in seen:
                raise ConfigError(
                    f"{where}: the same surfaces as pairs[{seen[key]}] "
                    f"({self.pairs[seen[key]].label}); give each pair once")
            seen[key] = i
        used = {a for link in self.links for a in link}
        for a, b in enumerate(self.bodies):
            if a not in used:
                raise ConfigError(
                    f"body {b.name!r} is in no contact pair; add its pair, or solve it on its "
                    "own (ElasticBody.solve)")

    def surfaces(self, a: int) -> list[str]:
        """The contact surfaces of body ``a`` (in the order of its pairs)."""
        out = []
        for p, link in zip(self.pairs, self.links):
            for side, b in enumerate(link):
                s = (p.surface1, p.surface2)[side]
                if b == a and s not in out:
                    out.append(s)
        return out

    @property
    def frames(self) -> FrameSet:
        """The contact frames of all pairs (built on first use)."""
        if self._frames is None:
            frames = []
            for i, (p, link) in enumerate(zip(self.pairs, self.links)):
                b1, b2 = (self._solved[a] for a in link)
                try:
                    f = ContactFrame(
                        b1.trace, p.surface1, b2.trace, p.surface2,
                        p.frame, names=(b1.name, b2.name),
                        search_distance=p.search_distance,
                        owner={"body1": 0, "body2": 1}.get(p.frame_on),
                        between="auto" if p.frame_on == "auto" else p.frame_on == "between",
                        projected=p.relative_displacement == "projected",
                    )
                except ConfigError as exc:
                    exc.location.setdefault("pair", i)
                    if len(self.pairs) == 1:
                        raise
                    raise ConfigError(f"pairs[{i}] ({p.label}): {exc}", location=exc.location,
                                      detail=exc.detail) from None
                if len(self.pairs) > 1 and not f.active.any():
                    detail = (f"the two surfaces are nowhere within the search distance "
                              f"({f.search_distance:g}) of each other, so they can never touch; "
                              "move the bodies or raise contact.search_distance")
                    raise ConfigError(f"pairs[{i}] ({p.label}): {detail}",
                                      location={"pair": i}, detail=detail)
                frames.append(f)
            self._frames = FrameSet(frames, self.links, len(self.bodies))
        return self._frames

    @property
    def frame(self) -> ContactFrame:
        """The contact frame of the first (in a two-body problem the only)
        pair; an assembly's are in :attr:`frames`."""
        return self.frames.frames[0]

    def frame_memory(self) -> float:
        """Peak bytes of the frame builds (the largest pair's), from the
        contact surfaces' element counts alone
        (:func:`~bemcontact.contact.memory.frame_bytes`)."""
        peak = 0.0
        for p, link in zip(self.pairs, self.links):
            counts, k, corners = [], 0, 0
            for a, s in zip(link, (p.surface1, p.surface2)):
                m = self.bodies[a].trace.mesh
                counts.append(int(np.count_nonzero(m.element_region == m.region_names.index(s))))
                k, corners = max(k, m.elements.shape[1]), max(corners, CORNERS[m.element_type])
            peak = max(peak, frame_bytes(counts, k, corners))
        return peak

    def memory_estimate(self, options: SolverOptions | None = None, steps=None) -> MemoryEstimate:
        """Peak memory of :meth:`solve` with these ``options`` and ``steps``
        (:mod:`bemcontact.contact.memory`), from the sizes; builds the frame
        (:meth:`solve` first checks the frame build's own estimate)."""
        opt = options or SolverOptions()
        steps = [LoadStep(increments=opt.load_steps)] if steps is None else list(steps)
        states = self.states(steps)
        fs = self.frames
        return estimate(
            self.bodies, [fs.nodes(a).size for a in range(len(self.bodies))],
            fs.m, len(states),
            [len(b.controls(states[0][a])) for a, b in enumerate(self.bodies)], opt.linear,
            self.frame_memory(),
        )

    def _at_origin(self, states):
        """``states`` for the bodies as solved (relative to ``origin``)."""
        return states if self.origin is None else translated_states(states, self.origin)

    def _back(self, result):
        """``result`` of the bodies as solved, at the bodies' own position."""
        if self.origin is None or result is None:
            return result
        return translated_result(result, self.origin, [b.trace.mesh for b in self.bodies])

    def _check_memory(self, opt, steps) -> None:
        """Refuse a solve whose estimated peak exceeds the machine's available
        memory by more than the estimate's uncertainty (it would be killed
        out of memory after minutes); warn when it comes close.  The frame
        build is checked first, before it allocates."""
        self.check_frame_memory()
        total, available = machine_memory()
        est = self.memory_estimate(opt, steps)
        self._refuse(est, available, "compressed operators ([solver.linear] method = "
                     "\"hmatrix\") or smaller contact surfaces")
        if est.peak > 0.9 * available:
            warnings.warn(
                f"the solve needs about {est.text()}, close to {available_text(available)}",
                ResourceLimitWarning,
                stacklevel=3,
            )

    def check_frame_memory(self) -> None:
        """Refuse (ConfigError, one line) to build a frame whose estimated
        peak (:meth:`frame_memory`) exceeds the available memory by more
        than the estimate's uncertainty; nothing once the frame is built."""
        if self._frames is None:
            self._refuse(MemoryEstimate({"frame": self.frame_memory()}, resident_bytes()),
                         machine_memory()[1], "coarser or smaller contact surfaces")

    @staticmethod
    def _refuse(est: MemoryEstimate, available: float, fix: str) -> None:
        if est.peak > allowed(available):
            raise ConfigError(
                f"the solve needs about {est.text()}, more than {available_text(available)}; "
                f"use {fix}"
            )

    def contact_modulus(self, pair: int = 0) -> float:
        """E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) of the bodies of
        ``pair`` (an index into :attr:`pairs`)."""
        return 1.0 / sum(self.bodies[a].contact_compliance for a in self.links[pair])

    def states(self, steps) -> list[list[dict]]:
        """The boundary-condition state reached at each step, per body
        (checked: known bodies and regions, no condition on a contact
        surface, the same kind of condition per component throughout)."""
        names = [b.name for b in self.bodies]
        surfaces = [self.surfaces(a) for a in range(len(self.bodies))]
        current = [dict(b.boundary_conditions) for b in self.bodies]
        base = [_kinds(b, c) for b, c in zip(self.bodies, current)]
        out = []
        for i, step in enumerate(steps):
            try:
                if not isinstance(step, LoadStep):
                    raise ConfigError(
                        f"steps[{i}] must be a LoadStep, got {type(step).__name__}")
                where = f"step {i + 1}{f' ({step.label})' if step.label else ''}: "
                current = [dict(c) for c in current]
                for name, changes in step.conditions.items():
                    if name not in names:
                        raise ConfigError(f"{where}unknown body {name!r}; the bodies are {names}")
                    a = names.index(name)
                    body = self.bodies[a]
                    checked = body.checked_conditions(changes, where=where)
                    for s_ in surfaces[a]:
                        if s_ in checked:
                            raise ConfigError(
                                f"{where}{name}: region {s_!r} is "
                                f"{'the' if len(surfaces[a]) == 1 else 'a'} contact surface; it "
                                "cannot carry a boundary condition"
                            )
                    current[a].update(checked)
                    kinds = _kinds(body, current[a])
                    diff = np.flatnonzero(kinds != base[a])
                    if diff.size:
                        dof = int(diff[0])
                        region = body.region_names[int(body.trace.region[dof // 3])]
                        raise ConfigError(
                            f"{where}{name}: region {region!r} component {'xyz'[dof % 3]} "
                            f"changes from {_KIND_NAMES[base[a][dof]]} to "
                            f"{_KIND_NAMES[kinds[dof]]}; a step may change values, not kinds "
                            "(give the component its later kind from the start, e.g. Force "
                            "with value 0)"
                        )
            except ConfigError as exc:  # where, as data: the step
                exc.location.setdefault("step", i)
                raise
            out.append(current)
        return out

    def solve(
        self,
        options: SolverOptions | None = None,
        *,
        steps=None,
        raise_on_failure: bool = True,
        progress: Reporter | None = None,
        condensed: Condensation | None = None,
    ) -> ContactResult:
        """Condense both bodies, then run the generalized Newton method for
        each increment of the loading history.

        ``steps``: a sequence of :class:`LoadStep`; default one step to the
        bodies' own conditions in ``options.load_steps`` proportional
        increments.  Returns the result at the end of the last step, whose
        ``history`` lists the results at the end of every step.  Raises
        :class:`ConvergenceError` (carrying the result so far and its
        residual history) if an increment fails, unless ``raise_on_failure``
        is False.

        ``progress``: a callable receiving :class:`~bemcontact.progress.ProgressEvent` objects
        (stages, load increments, Newton iterations), e.g.
        :class:`~bemcontact.progress.LiveProgress`; default
        :func:`~bemcontact.progress.print_lines` if ``options.progress``, else none.

        ``condensed``: a :class:`~bemcontact.contact.reuse.Condensation` of
        these bodies (:meth:`condense`, possibly of another problem object
        with the same meshes, materials, frame and kinds of condition): the
        solve reuses its condensed operators, so only the friction, the
        penalty, the load values and history and the Newton options may
        differ (ConfigError otherwise)."""
        opt = options or SolverOptions()
        if not isinstance(opt, SolverOptions):
            raise ConfigError(f"options must be SolverOptions, got {type(opt).__name__}")
        if progress is not None and not callable(progress):
            raise ConfigError(f"progress must be callable or None, got {progress!r}")
        report = progress if progress is not None else (print_lines if opt.progress else None)
        if steps is None:
            steps = [LoadStep(increments=opt.load_steps)]
        steps = list(steps)
        if not steps:
            raise ConfigError("steps must hold at least one LoadStep")
        states = self.states(steps)
        if condensed is not None:
            self._reuse(condensed, opt)
        self._check_memory(opt, steps)
        threads = usable_threads(opt.threads)
        if threads != opt.threads:
            opt = dataclasses.replace(opt, threads=threads)
        # SolverOptions.threads bounds BLAS/LAPACK too (the condensation's LU)
        with blas_threads(opt.threads):
            try:
                return self._back(self._solve(opt, steps, self._at_origin(states),
                                              raise_on_failure, report, condensed))
            except ConvergenceError as exc:
                exc.result = self._back(exc.result)
                raise

    # ---------------------------------------------------------- re-solves
    def condense(
        self, options: SolverOptions | None = None, *, steps=None,
        progress: Reporter | None = None, condense_body: CondenseBody | None = None,
    ) -> Condensation:
        """Build the frame and condense both bodies once, on a basis of load
        fields (:mod:`bemcontact.contact.reuse`), for :meth:`solve` with
        ``condensed=``: re-solves with another friction coefficient
        (a problem with the same bodies and a pair differing only in
        it), penalty, load values or history (``steps``; the same kinds of
        condition) or Newton options, without assembling or factoring.
        ``options.linear`` and ``options.threads`` are the condensation's;
        ``steps`` (default: the bodies' own conditions) the states whose
        kinds and function-valued loads it must cover.  ``condense_body``
        stands in for :func:`~bemcontact.contact.condense` (a cache)."""
        opt = options or SolverOptions()
        if not isinstance(opt, SolverOptions):
            raise ConfigError(f"options must be SolverOptions, got {type(opt).__name__}")
        steps = [LoadStep(increments=opt.load_steps)] if steps is None else list(steps)
        states = self.states(steps)
        self._check_memory(opt, steps)
        threads = usable_threads(opt.threads)
        with blas_threads(threads):
            return condense_problem(self._solved, self.pairs, self.links, self.frames,
                                    self._at_origin(states), threads,
                                    opt.linear, progress, condense_body)

    def _reuse(self, condensed: Condensation, opt: SolverOptions) -> None:
        """Check that ``condensed`` fits this problem and take its frame."""
        if not isinstance(condensed, Condensation):
            raise ConfigError(f"condensed must be a Condensation, got {type(condensed).__name__}")
        condensed.check(self._solved, self.pairs, opt.linear)
        self._frames = condensed.frames

    def _solve(self, opt, steps, states, raise_on_failure, report,
               condensed=None) -> ContactResult:
        t0 = time.perf_counter()
        with Stopwatch(report, "frame", "contact frame" if len(self.pairs) == 1
                       else f"contact frames ({len(self.pairs)} pairs)"):
            fs = self.frames
        t1 = time.perf_counter()
        if condensed is not None:
            cb = condensed.bodies_for(self._solved, states)
        else:
            modes = fs.traction_modes()
            cb = tuple(
                b.condense(fs.nodes(a), opt.threads, [st[a] for st in states], report,
                           opt.linear, modes[a])
                for a, b in enumerate(self._solved)
            )
        t2 = time.perf_counter()
        system = InterfaceSystem(
            fs, cb, [p.friction_coefficient for p in self.pairs],
            [(opt.penalty if p.penalty is None else p.penalty) * self.contact_modulus(i)
             for i, p in enumerate(self.pairs)])
        recover = Recovery(system)
        t3 = time.perf_counter()
        steps_solver = NewtonSteps(reuse=opt.newton_steps == "mixed")
        predictor = (Predictor(system, fs.points) if opt.predictor == "coarse" else None)
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
            for i in range(1, step.increments + 1):
                tau = i / step.increments
                # the state this increment starts from: the law's history
                system.start_increment(z, ell)
                ell_prev, ell = ell, (1 - tau) * prev + tau * target
                done += 1
                if report is not None:
                    report(ProgressEvent("increment", "newton",
                                         f"{name} increment {i}/{step.increments}"
                                         + closed_text(system, self.pairs, z, ell_prev),
                                         index=done, total=total))
                z, rec, msg = solve_increment(system, predictor, z, ell_prev, ell, opt, report,
                                              done, total, steps_solver)
                rec.load_factor = tau
                rec.step = s_ + 1
                rec.label = step.label
                records.append(rec)
                if msg is not None:
                    failed = f"{name}, increment {i}/{step.increments}: {msg}"
                    break
            if failed is not None:
                break
            if S > 1:
                res = recover(z, ell, list(records))
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
                                 "iteration(s)" + closed_text(system, self.pairs, z, ell),
                                 index=total, total=total, seconds=t4 - t3))
        # states are those of the last increment, judged against its starting slip
        result = recover(z, ell, records)
        result.label = steps[s_ if failed else -1].label
        result.history = history if S > 1 else [result]
        if verified(result, history if S > 1 else None) and failed is None:
            failed = f"{name}: {result.verification.message()}"
        result.converged = result.converged and failed is None
        result.linear = {b.name: dict(c.solver) for b, c in zip(self.bodies, cb)}
        result.threads = opt.threads if opt.threads is not None else core().max_threads()
        result.timings = {
            "frame": t1 - t0,
            "assembly": sum(c.timings["assembly"] for c in cb),
            "condensation": sum(c.timings["condensation"] for c in cb) + (t3 - t2),
            "newton": t4 - t3,
            "total": time.perf_counter() - t0,
        }
        if failed is not None and raise_on_failure:
            hist = ", ".join(f"{r:.3e}" for r in records[-1].residual_history)
            raise ConvergenceError(
                f"contact solve did not converge at {failed}; scaled residual history: [{hist}]",
                result,
            )
        return result



__all__ = ["ContactProblem", "LoadStep"]

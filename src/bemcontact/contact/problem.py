"""Bodies in contact: the problem (its assembly of bodies and pairs, its
frames, the memory checks before it allocates, the shift to an origin of its
own) and its solve: the bodies condensed to their flexibilities, then the
loading history increment by increment (:mod:`.loading`)."""

from __future__ import annotations

import dataclasses
import time

from .._native import core
from ..errors import ConfigError, ConvergenceError
from ..linalg.threads import blas_threads, usable_threads
from ..progress import Reporter, Stopwatch, print_lines
from .assembly import checked_assembly, contact_surfaces
from .flexibility import Body
from .frame import ContactFrame
from .frames import FrameSet
from .history import LoadStep, checked_states
from .interface import InterfaceSystem
from .loading import frame_rolling, solve_history
from .memory import MemoryEstimate, estimate, frames_peak, guard, resident_bytes
from .options import SolverOptions
from .origin import own_origin, translated_bodies, translated_result, translated_states
from .pair import ContactPair
from .results import ContactResult
from .reuse import Condensation, CondenseBody, condense_problem


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
        self.bodies, self.pairs, self.links = checked_assembly(body1, body2, pair, bodies,
                                                               pairs)
        #: the first (in a two-body problem the only) contact pair
        self.pair = self.pairs[0]
        #: the point the bodies are solved relative to (None: the global origin)
        self.origin = own_origin(self.bodies)
        self._solved = (self.bodies if self.origin is None
                        else translated_bodies(self.bodies, self.origin))
        self._frames: FrameSet | None = None

    def surfaces(self, a: int) -> list[str]:
        """The contact surfaces of body ``a`` (in the order of its pairs)."""
        return contact_surfaces(self.pairs, self.links, a)

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
        (:func:`~bemcontact.contact.memory.frames_peak`)."""
        return frames_peak([b.trace.mesh for b in self.bodies], self.pairs, self.links)

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
        """``result`` of the bodies as solved, at the bodies' own position,
        with the bodies themselves (its stresses)."""
        if result is None:
            return result
        if self.origin is not None:
            result = translated_result(result, self.origin, [b.trace.mesh for b in self.bodies])
        for r in {id(r): r for r in [result, *result.history]}.values():
            r.models = dict(zip(result.names, self.bodies))
        return result

    def _check_memory(self, opt, steps) -> None:
        """Refuse a solve whose estimated peak exceeds the machine's available
        memory by more than the estimate's uncertainty (it would be killed
        out of memory after minutes); warn when it comes close
        (:func:`~bemcontact.contact.memory.guard`).  The frame build is
        checked first, before it allocates."""
        self.check_frame_memory()
        guard(self.memory_estimate(opt, steps), "compressed operators ([solver.linear] "
              "method = \"hmatrix\") or smaller contact surfaces", warn=True)

    def check_frame_memory(self) -> None:
        """Refuse (ConfigError, one line) to build a frame whose estimated
        peak (:meth:`frame_memory`) exceeds the available memory by more
        than the estimate's uncertainty; nothing once the frame is built."""
        if self._frames is None:
            guard(MemoryEstimate({"frame": self.frame_memory()}, resident_bytes()),
                  "coarser or smaller contact surfaces")

    def contact_modulus(self, pair: int = 0) -> float:
        """E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) of the bodies of
        ``pair`` (an index into :attr:`pairs`)."""
        return 1.0 / sum(self.bodies[a].contact_compliance for a in self.links[pair])

    def states(self, steps) -> list[list[dict]]:
        """The boundary-condition state reached at each step, per body
        (:func:`~bemcontact.contact.history.checked_states`)."""
        return checked_states(self.bodies, [self.surfaces(a) for a in range(len(self.bodies))],
                              steps)

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
        for i, step in enumerate(steps):  # a rolling step's direction and friction, first
            frame_rolling(fs, step, index=i, friction=[p.friction_coefficient for p in self.pairs])
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
        t3 = time.perf_counter()
        result, failed, newton_seconds = solve_history(system, self.pairs, steps, opt, report)
        result.linear = {b.name: dict(c.solver) for b, c in zip(self.bodies, cb)}
        result.threads = opt.threads if opt.threads is not None else core().max_threads()
        result.timings = {
            "frame": t1 - t0,
            "assembly": sum(c.timings["assembly"] for c in cb),
            "condensation": sum(c.timings["condensation"] for c in cb) + (t3 - t2),
            "newton": newton_seconds,
            "total": time.perf_counter() - t0,
        }
        if failed is not None and raise_on_failure:
            hist = ", ".join(f"{r:.3e}" for r in result.steps[-1].residual_history)
            raise ConvergenceError(
                f"contact solve did not converge at {failed}; scaled residual history: [{hist}]",
                result,
            )
        return result

__all__ = ["ContactProblem", "LoadStep"]

"""Results of a contact solve: per interface node of each body, per frame
node, per region, and global.

Conventions (docs/theory.md): global x, y, z components; pressure > 0
compressive; gap > 0 open; tangential traction is the tangential part of the
traction acting *on that body*; slip is the tangential displacement of that
body relative to the other body at the same place (accumulated over the load
steps); state codes 0 open, 1 stick, 2 slip (:data:`bemcontact.contact.law.STATE_NAMES`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..bem.body import BodySolution
from ..errors import ConfigError
from .law import STATE_NAMES
from .verification import Verification, verify


def state_counts(state: np.ndarray) -> dict[str, int]:
    """Number of nodes per state name (open, stick, slip)."""
    return {name: int(np.count_nonzero(state == i)) for i, name in enumerate(STATE_NAMES)}


@dataclass
class NodalContactFields:
    """The contact fields shared by the frame's and each body's interface
    nodes (n nodes): points, normals (n, 3); pressure (n,), > 0 compressive;
    tangential_traction (n, 3); gap (n,), > 0 open; slip (n, 3); state (n,)
    int8, 0 open / 1 stick / 2 slip; weights (n,), ∫ of each node's basis."""

    points: np.ndarray
    normals: np.ndarray
    pressure: np.ndarray
    tangential_traction: np.ndarray
    gap: np.ndarray
    slip: np.ndarray
    state: np.ndarray
    weights: np.ndarray

    def counts(self) -> dict[str, int]:
        """Number of nodes per state name."""
        return state_counts(self.state)


@dataclass
class InterfaceResult(NodalContactFields):
    """Fields at the n contact-surface functional nodes of one body.

    Attributes (besides :class:`NodalContactFields`')
    ----------
    body: body name.  surface: its contact region.
    nodes: (n,) functional node indices into the body's solution arrays.
    points: (n, 3) positions (undeformed).  normals: (n, 3) outward unit normals.
    displacement: (n, 3).  traction: (n, 3) traction on this body.
    tangential_traction: (n, 3) on this body.
    gap: (n,) normal gap to the other body.
    slip: (n, 3) tangential displacement relative to the other body.
    """

    body: str = ""
    surface: str = ""
    nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    displacement: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    traction: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    #: (n,) bool: coupled to an active frame node (paired within the
    #: search distance); an unpaired node is never held by the contact
    paired: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))


@dataclass
class FrameResult(NodalContactFields):
    """Fields at the m contact-frame nodes (the law's unknowns).

    points, normals: (m, 3); the normal points from body 1 into body 2.
    pressure: (m,) normal traction on body 2, > 0 compressive.
    tangential_traction: (m, 3) tangential traction on body 2 (global).
    gap: (m,) weighted normal gap, > 0 open.
    slip: (m, 3) relative tangential displacement of body 2 w.r.t. body 1.
    state: (m,) int8.  weights: (m,) ∫ N_j dS.
    slip_increment: (m, 3) the part of ``slip`` in the last load increment
    (what ``state`` is judged against).  friction: (m,) the friction
    coefficient in effect at each node in that increment (0 while it
    closed).  augmentation: (m,) the law's r_j (stress per length).
    microslip: (m, 3) a rolling step's slip per rolled distance (global;
    zero in stick and open), and power_density (m,) its frictional power per
    area, −t·s times the rolling speed (per unit speed without one); None
    when the step does not roll.
    """

    slip_increment: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    friction: np.ndarray = field(default_factory=lambda: np.zeros(0))
    augmentation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    microslip: np.ndarray | None = None
    power_density: np.ndarray | None = None


@dataclass
class PairResult:
    """One contact pair's results.

    names: the pair's body 1 and body 2.  surfaces: their contact regions.
    normal_force: N, > 0 compressive: normal force body 1 exerts on body 2.
    tangential_force: N, magnitude of the tangential force on body 2.
    contact_force: (3,) global force body 1 exerts on body 2 (N).
    interfaces: the two :class:`InterfaceResult` (body 1's, body 2's).
    frame: :class:`FrameResult`.
    transmitted: (2, 3) the resultants the frame's tractions put on body 1
        and body 2 through their couplings (N).
    untransmitted: N, the bound on their sum: sum_j |c2_j - c1_j| |lam_j|,
        c_a,j the integral of frame node j's basis over body a's contact
        surface (0 when both surfaces cover every node's support).
    """

    names: tuple[str, str]
    surfaces: tuple[str, str]
    normal_force: float
    tangential_force: float
    contact_force: np.ndarray
    interfaces: tuple[InterfaceResult, InterfaceResult]
    frame: FrameResult
    transmitted: np.ndarray = field(default_factory=lambda: np.zeros((2, 3)))
    untransmitted: float = 0.0

    @property
    def label(self) -> str:
        """``body1:surface1/body2:surface2``, the pair's name in messages and files."""
        return "/".join(f"{n}:{s}" for n, s in zip(self.names, self.surfaces))

    def summary(self) -> dict:
        """JSON-ready forces and state counts of the pair."""
        return {
            "bodies": list(self.names),
            "surfaces": list(self.surfaces),
            "normal_force": float(self.normal_force),
            "tangential_force": float(self.tangential_force),
            "contact_force": [float(c) for c in self.contact_force],
            "states": {"frame": self.frame.counts(),
                       **{i.body: i.counts() for i in self.interfaces}},
        }


@dataclass
class StepRecord:
    """One load increment: its fraction ``load_factor`` of the way from the
    previous state to step ``step`` (1-based; ``label`` its name), Newton
    iterations and the history of the scaled residual norm max|Phi| /
    traction scale (one entry per iterate, the first for the starting
    point)."""

    load_factor: float
    iterations: int
    residual_history: list[float]
    converged: bool
    line_search_steps: list[float] = field(default_factory=list)
    step: int = 1
    label: str = ""
    #: Newton matrices factored, and GMRES iterations of the steps solved
    #: with a single-precision or reused factorization (SolverOptions.newton_steps)
    factorizations: int = 0
    krylov_iterations: int = 0
    #: Newton iterations on the coarse levels of the predictor
    #: (SolverOptions.predictor), besides ``iterations`` on the frame itself
    coarse_iterations: int = 0


@dataclass
class ContactResult:
    """Everything a contact solve produces.

    Attributes
    ----------
    converged: every load step converged.
    newton_iterations: total over the load steps.
    steps: one :class:`StepRecord` per load step.
    normal_force: N, > 0 compressive: normal force body 1 exerts on body 2.
    tangential_force: N, magnitude of the tangential (friction) force on body 2.
    contact_force: (3,) global force body 1 exerts on body 2 (N).
    bodies: the :class:`~bemcontact.bem.body.BodySolution` of every body
        (whole surfaces), in the problem's order.
    names: the body names.
    interfaces: the two :class:`InterfaceResult`.
    frame: :class:`FrameResult`.
    pairs: one :class:`PairResult` per contact pair, in the problem's order.
        The forces, ``interfaces`` and ``frame`` above are those of the
        first pair: of the only one in a two-body problem; an assembly's
        are in ``pairs``.
    timings: seconds per stage (assembly, condensation, frame, newton, total).
    control_displacements: body name -> region -> (3,) translation of each
        force-controlled region (NaN in components not force controlled).
    label: the label of the load step this result ends.
    history: the results at the end of every load step (the last is this
        one's state); a one-step solve holds just this result.
    linear: body name -> how its system was solved (``method`` "dense" or
        "hmatrix"; for compressed operators also sizes in MB, seconds, the
        H-LU residual and the sampled exact residual).
    threads: the threads the solve ran on (OpenMP and BLAS).
    verification: the :class:`~bemcontact.contact.verification.Verification`
        of the solve (the worst of each check over the load history); None
        before it ran.  :meth:`verify` computes this state's checks anew.
    rolling: a rolling step's creep force, spin moment, frictional work and
        power, adhesion and slip areas and creepages in effect
        (:func:`~bemcontact.contact.rolling.rolling_quantities`; the first
        pair's); None when the step does not roll.
    """

    converged: bool
    newton_iterations: int
    steps: list[StepRecord]
    normal_force: float
    tangential_force: float
    contact_force: np.ndarray
    bodies: tuple[BodySolution, ...]
    names: tuple[str, ...]
    interfaces: tuple[InterfaceResult, InterfaceResult]
    frame: FrameResult
    pairs: list[PairResult] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    control_displacements: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)
    label: str = ""
    history: list = field(default_factory=list)
    linear: dict = field(default_factory=dict)
    threads: int | None = None
    verification: Verification | None = None
    rolling: dict | None = None
    #: body name -> the body (what :meth:`stresses` asks for its stresses)
    models: dict = field(default_factory=dict)
    #: how :meth:`stresses` computes them (said in the stress files' summary)
    stress_model: ClassVar[str] = "Somigliana's identity on the boundary solution"

    def stresses(self, body: str, points, step: int | None = None) -> np.ndarray:
        """The stress tensor (n, 6) = (σxx, σyy, σzz, σxy, σyz, σxz), tension
        positive, at interior ``points`` (n, 3) of the body named ``body``,
        from its solution in this result (a BEM body: Somigliana's identity,
        :func:`~bemcontact.bem.interior.interior_stresses`), or at the end of
        load step ``step`` (an index into ``history``)."""
        state = self if step is None else self._step(step)
        return state._model(body, "stresses").stresses(
            state.bodies[state.names.index(body)], points)

    def surface_points(self, body: str) -> np.ndarray:
        """(N, 3) the points where :meth:`surface_stresses` gives the stresses:
        the functional nodes of the body named ``body``."""
        self._model(body, "surface_stresses")
        return self.bodies[self.names.index(body)].points

    def _step(self, step) -> ContactResult:
        states = self.history or [self]
        if (isinstance(step, bool) or not isinstance(step, (int, np.integer))
                or not -len(states) <= step < len(states)):
            raise ConfigError(f"step must index the {len(states)} load steps, got {step!r}",
                              location={"field": "step"})
        return states[step]

    def surface_stresses(self, body: str) -> np.ndarray:
        """The stress tensor (N, 6) on the surface of the body named
        ``body``, at the N functional nodes of its solution (``bodies[k].points``):
        from its tractions and the tangential derivatives of its displacement
        (:func:`~bemcontact.bem.surface_stress.surface_stresses`)."""
        return self._model(body, "surface_stresses").surface_stresses(
            self.bodies[self.names.index(body)])

    def _model(self, body: str, method: str):
        if body not in self.names:
            raise ConfigError(f"unknown body {body!r}; the bodies are {list(self.names)}",
                              location={"body": body})
        model = self.models.get(body)
        if model is None or not hasattr(model, method):
            raise ConfigError(f"body {body!r} gives no stresses (only bodies with a "
                              f"{method}() method do)", location={"body": body})
        return model

    def verify(self) -> Verification:
        """This state's checks against the contact conditions
        (:func:`~bemcontact.contact.verification.verify`)."""
        return verify(self)

    def reactions(self) -> dict[str, dict[str, np.ndarray]]:
        """Body name -> region -> resultant force (3,) the surroundings
        (supports, loads and the other body) exert on that region."""
        return {n: b.reactions() for n, b in zip(self.names, self.bodies)}

    def summary(self) -> dict:
        """JSON-ready summary (the top level of ``summary.json``)."""
        return {
            "converged": bool(self.converged),
            "newton_iterations": int(self.newton_iterations),
            "normal_force": float(self.normal_force),
            "tangential_force": float(self.tangential_force),
            "contact_force": [float(c) for c in self.contact_force],
            "load_steps": [
                {
                    "step": s.step,
                    "label": s.label,
                    "load_factor": s.load_factor,
                    "iterations": s.iterations,
                    "converged": s.converged,
                    "residual_history": [float(r) for r in s.residual_history],
                }
                for s in self.steps
            ],
            "states": {
                "frame": self.frame.counts(),
                **{f"{i.body}": i.counts() for i in self.interfaces},
            },
            **({"pairs": [p.summary() for p in self.pairs]} if len(self.pairs) > 1 else {}),
            "reactions": {
                b: {r: [float(c) for c in f] for r, f in regs.items()}
                for b, regs in self.reactions().items()
            },
            "control_displacements": _controls_json(self.control_displacements),
            **({"rolling": self.rolling} if self.rolling is not None else {}),
            "history": [
                {
                    "label": h.label,
                    "normal_force": float(h.normal_force),
                    "tangential_force": float(h.tangential_force),
                    "contact_force": [float(c) for c in h.contact_force],
                    "control_displacements": _controls_json(h.control_displacements),
                    "states": h.frame.counts(),
                    **({"pairs": [p.summary() for p in h.pairs]} if len(h.pairs) > 1 else {}),
                    **({"rolling": h.rolling} if h.rolling is not None else {}),
                }
                for h in self.history
            ],
            "timings": {k: float(v) for k, v in self.timings.items()},
            "linear": self.linear,
            "threads": self.threads,
            **({"verification": self.verification.summary()}
               if self.verification is not None else {}),
        }


def _controls_json(controls: dict[str, dict[str, np.ndarray]]) -> dict:
    return {
        b: {r: [None if np.isnan(c) else float(c) for c in u] for r, u in regs.items()}
        for b, regs in controls.items()
    }


__all__ = ["InterfaceResult", "FrameResult", "PairResult", "StepRecord", "ContactResult"]

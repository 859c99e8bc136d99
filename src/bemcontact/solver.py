"""Two-body frictional contact: the partitioned system and its generalized
Newton solve (founding paper, eq. 17 and the GNMLS of Pang 1990).

The partitioned solve: each body's BEM system is assembled, factored and
condensed once onto its contact surface (:func:`condense`), so every Newton
iteration works only with interface-sized dense matrices: the unknowns are
the frame tractions lam (3 per frame node) and the amplitudes of any rigid
modes the supports leave free.  Newton directions solve the generalized
Jacobian system with the contact state frozen; the step length alpha is
halved until Psi = 1/2 |Phi|^2 decreases by the factor (1 - 2 sigma alpha).
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg

from . import law
from .body import BodySolution, ElasticBody
from .errors import AccuracyWarning, ConfigError, ConvergenceError
from .frame import ContactFrame, _functional_basis, _geometry, _locate
from .hmatrix import CompressedSystem, HMatrixOptions, LinearSolverOptions
from .operators import assemble_system, blas_threads
from .progress import ProgressEvent, Reporter, Stopwatch, print_lines
from .results import ContactResult, FrameResult, InterfaceResult, StepRecord
from .schema import MAX_THREADS


#: Values of :attr:`ContactPair.frame_on`.
FRAME_ON = ("coarser", "body1", "body2")


@dataclass(frozen=True)
class ContactPair:
    """Which surfaces of the two bodies may touch, and how.

    Attributes
    ----------
    surface1, surface2:
        Region names of body 1 and body 2 forming the contact interface.
    friction_coefficient:
        Coulomb coefficient mu >= 0 (0: frictionless).
    frame:
        Frame discretization rule: ``"mortar"`` (default; area-consistent
        coupling, passes the patch test) or ``"collocation"`` (the paper's
        point evaluation of the frame basis at the body nodes; for comparison).
    search_distance:
        Largest distance along the normal at which points of the two
        surfaces are paired (length units).  Bodies that start apart (curved
        surfaces, an initial gap) need it at least as large as the initial
        gap anywhere the contact zone may grow to.  Default: a quarter of the
        largest contact element (enough for surfaces that start in touch).
        Pairing is by normal projection; the initial gap comes from the
        geometry.
    frame_on:
        Which surface carries the frame (its nodes, elements and local
        bases, hence the normal direction of the gap and of the slip):
        ``"coarser"`` (default; the rule of docs/frame.md, independent of
        the body order), ``"body1"`` or ``"body2"``.  Put it on the flat
        body when a curved body presses on a flat one (sphere on block):
        a frame on the curved surface tilts the normal by r/R, so the
        relative approach shows a tangential component of order a/R that
        friction resists (measured: tangential tractions of 0.19 p0 under a
        purely normal load on the hemisphere of docs/validation.md, 0 on the
        block's frame).
    """

    surface1: str
    surface2: str
    friction_coefficient: float = 0.0
    frame: str = "mortar"
    search_distance: float | None = None
    frame_on: str = "coarser"

    def __post_init__(self) -> None:
        if self.frame_on not in FRAME_ON:
            raise ConfigError(
                f"ContactPair.frame_on must be one of {', '.join(map(repr, FRAME_ON))}, "
                f"got {self.frame_on!r}"
            )
        for name in ("surface1", "surface2"):
            v = getattr(self, name)
            if not isinstance(v, str) or not v:
                raise ConfigError(f"ContactPair.{name} must be a region name, got {v!r}")
        mu = self.friction_coefficient
        if isinstance(mu, bool) or not isinstance(mu, (int, float)) or not math.isfinite(mu) or mu < 0:
            raise ConfigError(
                f"ContactPair.friction_coefficient must be a finite number >= 0, got {mu!r}"
            )
        if self.frame not in ("mortar", "collocation"):
            raise ConfigError(
                f"ContactPair.frame must be 'mortar' or 'collocation', got {self.frame!r}"
            )
        d = self.search_distance
        if d is not None and (
            isinstance(d, bool) or not isinstance(d, (int, float)) or not math.isfinite(d) or d <= 0
        ):
            raise ConfigError(
                f"ContactPair.search_distance must be a finite number > 0 or None, got {d!r}"
            )


#: The condensation's default linear solver: as LinearSolverOptions(), but
#: leaves of 96 nodes (the H-LU is 1.15x / 1.7x faster than with 48 at 3,102 /
#: 5,694 nodes, for 2-9 % more memory; docs/benchmarks.md).
CONDENSATION_LINEAR = LinearSolverOptions(hmatrix=HMatrixOptions(leaf_size=96))


@dataclass(frozen=True)
class SolverOptions:
    """Generalized Newton settings.

    Attributes
    ----------
    tolerance:
        Converged when max |Phi| <= tolerance * traction scale (Phi is the
        contact-law residual in traction units; the scale is the largest
        contact traction, or E*/h times the largest prescribed displacement
        before contact develops).
    max_iterations:
        Newton iterations per load step.
    load_steps:
        Number of equal proportional load increments (boundary data scaled by
        i / load_steps); friction is path dependent, so use several for
        non-monotonic problems.
    penalty:
        Factor c of the augmentation parameters r_n = r_t = c E*/h (E* the
        contact modulus, h the local frame element size).  The converged
        solution does not depend on it.
    line_search_sigma:
        sigma in Psi(w + a dw) <= (1 - 2 sigma a) Psi(w).
    min_step:
        Smallest line-search step before giving up.
    watchdog:
        Full Newton steps tried without a decrease of the residual before
        going back to the best point and searching along its direction (a
        watchdog non-monotone line search; 0 = monotone line search on every
        step).  Stick-to-slip transitions make the residual rise for a few
        full steps on the way to the solution; a monotone search then takes
        tiny steps (tens of iterations instead of a handful).
    threads:
        Threads for every parallel part: the OpenMP assembly and H-matrix
        work, and BLAS/LAPACK (the condensation's LU) during the solve
        (default: all cores, or ``OMP_NUM_THREADS``).
    linear:
        How each body's BEM system is stored and solved for the condensation:
        dense LAPACK LU, or compressed operators (H-matrix, H-LU); default
        ``"auto"``: dense up to ``linear.dense_max_nodes`` nodes per body
        (default :data:`CONDENSATION_LINEAR`: H-matrix leaves of 96 nodes).
    progress:
        Print the stages, load increments and Newton iterations on stderr
        (:func:`bemcontact.progress.print_lines`; ``ContactProblem.solve``
        also takes any ``progress`` callable).
    """

    tolerance: float = 1e-10
    max_iterations: int = 50
    load_steps: int = 1
    penalty: float = 1.0
    line_search_sigma: float = 1e-4
    min_step: float = 2.0**-20
    watchdog: int = 5
    threads: int | None = None
    progress: bool = False
    linear: LinearSolverOptions = CONDENSATION_LINEAR

    def __post_init__(self) -> None:
        if not isinstance(self.linear, LinearSolverOptions):
            raise ConfigError(
                f"SolverOptions.linear must be LinearSolverOptions, got {self.linear!r}"
            )
        def num(name, lo, hi):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (lo < v < hi):
                raise ConfigError(f"SolverOptions.{name} must be in ({lo}, {hi}), got {v!r}")

        num("tolerance", 0, 1)
        num("penalty", 0, math.inf)
        num("line_search_sigma", 0, 0.5)
        num("min_step", 0, 1)
        for name in ("max_iterations", "load_steps"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ConfigError(f"SolverOptions.{name} must be an integer >= 1, got {v!r}")
        v = self.watchdog
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise ConfigError(f"SolverOptions.watchdog must be an integer >= 0, got {v!r}")
        if self.threads is not None and (
            isinstance(self.threads, bool) or not isinstance(self.threads, int)
            or not 1 <= self.threads <= MAX_THREADS
        ):
            raise ConfigError(
                f"SolverOptions.threads must be None or in [1, {MAX_THREADS}], got "
                f"{self.threads!r}"
            )


# --------------------------------------------------------------------------- condensation


def _solve_compressed(cs: CompressedSystem, rhs: np.ndarray, Rf: np.ndarray, C: np.ndarray,
                      W: np.ndarray, S: int, dofs: np.ndarray, lin: LinearSolverOptions,
                      name: str):
    """X = A⁻¹ rhs on the compressed A by its H-LU, for a floating body
    bordered by the free modes Rf with the equilibrium rows C (A + Rf C is
    factored: x = y - z alpha with alpha = (C z)⁻¹ C y, the bordered system's
    solution), then one step of iterative refinement with the compressed
    product (the H-LU truncations leave a residual of ~100 eps; one step
    brings it to ~1e-11, measured).  rhs = [B W[:, :S], G[:, dofs],
    B W[:, S:]].  The exact system's residual of every column is sampled at
    ``lin.check_nodes`` nodes (rows from the element integrals) and an
    :class:`AccuracyWarning` is given above ``lin.accuracy``."""
    t0 = time.perf_counter()
    nf = Rf.shape[1]
    F = cs.factor(update=(Rf, C.T) if nf else None)
    t1 = time.perf_counter()

    z = F.solve(Rf) if nf else None
    Cz = C @ z if nf else None

    def bordered(b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(x, alpha) with (A + Rf C) y = b, x = y - z alpha, C x = 0."""
        y = F.solve(b)
        if not nf:
            return y, np.zeros((0, b.shape[1]))
        alpha = np.linalg.solve(Cz, C @ y)
        return y - z @ alpha, alpha

    X, alpha = bordered(rhs)
    r = rhs - cs.matvec(X) - Rf @ alpha
    first = float(np.linalg.norm(r) / max(np.linalg.norm(rhs), 1e-300))
    dX, dalpha = bordered(r)
    X += dX
    alpha += dalpha
    t2 = time.perf_counter()
    check = 0.0
    if lin.check_nodes > 0:
        rows, As, Bs = cs.sampled_rows(lin.check_nodes)
        b = np.column_stack([Bs @ W[:, :S], Bs[:, dofs], Bs @ W[:, S:]])
        res = As @ X + Rf[rows] @ alpha - b
        check = float(np.linalg.norm(res) / max(np.linalg.norm(b), 1e-300))
    if check > lin.accuracy:
        warnings.warn(
            f"{name}: compressed operators with eps = {cs.options.eps:g}: the exact system's "
            f"residual is {check:.2e} (sampled at {lin.check_nodes} nodes), above the requested "
            f"accuracy {lin.accuracy:g}; use a smaller HMatrixOptions.eps",
            AccuracyWarning, stacklevel=3,
        )
    info = {
        "method": "hmatrix", "compressed_mb": cs.stored_bytes / 1e6,
        "factor_mb": F.stored_bytes / 1e6, "dense_mb": cs.dense_bytes / 1e6,
        "build_s": cs.build_seconds, "factor_s": t1 - t0, "solve_s": t2 - t1,
        "lu_residual": first, "exact_residual": check, "max_rank": F.max_rank,
    }
    return X, info


@dataclass
class CondensedBody:
    """One body reduced to its contact surface (the partitioned step).  For
    contact tractions t_c (3 n_c, interleaved xyz per node), load weights
    ell (S,) over the boundary-condition states, free rigid-mode amplitudes
    alpha and platen translations U (force control),

        x = x0 ell + X t_c + Rf alpha + Y U,   u_c = x[dofs]

    where x is the BEM unknown vector (displacement at traction-given dofs,
    traction at displacement-given dofs), x0 (n, S) the response to each
    state's boundary data, Rf the rigid modes the supports leave free
    (floating bodies; alpha fixed by the body's equilibrium), Y the response
    to a unit translation of each force-controlled component (U fixed by
    ``C x = forces ell``), F = X[dofs] the interface flexibility.
    """

    body: Any
    nodes: np.ndarray
    dofs: np.ndarray
    known_u: np.ndarray
    values: np.ndarray  # (3N, S) boundary values per state
    x0: np.ndarray  # (n, S)
    X: np.ndarray
    Rf: np.ndarray
    known_modal_force: np.ndarray  # (nf, S) ∫ Rf . t_known dS per state
    controls: list
    Y: np.ndarray  # (n, nc)
    C: np.ndarray  # (nc, n) resultant rows of the controlled components
    forces: np.ndarray  # (nc, S) prescribed resultants per state
    timings: dict
    solver: dict = field(default_factory=dict)  # linear solver used, sizes and residuals

    @property
    def F(self) -> np.ndarray:
        return self.X[self.dofs]

    @property
    def u0(self) -> np.ndarray:
        return self.x0[self.dofs]

    @property
    def Rc(self) -> np.ndarray:
        return self.Rf[self.dofs]

    @property
    def Yc(self) -> np.ndarray:
        return self.Y[self.dofs]


def condense(
    body: ElasticBody, nodes: np.ndarray, threads: int | None = None, states=None,
    progress: Reporter | None = None, linear: LinearSolverOptions | None = None,
) -> CondensedBody:
    """Assemble the body's BEM system once, factor it, and solve for the
    response to unit tractions at each contact dof (``nodes``: the contact
    functional nodes, which must carry no boundary condition), to each
    boundary-condition state in ``states`` (checked condition mappings with
    the same kind per dof; default: the body's own) and to unit platen
    translations of the force-controlled components.  ``progress`` receives
    the start and end events of the ``assembly`` and ``condensation`` stages
    (:mod:`bemcontact.progress`).  ``linear`` chooses dense operators (LAPACK
    LU) or compressed ones (H-matrix, H-LU with one step of iterative
    refinement; :class:`~bemcontact.hmatrix.LinearSolverOptions`)."""
    d = body.discretization
    t0 = time.perf_counter()
    what = f"{body.name}: {d.n_points:,} nodes, {nodes.size:,} on the contact surface"
    if progress is not None:
        progress(ProgressEvent("start", "assembly", f"assembly {what}"))
    states = [body.boundary_conditions] if states is None else list(states)
    data = [body.boundary_data(c) for c in states]
    known_u = data[0][0]  # the same for every state (checked by ContactProblem.states)
    controls = body.controls(states[0])
    values = np.column_stack([v for _, v in data])
    forces = np.array([[c.force for c in body.controls(st)] for st in states]).reshape(
        len(states), len(controls)
    ).T
    dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
    if known_u[dofs].any() or np.any(values[dofs] != 0):
        raise ConfigError(
            f"{body.name}: the contact surface also has a boundary condition; remove it "
            "(the contact decides the tractions there)"
        )
    # rigid modes the supports leave free
    ku = np.flatnonzero(known_u)
    R = body.rigid_modes()
    Rn = R / np.linalg.norm(R, axis=0)
    if ku.size:
        Z = scipy.linalg.null_space(Rn[ku], rcond=1e-9)
    else:
        Z = np.eye(6)
    Rf = Rn @ Z
    nf = Rf.shape[1]
    # A in place (bordered by the free modes); B values = b0 per state, B E =
    # -Hc for the platens, the contact columns of B = G (traction-given dofs)
    S = len(states)
    m = body.material
    n = 3 * d.n_points
    lin = linear or LinearSolverOptions()
    W = np.column_stack([values, body.control_indicators(controls)])
    C = (Rf * np.repeat(d.weights, 3)[:, None]).T  # equilibrium rows of the free modes
    solver_info: dict[str, Any] = {"method": "dense"}
    if lin.use_hmatrix(d.n_points):
        cs = CompressedSystem(d, m.shear_modulus, m.poisson_ratio, known_u, W, body.quadrature,
                              lin.hmatrix, threads)
        BW = cs.BW
        Gc = cs.g_columns(dofs)
        t1 = time.perf_counter()
        if progress is not None:
            progress(ProgressEvent("end", "assembly", f"assembly {what}", seconds=t1 - t0))
            progress(ProgressEvent("start", "condensation", f"condensation {body.name}"))
        rhs = np.column_stack([BW[:, :S], Gc, BW[:, S:]])
        del Gc
        sol, solver_info = _solve_compressed(cs, rhs, Rf, C, W, S, dofs, lin, body.name)
    else:
        A, BW, Gc = assemble_system(
            d, m.shear_modulus, m.poisson_ratio, known_u, W, dofs, body.quadrature, threads,
            border=nf,
        )
        t1 = time.perf_counter()
        if progress is not None:
            progress(ProgressEvent("end", "assembly", f"assembly {what}", seconds=t1 - t0))
            progress(ProgressEvent("start", "condensation", f"condensation {body.name}"))
        rhs = np.column_stack([BW[:, :S], Gc, BW[:, S:]])
        if nf:
            A[:n, n:] = Rf
            A[n:, :n] = C
            rhs = np.vstack([rhs, np.zeros((nf, rhs.shape[1]))])
        sol = body._lu_solve(A, rhs)
        del A
    x0 = np.ascontiguousarray(sol[:n, :S])
    X = np.ascontiguousarray(sol[:n, S : S + dofs.size])
    Y = np.ascontiguousarray(sol[:n, S + dofs.size :])
    Rf[ku] = 0.0  # exactly zero on supported dofs
    # work of the given tractions in the free modes: ∫ Rf . t_known dS
    modal = np.zeros((nf, S))
    if nf:
        for s_ in range(S):
            tk = np.where(known_u, 0.0, values[:, s_]).reshape(-1, 3)
            _, _, W, tq = d.interpolate(tk)
            for i in range(nf):
                _, _, _, rq = d.interpolate(Rf[:, i].reshape(-1, 3))
                modal[i, s_] = float(np.einsum("eq,eqk,eqk->", W, rq, tq))
    t2 = time.perf_counter()
    if progress is not None:
        progress(ProgressEvent("end", "condensation", f"condensation {body.name}",
                               seconds=t2 - t1))
    return CondensedBody(
        body, nodes, dofs, known_u, values, x0, X, Rf, modal, controls, Y,
        body.control_rows(controls), forces,
        {"assembly": t1 - t0, "condensation": t2 - t1}, solver_info,
    )


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
    increments: int = 1
    label: str = ""

    def __post_init__(self) -> None:
        v = self.increments
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise ConfigError(f"LoadStep.increments must be an integer >= 1, got {v!r}")
        if not isinstance(self.label, str):
            raise ConfigError(f"LoadStep.label must be a string, got {self.label!r}")
        if not isinstance(self.conditions, Mapping) or not all(
            isinstance(k, str) and isinstance(c, Mapping) for k, c in self.conditions.items()
        ):
            raise ConfigError(
                "LoadStep.conditions must map body names to {region: condition(s)}, got "
                f"{self.conditions!r}"
            )


_KIND_NAMES = ("traction", "displacement", "force")


def _kinds(body: ElasticBody, conditions) -> np.ndarray:
    """(3N,) 0 traction (or free), 1 displacement, 2 force per dof."""
    known_u, _ = body.boundary_data(conditions)
    k = known_u.astype(np.int8)
    for c in body.controls(conditions):
        k[c.dofs] = 2
    return k


# --------------------------------------------------------------------------- problem


class ContactProblem:
    """Two elastic bodies and the contact pair between them.

    Parameters
    ----------
    body1, body2:
        :class:`~bemcontact.body.ElasticBody` objects with distinct names.
        Their contact surfaces must carry no boundary condition.
    pair:
        :class:`ContactPair`: the contact surfaces, friction, frame rule.
    """

    def __init__(self, body1: ElasticBody, body2: ElasticBody, pair: ContactPair) -> None:
        for i, b in enumerate((body1, body2)):
            if not isinstance(b, ElasticBody):
                raise ConfigError(f"body{i + 1} must be an ElasticBody, got {type(b).__name__}")
        if not isinstance(pair, ContactPair):
            raise ConfigError(f"pair must be a ContactPair, got {type(pair).__name__}")
        if body1.name == body2.name:
            raise ConfigError(f"the two bodies have the same name {body1.name!r}; name them apart")
        for b, s in ((body1, pair.surface1), (body2, pair.surface2)):
            if s not in b.mesh.region_names:
                raise ConfigError(
                    f"{b.name}: unknown contact surface {s!r}; the mesh has regions "
                    f"{list(b.mesh.region_names)}"
                )
            if s in b.boundary_conditions:
                raise ConfigError(
                    f"{b.name}: the contact surface {s!r} also has a boundary condition; remove it"
                )
        self.bodies = (body1, body2)
        self.pair = pair
        self._frame: ContactFrame | None = None

    @property
    def frame(self) -> ContactFrame:
        if self._frame is None:
            b1, b2 = self.bodies
            self._frame = ContactFrame(
                b1.discretization, self.pair.surface1, b2.discretization, self.pair.surface2,
                self.pair.frame, names=(b1.name, b2.name),
                search_distance=self.pair.search_distance,
                owner={"coarser": None, "body1": 0, "body2": 1}[self.pair.frame_on],
            )
        return self._frame

    def contact_modulus(self) -> float:
        """E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)."""
        return 1.0 / sum(
            (1 - b.material.poisson_ratio**2) / b.material.youngs_modulus for b in self.bodies
        )

    def states(self, steps) -> list[list[dict]]:
        """The boundary-condition state reached at each step, per body
        (checked: known bodies and regions, no condition on a contact
        surface, the same kind of condition per component throughout)."""
        names = [b.name for b in self.bodies]
        surfaces = (self.pair.surface1, self.pair.surface2)
        current = [dict(b.boundary_conditions) for b in self.bodies]
        base = [_kinds(b, c) for b, c in zip(self.bodies, current)]
        out = []
        for i, step in enumerate(steps):
            if not isinstance(step, LoadStep):
                raise ConfigError(f"steps[{i}] must be a LoadStep, got {type(step).__name__}")
            where = f"step {i + 1}{f' ({step.label})' if step.label else ''}: "
            current = [dict(c) for c in current]
            for name, changes in step.conditions.items():
                if name not in names:
                    raise ConfigError(f"{where}unknown body {name!r}; the bodies are {names}")
                a = names.index(name)
                body = self.bodies[a]
                checked = body.checked_conditions(changes, where=where)
                if surfaces[a] in checked:
                    raise ConfigError(
                        f"{where}{name}: region {surfaces[a]!r} is the contact surface; it "
                        "cannot carry a boundary condition"
                    )
                current[a].update(checked)
                kinds = _kinds(body, current[a])
                diff = np.flatnonzero(kinds != base[a])
                if diff.size:
                    dof = int(diff[0])
                    region = body.mesh.region_names[int(body.discretization.region[dof // 3])]
                    raise ConfigError(
                        f"{where}{name}: region {region!r} component {'xyz'[dof % 3]} changes "
                        f"from {_KIND_NAMES[base[a][dof]]} to {_KIND_NAMES[kinds[dof]]}; a step "
                        "may change values, not kinds (give the component its later kind from "
                        "the start, e.g. Force with value 0)"
                    )
            out.append(current)
        return out

    def solve(
        self,
        options: SolverOptions | None = None,
        *,
        steps=None,
        raise_on_failure: bool = True,
        progress: Reporter | None = None,
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
        :func:`~bemcontact.progress.print_lines` if ``options.progress``, else none."""
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
        # SolverOptions.threads bounds BLAS/LAPACK too (the condensation's LU)
        with blas_threads(opt.threads):
            return self._solve(opt, steps, states, raise_on_failure, report)

    def _solve(self, opt, steps, states, raise_on_failure, report) -> ContactResult:
        t0 = time.perf_counter()
        with Stopwatch(report, "frame", "contact frame"):
            frame = self.frame
        t1 = time.perf_counter()
        cb = tuple(
            condense(b, frame.nodes(a), opt.threads, [st[a] for st in states], report, opt.linear)
            for a, b in enumerate(self.bodies)
        )
        t2 = time.perf_counter()
        system = _InterfaceSystem(frame, cb, self.pair.friction_coefficient, opt.penalty * self.contact_modulus())
        t3 = time.perf_counter()
        records: list[StepRecord] = []
        history: list[ContactResult] = []
        z = system.zero()
        k_prev = system.k_initial_t()
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
                ell = (1 - tau) * prev + tau * target
                k_start = k_prev
                done += 1
                if report is not None:
                    report(ProgressEvent("increment", "newton",
                                         f"{name} increment {i}/{step.increments}",
                                         index=done, total=total))
                z, rec, msg = system.newton(z, ell, k_prev, opt, report, done, total)
                rec.load_factor = tau
                rec.step = s_ + 1
                rec.label = step.label
                records.append(rec)
                if msg is not None:
                    failed = f"{name}, increment {i}/{step.increments}: {msg}"
                    break
                k_prev = system.k(z, ell)[:, :2].copy()
            if failed is not None:
                break
            if S > 1:
                res = system.result(z, ell, k_start, list(records), self.bodies)
                res.label = step.label
                history.append(res)
        t4 = time.perf_counter()
        if report is not None and failed is None:
            its = sum(r.iterations for r in records)
            report(ProgressEvent("end", "newton", f"{total} load increment(s), {its} Newton "
                                 "iteration(s)", index=total, total=total, seconds=t4 - t3))
        # states are those of the last increment, judged against its starting slip
        result = system.result(z, ell, k_start, records, self.bodies)
        result.label = steps[len(history) if failed else -1].label
        result.history = history if S > 1 else [result]
        result.linear = {b.name: dict(c.solver) for b, c in zip(self.bodies, cb)}
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


def _balance(force, target: float, step: float) -> float | None:
    """du with force(du) = target (to bisection accuracy, on the side that
    reaches it) for a force(du) that is zero near du = 0 and grows
    monotonically in magnitude in one direction (a penalty resultant):
    doubling steps in each direction bracket it, then 100 bisections.
    None when neither direction reaches ``target``."""
    sign_t = np.sign(target)
    for direction in (1.0, -1.0):
        lo, h = 0.0, step
        for _ in range(80):
            hi = direction * h
            f = force(hi)
            if f != 0.0 and (f - target) * sign_t >= 0:
                for _ in range(100):
                    mid = 0.5 * (lo + hi)
                    if (force(mid) - target) * sign_t >= 0:
                        hi = mid
                    else:
                        lo = mid
                return hi
            lo, h = hi, 2.0 * h
    return None


class _InterfaceSystem:
    """The nonsmooth interface system of eq. 17 after condensing both bodies:
    unknowns z = (lam (m active frame nodes x 3, local), alpha_1, alpha_2,
    U_1, U_2) with alpha the free rigid-mode amplitudes and U the platen
    translations of force-controlled components.  Loads enter through the
    weights ell (S,) over the boundary-condition states."""

    def __init__(self, frame: ContactFrame, cb, mu: float, r_scale: float) -> None:
        self.frame = frame
        self.cb = cb
        self.mu = float(mu)
        act = np.flatnonzero(frame.active)
        self.act = act
        m = act.size
        self.m = m
        Q = frame.Q[act]  # (m, 3, 3)
        a = frame.weights[act]
        self.a = a
        self.area = float(a.sum())
        self.r = r_scale / frame.size[act]  # r_n = r_t = c E*/h_j
        signs = (-1.0, 1.0)
        self.DQ, self.T, self.W = [], [], []
        K = np.zeros((3 * m, 3 * m))
        k0X = np.zeros(3 * m)
        k0u = np.zeros((3 * m, cb[0].x0.shape[1]))
        # extra unknowns: per body, alpha then U; L[b] their columns in k
        self.nf = [c.Rf.shape[1] for c in cb]
        self.nc = [c.Y.shape[1] for c in cb]
        self.L = []
        self.E = []
        self.CT = []  # (nc, 3m): resultants of the controlled components per lam
        self.CY = []  # (nc, nc): ... per platen translation
        for i, c in enumerate(cb):
            # tractions on the whole contact surface (M^-1 D is not local):
            # exact balance of the two bodies' interface forces
            D = frame.D[i][:, act]  # (n, m)
            n = D.shape[0]
            MiD = scipy.linalg.cho_solve(scipy.linalg.cho_factor(frame.M[i]), D)
            # block (p, j) = coefficient * Q_j  ->  (3n, 3m)
            DQ = signs[i] * np.einsum("pj,jcl->pcjl", D, Q).reshape(3 * n, 3 * m)
            T = signs[i] * np.einsum("pj,jcl->pcjl", MiD, Q).reshape(3 * n, 3 * m)
            Wm = signs[i] * np.einsum("pj,jcl->jlpc", D / a[None, :], Q).reshape(3 * m, 3 * n)
            self.DQ.append(DQ)
            self.T.append(T)
            self.W.append(Wm)
            K += Wm @ (c.F @ T)
            if frame.rule == "mortar":
                # positions: exact for any overlap because (*) holds
                X = c.body.discretization.points[c.nodes].ravel()
            else:
                # point evaluation violates (*): take the initial gap from each
                # node's offset to the frame surface (the paper's g0), so the
                # position of the origin does not enter
                X = frame.offsets(i).ravel()
            k0X += Wm @ X
            k0u += Wm @ c.u0
            self.L.append(Wm @ c.Rc)
            self.L.append(Wm @ c.Yc)
            # equilibrium in the free rigid modes, scaled to traction units
            self.E.append(c.Rc.T @ DQ)
            self.CT.append((c.C @ c.X) @ T)  # (C X) first: C has a row per control
            # a platen translation that strains nothing (the body is held only
            # by the contact in that direction) has no resultant: make that
            # exact, so an open contact shows as a singular Newton matrix
            CY = c.C @ c.Y
            E = c.body.material.youngs_modulus
            for k_, ctl in enumerate(c.controls):
                size = math.sqrt(c.C[k_].sum())
                if abs(CY[k_, k_]) <= 1e-8 * E * size:
                    CY[k_, :] = 0.0
                    CY[:, k_] = 0.0
            self.CY.append(CY)
        self.K = K
        self.k0X = k0X
        self.k0u = k0u
        self._located: dict[int, tuple] = {}
        # dk/dz (3m, nz) and the linear rows besides the law (ne, nz)
        self._dk = np.hstack([K, *[L for L in self.L if L.shape[1]]])
        m3, nz = 3 * m, self._dk.shape[1]
        eq = []
        col = m3
        for i in range(len(cb)):
            nf, nc = self.nf[i], self.nc[i]
            if nf:
                r = np.zeros((nf, nz))
                r[:, :m3] = self.E[i] / self.area
                eq.append(r)
            if nc:
                r = np.zeros((nc, nz))
                r[:, :m3] = self.CT[i] / self.area
                r[:, col + nf : col + nf + nc] = self.CY[i] / self.area
                eq.append(r)
            col += nf + nc
        self._eq = np.vstack(eq) if eq else np.zeros((0, nz))

    # -- vectors
    def zero(self) -> np.ndarray:
        return np.zeros(3 * self.m + sum(self.nf) + sum(self.nc))

    def split(self, z):
        """lam, [alpha_1, U_1, alpha_2, U_2] (the order of self.L)."""
        m3 = 3 * self.m
        parts, o = [], m3
        for nf, nc in zip(self.nf, self.nc):
            parts += [z[o : o + nf], z[o + nf : o + nf + nc]]
            o += nf + nc
        return z[:m3], parts

    def k(self, z: np.ndarray, ell: np.ndarray) -> np.ndarray:
        lam, parts = self.split(z)
        kk = self.k0X + self.k0u @ ell + self.K @ lam
        for L, v in zip(self.L, parts):
            if v.size:
                kk = kk + L @ v
        return kk.reshape(-1, 3)

    def k_initial_t(self) -> np.ndarray:
        return self.k0X.reshape(-1, 3)[:, :2].copy()

    def _rows(self, lam, parts, ell):
        """Linear equations besides the law: free-mode equilibrium and the
        prescribed resultants of controlled components (traction units)."""
        out = []
        for i, c in enumerate(self.cb):
            if self.nf[i]:
                out.append((self.E[i] @ lam + c.known_modal_force @ ell) / self.area)
            if self.nc[i]:
                U = parts[2 * i + 1]
                out.append(
                    (c.C @ (c.x0 @ ell) + self.CT[i] @ lam + self.CY[i] @ U - c.forces @ ell)
                    / self.area
                )
        return out

    def residual(self, z, ell, k_prev):
        lam, parts = self.split(z)
        kk = self.k(z, ell)
        phi = law.residual(lam.reshape(-1, 3), kk, k_prev, self.mu, self.r, self.r).ravel()
        eq = self._rows(lam, parts, ell)
        return np.concatenate([phi, *eq]) if eq else phi

    def jacobian(self, z, ell, k_prev):
        """The rows of the generalized Jacobian that are not those of open
        nodes (an open node's row is the identity: lam_j = 0), with every
        column: returns ``(J[rows], rows, state)``."""
        lam, _ = self.split(z)
        kk = self.k(z, ell)
        Jl, Jk, state = law.jacobian(lam.reshape(-1, 3), kk, k_prev, self.mu, self.r, self.r)
        m3, nz = 3 * self.m, z.size
        closed = np.flatnonzero(state != law.OPEN)
        cdofs = (3 * closed[:, None] + np.arange(3)).ravel()
        rows = np.concatenate([cdofs, np.arange(m3, nz)])
        J = np.empty((rows.size, nz))
        mc = closed.size
        # law rows of closed nodes: Jl_j on the diagonal block + Jk_j (dk_j/dz)
        J[: 3 * mc] = np.einsum(
            "jab,jbn->jan", Jk[closed], self._dk[cdofs].reshape(mc, 3, nz)
        ).reshape(3 * mc, nz)
        diag = J[: 3 * mc].reshape(mc, 3, nz)
        cols = 3 * closed[:, None, None] + np.arange(3)[None, None, :]
        np.add.at(diag, (np.arange(mc)[:, None, None], np.arange(3)[None, :, None], cols), Jl[closed])
        J[3 * mc :] = self._eq
        return J, rows, state

    def first_touch(self, z, ell, k_prev) -> np.ndarray:
        """Predictor for a force-controlled body held only by the contact
        (a sphere pushed by a force onto a block, touching at a point): with
        every node open at ``z`` the Newton matrix is singular in the
        platen's translation.  Each such translation (its resultant row has
        no stiffness of its own) is moved, traction multipliers held, until
        the augmented-Lagrangian trial pressures max(0, -r k_n) of the nodes
        it closes balance the prescribed force: a penalty contact that
        starts Newton with a patch of about the right size.  ``z`` is
        returned unchanged when a node is already closed, or when no such
        translation moves the normal gaps (it is left to the error of the
        singular matrix)."""
        lam, _ = self.split(z)
        state = law.contact_state(lam.reshape(-1, 3), self.k(z, ell), k_prev, self.mu, self.r, self.r)
        if (state != law.OPEN).any():
            return z
        z = z.copy()
        kn0 = self.k(z, ell)[:, 2]
        col = 3 * self.m
        for i, c in enumerate(self.cb):
            nf, nc = self.nf[i], self.nc[i]
            need = c.forces @ ell - c.C @ (c.x0 @ ell) - self.CT[i] @ lam if nc else ()
            for k_ in range(nc):
                s = self.L[2 * i + 1][:, k_].reshape(-1, 3)[:, 2]  # dk_n / dU
                if np.any(self.CY[i][k_] != 0.0) or not np.any(s != 0.0) or need[k_] == 0.0:
                    # restrained by the body's own supports, or tangential (the
                    # friction of the closed nodes holds it), or nothing to carry
                    continue
                ct = self.CT[i][k_].reshape(-1, 3)[:, 2]  # resultant per pressure
                # k is affine in z: only U_k moves
                u = _balance(
                    lambda du, s=s, ct=ct: float(ct @ np.maximum(0.0, -self.r * (kn0 + s * du))),
                    float(need[k_]), max(float(np.abs(kn0).max()), 1e-12) / float(np.abs(s).max()),
                )
                if u is not None:
                    z[col + nf + k_] += u
                    kn0 = kn0 + s * u
            col += nf + nc
        return z

    def newton(self, z, ell, k_prev, opt: SolverOptions, report: Reporter | None = None,
               index: int = 0, total: int = 0):
        hist: list[float] = []
        steps: list[float] = []
        z = self.first_touch(z, ell, k_prev)
        phi = self.residual(z, ell, k_prev)
        scale = max(np.abs(phi).max(initial=0.0), np.abs(z[: 3 * self.m]).max(initial=0.0), 1e-300)
        it = 0
        msg = None
        best = None  # watchdog reference: (z, merit, Newton direction)
        trial = 0
        while True:
            lam_scale = max(scale, np.abs(z[: 3 * self.m]).max(initial=0.0))
            err = np.abs(phi).max(initial=0.0) / lam_scale
            hist.append(float(err))
            if report is not None:
                report(ProgressEvent("iteration", "newton", "", index=index, total=total,
                                     iteration=it, residual=float(err)))
            if err <= opt.tolerance:
                break
            if it >= opt.max_iterations:
                msg = f"no convergence in {opt.max_iterations} iterations"
                break
            J, keep, state = self.jacobian(z, ell, k_prev)
            # rows of open nodes read lam = 0 (identity, no coupling): eliminate
            # them and factor only the closed nodes and the extra unknowns
            is_open = np.ones(z.size, dtype=bool)
            is_open[keep] = False
            dz = np.zeros_like(z)
            dz[is_open] = -phi[is_open]
            if keep.size:
                Jkk = J[:, keep]
                rhs = -phi[keep] - J @ dz  # dz holds only the open rows yet
                try:
                    with warnings.catch_warnings():
                        # exact singularity is diagnosed below, with a better message
                        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                        lu = scipy.linalg.lu_factor(Jkk, check_finite=True)
                except (ValueError, np.linalg.LinAlgError) as exc:
                    msg = f"the Newton matrix is not usable ({exc})"
                    break
                d = np.abs(np.diag(lu[0]))
                if d.min() <= 1e-13 * d.max():
                    msg = (
                        "the Newton matrix is singular: a body is free to move (rigid motion "
                        "not restrained by supports or by contact, e.g. a force that pulls a "
                        "body held only by the contact away from it) or the contact surfaces "
                        "do not face each other"
                    )
                    break
                dz[keep] = scipy.linalg.lu_solve(lu, rhs)
            psi = 0.5 * float(phi @ phi)
            if best is None or psi <= (1 - 2 * opt.line_search_sigma) * best[1]:
                # sufficient decrease since the reference point: it becomes the new one
                best, trial = (z, psi, dz), 0
            if trial < opt.watchdog:
                # watchdog: a full step, judged by the next iterations
                zt, alpha = z + dz, 1.0
                pt = self.residual(zt, ell, k_prev)
                trial += 1
            else:
                # no decrease within the watchdog's steps: back to the reference
                # point, monotone line search along its Newton direction
                z0, psi0, d0 = best
                alpha = 1.0 if opt.watchdog == 0 else 0.5
                while True:
                    zt = z0 + alpha * d0
                    pt = self.residual(zt, ell, k_prev)
                    if 0.5 * float(pt @ pt) <= (1 - 2 * opt.line_search_sigma * alpha) * psi0:
                        break
                    alpha *= 0.5
                    if alpha < opt.min_step:
                        break
                if alpha < opt.min_step:
                    msg = "line search failed (no decrease of the residual along the Newton direction)"
                    break
                best, trial = None, 0
            z, phi = zt, pt
            steps.append(alpha)
            it += 1
        rec = StepRecord(1.0, it, hist, msg is None, steps)
        return z, rec, msg

    # -- results
    def result(self, z, ell, k_prev, steps, bodies) -> ContactResult:
        fr = self.frame
        lam, parts = self.split(z)
        kk = self.k(z, ell)
        lam3 = lam.reshape(-1, 3)
        state_act = law.contact_state(lam3, kk, k_prev, self.mu, self.r, self.r)
        act = self.act
        Q = fr.Q[act]
        mfull = fr.n_frame
        # frame results (inactive nodes: open, zero traction, NaN gap)
        def full(v, fill=0.0):
            out = np.full((mfull,) + v.shape[1:], fill, dtype=v.dtype)
            out[act] = v
            return out

        t_glob = np.einsum("jcl,jl->jc", Q[:, :, :2], lam3[:, :2])
        k_init = self.k0X.reshape(-1, 3)
        slip = np.einsum("jcl,jl->jc", Q[:, :, :2], kk[:, :2] - k_init[:, :2])
        frame_res = FrameResult(
            points=fr.points,
            normals=fr.Q[:, :, 2],
            pressure=full(lam3[:, 2]),
            tangential_traction=full(t_glob),
            gap=full(kk[:, 2], np.nan),
            slip=full(slip),
            state=full(state_act.astype(np.int8), np.int8(0)),
            weights=fr.weights,
        )
        F = np.einsum("j,jcl,jl->c", self.a, Q, lam3)  # force on body 2
        nbar = np.einsum("j,jc->c", self.a, Q[:, :, 2])
        nbar /= np.linalg.norm(nbar)
        Fn = float(F @ nbar)
        Ft = float(np.linalg.norm(F - Fn * nbar))
        sols, ifaces = [], []
        controlled: dict[str, dict[str, np.ndarray]] = {}
        state_full = frame_res.state
        for i, (c, b) in enumerate(zip(self.cb, bodies)):
            d = b.discretization
            tc = self.T[i] @ lam
            al, U = parts[2 * i], parts[2 * i + 1]
            x = c.x0 @ ell + c.X @ tc
            if al.size:
                x = x + c.Rf @ al
            if U.size:
                x = x + c.Y @ U
            vals = c.values @ ell
            for ctl, Uk in zip(c.controls, U):
                vals[ctl.dofs] = Uk
                controlled.setdefault(b.name, {}).setdefault(
                    ctl.region, np.full(3, np.nan)
                )[ctl.component] = Uk
            u = np.where(c.known_u, vals, x)
            t = np.where(c.known_u, x, vals)
            t[c.dofs] = tc
            sols.append(
                BodySolution(
                    points=d.points, normals=d.normals, displacement=u.reshape(-1, 3),
                    traction=t.reshape(-1, 3), weights=d.weights, region=d.region,
                    region_names=b.mesh.region_names, discretization=d,
                    timings=dict(c.timings),
                )
            )
        for i, (c, b) in enumerate(zip(self.cb, bodies)):
            ifaces.append(self._interface(i, c, b, sols[i], sols[1 - i], state_full))
        return ContactResult(
            converged=all(s.converged for s in steps) and len(steps) > 0,
            newton_iterations=sum(s.iterations for s in steps),
            steps=steps,
            normal_force=Fn,
            tangential_force=Ft,
            contact_force=F,
            bodies=(sols[0], sols[1]),
            names=(bodies[0].name, bodies[1].name),
            interfaces=(ifaces[0], ifaces[1]),
            frame=frame_res,
            control_displacements=controlled,
        )

    def _interface(self, i, c, b, sol, other_sol, frame_state) -> InterfaceResult:
        fr = self.frame
        d = b.discretization
        nodes = c.nodes
        X = d.points[nodes]
        n = d.normals[nodes]
        u = sol.displacement[nodes]
        t = sol.traction[nodes]
        tn = np.einsum("pc,pc->p", t, n)
        # pointwise gap and slip against the other body's surface
        other = self.cb[1 - i]
        od = other.body.discretization
        oel = fr.surface_elements(1 - i)
        if i not in self._located:
            # where each node sits on the other surface: geometry only, once
            el, xi, inside = _locate(od, oel, X, fr.search_distance)
            xo, _, _ = _geometry(od, el, xi)
            self._located[i] = (el, inside, xo, _functional_basis(od, el, xi))
        el, inside, xo, phi = self._located[i]
        k = od.mesh.elements.shape[1]
        uo = np.einsum("pk,pkc->pc", phi, other_sol.displacement[od.fconn[el, :k]])
        rel = (xo + uo) - (X + u)
        gap = np.where(inside, np.einsum("pc,pc->p", rel, n), np.nan)
        du = u - uo
        slip = du - np.einsum("pc,pc->p", du, n)[:, None] * n
        slip[~inside] = np.nan
        # state: that of the frame node most strongly coupled to the node
        D = fr.D[i]
        strongest = np.argmax(np.abs(D), axis=1)
        coupled = np.abs(D).max(axis=1) > 0
        # nodes off the other body's surface are open whatever their coupling
        state = np.where(coupled & inside, frame_state[strongest], 0).astype(np.int8)
        return InterfaceResult(
            body=b.name, surface=b.mesh.region_names[int(d.region[nodes[0]])], nodes=nodes,
            points=X, normals=n, displacement=u, traction=t, pressure=-tn,
            tangential_traction=t - tn[:, None] * n, gap=gap, slip=slip, state=state,
            weights=d.weights[nodes],
        )


__all__ = [
    "ContactPair",
    "LoadStep",
    "SolverOptions",
    "ContactProblem",
    "CondensedBody",
    "condense",
]

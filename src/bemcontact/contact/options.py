"""Settings of the contact solve (generalized Newton, load steps, threads,
the condensation's linear solver)."""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ConfigError
from ..linalg.options import HMatrixOptions, LinearSolverOptions
from ..settings import MAX_THREADS, Key, check_settings, setting


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
        contact modulus, h the local frame element size), in [0.01, 100].  The
        converged solution does not depend on it, within that range: the
        states are judged on lam - r k, so a huge r lets round-off in k
        decide them (c = 1e16 on the two cubes: 8 of 36 stick nodes read
        open or slip), c = 1e6 made the line search fail on a
        Cattaneo–Mindlin increment, and iterations grow away from 1 (sphere
        on block: 11 at c = 1, 16-20 at c = 1e-3 and 1e3).
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
    newton_steps:
        How each Newton step's linear system (the closed nodes' block of the
        generalized Jacobian) is solved: ``"lu"`` factors it in every
        iteration in double precision; ``"mixed"`` (default) factors blocks
        of at least 3,000 unknowns in single precision and solves them by
        GMRES to 1e-10 with that LU as preconditioner (1-2 iterations; the
        same iterates, forces to 1e-15 on Cattaneo–Mindlin, 15 % less Newton
        time at a/h = 25; :class:`~bemcontact.contact.newton.NewtonSteps`).
    predictor:
        Where each load increment's Newton iteration starts: ``"coarse"``
        (default) from its solution on the frame aggregated into clusters of
        about 4 nodes, recursively (:mod:`~bemcontact.contact.predictor`),
        which brings the fronts to within a ring or two of their place;
        ``"none"``: from the previous increment's solution.  The solution is
        the same; frames of at most 150 active nodes have no coarse level.
    closing:
        A node that closes during a load increment: ``"frictionless"``
        (default) in that increment, its stick reference where it ends the
        increment (it carries no shear until the next one); or
        ``"first_touch"``: friction from where it first touches, estimated on
        the path with the increment's starting tractions held, the increment
        solved again (about twice the Newton iterations).  Under a growing
        load with dissimilar materials (Spence's problem) ``first_touch``
        gives the ring closing last its shear (radial traction error 2.2 %
        against 11.6 %); between identical curved bodies it adds spurious
        shear at that ring (two spheres, weighted gap: 0.021 against 0.008
        p0), since the estimate of the first touch is only first order.
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

    tolerance: float = setting(Key(
        "tolerance", "number", "converged when max |Φ| <= tolerance × traction scale",
        default=1e-10, lo=0, lo_open=True, hi=1, hi_open=True))
    max_iterations: int = setting(Key(
        "max_iterations", "integer", "Newton iterations per load increment", default=50, lo=1))
    load_steps: int = setting(Key(
        "load_steps", "integer", "equal proportional load increments when there are no "
        "`[[step]]` sections (friction is path dependent)", default=1, lo=1))
    penalty: float = setting(Key(
        "penalty", "number", "factor c of the augmentation parameters r = c E*/h; does not "
        "change the converged solution within its range (beyond it round-off decides the "
        "contact states, or the line search fails)", default=1.0, lo=1e-2, hi=1e2))
    line_search_sigma: float = setting(Key(
        "line_search_sigma", "number", "sufficient-decrease constant of the line search",
        default=1e-4, lo=0, lo_open=True, hi=0.5, hi_open=True))
    min_step: float = setting(Key(
        "min_step", "number", "smallest line-search step before giving up",
        default=2.0**-20, default_text="`2**-20`", lo=0, lo_open=True, hi=1, hi_open=True))
    watchdog: int = setting(Key(
        "watchdog", "integer", "full Newton steps allowed without a decrease of the residual "
        "before returning to the best point (0: monotone line search)", default=5, lo=0))
    newton_steps: str = setting(Key(
        "newton_steps", "string", "`lu`: factor the closed nodes' Newton matrix in double "
        "precision; `mixed`: large ones (>= 3,000 unknowns) in single precision, as the "
        "preconditioner of GMRES to 1e-10 (the same iterates)", default="mixed",
        choices=("lu", "mixed")))
    predictor: str = setting(Key(
        "predictor", "string", "`coarse`: start each load increment from its solution on the "
        "frame aggregated into clusters of about 4 nodes (recursively; the same solution in "
        "fewer Newton iterations on large frames); `none`: from the previous increment's",
        default="coarse", choices=("coarse", "none")))
    closing: str = setting(Key(
        "closing", "string", "a node closing during an increment: `frictionless` in it, or "
        "with friction from its estimated `first_touch` (the increment solved again)",
        default="frictionless", choices=("frictionless", "first_touch")))
    threads: int | None = setting(Key(
        "threads", "integer", "threads of every parallel part: assembly and compression "
        "(OpenMP) and the LU (BLAS/LAPACK); the command line's `--threads` overrides it",
        default=None, lo=1, hi=MAX_THREADS, default_text="all cores, or OMP_NUM_THREADS"))
    progress: bool = setting(Key(
        "progress", "boolean", "print the stages, increments and iterations on stderr",
        default=False))
    linear: LinearSolverOptions = CONDENSATION_LINEAR

    def __post_init__(self) -> None:
        if not isinstance(self.linear, LinearSolverOptions):
            raise ConfigError(
                f"SolverOptions.linear must be LinearSolverOptions, got {self.linear!r}"
            )
        check_settings(self)


__all__ = ["SolverOptions", "CONDENSATION_LINEAR"]

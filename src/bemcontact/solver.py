"""Two-body frictional contact: the partitioned system and its generalized
Newton solve (founding paper, eq. 17 and the GNMLS of Pang 1990).

(implementation in progress)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ConfigError


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
    """

    surface1: str
    surface2: str
    friction_coefficient: float = 0.0
    frame: str = "mortar"

    def __post_init__(self) -> None:
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
    threads:
        OpenMP threads for assembly (default: all).
    progress:
        Print one line per Newton iteration.
    """

    tolerance: float = 1e-10
    max_iterations: int = 50
    load_steps: int = 1
    penalty: float = 1.0
    line_search_sigma: float = 1e-4
    min_step: float = 2.0**-20
    threads: int | None = None
    progress: bool = False

    def __post_init__(self) -> None:
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
        if self.threads is not None and (
            isinstance(self.threads, bool) or not isinstance(self.threads, int) or self.threads < 1
        ):
            raise ConfigError(f"SolverOptions.threads must be None or >= 1, got {self.threads!r}")

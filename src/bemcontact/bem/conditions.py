"""Boundary conditions of an elastic body, per region and global component.

A component with no prescribed value is traction free.  Displacements are in
length units, tractions in stress units; traction is the force per area the
*surroundings exert on the body*, t = sigma n with n the outward normal, so a
pressure p (> 0 compressive) is t = -p n.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Union

import numpy as np

from ..errors import ConfigError

ComponentValue = Union[float, None]
FieldValue = Union[Sequence[ComponentValue], Callable[[np.ndarray], Any]]


def _check_value(kind: str, value: Any, allow_callable: bool = True) -> Any:
    if callable(value):
        if not allow_callable:
            raise ConfigError(f"{kind}: value must be 3 components (numbers or None), got a callable")
        return value
    try:
        seq = list(value)
    except TypeError:
        raise ConfigError(
            f"{kind}: value must be 3 components (numbers or None) or a callable of the "
            f"points, got {value!r}"
        ) from None
    if len(seq) != 3:
        raise ConfigError(f"{kind}: value must have 3 components (x, y, z), got {value!r}")
    out = []
    for c in seq:
        if c is None:
            out.append(None)
            continue
        if isinstance(c, bool) or not isinstance(c, (int, float, np.floating, np.integer)):
            raise ConfigError(f"{kind}: component {c!r} is not a number or None")
        if not np.isfinite(c):
            raise ConfigError(f"{kind}: component {c!r} is not finite")
        out.append(float(c))
    return tuple(out)


@dataclass(frozen=True)
class Displacement:
    """Prescribed displacement components (global x, y, z); ``None`` leaves a
    component free (traction free unless a :class:`Traction` sets it).  The
    value may be a callable ``f(points (n, 3)) -> (n, 3)`` (NaN entries mean
    free)."""

    value: FieldValue

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _check_value("Displacement", self.value))


@dataclass(frozen=True)
class Traction:
    """Prescribed traction components (global x, y, z; force per area acting on
    the body); ``None`` leaves a component free.  May be a callable
    ``f(points, normals) -> (n, 3)``."""

    value: FieldValue

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _check_value("Traction", self.value))


@dataclass(frozen=True)
class Pressure:
    """Normal pressure p (> 0 pushes on the body): t = -p n on all components."""

    pressure: float

    def __post_init__(self) -> None:
        p = self.pressure
        if isinstance(p, bool) or not isinstance(p, (int, float, np.floating)) or not np.isfinite(p):
            raise ConfigError(f"Pressure: pressure must be a finite number, got {p!r}")


@dataclass(frozen=True)
class Force:
    """Force control: the prescribed resultant (global x, y, z components,
    force units) of the tractions on a region that moves as a *rigid
    translation* in those components (a rigid platen pushed with a given
    force).  The platen's translation is an unknown of the solve, reported as
    the region's controlled displacement.  ``None`` leaves a component to
    other conditions."""

    value: Sequence[ComponentValue]

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _check_value("Force", self.value, allow_callable=False))


def Fixed() -> Displacement:
    """All displacement components zero (clamped)."""
    return Displacement((0.0, 0.0, 0.0))


BoundaryCondition = Union[Displacement, Traction, Pressure, Force]
#: The boundary-condition classes (what ``isinstance`` checks accept).
CONDITION_KINDS = (Displacement, Traction, Pressure, Force)


@dataclass(frozen=True)
class Control:
    """One force-controlled component of a region: its dofs (indices into the
    3N unknowns), the prescribed resultant ``force`` and the labels."""

    region: str
    component: int
    dofs: np.ndarray
    force: float



__all__ = ["CONDITION_KINDS", "Displacement", "Traction", "Pressure", "Force", "Fixed", "Control",
           "BoundaryCondition"]

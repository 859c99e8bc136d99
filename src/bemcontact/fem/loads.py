"""Body forces on a finite-element body: its weight in a uniform gravity
field and the centrifugal load of a steady rotation (:class:`BodyForce`),
per unit volume the density times an acceleration field, and their
consistent nodal forces (:func:`nodal_body_forces`).

Conventions.  ``gravity`` is the acceleration of gravity g (length / time²,
e.g. [0, 0, -9810] mm/s² pointing down); ``angular_velocity`` ω (rad /
time) about the axis through ``center`` along ω.  The body is at rest in
the frame that rotates with it, where the centrifugal force per unit volume
is ρ (|ω|² r − (ω · r) ω), r = x − center: ρ ω² times the distance from
the axis, pointing away from it.  Densities are mass per volume in units
consistent with the rest (mm, N, MPa, s: tonnes per mm³, steel 7.85e-9).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..settings import Key, setting


def _vector(owner: str, name: str, value) -> tuple[float, float, float]:
    a = np.asarray(value, dtype=float) if not isinstance(value, (str, bytes)) else None
    if a is None or a.shape != (3,) or not np.isfinite(a).all():
        raise ConfigError(f"{owner}.{name} must be 3 finite numbers, got {value!r}",
                          location={"field": name})
    return tuple(float(v) for v in a)


@dataclass(frozen=True)
class BodyForce:
    """A body force per unit volume ρ a(x): uniform gravity and a steady
    rotation (module docstring's conventions).

    Parameters
    ----------
    gravity:
        Acceleration of gravity g (length / time²).
    angular_velocity:
        Angular velocity ω (rad / time) of a steady rotation about the axis
        through ``center`` along ω.
    center:
        A point of the rotation's axis (length).
    """

    gravity: tuple = setting(Key(
        "gravity", "vector", "acceleration of gravity g (length / time²), e.g. [0, 0, -9810] in "
        "mm/s²", default=(0.0, 0.0, 0.0)))
    angular_velocity: tuple = setting(Key(
        "angular_velocity", "vector", "angular velocity ω (rad / time) of a steady rotation about "
        "the axis through `center` along ω: the centrifugal load ρ ω² r away from the axis",
        default=(0.0, 0.0, 0.0)))
    center: tuple = setting(Key(
        "center", "vector", "a point of the rotation's axis (length)", default=(0.0, 0.0, 0.0)))

    def __post_init__(self) -> None:
        for name in ("gravity", "angular_velocity", "center"):
            object.__setattr__(self, name, _vector("BodyForce", name, getattr(self, name)))

    @property
    def is_zero(self) -> bool:
        return not (any(self.gravity) or any(self.angular_velocity))

    def acceleration(self, x: np.ndarray) -> np.ndarray:
        """The acceleration field a (..., 3) at points ``x`` (..., 3): the
        force per unit volume is ρ a."""
        g = np.asarray(self.gravity)
        w = np.asarray(self.angular_velocity)
        r = np.asarray(x, dtype=float) - np.asarray(self.center)
        return g + (w @ w) * r - (r @ w)[..., None] * w

    def translated(self, origin: np.ndarray) -> BodyForce:
        """The same field for coordinates translated by ``-origin``."""
        c = np.asarray(self.center) - np.asarray(origin, dtype=float)
        return BodyForce(self.gravity, self.angular_velocity, tuple(c.tolist()))


def densities(name: str, volume_names: tuple[str, ...], density) -> dict[str, float] | None:
    """Volume region -> density from ``density`` (a number for the whole
    body, a mapping per region, or None: none given)."""
    if density is None:
        return None
    if not isinstance(density, Mapping):
        density = {r: density for r in volume_names}
    out = {}
    for r, rho in density.items():
        if r not in volume_names:
            raise ConfigError(f"{name}: density: the volume mesh has no volume region {r!r} "
                              f"(its regions: {', '.join(volume_names)})", location={"region": r})
        if (isinstance(rho, bool) or not isinstance(rho, (int, float)) or not math.isfinite(rho)
                or rho < 0):
            raise ConfigError(f"{name}: the density of {r!r} must be a finite number >= 0, got "
                              f"{rho!r}", location={"region": r})
        out[r] = float(rho)
    return out


def nodal_body_forces(body) -> np.ndarray:
    """(3n,) consistent nodal forces ∫ φ_a ρ a(x) dV of ``body``'s body
    force (dof 3i + c, as the stiffness), by regions of their densities;
    zeros without one.  The quadrature is the element's own (exact for a
    linear field on straight-sided elements)."""
    v = body.volume
    out = np.zeros((v.n_nodes, 3))
    force = body.body_force
    if force is None or force.is_zero:
        return out.ravel()
    from skfem import Basis, LinearForm, asm

    basis = v.basis()
    for r, region in enumerate(v.volume_names):
        rho = body.density[region]
        if rho == 0.0:
            continue
        cells = np.flatnonzero(v.cell_region == r)
        sub = basis if len(v.volume_names) == 1 else Basis(v.skfem, basis.elem, elements=cells)
        for c in range(3):
            form = LinearForm(lambda w_, w, c=c: rho * force.acceleration(
                np.moveaxis(w.x, 0, -1))[..., c] * w_)
            out[:, c] += asm(form, sub)[v.dof_order]
    return out.ravel()


__all__ = ["BodyForce", "densities", "nodal_body_forces"]

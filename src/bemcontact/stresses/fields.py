"""Stress fields on the points of a probe, their measures and maxima.

:func:`evaluate` asks a solved result for the stresses of one
:class:`~.probes.StressRequest` (``result.stresses(body, points)``: Somigliana's
identity on the full path, the half-space field of the grid tractions on the
multiscale path) at the end of every load step, and returns a
:class:`StressField`: the points, the lattice, the final state's tensor and
measures (von Mises, Tresca = the maximum shear stress (σ1 − σ3)/2,
principal stresses) and, per step, each measure's maximum and where it is.

Stresses are Cauchy stresses in the problem's stress units, tension positive
(compression negative), components (σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz) in the
global axes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ConfigError
from ..halfspace import principal_stresses, tresca, von_mises
from .probes import Box, Line, Plane, StressRequest

#: Columns of ``stresses_<body>_<label>.csv``.
COLUMNS = ("x", "y", "z", "sxx", "syy", "szz", "sxy", "syz", "sxz", "von_mises", "tresca")

#: The measures whose maxima are reported: von Mises, Tresca and the largest
#: principal stress σ1 (the largest tension, where brittle parts crack).
MEASURES = ("von_mises", "tresca", "max_principal")


@dataclass(frozen=True)
class Lattice:
    """Points (n, 3) in C order of ``shape``, with each lattice direction's
    coordinates (1-D) and name (for tables and figures)."""

    points: np.ndarray
    shape: tuple[int, ...]
    coordinates: tuple[np.ndarray, ...]
    names: tuple[str, ...]

    @classmethod
    def of(cls, probe) -> Lattice:
        """The lattice of a :class:`Line`, :class:`Plane` or :class:`Box`."""
        if isinstance(probe, Line):
            return cls(probe.locations(), probe.shape, (probe.distance(),), ("s",))
        if isinstance(probe, Plane):
            return cls(probe.locations(), probe.shape, probe.coordinates(), ("u", "v"))
        if isinstance(probe, Box):
            return cls(probe.locations(), probe.shape,
                       tuple(np.linspace(a, b, n) for a, b, n in
                             zip(probe.lower, probe.upper, probe.points)), ("x", "y", "z"))
        raise ConfigError(f"a probe is a Line, Plane or Box, got {type(probe).__name__}")


@dataclass
class StressField:
    """The stresses of one request.

    request: what was asked.  lattice: the points.  stresses: (n, 6) at the
    end of the last step.  maxima: per load step, ``{measure: {"value",
    "point"}}`` for :data:`MEASURES`.  note: how the field was computed
    (the path and its model)."""

    request: StressRequest
    lattice: Lattice
    stresses: np.ndarray
    maxima: list[dict] = field(default_factory=list)
    note: str = ""

    @property
    def points(self) -> np.ndarray:
        return self.lattice.points

    @property
    def von_mises(self) -> np.ndarray:
        return von_mises(self.stresses)

    @property
    def tresca(self) -> np.ndarray:
        return tresca(self.stresses)

    @property
    def principal(self) -> np.ndarray:
        """(n, 3) σ1 ≥ σ2 ≥ σ3."""
        return principal_stresses(self.stresses)

    def table(self) -> np.ndarray:
        """(n, 11) in the order of :data:`COLUMNS`."""
        return np.column_stack([self.points, self.stresses, self.von_mises, self.tresca])

    def summary(self) -> dict:
        """JSON-ready: the request, the number of points and the maxima of
        the last step and of every step."""
        return {"body": self.request.body, "label": self.request.label,
                "kind": self.request.kind, "points": int(len(self.points)),
                "shape": list(self.lattice.shape), "note": self.note,
                "maximum": self.maxima[-1] if self.maxima else {}, "steps": self.maxima}


def measures(stresses: np.ndarray) -> dict[str, np.ndarray]:
    """The :data:`MEASURES` of (n, 6) stresses: name -> (n,)."""
    return {"von_mises": von_mises(stresses), "tresca": tresca(stresses),
            "max_principal": principal_stresses(stresses)[..., 0]}


def maxima(points: np.ndarray, stresses: np.ndarray) -> dict:
    """``{measure: {"value": float, "point": [x, y, z]}}`` for :data:`MEASURES`."""
    out = {}
    for name, values in measures(stresses).items():
        k = int(np.argmax(values))
        out[name] = {"value": float(values[k]), "point": points[k].tolist()}
    return out


def surface_maxima(result) -> dict:
    """Per body of ``result``, the :func:`maxima` of its surface stresses at
    the end of the last step (``result.surface_points`` and
    ``.surface_stresses``: the full path's functional nodes, the grid's
    cells); bodies that give none are left out."""
    out = {}
    for name in result.names:
        try:
            points = result.surface_points(name)
        except ConfigError:  # a body without surface stresses
            continue
        out[name] = maxima(points, result.surface_stresses(name))
    return out


def _states(result) -> list:
    """Per load step, stresses(body, points) at its end (``result.stresses``
    with ``step``, on either path)."""
    n = len(getattr(result, "history", None) or [result])
    return [lambda b, x, k=k: result.stresses(b, x, step=k) for k in range(n)]


def evaluate(result, request: StressRequest, lattice: Lattice | None = None, *,
             every_step: bool = True) -> StressField:
    """The :class:`StressField` of ``request`` on a solved ``result``
    (``lattice``: its points, by default the probe's).  With ``every_step``
    the maxima of every load step are computed (one evaluation per step),
    else of the last only.  Raises :class:`ConfigError` for an unknown body or
    a point outside it (naming the request's label)."""
    return evaluate_all(result, [(request, lattice)], every_step=every_step)[0]


def evaluate_all(result, items, *, every_step: bool = True) -> list[StressField]:
    """:func:`evaluate` for each (request, lattice or None) of ``items``, the
    requests of one body together (one evaluation per body and step: the
    quadrature's set-up, or the grid's FFT layers at the depths they share,
    once)."""
    for request, _ in items:
        if not isinstance(request, StressRequest):
            raise ConfigError(f"evaluate: expected a StressRequest, got "
                              f"{type(request).__name__}")
    lats = [lat if lat is not None else Lattice.of(r.probe) for r, lat in items]
    states = _states(result)
    if not every_step:
        states = states[-1:]
    maxs: list[list] = [[] for _ in items]
    last: list = [None] * len(items)
    bodies: dict[str, list[int]] = {}
    for k, (r, _) in enumerate(items):
        bodies.setdefault(r.body, []).append(k)
    for body, ks in bodies.items():
        points = np.concatenate([lats[k].points for k in ks])
        bounds = np.cumsum([0] + [len(lats[k].points) for k in ks])
        for state in states:
            try:
                s = np.asarray(state(body, points), dtype=float)
            except ConfigError as exc:
                i = int(exc.location.get("point", 0))
                j = max(int(np.searchsorted(bounds, i, side="right")) - 1, 0)
                r = items[ks[j]][0]
                own = int(i - bounds[j])
                detail = str(exc).replace(f"point {i} ", f"point {own} ", 1)
                raise ConfigError(f"output.stresses {r.label!r} ({r.kind} in {r.body!r}): "
                                  f"{detail}", location={**exc.location, "point": own,
                                                         "label": r.label}) from None
            for j, k in enumerate(ks):
                part = s[bounds[j]:bounds[j + 1]]
                maxs[k].append(maxima(lats[k].points, part))
                last[k] = part
    note = getattr(result, "stress_model", "")
    return [StressField(r, lat, last[k], maxs[k], note)
            for k, ((r, _), lat) in enumerate(zip(items, lats))]


__all__ = ["COLUMNS", "Lattice", "MEASURES", "StressField", "evaluate", "evaluate_all", "maxima",
           "measures", "surface_maxima"]

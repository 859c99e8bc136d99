"""Where stresses are asked for: a line, a plane or a box of points in a body.

Each probe is a frozen dataclass that checks itself and gives its points
(:meth:`locations`, an (n, 3) array in global coordinates, length units) and the
shape of its lattice (:attr:`shape`: (n,) for a line, (nu, nv) for a plane,
(nx, ny, nz) for a box), so the files can keep the lattice (a VTU image of a
plane or box, a figure of a plane).  Points are ordered in C order of
:attr:`shape`.

* :class:`Line` — ``points`` evenly spaced from ``start`` to ``end``, both
  included.
* :class:`Plane` — a ``size[0]`` × ``size[1]`` rectangle centred on
  ``origin``, normal to ``normal``; its in-plane axes u, v (:meth:`Plane.axes`)
  are ``u_axis`` (projected onto the plane) and n × u; ``points`` = (nu, nv)
  nodes along u and v, edges included.
* :class:`Box` — the axis-aligned box ``lower`` to ``upper`` with
  ``points`` = (nx, ny, nz) nodes along x, y, z, faces included (1 along an
  axis whose bounds coincide: a slice).

A :class:`StressRequest` names the body a probe lies in and its ``label``
(which names the files).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..settings import Key

#: Most points one probe may hold (a box of 100 x 100 x 100).
MAX_POINTS = 1_000_000

_LABEL = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_-]*$")


def _vector(owner: str, name: str, value: object, length: int = 3) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ConfigError(f"{owner}: {name} must be {length} numbers, got {value!r}",
                          location={"field": name}) from None
    if v.size != length or not np.all(np.isfinite(v)):
        raise ConfigError(f"{owner}: {name} must be {length} finite numbers, got {value!r}",
                          location={"field": name})
    return v


def _counts(owner: str, value: object, length: int, least: int) -> tuple[int, ...]:
    items = [value] if length == 1 and not isinstance(value, (list, tuple, np.ndarray)) \
        else list(np.asarray(value).reshape(-1)) if isinstance(value, np.ndarray) else value
    if not isinstance(items, (list, tuple)) or len(items) != length:
        raise ConfigError(f"{owner}: points must be {length} integers, got {value!r}",
                          location={"field": "points"})
    out = []
    for v in items:
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or v < least:
            raise ConfigError(f"{owner}: points must be integers >= {least}, got {value!r}",
                              location={"field": "points"})
        out.append(int(v))
    if math.prod(out) > MAX_POINTS:
        raise ConfigError(f"{owner}: {math.prod(out):,} points, more than {MAX_POINTS:,}; "
                          "ask for fewer", location={"field": "points"})
    return tuple(out)


@dataclass(frozen=True)
class Line:
    """``points`` points evenly spaced on the segment ``start`` → ``end``."""

    start: tuple[float, float, float]
    end: tuple[float, float, float]
    points: int = 51

    def __post_init__(self) -> None:
        a, b = _vector("line", "from", self.start), _vector("line", "to", self.end)
        if np.linalg.norm(b - a) == 0.0:
            raise ConfigError(f"line: from and to are the same point {a.tolist()}",
                              location={"field": "to"})
        object.__setattr__(self, "start", tuple(a.tolist()))
        object.__setattr__(self, "end", tuple(b.tolist()))
        object.__setattr__(self, "points", _counts("line", self.points, 1, 2)[0])

    @property
    def shape(self) -> tuple[int, ...]:
        return (self.points,)

    def locations(self) -> np.ndarray:
        s = np.linspace(0.0, 1.0, self.points)[:, None]
        return np.asarray(self.start) * (1.0 - s) + np.asarray(self.end) * s

    def distance(self) -> np.ndarray:
        """(n,) each point's distance from ``start`` (a profile's abscissa)."""
        return np.linspace(0.0, 1.0, self.points) * float(
            np.linalg.norm(np.subtract(self.end, self.start)))


@dataclass(frozen=True)
class Plane:
    """A rectangle ``size`` = (along u, along v) centred on ``origin``, normal
    to ``normal``, with ``points`` = (nu, nv) nodes; u is ``u_axis`` projected
    onto the plane (default: the global axis least aligned with the normal)."""

    origin: tuple[float, float, float]
    normal: tuple[float, float, float]
    size: tuple[float, float]
    points: tuple[int, int] = (41, 41)
    u_axis: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        o = _vector("plane", "origin", self.origin)
        n = _vector("plane", "normal", self.normal)
        if np.linalg.norm(n) == 0.0:
            raise ConfigError("plane: normal must not be zero", location={"field": "normal"})
        s = _vector("plane", "size", self.size, 2)
        if np.any(s <= 0.0):
            raise ConfigError(f"plane: size must be two lengths > 0, got {s.tolist()}",
                              location={"field": "size"})
        n = n / np.linalg.norm(n)
        u = np.eye(3)[int(np.argmin(np.abs(n)))] if self.u_axis is None \
            else _vector("plane", "u_axis", self.u_axis)
        u = u - (u @ n) * n
        if np.linalg.norm(u) < 1e-9:
            raise ConfigError("plane: u_axis is along the normal", location={"field": "u_axis"})
        object.__setattr__(self, "origin", tuple(o.tolist()))
        object.__setattr__(self, "normal", tuple(n.tolist()))
        object.__setattr__(self, "size", tuple(s.tolist()))
        object.__setattr__(self, "u_axis", tuple((u / np.linalg.norm(u)).tolist()))
        object.__setattr__(self, "points", _counts("plane", self.points, 2, 2))

    @property
    def shape(self) -> tuple[int, ...]:
        return self.points

    def axes(self) -> np.ndarray:
        """(3, 3): rows u, v, n (right-handed, unit)."""
        n, u = np.asarray(self.normal), np.asarray(self.u_axis)
        return np.stack([u, np.cross(n, u), n])

    def coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """The nodes' in-plane coordinates along u and v (from ``origin``)."""
        return (np.linspace(-0.5, 0.5, self.points[0]) * self.size[0],
                np.linspace(-0.5, 0.5, self.points[1]) * self.size[1])

    def locations(self) -> np.ndarray:
        u, v = self.coordinates()
        A = self.axes()
        U, V = np.meshgrid(u, v, indexing="ij")
        return (np.asarray(self.origin) + U.reshape(-1, 1) * A[0] + V.reshape(-1, 1) * A[1])


@dataclass(frozen=True)
class Box:
    """The box ``lower`` → ``upper`` with ``points`` = (nx, ny, nz) nodes."""

    lower: tuple[float, float, float]
    upper: tuple[float, float, float]
    points: tuple[int, int, int] = (11, 11, 11)

    def __post_init__(self) -> None:
        lo, hi = _vector("box", "lower", self.lower), _vector("box", "upper", self.upper)
        if np.any(hi < lo):
            raise ConfigError(f"box: upper {hi.tolist()} must be >= lower {lo.tolist()} in "
                              "every component", location={"field": "upper"})
        pts = _counts("box", self.points, 3, 1)
        for k in range(3):
            if (pts[k] == 1) != (hi[k] == lo[k]):
                raise ConfigError(f"box: points[{k}] = {pts[k]} but the box's extent along "
                                  f"{'xyz'[k]} is {hi[k] - lo[k]:g} (1 point exactly when the "
                                  "bounds coincide)", location={"field": "points"})
        object.__setattr__(self, "lower", tuple(lo.tolist()))
        object.__setattr__(self, "upper", tuple(hi.tolist()))
        object.__setattr__(self, "points", pts)

    @property
    def shape(self) -> tuple[int, ...]:
        return self.points

    def locations(self) -> np.ndarray:
        axes = [np.linspace(a, b, n) for a, b, n in zip(self.lower, self.upper, self.points)]
        return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


Probe = Line | Plane | Box

#: Problem-file keys of each probe (``[[output.stresses]]``).
PROBE_KEYS = {
    "line": Key("line", "table", "points on a segment", section="output.stresses.line", keys=(
        Key("from", "vector", "first point [x, y, z] (length)", True),
        Key("to", "vector", "last point [x, y, z] (length)", True),
        Key("points", "integer", "number of points, both ends included", default=51, lo=2),
    )),
    "plane": Key("plane", "table", "a rectangle of points", section="output.stresses.plane",
                 keys=(
        Key("origin", "vector", "its centre [x, y, z] (length)", True),
        Key("normal", "vector", "its normal (not zero)", True),
        Key("size", "number-or-pair", "its sides along u and v (length): one number for a "
            "square, or [along u, along v]", True, lo=0, lo_open=True),
        Key("points", "integer-or-pair", "nodes along u and v: one integer, or [nu, nv]",
            default=41, lo=2),
        Key("u_axis", "vector", "in-plane direction u (projected onto the plane); v = normal "
            "x u", default_text="the global axis least aligned with the normal"),
    )),
    "box": Key("box", "table", "an axis-aligned box of points", section="output.stresses.box",
               keys=(
        Key("lower", "vector", "lower corner (length)", True),
        Key("upper", "vector", "upper corner (length), >= lower", True),
        Key("points", "integer-or-vector", "nodes along x, y, z: one integer or [nx, ny, nz] "
            "(1 where lower and upper coincide)", default=11, lo=1),
    )),
}


@dataclass(frozen=True)
class StressRequest:
    """Stresses asked for in ``body`` at the points of ``probe``; ``label``
    names the files (``stresses_<body>_<label>``)."""

    body: str
    probe: Probe
    label: str

    def __post_init__(self) -> None:
        if not isinstance(self.body, str) or not self.body:
            raise ConfigError(f"stresses: body must be a body's name, got {self.body!r}",
                              location={"field": "body"})
        if not isinstance(self.probe, (Line, Plane, Box)):
            raise ConfigError(f"stresses: probe must be a Line, Plane or Box, got "
                              f"{type(self.probe).__name__}", location={"field": "probe"})
        if not isinstance(self.label, str) or not _LABEL.match(self.label):
            raise ConfigError(f"stresses: label must be letters, digits, _ or - (a letter or "
                              f"digit first), got {self.label!r}", location={"field": "label"})

    @property
    def kind(self) -> str:
        return type(self.probe).__name__.lower()


__all__ = ["Box", "Line", "MAX_POINTS", "PROBE_KEYS", "Plane", "Probe", "StressRequest"]

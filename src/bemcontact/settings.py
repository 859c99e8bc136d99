"""Settings: the one declaration of a setting's type, range, default and
documentation (:class:`Key`).

An options dataclass declares each field with :func:`setting` (its
:class:`Key` rides in the field's metadata) and checks itself with
:func:`check_settings`; the problem-file schema takes the same keys with
:func:`keys_of`.  So a range or a default is written once, and the problem
file, the reference page and the Python API cannot disagree.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from .errors import ConfigError

#: Value that marks "no default" (the key is required or has a computed default).
NO_DEFAULT = object()
#: Every number must be 0 or of a magnitude in [SMALLEST, LARGEST] (beyond,
#: products of coordinates, moduli and displacements overflow or underflow).
SMALLEST = 1e-100
LARGEST = 1e100
#: Most OpenMP threads accepted.
MAX_THREADS = 4096


@dataclass(frozen=True)
class Key:
    """One key of the problem file (see the module docstring for ``type``)."""

    name: str
    type: str
    doc: str
    required: bool = False
    default: Any = NO_DEFAULT
    #: How the default reads in the docs when it is computed, not a constant.
    default_text: str = ""
    lo: float | None = None
    lo_open: bool = False
    hi: float | None = None
    hi_open: bool = False
    choices: tuple[str, ...] = ()
    length: int = 0
    keys: tuple[Key, ...] = ()
    entry: Key | None = None
    #: Name of the section in the reference page (tables, maps, arrays of tables).
    section: str = ""
    #: Longer notes printed under the section's table.
    notes: str = ""

    def key(self, name: str) -> Key:
        """The child key ``name`` of a table (KeyError if it has none)."""
        for k in self.keys:
            if k.name == name:
                return k
        raise KeyError(name)

    @property
    def allowed(self) -> tuple[str, ...]:
        return tuple(k.name for k in self.keys)

    @property
    def needed(self) -> tuple[str, ...]:
        return tuple(k.name for k in self.keys if k.required)

    def range_text(self) -> str:
        """'in (0, 1)', '>= 1', '' (no bounds)."""
        return range_text(self.lo, self.lo_open, self.hi, self.hi_open)

    def violation(self, value: Any) -> str | None:
        """What is wrong with ``value`` for this key ('must be in (0, 1)',
        'must be an integer >= 1', "must be 'all' or 'last'", ...), or None.
        ``None`` is accepted where it is the default (an optional setting)."""
        if value is None and self.default is None:
            return None
        rng = self.range_text()
        if self.type in ("number", "integer"):
            integer = self.type == "integer"
            kind = "an integer" if integer else "a number"
            if isinstance(value, bool) or not isinstance(value, int if integer else (int, float)):
                return f"must be {kind}" + (f" {rng}" if rng else "") + (
                    " or None" if self.default is None else "")
            if not math.isfinite(value):
                return "must be finite"
            if not in_range(value, self.lo, self.lo_open, self.hi, self.hi_open):
                return f"must be {kind} {rng}" if integer else f"must be {rng}"
            if self.choices and str(value) not in self.choices:
                return f"must be {choice_text(self.choices)}"
            return None
        if self.type == "boolean":
            return None if isinstance(value, bool) else "must be True or False"
        if self.type == "string":
            if not isinstance(value, str):
                return "must be a string"
            if self.choices and value not in self.choices:
                return f"must be {choice_text(self.choices)}"
        return None


def range_text(lo: float | None, lo_open: bool, hi: float | None, hi_open: bool) -> str:
    """'in (0, 1]' with both bounds, '> 0' or '<= 1' with one, '' with none."""
    if lo is not None and hi is not None:
        return f"in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}"
    if hi is not None:
        return f"{'<' if hi_open else '<='} {hi:g}"
    return ""


def in_range(value: float, lo: float | None, lo_open: bool, hi: float | None,
             hi_open: bool) -> bool:
    low = lo is not None and (value <= lo if lo_open else value < lo)
    high = hi is not None and (value >= hi if hi_open else value > hi)
    return not (low or high)


def choice_text(choices: tuple[str, ...]) -> str:
    """"'a' or 'b'", "one of 'a', 'b', 'c'"."""
    quoted = [repr(c) for c in choices]
    if len(quoted) == 2:
        return f"{quoted[0]} or {quoted[1]}"
    return "one of " + ", ".join(quoted)


def setting(key: Key) -> Any:
    """A dataclass field declared by ``key``: its default is the key's, and
    :func:`check_settings` and :func:`keys_of` find the key in its metadata."""
    if key.default is NO_DEFAULT:
        return dataclasses.field(metadata={"key": key})
    return dataclasses.field(default=key.default, metadata={"key": key})


def check_settings(obj: Any, error: type[Exception] = ConfigError) -> None:
    """Check every :func:`setting` field of the dataclass ``obj`` against its
    key: raises ``error("<Class>.<field> must be ..., got <value>")``."""
    for f in dataclasses.fields(obj):
        key = f.metadata.get("key")
        if key is None:
            continue
        value = getattr(obj, f.name)
        problem = key.violation(value)
        if problem is not None:
            raise error(f"{type(obj).__name__}.{f.name} {problem}, got {value!r}")


def key_of(cls: type, name: str) -> Key:
    """The :class:`Key` of field ``name`` of the options dataclass ``cls``."""
    for f in dataclasses.fields(cls):
        if f.name == name and "key" in f.metadata:
            return f.metadata["key"]
    raise KeyError(f"{cls.__name__}.{name} is not a setting")


def keys_of(cls: type, *names: str, defaults: Any = None, **changes: dict[str, Any]) -> tuple[Key, ...]:
    """The keys of fields ``names`` of ``cls`` (all its settings, in field
    order, if none are named), for a schema table.  ``defaults``, an
    instance, supplies the defaults (e.g. the condensation's own linear
    options); ``changes[name]`` replaces attributes of one key (its doc in
    the problem file, a computed default)."""
    fields = [f.name for f in dataclasses.fields(cls) if "key" in f.metadata]
    out = []
    for name in names or fields:
        key = key_of(cls, name)
        if defaults is not None:
            key = dataclasses.replace(key, default=getattr(defaults, name))
        if name in changes:
            key = dataclasses.replace(key, **changes[name])
        out.append(key)
    return tuple(out)

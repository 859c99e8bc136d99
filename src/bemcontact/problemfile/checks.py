"""Checking problem-file values: tables against their schema keys, numbers,
strings, vectors and component lists, with one-line errors that name the
file and the dotted field (``body[1].material.poisson_ratio``) and suggest
the closest allowed key or choice."""

from __future__ import annotations

import copy
import difflib
import math
import pathlib
from typing import Any, NoReturn

from ..errors import BemcontactError, ConfigError
from ..settings import LARGEST, NO_DEFAULT, SMALLEST, Key, in_range, range_text

#: The string that leaves a displacement or traction component unprescribed.
FREE = "free"

#: Unit labels the ``units`` table accepts, with their SI factors.
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6, "µm": 1e-6, "km": 1e3,
               "in": 0.0254, "ft": 0.3048},
    "force": {"N": 1.0, "mN": 1e-3, "kN": 1e3, "MN": 1e6, "lbf": 4.4482216152605,
              "kip": 4448.2216152605},
    "stress": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "N/mm²": 1e6, "N/mm^2": 1e6,
               "psi": 6894.757293168, "ksi": 6894757.293168, "psf": 47.88025898033584},
}
#: Consistent sets named by the error for inconsistent ``units``.
CONSISTENT_UNITS = ("{m, N, Pa}, {mm, N, MPa}, {m, kN, kPa}, {mm, kN, GPa}, {m, MN, MPa}, "
                    "{in, lbf, psi}, {in, kip, ksi}")


def one_line(text: str) -> str:
    return " ".join(str(text).split())


def _short(value: Any, limit: int = 80) -> str:
    r = repr(value)
    return r if len(r) <= limit else r[: limit - 3] + "..."


def suggest(word: str, choices: Any) -> str:
    close = difflib.get_close_matches(str(word), [str(c) for c in choices], n=1, cutoff=0.6)
    return f"did you mean {close[0]!r}?" if close else ""


class Checker:
    """Checks the values of one file's content against the schema; every
    method raises a one-line :class:`ConfigError` naming the file and the field
    (``<file>: <field>: <what is wrong>, got <value>``)."""

    def __init__(self, src: str, base: pathlib.Path) -> None:
        self.src = src
        self.base = base

    # ------------------------------------------------------------------ errors
    def fail(self, where: str, what: str, value: Any, fix: str = "") -> NoReturn:
        msg = f"{self.src}: {where}: {what}, got {_short(value)}"
        if fix:
            msg += f" ({fix})" if fix.startswith("did you mean") else f"; {fix}"
        raise ConfigError(one_line(msg))

    def wrap(self, where: str, exc: BemcontactError, value: Any, fix: str = "") -> NoReturn:
        """Re-raise a library error as a field error (the library's message,
        without a leading ``<source>: `` of its own, is the 'what')."""
        text = one_line(str(exc))
        for prefix in (f"{self.src}: ", "box: "):
            if text.startswith(prefix):
                text = text[len(prefix) :]
        self.fail(where, text.rstrip("."), value, fix)

    # --------------------------------------------------------------- primitives
    def table(self, where: str, value: Any, key: Key) -> dict[str, Any]:
        """``value`` must be a table holding only ``key``'s keys and all its required ones."""
        if not isinstance(value, dict):
            self.fail(where or "top level", f"must be a table, not {a_type(value)}", value)
        allowed = key.allowed
        for name in value:
            if name not in allowed:
                self.fail(
                    f"{where}.{name}" if where else name,
                    "unknown key",
                    name,
                    suggest(name, allowed) or f"allowed keys: {', '.join(allowed)}",
                )
        for name in key.needed:
            if name not in value:
                self.fail(
                    f"{where}.{name}" if where else name, "missing required key", value,
                    f"add {name} = ...",
                )
        return value

    def value(self, where: str, value: Any, key: Key) -> Any:
        """A scalar, vector or string checked against its schema ``key``."""
        if key.type in ("number", "integer"):
            v = self.number(
                where, value, integer=key.type == "integer", lo=key.lo, lo_open=key.lo_open,
                hi=key.hi, hi_open=key.hi_open,
            )
            if key.choices and str(v) not in key.choices:
                self.fail(where, f"must be one of {', '.join(key.choices)}", value)
            return v
        if key.type == "string":
            return self.string(where, value, key.choices or None)
        if key.type == "boolean":
            if not isinstance(value, bool):
                self.fail(where, f"must be true or false, not {a_type(value)}", value)
            return value
        if key.type == "vector":
            return self.vector(where, value)
        if key.type == "pair":
            return [self.number(f"{where}[{a}]", v)
                    for a, v in enumerate(self.array(where, value, 2))]
        if key.type == "components":
            return self.vector(where, value, free=True)
        if key.type == "strings":
            self.array(where, value, key.length)
            return [self.string(f"{where}[{k}]", v) for k, v in enumerate(value)]
        if key.type == "numbers":
            if not isinstance(value, list):
                self.fail(where, f"must be an array of numbers, not {a_type(value)}", value)
            return [self.number(f"{where}[{k}]", v, lo=key.lo, lo_open=key.lo_open)
                    for k, v in enumerate(value)]
        if key.type == "matrix":
            n = key.length
            return [[self.number(f"{where}[{i}][{j}]", v)
                     for j, v in enumerate(self.array(f"{where}[{i}]", row, n))]
                    for i, row in enumerate(self.array(where, value, n))]
        if key.type in ("number-or-vector", "integer-or-vector", "number-or-pair",
                        "integer-or-pair"):
            integer = key.type.startswith("integer")
            if isinstance(value, list):
                self.array(where, value, 2 if key.type.endswith("pair") else 3)
                return [
                    self.number(f"{where}[{a}]", v, integer=integer, lo=key.lo,
                                lo_open=key.lo_open)
                    for a, v in enumerate(value)
                ]
            return self.number(where, value, integer=integer, lo=key.lo, lo_open=key.lo_open)
        raise AssertionError(f"schema type {key.type} is not a value")  # pragma: no cover

    def fields(self, where: str, t: dict, key: Key) -> dict[str, Any]:
        """Every scalar key of table ``t`` checked, defaults filled in (keys
        without a default and not given are left out)."""
        out = {}
        for k in key.keys:
            if k.type in ("table", "tables", "map"):
                continue
            if k.name in t:
                out[k.name] = self.value(f"{where}.{k.name}" if where else k.name, t[k.name], k)
            elif k.default is not NO_DEFAULT:
                out[k.name] = copy.deepcopy(k.default)
        if key.name == "units" and not where.count("."):
            self.check_units(where, out)
        return out

    def check_units(self, where: str, labels: dict[str, str]) -> None:
        """The ``units`` labels name known units (:data:`UNITS`) and, when
        all three are given, a consistent set: stress = force / length²."""
        for kind, label in labels.items():
            if label not in UNITS[kind]:
                self.fail(f"{where}.{kind}", f"unknown {kind} unit", label,
                          suggest(label, UNITS[kind]) or f"known: {', '.join(UNITS[kind])}")
        if len(labels) == 3:
            L, F, S = (UNITS[k][labels[k]] for k in ("length", "force", "stress"))
            if not math.isclose(F / L**2, S, rel_tol=1e-6):
                fit = next((n for n, v in UNITS["stress"].items()
                            if math.isclose(F / L**2, v, rel_tol=1e-6)), "none of the known")
                self.fail(where, f"inconsistent: {labels['force']} / {labels['length']}² is "
                          f"{fit}, not {labels['stress']}", labels,
                          f"use a consistent set, e.g. {CONSISTENT_UNITS}")

    def number(
        self, where: str, value: Any, *, integer: bool = False, lo: float | None = None,
        lo_open: bool = False, hi: float | None = None, hi_open: bool = False,
    ) -> Any:
        kind = "an integer" if integer else "a number"
        if isinstance(value, bool):
            self.fail(where, f"must be {kind}, not a boolean", value)
        if integer:
            if not isinstance(value, int):
                whole = isinstance(value, float) and math.isfinite(value) and value.is_integer()
                fix = f"write {int(value)}" if whole else ""
                self.fail(where, f"must be an integer, not {a_type(value)}", value, fix)
        elif not isinstance(value, (int, float)):
            self.fail(where, f"must be a number, not {a_type(value)}", value)
        try:
            finite = math.isfinite(value)
        except OverflowError:  # an integer beyond the float range
            finite = False
        if not finite:
            self.fail(where, "must be finite", value)
        if not (value == 0 or SMALLEST <= abs(value) <= LARGEST):
            self.fail(where, f"must be 0 or of magnitude {SMALLEST:g} to "
                      f"{LARGEST:g}", value, "use other units")
        if not in_range(value, lo, lo_open, hi, hi_open):
            self.fail(where, f"must be {range_text(lo, lo_open, hi, hi_open)}", value)
        return value if integer else float(value)

    def string(self, where: str, value: Any, choices: tuple[str, ...] | None = None) -> str:
        if not isinstance(value, str):
            self.fail(where, f"must be a string, not {a_type(value)}", value)
        if choices is not None and value not in choices:
            self.fail(
                where, f"must be one of {', '.join(choices)}", value, suggest(value, choices)
            )
        return value

    def array(self, where: str, value: Any, length: int) -> list:
        if not isinstance(value, list):
            self.fail(
                where, f"must be an array of {length} values, not {a_type(value)}", value
            )
        if len(value) != length:
            self.fail(where, f"must have {length} values, not {len(value)}", value)
        return value

    def vector(self, where: str, value: Any, *, free: bool = False) -> tuple:
        out = []
        for i, c in enumerate(self.array(where, value, 3)):
            if free and isinstance(c, str):
                if c != FREE:
                    self.fail(
                        f"{where}[{i}]", f'must be a number or "{FREE}"', c, suggest(c, (FREE,))
                    )
                out.append(None)
            elif free and (isinstance(c, bool) or not isinstance(c, (int, float))):
                self.fail(
                    f"{where}[{i}]", f'must be a number or "{FREE}", not {a_type(c)}', c
                )
            else:
                out.append(self.number(f"{where}[{i}]", c))
        return tuple(out)


def a_type(value: Any) -> str:
    """'a string', 'an integer', ...: the type of ``value`` with its article."""
    name = _type_name(value)
    return f"{'an' if name[0] in 'aeiou' else 'a'} {name}"


def _type_name(value: Any) -> str:
    return {
        bool: "boolean", int: "integer", float: "number", str: "string", list: "array",
        dict: "table",
    }.get(type(value), type(value).__name__)


__all__ = ["Checker", "FREE"]

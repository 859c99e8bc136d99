"""The points of a sweep: the varied keys (dotted paths as in the
problem file's error messages, ``contact.friction_coefficient``,
``body[1].boundary_conditions.zmax.displacement[2]``), their values, the
problem file of each point and the checks of all of them before anything
runs.

A point's problem file is the base file's content with the point's values
set, written as TOML (:func:`toml_text`; mesh files named by absolute path)
and read by :func:`~bemcontact.problemfile.load_problem`, so a point is
exactly what ``bemcontact run`` of that file solves.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import math
import os
import pathlib
import re
import tempfile
import tomllib
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..bem.conditions import Displacement, Force, Pressure
from ..contact.reuse import FRAME_FIELDS
from ..errors import BemcontactError, BemcontactWarning, ConfigError
from ..problemfile import load_problem
from ..problemfile import schema
from ..problemfile.checks import Checker, a_type, one_line, suggest

#: Most points of one sweep (a full factorial grows fast).
MAX_POINTS = 10_000
#: Value types of a varied key.
_VECTORS = ("vector", "components", "number-or-vector", "integer-or-vector", "strings", "pair")
_NAME = re.compile(r"^([^\[\]]+)((?:\[\d+\])*)$")


@dataclass
class Point:
    """One point: its number (0-based), the varied keys' values, the
    point's problem-file content and, once checked, its problem file's text
    and the key of the bodies it condenses (points with equal keys share the
    condensed operators)."""

    index: int
    values: dict[str, Any]
    content: dict
    text: str = ""
    group: str = ""
    kinds: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        return f"p{self.index + 1:04d}"


# ------------------------------------------------------------------ keys


def parse_key(text: str) -> list[str | int]:
    """``body[1].boundary_conditions.zmax.displacement[2]`` -> ['body', 1,
    'boundary_conditions', 'zmax', 'displacement', 2]; ConfigError if malformed."""
    out: list[str | int] = []
    for part in str(text).split("."):
        m = _NAME.match(part.strip())
        if not m:
            raise ConfigError(f"{text!r} is not a dotted problem-file key (e.g. "
                              "contact.friction_coefficient or body[1].material.youngs_modulus)")
        out.append(m.group(1))
        out += [int(i) for i in re.findall(r"\[(\d+)\]", m.group(2))]
    return out


def check_key(chk: Checker, text: str) -> list[str | int]:
    """The tokens of a varied key, checked against the schema: every name a
    key of its table (with a did-you-mean), indices only on arrays, the
    end a value (not a table)."""
    where = f"sweep key {text}"
    try:
        tokens = parse_key(text)
    except ConfigError as exc:
        chk.fail("sweep", str(exc), text)
    key = schema.ROOT
    element = False  # inside one table of an array of tables
    shown = ""
    for i, tok in enumerate(tokens):
        if isinstance(tok, int):
            # [[contact]] may also be an array of tables (an assembly's pairs)
            if (key.type == "tables" or key is schema.CONTACT) and not element:
                element = True
            elif key.type in _VECTORS and i == len(tokens) - 1:
                if key.type == "pair" and tok > 1:
                    chk.fail(where, f"{shown} has 2 components, [0] and [1]", text)
                if tok > 2 and key.type != "strings":
                    chk.fail(where, f"{shown} has 3 components, [0] to [2]", text)
            else:
                chk.fail(where, f"{shown} is not an array", text)
            shown += f"[{tok}]"
            continue
        if key.type == "tables" and not element:
            chk.fail(where, f"{shown} is an array of [[{key.name}]] sections; give the index, "
                     f"e.g. {shown}[0].{tok}", text)
        if key.type == "map":
            key, element = key.entry, False
            if key is None:
                chk.fail(where, f"{shown}: no keys below it", text)
        elif key.keys:
            names = key.allowed
            if tok not in names or tok == "sweep":
                allowed = [n for n in names if n != "sweep"]
                chk.fail(f"{shown}.{tok}" if shown else tok, "unknown key", tok,
                         suggest(tok, allowed) or f"allowed keys: {', '.join(allowed)}")
            key, element = next(k for k in key.keys if k.name == tok), False
        else:
            chk.fail(where, f"{shown} is a value, not a table", text)
        shown = f"{shown}.{tok}" if shown else tok
    if key.type in ("table", "map") or (key.type == "tables" and not element):
        chk.fail(where, f"{shown} is a table; vary one of its keys", text)
    return tokens


def set_key(chk: Checker, content: dict, text: str, tokens, value) -> None:
    """``content`` with the key ``tokens`` set to ``value`` (tables created
    on the way; array indices must exist)."""
    node: Any = content
    shown = ""
    for i, tok in enumerate(tokens):
        last = i == len(tokens) - 1
        if isinstance(tok, int):
            if not isinstance(node, list) or tok >= len(node):
                n = len(node) if isinstance(node, list) else 0
                chk.fail(f"sweep key {text}", f"{shown} has {n} entries in the problem file, no "
                         f"[{tok}]", text)
            if last:
                node[tok] = value
                return
            node = node[tok]
        else:
            if not isinstance(node, dict):
                chk.fail(f"sweep key {text}", f"{shown} is not a table in the problem file", text)
            if last:
                node[tok] = value
                return
            nxt = tokens[i + 1]
            if tok not in node:
                if isinstance(nxt, int):
                    chk.fail(f"sweep key {text}", f"{shown}.{tok} is not in the problem file; "
                             "an index needs the array", text)
                node[tok] = {}
            node = node[tok]
        shown += f"[{tok}]" if isinstance(tok, int) else (f".{tok}" if shown else tok)


def parse_values(text: str) -> list:
    """``0.1,0.2`` -> [0.1, 0.2]; ``[0,0,-1],[0,0,-2]`` -> two vectors;
    TOML values, a bare word as a string; commas inside brackets or quotes
    do not split."""
    parts, depth, quote, cur = [], 0, "", ""
    for ch in text:
        if quote:
            quote = "" if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        cur += ch
    parts.append(cur)
    out = []
    for p in parts:
        p = p.strip()
        try:
            out.append(tomllib.loads(f"v = {p}")["v"])
        except tomllib.TOMLDecodeError:
            out.append(p)
    return out


# ------------------------------------------------------------------ TOML


def _toml_string(s: str) -> str:
    """A TOML basic string: quotes, backslashes, control characters and DEL
    escaped, everything else as it is (JSON's \\uD83D\\uDE00 surrogate escapes
    are not TOML: a title with an emoji made an unreadable point file)."""
    out = []
    for ch in s:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _toml_string(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_string(str(k))} = {_toml(x)}" for k, x in v.items()) + "}"
    raise ConfigError(f"cannot write {v!r} ({a_type(v)}) into a problem file")


def toml_text(content: dict, header: str = "") -> str:
    """A problem file's text for ``content`` (top-level keys, every table inline)."""
    lines = [f"# {line}" for line in header.splitlines()]
    lines += [f"{_toml_string(str(k))} = {_toml(v)}" for k, v in content.items()]
    return "\n".join(lines) + "\n"


def _absolute_meshes(content: dict, base: pathlib.Path) -> None:
    for b in content.get("body", []) if isinstance(content.get("body"), list) else []:
        mesh = b.get("mesh") if isinstance(b, dict) else None
        if isinstance(mesh, dict) and isinstance(mesh.get("file"), str):
            mesh["file"] = str((base / mesh["file"]).resolve())


# ------------------------------------------------------------------ points


def points_of(chk: Checker, content: dict, vary: Sequence[tuple[str, list]] | None,
              listed: Sequence[dict] | None) -> list[Point]:
    """The points: every combination of the ``vary`` values (full
    factorial, the first key slowest), or the ``listed`` points (each a
    mapping key -> value)."""
    base = {k: v for k, v in content.items() if k != "sweep"}
    if vary:
        keys = [k for k, _ in vary]
        combos = [dict(zip(keys, c)) for c in itertools.product(*[v for _, v in vary])]
    else:
        combos = [dict(p) for p in listed or []]
    if not combos:
        chk.fail("sweep", "no points to run", vary or listed,
                 "give --vary KEY=VALUES or a [sweep] table with vary or points")
    if len(combos) > MAX_POINTS:
        chk.fail("sweep", f"{len(combos):,} points, more than the {MAX_POINTS:,} accepted",
                 [k for k, _ in vary or []])
    tokens = {}
    out = []
    for i, values in enumerate(combos):
        c = copy.deepcopy(base)
        for key, v in values.items():
            if key not in tokens:
                tokens[key] = check_key(chk, key)
            set_key(chk, c, key, tokens[key], v)
        out.append(Point(i, values, c))
    return out


def kinds_of(pf) -> dict:
    """Per body, per region with conditions, the kind of each component:
    'displacement', 'force' or 'traction' (mesh independent)."""
    out = {}
    for b in pf.bodies:
        regions = {}
        for region, items in b.boundary_conditions.items():
            k = ["traction"] * 3
            for bc in items:
                if isinstance(bc, Pressure):
                    continue
                for c in range(3):
                    if bc.value[c] is not None and isinstance(bc, (Displacement, Force)):
                        k[c] = "displacement" if isinstance(bc, Displacement) else "force"
            regions[region] = tuple(k)
        out[b.name] = regions
    return out


def group_key(pf) -> str:
    """The key of the condensed operators a point needs: points with equal
    keys share them (meshes, materials, quadrature, kinds of condition per
    dof, contact surfaces and frame settings, linear solver options)."""
    h = hashlib.sha256()
    for b in pf.bodies:
        known_u, _ = b.boundary_data()
        h.update(b.model_key().encode())  # mesh, material, quadrature / elements
        h.update(np.ascontiguousarray(known_u).tobytes())
        h.update(repr((b.name, [c.dofs.tolist() for c in b.controls()])).encode())
    h.update(repr([getattr(pf.pair, f) for f in FRAME_FIELDS]).encode())
    h.update(repr(pf.options.linear).encode())
    return h.hexdigest()


def check_points(chk: Checker, path: pathlib.Path, points: list[Point]) -> None:
    """Read every point's problem file (the base file's errors name it, the
    point's name the point and its values); fills ``text``, ``group``,
    ``kinds``.  A point whose kinds of condition differ from the first's
    is refused: a sweep varies values."""
    base = path.parent.resolve()
    with tempfile.TemporaryDirectory(prefix="bemcontact-sweep-") as tmp:
        for p in points:
            _absolute_meshes(p.content, base)
            values = ", ".join(f"{k} = {_toml(v)}" for k, v in p.values.items())
            p.text = toml_text(p.content, f"bemcontact sweep of {path}: point {p.name}\n"
                               f"{values}")
            f = pathlib.Path(tmp) / path.name
            f.write_text(p.text, encoding="utf-8")
            try:
                with warnings.catch_warnings():  # the base file's load has warned once
                    warnings.simplefilter("ignore", BemcontactWarning)
                    pf = load_problem(f, check_overlap=False)
            except BemcontactError as exc:
                text = one_line(str(exc)).replace(os.fspath(f), "", 1).lstrip(": ")
                raise ConfigError(f"{path}: sweep point {p.index + 1} ({values}): {text}") from None
            p.group = group_key(pf)
            p.kinds = kinds_of(pf)
            if p.kinds != points[0].kinds:
                keys = [k for k in p.values if "boundary_conditions" in k] or list(p.values)
                chk.fail(keys[0], "changes the kind of a boundary condition (displacement, "
                         "traction or force per component) between points "
                         f"({_kind_change(points[0].kinds, p.kinds)}); a sweep varies values",
                         p.values[keys[0]])


def _kind_change(a: dict, b: dict) -> str:
    for body in a:
        for region in sorted(set(a[body]) | set(b.get(body, {}))):
            ka = a[body].get(region, ("traction",) * 3)
            kb = b.get(body, {}).get(region, ("traction",) * 3)
            for c in range(3):
                if ka[c] != kb[c]:
                    return f"{body}: region {region!r} component {'xyz'[c]} {ka[c]} -> {kb[c]}"
    return "the conditions differ"  # pragma: no cover


__all__ = ["Point", "check_key", "check_points", "group_key", "kinds_of", "parse_key",
           "parse_values", "points_of", "set_key", "toml_text"]

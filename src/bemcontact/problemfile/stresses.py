"""The ``[[output.stresses]]`` sections: one :class:`StressRequest` each.

Checked before the solve: the section's keys, exactly one probe, a known
body, and every point within the body's bounding box (a point outside it
cannot lie inside the body; whether a point inside the box lies inside the
body is checked on the solution, before anything is written)."""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..stresses import PROBE_KEYS, Box, Line, Plane, StressRequest
from . import schema
from .checks import Checker, a_type, suggest

_PROBES = tuple(PROBE_KEYS)


def stress_requests(check: Checker, value: Any, names: list[str], meshes: list) -> tuple:
    """The requests of ``output.stresses`` (a list of tables)."""
    key = schema.OUTPUT.key("stresses")
    if not isinstance(value, list):
        check.fail("output.stresses", f"must be an array of tables, not {a_type(value)}", value,
                   "write each as an [[output.stresses]] section")
    out, labels = [], set()
    for k, raw in enumerate(value):
        where = f"output.stresses[{k}]"
        t = check.table(where, raw, key)
        f = check.fields(where, t, key)
        body = f["body"]
        if body not in names:
            check.fail(f"{where}.body", "unknown body", body,
                       suggest(body, names) or f"the bodies are {', '.join(names)}")
        given = [p for p in _PROBES if p in t]
        if len(given) != 1:
            check.fail(where, "give exactly one of " + ", ".join(_PROBES)
                       + (f" (given: {', '.join(given)})" if given else ""), raw)
        kind = given[0]
        pw = f"{where}.{kind}"
        pt = check.table(pw, t[kind], PROBE_KEYS[kind])
        pf = check.fields(pw, pt, PROBE_KEYS[kind])
        label = f.get("label", str(k + 1))
        try:
            probe = _probe(kind, pf)
            request = StressRequest(body, probe, label)
        except ConfigError as exc:
            field = exc.location.get("field")
            if field == "label":
                w, value = f"{where}.label", label
            else:
                w, value = (f"{pw}.{field}", pt[field]) if field in pt else (pw, pt)
            check.fail(w, _what(str(exc)), value)
        if (body, label) in labels:
            check.fail(f"{where}.label", f"is used twice for body {body!r} (it names the files)",
                       label, "give each section its own label")
        labels.add((body, label))
        _inside_box(check, pw, probe, meshes[names.index(body)], body)
        out.append(request)
    return tuple(out)


def _what(message: str) -> str:
    """A probe's or request's message as the 'what' of a field error: without
    its owner's prefix (``line: ``, ``stresses: ``) and its own ``, got ...``
    (the field error says what it got)."""
    text = re.sub(r"^(line|plane|box|stresses): ", "", message)
    return re.sub(r", got .*$", "", text).rstrip(".")


def _pair(v) -> tuple:
    return tuple(v) if isinstance(v, list) else (v, v)


def _probe(kind: str, f: dict):
    if kind == "line":
        return Line(f["from"], f["to"], f["points"])
    if kind == "plane":
        return Plane(f["origin"], f["normal"], _pair(f["size"]), _pair(f["points"]),
                     f.get("u_axis"))
    pts = f["points"]
    if not isinstance(pts, list):  # one count: 1 along an axis whose bounds coincide
        pts = [1 if a == b else pts for a, b in zip(f["lower"], f["upper"])]
    return Box(f["lower"], f["upper"], tuple(pts))


def _inside_box(check: Checker, where: str, probe, mesh, body: str) -> None:
    lo, hi = mesh.nodes.min(axis=0), mesh.nodes.max(axis=0)
    tol = 1e-9 * float(np.max(hi - lo))
    X = probe.locations()
    out = np.flatnonzero(np.any((X < lo - tol) | (X > hi + tol), axis=1))
    if out.size:
        i = int(out[0])
        check.fail(where, f"point {i} at {np.round(X[i], 9).tolist()} lies outside body "
                   f"{body!r} (its bounding box is {np.round(lo, 9).tolist()} to "
                   f"{np.round(hi, 9).tolist()})", np.round(X[i], 9).tolist())


__all__ = ["stress_requests"]

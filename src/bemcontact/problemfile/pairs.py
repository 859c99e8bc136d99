"""The ``[contact]`` section of a problem file: one table (a two-body
problem) or an array of tables ``[[contact]]`` (an assembly), each a
:class:`~bemcontact.contact.ContactPair` between two named bodies."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..contact import ContactPair
from ..errors import BemcontactError
from ..mesh import SurfaceMesh
from . import schema
from .checks import Checker, suggest


@dataclass(frozen=True)
class PairSpec:
    """One checked pair: ``where`` its field path (``contact`` or
    ``contact[k]``), ``order`` the indices of its two bodies in the
    ``[[body]]`` array, ``pair`` the ContactPair (naming its bodies)."""

    where: str
    order: tuple[int, int]
    pair: ContactPair

    def surface_where(self, side: int) -> str:
        return f"{self.where}.surfaces[{side}]"


def read_pairs(chk: Checker, value: Any, names: list[str],
               meshes: list[SurfaceMesh]) -> list[PairSpec]:
    """The pairs of ``value`` (the ``contact`` entry of the file), checked
    against the bodies ``names`` and their ``meshes``; every body in a pair,
    no pair twice."""
    if isinstance(value, list):
        if not value or not all(isinstance(v, dict) for v in value):
            chk.fail("contact", "must be a table or an array of tables", value,
                     "write each contact pair as a [[contact]] section")
        specs = [_pair(chk, f"contact[{k}]", v, names, meshes, len(value))
                 for k, v in enumerate(value)]
    else:
        specs = [_pair(chk, "contact", value, names, meshes, 1)]
    seen: dict[frozenset, str] = {}
    for s in specs:
        key = frozenset({(s.order[0], s.pair.surface1), (s.order[1], s.pair.surface2)})
        if key in seen:
            chk.fail(s.where, f"the same two surfaces as {seen[key]}", list(s.pair.bodies),
                     "give each pair once")
        seen[key] = s.where
    used = {i for s in specs for i in s.order}
    for i, n in enumerate(names):
        if i not in used:
            chk.fail(f"body[{i}]", "is in no contact pair", n,
                     "add a [[contact]] section for it or remove the body")
    return specs


def _pair(chk: Checker, where: str, value: Any, names: list[str], meshes: list[SurfaceMesh],
          count: int) -> PairSpec:
    key = schema.CONTACT
    t = chk.table(where, value, key)
    if "bodies" not in t and len(names) > 2:
        chk.fail(f"{where}.bodies", "is needed with more than two bodies", None,
                 f"name the pair's two bodies, e.g. bodies = {names[:2]!r}".replace("'", '"'))
    bodies = chk.value(f"{where}.bodies", t.get("bodies", list(names)), key.key("bodies"))
    order = []
    for k, b in enumerate(bodies):
        if b not in names:
            chk.fail(
                f"{where}.bodies[{k}]", f"no body of that name (bodies: {', '.join(names)})",
                b, suggest(b, names),
            )
        order.append(names.index(b))
    if order[0] == order[1]:
        chk.fail(f"{where}.bodies", "the two contact bodies must differ", bodies)
    surfaces = chk.value(f"{where}.surfaces", t["surfaces"], key.key("surfaces"))
    for k, s in enumerate(surfaces):
        regions = meshes[order[k]].region_names
        if s not in regions:
            chk.fail(
                f"{where}.surfaces[{k}]", f"body {bodies[k]!r} has no region {s!r} (its "
                f"regions: {', '.join(regions)})", s, suggest(s, regions),
            )
    f = chk.fields(where, t, key)
    on = f["frame_on"]
    choices = ("auto", "between", "coarser", *bodies)
    if on not in choices:
        chk.fail(f"{where}.frame_on", f"must be one of {', '.join(choices)}", on,
                 suggest(on, choices))
    frame_on = on if on in ("auto", "between", "coarser") else f"body{bodies.index(on) + 1}"
    try:
        pair = ContactPair(surfaces[0], surfaces[1],
                           friction_coefficient=f["friction_coefficient"], frame=f["frame"],
                           search_distance=f.get("search_distance"), frame_on=frame_on,
                           relative_displacement=f["relative_displacement"],
                           penalty=f.get("penalty"), method=f["method"],
                           grid_size=f.get("grid_size"), bodies=(bodies[0], bodies[1]))
    except BemcontactError as exc:  # pragma: no cover - checked above
        chk.wrap(where, exc, value)
    return PairSpec(where, (order[0], order[1]), pair)


__all__ = ["PairSpec", "read_pairs"]

"""An assembly of bodies and contact pairs, checked: every body a body of the
seam (:class:`~bemcontact.contact.flexibility.Body`) with its own name, every
pair naming two of them and two of their regions that carry no boundary
condition, no pair twice, every body in a pair."""

from __future__ import annotations

import difflib

from ..errors import ConfigError
from .flexibility import Body
from .pair import ContactPair


def _sequence(name: str, value) -> list:
    if value is None or isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise ConfigError(f"{name} must be a list, got {value!r}")
    return list(value)


# --------------------------------------------------------------------------- problem


def checked_assembly(body1, body2, pair, bodies, pairs) -> tuple[tuple, tuple, tuple]:
    """(bodies, pairs, links) of a :class:`~bemcontact.contact.ContactProblem`
    given ``body1, body2, pair`` or ``bodies=, pairs=`` (see its
    docstring); ``links[p]`` the body indices of pair p."""
    if bodies is not None or pairs is not None:
        if body1 is not None or body2 is not None or pair is not None:
            raise ConfigError(
                "give either body1, body2 and pair, or bodies= and pairs=, not both")
        bodies, pairs = _sequence("bodies", bodies), _sequence("pairs", pairs)
        named = True
    else:
        for i, b in enumerate((body1, body2)):
            if not isinstance(b, Body):
                raise ConfigError(f"body{i + 1} must be an ElasticBody (or a Body), got "
                                  f"{type(b).__name__}")
        bodies, pairs, named = [body1, body2], [pair], False
    for i, b in enumerate(bodies):
        if not isinstance(b, Body):
            raise ConfigError(f"bodies[{i}] must be an ElasticBody (or a Body), got "
                              f"{type(b).__name__}")
    for i, p in enumerate(pairs):
        if not isinstance(p, ContactPair):
            what = "pair" if not named else f"pairs[{i}]"
            raise ConfigError(f"{what} must be a ContactPair, got {type(p).__name__}")
    names = [b.name for b in bodies]
    if len(bodies) < 2:
        raise ConfigError(f"an assembly needs at least two bodies, got {len(bodies)}")
    if not pairs:
        raise ConfigError("an assembly needs at least one contact pair (pairs=[])")
    for i, n in enumerate(names):
        if n in names[:i]:
            raise ConfigError(f"two bodies have the same name {n!r}; name them apart")
    bodies, pairs = tuple(bodies), tuple(pairs)
    links = tuple(_link(i, p, names, named) for i, p in enumerate(pairs))
    _check_surfaces(bodies, pairs, links)
    return bodies, pairs, links


def _link(i: int, p: ContactPair, names: list[str], named: bool) -> tuple[int, int]:
    """The body indices of pair ``i`` (checked)."""
    if p.bodies is None:
        if named:
            raise ConfigError(
                f"pairs[{i}] ({p.label}): name its two bodies (ContactPair.bodies); "
                f"the bodies are {names}")
        return (0, 1)
    for b in p.bodies:
        if b not in names:
            close = difflib.get_close_matches(b, names, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ConfigError(
                f"{'pairs[%d]' % i if named else 'pair'} ({p.label}): unknown body {b!r}"
                f"{hint}; the bodies are {names}")
    link = (names.index(p.bodies[0]), names.index(p.bodies[1]))
    if not named and link != (0, 1):
        raise ConfigError(
            f"pair.bodies is {list(p.bodies)}; it must name body 1 and body 2, "
            f"{names[:2]}, in this order")
    return link

def _check_surfaces(bodies, pairs, links) -> None:
    """Every contact surface a region of its body without a boundary
    condition; no pair twice; every body in a pair."""
    seen: dict[frozenset, int] = {}
    for i, (p, link) in enumerate(zip(pairs, links)):
        where = f"pairs[{i}] ({p.label})" if len(pairs) > 1 else "pair"
        for b, s in zip((bodies[a] for a in link), (p.surface1, p.surface2)):
            if s not in b.region_names:
                raise ConfigError(
                    f"{where}: {b.name}: unknown contact surface {s!r}; the mesh has regions "
                    f"{list(b.region_names)}"
                )
            if s in b.boundary_conditions:
                raise ConfigError(
                    f"{b.name}: the contact surface {s!r} also has a boundary condition; "
                    "remove it"
                )
        key = frozenset({(link[0], p.surface1), (link[1], p.surface2)})
        if key in seen:
            raise ConfigError(
                f"{where}: the same surfaces as pairs[{seen[key]}] "
                f"({pairs[seen[key]].label}); give each pair once")
        seen[key] = i
    used = {a for link in links for a in link}
    for a, b in enumerate(bodies):
        if a not in used:
            raise ConfigError(
                f"body {b.name!r} is in no contact pair; add its pair, or solve it on its "
                "own (ElasticBody.solve)")

def contact_surfaces(pairs, links, a: int) -> list[str]:
    """The contact surfaces of body ``a`` (in the order of its pairs)."""
    out = []
    for p, link in zip(pairs, links):
        for side, b in enumerate(link):
            s = (p.surface1, p.surface2)[side]
            if b == a and s not in out:
                out.append(s)
    return out


__all__ = ["checked_assembly", "contact_surfaces"]

"""A loading history: its steps (:class:`LoadStep`) and the states they
reach, checked against the bodies (the same kind of condition per component
throughout, none on a contact surface)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..settings import Key, check_settings, setting
from .rolling import Rolling


@dataclass(frozen=True)
class LoadStep:
    """One state of a loading history.

    Attributes
    ----------
    conditions:
        Body name -> region -> boundary condition(s) that *change* at this
        step; every other region keeps its condition of the previous state
        (the first step starts from the bodies' own conditions).  A step may
        change values only, not the kind of condition of a component
        (displacement, traction or force): to apply a tangential force later,
        give that component ``Force`` with value 0 from the start.
    increments:
        The step is reached in this many equal increments, each a linear
        interpolation between the previous state and this one (friction is
        path dependent: use several for a path that matters).
    label:
        Name used in messages and results.
    rolling:
        A :class:`~bemcontact.contact.rolling.Rolling`: the step rolls the
        bodies (steady state, or transient by its rolled distance per
        increment); None (the default): they are pressed and shifted only.

    The history starts unloaded; slip is measured from the start of each
    increment, so a stuck point is one with no new slip in it.
    """

    conditions: Any = field(default_factory=dict)
    increments: int = setting(Key(
        "increments", "integer", "the step is reached in this many linear increments from "
        "the previous state", default=1, lo=1))
    label: str = setting(Key(
        "label", "string", "the step's name in messages and summary.json", default=""))
    rolling: Rolling | None = None

    def __post_init__(self) -> None:
        check_settings(self)
        if self.rolling is not None and not isinstance(self.rolling, Rolling):
            raise ConfigError(f"LoadStep.rolling must be a Rolling or None, got "
                              f"{type(self.rolling).__name__}")
        if not isinstance(self.conditions, Mapping) or not all(
            isinstance(k, str) and isinstance(c, Mapping) for k, c in self.conditions.items()
        ):
            raise ConfigError(
                "LoadStep.conditions must map body names to {region: condition(s)}, got "
                f"{self.conditions!r}"
            )


_KIND_NAMES = ("traction", "displacement", "force")


def checked_states(bodies, surfaces, steps) -> list[list[dict]]:
    """The boundary-condition state reached at each of ``steps`` (a
    sequence of :class:`LoadStep`), per body of ``bodies`` (checked: known
    bodies and regions, no condition on a contact surface, the same kind of
    condition per component throughout); ``surfaces[a]`` the contact
    surfaces of body a.  An error carries its step index in ``location``."""
    names = [b.name for b in bodies]
    current = [dict(b.boundary_conditions) for b in bodies]
    base = [b.condition_kinds(c) for b, c in zip(bodies, current)]
    out = []
    for i, step in enumerate(steps):
        try:
            if not isinstance(step, LoadStep):
                raise ConfigError(
                    f"steps[{i}] must be a LoadStep, got {type(step).__name__}")
            where = f"step {i + 1}{f' ({step.label})' if step.label else ''}: "
            current = [dict(c) for c in current]
            for name, changes in step.conditions.items():
                if name not in names:
                    raise ConfigError(f"{where}unknown body {name!r}; the bodies are {names}")
                a = names.index(name)
                body = bodies[a]
                checked = body.checked_conditions(changes, where=where)
                for s_ in surfaces[a]:
                    if s_ in checked:
                        raise ConfigError(
                            f"{where}{name}: region {s_!r} is "
                            f"{'the' if len(surfaces[a]) == 1 else 'a'} contact surface; it "
                            "cannot carry a boundary condition"
                        )
                current[a].update(checked)
                kinds = body.condition_kinds(current[a])
                diff = np.flatnonzero(kinds != base[a])
                if diff.size:
                    dof = int(diff[0])
                    region = body.region_names[int(body.trace.region[dof // 3])]
                    raise ConfigError(
                        f"{where}{name}: region {region!r} component {'xyz'[dof % 3]} "
                        f"changes from {_KIND_NAMES[base[a][dof]]} to "
                        f"{_KIND_NAMES[kinds[dof]]}; a step may change values, not kinds "
                        "(give the component its later kind from the start, e.g. Force "
                        "with value 0)"
                    )
        except ConfigError as exc:  # where, as data: the step
            exc.location.setdefault("step", i)
            raise
        out.append(current)
    return out


__all__ = ["LoadStep", "checked_states"]

"""A ``[[step]]`` section's ``rolling`` table: its
:class:`~bemcontact.contact.rolling.Rolling`, checked when the file is read
(keys, types, the mode's distance); its direction against the contact plane
and the pair's friction are checked before the solve, when the plane is
known (:func:`~bemcontact.multiscale.pair.solve_on_grid`)."""

from __future__ import annotations

from typing import Any

from ..contact.rolling import Rolling
from ..errors import ConfigError
from . import schema
from .checks import Checker


def step_rolling(check: Checker, where: str, value: Any) -> Rolling | None:
    """The :class:`Rolling` of the table ``value`` at ``where``
    (``step[k].rolling``; None when not given); a bad value is a one-line
    error naming its key."""
    if value is None:
        return None
    key = schema.STEP.key("rolling")
    fields = check.fields(where, check.table(where, value, key), key)
    try:
        return Rolling(**fields)
    except ConfigError as exc:
        name = exc.location.get("field", "rolling").removeprefix("rolling").lstrip(".")
        text = str(exc).removeprefix("Rolling: ")
        check.fail(f"{where}.{name}" if name else where, text.rstrip("."),
                   value.get(name, value) if name else value)


__all__ = ["step_rolling"]

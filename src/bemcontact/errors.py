"""The one exception hierarchy of bemcontact.

Every error that bemcontact raises on purpose is a :class:`BemcontactError`.
The subclasses also derive from the built-in exception a caller would expect
(``ValueError`` for bad input, ``RuntimeError`` for a solve that failed), so
``except ValueError`` keeps working.
"""

from __future__ import annotations

from typing import Any


class BemcontactError(Exception):
    """Base class of every error raised by bemcontact.

    ``location``: where the error lies, as data (e.g. ``{"step": 2}``,
    ``{"pair": 1}``, ``{"body": "sphere"}``; indices from 0), for callers
    that map it to their own terms (the problem-file reader to its fields);
    ``detail``: the message without the location written into it."""

    def __init__(self, message: str = "", *args: Any, location: dict | None = None,
                 detail: str | None = None) -> None:
        super().__init__(message, *args)
        self.location: dict = dict(location or {})
        self.detail: str = message if detail is None else detail


class MeshError(BemcontactError, ValueError):
    """A mesh is malformed: non-finite nodes, degenerate or inverted elements,
    an open surface, unknown element types or region names."""


class MaterialError(BemcontactError, ValueError):
    """A material constant is out of its physical range."""


class ConfigError(BemcontactError, ValueError):
    """Boundary conditions, options or a problem description are inconsistent."""


class ConvergenceError(BemcontactError, RuntimeError):
    """An iterative solve did not converge; ``result`` holds what was reached
    (including the residual history)."""

    def __init__(self, message: str, result: Any = None) -> None:
        super().__init__(message)
        self.result = result


class BemcontactWarning(UserWarning):
    """Base class of the warnings bemcontact issues; each message is one
    self-contained line (the ``bemcontact`` command prints it as
    ``bemcontact: warning: <message>``)."""


class AccuracyWarning(BemcontactWarning):
    """A result is less accurate than requested (e.g. an H-matrix tolerance
    too loose for the requested solve accuracy); the message says by how much
    and what to change."""


class ResourceLimitWarning(BemcontactWarning):
    """A solve's estimated memory comes close to what the machine has
    available (it may be slow or be killed)."""


class OptionalDependencyWarning(BemcontactWarning):
    """An optional dependency is not installed, so an output that was on by
    default is skipped (e.g. figures without matplotlib); the message names
    the install command."""


__all__ = [
    "BemcontactError",
    "MeshError",
    "MaterialError",
    "ConfigError",
    "ConvergenceError",
    "BemcontactWarning",
    "AccuracyWarning",
    "OptionalDependencyWarning",
    "ResourceLimitWarning",
]

"""How a pair's ``method`` is followed: the contact grid for
``"multiscale"``; for ``"auto"`` the full path when the bodies' meshes
already resolve the contact (at least :data:`RESOLVED` elements per contact
half-width, found by the grid's sizing pass: the problem is solved as
meshed), else the grid where it applies (its applicability checks:
:func:`~bemcontact.multiscale.pair.applicability`), else the full path (and
always for a finite-element body); the choice said in one line."""

from __future__ import annotations

from ..bem import ElasticBody
from ..contact import LoadStep, SolverOptions
from ..errors import ConfigError, ConvergenceError
from ..multiscale.pair import GridOptions, applicability, solve_on_grid

#: ``"auto"`` solves a contact as meshed (the full path) when both bodies have
#: at least this many elements per contact half-width at the contact.
RESOLVED = 4.0


def on_grid(problem, steps, method: str, options: SolverOptions):
    """(the :class:`~bemcontact.multiscale.pair.GridResult`, or None when
    ``method`` is "auto" and the grid does not apply; the line that says
    which path solved it and why) for the two-body ``problem`` (a
    :class:`~bemcontact.contact.ContactProblem`) and its load ``steps``."""
    fem = [b.name for b in problem.bodies if not isinstance(b, ElasticBody)]
    if fem:  # the reader refuses "multiscale" for them
        return None, (f"contact.method = \"auto\": the full path ({fem[0]} is a finite-element "
                      "body; the contact grid takes BEM bodies)")
    steps = steps or (LoadStep(increments=options.load_steps),)
    grid = GridOptions(grid_size=problem.pairs[0].grid_size,
                       resolved=RESOLVED if method == "auto" else None)
    try:
        result = solve_on_grid(problem, steps, grid, solver=options)
    except (ConfigError, ConvergenceError) as exc:
        if method == "multiscale":
            raise
        why = str(exc).removeprefix("method = \"multiscale\": ")
        return None, f"contact.method = \"auto\": the full path ({why})"
    app = applicability(result, problem)
    if method == "auto" and app["reason"]:
        return None, f"contact.method = \"auto\": the full path ({app['reason']})"
    result.method = {"requested": method,
                     "reason": app["reason"] or "every applicability check holds",
                     "applicability": app["checks"]}
    note = (f"contact.method = \"{method}\": the contact grid "
            f"({result.grid.nx} x {result.grid.ny} cells)")
    if app["reason"]:
        note += f"; warning: {app['reason']}, the full path would be more accurate"
    return result, note


__all__ = ["RESOLVED", "on_grid"]

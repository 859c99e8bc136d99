"""How a pair's ``method`` is followed: the contact grid for
``"multiscale"``; for ``"auto"`` the full path when the bodies' meshes
already resolve the contact (at least :data:`RESOLVED` elements per contact
half-width, found by the grid's sizing pass: the problem is solved as
meshed), else the grid where it applies (its applicability checks:
:func:`~bemcontact.multiscale.pair.applicability`), else the full path (and
always for a finite-element body); the choice said in one line.

An assembly follows one method for all its pairs (:func:`method_of`): one
grid per pair, coupled through the bodies they share
(:mod:`bemcontact.multiscale.assembly`), or the full path."""

from __future__ import annotations

from ..bem import ElasticBody
from ..contact import LoadStep, SolverOptions
from ..errors import ConfigError, ConvergenceError
from ..multiscale.assembly import assembly_applicability, solve_assembly_on_grid
from ..multiscale.pair import GridOptions, applicability, solve_on_grid

#: ``"auto"`` solves a contact as meshed (the full path) when both bodies have
#: at least this many elements per contact half-width at the contact.
RESOLVED = 4.0


def method_of(pairs) -> str:
    """The method of a problem's pairs (each with a ``method``): "full" when
    any pair asks for it (the grid solves all pairs or none), else
    "multiscale" when any pair asks for it, else "auto"."""
    methods = {p.method for p in pairs}
    return next(m for m in ("full", "multiscale", "auto") if m in methods)


def on_grid(problem, steps, method: str, options: SolverOptions):
    """(the :class:`~bemcontact.multiscale.pair.GridResult` (an assembly:
    :class:`~bemcontact.multiscale.assembly.GridAssemblyResult`), or None
    when ``method`` is "auto" and the grid does not apply; the line that
    says which path solved it and why) for ``problem`` (a
    :class:`~bemcontact.contact.ContactProblem`) and its load ``steps``."""
    fem = [b.name for b in problem.bodies if not isinstance(b, ElasticBody)]
    if fem:  # the reader refuses "multiscale" for them
        return None, (f"contact.method = \"auto\": the full path ({fem[0]} is a finite-element "
                      "body; the contact grid takes BEM bodies)")
    steps = steps or (LoadStep(increments=options.load_steps),)
    several = len(problem.pairs) > 1
    grid = GridOptions(grid_size=None if several else problem.pairs[0].grid_size,
                       resolved=RESOLVED if method == "auto" else None)
    try:
        if several:
            result = solve_assembly_on_grid(problem, steps, grid, solver=options)
        else:
            result = solve_on_grid(problem, steps, grid, solver=options)
    except (ConfigError, ConvergenceError) as exc:
        if method == "multiscale":
            raise
        why = str(exc).removeprefix("method = \"multiscale\": ")
        return None, f"contact.method = \"auto\": the full path ({why})"
    app = (assembly_applicability if several else applicability)(result, problem)
    if method == "auto" and app["reason"]:
        return None, f"contact.method = \"auto\": the full path ({app['reason']})"
    result.method = {"requested": method,
                     "reason": app["reason"] or "every applicability check holds",
                     "applicability": app["checks"]}
    if several:
        note = (f"contact.method = \"{method}\": a contact grid per pair ("
                + ", ".join(f"{r.grid.nx} x {r.grid.ny}" for r in result.pairs)
                + f" cells), coupled through their shared bodies in {len(result.sweeps)} "
                "sweep(s)")
    else:
        note = (f"contact.method = \"{method}\": the contact grid "
                f"({result.grid.nx} x {result.grid.ny} cells)")
    if app["reason"]:
        note += f"; warning: {app['reason']}, the full path would be more accurate"
    return result, note


__all__ = ["RESOLVED", "method_of", "on_grid"]

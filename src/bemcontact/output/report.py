"""What ``bemcontact run`` prints once a solve has converged (one place
for the lines of a full and of a multiscale result)."""

from __future__ import annotations

import pathlib

import numpy as np


def force_text(value: float, floor: float, unit: str) -> str:
    """A force for the summary: 0 with the resolution when it is below it."""
    if abs(value) <= floor:
        return f"0{unit} (below the solve's resolution, {floor:.1g}{unit})"
    return f"{value:.6g}{unit}"


def counts(c: dict[str, int]) -> str:
    """``3 open, 5 stick, 2 slip``."""
    return ", ".join(f"{v} {k}" for k, v in c.items())


def run_report(problem, result, out: pathlib.Path, files) -> str:
    """What ``bemcontact run`` prints after a solve: the iterations and
    time, how the method was chosen, the forces and contact states of each
    pair (of the grid for a multiscale solve) and the files written
    (``problem``: the :class:`~bemcontact.problemfile.ProblemFile`)."""
    force = problem.units.get("force", "")
    unit = f" {force}" if force else ""
    note = getattr(problem, "method_note", "")
    from ..multiscale.assembly import GridAssemblyResult
    from ..multiscale.pair import GridResult

    if isinstance(result, (GridResult, GridAssemblyResult)):  # solved on the contact grid
        from .grid import report

        return "\n".join([f"{problem.path}: " + report(result, note, unit, force_text,
                                                         problem.options.tolerance),
                           f"results in {out}: " + ", ".join(f.name for f in files)])
    steps = len(result.history)
    increments = len(result.steps)
    # forces below what the Newton tolerance resolves are round-off, not results
    floor = 10.0 * problem.options.tolerance * max(
        float(np.linalg.norm(pr.contact_force)) for pr in result.pairs or [result])
    lines = [
        f"{problem.path}: converged in {result.newton_iterations} Newton iteration(s), "
        f"{steps} load step(s) in {increments} increment(s), "
        f"{result.timings.get('total', 0.0):.2f} s",
    ]
    if note:
        lines.append(f"  {note}")
    several = len(result.pairs) > 1
    for pr in result.pairs or [result]:
        pad = "  " if several else ""
        if several:
            lines.append(f"  pair {pr.label}:")
        lines += [
            f"  {pad}normal force      {force_text(pr.normal_force, floor, unit)}",
            f"  {pad}tangential force  {force_text(pr.tangential_force, floor, unit)}",
        ]
        for iface in pr.interfaces:
            lines.append(f"  {pad}{iface.body} ({iface.surface}, {iface.state.size} nodes): "
                         f"{counts(iface.counts())}")
        lines.append(f"  {pad}frame ({pr.frame.state.size} nodes): {counts(pr.frame.counts())}")
    lines.append(f"results in {out}: " + ", ".join(f.name for f in files))
    return "\n".join(lines)


__all__ = ["counts", "force_text", "run_report"]

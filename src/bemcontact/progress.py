"""Progress of a contact solve: events, a plain line printer and a live
display (rich).

:meth:`ContactProblem.solve <bemcontact.contact.ContactProblem.solve>` calls
its ``progress`` callable with a :class:`ProgressEvent` when a stage starts
and ends (``frame``, then ``assembly`` and ``condensation`` per body), when a
load increment starts, and after each Newton iteration.  Any callable taking
one event works; two are provided:

* :func:`print_lines`: one line per event on stderr (what
  ``SolverOptions(progress=True)`` does);
* :class:`LiveProgress`: a rich live display (spinners for the stages, a bar
  over the load increments with the current residual), used by ``bemcontact
  run`` when stderr is a terminal.
"""

from __future__ import annotations

import sys
import time
import unicodedata
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TextIO


@dataclass(frozen=True)
class ProgressEvent:
    """One progress report.

    kind: ``"start"`` or ``"end"`` of a stage, ``"increment"`` (a load
        increment starts) or ``"iteration"`` (a Newton iteration ended).
    stage: ``"frame"``, ``"assembly"``, ``"condensation"`` or ``"newton"``.
    message: what is being done, e.g. ``"assembly lower: 1,538 nodes"``.
    index, total: the increment's number (1-based) and the number of
        increments of the whole history (``"increment"`` and
        ``"iteration"``); the iteration number in ``iteration``.
    iteration: Newton iteration number (0: the starting point).
    residual: scaled residual after that iteration.
    seconds: duration of the stage (``"end"``).
    """

    kind: str
    stage: str
    message: str
    index: int = 0
    total: int = 0
    iteration: int = 0
    residual: float = float("nan")
    seconds: float = 0.0


Reporter = Callable[[ProgressEvent], Any]


#: Longest line of text printed to the terminal (a 200,000-character key
#: name made a 200 kB error line).
MAX_LINE = 1000


def _shown(ch: str) -> str:
    # control and format characters (escape sequences, bidirectional
    # overrides) as Python escapes; everything else as it is
    if ch == "\t" or unicodedata.category(ch) not in ("Cc", "Cf", "Cs"):
        return ch
    return ascii(ch)[1:-1]


def terminal_text(text: object, max_line: int = MAX_LINE) -> str:
    """``text`` safe to print on a terminal: control and format characters
    (an escape sequence in a title or region name could clear the screen)
    shown as escapes (``\\x1b``, ``\\u202e``), and every line cut after
    ``max_line`` characters with a note of how many more there were.
    Newlines stay."""
    out = []
    for line in str(text).split("\n"):
        more = len(line) - max_line
        line = "".join(_shown(c) for c in line[:max_line])
        if more > 0:
            line += f"... ({more} more characters)"
        out.append(line)
    return "\n".join(out)


def _markup(text: str) -> str:
    """A message for rich: terminal-safe, its square brackets not markup."""
    from rich.markup import escape

    return escape(terminal_text(text, 200))


def print_lines(event: ProgressEvent, stream: TextIO | None = None) -> None:
    """Print one line per event (stage ends, increments and iterations)."""
    out = sys.stderr if stream is None else stream
    if event.kind == "start":
        print(terminal_text(f"  {event.message} ..."), file=out)
    elif event.kind == "end":
        print(terminal_text(f"  {event.message}: {event.seconds:.2f} s"), file=out)
    elif event.kind == "increment":
        print(terminal_text(f"  {event.message}"), file=out)
    else:
        print(f"    iteration {event.iteration:3d}  residual {event.residual:.3e}", file=out)


class LiveProgress:
    """A rich live display of the events, on stderr unless a ``console`` is
    given; use as a context manager around the solve::

        with LiveProgress() as show:
            problem.contact_problem().solve(options, progress=show)

    Stages show as spinners that turn into their durations; the load
    increments as a bar with the step label, the Newton iteration and the
    residual.  The display is left on screen when it ends.
    """

    def __init__(self, console=None) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            SpinnerColumn,
            TextColumn,
            TimeElapsedColumn,
        )

        self._console = console if console is not None else Console(stderr=True)
        self._progress = Progress(
            SpinnerColumn(finished_text="[green]done"),
            TextColumn("{task.description}"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            console=self._console,
        )
        self._stages: dict[str, Any] = {}
        self._newton: Any = None
        self._increment = ""

    def __enter__(self) -> LiveProgress:
        self._progress.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._progress.stop()

    def __call__(self, event: ProgressEvent) -> None:
        p = self._progress
        if event.stage == "newton" and event.kind in ("increment", "iteration", "end"):
            if self._newton is None:
                self._newton = p.add_task("load increments", total=max(event.total, 1))
            if event.kind == "increment":
                self._increment = _markup(event.message)
                p.update(self._newton, completed=event.index - 1, description=self._increment)
            elif event.kind == "iteration":
                p.update(
                    self._newton,
                    description=f"{self._increment}: iteration {event.iteration}, residual "
                    f"{event.residual:.2e}",
                )
            else:
                p.update(self._newton, completed=event.total,
                         description=f"{_markup(event.message)} ({event.seconds:.2f} s)")
        elif event.kind == "start":
            self._stages[event.message] = p.add_task(_markup(event.message), total=1)
        elif event.kind == "end":
            task = self._stages.pop(event.message, None)
            if task is None:
                task = p.add_task(event.message, total=1)
            p.update(task, completed=1, description=f"{event.message} ({event.seconds:.2f} s)")


class Stopwatch:
    """Emit the ``start`` and ``end`` events of one stage around a block."""

    def __init__(self, report: Reporter | None, stage: str, message: str) -> None:
        self.report, self.stage, self.message = report, stage, message

    def __enter__(self) -> Stopwatch:
        self.t0 = time.perf_counter()
        if self.report is not None:
            self.report(ProgressEvent("start", self.stage, self.message))
        return self

    def __exit__(self, exc_type, *rest: object) -> None:
        if self.report is not None and exc_type is None:
            self.report(ProgressEvent("end", self.stage, self.message,
                                      seconds=time.perf_counter() - self.t0))


__all__ = ["ProgressEvent", "Reporter", "print_lines", "LiveProgress", "Stopwatch", "MAX_LINE",
           "terminal_text"]

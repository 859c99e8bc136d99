"""Progress events of a contact solve, the line printer, the live (rich)
display and the command line's --progress modes."""

from __future__ import annotations

import io as stdio

import pytest

import bemcontact as bc
from bemcontact.cli import main
from bemcontact.progress import LiveProgress, ProgressEvent, print_lines

from .test_cli import problem


def two_steps():
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (1, 1, 1), 2), bc.LinearElastic(1e4, 0.3), {"zmin": bc.Fixed()},
        name="lower",
    )
    upper = bc.ElasticBody(
        bc.box((0, 0, 1), (1, 1, 2), 2), bc.LinearElastic(2e4, 0.3),
        {"zmax": bc.Displacement((0.0, 0.0, -0.01))}, name="upper",
    )
    steps = [
        bc.LoadStep({}, 1, "P"),
        bc.LoadStep({"upper": {"zmax": [bc.Displacement((0.002, 0.0, -0.01))]}}, 2, "shift"),
    ]
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.2)), steps


@pytest.fixture(scope="module")
def events():
    cp, steps = two_steps()
    seen: list[ProgressEvent] = []
    result = cp.solve(bc.SolverOptions(threads=1), steps=steps, progress=seen.append)
    return seen, result


def test_events_cover_every_stage_increment_and_iteration(events):
    seen, result = events
    stages = [(e.kind, e.stage) for e in seen if e.kind in ("start", "end")]
    assert stages == [
        ("start", "frame"), ("end", "frame"),
        ("start", "assembly"), ("end", "assembly"),
        ("start", "condensation"), ("end", "condensation"),
        ("start", "assembly"), ("end", "assembly"),
        ("start", "condensation"), ("end", "condensation"),
        ("end", "newton"),
    ]  # fmt: skip
    assert "assembly lower: 78 nodes, 13 on the contact surface" in seen[2].message
    incs = [e for e in seen if e.kind == "increment"]
    assert [(e.index, e.total) for e in incs] == [(1, 3), (2, 3), (3, 3)]
    assert [e.message for e in incs] == [
        "step 1/2 (P) increment 1/1", "step 2/2 (shift) increment 1/2",
        "step 2/2 (shift) increment 2/2",
    ]  # fmt: skip
    # the iteration events are the residual histories of the step records
    per_increment: list[list[float]] = []
    for e in seen:
        if e.kind == "increment":
            per_increment.append([])
        elif e.kind == "iteration":
            per_increment[-1].append(e.residual)
    assert per_increment == [list(r.residual_history) for r in result.steps]
    assert all(e.seconds >= 0 for e in seen)


def test_print_lines(events):
    seen, _ = events
    buf = stdio.StringIO()
    for e in seen:
        print_lines(e, buf)
    text = buf.getvalue()
    assert "  assembly lower: 78 nodes, 13 on the contact surface" in text and "condensation upper: " in text
    assert "  step 2/2 (shift) increment 2/2" in text
    assert text.count("iteration ") == sum(len(r.residual_history) for r in events[1].steps)


def test_live_display_renders_the_stages_and_the_increment_bar(events):
    from rich.console import Console

    seen, _ = events
    buf = stdio.StringIO()
    console = Console(file=buf, force_terminal=True, width=150, color_system=None)
    with LiveProgress(console) as show:
        for e in seen:
            show(e)
    text = buf.getvalue()
    assert "assembly lower: 78 nodes, 13 on the contact surface" in text
    assert "condensation upper (" in text
    assert "3 load increment(s)" in text and "3/3" in text


def test_progress_must_be_callable():
    cp, _ = two_steps()
    with pytest.raises(bc.ConfigError, match="progress must be callable"):
        cp.solve(progress="yes")


def test_cli_progress_modes(tmp_path, capsys):
    path = problem(tmp_path)
    assert main(["run", str(path), "--out", str(tmp_path / "a"), "--progress", "lines"]) == 0
    err = capsys.readouterr().err
    assert "assembly lower" in err and "iteration   0" in err
    # not a terminal (pytest captures stderr): auto shows nothing
    assert main(["run", str(path), "--out", str(tmp_path / "b")]) == 0
    assert capsys.readouterr().err == ""


def test_terminal_text_escapes_control_characters_and_caps_lines():
    """Escape sequences and bidirectional overrides are shown as escapes,
    tabs and newlines stay, and a line longer than MAX_LINE is cut with a
    count of what was left out."""
    from bemcontact.progress import MAX_LINE, terminal_text

    assert terminal_text("a\x1b[2Jb\u202ec\td\ne\x07") == "a\\x1b[2Jb\\u202ec\td\ne\\x07"
    assert terminal_text("Grenzfläche σ 接触") == "Grenzfläche σ 接触"
    long = terminal_text("x" * 200_000)
    assert long == "x" * MAX_LINE + f"... ({200_000 - MAX_LINE} more characters)"
    two = terminal_text("y" * 1500 + "\n" + "z").split("\n")
    assert len(two) == 2 and two[1] == "z" and two[0].endswith("(500 more characters)")


def test_printed_user_strings_are_escaped_and_capped(tmp_path, capsys):
    """A title holding escape sequences (they could clear the screen) is
    shown escaped by check; an unknown key 200,000 characters long gives
    one error line of about MAX_LINE characters, not 200 kB."""
    from bemcontact.progress import MAX_LINE

    p = problem(tmp_path)
    p.write_text('title = "\\u001b[2J\\u001b[31mred"\n' + p.read_text())
    assert main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\\x1b[2J\\x1b[31mred" in out
    p.write_text(p.read_text().replace("[contact]", "[contact]\n" + "k" * 200_000 + " = 1"))
    assert main(["check", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and MAX_LINE < len(err) < MAX_LINE + 100
    assert "more characters)" in err

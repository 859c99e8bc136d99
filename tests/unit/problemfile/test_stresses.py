"""``[[output.stresses]]``: read into requests, refused in one line before
the solve when wrong, and the run's stress files."""

from __future__ import annotations

import csv
import json

import meshio
import numpy as np
import pytest

import bemcontact as bc
from bemcontact.cli import main
from bemcontact.problemfile import load_problem
from bemcontact.stresses import Box, Line, Plane

from .test_reader import BASE, write

LINE = '\n[[output.stresses]]\nbody = "lower"\nline = { from = [1, 1, 1.9], to = [1, 1, 0.5], points = 8 }\n'
PLANE = ('\n[[output.stresses]]\nbody = "upper"\nlabel = "mid"\nplane = { origin = [1, 1, 3], '
         'normal = [0, 1, 0], size = [1.6, 1.2], points = [5, 4], u_axis = [1, 0, 0] }\n')
BOX = ('\n[[output.stresses]]\nbody = "lower"\nbox = { lower = [0.5, 0.5, 1], upper = [1.5, 1.5, 1], '
       'points = 3 }\n')


def test_sections_become_requests_in_order_with_their_labels(tmp_path):
    p = load_problem(write(tmp_path, BASE + LINE + PLANE + BOX), check_overlap=False)
    r = p.output.stresses
    assert [(q.body, q.label, q.kind) for q in r] == [
        ("lower", "1", "line"), ("upper", "mid", "plane"), ("lower", "3", "box")]
    assert isinstance(r[0].probe, Line) and r[0].probe.points == 8
    assert isinstance(r[1].probe, Plane) and r[1].probe.shape == (5, 4)
    assert isinstance(r[2].probe, Box) and r[2].probe.shape == (3, 3, 1)  # a slice: z = 1


@pytest.mark.parametrize("section, match", [
    ('body = "middle"\nline = { from = [1, 1, 1], to = [1, 1, 0.5] }',
     r"output\.stresses\[0\]\.body: unknown body.*'middle'"),
    ('body = "lower"', r"output\.stresses\[0\]: give exactly one of line, plane, box"),
    ('body = "lower"\nline = { from = [1, 1, 1], to = [1, 1, 0.5] }\n'
     'box = { lower = [0, 0, 0], upper = [1, 1, 1] }', r"give exactly one of .*given: line, box"),
    ('body = "lower"\nline = { from = [1, 1, 1], to = [1, 1, 5] }',
     r"output\.stresses\[0\]\.line: point \d+ at \[1\.0, 1\.0, [\d.]+\] lies outside body 'lower'"),
    ('body = "lower"\nline = { from = [1, 1, 1], to = [1, 1, 1] }',
     r"output\.stresses\[0\]\.line\.to: .*same point"),
    ('body = "lower"\nline = { from = [1, 1, 1], to = [1, 1, 0.5], points = 1 }',
     r"output\.stresses\[0\]\.line\.points: must be >= 2"),
    ('body = "lower"\nlabel = "a b"\nline = { from = [1, 1, 1], to = [1, 1, 0.5] }',
     r"output\.stresses\[0\]\.label: .*letters, digits"),
    ('body = "lower"\nplane = { origin = [1, 1, 1], normal = [0, 0, 0], size = 1 }',
     r"output\.stresses\[0\]\.plane\.normal: .*not be zero"),
    ('body = "lower"\nplane = { origin = [1, 1, 1], normal = [0, 0, 1], size = [1, 1, 1] }',
     r"output\.stresses\[0\]\.plane\.size: must have 2 values"),
    ('body = "lower"\nbox = { lower = [0, 0, 0], upper = [1, 1, 1], points = 200 }',
     r"output\.stresses\[0\]\.box\.points: .*more than 1,000,000"),
    ('body = "lower"\nlne = { from = [1, 1, 1], to = [1, 1, 0.5] }',
     r"output\.stresses\[0\]\.lne: unknown key.*did you mean 'line'"),
])
def test_bad_sections_are_one_line_errors_naming_the_field(tmp_path, section, match):
    path = write(tmp_path, BASE + "\n[[output.stresses]]\n" + section + "\n")
    with pytest.raises(bc.ConfigError, match=match) as e:
        load_problem(path, check_overlap=False)
    assert "\n" not in str(e.value) and str(e.value).startswith(str(path))


def test_a_label_used_twice_in_one_body_is_refused(tmp_path):
    path = write(tmp_path, BASE + LINE + LINE.replace('body = "lower"', 'body = "lower"\nlabel = "1"'))
    with pytest.raises(bc.ConfigError, match=r"output\.stresses\[1\]\.label: is used twice"):
        load_problem(path, check_overlap=False)


def test_run_writes_the_stress_files_and_their_maxima(tmp_path):
    """The CSV holds the result's own stresses at the probe's points (to the
    17 digits written), the VTU the same as point data, and summary.json's
    maxima are the CSV's largest von Mises and Tresca, at their points."""
    path = write(tmp_path, BASE + LINE + PLANE + '\n[output]\nfigures = false\nsteps = "last"\n')
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    problem = load_problem(path)
    result = problem.solve()
    for label, body, probe in (("1", "lower", problem.output.stresses[0].probe),
                               ("mid", "upper", problem.output.stresses[1].probe)):
        with open(out / f"stresses_{body}_{label}.csv") as f:
            rows = list(csv.reader(f))
        assert rows[0] == ["x", "y", "z", "sxx", "syy", "szz", "sxy", "syz", "sxz", "von_mises",
                           "tresca"]
        table = np.array(rows[1:], dtype=float)
        assert np.array_equal(table[:, :3], probe.locations())
        assert np.allclose(table[:, 3:9], result.stresses(body, probe.locations()), rtol=1e-12,
                           atol=1e-12 * np.abs(table[:, 3:9]).max())
        s = table[:, 3:9]
        vm = np.sqrt(0.5 * ((s[:, 0] - s[:, 1]) ** 2 + (s[:, 1] - s[:, 2]) ** 2
                            + (s[:, 2] - s[:, 0]) ** 2) + 3 * (s[:, 3:] ** 2).sum(axis=1))
        assert np.allclose(table[:, 9], vm, rtol=1e-12)
        mesh = meshio.read(out / f"stresses_{body}_{label}.vtu")
        assert np.allclose(mesh.point_data["von_mises"], table[:, 9], rtol=1e-12)
        assert mesh.point_data["stress"].shape == (len(table), 6)
        summary = json.loads((out / "summary.json").read_text())
        field = next(f for f in summary["stresses"]["fields"] if f["label"] == label)
        k = int(np.argmax(table[:, 9]))
        assert field["maximum"]["von_mises"]["value"] == pytest.approx(table[k, 9], rel=1e-12)
        assert field["maximum"]["von_mises"]["point"] == pytest.approx(table[k, :3].tolist())
        assert field["points"] == len(table) and len(field["steps"]) == 1


def test_a_point_on_the_surface_writes_nothing(tmp_path, capsys):
    """A line ending on the body's surface (inside its bounding box) is
    refused after the solve, before anything is written (exit 2, one line
    naming the section)."""
    path = write(tmp_path, BASE + '\n[[output.stresses]]\nbody = "lower"\n'
                 'line = { from = [1, 1, 1], to = [1, 1, 2] }\n')
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "output.stresses '1'" in err and "from the surface" in err
    assert not out.exists()


def test_a_bad_point_is_named_in_its_own_section(tmp_path, capsys):
    """Sections of one body are evaluated together; a point on the surface
    in the second is reported with that section's label and its own index."""
    path = write(tmp_path, BASE + LINE + '\n[[output.stresses]]\nbody = "lower"\nlabel = "top"\n'
                 'line = { from = [1, 1, 1], to = [1, 1, 2], points = 5 }\n')
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "output.stresses 'top' (line in 'lower'): point 4 at (1, 1, 2)" in err, err
    assert not out.exists()


def test_check_lists_the_stresses_asked_for(tmp_path, capsys):
    path = write(tmp_path, BASE + LINE + PLANE)
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "stresses: 1 (line in lower, 8 points); mid (plane in upper, 20 points)" in out
    assert "method = auto" in out


def test_slices_of_a_box_and_a_single_point_are_drawn_or_skipped(tmp_path):
    """A box one point thick along x or y is a plane: drawn as one; a box of
    one point has nothing to draw: its CSV and VTU only."""
    text = BASE + '\n[[output.stresses]]\nbody = "lower"\nlabel = "xz"\nbox = { lower = [0.5, 1, 0.5], upper = [1.5, 1, 1.5], points = 5 }\n'
    text += '\n[[output.stresses]]\nbody = "lower"\nlabel = "dot"\nbox = { lower = [1, 1, 1], upper = [1, 1, 1], points = 1 }\n'
    path = write(tmp_path, text + '\n[output]\nsteps = "last"\n')
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    written = json.loads((out / "summary.json").read_text())
    assert written["stresses"]["fields"][1]["points"] == 1
    assert (out / "stresses_lower_xz.png").is_file() and (out / "stresses_lower_xz.csv").is_file()
    assert not (out / "stresses_lower_dot.png").exists()
    assert (out / "stresses_lower_dot.csv").is_file() and (out / "stresses_lower_dot.vtu").is_file()


def test_a_bad_points_location_is_its_index_in_its_own_request(tmp_path):
    from bemcontact.stresses import StressRequest, evaluate_all

    result = load_problem(write(tmp_path, BASE), check_overlap=False).solve()
    ok = StressRequest("lower", Line((1, 1, 0.5), (1, 1, 1.5), 5), "ok")
    bad = StressRequest("lower", Line((1, 1, 1), (1, 1, 2), 5), "bad")
    with pytest.raises(bc.ConfigError, match=r"'bad' \(line in 'lower'\): point 4 ") as e:
        evaluate_all(result, [(ok, None), (bad, None)])
    assert e.value.location["point"] == 4 and e.value.location["label"] == "bad"


def test_a_results_stresses_at_a_load_step(tmp_path):
    """``ContactResult.stresses(body, points, step)`` is the stresses of the
    step's state (``history[step]``); a step outside the history is refused."""
    result = load_problem(write(tmp_path, BASE), check_overlap=False).solve()
    X = [[1.0, 1.0, 1.0], [0.5, 0.7, 1.2]]
    assert np.array_equal(result.stresses("lower", X, step=0),
                          result.history[0].stresses("lower", X))
    assert np.array_equal(result.stresses("lower", X, step=-1), result.stresses("lower", X))
    with pytest.raises(bc.ConfigError, match="step must index the 1 load steps"):
        result.stresses("lower", X, step=1)
    assert np.array_equal(result.surface_points("upper"), result.bodies[1].points)

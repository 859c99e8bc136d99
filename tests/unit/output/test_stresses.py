"""The stress files a run writes without being asked: the default probes
under the peak pressure, one figure per body, the maxima in summary.json;
and none, with the reason, where the contact is not small."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest

from bemcontact.cli import main
from bemcontact.validation.reference import contact as ref
from bemcontact.validation.reference import stress as stress_ref

from ..problemfile.test_reader import BASE, write

EXAMPLE = pathlib.Path(__file__).resolve().parents[3] / "examples" / "cattaneo_mindlin_multiscale.toml"


@pytest.fixture(scope="module")
def multiscale_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "out"
    assert main(["run", str(EXAMPLE), "--out", str(out), "--quiet"]) == 0
    return out, json.loads((out / "summary.json").read_text())


def test_the_default_probes_and_one_figure_per_body_are_written(multiscale_run):
    out, s = multiscale_run
    for body in ("block", "sphere"):
        for label in ("profile", "section1", "section2"):
            assert (out / f"stresses_{body}_{label}.csv").is_file()
            assert (out / f"stresses_{body}_{label}.vtu").is_file()
        assert (out / f"stresses_{body}.png").is_file()
    assert not list(out.glob("stresses_*_profile.png"))
    fields = s["stresses"]["fields"]
    assert [(f["body"], f["label"]) for f in fields] == [
        (b, k) for b in ("block", "sphere") for k in ("profile", "section1", "section2")]
    assert all(len(f["steps"]) == len(s["steps"]) for f in fields)  # maxima per load step


def test_the_default_profile_finds_hertz_largest_shear_below_the_contact(multiscale_run):
    """The first step of the example is the normal load alone (Hertz): the
    largest Tresca stress on the block's profile is Johnson's τ1 maximum,
    0.310 p0 at 0.481a, within 1 % in value and 3 % of a in depth (the
    profile's 100 points are 0.03a apart; the grid's p0 within 0.2 %)."""
    out, s = multiscale_run
    P = s["steps"][0]["normal_force"]
    h = ref.hertz(P, 10.0, ref.effective_modulus(210e3, 0.3, 210e3, 0.3))
    a, p0 = h.contact_radius, h.peak_pressure
    exact = stress_ref.hertz_axis_stresses([0.5 * a], a, p0, 0.3)
    prof = next(f for f in s["stresses"]["fields"] if f["label"] == "profile"
                and f["body"] == "block")
    first = prof["steps"][0]["tresca"]
    assert first["value"] == pytest.approx(exact.max_shear, rel=0.01)
    top = np.loadtxt(out / "stresses_block_profile.csv", delimiter=",", skiprows=1)[0, :3]
    depth = top[2] + 0.02 * a - first["point"][2]  # the profile starts 0.02a below the surface
    assert abs(depth - exact.max_shear_depth) <= 0.03 * a


def test_no_default_probes_where_the_contact_is_not_small(tmp_path):
    """The tiny cubes touch over a whole face: no probes, and summary.json
    says why; the surface stresses' maxima are there all the same."""
    path = write(tmp_path, BASE + '\n[output]\nfigures = false\nsteps = "last"\n')
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())["stresses"]
    assert s["fields"] == [] and len(s["skipped"]) == 2
    assert all("not small against the body" in line for line in s["skipped"])
    assert set(s["surface"]) == {"lower", "upper"}
    assert not list(out.glob("stresses_*"))

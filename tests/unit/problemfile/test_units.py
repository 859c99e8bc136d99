"""The problem file's ``units`` labels: known units, and a consistent set
(stress = force / length²) when all three are given; one-line errors naming
the file, the field and the value."""

from __future__ import annotations

import pathlib

import pytest

import bemcontact as bc
from bemcontact.problemfile.checks import UNITS

EXAMPLE = pathlib.Path(__file__).resolve().parents[3] / "examples" / "two_cubes_similar.toml"
LINE = 'units = { length = "mm", force = "N", stress = "MPa" }'


def _file(tmp_path, units: str) -> pathlib.Path:
    text = EXAMPLE.read_text()
    assert LINE in text
    p = tmp_path / "p.toml"
    p.write_text(text.replace(LINE, units))
    return p


@pytest.mark.parametrize("length, force, stress", [
    ("m", "N", "Pa"), ("mm", "N", "MPa"), ("m", "kN", "kPa"), ("mm", "kN", "GPa"),
    ("m", "MN", "MPa"), ("mm", "N", "N/mm²"), ("in", "lbf", "psi"), ("in", "kip", "ksi"),
    ("ft", "lbf", "psf"), ("um", "mN", "GPa"),
])
def test_consistent_units_are_accepted(tmp_path, length, force, stress):
    units = {"length": length, "force": force, "stress": stress}
    text = "units = { " + ", ".join(f'{k} = "{v}"' for k, v in units.items()) + " }"
    assert bc.load_problem(_file(tmp_path, text)).units == units


@pytest.mark.parametrize("units, message", [
    ('{ length = "m", force = "kN", stress = "GPa" }',
     "units: inconsistent: kN / m² is kPa, not GPa, got {'length': 'm', 'force': 'kN', "
     "'stress': 'GPa'}; use a consistent set, e.g. {m, N, Pa}, {mm, N, MPa}, {m, kN, kPa}, "
     "{mm, kN, GPa}, {m, MN, MPa}, {in, lbf, psi}, {in, kip, ksi}"),
    ('{ length = "mm", force = "N", stress = "Pa" }',
     "units: inconsistent: N / mm² is MPa, not Pa, got"),
    ('{ length = "mm", force = "N", stress = "Mpa" }',
     "units.stress: unknown stress unit, got 'Mpa' (did you mean 'MPa'?)"),
    ('{ length = "furlong" }',
     "units.length: unknown length unit, got 'furlong'; known: m, mm, cm, um, µm, km, in, ft"),
])
def test_inconsistent_or_unknown_units_are_one_line_errors(tmp_path, units, message):
    path = _file(tmp_path, f"units = {units}")
    with pytest.raises(bc.ConfigError) as err:
        bc.load_problem(path)
    text = str(err.value)
    assert "\n" not in text
    assert text.startswith(f"{path}: {message}"), text


def test_partial_units_are_checked_label_by_label(tmp_path):
    assert bc.load_problem(_file(tmp_path, 'units = { length = "mm" }')).units == {"length": "mm"}
    assert set(UNITS) == {"length", "force", "stress"}

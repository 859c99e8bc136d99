"""Problem files of assemblies: ``[[contact]]`` arrays over two or more
``[[body]]`` sections load into a ContactProblem of several pairs and solve;
bad pairs are one-line errors naming the ``contact[k]`` field."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.problemfile import load_problem

# Three blocks stacked on non-matching meshes, pressed by p = 2 on top: the
# patch test through two interfaces (tests/validation/test_assemblies.py).
STACK = """\
[solver]
tolerance = 1e-12

[[body]]
name = "bottom"
mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 1], divisions = [3, 3, 1] } }
material = { youngs_modulus = 1e4, poisson_ratio = 0.3 }
boundary_conditions.zmin = { displacement = ["free", "free", 0] }
boundary_conditions.xmin = { displacement = [0, "free", "free"] }
boundary_conditions.ymin = { displacement = ["free", 0, "free"] }

[[body]]
name = "middle"
mesh = { box = { lower = [0, 0, 1], upper = [2, 2, 2], divisions = [4, 4, 1] } }
material = { youngs_modulus = 3e4, poisson_ratio = 0.2 }
boundary_conditions.xmin = { displacement = [0, "free", "free"] }
boundary_conditions.ymin = { displacement = ["free", 0, "free"] }

[[body]]
name = "top"
mesh = { box = { lower = [0, 0, 2], upper = [2, 2, 3], divisions = [2, 2, 1] } }
material = { youngs_modulus = 2e4, poisson_ratio = 0.25 }
boundary_conditions.zmax = { pressure = 2 }
boundary_conditions.xmin = { displacement = [0, "free", "free"] }
boundary_conditions.ymin = { displacement = ["free", 0, "free"] }

[[contact]]
bodies = ["bottom", "middle"]
surfaces = ["zmax", "zmin"]

[[contact]]
bodies = ["middle", "top"]
surfaces = ["zmax", "zmin"]
friction_coefficient = 0.2
penalty = 2.0
"""


def write(tmp_path, text):
    p = tmp_path / "stack.toml"
    p.write_text(text, encoding="utf-8")
    return p


def test_an_assembly_file_loads_and_solves(tmp_path):
    pf = load_problem(write(tmp_path, STACK))
    assert [b.name for b in pf.bodies] == ["bottom", "middle", "top"]
    assert [p.bodies for p in pf.pairs] == [("bottom", "middle"), ("middle", "top")]
    assert pf.pairs[1].friction_coefficient == 0.2 and pf.pairs[1].penalty == 2.0
    assert pf.pair is pf.pairs[0]
    res = pf.solve()
    assert res.converged and len(res.pairs) == 2
    # the floating blocks' exact equilibrium in z: each pair carries p A
    assert [p.normal_force for p in res.pairs] == pytest.approx([8.0, 8.0], rel=1e-8)
    assert res.pairs[1].tangential_force > 1e-3  # friction against the Poisson mismatch
    # frictionless: uniform stress, the patch test through both interfaces
    smooth = load_problem(write(tmp_path, STACK.replace("friction_coefficient = 0.2", "")))
    for p in smooth.solve().pairs:
        act = p.frame.weights > 0
        assert np.abs(p.frame.pressure[act] / 2.0 - 1.0).max() <= 1e-8


@pytest.mark.parametrize("old, new, field, message", [
    ('bodies = ["middle", "top"]', 'bodies = ["midle", "top"]', "contact[1].bodies[0]",
     "no body of that name (bodies: bottom, middle, top), got 'midle' (did you mean 'middle'?)"),
    ('[[contact]]\nbodies = ["middle", "top"]', '[[contact]]', "contact[1].bodies",
     'is needed with more than two bodies'),
    ('bodies = ["middle", "top"]', 'bodies = ["bottom", "middle"]', "contact[1]",
     "the same two surfaces as contact[0], got ['bottom', 'middle']; give each pair once"),
    ('bodies = ["middle", "top"]\nsurfaces = ["zmax", "zmin"]',
     'bodies = ["middle", "bottom"]\nsurfaces = ["zmax", "zmax"]', "body[2]",
     "is in no contact pair, got 'top'"),
    ('boundary_conditions.zmax = { pressure = 2 }', 'boundary_conditions.zmin = { pressure = 2 }',
     "body[2].boundary_conditions.zmin",
     "region 'zmin' is this body's contact surface (contact[1].surfaces[1])"),
    ('surfaces = ["zmax", "zmin"]\nfriction', 'surfaces = ["ymax", "zmin"]\nfriction',
     "contact[1].surfaces", "contact surfaces of middle and top"),
])
def test_bad_pairs_name_their_field(tmp_path, old, new, field, message):
    assert old in STACK
    path = write(tmp_path, STACK.replace(old, new, 1))
    with pytest.raises(bc.ConfigError) as info:
        load_problem(path)
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.startswith(f"{path}: {field}: "), msg
    assert message in msg, msg


def test_contact_must_be_a_table_or_tables(tmp_path):
    text = "contact = [1, 2]\n" + STACK.split("[[contact]]")[0]  # top level
    with pytest.raises(bc.ConfigError, match=r"contact: must be a table or an array of tables"):
        load_problem(write(tmp_path, text))

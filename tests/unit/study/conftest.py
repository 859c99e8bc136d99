"""Tiny two-cube problem files for the study tests (1 element per face)."""

from __future__ import annotations

TINY = """\
units = {{ length = "mm", force = "N", stress = "MPa" }}
{solver}
[[body]]
name = "lower"
mesh = {{ box = {{ lower = [0, 0, 0], upper = [2, 2, 2], divisions = {div} }} }}
material = {{ youngs_modulus = {E}, poisson_ratio = 0.3 }}
[body.boundary_conditions.zmin]
displacement = [0, 0, 0]

[[body]]
name = "upper"
mesh = {{ box = {{ lower = [0, 0, 2], upper = [2, 2, 4], divisions = {div} }} }}
material = {{ youngs_modulus = 1e4, poisson_ratio = 0.3 }}
[body.boundary_conditions.zmax]
displacement = {top}

[contact]
surfaces = ["zmax", "zmin"]
friction_coefficient = {mu}
{contact}
{extra}
"""


def tiny_problem(tmp_path, *, E="1e4", top="[0.002, 0, -0.04]", mu="0.1", penalty=None,
                 steps=None, frame=None, div=2, extra="", name="tiny.toml"):
    """A problem file in ``tmp_path``: two cubes (``div`` elements per edge),
    the upper pushed by ``top``; ``steps`` [[step]] sections scaling it."""
    solver = "[solver]\ntolerance = 1e-10\n"
    contact = ""
    if penalty is not None:
        contact += f"penalty = {penalty}\n"
    if frame is not None:
        contact += f'frame_on = "{frame}"\n'
    if steps:
        vals = [float(v) for v in top.strip("[]").split(",")]
        for k in range(1, steps + 1):
            f = k / steps
            extra += (f"\n[[step]]\nlabel = \"s{k}\"\n[step.boundary_conditions.upper.zmax]\n"
                      f"displacement = [{', '.join(repr(v * f) for v in vals)}]\n")
    p = tmp_path / name
    p.write_text(TINY.format(E=E, top=top, mu=mu, solver=solver, contact=contact, div=div,
                             extra=extra))
    return p

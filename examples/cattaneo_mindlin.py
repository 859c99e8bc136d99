"""Hertz, Cattaneo–Mindlin and a fretting loop: a steel hemisphere (R = 10 mm)
pressed on a steel block by 0.03 mm, then loaded tangentially through its
base up to Q* = 0.75 mu P, back to -Q* and up to Q* again (mu = 0.3).

    python examples/cattaneo_mindlin.py OUT_DIR [FINE_SIZE]

writes OUT_DIR/profiles.png (pressure and tangential traction along the
radius at Q*, against Hertz and Cattaneo–Mindlin) and OUT_DIR/fretting_loop.png
(the platen's force against the contact's tangential approach, against
Mindlin–Deresiewicz),
and prints the stick radius and the loop's dissipated energy against their
analytic values.  The default mesh (h = 0.1 mm, 11 elements across the
contact) takes about 20 s; docs/validation.md has the converged figures at
h = 0.05.  The platen translation also holds the finite bodies' linear
elastic compliance, measured by a small all-stick step (Q = 0.02 mu P) and
taken off in the loop figure.
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np

import bemcontact as bc
from bemcontact.validation import cases
from bemcontact.output.plot import plot_force_displacement, plot_radial_profile
from bemcontact.validation.reference import contact as ref

MU, RATIO, APPROACH = 0.3, 0.75, 0.03


def run(out_dir: str, fine_size: float = 0.1, increments: int = 8) -> dict[str, float]:
    """Solve, write both figures into ``out_dir`` and return the key numbers."""
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    s = cases.SphereOnBlock()
    p_est = ref.hertz_force(APPROACH, s.radius, s.contact_modulus)  # loads set before solving
    q_max = RATIO * MU * p_est
    down = np.linspace(q_max, -q_max, increments + 1)[1:]
    steps = (
        [bc.LoadStep(label="P")]
        + cases.tangential_steps([0.02 * MU * p_est], APPROACH, increments=1, label="small")
        + cases.tangential_steps([q_max], APPROACH, increments=2)
        + cases.tangential_steps(down, APPROACH, increments=1, label="unload")
        + cases.tangential_steps(-down, APPROACH, increments=1, label="reload")
    )
    res = cases.sphere_on_block(fine_size, APPROACH, friction_coefficient=MU).solve(steps=steps)
    Q, U = cases.platen_history(res)
    top = res.history[2]
    P = top.normal_force
    hz = ref.hertz(P, s.radius, s.contact_modulus)
    a = hz.contact_radius
    S = s.tangential_compliance_factor
    delta = cases.tangential_approach(Q, U, a, S)  # less the bodies' linear compliance
    plot_radial_profile(
        top, out / "profiles.png", pressure=hz.pressure,
        traction=lambda r: ref.cattaneo_mindlin_traction(r, hz, Q[2], MU),
        title=f"sphere on block, h = {fine_size:g} mm: Q = {Q[2] / (MU * P):.3f} μP",
    )
    # analytic loop: loading curve to Q*, Mindlin–Deresiewicz branches
    qa = np.linspace(q_max, -q_max, 200)
    d_un = ref.mindlin_deresiewicz_unloading(qa, q_max, MU, P, a, S)
    ua = np.concatenate([d_un, -d_un])
    fa = np.concatenate([qa, -qa])
    loop_U, loop_Q = U[2:], Q[2:]
    # the contact's own tangential approach (the bodies' linear compliance
    # adds no area, but hides the loop)
    plot_force_displacement(
        delta[2:], loop_Q, out / "fretting_loop.png", analytic=(ua, fa),
        title=f"fretting loop, Q* = {q_max / (MU * P):.3f} μP",
        xlabel="tangential approach δ = $U_x$ − $C_{bulk}$ Q (mm)",
    )
    poly_U, poly_Q = loop_U[:-1], loop_Q[:-1]
    W = 0.5 * abs(np.sum(poly_Q * np.roll(poly_U, -1) - np.roll(poly_Q, -1) * poly_U))
    W_exact = ref.fretting_loop_energy(q_max, MU, P, a, S)
    c = cases.stick_radius(top.frame)
    c_exact = ref.cattaneo_mindlin_stick_radius(a, Q[2], MU, P)
    return {
        "normal_force_N": P,
        "contact_radius_mm": a,
        "stick_radius_mm": c,
        "stick_radius_exact_mm": c_exact,
        "loop_energy_Nmm": W,
        "loop_energy_exact_Nmm": W_exact,
        "newton_iterations": res.newton_iterations,
    }


def main(argv: list[str]) -> None:
    if len(argv) not in (2, 3):
        sys.exit("usage: python examples/cattaneo_mindlin.py OUT_DIR [FINE_SIZE]")
    r = run(argv[1], float(argv[2]) if len(argv) == 3 else 0.1)
    print(f"P = {r['normal_force_N']:.1f} N, a = {r['contact_radius_mm']:.4f} mm")
    print(f"stick radius {r['stick_radius_mm']:.4f} mm, Cattaneo-Mindlin "
          f"{r['stick_radius_exact_mm']:.4f} mm ({r['stick_radius_mm'] / r['stick_radius_exact_mm'] - 1:+.1%})")
    print(f"loop energy {r['loop_energy_Nmm']:.4g} N mm, Mindlin-Deresiewicz "
          f"{r['loop_energy_exact_Nmm']:.4g} N mm ({r['loop_energy_Nmm'] / r['loop_energy_exact_Nmm'] - 1:+.1%})")
    print(f"figures in {argv[1]}: profiles.png, fretting_loop.png")


if __name__ == "__main__":
    main(sys.argv)

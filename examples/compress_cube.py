"""Compress a 2 x 2 x 2 cube between frictionless plates and compare the
reaction force with E * A * strain.

The bottom face (z = 0) is held in z, the top face (z = 2) moved down by
delta, x and y are held only on the symmetry faces xmin and ymin, so the
stress is uniaxial and the reaction exactly E * A * delta / L.
"""

from __future__ import annotations

import bemcontact as bc


def run(divisions: int = 2, element_type: str = "quad4") -> dict[str, float]:
    E, nu, L, delta = 1.0e4, 0.3, 2.0, 0.02
    mesh = bc.box((0, 0, 0), (L, L, L), divisions, element_type)
    body = bc.ElasticBody(
        mesh,
        bc.LinearElastic(youngs_modulus=E, poisson_ratio=nu),
        {
            "zmin": bc.Displacement((None, None, 0.0)),
            "zmax": bc.Displacement((None, None, -delta)),
            "xmin": bc.Displacement((0.0, None, None)),
            "ymin": bc.Displacement((None, 0.0, None)),
        },
    )
    sol = body.solve()
    force = -sol.reaction("zmax")[2]
    exact = E * L * L * delta / L
    return {"reaction_N": force, "exact_N": exact, "relative_error": abs(force - exact) / exact}


if __name__ == "__main__":
    r = run()
    print(f"cube 2x2x2, E = 1e4, strain = 1 %: reaction on top face {r['reaction_N']:.10g} N")
    print(f"E * A * strain                                          {r['exact_N']:.10g} N")
    print(f"relative difference                                     {r['relative_error']:.2e}")

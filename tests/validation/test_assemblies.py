"""Assemblies: several bodies and contact pairs solved at once
(ContactProblem(bodies=, pairs=); docs/validation.md).

* Three blocks stacked on non-matching meshes, three materials, uniform
  pressure p0 on top, rollers on the x = 0 and y = 0 planes, the middle and
  top blocks free in z (held only by the contacts): the exact solution is
  uniform stress, so both interfaces carry p0 everywhere with no shear.
  Tolerance 1e-8, the two-body patch test's (tests/validation/
  test_contact_patch.py: the BEM's own floor on uniform stress); measured
  1.2e-10.  Each frame carries p0 times the area, the resultant of the
  floating blocks' exact equilibrium rows (1e-8; measured 5e-15).
* A ball between two blocks, mirror symmetric by construction
  (:func:`bemcontact.validation.assemblies.ball_between_blocks`, h = 0.1 mm):
  both contacts reproduce Hertz within the tiers of the sphere on a block at
  that size (contact radius and peak pressure 3 %, profile 5 %; measured
  1.1 / 0.6 / 2.3 %); the two contact forces equal the force the upper
  block transmits to the collocation accuracy of its face's reaction (0.2 %;
  measured 7e-4); the two contacts give the same pressures to 1e-8 of p0
  (measured 9e-11: the symmetric problem differs from its mirror image by a
  rigid translation, so only round-off and the Newton tolerance differ).
  With friction (mu = 0.3, identical materials): the same Hertz tiers, the
  normal force as without friction to 1e-4 (measured 4e-6) and shear below
  0.01 p0 (measured 0.005), re-solved on the frictionless solve's
  condensation.
* A bridge on two supports of another material, with friction, under
  uniform pressure (rollers on its x = 0 and y = 0 faces, free in z): the
  supports' normal forces add up to the load (1e-8: the bridge's exact
  equilibrium in z), and listing the bodies and pairs in another order, with
  each pair's surfaces swapped, gives the same solution (1e-10).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from bemcontact import (
    ContactPair,
    ContactProblem,
    Displacement,
    ElasticBody,
    Fixed,
    LinearElastic,
    Pressure,
    SolverOptions,
    box,
)
from bemcontact.validation import assemblies, cases
from bemcontact.validation.reference import contact as ref

pytestmark = pytest.mark.validation

P0 = 10.0
ROLLERS = {"xmin": Displacement((0.0, None, None)), "ymin": Displacement((None, 0.0, None))}


def test_three_stacked_blocks_pass_the_patch_test():
    mats = [LinearElastic(1.0e4, 0.3), LinearElastic(3.0e4, 0.2), LinearElastic(2.0e4, 0.25)]
    meshes = [box((0, 0, z), (2, 2, z + 1), (n, n, 2), element_type=t)
              for z, n, t in ((0, 7, "quad4"), (1, 11, "quad4"), (2, 6, "tri3"))]
    bodies = [
        ElasticBody(meshes[0], mats[0], {"zmin": Displacement((None, None, 0.0)), **ROLLERS},
                    name="bottom"),
        ElasticBody(meshes[1], mats[1], dict(ROLLERS), name="middle"),
        ElasticBody(meshes[2], mats[2], {"zmax": Pressure(P0), **ROLLERS}, name="top"),
    ]
    pairs = [ContactPair("zmax", "zmin", bodies=("bottom", "middle"), frame_on="coarser"),
             ContactPair("zmax", "zmin", bodies=("middle", "top"), frame_on="coarser")]
    res = ContactProblem(bodies=bodies, pairs=pairs).solve(SolverOptions(tolerance=1e-12))
    assert res.converged
    assert len(res.pairs) == 2 and res.names == ("bottom", "middle", "top")
    for p in res.pairs:
        act = p.frame.weights > 0
        assert np.abs(p.frame.pressure[act] / P0 - 1.0).max() <= 1e-8
        assert np.abs(p.frame.tangential_traction[act]).max() <= 1e-8 * P0
        assert np.allclose(p.contact_force, [0.0, 0.0, 4.0 * P0], rtol=0, atol=1e-8 * 4 * P0)
    # the middle block's contact tractions, from its own solution
    mid = res.bodies[1]
    for region, sign in (("zmin", 1.0), ("zmax", -1.0)):  # t = sigma n, sigma_zz = -p0
        t = mid.traction[mid.region == mid.region_names.index(region)]
        assert np.abs(t[:, 2] / (sign * P0) - 1.0).max() <= 1e-8


@pytest.fixture(scope="module")
def ball():
    prob = assemblies.ball_between_blocks(0.1)
    cond = prob.condense()
    rough = ContactProblem(
        bodies=prob.bodies,
        pairs=[dataclasses.replace(p, friction_coefficient=0.3) for p in prob.pairs])
    return (prob.solve(condensed=cond),
            rough.solve(SolverOptions(load_steps=4), condensed=cond))


@pytest.mark.parametrize("which", ["frictionless", "friction"])
def test_ball_between_two_blocks_gives_hertz_on_both_contacts(ball, which):
    res = ball[which == "friction"]
    assert res.converged
    s = cases.SphereOnBlock()
    P = assemblies.transmitted_force(res)
    forces = [p.normal_force for p in res.pairs]
    assert np.allclose(forces, P, rtol=2e-3)
    for p in res.pairs:
        h = ref.hertz(p.normal_force, s.radius, s.contact_modulus)
        e = cases.hertz_errors(p.frame, h)
        assert abs(e.contact_radius) <= 0.03
        assert abs(e.peak_pressure) <= 0.03
        assert e.profile_l2 <= 0.05
        assert np.abs(p.frame.tangential_traction).max() <= 0.01 * h.peak_pressure
    lo, hi = (p.frame for p in res.pairs)
    assert np.abs(lo.pressure - hi.pressure).max() <= 1e-8 * lo.pressure.max()
    assert abs(forces[0] - forces[1]) <= 1e-10 * forces[0]


def test_ball_friction_keeps_the_normal_force(ball):
    smooth, rough = ball
    for a, b in zip(smooth.pairs, rough.pairs):
        assert abs(b.normal_force / a.normal_force - 1.0) <= 1e-4
        assert b.tangential_force > 0.0


def _bridge(reverse: bool) -> ContactProblem:
    steel, alu = LinearElastic(2.0e4, 0.3), LinearElastic(7.0e3, 0.33)
    left = ElasticBody(box((0, 0, 0), (1, 1, 1), (5, 5, 4)), alu, {"zmin": Fixed()}, name="left")
    right = ElasticBody(box((3, 0, 0), (4, 1, 1), (4, 4, 4)), alu, {"zmin": Fixed()},
                        name="right")
    bridge = ElasticBody(box((0, 0, 1), (5, 1, 1.5), (23, 5, 2)), steel,
                         {"zmax": Pressure(P0), **ROLLERS}, name="bridge")
    if reverse:
        return ContactProblem(bodies=[right, bridge, left], pairs=[
            ContactPair("zmin", "zmax", 0.3, bodies=("bridge", "right")),
            ContactPair("zmin", "zmax", 0.3, bodies=("bridge", "left"))])
    return ContactProblem(bodies=[bridge, left, right], pairs=[
        ContactPair("zmax", "zmin", 0.3, bodies=("left", "bridge")),
        ContactPair("zmax", "zmin", 0.3, bodies=("right", "bridge"))])


@pytest.fixture(scope="module")
def bridge():
    opt = SolverOptions(load_steps=2, tolerance=1e-12)
    return _bridge(False).solve(opt), _bridge(True).solve(opt)


def test_bridge_on_two_supports_statics_and_order(bridge):
    a, b = bridge
    assert a.converged and b.converged
    load = P0 * 5.0 * 1.0
    fa = {p.names[0]: p.contact_force for p in a.pairs}  # on the bridge
    fb = {p.names[1]: -p.contact_force for p in b.pairs}  # the bridge is body 1 here
    assert abs(fa["left"][2] + fa["right"][2] - load) <= 1e-8 * load
    # the overhang puts more on the right support; both carry
    assert 0.2 * load < fa["left"][2] < fa["right"][2] < 0.8 * load
    assert max(abs(fa["left"][0]), abs(fa["right"][0])) > 1e-3 * load  # friction acts
    for name in ("left", "right"):
        np.testing.assert_allclose(fb[name], fa[name], rtol=0, atol=1e-10 * load)
    for body in ("bridge", "left", "right"):
        ua = a.bodies[a.names.index(body)].displacement
        ub = b.bodies[b.names.index(body)].displacement
        assert np.abs(ua - ub).max() <= 1e-10 * np.abs(ua).max()


def test_assembly_results_name_their_pairs(bridge):
    res = bridge[0]
    assert [p.label for p in res.pairs] == ["left:zmax/bridge:zmin", "right:zmax/bridge:zmin"]
    summary = res.summary()
    assert [p["bodies"] for p in summary["pairs"]] == [["left", "bridge"], ["right", "bridge"]]
    assert summary["pairs"][1]["normal_force"] == pytest.approx(res.pairs[1].normal_force)
    # the top-level fields are the first pair's
    assert res.normal_force == res.pairs[0].normal_force
    assert res.frame is res.pairs[0].frame

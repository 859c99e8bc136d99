"""ContactProblem over several bodies and pairs: the checks of its input
(one line each, naming the pair and the field) and the frame set's
numbering (bemcontact.contact.frames)."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact import ContactPair, ContactProblem, ElasticBody, Fixed, LinearElastic, Pressure, box
from bemcontact.contact.frames import FrameSet

MAT = LinearElastic(1.0e4, 0.3)


def _blocks():
    lower = ElasticBody(box((0, 0, 0), (1, 1, 1), (2, 2, 2)), MAT, {"zmin": Fixed()}, name="lower")
    middle = ElasticBody(box((0, 0, 1), (1, 1, 2), (3, 3, 2)), MAT, {"xmin": Fixed()}, name="middle")
    upper = ElasticBody(box((0, 0, 2), (1, 1, 3), (2, 2, 2)), MAT, {"zmax": Pressure(1.0)},
                        name="upper")
    return lower, middle, upper


def _pairs():
    return [ContactPair("zmax", "zmin", bodies=("lower", "middle")),
            ContactPair("zmax", "zmin", bodies=("middle", "upper"))]


def test_a_valid_assembly_numbers_its_frames():
    prob = ContactProblem(bodies=_blocks(), pairs=_pairs())
    fs = prob.frames
    assert isinstance(fs, FrameSet) and len(fs.frames) == 2
    assert fs.links == ((0, 1), (1, 2))
    m0 = int(fs.frames[0].active.sum())
    assert fs.slice(0) == slice(0, m0) and fs.m == m0 + int(fs.frames[1].active.sum())
    np.testing.assert_array_equal(fs.pair_of, np.repeat([0, 1], [m0, fs.m - m0]))
    # the middle body: both its contact surfaces, each node once
    mid = fs.nodes(1)
    assert mid.size == np.unique(mid).size
    assert set(fs.frames[0].nodes(1)) | set(fs.frames[1].nodes(0)) == set(mid)
    assert prob.surfaces(1) == ["zmin", "zmax"]
    modes = fs.traction_modes()
    assert [t.size for t in modes] == [3 * fs.m] * 3
    # body 1 of pair 0 (lower) receives -lam and nothing of pair 1
    B = modes[0].B.toarray()
    assert np.abs(B[:, 3 * m0:]).max() == 0.0
    assert B[:, : 3 * m0].sum() < 0.0


@pytest.mark.parametrize("change, message", [
    (lambda b, p: (b, [ContactPair("zmax", "zmin", bodies=("lowr", "middle")), p[1]]),
     r"pairs\[0\] \(lowr:zmax/middle:zmin\): unknown body 'lowr' \(did you mean 'lower'\?\); "
     r"the bodies are \['lower', 'middle', 'upper'\]"),
    (lambda b, p: (b, [ContactPair("zmax", "zmin"), p[1]]),
     r"pairs\[0\] \(zmax/zmin\): name its two bodies \(ContactPair.bodies\)"),
    (lambda b, p: (b, p[:1]),
     r"body 'upper' is in no contact pair; add its pair, or solve it on its own"),
    (lambda b, p: (b, p + [ContactPair("zmin", "zmax", bodies=("middle", "lower"))]),
     r"pairs\[2\] \(middle:zmin/lower:zmax\): the same surfaces as pairs\[0\] "
     r"\(lower:zmax/middle:zmin\); give each pair once"),
    (lambda b, p: (b, [ContactPair("zmax", "top", bodies=("lower", "middle")), p[1]]),
     r"pairs\[0\] \(lower:zmax/middle:top\): middle: unknown contact surface 'top'"),
    (lambda b, p: (b, [ContactPair("zmin", "zmax", bodies=("lower", "middle")), p[1]]),
     r"lower: the contact surface 'zmin' also has a boundary condition; remove it"),
    (lambda b, p: (b[:1], p), r"an assembly needs at least two bodies, got 1"),
    (lambda b, p: (b, []), r"an assembly needs at least one contact pair"),
    (lambda b, p: ([b[0], b[0], b[2]], p), r"two bodies have the same name 'lower'"),
    (lambda b, p: (b, "pairs"), r"pairs must be a list, got 'pairs'"),
    (lambda b, p: (b, [p[0], 3]), r"pairs\[1\] must be a ContactPair, got int"),
])
def test_bad_assemblies_are_refused_in_one_line(change, message):
    bodies, pairs = change(list(_blocks()), _pairs())
    with pytest.raises(bc.ConfigError, match=message) as info:
        ContactProblem(bodies=bodies, pairs=pairs)
    assert "\n" not in str(info.value)


def test_a_pair_naming_one_body_twice_is_refused():
    with pytest.raises(bc.ConfigError, match=r"ContactPair.bodies names 'lower' twice"):
        ContactPair("zmax", "zmin", bodies=("lower", "lower"))
    with pytest.raises(bc.ConfigError, match=r"ContactPair.bodies must be two body names"):
        ContactPair("zmax", "zmin", bodies="lower")


def test_pairs_that_can_never_touch_are_refused():
    lower, middle, upper = _blocks()
    far = ElasticBody(box((5, 5, 2), (6, 6, 3), (2, 2, 2)), MAT, {"zmax": Fixed()}, name="far")
    prob = ContactProblem(bodies=[lower, middle, far], pairs=[
        _pairs()[0], ContactPair("zmax", "zmin", bodies=("middle", "far"))])
    with pytest.raises(bc.ConfigError, match=r"pairs\[1\] \(middle:zmax/far:zmin\): contact "
                       r"surfaces of middle and far do not overlap"):
        prob.frames


def test_two_body_form_checks_the_pair_bodies():
    lower, middle, _ = _blocks()
    pair = ContactPair("zmax", "zmin", bodies=("middle", "lower"))
    with pytest.raises(bc.ConfigError, match=r"pair.bodies is \['middle', 'lower'\]; it must name "
                       r"body 1 and body 2, \['lower', 'middle'\], in this order"):
        ContactProblem(lower, middle, pair)
    with pytest.raises(bc.ConfigError, match="give either body1, body2 and pair, or bodies= and pairs="):
        ContactProblem(lower, middle, pair, bodies=[lower, middle], pairs=[pair])
    ok = ContactProblem(lower, middle, ContactPair("zmax", "zmin", bodies=("lower", "middle")))
    assert ok.links == ((0, 1),)


def test_a_force_controlled_platen_on_a_stack():
    """The top of a stack of three blocks pushed by a force through a rigid
    platen (z force controlled, x and y held), the middle block floating in
    z: both pairs carry the same force (the middle block's exact equilibrium
    row: 1e-10; measured 1e-15), the platen's force to the collocation
    accuracy of the upper block's own equilibrium on its 2 x 2 faces (2e-3;
    measured 9e-4)."""
    rollers = {"xmin": bc.Displacement((0, None, None)), "ymin": bc.Displacement((None, 0, None))}
    bodies = [
        ElasticBody(box((0, 0, 0), (1, 1, 1), (3, 3, 2)), MAT,
                    {"zmin": bc.Displacement((None, None, 0)), **rollers}, name="lower"),
        ElasticBody(box((0, 0, 1), (1, 1, 2), (4, 4, 2)), MAT, dict(rollers), name="middle"),
        ElasticBody(box((0, 0, 2), (1, 1, 3), (2, 2, 2)), MAT,
                    {"zmax": [bc.Displacement((0, 0, None)), bc.Force((None, None, -8.0))]},
                    name="upper"),
    ]
    res = ContactProblem(bodies=bodies, pairs=_pairs()).solve()
    assert res.converged
    forces = [p.normal_force for p in res.pairs]
    assert forces[1] == pytest.approx(forces[0], rel=1e-10)
    assert forces[0] == pytest.approx(8.0, rel=2e-3)
    assert res.control_displacements["upper"]["zmax"][2] < 0.0

"""Re-solves reusing the condensed bodies: the same numbers as a
fresh solve, kinds of condition and other bodies refused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.contact import ContactProblem
from bemcontact.errors import ConfigError

from .conftest import tiny_problem


def _fields(r):
    """The numbers a result is compared by."""
    return np.concatenate([
        [r.normal_force, r.tangential_force], r.contact_force, r.frame.pressure,
        r.frame.tangential_traction.ravel(), r.frame.slip.ravel(), r.frame.gap,
        r.bodies[0].displacement.ravel(), r.bodies[1].traction.ravel(),
        r.interfaces[1].displacement.ravel(),
    ])


def _close(a, b):
    fa, fb = _fields(a), _fields(b)
    scale = np.abs(fb).max()
    assert np.abs(fa - fb).max() <= 1e-10 * scale, np.abs(fa - fb).max() / scale
    assert [s.iterations for s in a.steps] == [s.iterations for s in b.steps]
    assert np.array_equal(a.frame.state, b.frame.state)


def _problem(tmp_path, **kw):
    return bc.load_problem(tiny_problem(tmp_path, **kw))


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    pf = _problem(tmp_path_factory.mktemp("base"))
    cp = pf.contact_problem()
    return pf, cp, cp.condense(pf.options)


def test_same_problem_reused_equals_fresh(base):
    pf, cp, cond = base
    fresh = ContactProblem(*pf.bodies, pf.pair).solve(pf.options)
    _close(cp.solve(pf.options, condensed=cond), fresh)
    assert fresh.normal_force > 1.0  # the cubes are pressed together


@pytest.mark.parametrize("kw", [
    {"mu": "0.01"}, {"mu": "0.0"}, {"top": "[0.005, 0, -0.03]"}, {"penalty": "3.0"},
    {"steps": 3},
])
def test_changed_friction_load_penalty_history_equal_fresh(tmp_path, base, kw):
    pf0, _, cond = base
    pf = _problem(tmp_path, **kw)
    fresh = ContactProblem(*pf.bodies, pf.pair).solve(pf.options, steps=pf.steps or None)
    again = ContactProblem(*pf.bodies, pf.pair).solve(
        pf.options, steps=pf.steps or None, condensed=cond)
    _close(again, fresh)
    if "mu" in kw or "top" in kw:  # the change changes the result
        before = ContactProblem(*pf0.bodies, pf0.pair).solve(pf0.options, condensed=cond)
        diff = np.abs(_fields(again) - _fields(before)).max()
        assert diff > 1e-5 * np.abs(_fields(before)).max(), diff


def test_changed_kind_of_condition_is_refused(tmp_path, base):
    _, _, cond = base
    pf = _problem(tmp_path, top='["free", 0, -0.04]')
    with pytest.raises(ConfigError, match=r"^upper: the kinds of its boundary conditions .*"
                                          "values only$"):
        pf.contact_problem().solve(pf.options, condensed=cond)


@pytest.mark.parametrize("kw, match", [
    ({"E": "2e4"}, "body 'lower': its mesh, material or quadrature differ"),
    ({"frame": "upper"}, "contact.frame_on is 'body2', the condensed bodies have .auto."),
])
def test_other_bodies_or_frame_refused(tmp_path, base, kw, match):
    _, _, cond = base
    pf = _problem(tmp_path, **kw)
    with pytest.raises(ConfigError, match=match):
        pf.contact_problem().solve(pf.options, condensed=cond)


def test_other_linear_options_refused(base):
    pf, cp, cond = base
    lin = dataclasses.replace(pf.options.linear, dense_max_nodes=5)
    with pytest.raises(ConfigError, match="other linear solver options"):
        cp.solve(dataclasses.replace(pf.options, linear=lin), condensed=cond)


def test_load_fields_span_uniform_loads(base):
    """The basis: per free region 3 unit fields + the normal, flat faces
    reduce it to the 3 unit fields each (5 regions besides the contact
    surface per cube)."""
    _, cp, cond = base
    assert [c.values.shape[1] for c in cond.condensed] == [15, 15]


def _force_problem(tmp_path, force, mu):
    p = tiny_problem(tmp_path, top="[0, 0, 0]", mu=mu, name=f"f{mu}.toml")
    p.write_text(p.read_text().replace(
        "[body.boundary_conditions.zmax]\ndisplacement = [0, 0, 0]",
        f"[body.boundary_conditions.zmax]\nforce = {force}"))
    return bc.load_problem(p)


def test_force_controlled_reuse_equals_fresh(tmp_path):
    """Force control: the platen responses are reused, the prescribed
    forces are the new ones."""
    pf = _force_problem(tmp_path, "[5, 0, -300]", "0.2")
    cond = pf.contact_problem().condense(pf.options)
    new = _force_problem(tmp_path, "[10, 0, -500]", "0.3")
    fresh = ContactProblem(*new.bodies, new.pair).solve(new.options)
    again = ContactProblem(*new.bodies, new.pair).solve(new.options, condensed=cond)
    _close(again, fresh)
    assert again.normal_force == pytest.approx(500.0, rel=2e-3)
    assert again.tangential_force > 1.0

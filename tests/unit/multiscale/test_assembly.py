"""An assembly on the contact grid (multiscale/assembly.py): one grid per
pair, coupled through the shared block of examples/two_indenters_multiscale.toml
(two hemispheres 4 mm apart pressed 0.03 and 0.02 mm into one block)."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from bemcontact.bem import ElasticBody
from bemcontact.bem.conditions import Displacement, Force
from bemcontact.contact import ContactPair, ContactProblem, LoadStep, SolverOptions
from bemcontact.contact.rolling import Rolling
from bemcontact.errors import ConfigError
from bemcontact.multiscale.assembly import (GridAssemblyResult, assembly_applicability,
                                            solve_assembly_on_grid)
from bemcontact.multiscale.pair import GridOptions, solve_on_grid
from bemcontact.problemfile import load_problem
from bemcontact.problemfile.method import on_grid
from bemcontact.validation.assemblies import TWO_INDENTERS, two_indenters_on_block

EXAMPLES = pathlib.Path(__file__).resolve().parents[3] / "examples"
APPROACH = {name: approach for name, (_, approach) in TWO_INDENTERS.items()}


@pytest.fixture(scope="module")
def problem():
    return load_problem(EXAMPLES / "two_indenters_multiscale.toml",
                        check_overlap=False).contact_problem()


#: the example's history: pressed in 4 increments ([solver] load_steps)
INCREMENTS = 4
#: the lateral force against the full path at a/h = 3: the full path's own
#: change to a/h = 5 (3.3 %) plus the grid's difference from a/h = 5's (2.6 %)
TANGENTIAL = 0.08


@pytest.fixture(scope="module")
def result(problem) -> GridAssemblyResult:
    return solve_assembly_on_grid(problem, [LoadStep(increments=INCREMENTS)],
                                  options=GridOptions(grid_size=0.05))


def _pair_alone(problem, k: int, approach: float):
    """Pair ``k`` of the assembly as a problem of its own, the indenter's
    base pushed down by ``approach``."""
    a, b = problem.links[k]
    pair = problem.pairs[k]
    alone = ContactProblem(problem.bodies[a], problem.bodies[b],
                           ContactPair(pair.surface1, pair.surface2, pair.friction_coefficient))
    step = LoadStep({problem.bodies[b].name: {"base": [Displacement((0.0, 0.0, -approach))]}},
                    increments=INCREMENTS)
    return solve_on_grid(alone, [step], GridOptions(grid_size=0.05))


def test_the_coupling_is_reciprocal(result):
    """Maxwell–Betti: the work of pair 0's tractions on the displacement
    pair 1's cause through the block equals the converse.  The two
    couplings are built from different grids' anchors and fits, so this
    checks their frames, signs and interpolations; to 1 %, the fits'
    estimates (≤ 1.7e-3 of the block's whole flexibility) over the
    coupling's strength (≥ 0.2 of it); measured 0.1 %."""
    c = {(i, j): x for i, j, _, x in result.couplings}
    g = [r.grid for r in result.pairs]
    for direction in (2, 0, 1):
        t = [np.zeros((gr.size, 3)) for gr in g]
        for tk, gr in zip(t, g):
            tk[:, direction] = 1.0 + 0.3 * gr.centres[:, 0] / (gr.nx * gr.dx)
        w01 = g[0].cell_area * np.sum(t[0] * c[(0, 1)].matvec(t[1]))
        w10 = g[1].cell_area * np.sum(t[1] * c[(1, 0)].matvec(t[0]))
        assert w01 == pytest.approx(w10, rel=0.01)


def test_the_neighbour_acts_as_a_shallower_approach(problem, result):
    """Each pair's force in the assembly against the pair alone pressed by
    its approach less the neighbour's normal offset (the block's surface
    lowered under it by the other pair's tractions, pressure-weighted over
    the contact): equal to 5e-4 (what is left is the offset's variation over
    the contact and its tangential part; measured 5e-5 and 1.1e-4), while the
    neighbour itself lowers the forces by 1.2 % and 3.5 %."""
    c = {(i, j): x for i, j, _, x in result.couplings}
    for k, name in enumerate(("left", "right")):
        p = result.pairs[k].history[-1].p
        offset = c[(k, 1 - k)].matvec(result.pairs[1 - k].history[-1].p)
        w = float(np.sum(offset[:, 2] * p[:, 2]) / np.sum(p[:, 2]))
        assert w > 0.0  # the neighbour opens the gap
        coupled = result.pairs[k].history[-1].force[2]
        shallower = _pair_alone(problem, k, APPROACH[name] - w).history[-1].force[2]
        assert coupled == pytest.approx(shallower, rel=5e-4)
        assert w / APPROACH[name] > 5e-3


def test_the_sweeps_settle_and_every_state_is_checked(result):
    """Gauss–Seidel over the histories: the offsets' change falls by orders
    of magnitude per sweep (the coupling is about a fifth of the block's
    flexibility on the grid, and the pairs' rigid approaches are their
    own); the last change is below its hundredth of the penetration
    tolerance, and each step carries it as its coupling check."""
    assert 2 <= len(result.sweeps) <= 6
    assert all(b < 0.05 * a for a, b in zip(result.sweeps, result.sweeps[1:]))
    for r in result.pairs:
        check = r.history[-1].checks["coupling"]
        assert check["worst"] <= 0.01 * check["tolerance"]


def test_the_shared_block_balances_both_contacts(result):
    """The block's fields superposed over both pairs: its clamped base's
    reaction balances the two contact forces (each pair's fields balance
    its own within 0.65-1.1 %, tests/unit/multiscale/test_result.py)."""
    total = sum(r.history[-1].force @ r.axes for r in result.pairs)
    reaction = result.reactions()["block"]
    assert reaction[2] == pytest.approx(total[2], rel=0.015)


def test_the_applicability_checks_hold_and_name_the_separation(problem, result):
    app = assembly_applicability(result, problem)
    assert app["reason"] == ""
    sep = app["checks"]["separation_over_a"]
    assert sep["holds"] and sep["value"] == pytest.approx(4.0 / 0.625, rel=0.05)


def test_stresses_below_each_contact_sum_both_pairs(result):
    """A point below the left contact: the left grid's field plus the right
    one's, which at 2 contact radii deep and 4 mm away is small but not
    zero."""
    x = np.array([[-2.0, 0.0, -0.3]])
    left, right = result.pairs
    s = result.stresses("block", x)
    own = left.stresses("block", x)
    assert np.all(s != own)
    assert np.abs(s - own).max() < 0.02 * np.abs(own).max()


def test_a_shared_body_must_be_held(problem):
    """A force on the shared block would couple the pairs through its
    balance: refused in one line (the full path takes it)."""
    block = problem.bodies[0]
    pushed = ElasticBody(block.mesh, block.material,
                         {"zmin": [Displacement((0.0, 0.0, None)), Force((None, None, 0.0))]},
                         name="block")
    prob = ContactProblem(bodies=[pushed, *problem.bodies[1:]], pairs=list(problem.pairs))
    with pytest.raises(ConfigError, match=r"block: a body in 2 contact pairs is held in every "
                                          r"component on the grid") as info:
        solve_assembly_on_grid(prob)
    assert "\n" not in str(info.value)


def test_an_assembly_does_not_roll_on_the_grid(problem):
    step = LoadStep(rolling=Rolling(creepage=(1e-3, 0.0)))
    with pytest.raises(ConfigError, match="an assembly on the grid does not roll"):
        solve_assembly_on_grid(problem, [step])


def test_auto_takes_the_full_path_for_a_floating_ball():
    """The thrust bearing's ball is held only by its contacts: ``auto``
    says so in one line and leaves the assembly to the full path."""
    pf = load_problem(EXAMPLES / "thrust_bearing_ball.toml", check_overlap=False)
    grid, note = on_grid(pf.contact_problem(), pf.steps, "auto", SolverOptions())
    assert grid is None
    assert note.startswith("contact.method = \"auto\": the full path (ball: nothing holds it")


def _full_path(names, h: float):
    """The example's bodies meshed finely for the full path
    (:func:`~bemcontact.validation.assemblies.two_indenters_on_block`: ``h``
    near both contacts), the indenters ``names``, solved through the
    example's history: each pair's contact force."""
    res = two_indenters_on_block(h, names).solve(SolverOptions(load_steps=INCREMENTS))
    return {p.names[1]: np.asarray(p.contact_force, dtype=float) for p in (res.pairs or [res])}


@pytest.mark.slow
@pytest.mark.validation
def test_the_coupling_moves_the_forces_as_the_full_path_does(problem, result):
    """What the neighbour does to each pair's force, on the grid against
    the full path on fine meshes (a/h = 3; the coupling's effect there is
    within 0.6 % of a/h = 5's: measured -33.2 / -51.5 N at h = 0.18, -33.4 /
    -50.6 N at h = 0.11): within 5 % of it (measured 1.5 % and 2.9 %; the
    full path's own change from h = 0.18 to 0.11 is up to 1.7 %).  The
    forces themselves differ as for a pair alone (the full path at a/h = 5
    is 0.6 % stiffer than converged).  The lateral pull each indenter feels
    toward the other, against the full path's (:data:`TANGENTIAL`; measured
    +6.0 / -1.3 % at a/h = 3, +2.6 / +2.1 % at a/h = 5)."""
    full = _full_path(("left", "right"), 0.18)
    for k, name in enumerate(("left", "right")):
        alone_full = _full_path((name,), 0.18)[name][2]
        alone_grid = _pair_alone(problem, k, APPROACH[name]).history[-1].force[2]
        effect_grid = result.pairs[k].history[-1].force[2] - alone_grid
        effect_full = full[name][2] - alone_full
        assert effect_full < 0.0
        assert effect_grid == pytest.approx(effect_full, rel=0.05)
        # the lateral pull toward the other contact
        fx_grid = (result.pairs[k].history[-1].force @ result.pairs[k].axes)[0]
        assert fx_grid == pytest.approx(full[name][0], rel=TANGENTIAL)


def test_a_sweep_row_has_each_pairs_outputs(result):
    """A sweep point the grid solves as an assembly: its row gets each
    pair's forces and cells as ``pair<k>.<name>``, as the full path's
    assemblies do."""
    from bemcontact.study.table import grid_outputs

    row = grid_outputs(result)
    assert row["converged"] is True and row["increments"] == INCREMENTS
    for k, r in enumerate(result.pairs, 1):
        assert row[f"pair{k}.normal_force"] == pytest.approx(r.history[-1].force[2], rel=1e-12)
        assert row[f"pair{k}.contact_area"] > 0.0

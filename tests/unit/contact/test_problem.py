"""Load steps and force control in the contact solver (solver.py).

Small two-block problems: the lower block clamped at its base, the upper one
pushed through its top face by a rigid platen under force control (normal
load P, then a tangential load Q), which is the loading of the
Cattaneo-Mindlin and fretting cases on a geometry cheap enough for unit
tests."""

import numpy as np
import pytest

import bemcontact as bc

E, NU, MU, P = 1e4, 0.3, 0.2, 400.0


def _problem(mu=MU, nl=4, nu_=3):
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 2), nl), bc.LinearElastic(E, NU), {"zmin": bc.Fixed()}, name="lower"
    )
    upper = bc.ElasticBody(
        bc.box((0, 0, 2), (2, 2, 4), nu_),
        bc.LinearElastic(E, NU),
        {"zmax": [bc.Force((0.0, None, -P)), bc.Displacement((None, 0.0, None))]},
        name="upper",
    )
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", mu))


def _system(prob, steps):
    """The interface system of ``prob`` for the load ``steps``: both bodies
    condensed on the frame's traction modes (what ContactProblem.solve does)."""
    from bemcontact.contact import interface

    states = prob.states(steps)
    frame = prob.frame
    modes = interface.traction_modes(frame)
    cb = tuple(
        bc.condense(b, frame.nodes(a), 1, [st[a] for st in states], modes=modes[a])
        for a, b in enumerate(prob.bodies)
    )
    return interface.InterfaceSystem(frame, cb, MU, prob.contact_modulus())


def _q(q, p=P):
    return bc.LoadStep(
        {"upper": {"zmax": [bc.Force((q, None, -p)), bc.Displacement((None, 0.0, None))]}},
        label=f"Q={q:g}",
    )


@pytest.fixture(scope="module")
def cycle():
    """P, then Q up to 0.85 mu P, back to 0.5 mu P and to 0."""
    prob = _problem()
    qs = [20.0, 40.0, 68.0, 40.0, 0.0]
    return prob.solve(steps=[bc.LoadStep(label="P")] + [_q(q) for q in qs]), qs


def test_force_control_resultant_is_prescribed(cycle):
    """The platen's tractions sum to the prescribed force at every step: an
    equation of the system, so to the solver tolerance (1e-10 relative)."""
    res, qs = cycle
    assert [h.label for h in res.history] == ["P"] + [f"Q={q:g}" for q in qs]
    for h, q in zip(res.history, [0.0] + qs):
        R = h.bodies[1].reaction("zmax")
        assert R[0] == pytest.approx(q, abs=1e-8 * P)
        assert R[2] == pytest.approx(-P, rel=1e-9)
        # and the contact carries them, to the body's BEM equilibrium (coarse
        # 3x3 faces with the platen's edge singularities: measured 2.6 % of Q
        # at Q = 68, 2e-4 of P, 0.035 left at Q = 0)
        assert h.normal_force == pytest.approx(P, rel=1e-3)
        assert h.contact_force[0] == pytest.approx(-q, abs=0.04 * q + 1e-3 * P)


def test_platen_translation_reported(cycle):
    """U_z is the same for every Q (the normal and tangential problems
    decouple for identical materials: to 1e-6 relative, the coupling left by
    the discretization), U_x grows with Q and is NaN in y (not controlled).
    Under P alone U_x is zero by the mirror symmetry about x = 1: round-off
    of the solve, bounded against U_z (measured 4e-15 of it)."""
    res, qs = cycle
    U = np.array([h.control_displacements["upper"]["zmax"] for h in res.history])
    assert np.isnan(U[:, 1]).all()
    assert abs(U[0, 0]) <= 1e-11 * abs(U[0, 2])
    assert np.allclose(U[:, 2], U[0, 2], rtol=1e-5)
    assert U[0, 2] < 0
    assert U[1, 0] > 0 and U[2, 0] == pytest.approx(2 * U[1, 0], rel=1e-9)  # linear while all stick


def test_partial_slip_and_reversal(cycle):
    """All stick for small Q, partial slip near mu P, every node stuck again
    right after the reversal (Mindlin-Deresiewicz), and a residual tangential
    displacement of the platen after unloading to Q = 0 (the slip is not
    undone)."""
    res, qs = cycle
    counts = [h.frame.counts() for h in res.history]
    assert counts[1]["slip"] == 0 and counts[2]["slip"] == 0
    assert counts[3]["slip"] > 0 and counts[3]["stick"] > 0
    assert counts[4]["slip"] == 0  # reversal: the whole interface sticks again
    U = [h.control_displacements["upper"]["zmax"][0] for h in res.history]
    assert U[5] > 1e-3 * U[3]
    # invariants at every step: Coulomb cone and nonnegative pressure
    for h in res.history:
        fr = h.frame
        assert fr.pressure.min() >= -1e-9 * fr.pressure.max()
        tt = np.linalg.norm(fr.tangential_traction, axis=1)
        assert np.all(tt <= MU * fr.pressure + 1e-9 * fr.pressure.max())


def test_elastic_path_independence():
    """Without slip the response is path independent: P, Q, then back to
    Q = 0 gives the P-only state (to 1e-9 relative; elastic, all stick)."""
    prob = _problem(mu=0.5)
    res = prob.solve(steps=[bc.LoadStep(label="P"), _q(30.0), _q(0.0)])
    a, c = res.history[0], res.history[2]
    assert res.history[1].frame.counts()["slip"] == 0
    assert np.allclose(c.frame.pressure, a.frame.pressure, rtol=1e-9, atol=1e-9 * P)
    assert np.allclose(
        c.bodies[1].displacement, a.bodies[1].displacement, rtol=0, atol=1e-9 * abs(a.bodies[1].displacement).max()
    )


def test_increments_equal_load_steps_option():
    """One LoadStep in 3 increments is the solve with load_steps = 3."""
    prob = _problem()
    a = prob.solve(bc.SolverOptions(load_steps=3))
    b = prob.solve(steps=[bc.LoadStep(increments=3)])
    assert [s.load_factor for s in b.steps] == pytest.approx([1 / 3, 2 / 3, 1])
    assert np.array_equal(a.frame.pressure, b.frame.pressure)


def test_step_input_errors():
    prob = _problem()
    with pytest.raises(bc.ConfigError, match="unknown body 'top'"):
        prob.solve(steps=[bc.LoadStep({"top": {}})])
    with pytest.raises(bc.ConfigError, match="step 1 \\(bad\\): upper: boundary condition on unknown region 'lid'"):
        prob.solve(steps=[bc.LoadStep({"upper": {"lid": bc.Fixed()}}, label="bad")])
    with pytest.raises(bc.ConfigError, match="region 'zmax' component x changes from force to displacement"):
        prob.solve(steps=[bc.LoadStep({"upper": {"zmax": [bc.Displacement((0.0, 0.0, None)), bc.Force((None, None, -P))]}})])
    with pytest.raises(bc.ConfigError, match="'zmin' is the contact surface"):
        prob.solve(steps=[bc.LoadStep({"upper": {"zmin": bc.Pressure(1.0)}})])
    with pytest.raises(bc.ConfigError, match="LoadStep.increments must be an integer >= 1, got 0"):
        bc.LoadStep(increments=0)
    with pytest.raises(bc.ConfigError, match="steps must hold at least one LoadStep"):
        prob.solve(steps=[])
    with pytest.raises(bc.ConfigError, match="Force: value must be 3 components"):
        bc.Force(lambda x: x)


def test_newton_matrix_matches_central_differences():
    """The rows of the interface system's generalized Jacobian that Newton
    factors (closed nodes, free-mode and platen-force rows; every column,
    including the platen translation's) equal central differences of the
    residual at a partial-slip point, to 1e-6 of the largest entry (the
    difference step's truncation error; a wrong block is off by O(1))."""
    from bemcontact.contact import law
    from bemcontact.contact.newton import newton

    system = _system(_problem(), [bc.LoadStep(label="P"), _q(68.0)])
    opt = bc.SolverOptions()
    z, rec, msg = newton(system, system.zero(), np.array([1.0, 0.0]), opt)
    assert msg is None
    ell = np.array([0.0, 1.0])
    system.law.reference = system.k(z, np.array([1.0, 0.0]))[:, :2].copy()
    z, _, msg = newton(system, z, ell, bc.SolverOptions(max_iterations=2))
    z[[2, 3 * 5 + 2]] = -P  # two nodes pulled open (flat blocks: all closed otherwise)
    J, rows, state = system.jacobian(z, ell)
    counts = np.bincount(state, minlength=3)
    assert counts[law.STICK] > 0 and counts[law.SLIP] > 0 and counts[law.OPEN] > 0
    assert system.nc == [0, 2]  # the platen's x and z translations are columns
    m3 = 3 * system.m
    assert np.array_equal(rows[: rows.size - (z.size - m3)] // 3, np.repeat(np.flatnonzero(state != 0), 3))
    lam_scale = np.abs(z[:m3]).max()
    Jfd = np.empty_like(J)
    for j in range(z.size):
        eps = 1e-6 * lam_scale if j < m3 else 1e-6 * np.abs(z[j])
        e = np.zeros_like(z)
        e[j] = eps
        Jfd[:, j] = (system.residual(z + e, ell) - system.residual(z - e, ell))[rows] / (2 * eps)
    assert np.abs(J - Jfd).max() <= 1e-6 * np.abs(J).max()
    # and open rows of the full residual are lam_j itself (identity rows)
    open_rows = np.setdiff1d(np.arange(z.size), rows)
    phi = system.residual(z, ell)
    assert np.array_equal(phi[open_rows], z[open_rows])
    # Newton's reduced system (open rows eliminated, only the closed block
    # factored) gives the step of the full one, to round-off (measured 1e-15)
    from bemcontact.contact.newton import newton_direction

    Jfull = np.eye(z.size)
    Jfull[rows] = J
    A, b, keep, _ = system.newton_system(z, ell, phi)
    np.testing.assert_array_equal(keep, rows)
    dz = newton_direction(A, b, keep, phi)
    want = np.linalg.solve(Jfull, -phi)
    assert np.abs(dz - want).max() <= 1e-12 * np.abs(want).max()


def test_frame_on_chooses_the_frame_surface():
    """ContactPair.frame_on overrides the coarser-surface rule (the upper
    3 x 3 face is coarser than the lower 4 x 4 one); a bad value is refused."""
    lower, upper = _problem().bodies
    for on, owner in (("coarser", 1), ("body1", 0), ("body2", 1), ("auto", 1)):
        prob = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", MU, frame_on=on))
        assert prob.frame.owner == owner
    with pytest.raises(bc.ConfigError, match=r"frame_on must be one of 'auto', 'between', 'coarser', 'body1', 'body2', got 'lower'"):
        bc.ContactPair("zmax", "zmin", frame_on="lower")


def test_watchdog_and_monotone_line_search_agree(cycle):
    """The watchdog (default) and the monotone line search (watchdog = 0)
    reach the same solution (the solution does not depend on the path to it:
    1e-8 of P in the contact force, same states); the watchdog's iteration
    count is printed next to the monotone one."""
    res, qs = cycle
    mono = _problem().solve(
        bc.SolverOptions(watchdog=0), steps=[bc.LoadStep(label="P")] + [_q(q) for q in qs]
    )
    for a, b in zip(res.history, mono.history):
        np.testing.assert_allclose(a.contact_force, b.contact_force, rtol=0, atol=1e-8 * P)
        np.testing.assert_array_equal(a.frame.state, b.frame.state)
    print("iterations: watchdog", [s.iterations for s in res.steps],
          "monotone", [s.iterations for s in mono.steps])
    with pytest.raises(bc.ConfigError, match=r"watchdog must be an integer >= 0, got -1"):
        bc.SolverOptions(watchdog=-1)


@pytest.mark.parametrize("gap", [0.0, 0.01])
def test_force_control_starts_from_an_open_contact(gap):
    """The upper block under force control alone in z (held in x by
    friction only), placed 0.01 above the lower one: every node open, so the
    Newton matrix at the start is singular in the platen's translation.  The
    first-touch predictor moves the platen until a penalty patch carries P;
    Newton then converges to the solution of the block placed in contact
    (gap 0, the reference's own set-up): the same tractions to 1e-8 of the
    mean pressure, and a platen translation larger by exactly the gap."""
    def solve(g):
        lower = bc.ElasticBody(bc.box((0, 0, 0), (2, 2, 2), 4), bc.LinearElastic(E, NU),
                               {"zmin": bc.Fixed()}, name="lower")
        upper = bc.ElasticBody(
            bc.box((0, 0, 2 + g), (2, 2, 4 + g), 3), bc.LinearElastic(E, NU),
            {"zmax": [bc.Force((0.0, None, -P)), bc.Displacement((None, 0.0, None))]}, name="upper",
        )
        pair = bc.ContactPair("zmax", "zmin", MU, search_distance=0.05)
        return bc.ContactProblem(lower, upper, pair).solve()

    ref = _problem().solve()
    res = solve(gap)
    assert res.converged and res.newton_iterations <= 10, res.newton_iterations
    p_mean = P / 4.0
    assert np.abs(res.frame.pressure - ref.frame.pressure).max() <= 1e-8 * p_mean
    u, u_ref = (r.control_displacements["upper"]["zmax"][2] for r in (res, ref))
    assert u - u_ref == pytest.approx(-gap, abs=1e-9)


def test_force_pulling_a_floating_body_away_is_a_clear_error():
    """The same block pulled up (+P) away from the contact that alone holds
    it: the predictor finds no force balance and the solve stops at once
    with the singular-matrix diagnosis, not after a search."""
    lower = bc.ElasticBody(bc.box((0, 0, 0), (2, 2, 2), 4), bc.LinearElastic(E, NU),
                           {"zmin": bc.Fixed()}, name="lower")
    upper = bc.ElasticBody(
        bc.box((0, 0, 2.01), (2, 2, 4.01), 3), bc.LinearElastic(E, NU),
        {"zmax": [bc.Force((0.0, None, P)), bc.Displacement((None, 0.0, None))]}, name="upper",
    )
    prob = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", MU, search_distance=0.05))
    with pytest.raises(bc.ConvergenceError, match="pulls a body held only by the contact away"):
        prob.solve()


def test_more_threads_than_cores_are_capped(monkeypatch):
    """threads = 4096 (4096 threads on 2 cores ran 18x slower): one
    ResourceLimitWarning, and the solve runs on the cores there are with the
    answer of threads = cores (to rounding: 1e-12 of the normal force)."""
    from bemcontact.linalg import threads

    cores = threads.available_cores()
    prob = _problem()
    with pytest.warns(bc.ResourceLimitWarning, match="threads = 4096"):
        many = prob.solve(bc.SolverOptions(threads=4096))
    same = prob.solve(bc.SolverOptions(threads=cores))
    np.testing.assert_allclose(many.contact_force, same.contact_force, rtol=0,
                               atol=1e-12 * abs(same.normal_force))


def test_a_floating_block_resting_on_another_starts_from_its_first_touch():
    """A block held in z only by the contact (rollers on x = 0 and y = 0),
    pressed by p = 2 onto another, its interface nodes starting at gaps of
    round-off size (all open at lam = 0): the free mode is moved until the
    trial pressures carry the load (InterfaceSystem.first_touch), so the
    first Newton matrix is not singular.  Uniform stress: the patch test's
    1e-8 (measured 7e-11), in one Newton iteration."""
    rollers = {"xmin": bc.Displacement((0, None, None)), "ymin": bc.Displacement((None, 0, None))}
    m = bc.LinearElastic(1e4, 0.3)
    lower = bc.ElasticBody(bc.box((0, 0, 0), (1, 1, 1), (3, 3, 2)), m,
                           {"zmin": bc.Displacement((None, None, 0)), **rollers}, name="bottom")
    upper = bc.ElasticBody(bc.box((0, 0, 1), (1, 1, 2), (4, 4, 2)), m,
                           {"zmax": bc.Pressure(2.0), **rollers}, name="top")
    res = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", frame_on="coarser")).solve()
    assert res.converged and res.newton_iterations <= 2
    act = res.frame.weights > 0
    assert np.abs(res.frame.pressure[act] / 2.0 - 1.0).max() <= 1e-8


def test_the_first_touch_node_keeps_no_locked_in_shear():
    """The node touching first holds the bodies alone in the first
    increment (every other node closing in it is frictionless there), so the
    lateral force of that increment lands on it: on the sphere of the
    Cattaneo-Mindlin case the discrete sphere's equilibrium defect, a
    traction growing as 1/h^2 (0.016 p0 at a/h = 12, 0.06 p0 at a/h = 25, a
    third of the q profile's error there if it stayed locked in while the
    node sticks).  Once its neighbours touch, the stick references leave out
    the displacement of that traction (InterfaceSystem.start_increment): after
    a small tangential load Q = 0.02 mu P, where the exact shear is smooth
    at the centre, the first-touch node carries its six neighbours' shear to
    5 % (they spread by 3 %; with the traction locked in it carries 13.6 MPa
    against their -7.5 MPa, the opposite sign).  h = 0.1 mm, a/h = 5.5."""
    from bemcontact.contact import law
    from bemcontact.validation import cases
    from bemcontact.validation.reference import contact as ref

    s = cases.SphereOnBlock()
    load = ref.hertz_force(0.03, s.radius, s.contact_modulus)
    prob = cases.sphere_on_block(0.1, 0.03, friction_coefficient=0.3)
    steps = [bc.LoadStep(label="P")] + cases.tangential_steps([0.02 * 0.3 * load], 0.03,
                                                                increments=1)
    res = prob.solve(steps=steps)
    after_p, after_q = res.history[0].frame, res.history[1].frame
    q = np.linalg.norm(after_p.tangential_traction, axis=1)
    anchor = int(np.argmax(q))
    # only it holds after P: the others closed frictionless, where the law is
    # lam_t = 0, solved to the Newton tolerance (1e-10 of the traction scale;
    # measured exactly 0, which the LU's pivoting gives but does not promise)
    held = q > 1e-9 * after_p.pressure.max()
    assert np.count_nonzero(held) == 1 and held[anchor] and q[anchor] > 10.0
    near = np.argsort(np.linalg.norm(after_q.points - after_q.points[anchor], axis=1))[1:7]
    qx = after_q.tangential_traction[:, 0]
    assert np.all(after_q.state[[anchor, *near]] == law.STICK)
    assert abs(qx[anchor] - qx[near].mean()) <= 0.05 * abs(qx[near].mean()), (qx[anchor],
                                                                              qx[near])


def test_errors_carry_their_step_and_pair_as_data():
    """A bad load step names its index in ``location`` (the problem-file
    reader maps it to its field without reading the message); a frame error
    of a pair its pair index, and ``detail`` the message without it."""
    prob = _problem()
    bad = [bc.LoadStep(label="P"),
           bc.LoadStep({"upper": {"zmax": bc.Displacement((0.0, None, -0.01))}}, label="push")]
    with pytest.raises(bc.ConfigError, match=r"^step 2 \(push\): upper: region 'zmax'") as info:
        prob.states(bad)
    assert info.value.location == {"step": 1}
    with pytest.raises(bc.ConfigError) as info:
        prob.states([bc.LoadStep(), "P"])
    assert info.value.location == {"step": 1}
    err = bc.ConfigError("pairs[1] (a/b): too far", location={"pair": 1}, detail="too far")
    assert err.location == {"pair": 1} and err.detail == "too far" and str(err).startswith("pairs[1]")
    assert bc.ConfigError("plain").detail == "plain" and bc.ConfigError("plain").location == {}
